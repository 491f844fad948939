// SPDX-License-Identifier: MIT
// The one file that knows GDAL: rasters other than ESRI ASCII are opened
// here, and GeoTIFF outputs are encoded here (terrain.h declares the API).
// GDAL is registered on first use only, so a scene without terrain never
// initialises it. Handles live on the loading thread only: the raster is
// read once, into a Dem, and closed.
#pragma once

#include "src/scene/terrain.h"

namespace plancheck {

std::unique_ptr<DemReader> open_gdal_dem(const std::filesystem::path& file, int band);

}  // namespace plancheck

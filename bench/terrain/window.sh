#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The terrain window on a large mosaic (issue 35): a 20,000 x 20,000 tiled,
# compressed float32 GeoTIFF with the site in its south-west corner, loaded by
# `plancheck scene` (which reads only the window the arm can reach), against
# the window alone (gdal_translate -srcwin of the same pixels) and against a
# whole-file read into memory (gdal_translate -of MEM -ot Float64: the 8 bytes
# a pixel a Dem holds as heights). Checks first that both scenes read the
# same window, then prints wall time and peak RSS.
# Not part of `make test` (the mosaic takes ~10-20 s to write).
# Usage: bench/terrain/window.sh BUILD_DIR [WORK_DIR]
set -euo pipefail
build=$(realpath "${1:?usage: window.sh BUILD_DIR [WORK_DIR]}")
work=${2:-$(mktemp -d)}
plancheck="$build/plancheck"
srs='+proj=stere +lat_0=-90 +lon_0=0 +k=1 +x_0=0 +y_0=0 +R=1737400 +units=m +no_defs'
mkdir -p "$work"
cd "$work"

# The arm: a lander box, an arm on J1 (about z) and a scoop on S (about y).
cat > m.obj <<'OBJ'
o Lander
v -0.3 -0.3 0
v 0.3 -0.3 0
v 0.3 0.3 0
v -0.3 0.3 0
v -0.3 -0.3 0.6
v 0.3 -0.3 0.6
v 0.3 0.3 0.6
v -0.3 0.3 0.6
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
o Arm
v 0 -0.05 0.55
v 1 -0.05 0.55
v 1 0.05 0.55
v 0 0.05 0.55
v 0 -0.05 0.65
v 1 -0.05 0.65
v 1 0.05 0.65
v 0 0.05 0.65
f 9 11 10
f 9 12 11
f 13 14 15
f 13 15 16
f 9 10 14
f 9 14 13
f 10 11 15
f 10 15 14
f 11 12 16
f 11 16 15
f 12 9 13
f 12 13 16
OBJ
scene() {  # scene() DEM FILE
  cat > "$2" <<JSON
{"format": "plancheck-scene/1", "model": "m.obj", "length_unit": "m", "angle_unit": "deg",
 "actions": [{"name": "J1", "node": "Arm", "type": "rotate", "pivot": [0, 0, 0.6], "axis": [0, 0, 1]}],
 "allowed_collisions": [["Arm", "Lander"]], "safety_margin": 0.02,
 "terrain": {"dem": "$1", "map_origin": [20005, -39995, -0.5]}}
JSON
}
# 0.05 m cells: 1 km x 1 km; the site 5 m from the south-west corner.
if [ ! -f mosaic.tif ]; then
  start=$(date +%s.%N)
  gdal_create -q -of GTiff -ot Float32 -outsize 20000 20000 -burn 0 -a_nodata -9999 \
    -co TILED=YES -co COMPRESS=DEFLATE -co BIGTIFF=YES -a_srs "$srs" \
    -a_ullr 20000 -39000 21000 -40000 mosaic.tif
  echo "mosaic written in $(echo "$(date +%s.%N) - $start" | bc) s: $(du -h mosaic.tif | cut -f1) on disk"
fi
scene mosaic.tif big.json
"$plancheck" scene big.json > big.txt
window=$(grep -o 'read the window within reach, [0-9]* x [0-9]* pixels from column [0-9]*, row [0-9]*' big.txt)
echo "mosaic: $window"
read -r cols rows col row < <(echo "$window" | sed -E 's/.* ([0-9]+) x ([0-9]+) pixels from column ([0-9]+), row ([0-9]+)/\1 \2 \3 \4/')
gdal_translate -q -srcwin $((col - 1)) $((row - 1)) "$cols" "$rows" -co TILED=YES -co COMPRESS=DEFLATE mosaic.tif window.tif
scene window.tif small.json
"$plancheck" scene small.json > small.txt
grep -q "read the whole raster, $cols x $rows pixels" small.txt || { echo "window.tif is not the same window" >&2; exit 1; }

measure() {  # measure RUNS LABEL COMMAND...: best of RUNS wall times, its peak RSS
  local best= rss= runs=$1
  shift
  for _ in $(seq "$runs"); do
    /usr/bin/time -f '%e %M' -o t.txt "${@:2}" > /dev/null
    read -r s k < t.txt
    if [ -z "$best" ] || [ "$(echo "$s < $best" | bc)" = 1 ]; then best=$s; rss=$k; fi
  done
  printf '%-42s %8s s %10s KiB peak RSS\n' "$1" "$best" "$rss"
}
measure 3 "plancheck scene, mosaic (window read)" "$plancheck" scene big.json
measure 3 "plancheck scene, the window alone" "$plancheck" scene small.json
measure 1 "whole-file read (gdal_translate -of MEM)" gdal_translate -q -ot Float64 -of MEM mosaic.tif mem
echo "(a whole-file read through plancheck is refused: 4e8 pixels is over its 2e8-pixel window limit)"

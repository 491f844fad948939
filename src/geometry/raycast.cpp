// SPDX-License-Identifier: MIT
#include "src/geometry/raycast.h"

#include "src/geometry/heightfield.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace plancheck {

namespace {

// User data of a heightfield geometry.
struct TerrainGeometry {
  const Heightfield* base;
  float lo[3], hi[3];  // Embree bounds
};

}  // namespace

struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  bool committed = false;
  std::vector<std::unique_ptr<TerrainGeometry>> terrains;
};

namespace {

// The intersect context extended (Embree passes it to user callbacks): the
// field to walk this call and the double rays, found by ray id.
struct TerrainContext {
  RTCIntersectContext context;  // first member: the callback casts back
  const Heightfield* terrain;
  const Ray* rays;
};

void terrain_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* t = static_cast<const TerrainGeometry*>(args->geometryUserPtr);
  args->bounds_o->lower_x = t->lo[0], args->bounds_o->lower_y = t->lo[1], args->bounds_o->lower_z = t->lo[2];
  args->bounds_o->upper_x = t->hi[0], args->bounds_o->upper_y = t->hi[1], args->bounds_o->upper_z = t->hi[2];
}

// Walks the heightfield in double along the caller's double ray; a hit
// nearer than Embree's current tfar (float) replaces it.
void terrain_intersect(const RTCIntersectFunctionNArguments* args) {
  const auto* t = static_cast<const TerrainGeometry*>(args->geometryUserPtr);
  const auto* ctx = reinterpret_cast<const TerrainContext*>(args->context);
  const Heightfield& field = ctx->terrain ? *ctx->terrain : *t->base;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const Ray& r = ctx->rays[RTCRayN_id(ray, args->N, i)];
    const double o[3] = {r.origin.x(), r.origin.y(), r.origin.z()};
    const double d[3] = {r.direction.x(), r.direction.y(), r.direction.z()};
    double t_far = RTCRayN_tfar(ray, args->N, i);
    std::uint32_t tri = 0;
    if (!field.intersect_ray(o, d, RTCRayN_tnear(ray, args->N, i), t_far, tri)) continue;
    const float tf = static_cast<float>(t_far);
    if (!(tf < RTCRayN_tfar(ray, args->N, i))) continue;
    RTCRayN_tfar(ray, args->N, i) = tf;
    RTCHitN_Ng_x(hit, args->N, i) = 0.0f;
    RTCHitN_Ng_y(hit, args->N, i) = 0.0f;
    RTCHitN_Ng_z(hit, args->N, i) = 1.0f;
    RTCHitN_u(hit, args->N, i) = 0.0f;
    RTCHitN_v(hit, args->N, i) = 0.0f;
    RTCHitN_primID(hit, args->N, i) = tri;
    RTCHitN_geomID(hit, args->N, i) = args->geomID;
    RTCHitN_instID(hit, args->N, i, 0) = args->context->instID[0];
  }
}

void terrain_occluded(const RTCOccludedFunctionNArguments*) {}  // probes only intersect

void check_device(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + what + " failed (error " + std::to_string(static_cast<int>(e)) + ")");
}

}  // namespace

RayScene::RayScene() : impl_(std::make_unique<Impl>()) {
#if defined(PLANCHECK_TSAN)
  // Embree builds on TBB workers, which hand the finished BVH back through
  // TBB's uninstrumented scheduler: TSan sees that hand-over (and the user
  // geometry callbacks our code runs on those workers) as races, without a
  // stack to suppress by. The TSan build lets Embree build on the calling
  // thread only; the answers are the same.
  impl_->device = rtcNewDevice("threads=1");
#else
  impl_->device = rtcNewDevice(nullptr);
#endif
  if (!impl_->device) throw std::runtime_error("Embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  // Robust mode: rays that graze shared edges do not slip between triangles.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  check_device(impl_->device, "scene creation");
}

RayScene::~RayScene() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

int RayScene::add_mesh(const Mesh& mesh, const Affine& pose) {
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3 p = pose * mesh.vertices[i];
    for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(p[k]);
  }
  auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                           3 * sizeof(unsigned), mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) t[3 * i + k] = mesh.triangles[i][static_cast<std::size_t>(k)];
  rtcCommitGeometry(g);
  const unsigned id = rtcAttachGeometry(impl_->scene, g);
  rtcReleaseGeometry(g);
  check_device(impl_->device, "adding a mesh");
  ++mesh_count_;
  return static_cast<int>(id);
}

int RayScene::add_heightfield(const Heightfield& base, double z_slack) {
  auto data = std::make_unique<TerrainGeometry>();
  data->base = &base;
  double lo[3], hi[3];
  if (!base.block_box(static_cast<int>(base.levels().size()) - 1, 0, 0, lo, hi)) {
    lo[0] = lo[1] = lo[2] = 0.0;
    hi[0] = hi[1] = hi[2] = -1.0;  // an empty field: an empty box is never entered
  } else {
    lo[2] -= z_slack, hi[2] += z_slack;
  }
  for (int k = 0; k < 3; ++k) {
    // Outward by a float ulp or so, so the float box holds the double one.
    data->lo[k] = std::nextafter(static_cast<float>(lo[k]), -std::numeric_limits<float>::infinity());
    data->hi[k] = std::nextafter(static_cast<float>(hi[k]), std::numeric_limits<float>::infinity());
  }
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(g, 1);
  rtcSetGeometryUserData(g, data.get());
  rtcSetGeometryBoundsFunction(g, terrain_bounds, nullptr);
  rtcSetGeometryIntersectFunction(g, terrain_intersect);
  rtcSetGeometryOccludedFunction(g, terrain_occluded);
  rtcCommitGeometry(g);
  const unsigned id = rtcAttachGeometry(impl_->scene, g);
  rtcReleaseGeometry(g);
  check_device(impl_->device, "adding a heightfield");
  impl_->terrains.push_back(std::move(data));
  ++mesh_count_;
  return static_cast<int>(id);
}

void RayScene::commit() {
  rtcCommitScene(impl_->scene);
  check_device(impl_->device, "building the ray scene");
  impl_->committed = true;
}

void RayScene::intersect(const std::vector<Ray>& rays, std::vector<RayHit>& hits, const Heightfield* terrain) const {
  hits.assign(rays.size(), RayHit{});
  if (rays.empty()) return;
  std::vector<RTCRayHit> rh(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    RTCRayHit& r = rh[i];
    r.ray.org_x = static_cast<float>(rays[i].origin.x());
    r.ray.org_y = static_cast<float>(rays[i].origin.y());
    r.ray.org_z = static_cast<float>(rays[i].origin.z());
    r.ray.dir_x = static_cast<float>(rays[i].direction.x());
    r.ray.dir_y = static_cast<float>(rays[i].direction.y());
    r.ray.dir_z = static_cast<float>(rays[i].direction.z());
    r.ray.tnear = 0.0f;
    r.ray.tfar = static_cast<float>(rays[i].max_range);
    r.ray.time = 0.0f;
    r.ray.mask = 0xFFFFFFFFu;
    r.ray.id = static_cast<unsigned>(i);
    r.ray.flags = 0;
    r.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    r.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  }
  TerrainContext context;
  rtcInitIntersectContext(&context.context);
  context.context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  context.terrain = terrain;
  context.rays = rays.data();
  rtcIntersect1M(impl_->scene, &context.context, rh.data(), static_cast<unsigned>(rh.size()), sizeof(RTCRayHit));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    RayHit& h = hits[i];
    if (rh[i].hit.geomID == RTC_INVALID_GEOMETRY_ID) {
      h.distance = rays[i].max_range;
      continue;
    }
    h.hit = true;
    h.distance = rh[i].ray.tfar;
    h.mesh = static_cast<int>(rh[i].hit.geomID);
    h.triangle = rh[i].hit.primID;
  }
}

}  // namespace plancheck

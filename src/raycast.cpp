// SPDX-License-Identifier: MIT
#include "src/raycast.h"

#include <embree3/rtcore.h>

#include <limits>
#include <stdexcept>
#include <string>

namespace plancheck {

struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  bool committed = false;
};

namespace {

void check_device(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + what + " failed (error " + std::to_string(static_cast<int>(e)) + ")");
}

}  // namespace

RayScene::RayScene() : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
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

void RayScene::commit() {
  rtcCommitScene(impl_->scene);
  check_device(impl_->device, "building the ray scene");
  impl_->committed = true;
}

void RayScene::intersect(const std::vector<Ray>& rays, std::vector<RayHit>& hits) const {
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
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  rtcIntersect1M(impl_->scene, &context, rh.data(), static_cast<unsigned>(rh.size()), sizeof(RTCRayHit));
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

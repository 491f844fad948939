// SPDX-License-Identifier: MIT
#include "src/checks/built_ahead.h"

#include "src/base/error.h"
#include "src/geometry/bvh.h"
#include "src/scene/model_loader.h"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <utility>

namespace plancheck {

BuiltAhead::~BuiltAhead() { finish(); }

void BuiltAhead::take(std::vector<Mesh> meshes) {
  meshes_ = std::move(meshes);
  order_.resize(meshes_.size());
  std::iota(order_.begin(), order_.end(), std::size_t{0});
  std::stable_sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) {
    return meshes_[a].triangles.size() > meshes_[b].triangles.size();
  });
  state_ = std::make_unique<std::atomic<int>[]>(meshes_.size());
  for (std::size_t i = 0; i < meshes_.size(); ++i) state_[i] = meshes_[i].triangles.empty() ? kSkipped : kPending;
  data_.assign(meshes_.size(), nullptr);
}

void BuiltAhead::run(const std::atomic<bool>& stop) {
  for (std::size_t i : order_) {
    if (stop || stop_) break;
    int expected = kPending;
    if (!state_[i].compare_exchange_strong(expected, kBuilding)) continue;  // claimed by find(), or skipped
    int done = kSkipped;
    try {
      data_[i] = std::make_shared<const CollisionModelData>(build_collision_data(meshes_[i]));
      done = kBuilt;
    } catch (const InputError&) {
      // A face out of range or a point out of range: no part has this mesh.
    }
    state_[i].store(done, std::memory_order_release);  // data_[i] before the state
    state_[i].notify_all();
  }
}

void BuiltAhead::build(const std::filesystem::path& model, double length_scale, const std::atomic<bool>& stop) {
  build([&] { return drawn_object_meshes(model, length_scale); }, stop);
}

void BuiltAhead::build(const std::function<std::vector<Mesh>()>& drawn, const std::atomic<bool>& stop) {
  take(drawn());
  run(stop);
}

void BuiltAhead::start(const std::function<std::vector<Mesh>()>& drawn) {
  take(drawn());
  job_ = std::make_unique<BesideJob>([this] {
    const std::atomic<bool> go_on{false};
    run(go_on);
  });
}

void BuiltAhead::finish() {
  stop_ = true;
  job_.reset();  // joins
  // What a checker took it shares; the rest (objects of pruned parts, or
  // of none) is not kept.
  meshes_.clear();
  data_.clear();
}

std::shared_ptr<const CollisionModelData> BuiltAhead::find(const Mesh& mesh) const {
  if (mesh.triangles.empty()) return nullptr;
  for (std::size_t i = 0; i < meshes_.size(); ++i) {
    const Mesh& b = meshes_[i];
    if (b.vertices.size() != mesh.vertices.size() || b.triangles.size() != mesh.triangles.size()) continue;
    if (std::memcmp(b.vertices.data(), mesh.vertices.data(), mesh.vertices.size() * sizeof(Vec3)) != 0 ||
        std::memcmp(b.triangles.data(), mesh.triangles.data(), mesh.triangles.size() * sizeof(Tri)) != 0)
      continue;
    for (;;) {
      int s = state_[i].load(std::memory_order_acquire);
      if (s == kBuilt) return data_[i];
      if (s == kBuilding) {
        state_[i].wait(kBuilding, std::memory_order_acquire);
      } else if (s == kPending) {
        if (state_[i].compare_exchange_strong(s, kClaimed)) return nullptr;  // the caller builds it
      } else {
        break;  // claimed by another caller, or skipped: look further
      }
    }
  }
  return nullptr;
}

std::size_t BuiltAhead::size() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < meshes_.size(); ++i) n += state_[i].load(std::memory_order_acquire) == kBuilt ? 1 : 0;
  return n;
}

}  // namespace plancheck

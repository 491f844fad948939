// SPDX-License-Identifier: MIT
#include "support/fcl_reference.h"

#include "src/kinematics.h"

#include <fcl/fcl.h>

#include <limits>

namespace plancheck::testing {

struct FclReference::Impl {
  const Scene* scene = nullptr;
  std::vector<std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>>> models;
  std::vector<int> chain;  // per part: chain id or -1
  std::vector<std::pair<int, int>> pairs;
};

FclReference::FclReference(const Scene& scene, const std::vector<const Mesh*>& meshes,
                           std::vector<std::pair<int, int>> pairs)
    : impl_(std::make_unique<Impl>()) {
  impl_->scene = &scene;
  impl_->pairs = std::move(pairs);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    auto m = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    std::vector<fcl::Vector3d> v(meshes[i]->vertices.begin(), meshes[i]->vertices.end());
    std::vector<fcl::Triangle> t;
    for (const Tri& tri : meshes[i]->triangles) t.emplace_back(tri[0], tri[1], tri[2]);
    m->beginModel();
    m->addSubModel(v, t);
    m->endModel();
    impl_->models.push_back(m);
    impl_->chain.push_back(i < scene.parts.size() && scene.parts[i].moving() ? scene.parts[i].chain_id : -1);
  }
}

FclReference::~FclReference() = default;

FclReference::Answer FclReference::check(const std::vector<double>& params) const {
  std::vector<Affine> chains;
  chain_transforms(*impl_->scene, params, chains);
  auto pose = [&](int i) {
    const int c = impl_->chain[static_cast<std::size_t>(i)];
    const Affine t = c >= 0 ? chains[static_cast<std::size_t>(c)] : Affine::Identity();
    fcl::Transform3d f = fcl::Transform3d::Identity();
    f.linear() = t.linear();
    f.translation() = t.translation();
    return f;
  };
  Answer answer;
  answer.distance = std::numeric_limits<double>::infinity();
  // One result shared across the pairs, as FCL's broadphase callbacks do: the
  // best distance so far bounds the traversal of the next pair.
  fcl::DistanceResultd dres;
  for (std::size_t k = 0; k < impl_->pairs.size(); ++k) {
    const auto [a, b] = impl_->pairs[k];
    fcl::CollisionObjectd oa(impl_->models[static_cast<std::size_t>(a)], pose(a));
    fcl::CollisionObjectd ob(impl_->models[static_cast<std::size_t>(b)], pose(b));
    fcl::CollisionRequestd creq;
    fcl::CollisionResultd cres;
    fcl::collide(&oa, &ob, creq, cres);
    if (cres.isCollision()) {
      if (!answer.collision) answer.pair = static_cast<int>(k);
      answer.collision = true;
      answer.distance = 0.0;
      continue;
    }
    if (answer.collision) continue;
    fcl::DistanceRequestd dreq;
    fcl::distance(&oa, &ob, dreq, dres);
    if (dres.min_distance < answer.distance) {
      answer.distance = dres.min_distance;
      answer.pair = static_cast<int>(k);
    }
  }
  return answer;
}

}  // namespace plancheck::testing

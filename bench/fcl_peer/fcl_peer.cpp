// SPDX-License-Identifier: MIT
#include "bench/fcl_peer/fcl_peer.h"

#include "src/scene/kinematics.h"

#include <fcl/fcl.h>

#include <limits>

namespace plancheck::reference {

namespace {

std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> obbrss_model(const Mesh& mesh) {
  auto m = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> v(mesh.vertices.begin(), mesh.vertices.end());
  std::vector<fcl::Triangle> t;
  t.reserve(mesh.triangles.size());
  for (const Tri& tri : mesh.triangles) t.emplace_back(tri[0], tri[1], tri[2]);
  m->beginModel();
  m->addSubModel(v, t);
  m->endModel();
  return m;
}

fcl::Transform3d fcl_transform(const Affine& t) {
  fcl::Transform3d f = fcl::Transform3d::Identity();
  f.linear() = t.linear();
  f.translation() = t.translation();
  return f;
}

}  // namespace

struct FclPeer::Impl {
  const Scene* scene = nullptr;
  std::vector<std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>>> models;
  // One object per part, re-posed per state (setTransform + computeAABB), so
  // a state costs FCL no allocation, as in a broadphase manager.
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
  std::vector<int> chain;  // per part: chain id or -1
  std::vector<std::pair<int, int>> pairs;
  mutable std::vector<Affine> chains;
};

FclPeer::FclPeer(const Scene& scene, const std::vector<const Mesh*>& meshes,
                 std::vector<std::pair<int, int>> pairs)
    : impl_(std::make_unique<Impl>()) {
  impl_->scene = &scene;
  impl_->pairs = std::move(pairs);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    auto m = obbrss_model(*meshes[i]);
    impl_->models.push_back(m);
    impl_->objects.push_back(std::make_unique<fcl::CollisionObjectd>(m));
    impl_->chain.push_back(i < scene.parts.size() && scene.parts[i].moving() ? scene.parts[i].chain_id
                                                                              : -1);
  }
}

FclPeer::~FclPeer() = default;

std::size_t FclPeer::memory_bytes() const {
  std::size_t n = 0;
  // BVHModel::memUsage returns a status, not the size: count what it would
  // print (nodes with their OBBRSS, triangles, vertices, primitive indices).
  for (const auto& m : impl_->models)
    n += sizeof(fcl::BVNode<fcl::OBBRSSd>) * static_cast<std::size_t>(m->getNumBVs()) +
         (sizeof(fcl::Triangle) + sizeof(unsigned int)) * static_cast<std::size_t>(m->num_tris) +
         sizeof(fcl::Vector3d) * static_cast<std::size_t>(m->num_vertices);
  return n;
}

FclPeer::Answer FclPeer::check(const std::vector<double>& params, bool with_distance,
                               double rel_err) const {
  Impl& im = *impl_;
  chain_transforms(*im.scene, params, im.chains);
  for (std::size_t i = 0; i < im.objects.size(); ++i) {
    const int c = im.chain[i];
    if (c < 0) continue;  // static parts keep the identity set at construction
    im.objects[i]->setTransform(fcl_transform(im.chains[static_cast<std::size_t>(c)]));
    im.objects[i]->computeAABB();
  }
  Answer answer;
  answer.distance = std::numeric_limits<double>::infinity();
  fcl::DistanceRequestd dreq;
  dreq.rel_err = rel_err;
  fcl::DistanceResultd dres;  // shared: its min_distance bounds every later pair
  for (const auto& [a, b] : im.pairs) {
    const fcl::CollisionObjectd* oa = im.objects[static_cast<std::size_t>(a)].get();
    const fcl::CollisionObjectd* ob = im.objects[static_cast<std::size_t>(b)].get();
    // World boxes first, as a broadphase manager would: pairs whose AABBs
    // are apart are neither collided nor, when the gap exceeds the best
    // distance so far, distanced.
    const double gap = oa->getAABB().distance(ob->getAABB());
    bool hit = false;
    if (gap <= 0.0) {
      fcl::CollisionRequestd creq;
      fcl::CollisionResultd cres;
      fcl::collide(oa, ob, creq, cres);
      hit = cres.isCollision();
    }
    if (hit) {
      answer.collision = true;
      answer.distance = 0.0;
      continue;
    }
    if (answer.collision || !with_distance || gap >= dres.min_distance) continue;
    fcl::distance(oa, ob, dreq, dres);
    answer.distance = std::min(answer.distance, dres.min_distance);
  }
  if (!with_distance && !answer.collision) answer.distance = std::numeric_limits<double>::infinity();
  return answer;
}

struct FclMeshPair::Impl {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> a, b;
};

FclMeshPair::FclMeshPair(const Mesh& a, const Mesh& b) : impl_(std::make_unique<Impl>()) {
  impl_->a = obbrss_model(a);
  impl_->b = obbrss_model(b);
}

FclMeshPair::~FclMeshPair() = default;

FclAnswer FclMeshPair::check(const Affine& ta, const Affine& tb, bool with_distance) const {
  const fcl::Transform3d fa = fcl_transform(ta), fb = fcl_transform(tb);
  FclAnswer answer;
  answer.distance = std::numeric_limits<double>::infinity();
  fcl::CollisionRequestd creq;
  fcl::CollisionResultd cres;
  fcl::collide(impl_->a.get(), fa, impl_->b.get(), fb, creq, cres);
  if (cres.isCollision()) {
    answer.collision = true;
    answer.distance = 0.0;
    return answer;
  }
  if (!with_distance) return answer;
  fcl::DistanceRequestd dreq;
  fcl::DistanceResultd dres;
  fcl::distance(impl_->a.get(), fa, impl_->b.get(), fb, dreq, dres);
  answer.distance = dres.min_distance;
  return answer;
}

}  // namespace plancheck::reference

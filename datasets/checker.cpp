// SPDX-License-Identifier: MIT
#include "datasets/checker.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plancheck::dataset {
namespace {

// Closest point on triangle abc to p (Voronoi-region walk, Ericson 5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  Vec3 ab = b - a, ac = c - a, ap = p - a;
  double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  Vec3 bp = p - b;
  double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  Vec3 cp = p - c;
  double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Squared distance between segments p1q1 and p2q2 (Ericson 5.1.9).
double segment_distance2(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
  Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  const double eps = 1e-30;
  if (a <= eps && e <= eps) return r.squaredNorm();
  if (a <= eps) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    double c = d1.dot(r);
    if (e <= eps) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p1 + d1 * s) - (p2 + d2 * t)).squaredNorm();
}

// Does segment pq cross triangle abc (including touching)?
bool segment_hits_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  Vec3 n = (b - a).cross(c - a);
  double dp = n.dot(p - a), dq = n.dot(q - a);
  if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0)) return false;
  if (dp == dq) return false;  // parallel to the plane: left to the edge distances
  Vec3 x = p + (q - p) * (dp / (dp - dq));
  // Inside test by signed areas against the normal.
  double s1 = n.dot((b - a).cross(x - a)), s2 = n.dot((c - b).cross(x - b)), s3 = n.dot((a - c).cross(x - c));
  return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

Eigen::AlignedBox3d box_of(const Triangle& t) {
  Eigen::AlignedBox3d b(t.p[0]);
  b.extend(t.p[1]);
  b.extend(t.p[2]);
  return b;
}

double box_distance(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
  Vec3 gap = (a.min() - b.max()).cwiseMax(b.min() - a.max()).cwiseMax(0.0);
  return gap.norm();
}

Vec3 rounded(const Vec3& v) {
  // The file stores floats: check what the verifier will read.
  return Vec3(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
}

}  // namespace

double triangle_distance(const Triangle& a, const Triangle& b) {
  for (int i = 0; i < 3; ++i) {
    if (segment_hits_triangle(a.p[i], a.p[(i + 1) % 3], b.p[0], b.p[1], b.p[2])) return 0.0;
    if (segment_hits_triangle(b.p[i], b.p[(i + 1) % 3], a.p[0], a.p[1], a.p[2])) return 0.0;
  }
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    best = std::min(best, (a.p[i] - closest_on_triangle(a.p[i], b.p[0], b.p[1], b.p[2])).squaredNorm());
    best = std::min(best, (b.p[i] - closest_on_triangle(b.p[i], a.p[0], a.p[1], a.p[2])).squaredNorm());
    for (int j = 0; j < 3; ++j)
      best = std::min(best, segment_distance2(a.p[i], a.p[(i + 1) % 3], b.p[j], b.p[(j + 1) % 3]));
  }
  return std::sqrt(best);
}

Checker::Checker(const Model& model, const std::vector<double>& dem,
                 const std::vector<std::pair<std::string, std::string>>& allowed, double cutoff)
    : cutoff_(cutoff) {
  for (const auto& [a, b] : allowed) {
    allowed_.insert({a, b});
    allowed_.insert({b, a});
  }
  int arm = model.find("arm");
  const char* joints[4] = {"J1", "J2", "J3", "J4"};
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    const ModelNode& n = model.nodes[i];
    if (n.mesh.triangles.empty()) continue;
    std::vector<Triangle> tris;
    for (const Tri& t : n.mesh.triangles)
      tris.push_back({{rounded(n.mesh.vertices[t[0]]), rounded(n.mesh.vertices[t[1]]), rounded(n.mesh.vertices[t[2]])}});
    if (model.in_subtree(static_cast<int>(i), arm)) {
      int chain = -1;
      for (int k = 0; k < 4; ++k)
        if (model.in_subtree(static_cast<int>(i), model.find(joints[k]))) chain = k;
      Eigen::AlignedBox3d box;
      std::vector<Eigen::AlignedBox3d> clusters;
      for (std::size_t k = 0; k < tris.size(); ++k) {
        if (k % kCluster == 0) clusters.emplace_back(box_of(tris[k]));
        else clusters.back().extend(box_of(tris[k]));
        box.extend(box_of(tris[k]));
      }
      moving_.push_back({n.name, chain, std::move(tris), box, std::move(clusters)});
    } else {
      int owner = static_cast<int>(static_parts_.size());
      Eigen::AlignedBox3d box;
      std::size_t first = static_tris_.size();
      for (const Triangle& t : tris) {
        box.extend(box_of(t));
        static_tris_.push_back(t);
        static_owner_.push_back(owner);
      }
      static_parts_.push_back({n.name, box, first, tris.size(), {}});
    }
  }
  // The DEM as two triangles per square between cell centres.
  {
    int owner = static_cast<int>(static_parts_.size());
    Eigen::AlignedBox3d box;
    std::size_t first = static_tris_.size();
    const double size = kDemSize * kDemCell;
    auto at = [&](int r, int c) {
      return Vec3(kDemOrigin.x() + (c + 0.5) * kDemCell, kDemOrigin.y() + size - (r + 0.5) * kDemCell,
                  kDemOrigin.z() + dem[static_cast<std::size_t>(r * kDemSize + c)]);
    };
    for (int r = 0; r + 1 < kDemSize; ++r)
      for (int c = 0; c + 1 < kDemSize; ++c) {
        Triangle t1{{at(r, c), at(r + 1, c), at(r + 1, c + 1)}}, t2{{at(r, c), at(r + 1, c + 1), at(r, c + 1)}};
        for (const Triangle& t : {t1, t2}) {
          box.extend(box_of(t));
          static_tris_.push_back(t);
          static_owner_.push_back(owner);
        }
      }
    static_parts_.push_back({"terrain", box, first, static_tris_.size() - first, {}});
  }
  for (const Triangle& t : static_tris_) static_boxes_.push_back(box_of(t));
  for (StaticPart& part : static_parts_) {
    Grid& g = part.grid;
    g.min = part.box.min() - Vec3::Constant(1e-6);
    Vec3 ext = part.box.max() - g.min;
    g.nx = static_cast<int>(ext.x() / cell_) + 1;
    g.ny = static_cast<int>(ext.y() / cell_) + 1;
    g.nz = static_cast<int>(ext.z() / cell_) + 1;
    std::size_t cells = static_cast<std::size_t>(g.nx) * g.ny * g.nz;
    std::vector<std::uint32_t> count(cells + 1, 0);
    for (std::size_t i = part.first; i < part.first + part.count; ++i)
      for_cells(g, static_boxes_[i], [&](std::size_t c) { ++count[c + 1]; });
    for (std::size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
    g.start = count;
    g.items.resize(count.back());
    std::vector<std::uint32_t> fill(count.begin(), count.end() - 1);
    for (std::size_t i = part.first; i < part.first + part.count; ++i)
      for_cells(g, static_boxes_[i], [&](std::size_t c) { g.items[fill[c]++] = static_cast<std::uint32_t>(i); });
  }
}

template <class Fn>
void Checker::for_cells(const Grid& g, const Eigen::AlignedBox3d& b, Fn&& fn) const {
  Vec3 lo = (b.min() - g.min) / cell_, hi = (b.max() - g.min) / cell_;
  int x0 = std::max(0, static_cast<int>(std::floor(lo.x()))), x1 = std::min(g.nx - 1, static_cast<int>(std::floor(hi.x())));
  int y0 = std::max(0, static_cast<int>(std::floor(lo.y()))), y1 = std::min(g.ny - 1, static_cast<int>(std::floor(hi.y())));
  int z0 = std::max(0, static_cast<int>(std::floor(lo.z()))), z1 = std::min(g.nz - 1, static_cast<int>(std::floor(hi.z())));
  for (int z = z0; z <= z1; ++z)
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) fn((static_cast<std::size_t>(z) * g.ny + y) * g.nx + x);
}

bool Checker::allowed(const std::string& a, const std::string& b) const { return allowed_.count({a, b}) > 0; }

StateCheck Checker::check(const Joints& q) const {
  const std::array<Affine, 4> poses = chain_poses(q);
  StateCheck out;
  double best = cutoff_;
  auto consider = [&](double d, const std::string& a, const std::string& b) {
    if (d == 0.0) {
      out.collision = true;
      out.colliding.insert(a < b ? std::make_pair(a, b) : std::make_pair(b, a));
    }
    if (d < best || (d == 0.0 && out.part_a.empty())) {
      best = d;
      out.part_a = a;
      out.part_b = b;
    }
  };
  auto rough = [](const Affine& pose, const Eigen::AlignedBox3d& b) {
    Eigen::AlignedBox3d r;
    for (int k = 0; k < 8; ++k) r.extend(pose * b.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)));
    return r;
  };
  // Two-level pruning: conservative world boxes of whole parts and of
  // clusters of 32 triangles (the reference box's corners posed); a cluster's
  // triangles are posed only when its rough box comes within reach.
  struct Posed {
    Eigen::AlignedBox3d box;                       // rough, whole part
    std::vector<Eigen::AlignedBox3d> rough;        // rough, per cluster
    std::vector<char> done;                        // cluster posed?
    std::vector<Triangle> tris;
    std::vector<Eigen::AlignedBox3d> boxes;        // exact, per posed triangle
    std::vector<Eigen::AlignedBox3d> exact;        // exact, per posed cluster
  };
  std::vector<Posed> posed(moving_.size());
  for (std::size_t m = 0; m < moving_.size(); ++m) {
    const Affine& pose = poses[static_cast<std::size_t>(moving_[m].chain)];
    posed[m].box = rough(pose, moving_[m].box);
  }
  auto cluster_rough = [&](std::size_t m, std::size_t c) -> const Eigen::AlignedBox3d& {
    Posed& p = posed[m];
    if (p.rough.empty()) {
      const Affine& pose = poses[static_cast<std::size_t>(moving_[m].chain)];
      for (const auto& b : moving_[m].cluster_boxes) p.rough.push_back(rough(pose, b));
      p.done.assign(moving_[m].cluster_boxes.size(), 0);
      p.tris.resize(moving_[m].tris.size());
      p.boxes.resize(moving_[m].tris.size());
      p.exact.resize(moving_[m].cluster_boxes.size());
    }
    return p.rough[c];
  };
  auto pose_cluster = [&](std::size_t m, std::size_t c) {
    Posed& p = posed[m];
    cluster_rough(m, c);
    if (p.done[c]) return;
    p.done[c] = 1;
    const Affine& pose = poses[static_cast<std::size_t>(moving_[m].chain)];
    Eigen::AlignedBox3d e;
    for (std::size_t i = c * kCluster; i < std::min(p.tris.size(), (c + 1) * kCluster); ++i) {
      const Triangle& t = moving_[m].tris[i];
      p.tris[i] = Triangle{{pose * t.p[0], pose * t.p[1], pose * t.p[2]}};
      p.boxes[i] = box_of(p.tris[i]);
      e.extend(p.boxes[i]);
    }
    p.exact[c] = e;
  };

  // Per-call dedupe stamps; a thread-local buffer keeps check() const and cheap.
  thread_local std::vector<std::uint32_t> stamp;
  thread_local std::uint32_t epoch = 0;
  if (stamp.size() != static_tris_.size()) {
    stamp.assign(static_tris_.size(), 0);
    epoch = 0;
  }
  // Moving against static.
  for (std::size_t m = 0; m < moving_.size(); ++m) {
    for (std::size_t owner = 0; owner < static_parts_.size(); ++owner) {
      const StaticPart& part = static_parts_[owner];
      if (allowed(moving_[m].name, part.name) || box_distance(posed[m].box, part.box) > best) continue;
      for (std::size_t c = 0; c < moving_[m].cluster_boxes.size(); ++c) {
        if (box_distance(cluster_rough(m, c), part.box) > best) continue;
        pose_cluster(m, c);
        const Posed& p = posed[m];
        if (box_distance(p.exact[c], part.box) > best) continue;
        Eigen::AlignedBox3d q_box = p.exact[c];
        q_box.min() -= Vec3::Constant(best);
        q_box.max() += Vec3::Constant(best);
        ++epoch;
        for_cells(part.grid, q_box, [&](std::size_t cell) {
          for (std::uint32_t k = part.grid.start[cell]; k < part.grid.start[cell + 1]; ++k) {
            std::uint32_t s = part.grid.items[k];
            if (stamp[s] == epoch) continue;
            stamp[s] = epoch;
            if (box_distance(p.exact[c], static_boxes_[s]) > best) continue;
            std::size_t end = std::min(p.tris.size(), (c + 1) * kCluster);
            for (std::size_t i = c * kCluster; i < end; ++i) {
              if (box_distance(p.boxes[i], static_boxes_[s]) > best) continue;
              consider(triangle_distance(p.tris[i], static_tris_[s]), moving_[m].name, part.name);
            }
          }
        });
      }
    }
  }
  // Moving against moving on different chains.
  for (std::size_t a = 0; a < moving_.size(); ++a)
    for (std::size_t b = a + 1; b < moving_.size(); ++b) {
      if (moving_[a].chain == moving_[b].chain || allowed(moving_[a].name, moving_[b].name)) continue;
      if (box_distance(posed[a].box, posed[b].box) > best) continue;
      for (std::size_t ca = 0; ca < moving_[a].cluster_boxes.size(); ++ca) {
        if (box_distance(cluster_rough(a, ca), posed[b].box) > best) continue;
        for (std::size_t cb = 0; cb < moving_[b].cluster_boxes.size(); ++cb) {
          if (box_distance(cluster_rough(a, ca), cluster_rough(b, cb)) > best) continue;
          pose_cluster(a, ca);
          pose_cluster(b, cb);
          const Posed& pa = posed[a];
          const Posed& pb = posed[b];
          if (box_distance(pa.exact[ca], pb.exact[cb]) > best) continue;
          for (std::size_t i = ca * kCluster; i < std::min(pa.tris.size(), (ca + 1) * kCluster); ++i)
            for (std::size_t j = cb * kCluster; j < std::min(pb.tris.size(), (cb + 1) * kCluster); ++j) {
              if (box_distance(pa.boxes[i], pb.boxes[j]) > best) continue;
              consider(triangle_distance(pa.tris[i], pb.tris[j]), moving_[a].name, moving_[b].name);
            }
        }
      }
    }
  out.min_distance = best;
  return out;
}

}  // namespace plancheck::dataset

// SPDX-License-Identifier: MIT
// Pair checking: the Checker poses the parts of one state and runs the pair
// queries (part vs part, part vs terrain). Plans are run and judged in
// plan_check.cpp; reports are written in src/output/.
#include "src/checks/verify.h"
#include "src/checks/built_ahead.h"
#include "src/checks/pair_order.h"

#include "src/base/error.h"
#include "src/base/progress.h"

#include "src/scene/kinematics.h"
#include "src/scene/reach.h"
#include "src/base/parallel.h"
#include "src/scene/terrain.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <latch>
#include <numeric>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace plancheck {

namespace {

// Relative tolerance of the coarse pass's first search, which seeds a cold
// state's distance search (check_pairs). Measured on the default plans, every
// state checked from cold, when every search of the pass used it: 0.1 saves
// 40% of the time, 0.3 to 3 save 57-59% (within noise). Since the later
// searches ask only for anything below the best (see check_pairs), the first
// need only set a bound: 2,000 cold states of the default scene (seed 1,
// thread CPU, min of 7, alternating) took 0.216 / 0.211 s at 1, 0.212 /
// 0.204 s at 2, 0.208 / 0.207 s at 4; once each leaf settles its nearest
// pair first (DistanceQuery::leaves), min of 9, three alternations: 0.200 /
// 0.199 / 0.192 s at 2, 0.190 / 0.195 / 0.184 s at 4, 0.192 / 0.193 /
// 0.184 s at 16.
constexpr double kProbeTolerance = 4.0;

struct Box {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
};

Box mesh_box(const Mesh& mesh) {
  Box b;
  for (const Tri& t : mesh.triangles)
    for (std::uint32_t v : t) {
      b.lo = b.lo.cwiseMin(mesh.vertices[v]);
      b.hi = b.hi.cwiseMax(mesh.vertices[v]);
    }
  return b;
}

// The world box of a posed local box, widened by a relative epsilon so that
// rounding in the transform never separates boxes whose contents touch.
Box posed_box(const Box& local, const Affine& t) {
  const Vec3 c = 0.5 * (local.lo + local.hi);
  const Vec3 h = 0.5 * (local.hi - local.lo);
  const Vec3 wc = t * c;
  const Vec3 wh = t.linear().cwiseAbs() * h;
  const double pad = 1e-9 * (wc.cwiseAbs().maxCoeff() + wh.maxCoeff() + 1.0);
  return {wc - wh - Vec3::Constant(pad), wc + wh + Vec3::Constant(pad)};
}

// std::max(x, 0.0), without a branch: (x < 0) ? 0 : x, so NaN and -0.0
// stay as they are. GCC compiles std::max(x, 0.0) to a compare and a jump,
// which mispredicts on box gaps (some axes apart, some overlapping): on the
// default plans' collision-only check that was most of a state's time.
// maxsd(a, b) is (a > b) ? a : b, the same value bit for bit.
inline double max0(double x) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_max_sd(_mm_setzero_pd(), _mm_set_sd(x)));
#else
  return std::max(x, 0.0);
#endif
}

// Squared distance between two boxes; 0 when they meet. A state computes
// one per checked pair (over a hundred on the default scene), so this stays
// a few scalar operations the compiler can inline, without branches.
inline double box_gap2(const Box& a, const Box& b) {
#if defined(__SSE2__)
  // x and y in the two lanes of one register, z alone: the same
  // operations per axis (std::max(u, v) is maxpd(v, u)), summed in the same
  // order (0 + x^2 is x^2: a square is +0, positive or NaN).
  const __m128d u = _mm_sub_pd(_mm_loadu_pd(a.lo.data()), _mm_loadu_pd(b.hi.data()));
  const __m128d v = _mm_sub_pd(_mm_loadu_pd(b.lo.data()), _mm_loadu_pd(a.hi.data()));
  const __m128d g = _mm_max_pd(_mm_setzero_pd(), _mm_max_pd(v, u));
  const __m128d sq = _mm_mul_pd(g, g);
  const double xy = _mm_cvtsd_f64(_mm_add_sd(sq, _mm_unpackhi_pd(sq, sq)));
  const double gz = max0(std::max(a.lo[2] - b.hi[2], b.lo[2] - a.hi[2]));
  return xy + gz * gz;
#else
  double s = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double g = max0(std::max(a.lo[i] - b.hi[i], b.lo[i] - a.hi[i]));
    s += g * g;
  }
  return s;
#endif
}

// The distance between two boxes (pair_distance's lower bound before any search).
inline double box_gap(const Box& a, const Box& b) {
  const double g2 = box_gap2(a, b);
  return g2 > 0.0 ? std::sqrt(g2) : 0.0;
}

// What settles a margin comparison of a pair in double, from its two parts'
// magnitudes (Checker::part_magnitude).
inline double magnitude_guard(double mag_a, double mag_b) {
  return std::max(kDistanceTolerance, 64.0 * std::numeric_limits<double>::epsilon() * std::max(mag_a, mag_b));
}

// The terrain's box: its pyramid's root, padded as a static part's box.
// What a state proves of pairs [0, n) for the next (the seed's
// separations): each pair's lower bound l = std::max(sqrt(g2[k]),
// carried[k]) (carried null: 0), or 0 where l or lower[k] is not finite
// (lower[k] infinite marks a pair outside the check). l is the pair loop's
// bound bit for bit: its gap is sqrt(g2) (g2 is +0, positive, infinite or
// NaN, and sqrt(+0) is +0), and std::max(a, b) is (a < b) ? b : a, which
// maxpd(b, a) ((b > a) ? b : a) is too. `out` may be `carried`: each entry
// is read before it is written. Two pairs a step without branches: the
// verdict-only plan path's pairs beyond the cutoff take their root here
// instead of in the pair loop.
void prove_bounds(const double* g2, const double* carried, const double* lower, double* out, std::size_t n) {
  std::size_t k = 0;
#if defined(__SSE2__)
  const __m128d inf = _mm_set1_pd(std::numeric_limits<double>::infinity());
  const __m128d sign = _mm_set1_pd(-0.0);
  for (; k + 2 <= n; k += 2) {
    const __m128d root = _mm_sqrt_pd(_mm_loadu_pd(g2 + k));
    const __m128d c = carried ? _mm_loadu_pd(carried + k) : _mm_setzero_pd();
    const __m128d l = _mm_max_pd(c, root);
    // |x| < inf: false for infinities and NaN.
    const __m128d finite = _mm_and_pd(_mm_cmplt_pd(_mm_andnot_pd(sign, l), inf),
                                      _mm_cmplt_pd(_mm_andnot_pd(sign, _mm_loadu_pd(lower + k)), inf));
    _mm_storeu_pd(out + k, _mm_and_pd(finite, l));
  }
#endif
  for (; k < n; ++k) {
    const double l = std::max(std::sqrt(g2[k]), carried ? carried[k] : 0.0);
    out[k] = std::isfinite(l) && std::isfinite(lower[k]) ? l : 0.0;
  }
}

Box terrain_root_box(const Heightfield& terrain) {
  double lo[3], hi[3];
  terrain.block_box(static_cast<int>(terrain.levels().size()) - 1, 0, 0, lo, hi);
  return posed_box({Vec3(lo[0], lo[1], lo[2]), Vec3(hi[0], hi[1], hi[2])}, Affine::Identity());
}

// Whether a distance search at transforms (ta, tb) with request q has
// bitwise the inputs of `last` (so distance() would return last.result).
bool same_search(const StateSeed::Search& last, const Affine& ta, const Affine& tb, const DistanceRequest& q) {
  const auto same = [](double x, double y) { return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y); };
  // An affine map is its top three rows (the last is never read).
  const auto same_map = [&](const Affine& x, const Affine& y) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 3; ++r)
        if (!same(x.matrix()(r, c), y.matrix()(r, c))) return false;
    return true;
  };
  const DistanceRequest& p = last.request;
  return same_map(last.ta, ta) && same_map(last.tb, tb) &&
         same(p.upper_bound, q.upper_bound) && same(p.rel_tolerance, q.rel_tolerance) &&
         same(p.abs_tolerance, q.abs_tolerance) && p.seed_slot_a == q.seed_slot_a &&
         p.seed_slot_b == q.seed_slot_b && p.first_below == q.first_below &&
         p.known_disjoint == q.known_disjoint && p.leaf_cull == q.leaf_cull &&
         p.tie_cull == q.tie_cull;
}

}  // namespace

namespace {

bool same_mesh(const Mesh& a, const Mesh& b) {
  return a.vertices.size() == b.vertices.size() && a.triangles.size() == b.triangles.size() &&
         std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(Vec3)) == 0 &&
         std::memcmp(a.triangles.data(), b.triangles.data(), a.triangles.size() * sizeof(Tri)) == 0;
}

}  // namespace

Checker::InstanceId::InstanceId() {
  static std::atomic<std::uint64_t> last{0};
  value = last.fetch_add(1, std::memory_order_relaxed) + 1;
}

Checker::Checker(const Scene& scene, int threads, const BuiltAhead* ahead, const Checker* reuse)
    : scene_(scene), chain_prefixes_(chain_prefixes(scene)), motion_(scene) {
  std::vector<const Mesh*> meshes;
  for (const Part& p : scene.parts) {
    names_.push_back(p.name);
    meshes.push_back(&p.mesh);
    chain_of_.push_back(p.moving() ? p.chain_id : -1);
    if (p.moving()) moving_parts_.push_back(static_cast<int>(names_.size()) - 1);
  }
  // The terrain is a heightfield, never a BVH over its triangles. Its mesh
  // is drawn only to bound the minimum distance for pruning (below), and
  // only when nothing digs it: a dug terrain's vertices move, so its
  // undisturbed vertices bound nothing.
  Mesh terrain_mesh;
  const bool terrain = scene.terrain && scene.terrain->collide;
  const bool dug = terrain && scene.scoop;
  if (terrain) {
    const Dem& dem = *scene.terrain->grid;
    if (reuse != nullptr && reuse->terrain_ && reuse->scene_.terrain && reuse->scene_.terrain->grid == scene.terrain->grid &&
        reuse->scene_.terrain->origin == scene.terrain->origin)
      terrain_ = reuse->terrain_;  // the same grid at the same place
    else
      terrain_ = std::make_shared<const Heightfield>(dem, scene.terrain->origin);
    if (!dug) terrain_mesh = dem_mesh(dem, scene.terrain->origin);
    names_.push_back("terrain");
    meshes.push_back(&terrain_mesh);
    chain_of_.push_back(-1);
    terrain_index_ = static_cast<int>(names_.size()) - 1;
  }

  // The moving part first in each pair, as reports name them (arm part, then what it meets).
  for (const CheckedPair& p : scene.checked_pairs) {
    if (chain_of_[static_cast<std::size_t>(p.a)] < 0 && chain_of_[static_cast<std::size_t>(p.b)] >= 0)
      pairs_.push_back({p.b, p.a});
    else
      pairs_.push_back({p.a, p.b});
  }
  if (terrain) {
    const int t = static_cast<int>(names_.size()) - 1;
    for (std::size_t i = 0; i < scene.parts.size(); ++i) {
      if (!scene.parts[i].moving()) continue;
      const auto& allowed = scene.terrain_allowed_parts;
      if (std::find(allowed.begin(), allowed.end(), static_cast<int>(i)) != allowed.end()) continue;
      pairs_.push_back({static_cast<int>(i), t});
      has_terrain_pairs_ = true;
    }
  }

  // The structures are jobs of one queue, taken in this order by the
  // threads as they come free: the probes' ray scene (Embree's BVH over the
  // static parts, from the scene alone: the longest job, so first), then
  // leaving out the static triangles no moving part can reach (kept_ maps
  // back; one thread's job, beside the ray scene), then each part's BVH,
  // the moving parts first (they do not depend on the pruning), then the
  // static ones, largest first so the last jobs are short; a static part
  // waits for the pruning, which decides its mesh. Nothing waits for the
  // pruning to start the ray scene or the moving parts, and the queue keeps
  // both threads busy to its end. Without a ray scene (or a second thread)
  // nothing would run beside the pruning: it runs first, on every thread.
  // A part's box is found beside its BVH.
  std::vector<Mesh> pruned;
  kept_->resize(meshes.size());
  const int job_threads = threads > 0 ? threads : hardware_threads();
  const std::size_t probe_jobs = scene.probes.empty() ? 0 : 1;
  const std::size_t prune_jobs = probe_jobs > 0 && job_threads > 1 ? 1 : 0;
  std::latch pruning_done(1);
  if (prune_jobs == 0) {
    left_out_ = prune_static(scene, meshes, pruned, threads);
    pruning_done.count_down();
  }
  const std::size_t part_count = scene.parts.size();  // meshes[part_count]: the terrain's, for pruning only
  std::vector<std::size_t> order(part_count);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if ((chain_of_[a] >= 0) != (chain_of_[b] >= 0)) return chain_of_[a] >= 0;
    return meshes[a]->triangles.size() > meshes[b]->triangles.size();
  });
  std::vector<std::optional<CollisionModel>> built(part_count);
  std::vector<Box> boxes(part_count);
  const std::size_t jobs = probe_jobs + prune_jobs + part_count;
  const auto run_job = [&](std::size_t job) {
    if (job < probe_jobs) {
      probes_ = std::make_shared<const ProbeCaster>(scene);
    } else if (job < probe_jobs + prune_jobs) {
      struct CountDown {
        std::latch& latch;
        ~CountDown() { latch.count_down(); }  // also when pruning throws: no thread waits forever
      } count_down{pruning_done};
      left_out_ = prune_static(scene, meshes, pruned, 1);
    } else {
      const std::size_t part = order[job - probe_jobs - prune_jobs];
      if (chain_of_[part] < 0) pruning_done.wait();
      const int earlier = reuse != nullptr ? reuse->scene_.find_part(scene.parts[part].name) : -1;
      if (earlier >= 0 && (*reuse->kept_)[static_cast<std::size_t>(earlier)] == (*kept_)[part] &&
          same_mesh(reuse->scene_.parts[static_cast<std::size_t>(earlier)].mesh, scene.parts[part].mesh))
        built[part].emplace(reuse->models_[static_cast<std::size_t>(earlier)].shared_data());
      else if (auto data = ahead != nullptr ? ahead->find(*meshes[part]) : nullptr)
        built[part].emplace(std::move(data));  // built from this very mesh (BuiltAhead)
      else
        built[part].emplace(*meshes[part]);
      boxes[part] = mesh_box(*meshes[part]);
    }
  };
  run_queue(jobs, job_threads, run_job);
  for (auto& m : built) models_.push_back(std::move(*m));
  for (PairRef& p : pairs_)
    p.empty = models_[static_cast<std::size_t>(p.a)].triangle_count() == 0 ||
              (p.b != terrain_index_ && models_[static_cast<std::size_t>(p.b)].triangle_count() == 0);
  // What the verdict-only cutoff's guard scales with (check_pairs): the
  // parts of the checked pairs, and twice the undisturbed terrain's root
  // magnitude (a dug copy reaches lower by at most a scoop's depth, far less
  // than the terrain's extent).
  std::vector<char> in_pair(models_.size(), 0);
  for (const PairRef& p : pairs_) {
    if (p.empty) continue;
    in_pair[static_cast<std::size_t>(p.a)] = 1;
    if (p.b != terrain_index_) {
      in_pair[static_cast<std::size_t>(p.b)] = 1;
    } else if (terrain_) {
      double lo[3], hi[3];
      terrain_->block_box(static_cast<int>(terrain_->levels().size()) - 1, 0, 0, lo, hi);
      for (int k = 0; k < 3; ++k) terrain_magnitude_ = std::max({terrain_magnitude_, 2.0 * std::abs(lo[k]), 2.0 * std::abs(hi[k])});
    }
  }
  for (std::size_t i = 0; i < in_pair.size(); ++i)
    if (in_pair[i]) guard_parts_.push_back(static_cast<int>(i));
  placement_.assign(models_.size(), Affine::Identity());
  for (const Box& b : boxes) {
    local_boxes_.emplace_back(b.lo, b.hi);
    // Static parts never move: their world box (the very value a state
    // would compute with the identity) is computed here once.
    const Box w = posed_box(b, Affine::Identity());
    static_boxes_.emplace_back(w.lo, w.hi);
  }
  set_gap_rows();
  if (terrain_ && terrain_->triangle_count() > 0) {
    const Box t = terrain_root_box(*terrain_);
    terrain_box_ = {t.lo, t.hi};
  }
  // The parts of the verdict-only guard (check_pairs) that never move, with
  // the terrain, folded into one magnitude here, and every part's own-frame
  // magnitude: a state computes only its moving parts' world boxes' (a
  // maximum of finite values, so the same in any order).
  auto mag = [](const Vec3& lo, const Vec3& hi) { return std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()); };
  for (const auto& [lo, hi] : local_boxes_) local_magnitude_.push_back(mag(lo, hi));
  static_magnitude_ = terrain_magnitude_;
  for (int i : guard_parts_) {
    const std::size_t p = static_cast<std::size_t>(i);
    if (chain_of_[p] >= 0)
      moving_guard_parts_.push_back(i);
    else
      static_magnitude_ = std::max(static_magnitude_, std::max(mag(static_boxes_[p].first, static_boxes_[p].second), local_magnitude_[p]));
  }
  if (scene.scoop && scene.terrain) digger_ = std::make_shared<const Digger>(scene);
}

void Checker::set_gap_rows() {
  gap_rows_.clear();
  other_gap_pairs_.clear();
  std::vector<int> group(names_.size(), -1);  // moving part -> its entry in gap_rows_
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const PairRef& p = pairs_[k];
    const bool grouped = !p.empty && chain_of_[static_cast<std::size_t>(p.a)] >= 0 && p.b != terrain_index_ &&
                         chain_of_[static_cast<std::size_t>(p.b)] < 0;
    if (!grouped) {
      other_gap_pairs_.push_back(static_cast<std::uint32_t>(k));
      continue;
    }
    int& g = group[static_cast<std::size_t>(p.a)];
    if (g < 0) {
      g = static_cast<int>(gap_rows_.size());
      gap_rows_.push_back(GapRows{});
      gap_rows_.back().part = p.a;
    }
    gap_rows_[static_cast<std::size_t>(g)].pairs.push_back(static_cast<std::uint32_t>(k));
  }
  // Clusters: the partners split in halves (an even count on the left, so
  // two-pair steps stay whole) across the widest spread of their box
  // centres, down to at most kClusterSize.
  constexpr std::size_t kClusterSize = 4;
  for (GapRows& rows : gap_rows_) {
    const auto& boxes = static_boxes_;
    const auto partner_box = [&](std::uint32_t k) -> const std::pair<Vec3, Vec3>& {
      return boxes[static_cast<std::size_t>(pairs_[k].b)];
    };
    std::vector<std::uint32_t>& pairs = rows.pairs;
    const auto split = [&](const auto& self, std::size_t begin, std::size_t end) -> void {
      if (end - begin <= kClusterSize) {
        rows.ends.push_back(static_cast<std::uint32_t>(end));
        return;
      }
      Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (std::size_t i = begin; i < end; ++i) {
        const auto& [blo, bhi] = partner_box(pairs[i]);
        lo = lo.cwiseMin(blo + bhi);
        hi = hi.cwiseMax(blo + bhi);
      }
      int axis = 0;
      (hi - lo).maxCoeff(&axis);
      std::stable_sort(pairs.begin() + static_cast<std::ptrdiff_t>(begin), pairs.begin() + static_cast<std::ptrdiff_t>(end),
                       [&](std::uint32_t x, std::uint32_t y) {
                         const auto& [xlo, xhi] = partner_box(x);
                         const auto& [ylo, yhi] = partner_box(y);
                         return xlo[axis] + xhi[axis] < ylo[axis] + yhi[axis];
                       });
      const std::size_t half = ((end - begin + 1) / 2 + 1) / 2 * 2;
      self(self, begin, begin + half);
      self(self, begin + half, end);
    };
    split(split, 0, pairs.size());
    // Blocks of two: box j of a block sits in lane j % 2 of each coordinate.
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const std::array<double, 6> never = {kInf, kInf, kInf, -kInf, -kInf, -kInf};  // meets nothing
    const auto put = [](std::vector<double>& blocks, std::size_t j, const std::array<double, 6>& b) {
      if (blocks.size() < (j / 2 + 1) * 12) blocks.resize((j / 2 + 1) * 12, 0.0);
      for (std::size_t i = 0; i < 6; ++i) blocks[j / 2 * 12 + 2 * i + j % 2] = b[i];
    };
    // The unions, exact (minima and maxima of finite values).
    rows.root = never;
    const std::vector<std::uint32_t> order = pairs;
    // A NaN in a partner's box (a world object placed beyond the range of
    // doubles) would be lost in a minimum: such a part's unions are NaN,
    // whose gap is NaN, never apart.
    bool nan = false;
    for (std::uint32_t k : order) nan = nan || partner_box(k).first.hasNaN() || partner_box(k).second.hasNaN();
    std::vector<std::uint32_t> ends;
    ends.swap(rows.ends);
    pairs.clear();
    std::size_t begin = 0;
    for (std::size_t c = 0; c < ends.size(); ++c) {
      const std::size_t end = ends[c];
      std::array<double, 6> u = never;
      for (std::size_t j = begin; j < end; ++j) {
        const auto& [lo, hi] = partner_box(order[j]);
        const std::array<double, 6> b = {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
        put(rows.boxes, pairs.size(), b);
        pairs.push_back(order[j]);
        for (std::size_t i = 0; i < 3; ++i) {
          u[i] = std::min(u[i], b[i]);
          u[3 + i] = std::max(u[3 + i], b[3 + i]);
        }
      }
      if (pairs.size() % 2 == 1) {  // each cluster starts a block (only the last one's count is odd)
        put(rows.boxes, pairs.size(), never);
        pairs.push_back(static_cast<std::uint32_t>(pairs_.size()));
      }
      rows.ends.push_back(static_cast<std::uint32_t>(pairs.size() / 2));
      if (nan) u.fill(std::numeric_limits<double>::quiet_NaN());
      put(rows.clusters, c, u);
      for (std::size_t i = 0; i < 3; ++i) {
        rows.root[i] = std::min(rows.root[i], u[i]);
        rows.root[3 + i] = std::max(rows.root[3 + i], u[3 + i]);
      }
      begin = end;
    }
    if (ends.size() % 2 == 1) put(rows.clusters, ends.size(), never);
    if (nan) rows.root.fill(std::numeric_limits<double>::quiet_NaN());
  }
}

bool Checker::terrain_box(const Heightfield* field, Vec3& lo, Vec3& hi) const {
  const Heightfield* f = field ? field : terrain_.get();
  if (!(f && f->triangle_count() > 0)) return false;
  const Box b = terrain_root_box(*f);
  lo = b.lo;
  hi = b.hi;
  return true;
}

const BoxMotion& Checker::box_motion() const {
  LazyBoxMotion& lazy = *box_motion_;
  std::call_once(lazy.once, [&] { lazy.box = std::make_unique<const BoxMotion>(scene_, BoxMotion::Points::kTriangles); });
  return *lazy.box;
}

std::unique_ptr<const Checker> Checker::with_placement(int part, const Affine& placement) const {
  const std::size_t p = static_cast<std::size_t>(part);
  if (part < 0 || p >= scene_.parts.size() || chain_of_[p] >= 0 ||
      !scene_.nodes[static_cast<std::size_t>(scene_.parts[p].node)].object || !(*kept_)[p].empty())
    throw std::logic_error("with_placement: not a static world object kept whole");
  std::unique_ptr<Checker> c(new Checker(*this));
  c->placement_[p] = placement;
  const Box w = posed_box({local_boxes_[p].first, local_boxes_[p].second}, placement);
  c->static_boxes_[p] = {w.lo, w.hi};
  c->set_gap_rows();
  // The guard's static magnitude again, as the constructor folds it.
  auto mag = [](const Vec3& lo, const Vec3& hi) { return std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()); };
  c->static_magnitude_ = terrain_magnitude_;
  for (int i : guard_parts_) {
    const std::size_t q = static_cast<std::size_t>(i);
    if (chain_of_[q] < 0)
      c->static_magnitude_ = std::max(c->static_magnitude_, std::max(mag(c->static_boxes_[q].first, c->static_boxes_[q].second), local_magnitude_[q]));
  }
  return c;
}

// Soundness: let U bound the state's minimum distance from above in every
// pose: for any checked (moving m, static s) pair and vertices x of m, y of
// s, |posed x - y| <= R(x) + |p_1 - y|. A static triangle T with
// dist(T, p_1(m)) - r_max(m) > U for each moving partner m is then farther
// from every partner than U in every pose: it never touches one, and never
// holds the minimum, which is at most U. So verdicts, distances and contacts
// are unchanged. Distances are taken with a relative slack for rounding.
std::size_t Checker::prune_static(const Scene& scene, std::vector<const Mesh*>& meshes,
                                  std::vector<Mesh>& storage, int threads) {
  const std::size_t n = meshes.size();
  storage.resize(n);  // before any pointer into it is taken
  std::vector<std::vector<int>> partners(n);
  const auto is_object = [&](std::size_t p) {
    return p < scene.parts.size() && scene.nodes[static_cast<std::size_t>(scene.parts[p].node)].object;
  };
  for (const PairRef& p : pairs_) {
    if (chain_of_[static_cast<std::size_t>(p.b)] < 0) partners[static_cast<std::size_t>(p.b)].push_back(p.a);
    if (chain_of_[static_cast<std::size_t>(p.a)] < 0) partners[static_cast<std::size_t>(p.a)].push_back(p.b);
  }
  // The passes below are independent per part (the reaches per moving
  // partner, the nearest vertices and the kept triangles per static part),
  // so they run in parallel; the upper bound is a minimum, exact in any order.
  std::vector<Reach> reach(n);
  std::vector<char> is_partner(n, 0);
  for (std::size_t s = 0; s < n; ++s)
    if (chain_of_[s] < 0)
      for (int m : partners[s]) is_partner[static_cast<std::size_t>(m)] = 1;
  std::vector<std::size_t> movers;
  for (std::size_t m = 0; m < n; ++m)
    if (is_partner[m]) movers.push_back(m);
  parallel_for(movers.size(), threads, 1, [&](std::size_t begin, std::size_t end, int) {
    for (std::size_t i = begin; i < end; ++i) {
      const std::size_t m = movers[i];
      reach[m] = part_reach(scene, scene.parts[m].chain, *meshes[m]);
    }
  });
  for (std::size_t m : movers)
    if (!reach[m].bounded) return 0;  // a partner without a reach bound: keep everything
  // A static part's partners on chains from one first pivot share their
  // centre p_1 (on an arm, all of them): each distance to a centre is
  // computed once per centre, not once per partner (the same expressions,
  // so the same values).
  const auto same_centre = [](const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), sizeof(Vec3)) == 0; };
  std::vector<double> part_upper(n, std::numeric_limits<double>::infinity());
  parallel_for(n, threads, 1, [&](std::size_t begin, std::size_t end, int) {
    for (std::size_t s = begin; s < end; ++s) {
      // A world object may move (with_placement): the bound must hold wherever it stands.
      if (chain_of_[s] >= 0 || is_object(s)) continue;
      std::vector<std::pair<Vec3, double>> nearest_to;  // per distinct centre
      for (int m : partners[s]) {
        const Reach& rm = reach[static_cast<std::size_t>(m)];
        auto it = std::find_if(nearest_to.begin(), nearest_to.end(),
                               [&](const auto& e) { return same_centre(e.first, rm.centre); });
        if (it == nearest_to.end()) {
          // (An empty mesh, the dug terrain, gives infinity: no bound from it.)
          double nearest = std::numeric_limits<double>::infinity();
          for (const Tri& t : meshes[s]->triangles)
            for (std::uint32_t v : t) nearest = std::min(nearest, (meshes[s]->vertices[v] - rm.centre).norm());
          it = nearest_to.insert(nearest_to.end(), {rm.centre, nearest});
        }
        part_upper[s] = std::min(part_upper[s], rm.r_min + it->second);
      }
    }
  });
  double upper = std::numeric_limits<double>::infinity();
  for (double u : part_upper) upper = std::min(upper, u);
  // Without any static pair the minimum has no bound here; static parts in
  // no pair are still left out below (nothing ever queries them).
  const double limit = upper * (1.0 + 1e-9) + 1e-9;
  std::vector<std::size_t> dropped_of(n, 0);
  parallel_for(n, threads, 1, [&](std::size_t begin, std::size_t end, int) {
    for (std::size_t s = begin; s < end; ++s) {
      if (chain_of_[s] >= 0 || static_cast<int>(s) == terrain_index_) continue;  // the heightfield culls itself
      if (is_object(s)) continue;  // a world object may move (with_placement): all of it stays
      const Mesh& mesh = *meshes[s];
      // The partners by centre, each centre with its partners' largest
      // r_max: the gap below only shrinks as r_max grows (rounding is
      // monotone), so a triangle is needed by some partner of a centre
      // exactly when it is needed by the one of largest r_max.
      std::vector<std::pair<Vec3, double>> widest;
      for (int m : partners[s]) {
        const Reach& rm = reach[static_cast<std::size_t>(m)];
        auto it = std::find_if(widest.begin(), widest.end(),
                               [&](const auto& e) { return same_centre(e.first, rm.centre); });
        if (it == widest.end())
          widest.emplace_back(rm.centre, rm.r_max);
        else
          it->second = std::max(it->second, rm.r_max);
      }
      std::vector<std::uint32_t> keep;
      for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Tri& tri = mesh.triangles[t];
        // Ball around the triangle: centroid c, radius rho; every point of T is
        // within rho of c, so dist(T, p) >= |c - p| - rho.
        const Vec3 c = (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
        double rho = 0.0;
        for (std::uint32_t v : tri) rho = std::max(rho, (mesh.vertices[v] - c).norm());
        bool needed = false;
        for (const auto& [centre, r_max] : widest) {
          const double gap = (c - centre).norm() - rho - r_max;
          if (!(gap * (1.0 - 1e-9) > limit)) {
            needed = true;
            break;
          }
        }
        if (needed) keep.push_back(static_cast<std::uint32_t>(t));
      }
      if (keep.size() == mesh.triangles.size()) continue;
      dropped_of[s] = mesh.triangles.size() - keep.size();
      Mesh& out = storage[s];
      out.vertices = mesh.vertices;
      out.triangles.reserve(keep.size());
      for (std::uint32_t t : keep) out.triangles.push_back(mesh.triangles[t]);
      (*kept_)[s] = std::move(keep);
      meshes[s] = &out;
    }
  });
  std::size_t dropped = 0;
  for (std::size_t d : dropped_of) dropped += d;
  return dropped;
}

std::size_t Checker::triangle_count() const {
  std::size_t n = terrain_ ? terrain_->triangle_count() : 0;
  for (const auto& m : models_) n += m.triangle_count();
  return n;
}

std::size_t Checker::memory_bytes() const {
  std::size_t n = terrain_ ? terrain_->memory_bytes() : 0;
  for (const auto& m : models_) n += m.memory_bytes();
  return n;
}

void Checker::check_terrain(const std::vector<double>& params, const Heightfield& terrain, StateResult& out,
                            StateSeed* seed, const CheckRequest& request) const {
  StateResult t;
  // A state already colliding needs only the terrain's contacts (and with
  // request.all_contacts false, not even those).
  if (out.collision && !request.all_contacts) return;
  CheckRequest terrain_request = request;
  terrain_request.distance = !out.collision;
  terrain_request.rel_tolerance = 0.0;
  // The search starts below the other pairs' exact minimum; a lower bound
  // (verdict-only) bounds nothing, the request's cutoff does.
  const bool exact_before = !out.collision && !out.distance_is_bound;
  check_pairs(params, t, terrain_request, seed, &terrain, kTerrainPairs,
              exact_before ? out.min_distance : std::numeric_limits<double>::infinity());
  if (t.collision) {
    const bool first = !out.collision;
    for (PairContact& c : t.contacts) out.contacts.push_back(std::move(c));
    out.collision = true;
    if (!first) return;
  } else if (out.collision || (t.part_a < 0 && !t.distance_is_bound) || !(t.min_distance < out.min_distance)) {
    return;
  }
  // The terrain pairs come closer (or are the state's first contact): their
  // distance, exact or a lower bound, is the state's.
  out.distance_is_bound = t.distance_is_bound;
  out.min_distance = t.min_distance;
  out.distance_tolerance = t.distance_tolerance;
  out.part_a = t.part_a;
  out.part_b = t.part_b;
  out.point_a = t.point_a;
  out.point_b = t.point_b;
}

void Checker::check_pairs(const std::vector<double>& params, StateResult& out, const CheckRequest& request,
                          StateSeed* seed, const Heightfield* terrain, PairSet which, double bound) const {
  // A fresh result, keeping the contacts' storage: a colliding state would
  // otherwise free and allocate it again for the next.
  {
    std::vector<PairContact> contacts = std::move(out.contacts);
    contacts.clear();
    out = StateResult{};
    out.contacts = std::move(contacts);
  }
  out.min_distance = bound;
  // Per-thread scratch: a state allocates nothing once its thread has
  // checked one state (collision-only checks take ~2 us, where a handful of
  // heap allocations would show).
  struct Scratch {
    std::vector<Affine> chains;
    std::vector<const Affine*> pose;
    std::vector<Box> box;
    std::vector<double> lower;
    std::vector<std::size_t> order;
    std::vector<double> coarse;      // per pair: lower bound the coarse pass proved (m)
    std::vector<double> motion;      // per part: path length bound since seed->at (m)
    std::vector<double> separation;  // per pair: proven lower bound at this state (m)
    std::vector<double> gap2;        // per pair: its boxes' gap, squared
    std::vector<std::uint32_t> touching;  // pairs whose boxes meet
    std::vector<std::uint8_t> apart_below;  // per pair: its collision test proved nothing of it below `start`
    std::vector<std::size_t> last_order, sorted;  // sort_by_key's start and scratch
    std::vector<std::uint8_t> in_order;
    std::uint64_t statics_of = 0;  // the checker whose static parts pose and box hold (0: none)
  };
  static thread_local Scratch scratch;
  std::vector<Affine>& chains = scratch.chains;
  chain_transforms(scene_, chain_prefixes_, params, chains);
  const std::size_t n = models_.size();
  std::vector<const Affine*>& pose = scratch.pose;
  std::vector<Box>& box = scratch.box;
  // The static parts' poses and boxes are the same in every state: the
  // scratch keeps those of the checker that last used it (a copy of a
  // checker is another checker: InstanceId), and a state writes only its
  // moving parts'. (Copying the 26 static boxes of the default scene was a
  // tenth of a collision-only state.)
  if (scratch.statics_of != id_.value) {
    pose.assign(n, nullptr);
    box.assign(n + 1, Box{});
    for (std::size_t i = 0; i < n; ++i)
      if (chain_of_[i] < 0) {
        pose[i] = &placement_[i];
        box[i] = {static_boxes_[i].first, static_boxes_[i].second};
      }
    scratch.statics_of = id_.value;
  }
  for (int m : moving_parts_) {
    const std::size_t i = static_cast<std::size_t>(m);
    pose[i] = &chains[static_cast<std::size_t>(chain_of_[i])];
    box[i] = posed_box({local_boxes_[i].first, local_boxes_[i].second}, *pose[i]);
    // A pose past the range of doubles (a translation or factor
    // overflowing, a non-finite parameter) leaves no distance to settle:
    // NaN would defeat every pruning test and the search would visit every
    // triangle pair. It is refused, never checked and never "safe".
    if (!(box[i].lo.allFinite() && box[i].hi.allFinite()))
      throw InputError("a configuration poses part '" + names_[i] +
                       "' beyond the range of doubles (a parameter or what it moves is not finite)");
  }

  // The terrain's box: its pyramid's root (the undisturbed terrain's found
  // once, at build).
  Box terrain_box;
  if (terrain && terrain->triangle_count() > 0)
    terrain_box = terrain == terrain_.get() ? Box{terrain_box_.first, terrain_box_.second} : terrain_root_box(*terrain);

  // Largest coordinate of a part's boxes, world and own frame (the terrain:
  // its pyramid's root box): what the double distance's rounding scales with.
  auto pair_magnitude = [&](int i) {
    if (i == terrain_index_) return part_magnitude(i, terrain_box.lo, terrain_box.hi);
    const std::size_t p = static_cast<std::size_t>(i);
    return part_magnitude(i, box[p].lo, box[p].hi);
  };
  // The guard that settles a margin comparison of pair (a, b) in double.
  auto pair_guard = [&](int a, int b) { return magnitude_guard(pair_magnitude(a), pair_magnitude(b)); };
  // Verdict-only: distances are searched only below the cutoff. It lies
  // above exact_below by four times the largest guard G of any checked pair
  // (the terrain's magnitude from the undisturbed terrain, so a state's
  // terrain and other pairs share one cutoff) and the tie tolerance, so a
  // pair the search proves beyond it has a lower bound at least
  // exact_below + 3G (less rounding), above exact_below plus any pair's
  // guard: no margin comparison on it can come out as a violation, and one
  // that can is settled by an exact distance as in the full check.
  const bool verdict_only = request.distance && std::isfinite(request.exact_below);
  double cutoff = std::numeric_limits<double>::infinity();
  double largest_guard = kDistanceTolerance;
  if (verdict_only) {
    // The largest pair guard: that of the largest magnitude of any part in a
    // checked pair (parts once each, not pairs). The static parts' and the
    // terrain's are fixed at build (static_magnitude_); a NaN magnitude
    // (NaN parameters) never raises it, in any order, as std::max keeps its
    // first argument then.
    double m = static_magnitude_;
    for (int i : moving_guard_parts_) m = std::max(m, pair_magnitude(i));
    const double g = std::max(kDistanceTolerance, 64.0 * std::numeric_limits<double>::epsilon() * m);
    largest_guard = g;
    cutoff = request.exact_below + 4.0 * g + kDistanceTieTolerance;
  }
  // Where the distance search starts: only pairs whose lower bound is under
  // it can matter.
  const double start = std::min(bound, cutoff);

  // Separations the seed's state proved, less how far each pair's parts
  // can have moved since: still lower bounds on the pairs' distances here.
  // Pairs on a dug terrain copy are not carried (the ground itself moves).
  const bool terrain_cacheable = terrain == terrain_.get();
  auto cacheable = [&](std::size_t k) { return terrain_cacheable || pairs_[k].b != terrain_index_; };
  static const std::vector<std::uint32_t> kNoKept;  // the terrain's triangles are its own
  std::vector<double>& carried = scratch.separation;
  // A collision-only check proves nothing beyond box gaps, which are cheaper
  // to recompute than the motion bound: it neither reads nor leaves any.
  // Without a seed nothing is carried (0 for every pair, which leaves every
  // box gap as it is: std::max(x, 0.0) is x for any gap, NaN included).
  const bool carry =
      request.distance && seed && seed->separation.size() == pairs_.size() && seed->at.size() == params.size();
  if (carry) {
    carried.resize(pairs_.size());
    std::vector<double>& motion = scratch.motion;
    motion.assign(names_.size(), 0.0);
    for (std::size_t i = 0; i < n; ++i)
      if (chain_of_[i] >= 0) motion[i] = motion_.part_bound(static_cast<int>(i), seed->at, params);
    // Every pair written, without a branch on what it carries (states far
    // apart carry nothing on most pairs, which a branch mispredicts).
    const double* const separation = seed->separation.data();
    double* const carried_at = carried.data();
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      const double m = motion[static_cast<std::size_t>(pairs_[k].a)] + motion[static_cast<std::size_t>(pairs_[k].b)];
      const double c = separation[k] - m;
      carried_at[k] = c > 0.0 && cacheable(k) ? c : 0.0;  // NaN and infinite motion carry nothing
    }
  }

  // Collision: every checked pair whose part boxes meet and whose carried
  // separation does not already prove them apart. Each pair apart joins the
  // distance search's order (all of them in the full check; verdict-only,
  // those under `start`, often a handful) or, beyond it, the bound of the
  // skipped.
  std::vector<double>& lower = scratch.lower;
  // (Collision only: written where read, in the pair loop.)
  if (request.distance)
    lower.assign(pairs_.size(), 0.0);
  else
    lower.resize(pairs_.size());
  // The pairs apart, in visiting order: written by index, not push_back
  // (which GCC stops inlining in a function this long), sized at the end.
  std::vector<std::size_t>& order = scratch.order;
  if (request.distance) order.resize(pairs_.size());  // (collision only: unused; resizing from 0 zeroed it)
  std::size_t ordered = 0;
  // Verdict-only without a seed, a pair beyond `start` needs no square
  // root of its box gap: nothing reads its lower bound but the skipped
  // pairs' minimum, and the least square root is the root of the least
  // square (a correctly rounded root is monotone), taken once. A gap whose
  // square exceeds far2 is at least `start` (far2 is start squared raised
  // by 1e-12, far above the few ulps its rounding costs, so the exact root
  // is above start by 4e-13 of it and rounds to no less); the others get
  // their root and the exact comparison. (Cold states of the default scene
  // have 138 pairs, most of them beyond the cutoff; this and the other cuts
  // of this loop took 2,000 verdict-only states from 0.0325 to 0.0312 s.)
  const bool lazy = verdict_only && !seed;
  // Verdict-only with a seed, the same for each pair beyond far2 that
  // carries nothing (its bound is its box gap): states far apart (a
  // planner's samples written as a plan) carry nothing on most pairs. Such
  // a pair's lower[k] stays 0 (a bound, and finite: nothing after the pair
  // loop reads more of a pair outside `order`), its root joins the skipped
  // pairs' minimum as the root of the least square, and what the state
  // proves of it for the next is rooted after the loop with every pair's
  // (prove_bounds). 2,000 random states of the default arm as one plan:
  // this pair loop cost the plan path ~3k instructions a state more than
  // the cold one's.
  const bool lazy_seeded = verdict_only && seed;
  // (Below 1e-100 the square may be subnormal, rounded too coarsely.)
  const double far2 = start >= 1e-100 ? start * start * (1.0 + 1e-12) : std::numeric_limits<double>::infinity();
  double skipped = std::numeric_limits<double>::infinity();  // lazy: its square
  double skipped_seeded2 = std::numeric_limits<double>::infinity();  // lazy_seeded: the least square of its pairs
  // A pair apart (box gap squared g2, lower bound l) in the distance search.
  auto place = [&](std::size_t k, double l, double g2) {
    if (!verdict_only || l < start)
      order[ordered++] = k;
    else
      skipped = std::min(skipped, lazy ? g2 : l);
  };
  const bool terrain_live = terrain && terrain->triangle_count() > 0;
  // The first contact's answer as distance() gives it (a common point),
  // taken from the collision test itself instead of a second traversal.
  DistanceResult first_contact;
  // Verdict-only with no margin (exact_below 0: the cutoff is the rounding
  // guards, a few 1e-12 m): the collision test also asks whether the pair
  // comes closer than `start` (CollideRequest::near_below, the same
  // traversal, its culls widened by that much); a pair with nothing that
  // close needs no distance search below it, which would find nothing.
  // That search was a second traversal of every pair whose boxes meet and
  // that does not touch (two meshes at random poses: most of them). With a
  // margin the widened culls cost more than the search they save: the
  // search stops at the best bound found so far and colliding states run
  // none, while the widened test runs on every pair before the first
  // contact (2,000 random states of the default arm, instructions in the
  // pair checks: margin 0 147.5 -> 139.9 M, 5 mm 149.7 -> 153.3 M, 5 cm
  // 205 -> 266 M).
  std::vector<std::uint8_t>& apart_below = scratch.apart_below;
  const bool ask_near = verdict_only && request.exact_below <= 0.0 && start > 0.0;
  if (ask_near) apart_below.assign(pairs_.size(), 0);
  auto collide_request = [&] {
    CollideRequest c{request.max_triangle_pairs};
    if (request.distance && out.contacts.empty()) c.contact = &first_contact;
    if (ask_near) c.near_below = start;
    return c;
  };
  // Every pair's box gap (squared) first, in one pass without branches
  // (the terrain's box in the terrain's slot, n), listing the pairs whose
  // boxes meet. Without distances a pair whose boxes are apart does nothing
  // below (its bound is never read), so only those pairs are visited, and
  // only the pairs whose boxes may meet get a gap: the cold states of the
  // default plans have 138 pairs, fewer than one of them touching on
  // average (the collision-only check spent most of a state in this pass).
  box[n] = terrain_box;
  const std::size_t pair_count = pairs_.size();
  std::vector<double>& gap2 = scratch.gap2;
  std::vector<std::uint32_t>& touching = scratch.touching;
  gap2.resize(pair_count + 1);  // [pair_count]: the padding rows' (GapRows)
  touching.resize(pair_count + 1);
  std::size_t touching_count = 0;
  // A moving part against its static partners: their boxes two at a time,
  // with box_gap2's operations in its order; a pair joins `touching`
  // (without a branch) when !(gap2 > 0), in the order of the rows, sorted
  // into pair order below.
  const bool with_distance = request.distance;
  double* const gap2_at = gap2.data();
  std::uint32_t* const touching_at = touching.data();
  for (const GapRows& g : gap_rows_) {
    const Box& m = box[static_cast<std::size_t>(g.part)];
    // The moving box in locals: the stores into gap2 below may alias it
    // as far as the compiler knows, which would reload it every step.
    const double mlo[3] = {m.lo[0], m.lo[1], m.lo[2]};
    const double mhi[3] = {m.hi[0], m.hi[1], m.hi[2]};
#if defined(__SSE2__)
    const __m128d ml[3] = {_mm_set1_pd(mlo[0]), _mm_set1_pd(mlo[1]), _mm_set1_pd(mlo[2])};
    const __m128d mh[3] = {_mm_set1_pd(mhi[0]), _mm_set1_pd(mhi[1]), _mm_set1_pd(mhi[2])};
    // The two gaps, squared, of the moving box to block b's boxes.
    const auto gaps2 = [&](const double* b) {
      __m128d sq[3];
      for (std::size_t i = 0; i < 3; ++i) {
        const __m128d u = _mm_sub_pd(ml[i], _mm_loadu_pd(b + 6 + 2 * i));
        const __m128d v = _mm_sub_pd(_mm_loadu_pd(b + 2 * i), mh[i]);
        const __m128d d = _mm_max_pd(_mm_setzero_pd(), _mm_max_pd(v, u));
        sq[i] = _mm_mul_pd(d, d);
      }
      return _mm_add_pd(_mm_add_pd(sq[0], sq[1]), sq[2]);
    };
#endif
    // The gap, squared, of the moving box to box `lane` of block b.
    [[maybe_unused]] const auto gap2_of = [&](const double* b, std::size_t lane) {
      double sq[3];
      for (std::size_t i = 0; i < 3; ++i) {
        const double d = max0(std::max(mlo[i] - b[6 + 2 * i + lane], b[2 * i + lane] - mhi[i]));
        sq[i] = d * d;
      }
      return (sq[0] + sq[1]) + sq[2];
    };
    // The pairs of blocks [begin, end): their gaps, and those that meet.
    const std::uint32_t* const pairs = g.pairs.data();
    const double* const boxes = g.boxes.data();
    const auto pair_gaps = [&](std::size_t begin, std::size_t end) {
      for (std::size_t j = begin; j < end; ++j) {
        const std::uint32_t k0 = pairs[2 * j], k1 = pairs[2 * j + 1];
#if defined(__SSE2__)
        const __m128d s = gaps2(boxes + 12 * j);
        gap2_at[k0] = _mm_cvtsd_f64(s);
        gap2_at[k1] = _mm_cvtsd_f64(_mm_unpackhi_pd(s, s));
        // Lanes with !(s > 0): NaN too, as the scalar test below.
        const int meet = _mm_movemask_pd(_mm_cmpngt_pd(s, _mm_setzero_pd()));
#else
        gap2_at[k0] = gap2_of(boxes + 12 * j, 0);
        gap2_at[k1] = gap2_of(boxes + 12 * j, 1);
        const int meet = static_cast<int>(!(gap2_at[k0] > 0.0)) | static_cast<int>(!(gap2_at[k1] > 0.0)) << 1;
#endif
        touching_at[touching_count] = k0;
        touching_count += static_cast<std::size_t>(meet & 1);
        touching_at[touching_count] = k1;
        touching_count += static_cast<std::size_t>(meet >> 1);
      }
    };
    const std::uint32_t* const ends = g.ends.data();
    const std::size_t clusters = g.ends.size();
    if (with_distance) {
      pair_gaps(0, clusters == 0 ? 0 : ends[clusters - 1]);  // every pair's gap is a lower bound the search reads
      continue;
    }
    // Collision only: the pairs of the clusters whose union meets the
    // moving box. Apart from a union is apart from every box in it: each
    // axis' difference is monotone in the box's bound (rounding is), so
    // each partner's gap squared is at least the union's, which is > 0.
    // The other pairs' gaps are not written (nothing reads them).
    {
      double sq[3];
      for (std::size_t i = 0; i < 3; ++i) {
        const double d = max0(std::max(mlo[i] - g.root[3 + i], g.root[i] - mhi[i]));
        sq[i] = d * d;
      }
      if ((sq[0] + sq[1]) + sq[2] > 0.0) continue;
    }
    const double* const unions = g.clusters.data();
    for (std::size_t c = 0; c < clusters; c += 2) {
#if defined(__SSE2__)
      const int meet = _mm_movemask_pd(_mm_cmpngt_pd(gaps2(unions + 6 * c), _mm_setzero_pd()));
#else
      const int meet = static_cast<int>(!(gap2_of(unions + 6 * c, 0) > 0.0)) |
                       static_cast<int>(!(gap2_of(unions + 6 * c, 1) > 0.0)) << 1;
#endif
      // (A padding union meets nothing: an odd count's last bit stays 0.)
      if (meet & 1) pair_gaps(c == 0 ? 0 : ends[c - 1], ends[c]);
      if (meet & 2) pair_gaps(ends[c], ends[c + 1]);
    }
  }
  for (std::uint32_t k : other_gap_pairs_) {
    const double g2 = box_gap2(box[static_cast<std::size_t>(pairs_[k].a)], box[static_cast<std::size_t>(pairs_[k].b)]);
    gap2_at[k] = g2;
    touching_at[touching_count] = k;
    touching_count += !(g2 > 0.0);
  }
  // Pair order (the order contacts are found and listed in): a few pairs
  // as a rule, so an insertion sort; std::sort when many boxes meet.
  if (touching_count <= 32) {
    for (std::size_t i = 1; i < touching_count; ++i) {
      const std::uint32_t x = touching[i];
      std::size_t j = i;
      for (; j > 0 && touching[j - 1] > x; --j) touching[j] = touching[j - 1];
      touching[j] = x;
    }
  } else {
    std::sort(touching.begin(), touching.begin() + static_cast<std::ptrdiff_t>(touching_count));
  }
  const std::size_t visits = with_distance ? pair_count : touching_count;
  bool contact_done = false;  // the first contact is in, the rest need only their bounds
  std::size_t v = 0;  // (after the loop: the pair a first contact ended it at, else visits)
  for (; v < visits; ++v) {
    const std::size_t k = with_distance ? v : touching[v];
    const auto [a, b, empty] = pairs_[k];
    const bool on_terrain = b == terrain_index_;
    // Pairs outside `which`, and a part whose triangles were all left out
    // (an empty, inverted box), take no part.
    if (empty || (on_terrain ? (which == kNonTerrainPairs || !terrain_live) : which == kTerrainPairs)) {
      lower[k] = std::numeric_limits<double>::infinity();
      if (with_distance && !verdict_only) order[ordered++] = k;
      continue;
    }
    const double g2 = gap2[k];
    if (lazy && g2 > far2) {
      skipped = std::min(skipped, g2);
      continue;
    }
    if (lazy_seeded && g2 > far2 && (!carry || carried[k] == 0.0)) {
      skipped_seeded2 = std::min(skipped_seeded2, g2);
      continue;
    }
    // The box gap as a lower bound: a distance when distances are asked
    // for, else only its sign matters (no square root).
    const double gap = with_distance && g2 > 0.0 ? std::sqrt(g2) : g2;
    const double l = carry ? std::max(gap, carried[k]) : gap;
    lower[k] = l;
    if (contact_done) continue;  // bounds_after_contact: the bound only
    if (!(l > 0.0)) {
      CollideResult r;
      if (on_terrain) {
        collide(models_[a], *pose[a], *terrain, collide_request(), r);
      } else {
        collide(models_[a], *pose[a], models_[b], *pose[b], collide_request(), r);
        if (ask_near && !r.collide && !r.near) apart_below[k] = 1;
      }
      if (r.collide) {
        // Back to mesh triangle indices where triangles were left out.
        const auto& ka = (*kept_)[static_cast<std::size_t>(a)];
        const auto& kb = on_terrain ? kNoKept : (*kept_)[static_cast<std::size_t>(b)];
        for (auto& [i, j] : r.triangle_pairs) {
          if (!ka.empty()) i = ka[i];
          if (!kb.empty()) j = kb[j];
        }
        out.contacts.push_back({a, b, std::move(r.triangle_pairs)});
        if (!request.all_contacts) {
          if (!request.bounds_after_contact) break;
          contact_done = true;
        }
        continue;
      }
    }
    if (with_distance) place(k, l, g2);
  }
  order.resize(ordered);
  out.collision = !out.contacts.empty();
  out.limit_action = first_limit_violation(scene_, params);
  if (!request.distance) {
    if (seed) seed->separation.clear();
    return;
  }
  out.min_distance = start;
  // Lower bound of the pairs proven beyond the cutoff without an exact
  // distance (verdict-only; pairs searched below an exact distance found
  // before are settled by it, as in the full check).
  double beyond = std::numeric_limits<double>::infinity();

  // What this state proves for the next: each pair's lower bound, raised
  // below where a distance search settles it. Pairs outside `which` (an
  // infinite bound) prove nothing.
  std::vector<double>& proven = carried;  // carried[k] is folded into lower[k] by now
  if (seed) {
    // Every pair the loop visited (up to and with the one a first contact
    // ended it at: with distances, v is that pair) gets its bound, the
    // lazy_seeded ones' as the others'; the pairs after such a contact keep
    // a lower bound of 0, which proves nothing.
    const std::size_t visited = std::min(v + 1, pairs_.size());
    proven.resize(pairs_.size());
    prove_bounds(gap2.data(), carry ? carried.data() : nullptr, lower.data(), proven.data(), visited);
    std::fill(proven.begin() + static_cast<std::ptrdiff_t>(visited), proven.end(), 0.0);
    if (!terrain_cacheable)
      for (std::size_t k = 0; k < visited; ++k)
        if (!cacheable(k)) proven[k] = 0.0;
  }
  // (A swap, not a copy: the seed's former separations are not read after
  // this, and the scratch's vector is rewritten before it is read again.)
  auto store_separations = [&] {
    if (!seed) return;
    seed->separation.swap(proven);
    seed->at.assign(params.begin(), params.end());
  };

  // Minimum distance: pairs in order of their box lower bound, the best so
  // far pruning the rest; a colliding state needs only a common point.
  if (out.collision) {
    order.clear();
    for (std::size_t k = 0; k < pairs_.size(); ++k)
      if (pairs_[k].a == out.contacts[0].part_a && pairs_[k].b == out.contacts[0].part_b) order.push_back(k);
  } else {
    // (The full check sorts them all, as it always has: the order among
    // equal bounds decides which of equally close pairs is reported.)
    if (verdict_only && out.min_distance >= cutoff)
      beyond = std::min(beyond, std::min(lazy ? std::sqrt(skipped) : skipped, std::sqrt(skipped_seeded2)));
    sort_by_key(order, lower, scratch.last_order, scratch.in_order, scratch.sorted);
  }
  StateSeed hint;
  if (seed) {
    hint.pair = seed->pair;
    hint.slot_a = seed->slot_a;
    hint.slot_b = seed->slot_b;
    seed->pair = -1;
    // A hint whose parts have moved farther since its state than they were
    // apart there (the motion bound against the separation proven there)
    // names a triangle pair that may now be anywhere on them: its search
    // starts from a loose bound and costs more than the coarse pass, which
    // takes over (states far apart: candidate configurations, coarse
    // samples, a planner's tree written as a plan). Only the start of the
    // search changes; the exact pass decides as from any seed.
    if (carry && hint.pair >= 0 && static_cast<std::size_t>(hint.pair) < pairs_.size()) {
      const std::size_t k = static_cast<std::size_t>(hint.pair);
      const double moved = scratch.motion[static_cast<std::size_t>(pairs_[k].a)] + scratch.motion[static_cast<std::size_t>(pairs_[k].b)];
      if (moved > seed->separation[k]) hint.pair = -1;
    }
  }
  auto usable = [&](const StateSeed& h) {
    return h.pair >= 0 && static_cast<std::size_t>(h.pair) < pairs_.size() &&
           std::isfinite(lower[static_cast<std::size_t>(h.pair)]);
  };
  // Per pair, a lower bound on its distance the coarse pass proved (0: none;
  // empty when no coarse pass ran).
  std::vector<double>& coarse_bound = scratch.coarse;
  coarse_bound.clear();
  // With one pair to search there is nothing to order or prune: the coarse
  // search would only precede the exact one (a scene of two meshes, one
  // moving: 1.5x the pair's own query).
  if (!out.collision && !usable(hint) && request.rel_tolerance < kProbeTolerance && !verdict_only &&
      order.size() > 1) {
    coarse_bound.assign(pairs_.size(), 0.0);
    // A cold start (no previous state's pair to try first). Part boxes order
    // the pairs poorly, and every pair searched under a loose bound costs
    // several times a seeded search, so a coarse pass first finds a close
    // pair cheaply (cold states take 42% of their former time on the default
    // plans). Only its triangle pair is kept, as the hint a previous state
    // would have given: the exact pass below decides everything, as from any
    // other seed.
    // The first pair searched sets a bound within a factor (1 +
    // kProbeTolerance) of its closest. Each later pair is asked only whether
    // anything of it lies below the best so far (exactly, stopping at the
    // first such triangle pair): were it asked within the factor too, a pair
    // closer than the best by less than the factor would go unseen, and the
    // hint would name the wrong pair. On 2,000 cold states of the default
    // scene it did in 834 of 1,406 states apart (the arm's base over the
    // deck, nearly always the closest pair, lost to the third link and the
    // scoop, whose boxes meet), and the exact pass found the closest pair
    // only after an exact search of the hinted one. A pair with nothing
    // below the best is proven at least that far; the exact pass skips it.
    double best = out.min_distance;
    bool bounded = false;  // a pair has been found: later pairs ask below the best
    for (std::size_t k : order) {
      const double tolerance = bounded ? 0.0 : kProbeTolerance;
      if (lower[k] >= best / (1.0 + tolerance)) break;
      const int a = pairs_[k].a, b = pairs_[k].b;
      DistanceRequest q{best, tolerance, 0.0};
      q.first_below = bounded;
      q.known_disjoint = true;  // no contact (this branch): see below
      q.root_cull = false;      // bounded by the best so far: as the exact pass below
      DistanceResult r;
      if (b == terrain_index_)
        distance(models_[a], *pose[a], *terrain, q, r);
      else
        distance(models_[a], *pose[a], models_[b], *pose[b], q, r);
      // What the search proved of the pair, as the exact pass proves it (a
      // distance found within the tolerance is at most (1 + tolerance) times
      // the pair's; a pair found by a first-below search proves nothing).
      if (!r.found || !q.first_below)
        coarse_bound[k] = (r.found ? r.distance : q.upper_bound) / (1.0 + tolerance) - pair_guard(a, b);
      if (r.found && r.distance < best) {
        best = r.distance;
        bounded = true;
        hint.pair = static_cast<int>(k);
        hint.slot_a = r.slot_a;
        hint.slot_b = r.slot_b;
      }
    }
  }
  // The hinted pair first: its bound then prunes every other pair.
  if (!out.collision && usable(hint)) {
    const auto it = std::find(order.begin(), order.end(), static_cast<std::size_t>(hint.pair));
    if (it != order.end()) std::rotate(order.begin(), it, it + 1);
  }
  bool first = true;
  const double shrink = 1.0 / (1.0 + request.rel_tolerance);
  for (std::size_t k : order) {
    // The seeded pair may come first out of order: never stop on it.
    const bool seeded = first && hint.pair == static_cast<int>(k) && !out.collision;
    first = false;
    if (lower[k] >= out.min_distance * shrink) {
      // Beyond the cutoff by its box gap or carried separation (the pairs
      // after it in order are farther still).
      if (verdict_only && out.min_distance >= cutoff) beyond = std::min(beyond, lower[k]);
      if (seeded) continue;
      break;
    }
    // Proven by the coarse pass at least as far as the best: its search
    // could not find a closer pair (later pairs in order still may).
    if (!seeded && !coarse_bound.empty() && coarse_bound[k] >= out.min_distance) continue;
    const int a = pairs_[k].a, b = pairs_[k].b;
    DistanceRequest q{out.min_distance, request.rel_tolerance, kDistanceTieTolerance};
    // Without a contact every pair here was proven apart at this very pose:
    // by its box gap or carried separation (lower[k] > 0), or by the exact
    // collision test above, with the same models and transforms; the
    // search need not run its own.
    q.known_disjoint = !out.collision;
    // A verdict-only pass asks each pair below its cutoff, which the parts'
    // root boxes often clear (DistanceRequest::root_cull); an exact pass
    // (and the coarse pass above) asks below the best distance so far,
    // which they seldom do (Table 3's cold states: 1,727 of 17,237
    // searches), and there the test cost more than it saved (Table 3, 1
    // thread: 0.0508, 0.0514 -> 0.0544, 0.0522 s).
    q.root_cull = verdict_only;
    if (seeded) {
      q.seed_slot_a = hint.slot_a;
      q.seed_slot_b = hint.slot_b;
    }
    DistanceResult r;
    if (out.collision) {
      // The first contact's pair (the only one in order): what distance()
      // would find, its collision pass stopping at the same first pair.
      if (q.upper_bound > 0.0) r = first_contact;
    } else if (ask_near && apart_below[k]) {
      // Its collision test proved every triangle pair at least `start`
      // apart, and q.upper_bound <= start: distance() would find nothing.
    } else if (b == terrain_index_) {
      distance(models_[a], *pose[a], *terrain, q, r);
    } else if (seed) {
      // The same search as the last one run on this pair: the same answer.
      if (seed->searches.size() != pairs_.size()) seed->searches.assign(pairs_.size(), StateSeed::Search{});
      StateSeed::Search& last = seed->searches[k];
      if (last.valid && same_search(last, *pose[a], *pose[b], q)) {
        r = last.result;
      } else {
        distance(models_[a], *pose[a], models_[b], *pose[b], q, r);
        last = StateSeed::Search{true, *pose[a], *pose[b], q, r};
      }
    } else {
      distance(models_[a], *pose[a], models_[b], *pose[b], q, r);
    }
    // The pair's distance is at least what the search found, or else what
    // it looked below, each less its tolerances (with rel_tolerance a found
    // distance may exceed the pair's by that factor); rounding of the double
    // distance is taken off with the guard a margin test uses.
    const double settled = (r.found ? r.distance : q.upper_bound) * shrink - q.abs_tolerance;
    const double guard = pair_guard(a, b);
    if (seed && !out.collision && std::isfinite(settled)) proven[k] = std::max(proven[k], settled - guard);
    if (verdict_only && !r.found && q.upper_bound >= cutoff) beyond = std::min(beyond, std::max(lower[k], settled - guard));
    if (r.found && r.distance < out.min_distance) {
      if (seed) {
        seed->pair = static_cast<int>(k);
        seed->slot_a = r.slot_a;
        seed->slot_b = r.slot_b;
      }
      out.min_distance = r.distance;
      out.part_a = a;
      out.part_b = b;
      out.point_a = r.point_a;
      out.point_b = r.point_b;
    }
  }
  if (out.collision) {
    out.min_distance = 0.0;
  } else if (beyond < (out.part_a >= 0 ? out.min_distance : std::numeric_limits<double>::infinity())) {
    // Verdict-only, and some pair is known only to lie beyond the cutoff,
    // below any exact distance found: the state's minimum is only bounded.
    out.min_distance = beyond;
    out.distance_is_bound = true;
    // The guard of a margin comparison on the bound: that of any pair it
    // may stand for (the motion checks compare bounds with their targets).
    out.distance_tolerance = largest_guard;
    out.part_a = out.part_b = -1;
    out.point_a = out.point_b = Vec3::Zero();
  }
  if (out.part_a < 0 && !out.distance_is_bound) out.min_distance = std::numeric_limits<double>::infinity();
  if (out.part_a >= 0) out.distance_tolerance = pair_guard(out.part_a, out.part_b);
  store_separations();
}

std::vector<PairContact> Checker::reference_contacts() const {
  StateResult r;
  check_state(scene_.reference_parameters, r);
  return r.contacts;
}

Vec3 Checker::target_point(const std::vector<double>& params, std::optional<ChainCache>& cache) const {
  if (!scene_.scoop) return target_point(params);
  if (!cache) cache.emplace(scene_, scene_.parts[static_cast<std::size_t>(scene_.scoop->part_index)].chain);
  return (*cache)(params) * scene_.scoop->bottom_point;
}

Vec3 Checker::target_point(const std::vector<double>& params) const {
  if (scene_.scoop) {
    const int p = scene_.scoop->part_index;
    return part_transform(scene_, p, params) * scene_.scoop->bottom_point;
  }
  if (scene_.actions.empty()) return Vec3::Zero();
  // Without a scoop: the origin of the last action's node, moved by its chain.
  const Action& last = scene_.actions.back();
  const Node& node = scene_.nodes[static_cast<std::size_t>(last.node)];
  Affine t = Affine::Identity();
  std::vector<int> chain;
  for (int n = last.node; n >= 0; n = scene_.nodes[static_cast<std::size_t>(n)].parent)
    for (auto it = scene_.nodes[static_cast<std::size_t>(n)].actions.rbegin();
         it != scene_.nodes[static_cast<std::size_t>(n)].actions.rend(); ++it)
      chain.push_back(*it);
  std::reverse(chain.begin(), chain.end());
  for (int a : chain) {
    const Action& act = scene_.actions[static_cast<std::size_t>(a)];
    t = t * action_transform_at(scene_, act, params);
  }
  return t * node.origin;
}


// ---- Pair by pair (the sweep's certified regions) ----

void Checker::place(PosedParts& out, std::size_t i) const {
  if (chain_of_[i] >= 0) {
    out.pose[i] = &out.chains[static_cast<std::size_t>(chain_of_[i])];
    const Box b = posed_box({local_boxes_[i].first, local_boxes_[i].second}, *out.pose[i]);
    out.box[i] = {b.lo, b.hi};
  } else {
    out.pose[i] = &placement_[i];
    out.box[i] = static_boxes_[i];
  }
}

void Checker::pose_parts(const std::vector<double>& params, PosedParts& out, std::span<const int> parts) const {
  const std::size_t n = models_.size();
  out.pose.resize(n);
  out.box.resize(n);
  out.chains.resize(scene_.chains.size());
  auto pose_one = [&](std::size_t i) { place(out, i); };
  if (parts.empty()) {
    chain_transforms(scene_, chain_prefixes_, params, out.chains);
    for (std::size_t i = 0; i < n; ++i) pose_one(i);
    return;
  }
  // Only the chains of these parts (the same composition chain_transforms
  // runs). Two parts of one arm (a pair of arm parts): the longer chain
  // continues the shorter's product when that chain begins it, as
  // chain_transforms does (the same bits), not composed from the root again.
  if (parts.size() == 2 && parts[0] >= 0 && parts[1] >= 0 && static_cast<std::size_t>(parts[0]) < n &&
      static_cast<std::size_t>(parts[1]) < n) {
    int c0 = chain_of_[static_cast<std::size_t>(parts[0])], c1 = chain_of_[static_cast<std::size_t>(parts[1])];
    if (c0 >= 0 && c1 >= 0 && c0 != c1) {
      const std::vector<int>* s0 = &scene_.chains[static_cast<std::size_t>(c0)];
      const std::vector<int>* s1 = &scene_.chains[static_cast<std::size_t>(c1)];
      if (s0->size() > s1->size()) {
        std::swap(c0, c1);
        std::swap(s0, s1);
      }
      if (!s0->empty() && std::equal(s0->begin(), s0->end(), s1->begin())) {
        Affine& short_chain = out.chains[static_cast<std::size_t>(c0)];
        chain_transform(scene_, c0, -1, nullptr, params, short_chain);
        chain_transform(scene_, c1, c0, &short_chain, params, out.chains[static_cast<std::size_t>(c1)]);
        for (int i : parts) pose_one(static_cast<std::size_t>(i));
        return;
      }
    }
  }
  for (int i : parts) {
    if (i < 0 || static_cast<std::size_t>(i) >= n) continue;
    const int c = chain_of_[static_cast<std::size_t>(i)];
    if (c >= 0) out.chains[static_cast<std::size_t>(c)] = part_transform(scene_, i, params);
  }
  for (int i : parts)
    if (i >= 0 && static_cast<std::size_t>(i) < n) pose_one(static_cast<std::size_t>(i));
}

bool Checker::pose_parts_moving(const std::vector<double>& params, PosedParts& out, std::span<const int> parts,
                                int moving, std::span<const double> rates, Vec3& w, Vec3& u) const {
  const std::size_t n = models_.size();
  out.pose.resize(n);
  out.box.resize(n);
  out.chains.resize(scene_.chains.size());
  bool known = false;
  for (int i : parts) {
    if (i < 0 || static_cast<std::size_t>(i) >= n) continue;
    const int c = chain_of_[static_cast<std::size_t>(i)];
    if (c < 0) continue;
    Affine& t = out.chains[static_cast<std::size_t>(c)];
    if (i == moving && !known)
      known = part_transform_velocity(scene_, i, params, rates, t, w, u);
    else
      t = part_transform(scene_, i, params);
  }
  for (int i : parts)
    if (i >= 0 && static_cast<std::size_t>(i) < n) place(out, static_cast<std::size_t>(i));
  return known;
}

void Checker::pair_gaps(const PosedParts& posed, std::vector<double>& gap, std::vector<double>& guard) const {
  const std::size_t np = pairs_.size();
  gap.resize(np);
  guard.resize(np);
  const Heightfield* field = posed.terrain ? posed.terrain : terrain_.get();
  const bool has_field = field && field->triangle_count() > 0;
  const Box terrain_box = has_field ? terrain_root_box(*field) : Box{};
  // Each part's magnitude once (pair_distance computes both of a pair's),
  // the terrain's last.
  thread_local std::vector<double> magnitude;
  const std::size_t n = posed.box.size();
  magnitude.resize(n + 1);
  for (std::size_t i = 0; i < n; ++i) magnitude[i] = part_magnitude(static_cast<int>(i), posed.box[i].first, posed.box[i].second);
  magnitude[n] = has_field ? part_magnitude(terrain_index_, terrain_box.lo, terrain_box.hi) : 0.0;
  for (std::size_t k = 0; k < np; ++k) {
    const PairRef& p = pairs_[k];
    const bool on_terrain = p.b == terrain_index_;
    if (p.empty || (on_terrain && !has_field)) {
      gap[k] = std::numeric_limits<double>::infinity();
      guard[k] = kDistanceTolerance;
      continue;
    }
    const std::size_t a = static_cast<std::size_t>(p.a), b = on_terrain ? n : static_cast<std::size_t>(p.b);
    const Box box_a{posed.box[a].first, posed.box[a].second};
    gap[k] = box_gap(box_a, on_terrain ? terrain_box : Box{posed.box[b].first, posed.box[b].second});
    guard[k] = magnitude_guard(magnitude[a], magnitude[b]);
  }
}

bool Checker::pair_collides(const PosedParts& posed, std::size_t k) const {
  const PairRef& p = pairs_[k];
  if (p.empty) return false;
  const int a = p.a, b = p.b;
  const Affine& pa = *posed.pose[static_cast<std::size_t>(a)];
  const Box box_a{posed.box[static_cast<std::size_t>(a)].first, posed.box[static_cast<std::size_t>(a)].second};
  CollideResult r;
  if (b == terrain_index_) {
    const Heightfield* field = posed.terrain ? posed.terrain : terrain_.get();
    if (!(field && field->triangle_count() > 0)) return false;
    if (box_gap2(box_a, terrain_root_box(*field)) > 0.0) return false;
    collide(models_[a], pa, *field, CollideRequest{0}, r);
  } else {
    const Box box_b{posed.box[static_cast<std::size_t>(b)].first, posed.box[static_cast<std::size_t>(b)].second};
    if (box_gap2(box_a, box_b) > 0.0) return false;
    collide(models_[a], pa, models_[b], *posed.pose[static_cast<std::size_t>(b)], CollideRequest{0}, r);
  }
  return r.collide;
}

void Checker::pair_distance(const PosedParts& posed, std::size_t k, double need, PairAnswer& out, bool decide,
                            double rel_tolerance, bool beyond) const {
  const PairRef& p = pairs_[k];
  const bool seeded = out.seeded;
  const std::uint32_t seed_a = out.slot_a, seed_b = out.slot_b;
  out = PairAnswer{};
  out.distance = out.beyond = std::numeric_limits<double>::infinity();
  if (p.empty) return;  // never checked: no bound from it
  const int a = p.a, b = p.b;
  const bool on_terrain = b == terrain_index_;
  const Heightfield* field = posed.terrain ? posed.terrain : terrain_.get();
  if (on_terrain && !(field && field->triangle_count() > 0)) return;
  const Box box_a{posed.box[static_cast<std::size_t>(a)].first, posed.box[static_cast<std::size_t>(a)].second};
  const Box box_b = on_terrain ? terrain_root_box(*field)
                               : Box{posed.box[static_cast<std::size_t>(b)].first, posed.box[static_cast<std::size_t>(b)].second};
  const double gap = box_gap(box_a, box_b);
  out.guard = magnitude_guard(part_magnitude(a, box_a.lo, box_a.hi), part_magnitude(b, box_b.lo, box_b.hi));
  if (gap >= need) {  // beyond the need by the boxes
    out.distance = out.beyond = gap;
    return;
  }
  DistanceRequest q{need, rel_tolerance, kDistanceTieTolerance};
  q.first_below = decide;
  q.known_disjoint = true;  // the caller ran pair_collides
  q.beyond = beyond;
  if (seeded) {
    q.seed_slot_a = seed_a;
    q.seed_slot_b = seed_b;
  }
  const Affine& pa = *posed.pose[static_cast<std::size_t>(a)];
  DistanceResult r;
  if (on_terrain)
    distance(models_[a], pa, *field, q, r);
  else
    distance(models_[a], pa, models_[b], *posed.pose[static_cast<std::size_t>(b)], q, r);
  if (r.found && rel_tolerance > 0.0) {
    // Within the factor: the pair skipped for the one found had a lower
    // bound at least min(best / (1 + r), best - tie), best >= r.distance.
    out.distance = std::max({gap, r.distance / (1.0 + rel_tolerance) - q.abs_tolerance - out.guard, 0.0});
    out.upper = r.distance;
    out.seeded = true;
    out.slot_a = r.slot_a;
    out.slot_b = r.slot_b;
  } else if (r.found) {
    out.exact = !decide;
    out.distance = decide ? gap : r.distance;
    out.upper = r.distance;
    out.seeded = true;
    out.slot_a = r.slot_a;
    out.slot_b = r.slot_b;
  } else {
    // As check_pairs proves a pair it searched below q.upper_bound.
    out.distance = std::max({gap, need / (1.0 + rel_tolerance) - q.abs_tolerance - out.guard, 0.0});
  }
  out.beyond = r.found ? out.distance : std::max(out.distance, r.beyond - q.abs_tolerance - out.guard);
}

void Checker::pair_crossings(const PosedParts& posed, std::size_t k, std::size_t max,
                             std::vector<std::array<Vec3, 6>>& out) const {
  out.clear();
  const PairRef& p = pairs_[k];
  if (p.empty || p.b == terrain_index_ || max == 0) return;
  const std::size_t a = static_cast<std::size_t>(p.a), b = static_cast<std::size_t>(p.b);
  const Box box_a{posed.box[a].first, posed.box[a].second};
  const Box box_b{posed.box[b].first, posed.box[b].second};
  if (box_gap2(box_a, box_b) > 0.0) return;
  CollideResult r;
  collide(models_[a], *posed.pose[a], models_[b], *posed.pose[b], CollideRequest{max}, r);
  if (!r.collide) return;
  auto corners = [&](std::size_t part, std::uint32_t t, Vec3* x) {
    const auto& kept = (*kept_)[part];
    const Mesh& mesh = scene_.parts[part].mesh;
    const Tri& tri = mesh.triangles[kept.empty() ? t : kept[t]];
    for (int c = 0; c < 3; ++c) x[c] = *posed.pose[part] * mesh.vertices[tri[static_cast<std::size_t>(c)]];
  };
  for (const auto& [ia, ib] : r.triangle_pairs) {
    std::array<Vec3, 6> x;
    corners(a, ia, x.data());
    corners(b, ib, x.data() + 3);
    out.push_back(x);
  }
}

namespace {

// The parameters an action reads (a mimic joint: its master's).
void action_parameters(const Scene& scene, const Action& a, std::vector<int>& out) {
  if (a.mimic >= 0) {
    out.push_back(scene.actions[static_cast<std::size_t>(a.mimic)].first_parameter);
    return;
  }
  for (int j = 0; j < a.parameter_count; ++j) out.push_back(a.first_parameter + j);
}

}  // namespace

std::vector<int> Checker::pair_parameters(std::size_t k) const {
  auto chain = [&](int part) -> const std::vector<int>& {
    static const std::vector<int> kNone;
    return part < static_cast<int>(scene_.parts.size()) ? scene_.parts[static_cast<std::size_t>(part)].chain : kNone;
  };
  const std::vector<int>& ca = chain(pairs_[k].a);
  const std::vector<int>& cb = chain(pairs_[k].b);
  // Chains run from the root: the common actions are a common prefix, and
  // they move both parts alike.
  std::size_t common = 0;
  while (common < ca.size() && common < cb.size() && ca[common] == cb[common]) ++common;
  std::vector<int> out;
  for (std::size_t i = common; i < ca.size(); ++i) action_parameters(scene_, scene_.actions[static_cast<std::size_t>(ca[i])], out);
  for (std::size_t i = common; i < cb.size(); ++i) action_parameters(scene_, scene_.actions[static_cast<std::size_t>(cb[i])], out);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

double Checker::pair_motion(std::size_t k, std::span<const double> lo, std::span<const double> hi) const {
  // part_bound bounds the path of every point over the box spanned by lo
  // and hi, |dq_i| times the largest |dp/dq_i| in it: from the centre to any
  // point of the box, half of that. Both parts' motions add up (for a part
  // whose chain is a prefix of the other's, the first is zero: only the
  // pair's own parameters differ between lo and hi).
  const double m = motion_.part_bound(pairs_[k].a, lo, hi) + motion_.part_bound(pairs_[k].b, lo, hi);
  return 0.5 * m * (1.0 + 1e-9) + 1e-12;
}

double Checker::guard_bound(double reach) const {
  auto mag = [](const Vec3& lo, const Vec3& hi) { return std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()); };
  double m = terrain_magnitude_;
  for (int i : guard_parts_) {
    const auto& l = local_boxes_[static_cast<std::size_t>(i)];
    m = std::max(m, mag(l.first, l.second));
    if (chain_of_[static_cast<std::size_t>(i)] < 0) {
      m = std::max(m, mag(static_boxes_[static_cast<std::size_t>(i)].first, static_boxes_[static_cast<std::size_t>(i)].second));
    } else {
      // The world box at the reference pose, moved by at most `reach`; its
      // corners are within the local box's diagonal of the part's points
      // (twice that for slack under scale actions).
      const Box w = posed_box({l.first, l.second},
                              part_transform(scene_, i, scene_.reference_parameters));
      m = std::max(m, mag(w.lo, w.hi) + reach + 2.0 * (l.second - l.first).norm());
    }
  }
  return std::max(kDistanceTolerance, 64.0 * std::numeric_limits<double>::epsilon() * m * (1.0 + 1e-6));
}

}  // namespace plancheck

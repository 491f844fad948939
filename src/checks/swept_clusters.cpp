// SPDX-License-Identifier: MIT
#include "src/checks/swept_clusters.h"

#include "src/scene/kinematics.h"
#include "src/scene/plan.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <span>

namespace plancheck {

namespace {
constexpr int kTimes = 1 << SweptClusters::kLevels;  // finest pieces
static_assert(kTimes < 64, "one bit per time in PartData::posed");
}  // namespace

void SweptClusters::start(const Checker& checker, const std::vector<double>& qa, const std::vector<double>& qb,
                          bool tight) {
  checker_ = &checker;
  tight_ = tight;
  qa_ = &qa;
  qb_ = &qb;
  parts_.resize(checker.part_count());
  const bool same = checker.instance_id() == checker_id_;
  checker_id_ = checker.instance_id();
  if (!same) prefixes_ = chain_prefixes(checker.scene());
  chain_pose_.resize(prefixes_.size() * (kTimes + 1));
  chain_known_.assign(prefixes_.size(), 0);
  for (PartData& d : parts_) {
    d.known = false;
    d.spheres_known = d.spheres_known && same;
  }
}

SweptClusters::PartData& SweptClusters::part(int index) {
  PartData& d = parts_[static_cast<std::size_t>(index)];
  if (d.known) return d;
  d.known = true;
  d.usable = false;
  d.balls_known = false;
  d.posed = 0;
  const MotionBound& bound = checker_->motion_bound();
  if (!d.spheres_known) {
    d.spheres_known = true;
    const BoxMotion& box = checker_->box_motion();
    d.spheres.clear();
    d.levers.clear();
    // Only spheres that hold whole triangles bound every point of the part.
    if (box.points() == BoxMotion::Points::kTriangles) box.spheres(index, d.spheres);
    std::vector<double> levers;
    for (const BoxMotion::Sphere& s : d.spheres) {
      if (!bound.sphere_levers(index, s.centre, s.radius, levers)) {
        d.levers.clear();
        break;
      }
      d.levers.insert(d.levers.end(), levers.begin(), levers.end());
    }
  }
  if (d.spheres.empty()) return d;
  d.speed.resize(d.spheres.size());
  const std::size_t chain = d.levers.size() / d.spheres.size();
  // BoxMotion's balls over the box qa and qb span, from its middle: each
  // cluster's points move at most `move` from where they are there, so at
  // most 2 move per unit of t along the motion (its levers read at the
  // pose, where the bound above reads them for any pose).
  const std::size_t np = qa_->size();
  lo_.resize(np);
  hi_.resize(np);
  mid_.resize(np);
  for (std::size_t i = 0; i < np; ++i) {
    lo_[i] = std::min((*qa_)[i], (*qb_)[i]);
    hi_[i] = std::max((*qa_)[i], (*qb_)[i]);
    mid_[i] = std::clamp((*qa_)[i] + 0.5 * ((*qb_)[i] - (*qa_)[i]), lo_[i], hi_[i]);
  }
  d.balls_known = true;
  d.balls = checker_->box_motion().balls(index, lo_, hi_, mid_, d.ball);
  const bool balls = d.balls && d.ball.size() == d.spheres.size();
  for (std::size_t i = 0; i < d.spheres.size(); ++i) {
    d.speed[i] = d.levers.empty()
                     ? bound.sphere_bound(index, d.spheres[i].centre, d.spheres[i].radius, *qa_, *qb_)
                     : bound.levers_bound(index, std::span<const double>(d.levers).subspan(i * chain, chain), *qa_, *qb_);
    if (balls) {
      const double box = 2.0 * d.ball[i].move * (1.0 + 1e-12);
      if (box < d.speed[i]) d.speed[i] = box;
    }
    if (!(d.speed[i] < std::numeric_limits<double>::infinity())) return d;  // NaN or infinite
  }
  d.centre.resize(d.spheres.size() * (kTimes + 1));
  d.mag.resize(d.centre.size());
  d.hull.resize(static_cast<std::size_t>((kTimes + 1) * (kLevels + 1)));
  std::fill(std::begin(d.hull_known), std::end(d.hull_known), std::uint64_t{0});
  d.usable = true;
  return d;
}

const std::vector<BoxMotion::Ball>* SweptClusters::balls(int index) const {
  if (!checker_ || index < 0 || static_cast<std::size_t>(index) >= parts_.size()) return nullptr;
  const PartData& d = parts_[static_cast<std::size_t>(index)];
  return d.known && d.balls_known && d.balls ? &d.ball : nullptr;
}

const Vec3* SweptClusters::centres(PartData& d, int index, int m) {
  const std::size_t k = d.spheres.size();
  Vec3* out = &d.centre[static_cast<std::size_t>(m) * k];
  if (d.posed >> m & 1) return out;
  d.posed |= std::uint64_t{1} << m;
  const std::vector<double>* q = qa_;
  if (m == kTimes) {
    q = qb_;
  } else if (m > 0) {
    state_between(*qa_, *qb_, static_cast<double>(m) / kTimes, q_);
    q = &q_;
  }
  // The part's transform alone (pose_parts' for one part, without its box).
  const int chain = checker_->scene().parts[static_cast<std::size_t>(index)].chain_id;
  const Affine pose = chain >= 0 ? chain_at(chain, m, *q) : part_transform(checker_->scene(), index, *q);
  double* mag = &d.mag[static_cast<std::size_t>(m) * k];
  for (std::size_t i = 0; i < k; ++i) {
    out[i] = pose * d.spheres[i].centre;
    mag[i] = out[i].cwiseAbs().maxCoeff();
  }
  return out;
}

const Affine& SweptClusters::chain_at(int c, int m, const std::vector<double>& q) {
  Affine& out = chain_pose_[static_cast<std::size_t>(m) * prefixes_.size() + static_cast<std::size_t>(c)];
  std::uint64_t& known = chain_known_[static_cast<std::size_t>(c)];
  if (known >> m & 1) return out;
  const int p = prefixes_[static_cast<std::size_t>(c)];
  const Affine* from = p >= 0 ? &chain_at(p, m, q) : nullptr;
  chain_transform(checker_->scene(), c, p, from, q, out);
  known |= std::uint64_t{1} << m;
  return out;
}

bool SweptClusters::piece(PartData& d, int index, int lo, int hi, const Vec3& blo, const Vec3& bhi, double target,
                          double& least) {
  // Posed at the piece's middle, each point within speed * length / 2 of
  // where it is there; a finest piece is posed at its start and reaches
  // its whole length (its middle is not one of the times).
  const double length = static_cast<double>(hi - lo) / kTimes;
  const int m = hi - lo >= 2 ? (lo + hi) / 2 : lo;
  const double reach = hi - lo >= 2 ? 0.5 * length : length;
  const Vec3* c = centres(d, index, m);
  const double* mag = &d.mag[static_cast<std::size_t>(m) * d.spheres.size()];
  // Where the bound may be loose (not tight_), all the spheres at once
  // first: the box holding them grown (each ball lies in it, so no ball is
  // nearer the target box than it is). Where it keeps the target, so does
  // every ball, and its gap is the piece's bound. Tight, each ball's own
  // bound is taken below.
  if (!tight_) {
    const int level = std::countr_zero(static_cast<unsigned>(hi - lo));  // hi - lo is a power of two
    PartData::Hull& h = d.hull[static_cast<std::size_t>(m * (kLevels + 1) + level)];
    if (!(d.hull_known[level] >> m & 1)) {
      d.hull_known[level] |= std::uint64_t{1} << m;
      h.lo = Vec3::Constant(std::numeric_limits<double>::infinity());
      h.hi = -h.lo;
      double largest = 0.0;
      bool finite = true;
      for (std::size_t i = 0; i < d.spheres.size(); ++i) {
        const double grow = d.spheres[i].radius + d.speed[i] * reach;
        h.lo = h.lo.cwiseMin(c[i] - Vec3::Constant(grow));
        h.hi = h.hi.cwiseMax(c[i] + Vec3::Constant(grow));
        largest = std::max(largest, mag[i] + grow);
        finite = finite && c[i].allFinite() && std::isfinite(grow);
      }
      // Twice the balls' own pad: covers the box's rounding as theirs
      // covers the balls', and keeps its bound below theirs where a ball
      // is as near as the box (the nearest straight across, on an axis).
      // A ball not finite (min and max would drop a NaN): no box test (a
      // NaN pad fails it), the balls' own tests decide.
      h.pad = finite ? 2e-9 * (largest + 1.0) : std::numeric_limits<double>::quiet_NaN();
    }
    const double gap2 = (blo - h.hi).cwiseMax(h.lo - bhi).cwiseMax(Vec3::Zero()).squaredNorm();
    const double need = target + h.pad;
    if (gap2 >= need * need) return true;  // (loose: the bound is the target itself, see clear)
  }
  double bound = std::numeric_limits<double>::infinity();
  // Whether cluster i's ball, grown by `piece_reach`, fails the test at
  // its centre here. Where it fails even with the finest piece's reach
  // (the test of the finest piece from time m, the same numbers), the
  // whole is hardly provable: nothing is halved. That costs a missed
  // shortcut at most (the pair then marches) and saves the poses of every
  // level below.
  auto fails = [&](std::size_t i, double gap2, double piece_reach) {
    const double grow = d.spheres[i].radius + d.speed[i] * piece_reach;
    // Rounding: of the posed centre and of the sums here, far below this.
    const double pad = 1e-9 * (mag[i] + grow + 1.0);
    const double need = target + grow + pad;
    return !(gap2 >= need * need);  // true for NaN
  };
  for (std::size_t i = 0; i < d.spheres.size(); ++i) {
    const double gap2 = (blo - c[i]).cwiseMax(c[i] - bhi).cwiseMax(Vec3::Zero()).squaredNorm();
    if (fails(i, gap2, reach)) {
      if (hi - lo <= 1 || fails(i, gap2, 1.0 / kTimes)) return false;
      const int mid = (lo + hi) / 2;
      return piece(d, index, lo, mid, blo, bhi, target, least) && piece(d, index, mid, hi, blo, bhi, target, least);
    }
    if (tight_) {
      const double grow = d.spheres[i].radius + d.speed[i] * reach;
      bound = std::min(bound, std::sqrt(gap2) - grow - 1e-9 * (mag[i] + grow + 1.0));
    }
  }
  least = std::min(least, bound);
  return true;
}

double SweptClusters::clear(int part_index, const Vec3& lo, const Vec3& hi, double target) {
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  if (!checker_ || part_index < 0 || static_cast<std::size_t>(part_index) >= parts_.size() || !(target >= 0.0))
    return kNone;
  PartData& d = part(part_index);
  if (!d.usable) return kNone;
  double least = std::numeric_limits<double>::infinity();
  if (!piece(d, part_index, 0, kTimes / 2, lo, hi, target, least) ||
      !piece(d, part_index, kTimes / 2, kTimes, lo, hi, target, least))
    return kNone;
  // Each piece's test proved its balls at least target apart (squared, with
  // the pad); the bound read from it may round a hair below. Loose (not
  // tight_): the target itself, no distance read.
  return tight_ ? std::max(least, target) : target;
}

}  // namespace plancheck

// SPDX-License-Identifier: MIT
// Forward kinematics per the scene contract: a part under actions A1 (nearest
// the root) ... Ak (nearest the part) maps x to A1(A2(...Ak(x))), so a chain's
// transform is the product A1 * A2 * ... * Ak of the action transforms. Every
// pivot, axis and fixed point is given at the reference pose, which is what
// makes this order right: Ak acts first, while everything above it is still
// where the file drew it.
#include "src/scene/kinematics.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace plancheck {

double pose_value(const Action& action, double written) {
  if (action.whole_turn > 0.0) {
    // remainder(x, y) is x - n y, n the integer nearest x / y (exact, as
    // IEEE 754 defines it): x itself, zero's sign kept, when |x| < y / 2.
    // 2 |x| is exact (or infinite, and not below y), so the test is exact;
    // it skips the library call for every angle within half a turn.
    const double x = 2.0 * std::abs(written) < action.whole_turn ? written : std::remainder(written, action.whole_turn);
    return x * action.unit_to_si;
  }
  return written * action.unit_to_si;
}

Affine action_transform(const Action& action, const double* params) {
  Affine t;
  switch (action.type) {
    case ActionType::kRotate:
      // x' = R(u, a)(x - p) + p, right-handed about the unit axis u. As
      // Identity().translate(p).rotate(R).translate(-p) computes it, bit
      // for bit (tests/foundation/kinematics_test.cpp), without its
      // products by the identity: the linear part is R itself and the
      // translation p before the last step. A cold state's forward
      // kinematics was a third of the collision-only check of Table 3's
      // states.
      t.linear() = Eigen::AngleAxisd(pose_value(action, params[0]), action.axis).toRotationMatrix();
      t.translation() = action.pivot;
      t.makeAffine();
      t.translate(-action.pivot);
      break;
    case ActionType::kTranslateAxis:
      t.setIdentity();
      t.translate(action.axis * pose_value(action, params[0]));
      break;
    case ActionType::kTranslateFree:
      t.setIdentity();
      t.translate(Vec3(pose_value(action, params[0]), pose_value(action, params[1]), pose_value(action, params[2])));
      break;
    case ActionType::kScale:
      t.setIdentity();
      t.translate(action.fixed_point);
      t.scale(Vec3(params[0], params[1], params[2]));
      t.translate(-action.fixed_point);
      break;
  }
  return t;
}

double driving_value(const Scene& scene, const Action& action, std::span<const double> params) {
  if (action.mimic < 0) return params[static_cast<std::size_t>(action.first_parameter)];
  const Action& master = scene.actions[static_cast<std::size_t>(action.mimic)];
  return action.multiplier * params[static_cast<std::size_t>(master.first_parameter)] + action.offset;
}

Affine action_transform_at(const Scene& scene, const Action& action, std::span<const double> params) {
  if (action.mimic < 0) return action_transform(action, params.data() + action.first_parameter);
  const double value = driving_value(scene, action, params);
  return action_transform(action, &value);
}

namespace {

// out = a * b, written in place: the very expressions of Eigen's Affine
// product (transform_transform_product_impl: linear a.l * b.l, translation
// a.l * b.t + a.t), so the same bits, without its result's copy. out may
// be a: the translation is taken first, while a's linear part is intact
// (each product is evaluated into a temporary before it is assigned).
void times(const Affine& a, const Affine& b, Affine& out) {
  out.translation() = a.linear() * b.translation() + a.translation();
  out.linear() = a.linear() * b.linear();
  out.makeAffine();
}

// The product A1 * ... * Ak, from A1 itself (the identity times A1 is the
// same values, a zero's sign aside: chain_transforms and ChainCache start
// the same way, so that all three give the same bits).
Affine compose(const Scene& scene, const std::vector<int>& chain, std::span<const double> params) {
  if (chain.empty()) return Affine::Identity();
  Affine t = action_transform_at(scene, scene.actions[static_cast<std::size_t>(chain[0])], params);
  for (std::size_t k = 1; k < chain.size(); ++k)
    times(t, action_transform_at(scene, scene.actions[static_cast<std::size_t>(chain[k])], params), t);
  return t;
}

}  // namespace

std::vector<int> chain_prefixes(const Scene& scene) {
  // An arm's chains are prefixes of each other ([J1], [J1, J2], ...): a
  // chain continues the product of the longest earlier chain that begins
  // it. compose's product after those actions is that very value (the
  // same products in the same order), so the result is the same bit for
  // bit, and each action's transform (a sine and cosine) is computed
  // once, not once per chain below it. (Cold verdict-only states of the
  // default scene, 5 chains: compose, action_transform and sincos were
  // 2.3% of the time.)
  std::vector<int> from(scene.chains.size(), -1);
  for (std::size_t c = 0; c < scene.chains.size(); ++c) {
    const std::vector<int>& chain = scene.chains[c];
    std::size_t longest = 0;
    for (std::size_t p = 0; p < c; ++p) {
      const std::vector<int>& prefix = scene.chains[p];
      if (prefix.size() > longest && prefix.size() <= chain.size() &&
          std::equal(prefix.begin(), prefix.end(), chain.begin())) {
        longest = prefix.size();
        from[c] = static_cast<int>(p);
      }
    }
  }
  return from;
}

void chain_transform(const Scene& scene, int c, int prefix, const Affine* prefix_product,
                     std::span<const double> params, Affine& out) {
  const std::vector<int>& chain = scene.chains[static_cast<std::size_t>(c)];
  static const Affine kIdentity = Affine::Identity();
  const Affine& start = prefix >= 0 ? *prefix_product : kIdentity;
  std::size_t i = prefix >= 0 ? scene.chains[static_cast<std::size_t>(prefix)].size() : 0;
  if (i == chain.size()) {
    out = start;
    return;
  }
  const auto action = [&](std::size_t k) {
    return action_transform_at(scene, scene.actions[static_cast<std::size_t>(chain[k])], params);
  };
  // A chain from the root starts at its first action itself (as compose).
  if (prefix >= 0)
    times(start, action(i), out);
  else
    out = action(i);
  for (++i; i < chain.size(); ++i) times(out, action(i), out);
}

void chain_transforms(const Scene& scene, std::span<const int> prefixes, std::span<const double> params,
                      std::vector<Affine>& out) {
  out.resize(scene.chains.size());
  for (std::size_t c = 0; c < scene.chains.size(); ++c) {
    const int p = prefixes[c];
    chain_transform(scene, static_cast<int>(c), p, p >= 0 ? &out[static_cast<std::size_t>(p)] : nullptr, params,
                    out[c]);
  }
}

void chain_transforms(const Scene& scene, std::span<const double> params, std::vector<Affine>& out) {
  chain_transforms(scene, chain_prefixes(scene), params, out);
}

ChainCache::ChainCache(const Scene& scene, const std::vector<int>& chain) : scene_(scene), chain_(chain) {
  for (int a : chain_) {
    const Action& action = scene_.actions[static_cast<std::size_t>(a)];
    std::vector<int> reads;
    if (action.mimic >= 0) {
      reads.push_back(scene_.actions[static_cast<std::size_t>(action.mimic)].first_parameter);
    } else {
      for (int k = 0; k < action.parameter_count; ++k) reads.push_back(action.first_parameter + k);
    }
    first_seen_.push_back(seen_.size());
    seen_.resize(seen_.size() + reads.size(), 0);
    reads_.push_back(std::move(reads));
  }
  prefix_.assign(chain_.size() + 1, Affine::Identity());
}

const Affine& ChainCache::operator()(std::span<const double> params) {
  // The first action whose parameters changed (or that was never composed).
  std::size_t from = 0;
  while (from < valid_) {
    bool same = true;
    const std::vector<int>& reads = reads_[from];
    for (std::size_t r = 0; r < reads.size(); ++r) {
      std::uint64_t bits;
      std::memcpy(&bits, &params[static_cast<std::size_t>(reads[r])], sizeof bits);
      same = same && bits == seen_[first_seen_[from] + r];
    }
    if (!same) break;
    ++from;
  }
  for (std::size_t k = from; k < chain_.size(); ++k) {
    const std::vector<int>& reads = reads_[k];
    for (std::size_t r = 0; r < reads.size(); ++r)
      std::memcpy(&seen_[first_seen_[k] + r], &params[static_cast<std::size_t>(reads[r])], sizeof(std::uint64_t));
    // compose's product, one action at a time from the first.
    const Affine a = action_transform_at(scene_, scene_.actions[static_cast<std::size_t>(chain_[k])], params);
    prefix_[k + 1] = k == 0 ? a : prefix_[k] * a;
  }
  valid_ = chain_.size();
  return prefix_[chain_.size()];
}

Affine part_transform(const Scene& scene, int part, std::span<const double> params) {
  return compose(scene, scene.parts[part].chain, params);
}

bool part_transform_velocity(const Scene& scene, int part, std::span<const double> params,
                             std::span<const double> rates, Affine& out, Vec3& w, Vec3& u) {
  const std::vector<int>& chain = scene.parts[static_cast<std::size_t>(part)].chain;
  Vec3 spin = Vec3::Zero(), shift = Vec3::Zero();
  bool rigid = true;
  out = Affine::Identity();
  for (std::size_t k = 0; k < chain.size(); ++k) {
    const Action& action = scene.actions[static_cast<std::size_t>(chain[k])];
    // The action's rate (plan units per unit of time): its own parameter's,
    // or its master's times the multiplier (driving_value).
    const auto rate = [&](int i) {
      if (action.mimic < 0) return rates[static_cast<std::size_t>(action.first_parameter + i)];
      const Action& master = scene.actions[static_cast<std::size_t>(action.mimic)];
      return action.multiplier * rates[static_cast<std::size_t>(master.first_parameter)];
    };
    // out is the product of the actions above this one (the identity first).
    switch (action.type) {
      case ActionType::kRotate: {
        const double omega = rate(0) * action.unit_to_si;
        const Vec3 axis = k == 0 ? action.axis : Vec3(out.linear() * action.axis);
        const Vec3 pivot = k == 0 ? action.pivot : Vec3(out * action.pivot);
        spin += omega * axis;
        shift -= omega * axis.cross(pivot);
        break;
      }
      case ActionType::kTranslateAxis:
        shift += rate(0) * action.unit_to_si * (k == 0 ? action.axis : Vec3(out.linear() * action.axis));
        break;
      case ActionType::kTranslateFree: {
        const Vec3 v = Vec3(rate(0), rate(1), rate(2)) * action.unit_to_si;
        shift += k == 0 ? v : Vec3(out.linear() * v);
        break;
      }
      case ActionType::kScale:
        rigid = false;
        break;
    }
    // compose's product, in its order.
    if (k == 0)
      out = action_transform_at(scene, action, params);
    else
      times(out, action_transform_at(scene, action, params), out);
  }
  if (!rigid) return false;
  w = spin;
  u = shift;
  return true;
}

int first_limit_violation(const Scene& scene, std::span<const double> params) {
  for (std::size_t a = 0; a < scene.actions.size(); ++a) {
    const Action& action = scene.actions[a];
    if (!action.has_limits) continue;
    for (int k = 0; k < action.parameter_count; ++k) {
      const double v = params[action.first_parameter + k];
      // Written so that NaN counts as a violation: never a false "within limits".
      if (!(v >= action.lower && v <= action.upper)) return static_cast<int>(a);
    }
  }
  return -1;
}

bool is_rigid(const Affine& t) {
  constexpr double kTolerance = 1e-9;
  const Mat3 r = t.linear();
  return (r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() <= kTolerance &&
         std::abs(r.determinant() - 1.0) <= kTolerance;
}

}  // namespace plancheck

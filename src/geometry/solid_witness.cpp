// SPDX-License-Identifier: MIT
// Part-scale contact certificates (src/geometry/solid_witness.h).
#include "src/geometry/solid_witness.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace plancheck {

namespace {

// Union-find over corner ids.
struct Sets {
  std::vector<std::uint32_t> up;
  explicit Sets(std::size_t n) : up(n) { std::iota(up.begin(), up.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (up[x] != x) x = up[x] = up[up[x]];
    return x;
  }
  void join(std::uint32_t x, std::uint32_t y) { up[find(x)] = find(y); }
};

double abs_max(const Vec3& v) { return v.cwiseAbs().maxCoeff(); }

// Whether the linear part is a rotation to within rounding.
bool rigid(const Affine& t) {
  const Mat3 r = t.linear();
  if (!r.allFinite() || !t.translation().allFinite()) return false;
  return ((r.transpose() * r) - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-12 && r.determinant() > 0.0;
}

// Distance from p to the box [lo, hi] (0 inside).
double box_distance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  const Vec3 below = (lo - p).cwiseMax(0.0), above = (p - hi).cwiseMax(0.0);
  return (below + above).norm();
}

}  // namespace

SolidPieces solid_pieces(const Mesh& mesh, std::size_t max_planes) {
  SolidPieces out;
  const std::size_t nv = mesh.vertices.size();
  // Corners at equal positions are one corner.
  std::vector<std::uint32_t> id(nv);
  {
    std::vector<std::uint32_t> order(nv);
    std::iota(order.begin(), order.end(), 0u);
    auto key = [&](std::uint32_t v) {
      const Vec3& x = mesh.vertices[v];
      return std::array<double, 3>{x.x(), x.y(), x.z()};
    };
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
    for (std::size_t i = 0; i < nv; ++i)
      id[order[i]] = i > 0 && key(order[i]) == key(order[i - 1]) ? id[order[i - 1]] : order[i];
  }
  Sets sets(nv);
  for (const Tri& t : mesh.triangles) {
    sets.join(id[t[0]], id[t[1]]);
    sets.join(id[t[0]], id[t[2]]);
  }
  // Pieces: their corners (one vertex per position) and triangles.
  std::unordered_map<std::uint32_t, std::size_t> piece_of;
  std::vector<std::vector<std::size_t>> tris;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const std::uint32_t root = sets.find(id[mesh.triangles[i][0]]);
    auto [it, fresh] = piece_of.try_emplace(root, out.pieces.size());
    if (fresh) {
      out.pieces.push_back({});
      tris.push_back({});
    }
    tris[it->second].push_back(i);
  }
  for (std::size_t p = 0; p < out.pieces.size(); ++p) {
    SolidPieces::Piece& piece = out.pieces[p];
    std::vector<std::uint32_t> corners;
    for (std::size_t i : tris[p])
      for (std::uint32_t v : mesh.triangles[i]) corners.push_back(id[v]);
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    piece.vertices = corners;
    piece.lo = piece.hi = mesh.vertices[corners.front()];
    for (std::uint32_t v : corners) {
      piece.lo = piece.lo.cwiseMin(mesh.vertices[v]);
      piece.hi = piece.hi.cwiseMax(mesh.vertices[v]);
    }
    if (!piece.lo.allFinite() || !piece.hi.allFinite()) continue;
    out.magnitude = std::max({out.magnitude, abs_max(piece.lo), abs_max(piece.hi)});

    // Closed: every directed edge matched by its reverse.
    std::vector<std::pair<std::uint64_t, int>> edges;
    edges.reserve(3 * tris[p].size());
    bool closed = true;
    double volume = 0.0;
    const Vec3 origin = piece.lo;
    for (std::size_t i : tris[p]) {
      const Tri& t = mesh.triangles[i];
      const std::uint32_t c[3] = {id[t[0]], id[t[1]], id[t[2]]};
      if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) closed = false;
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t u = c[e], w = c[(e + 1) % 3];
        if (u < w) edges.push_back({(std::uint64_t{u} << 32) | w, 1});
        else edges.push_back({(std::uint64_t{w} << 32) | u, -1});
      }
      const Vec3 x = mesh.vertices[c[0]] - origin, y = mesh.vertices[c[1]] - origin, z = mesh.vertices[c[2]] - origin;
      volume += x.dot(y.cross(z));
    }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size() && closed;) {
      int sum = 0;
      std::size_t j = i;
      for (; j < edges.size() && edges[j].first == edges[i].first; ++j) sum += edges[j].second;
      closed = sum == 0;
      i = j;
    }
    if (!closed || !(volume != 0.0) || !std::isfinite(volume)) continue;
    const double sign = volume > 0.0 ? 1.0 : -1.0;  // outward normals

    // Planes: triangles grouped by normal and offset.
    const double diagonal = (piece.hi - piece.lo).norm();
    const double scale = std::max({abs_max(piece.lo), abs_max(piece.hi), diagonal});
    SolidPieces::Solid solid;
    solid.lo = piece.lo;
    solid.hi = piece.hi;
    std::map<std::array<long long, 4>, std::size_t> group;
    double spread = 0.0;
    bool ok = true;
    for (std::size_t i : tris[p]) {
      const Tri& t = mesh.triangles[i];
      const Vec3& x = mesh.vertices[id[t[0]]];
      const Vec3& y = mesh.vertices[id[t[1]]];
      const Vec3& z = mesh.vertices[id[t[2]]];
      Vec3 n = (y - x).cross(z - x);
      const double len = n.norm(), edges = (y - x).norm() * (z - x).norm();
      // A triangle too thin to have a trustworthy plane leaves the piece out.
      if (!(len > 1e-6 * edges)) {
        ok = false;
        break;
      }
      // The computed unit normal is within 1e-14 |e1| |e2| / |e1 x e2| of
      // the true one (a few roundings of the differences and products).
      spread = std::max(spread, 1e-14 * edges / len);
      n *= sign / len;
      const double off = n.dot(x);
      const std::array<long long, 4> key = {std::llround(n.x() * 1e6), std::llround(n.y() * 1e6),
                                            std::llround(n.z() * 1e6), std::llround(off / scale * 1e6)};
      auto [it, fresh] = group.try_emplace(key, solid.planes.size());
      if (fresh) {
        if (solid.planes.size() >= max_planes) {
          ok = false;
          break;
        }
        solid.planes.push_back({n, off});
      }
      SolidPieces::Plane& g = solid.planes[it->second];
      spread = std::max(spread, (n - g.n).norm());
      g.d = std::min({g.d, g.n.dot(x), g.n.dot(y), g.n.dot(z)});
    }
    if (!ok) continue;
    solid.slack = (spread + 1e-12) * diagonal + 1e-9 * scale + 1e-12;
    solid.deepest = 0.5 * (piece.hi - piece.lo).minCoeff();
    out.deepest = std::max(out.deepest, solid.deepest);
    out.solids.push_back(std::move(solid));
  }
  return out;
}

namespace {

// Vertices of a piece scanned for a witness, at most.
constexpr std::size_t kScan = 64;

// One order: a piece of `a` inside a solid of `b`; `lever` bounds a
// point of a's moves (null: `whole` for every point), `solid_move` every
// point of b's (pad included).
bool one_way(const Mesh& ma, const SolidPieces& sa, const Affine& pa, const SolidPieces& sb, const Affine& pb,
             const BoxMotion::Lever* lever, double whole, double solid_move, double pad, SolidHint& hint, int order) {
  if (sb.solids.empty() || sa.pieces.empty() || !(sb.deepest > solid_move + pad)) return false;
  // a's mesh frame into b's: x_b = R^T (pa x - t_b).
  const Mat3 rt = pb.linear().transpose();
  const Mat3 r = rt * pa.linear();
  const Vec3 t = rt * (pa.translation() - pb.translation());
  auto into_b = [&](std::uint32_t v) -> Vec3 { return r * ma.vertices[v] + t; };
  // Rounding of the transform: far below 1e-9 of the magnitudes it adds.
  const double rel = 1e-9;
  const double frame = rel * (abs_max(pa.translation()) + abs_max(pb.translation()) + sa.magnitude + sb.magnitude);
  // The depth of x below every plane, or at most `floor` once it cannot exceed that.
  auto depth = [&](const SolidPieces::Solid& s, const Vec3& x, double floor = 0.0) {
    double least = std::numeric_limits<double>::infinity();
    for (const SolidPieces::Plane& g : s.planes) {
      least = std::min(least, g.d - g.n.dot(x));
      if (!(least > floor)) return least;
    }
    return least;
  };
  // What a vertex of a must clear: its own move and the solid's, the
  // rounding, and for depth the planes' spread.
  // (The whole part's move bounds every point's: the lever only when
  // that is not enough.)
  auto clears = [&](const SolidPieces::Solid& s, std::uint32_t v, const Vec3& x, double d) {
    if (!(d > solid_move)) return false;
    const double rest = pad + solid_move + frame + rel * (abs_max(x) + abs_max(s.lo) + abs_max(s.hi)) + 1e-12;
    if (d > whole + rest) return true;
    return lever && d > lever->point(ma.vertices[v]) + rest;
  };
  auto deep = [&](const SolidPieces::Solid& s, std::uint32_t v, const Vec3& x) {
    return clears(s, v, x, depth(s, x) - s.slack);
  };
  auto far = [&](const SolidPieces::Solid& s, std::uint32_t v, const Vec3& x) {
    return clears(s, v, x, box_distance(x, s.lo, s.hi));
  };
  // The last witness first.
  if (hint.order == order && hint.solid < sb.solids.size() && hint.inside < ma.vertices.size() &&
      hint.outside < ma.vertices.size()) {
    const SolidPieces::Solid& s = sb.solids[hint.solid];
    if (deep(s, hint.inside, into_b(hint.inside)) && far(s, hint.outside, into_b(hint.outside))) return true;
  }
  // Every piece of a against every solid of b whose boxes meet.
  for (std::size_t si = 0; si < sb.solids.size(); ++si) {
    const SolidPieces::Solid& s = sb.solids[si];
    if (!(s.deepest > solid_move + pad)) continue;
    const Vec3 inner_lo = s.lo.array() + solid_move, inner_hi = s.hi.array() - solid_move;
    for (std::size_t pi = 0; pi < sa.pieces.size(); ++pi) {
      const SolidPieces::Piece& piece = sa.pieces[pi];
      // The piece's box in b's frame (its corners' hull) must reach the solid's core.
      Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (int c = 0; c < 8; ++c) {
        const Vec3 x(c & 1 ? piece.hi.x() : piece.lo.x(), c & 2 ? piece.hi.y() : piece.lo.y(),
                     c & 4 ? piece.hi.z() : piece.lo.z());
        const Vec3 y = r * x + t;
        lo = lo.cwiseMin(y);
        hi = hi.cwiseMax(y);
      }
      if ((hi.array() < inner_lo.array()).any() || (lo.array() > inner_hi.array()).any()) continue;
      // The deepest vertex and the farthest out, each then asked once with
      // its own move (a point's bound costs more than its depth).
      // (At most kScan vertices of a piece, evenly spread: any vertex
      // may be a witness; the scan only looks for a good one.)
      std::int64_t in = -1, out = -1;
      double most_in = 0.0, most_out = 0.0;
      const std::size_t n = piece.vertices.size(), step = (n + kScan - 1) / kScan;
      for (std::size_t j = 0; j < n; j += step) {
        const std::uint32_t v = piece.vertices[j];
        const Vec3 x = into_b(v);
        const double gap = ((s.lo - x).cwiseMax(0.0) + (x - s.hi).cwiseMax(0.0)).squaredNorm();
        if (gap > most_out) {
          most_out = gap;
          out = v;
        }
        if ((x.array() > inner_lo.array()).all() && (x.array() < inner_hi.array()).all()) {
          const double d = depth(s, x, most_in);
          if (d > most_in) {
            most_in = d;
            in = v;
          }
        }
      }
      if (in >= 0 && out >= 0) {
        const std::uint32_t i = static_cast<std::uint32_t>(in), o = static_cast<std::uint32_t>(out);
        const Vec3 xi = into_b(i), xo = into_b(o);
        if (deep(s, i, xi) && far(s, o, xo)) {
          hint = {order, static_cast<std::uint32_t>(si), static_cast<std::uint32_t>(pi), i, o, 1.0};
          return true;
        }
        // How near it came: the share of the moves these two clear.
        const double need_i = (lever ? lever->point(ma.vertices[i]) : whole) + solid_move + pad;
        const double need_o = (lever ? lever->point(ma.vertices[o]) : whole) + solid_move + pad;
        const double share = std::min((depth(s, xi) - s.slack) / need_i, box_distance(xo, s.lo, s.hi) / need_o);
        if (share > hint.ratio) hint.ratio = share;
      }
    }
  }
  return false;
}

}  // namespace

bool solid_crossing(const Mesh& ma, const SolidPieces& sa, const Affine& pa, const Mesh& mb,
                    const SolidPieces& sb, const Affine& pb, const SolidMoves& moves, SolidHint& hint) {
  hint.ratio = 0.0;
  if (!rigid(pa) || !rigid(pb)) return false;
  const double wa = moves.whole_a + moves.pad, wb = moves.whole_b + moves.pad;
  if (!(wa >= 0.0 && wb >= 0.0 && std::isfinite(wa) && std::isfinite(wb))) return false;
  const bool first = hint.order == 1;
  for (int n = 0; n < 2; ++n) {
    const bool reverse = (n == 0) == first;
    if (reverse ? one_way(mb, sb, pb, sa, pa, moves.b, moves.whole_b, wa, moves.pad, hint, 1)
                : one_way(ma, sa, pa, sb, pb, moves.a, moves.whole_a, wb, moves.pad, hint, 0))
      return true;
  }
  return false;
}

}  // namespace plancheck

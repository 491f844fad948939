// SPDX-License-Identifier: MIT
// A contact certificate at the parts' scale, for whole boxes of a sweep
// (src/checks/sweep_certify.h): one part's connected surface reaches deep
// into a closed piece of the other's and out of it again, so the two
// surfaces meet wherever the parts go within the box.
//
// The argument. Let C be a closed piece of part B's mesh (every directed
// edge matched by its reverse: a 2-cycle, so the winding number of C
// around a point off C is an integer, constant along any path that does
// not meet C). Let K be a connected piece of part A's surface with
//  - a vertex p below the plane of every triangle of C by more than m
//    (outward normals): each triangle, seen from p's side, subtends a solid
//    angle of the same sign, so their sum, an integer, is not 0 (p is
//    enclosed), and every point of C is farther than m from p;
//  - a vertex q farther than m from C's bounding box: winding number 0.
// If no point of A moves by more than da, and no point of C by more than
// db, between the box's centre (where the test is made, m = da + db) and
// any configuration of it, along a path of configurations within the box,
// p stays off C (the distance shrinks by at most da + db), and so does q
// (C stays in its box grown by db): p's winding number stays nonzero and
// q's 0, so K, connected, meets C at every configuration: the parts are
// in contact there, as the exact test (touching counts) reports.
//
// Depth below the triangles' planes: coplanar triangles are grouped under
// one normal n with the least n . v over their corners (so every point of
// them is at least that far along n); a triangle whose own normal differs
// from n by e is below its own plane wherever the group's depth exceeds e
// times the piece's diagonal. Rounding (posing, the transform into B's
// frame, the dot products) is far below the relative slack the test keeps.
#pragma once

#include "src/geometry/box_motion.h"
#include "src/scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace plancheck {

// One mesh's pieces, built once.
struct SolidPieces {
  struct Piece {  // connected through shared corners (equal positions)
    std::vector<std::uint32_t> vertices;  // indices into the mesh's vertices
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // their box, mesh frame
  };
  struct Plane {
    Vec3 n = Vec3::Zero();  // outward, unit
    double d = 0.0;  // least n . x over the group's corners
  };
  struct Solid {  // a closed piece (see above), mesh frame
    std::vector<Plane> planes;
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
    double slack = 0.0;  // the normals' spread times the diagonal, plus rounding
    double deepest = 0.0;  // no point is deeper than this (half the box's least side)
  };
  std::vector<Piece> pieces;
  std::vector<Solid> solids;
  double deepest = 0.0;    // over the solids
  double magnitude = 0.0;  // the largest coordinate of a piece's corner
};

// Pieces and closed pieces of a mesh. A closed piece with more than
// `max_planes` distinct planes, or with a degenerate triangle, is left out
// (it certifies nothing then; nothing else changes).
SolidPieces solid_pieces(const Mesh& mesh, std::size_t max_planes = 1024);

// Where the last witness of a pair was found, tried first next time.
struct SolidHint {
  int order = -1;  // 0: a piece of a in a solid of b; 1: the reverse
  std::uint32_t solid = 0, piece = 0, inside = 0, outside = 0;
  // Set by each call: 1 when it certified, else the largest share of the
  // moves a candidate pair of vertices cleared (0: none was found); a
  // share far below 1 says smaller boxes are not worth asking.
  double ratio = 0.0;
};

// How far points of the two parts move between the box's centre and any
// configuration of it (m): per point of a piece (its part's lever), and
// for the whole part (for a solid; and for a piece's points when its lever
// is null), each plus `pad` (posing's rounding).
struct SolidMoves {
  const BoxMotion::Lever* a = nullptr;
  const BoxMotion::Lever* b = nullptr;
  double whole_a = 0.0, whole_b = 0.0;
  double pad = 0.0;
};

// True when a connected piece of one mesh (posed by its pose) has a vertex
// inside a solid of the other, deeper than its own move plus the solid's
// part's, and a vertex outside that solid's box by more than the same:
// the parts' surfaces meet at every configuration of the box (above). Both
// poses must be rigid (checked: false otherwise). False proves nothing.
bool solid_crossing(const Mesh& ma, const SolidPieces& sa, const Affine& pa, const Mesh& mb,
                    const SolidPieces& sb, const Affine& pb, const SolidMoves& moves, SolidHint& hint);

}  // namespace plancheck

// SPDX-License-Identifier: GPL-3.0-or-later
// Whether two faces of one triangle mesh intersect beyond the corners they share, as CGAL's
// `self_intersections` counts it (exact predicates), and the R-tree of face boxes that finds the pairs to test.
// The overlay decimation and the repair of the N-way outputs test their new faces with them, one pair at a time,
// where the verifier tests the whole mesh.
#ifndef CROSSPARAM_INTERNAL_REMESHING_TRIANGLE_INTERSECTION_H
#define CROSSPARAM_INTERNAL_REMESHING_TRIANGLE_INTERSECTION_H

#include <crossparam/types.h>

#include <CGAL/intersections.h>

#include <boost/geometry/algorithms/covered_by.hpp> // the R-tree needs these three and the strategies
#include <boost/geometry/algorithms/equals.hpp>
#include <boost/geometry/algorithms/intersects.hpp>
#include <boost/geometry/geometries/box.hpp>
#include <boost/geometry/geometries/point.hpp>
#include <boost/geometry/index/rtree.hpp>
#include <boost/geometry/strategies/strategies.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

namespace crossparam {
namespace internal {

/// Faces by their boxes, in an R-tree (Boost.Geometry's, R*-tree nodes of at most 16): a query visits the faces
/// whose boxes meet a given box, at any mix of face sizes. An entry is a face's box as entered and the face; a
/// face whose corners move is taken out with that box and entered again.
using Face_box_point = boost::geometry::model::point<double, 3, boost::geometry::cs::cartesian>;
using Face_box = boost::geometry::model::box<Face_box_point>;
using Face_box_entry = std::pair<Face_box, std::uint32_t>;
using Face_box_index = boost::geometry::index::rtree<Face_box_entry, boost::geometry::index::rstar<16>>;
inline Face_box to_face_box(const CGAL::Bbox_3& b) {
  return Face_box(Face_box_point(b.xmin(), b.ymin(), b.zmin()), Face_box_point(b.xmax(), b.ymax(), b.zmax()));
}

/// Whether the corners of face `e` that face `f` does not share are all strictly on one side of f's plane, by
/// more than 10⁻⁹ of the product of the lengths involved (rounding of the computation is about 10⁻¹⁵ of it,
/// so the answer is certain); false when unsure or when e shares every corner. `P(v)` is the point of vertex v.
template <class Index, class Position>
bool strictly_one_side(const std::array<Index, 3>& f, const std::array<Index, 3>& e, const Position& P) {
  const Point_3 &a = P(f[0]), &b = P(f[1]), &c = P(f[2]);
  const Kernel::Vector_3 n = CGAL::cross_product(b - a, c - a);
  const double ln = std::sqrt(n.squared_length());
  const double span = std::sqrt(CGAL::squared_distance(a, b)) + std::sqrt(CGAL::squared_distance(a, c));
  int side = 0;
  for (const Index& v : e) {
    if (v == f[0] || v == f[1] || v == f[2]) continue;
    const Kernel::Vector_3 x = P(v) - a;
    const double dist = n * x, bound = 1e-9 * ln * (span + std::sqrt(x.squared_length()));
    const int sv = dist > bound ? 1 : dist < -bound ? -1 : 0;
    if (sv == 0 || (side != 0 && sv != side)) return false;
    side = sv;
  }
  return side != 0;
}

/// Whether faces `f` and `e`, which share one corner or one edge, are certainly apart beyond it: a plane through
/// the shared corner and one of f's edges there (or through the shared edge), perpendicular to f, has f's other
/// corner strictly on one side and e's corners that f does not share strictly on the other, by more than 10⁻⁹
/// of the product of the lengths involved (rounding is about 10⁻¹⁵ of it). f lies in one closed side and meets
/// the plane in that edge; e lies in the other and meets it in the shared corner or edge only; so the faces meet
/// there only. False when unsure. Such pairs, nearly coplanar (a face subdivided, or neighbours on a flat
/// part), are where the exact predicates are slowest.
template <class Index, class Position>
bool apart_at_shared(const std::array<Index, 3>& f, const std::array<Index, 3>& e, const Position& P) {
  auto shared = [&](const Index& v) { return v == e[0] || v == e[1] || v == e[2]; };
  const Kernel::Vector_3 n = CGAL::cross_product(P(f[1]) - P(f[0]), P(f[2]) - P(f[0]));
  for (int i = 0; i < 6; ++i) {
    // The plane through f's edge (a, b) at a shared corner a, f's third corner c not shared: both edges at a
    // where one corner is shared, the shared edge where two are.
    const int k = i / 2, j = 1 + i % 2;
    const Index &a = f[k], &b = f[(k + j) % 3], &c = f[(k + 3 - j) % 3];
    if (!shared(a) || shared(c)) continue;
    const Kernel::Vector_3 edge = P(b) - P(a), m = CGAL::cross_product(n, edge);
    const double lm = std::sqrt(m.squared_length());
    auto side = [&](const Index& v) {
      const Kernel::Vector_3 x = P(v) - P(a);
      const double d = m * x, bound = 1e-9 * lm * std::sqrt(x.squared_length());
      return d > bound ? 1 : d < -bound ? -1 : 0;
    };
    const int own = side(c);
    if (own == 0) continue;
    bool apart = true;
    for (const Index& v : e)
      if (v != f[0] && v != f[1] && v != f[2] && side(v) != -own) apart = false;
    if (apart) return true;
  }
  return false;
}

/// Whether triangles with corners c and d (vertex indices; `P(v)` the point of v) intersect beyond the corners
/// they share, with exact predicates: none shared, any common point; one, the opposite edge of either meets the
/// other; two, the other corners on one side of the shared edge in a common plane; three, the same face.
/// Neither face may be degenerate (the verifier counts a degenerate face on its own).
template <class Index, class Position>
bool faces_intersect(const std::array<Index, 3>& c, const std::array<Index, 3>& d, const Position& P) {
  int shared = 0, ci = -1, di = -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (c[i] == d[j]) ++shared, ci = i, di = j;
  // First in floating point: the corners of one face that it does not share, all strictly on one side of the
  // other's plane by far more than rounding, cannot meet the other face (but at a shared corner). Only the faces
  // this does not settle (near each other's planes) go to the exact predicates.
  if (shared < 3 && (strictly_one_side(c, d, P) || strictly_one_side(d, c, P))) return false;
  if ((shared == 1 || shared == 2) && (apart_at_shared(c, d, P) || apart_at_shared(d, c, P))) return false;
  const Kernel::Triangle_3 tc(P(c[0]), P(c[1]), P(c[2])), td(P(d[0]), P(d[1]), P(d[2]));
  if (shared == 0) return CGAL::do_intersect(tc, td);
  if (shared == 1) {
    const Kernel::Segment_3 oc(P(c[(ci + 1) % 3]), P(c[(ci + 2) % 3])), od(P(d[(di + 1) % 3]), P(d[(di + 2) % 3]));
    return CGAL::do_intersect(oc, td) || CGAL::do_intersect(od, tc);
  }
  if (shared == 2) {
    int oc = -1, od = -1; // the corners not shared
    for (int i = 0; i < 3; ++i) {
      if (c[i] != d[0] && c[i] != d[1] && c[i] != d[2]) oc = i;
      if (d[i] != c[0] && d[i] != c[1] && d[i] != c[2]) od = i;
    }
    const Point_3 &p = P(c[(oc + 1) % 3]), &q = P(c[(oc + 2) % 3]), &r = P(c[oc]), &t = P(d[od]);
    return CGAL::coplanar(p, q, r, t) && CGAL::coplanar_orientation(p, q, r, t) == CGAL::POSITIVE;
  }
  return true; // the same face twice
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_TRIANGLE_INTERSECTION_H

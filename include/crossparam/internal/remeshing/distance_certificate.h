// SPDX-License-Identifier: GPL-3.0-or-later
// A certified bound of the distance from a triangle of the target-shaped mesh to the target (an addition to the
// paper): whether every point of the triangle, not only samples of it, lies within a given distance of the
// target. Used by the overlay's decimation (overlay_decimation.h) for every face it makes, and by the strict
// repair (strict_repair.h) so that its repairs of the decimated overlay keep that bound.
#ifndef CROSSPARAM_INTERNAL_REMESHING_DISTANCE_CERTIFICATE_H
#define CROSSPARAM_INTERNAL_REMESHING_DISTANCE_CERTIFICATE_H

#include <crossparam/internal/remeshing/remesh_state.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace crossparam {
namespace internal {

/// Levels of midpoint subdivision a distance certificate may use (4^4 = 256 pieces) before it gives up (and
/// the face is refused). A face whose longest edge is within √3 times the distance needs none.
constexpr int certificate_depth = 4;

/// The target's faces in an AABB tree, for distance queries.
using Target_tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_face_graph_triangle_primitive<Work_mesh>>>;

/// A point with an upper bound of its distance from the target and a target face that near.
struct Distance_probe {
  Point_3 p;
  double d;
  WF near;
};

/// The triangle of target face t.
inline Kernel::Triangle_3 target_triangle(const Work_mesh& target, WF t) {
  const WH h = target.halfedge(t);
  return {target.point(target.source(h)), target.point(target.target(h)), target.point(target.target(target.next(h)))};
}

/// The probe of point p: its distance from the target and the face nearest it (the search starts from `hint`,
/// which it updates: nearby queries end sooner).
inline Distance_probe probe(const Target_tree& tree, const Point_3& p, std::pair<Point_3, WF>& hint) {
  hint = tree.closest_point_and_primitive(p, hint);
  return {p, std::sqrt(CGAL::squared_distance(p, hint.first)), hint.second};
}

/// Whether every point of triangle (a, b, c) is within `limit` of the target, given upper bounds of its
/// corners' distances and target faces near them. Two bounds certify it, each from a known fact:
///  - the distance to one target face t is convex, so over the triangle it is largest at a corner: if every
///    corner is within the limit of the face near one of them, so is the triangle (the usual case: a face
///    over one flat part of the target);
///  - the distance to the target changes by at most the distance moved, and no point of a triangle is farther
///    from its nearest corner than its longest edge over √3 (the circumradius of an acute triangle, whose
///    largest angle is at least 60°; less for an obtuse one): the largest corner bound plus that.
/// When neither does, the triangle is split at its edge midpoints (their distances measured) and each quarter
/// certified in turn, down to certificate_depth levels; false if that does not settle it.
inline bool certified_within(const Target_tree& tree, const Work_mesh& target, const Distance_probe& a,
                             const Distance_probe& b, const Distance_probe& c, double limit,
                             std::pair<Point_3, WF>& hint, int depth = 0) {
  const double limit2 = limit * limit;
  for (const WF t : {a.near, b.near, c.near}) {
    const Kernel::Triangle_3 T = target_triangle(target, t);
    if (CGAL::squared_distance(a.p, T) <= limit2 && CGAL::squared_distance(b.p, T) <= limit2 &&
        CGAL::squared_distance(c.p, T) <= limit2)
      return true;
  }
  const double longest =
      std::sqrt(std::max({CGAL::squared_distance(a.p, b.p), CGAL::squared_distance(b.p, c.p), CGAL::squared_distance(c.p, a.p)}));
  if (std::max({a.d, b.d, c.d}) + longest / std::sqrt(3.0) <= limit) return true;
  if (depth == certificate_depth) return false;
  const Distance_probe ab = probe(tree, CGAL::midpoint(a.p, b.p), hint), bc = probe(tree, CGAL::midpoint(b.p, c.p), hint),
                       ca = probe(tree, CGAL::midpoint(c.p, a.p), hint);
  if (std::max({ab.d, bc.d, ca.d}) > limit) return false;
  return certified_within(tree, target, a, ab, ca, limit, hint, depth + 1) &&
         certified_within(tree, target, ab, b, bc, limit, hint, depth + 1) &&
         certified_within(tree, target, ca, bc, c, limit, hint, depth + 1) &&
         certified_within(tree, target, ab, bc, ca, limit, hint, depth + 1);
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_DISTANCE_CERTIFICATE_H

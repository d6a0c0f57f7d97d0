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

/// A point with an upper bound of its distance from a surface and a face of it that near (Id: the surface's
/// AABB tree's primitive id; a target face for the target).
template <class Id>
struct Basic_distance_probe {
  Point_3 p;
  double d;
  Id near;
};
/// A probe of the target.
using Distance_probe = Basic_distance_probe<WF>;

/// The triangle of target face t.
inline Kernel::Triangle_3 target_triangle(const Work_mesh& target, WF t) {
  const WH h = target.halfedge(t);
  return {target.point(target.source(h)), target.point(target.target(h)), target.point(target.target(target.next(h)))};
}

/// The probe of point p: its distance from the surface in `tree` and the face nearest it (the search starts
/// from `hint`, which it updates: nearby queries end sooner).
template <class Tree>
Basic_distance_probe<typename Tree::Primitive_id> probe(const Tree& tree, const Point_3& p,
                                                        std::pair<Point_3, typename Tree::Primitive_id>& hint) {
  hint = tree.closest_point_and_primitive(p, hint);
  return {p, std::sqrt(CGAL::squared_distance(p, hint.first)), hint.second};
}

/// Whether every point of triangle (a, b, c) is within `limit` of the surface in `tree` (whose face `near`
/// gives as a triangle), given upper bounds of its corners' distances and faces near them. Two bounds certify
/// it, each from a known fact:
///  - the distance to one face t is convex, so over the triangle it is largest at a corner: if every corner is
///    within the limit of the face near one of them, so is the triangle (the usual case: a triangle over one
///    flat part of the surface);
///  - the distance to the surface changes by at most the distance moved, and no point of a triangle is farther
///    from its nearest corner than its longest edge over √3 (the circumradius of an acute triangle, whose
///    largest angle is at least 60°; less for an obtuse one): the largest corner bound plus that.
/// When neither does, the triangle is split at its edge midpoints (their distances measured) and each quarter
/// certified in turn, down to certificate_depth levels; false if that does not settle it.
template <class Tree, class Triangle_of, class Id = typename Tree::Primitive_id>
bool certified_within(const Tree& tree, const Triangle_of& near, const Basic_distance_probe<Id>& a,
                      const Basic_distance_probe<Id>& b, const Basic_distance_probe<Id>& c, double limit,
                      std::pair<Point_3, Id>& hint, int depth = 0) {
  const double limit2 = limit * limit;
  for (const Id& t : {a.near, b.near, c.near}) {
    const Kernel::Triangle_3 T = near(t);
    if (CGAL::squared_distance(a.p, T) <= limit2 && CGAL::squared_distance(b.p, T) <= limit2 &&
        CGAL::squared_distance(c.p, T) <= limit2)
      return true;
  }
  const double longest = longest_side(a.p, b.p, c.p);
  if (std::max({a.d, b.d, c.d}) + longest / std::sqrt(3.0) <= limit) return true;
  if (depth == certificate_depth) return false;
  const auto ab = probe(tree, CGAL::midpoint(a.p, b.p), hint), bc = probe(tree, CGAL::midpoint(b.p, c.p), hint),
             ca = probe(tree, CGAL::midpoint(c.p, a.p), hint);
  if (std::max({ab.d, bc.d, ca.d}) > limit) return false;
  return certified_within(tree, near, a, ab, ca, limit, hint, depth + 1) &&
         certified_within(tree, near, ab, b, bc, limit, hint, depth + 1) &&
         certified_within(tree, near, ca, bc, c, limit, hint, depth + 1) &&
         certified_within(tree, near, ab, bc, ca, limit, hint, depth + 1);
}

/// The same for the target, whose faces are those of `target`.
inline bool certified_within(const Target_tree& tree, const Work_mesh& target, const Distance_probe& a,
                             const Distance_probe& b, const Distance_probe& c, double limit,
                             std::pair<Point_3, WF>& hint) {
  return certified_within(tree, [&target](WF t) { return target_triangle(target, t); }, a, b, c, limit, hint);
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_DISTANCE_CERTIFICATE_H

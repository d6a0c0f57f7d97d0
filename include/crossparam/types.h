// SPDX-License-Identifier: GPL-3.0-or-later
// Vocabulary types shared by every stage.
#ifndef CROSSPARAM_TYPES_H
#define CROSSPARAM_TYPES_H

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <array>
#include <cstddef>
#include <utility>
#include <vector>

namespace crossparam {

/// The kernel used for every geometric decision (exact predicates, inexact constructions).
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point_3 = Kernel::Point_3;
/// The default mesh type of the CLI and the examples; the algorithms accept any BGL face graph.
using Surface_mesh = CGAL::Surface_mesh<Point_3>;

/// One feature correspondence: vertex `source` of the source mesh matches vertex `target` of the target
/// mesh. Indices are 0-based, in file order (for a Surface_mesh: the vertex index). Entry k is feature k.
struct Feature_pair {
  std::size_t source = 0;
  std::size_t target = 0;
  friend bool operator==(const Feature_pair& a, const Feature_pair& b) {
    return a.source == b.source && a.target == b.target;
  }
};
using Feature_correspondence = std::vector<Feature_pair>;

/// A polygon soup exactly as read from a file: points and polygons (0-based point indices) in file order.
struct Polygon_soup {
  std::vector<std::array<double, 3>> points;
  std::vector<std::vector<std::size_t>> polygons;
};

namespace internal {
/// Normal of triangle (a, b, c), not normalised; the zero vector for a degenerate triangle (unlike
/// CGAL::normal, whose precondition rejects it).
template <class P>
auto triangle_normal(const P& a, const P& b, const P& c) {
  return CGAL::cross_product(b - a, c - a);
}

/// The flip rule of the remeshing verification: triangle (a, b, c) is flipped against a surface if its normal
/// opposes the surface's at the points of the surface nearest its centroid and each of its corners (a face
/// across a sharp crease of the surface agrees with one side of it: a chord, not a flip). `tree`: an AABB tree
/// of the surface's faces; `face_normal(f)`: the normal of its face f (any length).
template <class Tree, class FaceNormal, class P>
bool flipped_against_nearest(const Tree& tree, const FaceNormal& face_normal, const P& a, const P& b, const P& c) {
  const auto n = triangle_normal(a, b, c);
  for (const P& p : {CGAL::centroid(a, b, c), a, b, c})
    if (!(n * face_normal(tree.closest_point_and_primitive(p).second) < 0)) return false;
  return true;
}
} // namespace internal

} // namespace crossparam

#endif // CROSSPARAM_TYPES_H

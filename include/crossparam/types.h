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
/// Features of N meshes: row k is feature k, its entry m the vertex (0-based, input order) of mesh m.
using Multi_feature_correspondence = std::vector<std::vector<std::size_t>>;

/// A polygon soup exactly as read from a file: points and polygons (0-based point indices) in file order.
struct Polygon_soup {
  std::vector<std::array<double, 3>> points;
  std::vector<std::vector<std::size_t>> polygons;
};

/// Which of the two meshes of a map a query is about: the source (the mesh the map F starts from) or the
/// target.
enum class Mesh_side { source, target };

/// The other mesh: `source` for `target` and conversely.
inline constexpr Mesh_side other_side(Mesh_side side) {
  return side == Mesh_side::source ? Mesh_side::target : Mesh_side::source;
}

/// A triangle mesh as plain arrays: points and, per face, its three corners as indices into `points`.
struct Indexed_triangle_mesh {
  std::vector<Point_3> points;
  std::vector<std::array<std::size_t, 3>> faces;
};

/// \name Refined meshes
/// The cross-parameterization works on its own copy of each input mesh, refined by edge splits (the layout's,
/// paper §3.2, and the adjacency constraint's, §4.2): the *refined mesh*. Its vertex i is vertex i of the input
/// for i below the input's vertex count, then one vertex per split in the order performed; its points are in
/// *working coordinates*, the input translated and scaled to a unit bounding-box diagonal (so that tolerances
/// and predicates do not depend on the input's scale), and its faces are oriented outward (counter-clockwise
/// seen from outside). `Cross_parameterization::working_mesh()` gives it;
/// `Cross_parameterization::to_input_units()` takes its points back to the user's coordinates.
/// @{

/// The refined mesh type. Smoothing-weights policies (concept `SmoothingWeights`, smoothing.h) receive one.
using Refined_mesh = CGAL::Surface_mesh<Point_3>;
using Refined_vertex = Refined_mesh::Vertex_index;
using Refined_halfedge = Refined_mesh::Halfedge_index;
using Refined_edge = Refined_mesh::Edge_index;
using Refined_face = Refined_mesh::Face_index;

/// A point of a refined mesh: face `face` and barycentric coordinates `b` with respect to the face's corners
/// in halfedge order: source(h), target(h), target(next(h)) with h = halfedge(face).
struct Refined_location {
  Refined_face face;
  std::array<double, 3> b{{0, 0, 0}};
};
/// @}

/// A point of the base domain (paper §4): base triangle `tri` (an index into `Patch_layout::base_triangles`)
/// and barycentric coordinates with respect to its corners in `Patch_layout::base_triangles[tri]` order. A zero
/// coordinate is exact: the point is on that edge or corner, and belongs to every base triangle sharing it.
struct Base_location {
  int tri = -1;
  std::array<double, 3> b{{0, 0, 0}};
};

/// A point of an input mesh reported against the mesh as the user gave it: face index in input order and
/// barycentric coordinates with respect to that face's vertices in input order.
struct Input_location {
  std::size_t face = 0;
  std::array<double, 3> b{{0, 0, 0}};
};

/// Where one face of a refinement of an input mesh lies on that input mesh: inside input face `face` (index in
/// input order), whose vertices are `vertices` (input vertex indices, in the input face's own order), with
/// corner c of the refined face at barycentric coordinates `corners[c]` with respect to `vertices`.
struct Input_face_location {
  std::size_t face = 0;
  std::array<std::size_t, 3> vertices{{0, 0, 0}};
  std::array<std::array<double, 3>, 3> corners{};
};

namespace internal {
/// The index 0 (source) or 1 (target) of a side, as internal arrays of two use it.
inline constexpr int side_index(Mesh_side side) { return side == Mesh_side::source ? 0 : 1; }

/// Normal of triangle (a, b, c), not normalised; the zero vector for a degenerate triangle (unlike
/// CGAL::normal, whose precondition rejects it).
template <class P>
auto triangle_normal(const P& a, const P& b, const P& c) {
  return CGAL::cross_product(b - a, c - a);
}

} // namespace internal

} // namespace crossparam

#endif // CROSSPARAM_TYPES_H

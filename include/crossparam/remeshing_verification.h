// SPDX-License-Identifier: GPL-3.0-or-later
// Independent checks of a compatible remeshing (paper §5), trusting nothing the remesher computed: the two
// outputs share one face list; the target-shaped mesh is within the tolerance of the target by a two-sided
// Hausdorff distance (CGAL's bounded-error algorithm, not the remesher's e(v)); the source-shaped mesh lies on
// the source; no target-shaped face is flipped against the target (the standard test: its normal against the
// target's at the point nearest its centroid); the target-shaped mesh intersects itself nowhere the target
// does not. Reported besides: faces deviating beyond 30 degrees from the target and creases beyond the target's.
#ifndef CROSSPARAM_REMESHING_VERIFICATION_H
#define CROSSPARAM_REMESHING_VERIFICATION_H

#include <crossparam/types.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/locate.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <cmath>
#include <iterator>
#include <map>
#include <string>
#include <vector>

namespace crossparam {

/// What `verify_compatible_remeshing` found. Distances in percent of the target's bounding-box diagonal
/// (source distances: of the source's diagonal).
struct Remeshing_verification {
  bool compatible = false;          ///< same vertex count and the same face list
  double hausdorff_target = 0;      ///< two-sided Hausdorff distance, target-shaped output vs target
  double hausdorff_to_target = 0;   ///< one-sided parts of it: from the output to the target
  double hausdorff_from_target = 0; ///< and from the target to the output
  double hausdorff_source = 0;      ///< one-sided, from the source-shaped output to the source
  std::size_t flipped_faces = 0;    ///< target-shaped faces flipped: normal more than 90° from the target's at
                                    ///< the point of the target nearest the face's centroid
  double normal_deviation_mean = 0; ///< degrees: that angle, mean weighted by face area
  std::size_t faces_above_30 = 0;   ///< target-shaped faces where that angle exceeds 30°
  double normal_deviation_above_30 = 0; ///< percent of the target-shaped area where that angle exceeds 30°
  std::size_t creases_output = 0;   ///< edges of the target-shaped mesh whose two faces' normals differ by more
                                    ///< than 150° (a dihedral angle below 30°: a face folded back onto its neighbour)
  std::size_t creases_target = 0;   ///< the same count on the input target
  std::size_t excess_creases = 0;   ///< creases_output - creases_target, 0 if negative
  std::size_t self_intersections_output = 0; ///< intersecting face pairs of the target-shaped mesh (CGAL's
                                             ///< self_intersections: pairs that share more than an edge or a vertex)
  std::size_t self_intersections_target = 0; ///< the same count on the input target
  bool valid = false;               ///< compatible, both distances within bounds, no flipped face, no more
                                    ///< self-intersecting pairs than the input target has
  std::string message;              ///< empty when valid
};

/// Angles of the strict checks of `verify_compatible_remeshing`, in degrees.
namespace verification_angles {
/// A face is flipped when its normal and the target's make an angle above this: they point to opposite sides.
constexpr double flipped = 90;
/// The deviation reported as large (the paper's §5.4 threshold for pseudo edge flips).
constexpr double deviation = 30;
/// Two faces across an edge whose normals differ by more than this are folded back onto each other (a crease
/// of less than 30° between the faces).
constexpr double crease = 150;
} // namespace verification_angles

namespace internal {

template <class Mesh>
std::vector<std::array<std::size_t, 3>> face_list(const Mesh& m) {
  std::map<typename boost::graph_traits<Mesh>::vertex_descriptor, std::size_t> index;
  std::size_t i = 0;
  for (auto v : vertices(m)) index[v] = i++;
  std::vector<std::array<std::size_t, 3>> out;
  for (auto f : faces(m)) {
    std::array<std::size_t, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(halfedge(f, m), m)) {
      if (k == 3) throw Input_error("compatibility check: a face is not a triangle");
      t[k++] = index[v];
    }
    out.push_back(t);
  }
  return out;
}

/// Edges of `m` whose two faces' normals make an angle above `degrees`.
template <class Mesh>
std::size_t count_creases(const Mesh& m, double degrees) {
  const double limit = std::cos(degrees * CGAL_PI / 180);
  auto normal = [&m](auto h) {
    return triangle_normal(get(CGAL::vertex_point, m, source(h, m)), get(CGAL::vertex_point, m, target(h, m)),
                           get(CGAL::vertex_point, m, target(next(h, m), m)));
  };
  std::size_t n = 0;
  for (auto e : edges(m)) {
    const auto h = halfedge(e, m), o = opposite(h, m);
    if (is_border(h, m) || is_border(o, m)) continue;
    const auto a = normal(h), b = normal(o);
    const double la = std::sqrt(a.squared_length()), lb = std::sqrt(b.squared_length());
    if (la > 0 && lb > 0 && (a * b) / (la * lb) < limit) ++n;
  }
  return n;
}

/// Intersecting face pairs of `m` (CGAL::Polygon_mesh_processing::self_intersections).
template <class Mesh>
std::size_t count_self_intersections(const Mesh& m) {
  using F = typename boost::graph_traits<Mesh>::face_descriptor;
  std::vector<std::pair<F, F>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections<CGAL::Sequential_tag>(m, std::back_inserter(pairs));
  return pairs.size();
}

template <class Mesh>
double bbox_diagonal(const Mesh& m) {
  CGAL::Bbox_3 b = CGAL::Polygon_mesh_processing::bbox(m);
  return std::sqrt(CGAL::square(b.xmax() - b.xmin()) + CGAL::square(b.ymax() - b.ymin()) + CGAL::square(b.zmax() - b.zmin()));
}

} // namespace internal

/// Whether two meshes have the same number of vertices and the same faces (as vertex index triples, in order).
template <class MeshA, class MeshB>
bool are_compatible(const MeshA& a, const MeshB& b) {
  return num_vertices(a) == num_vertices(b) && internal::face_list(a) == internal::face_list(b);
}

/// \brief Checks the two outputs of a compatible remeshing against the inputs (strict, standard checks).
///
/// - The Hausdorff distances are computed with CGAL's bounded-error algorithm to 1% of the tolerance.
/// - A face of the target-shaped mesh is flipped when its normal and the target's normal make an angle above
///   90°, the target's normal taken at the point of the target nearest the face's centroid: the normal of the
///   target face that CGAL's closest-point query returns for it (where that point is on a target edge or vertex,
///   one of the faces through it). The same angle gives the deviation figures.
/// - Creases: edges of the target-shaped mesh whose faces' normals differ by more than 150°, less those of the
///   input target (floored at 0).
/// - Self-intersections: CGAL's self_intersections on the target-shaped mesh and on the input target.
///
/// `valid`: compatible, the target within `tolerance` (two-sided), the source within `source_bound`, no flipped
/// face, and no more self-intersecting pairs than the input target.
/// \param tolerance the promised bound, percent of the target's bounding-box diagonal
/// \param source_bound the bound for the source side, percent of the source's diagonal (default 1e-6 %)
template <class Mesh>
Remeshing_verification verify_compatible_remeshing(const Mesh& src, const Mesh& tgt, const Mesh& out_source,
                                                   const Mesh& out_target, double tolerance,
                                                   double source_bound = 1e-6) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  Remeshing_verification r;
  r.compatible = are_compatible(out_source, out_target);
  const double dt = internal::bbox_diagonal(tgt), ds = internal::bbox_diagonal(src);
  const double bound = 0.01 * tolerance / 100 * dt;
  const double h1 = PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(out_target, tgt, bound);
  const double h2 = PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(tgt, out_target, bound);
  r.hausdorff_target = 100 * std::max(h1, h2) / dt;
  r.hausdorff_to_target = 100 * h1 / dt;
  r.hausdorff_from_target = 100 * h2 / dt;
  r.hausdorff_source =
      100 * PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(out_source, src, 1e-3 * source_bound / 100 * ds) / ds;
  // Each output face's normal against the target's at the point nearest its centroid.
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<typename CGAL::Kernel_traits<
      typename boost::property_traits<typename boost::property_map<Mesh, CGAL::vertex_point_t>::const_type>::value_type>::Kernel, Primitive>>;
  Tree tree(faces(tgt).first, faces(tgt).second, tgt);
  tree.accelerate_distance_queries();
  auto target_normal = [&tgt](auto f) {
    auto g = halfedge(f, tgt);
    return internal::triangle_normal(get(CGAL::vertex_point, tgt, source(g, tgt)), get(CGAL::vertex_point, tgt, target(g, tgt)),
                                     get(CGAL::vertex_point, tgt, target(next(g, tgt), tgt)));
  };
  double area = 0, weighted = 0, above = 0;
  for (auto f : faces(out_target)) {
    auto h = halfedge(f, out_target);
    const auto a = get(CGAL::vertex_point, out_target, source(h, out_target));
    const auto b = get(CGAL::vertex_point, out_target, target(h, out_target));
    const auto c = get(CGAL::vertex_point, out_target, target(next(h, out_target), out_target));
    const auto n = internal::triangle_normal(a, b, c), nt = target_normal(tree.closest_point_and_primitive(CGAL::centroid(a, b, c)).second);
    const double ln = std::sqrt(n.squared_length()), lt = std::sqrt(nt.squared_length());
    if (!(ln > 0 && lt > 0)) continue; // a degenerate face has no normal
    const double angle = std::acos(std::max(-1.0, std::min(1.0, (n * nt) / (ln * lt)))) * 180 / CGAL_PI;
    if (angle > verification_angles::flipped) ++r.flipped_faces;
    if (angle > verification_angles::deviation) ++r.faces_above_30, above += ln;
    area += ln, weighted += ln * angle;
  }
  if (area > 0) r.normal_deviation_mean = weighted / area, r.normal_deviation_above_30 = 100 * above / area;
  r.creases_output = internal::count_creases(out_target, verification_angles::crease);
  r.creases_target = internal::count_creases(tgt, verification_angles::crease);
  r.excess_creases = r.creases_output > r.creases_target ? r.creases_output - r.creases_target : 0;
  r.self_intersections_output = internal::count_self_intersections(out_target);
  r.self_intersections_target = internal::count_self_intersections(tgt);
  r.valid = r.compatible && r.hausdorff_target <= tolerance && r.hausdorff_source <= source_bound &&
            r.flipped_faces == 0 && r.self_intersections_output <= r.self_intersections_target;
  if (!r.valid) {
    r.message = std::string(r.compatible ? "" : "outputs are not compatible; ") + "target Hausdorff " +
                std::to_string(r.hausdorff_target) + "% (" + std::to_string(r.hausdorff_to_target) + "% to it, " +
                std::to_string(r.hausdorff_from_target) + "% from it; tolerance " + std::to_string(tolerance) + "%), source " +
                std::to_string(r.hausdorff_source) + "%, " + std::to_string(r.flipped_faces) + " flipped faces, " +
                std::to_string(r.self_intersections_output) + " self-intersecting face pairs (the target has " +
                std::to_string(r.self_intersections_target) + ")";
  }
  return r;
}

} // namespace crossparam

#endif // CROSSPARAM_REMESHING_VERIFICATION_H

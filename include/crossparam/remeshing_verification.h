// SPDX-License-Identifier: GPL-3.0-or-later
// Independent checks of a compatible remeshing (paper §5), trusting nothing the remesher computed: the two
// outputs share one face list; the target-shaped mesh is within the tolerance of the target by a two-sided
// Hausdorff distance (CGAL's bounded-error algorithm, not the remesher's e(v)); the source-shaped mesh lies on
// the source; no target-shaped face is flipped against the target surface nearest it, away from where the
// target folds itself; no face pair of the target-shaped mesh intersects where the target does not intersect
// itself.
#ifndef CROSSPARAM_REMESHING_VERIFICATION_H
#define CROSSPARAM_REMESHING_VERIFICATION_H

#include <crossparam/errors.h>
#include <crossparam/scaling.h>
#include <crossparam/types.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/locate.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <map>
#include <string>
#include <vector>

namespace crossparam {

/// What `verify_compatible_remeshing` found. Distances in percent of the target's bounding-box diagonal
/// (source distances: of the source's diagonal). The definitions are the field's usual ones (doc/algorithms.md,
/// "Remeshing verification"):
/// - a face of the target-shaped output is **flipped** when its normal and the target's normal at the point of
///   the target nearest its centroid make an angle above 90°;
/// - its **normal deviation** is that angle;
/// - a **crease** is an edge whose two faces' normals make an angle above 150° (a dihedral angle below 30°: the
///   faces are folded back onto each other); the output's creases are compared with the input target's;
/// - a **self-intersection** is a pair of faces that intersect other than in their shared vertex or edge, as
///   CGAL's `self_intersections` reports them (a degenerate face counts as a pair with itself).
struct Remeshing_verification {
  /// A place on the meshes, to look at: an element's index (in `vertices()` or `faces()` order), a point (in the
  /// meshes' own coordinates) and, for a distance, its value in percent of the target's bounding-box diagonal.
  struct Spot {
    bool found = false;
    std::size_t index = 0;
    std::array<double, 3> point{{0, 0, 0}};
    double distance = 0;
  };
  bool compatible = false;          ///< same vertex count and the same face list
  double hausdorff_target = 0;      ///< two-sided Hausdorff distance, target-shaped output vs target
  double hausdorff_to_target = 0;   ///< one-sided parts of it: from the output to the target
  double hausdorff_from_target = 0; ///< and from the target to the output
  double hausdorff_source = 0;      ///< one-sided, from the source-shaped output to the source
  std::size_t flipped_faces = 0;    ///< target-shaped faces flipped (normal > 90° from the target's at the
                                    ///< point nearest the centroid)
  std::size_t flipped_at_target_folds = 0; ///< of those, the faces whose centroid's nearest point lies within
                                           ///< the tolerance of a fold of the target itself: a target face on
                                           ///< a crease (above) or in a self-intersecting pair of the target
  double normal_deviation_mean = 0; ///< degrees: angle between each target-shaped face's normal and the target's
                                    ///< at the point nearest its centroid, mean weighted by face area
  std::size_t faces_above_30 = 0;   ///< target-shaped faces where that angle exceeds 30°
  double normal_deviation_above_30 = 0; ///< percent of the target-shaped area where that angle exceeds 30°
  std::size_t creases_output = 0;   ///< edges of the target-shaped output whose faces' normals differ by > 150°
  std::size_t creases_target = 0;   ///< the same count on the input target
  std::size_t self_intersections_output = 0; ///< intersecting face pairs of the target-shaped output
  std::size_t self_intersections_target = 0; ///< intersecting face pairs of the input target
  std::size_t new_self_intersections = 0;    ///< output pairs away from the target's own folds: the pair's
                                             ///< bounding box, grown by the tolerance, meets no face of the
                                             ///< target on a crease or in a self-intersecting pair
  bool valid = false; ///< compatible, both distances within bounds, no flipped face away from the target's own
                      ///< folds, no new self-intersection
  std::string message; ///< empty when valid; otherwise the figures above, and where the failures are (below)

  /// Where to look. The target's vertex farthest from the target-shaped output and the output's vertex farthest
  /// from the target: the vertex samples of the two one-sided distances (the distances above are over the whole
  /// surfaces, so these are at most those); a flipped face away from the target's folds (its centroid) and a
  /// face of a new self-intersecting pair (its centroid), the first of each in `faces()` order. `found` is false
  /// where there is none.
  Spot farthest_target_vertex, farthest_output_vertex, new_flipped_face, new_self_intersection;
  double tolerance = 0; ///< the tolerance checked, in percent of the target's diagonal

  /// The places' points multiplied by 2^exponent (exact), and the message remade with them: for meshes that were
  /// checked at another scale than the user's.
  void scale_places_by_power_of_two(int exponent);

  /// Flipped faces away from the target's own folds: the flips the input does not have.
  std::size_t new_flipped_faces() const { return flipped_faces - flipped_at_target_folds; }
  /// Creases of the output beyond those of the input target (0 if it has fewer).
  std::size_t excess_creases() const { return creases_output > creases_target ? creases_output - creases_target : 0; }
};

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

template <class Mesh>
double bbox_diagonal(const Mesh& m) {
  CGAL::Bbox_3 b = CGAL::Polygon_mesh_processing::bbox(m);
  return std::sqrt(CGAL::square(b.xmax() - b.xmin()) + CGAL::square(b.ymax() - b.ymin()) + CGAL::square(b.zmax() - b.zmin()));
}

/// A crease: an edge whose two faces' normals make an angle above this (a dihedral angle below 30°: the faces
/// are folded back onto each other).
constexpr double crease_degrees = 150.0;

/// Calls `visit(h)` for one halfedge h of every edge of `m` whose two faces' normals make an angle above
/// `degrees` (a crease; border edges and degenerate faces skipped).
template <class Mesh, class Visit>
void for_each_crease(const Mesh& m, double degrees, Visit visit) {
  const double c = std::cos(degrees * CGAL_PI / 180);
  auto normal = [&m](auto h) {
    return triangle_normal(get(CGAL::vertex_point, m, source(h, m)), get(CGAL::vertex_point, m, target(h, m)),
                           get(CGAL::vertex_point, m, target(next(h, m), m)));
  };
  for (auto e : edges(m)) {
    const auto h = halfedge(e, m), o = opposite(h, m);
    if (is_border(h, m) || is_border(o, m)) continue;
    const auto a = normal(h), b = normal(o);
    const double la = std::sqrt(a.squared_length()), lb = std::sqrt(b.squared_length());
    if (la > 0 && lb > 0 && a * b < c * la * lb) visit(h);
  }
}

/// Edges of `m` whose two faces' normals make an angle above `degrees` (degenerate faces skipped).
template <class Mesh>
std::size_t count_creases(const Mesh& m, double degrees) {
  std::size_t n = 0;
  for_each_crease(m, degrees, [&n](auto) { ++n; });
  return n;
}

/// The intersecting face pairs of triangle mesh `m` (CGAL's `self_intersections`).
template <class Mesh>
std::vector<std::pair<typename boost::graph_traits<Mesh>::face_descriptor, typename boost::graph_traits<Mesh>::face_descriptor>>
self_intersecting_pairs(const Mesh& m) {
  std::vector<std::pair<typename boost::graph_traits<Mesh>::face_descriptor, typename boost::graph_traits<Mesh>::face_descriptor>> out;
  CGAL::Polygon_mesh_processing::self_intersections(faces(m), m, std::back_inserter(out));
  return out;
}

/// Bounding box of face f of m.
template <class Mesh>
CGAL::Bbox_3 face_bbox(const Mesh& m, typename boost::graph_traits<Mesh>::face_descriptor f) {
  CGAL::Bbox_3 b;
  for (auto v : CGAL::vertices_around_face(halfedge(f, m), m)) b += get(CGAL::vertex_point, m, v).bbox();
  return b;
}

/// Bounding boxes of the faces of m on its folds: the two faces of every crease (crease_degrees), and the faces of every self-intersecting pair `pairs` of m.
template <class Mesh, class Pairs>
std::vector<CGAL::Bbox_3> fold_face_boxes(const Mesh& m, const Pairs& pairs) {
  std::vector<CGAL::Bbox_3> out;
  for_each_crease(m, crease_degrees, [&](auto h) {
    out.push_back(face_bbox(m, face(h, m)));
    out.push_back(face_bbox(m, face(opposite(h, m), m)));
  });
  for (const auto& p : pairs) out.push_back(face_bbox(m, p.first)), out.push_back(face_bbox(m, p.second));
  return out;
}

/// Whether box b, grown by g on every side, meets one of `boxes`.
inline bool meets_grown(CGAL::Bbox_3 b, double g, const std::vector<CGAL::Bbox_3>& boxes) {
  b = CGAL::Bbox_3(b.xmin() - g, b.ymin() - g, b.zmin() - g, b.xmax() + g, b.ymax() + g, b.zmax() + g);
  for (const CGAL::Bbox_3& q : boxes)
    if (CGAL::do_overlap(b, q)) return true;
  return false;
}

/// A Remeshing_verification::Spot at element `index`, point `p`, distance `d`.
template <class Point>
Remeshing_verification::Spot spot(std::size_t index, const Point& p, double d) {
  Remeshing_verification::Spot s;
  s.found = true;
  s.index = index;
  s.point = {{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}};
  s.distance = d;
  return s;
}

/// The message of a verification: empty when valid; otherwise its figures, then where the tolerance is missed
/// (the farthest vertices, when beyond it), a new flipped face and a new self-intersection are.
inline std::string verification_message(const Remeshing_verification& r) {
  if (r.valid) return {};
  const double tolerance = r.tolerance;
  std::string m = std::string(r.compatible ? "" : "outputs are not compatible; ") + "target Hausdorff " +
                  std::to_string(r.hausdorff_target) + "% (" + std::to_string(r.hausdorff_to_target) + "% to it, " +
                  std::to_string(r.hausdorff_from_target) + "% from it; tolerance " + std::to_string(tolerance) +
                  "%), source " + std::to_string(r.hausdorff_source) + "%, " + std::to_string(r.new_flipped_faces()) +
                  " flipped faces away from the target's own folds (" + std::to_string(r.flipped_faces) + " in all), " +
                  std::to_string(r.new_self_intersections) + " new self-intersecting face pairs";
  auto at = [](const Remeshing_verification::Spot& s) {
    char b[96];
    std::snprintf(b, sizeof b, " at (%.6g, %.6g, %.6g)", s.point[0], s.point[1], s.point[2]);
    return std::string(b);
  };
  if (r.farthest_target_vertex.found && r.farthest_target_vertex.distance > tolerance)
    m += "; target vertex " + std::to_string(r.farthest_target_vertex.index) + at(r.farthest_target_vertex) + " is " +
         std::to_string(r.farthest_target_vertex.distance) + "% from the output";
  if (r.farthest_output_vertex.found && r.farthest_output_vertex.distance > tolerance)
    m += "; output vertex " + std::to_string(r.farthest_output_vertex.index) + at(r.farthest_output_vertex) + " is " +
         std::to_string(r.farthest_output_vertex.distance) + "% from the target";
  if (r.new_flipped_face.found)
    m += "; flipped face " + std::to_string(r.new_flipped_face.index) + at(r.new_flipped_face);
  if (r.new_self_intersection.found)
    m += "; new self-intersection at face " + std::to_string(r.new_self_intersection.index) + at(r.new_self_intersection);
  return m;
}

} // namespace internal

inline void Remeshing_verification::scale_places_by_power_of_two(int exponent) {
  for (Spot* spot : {&farthest_target_vertex, &farthest_output_vertex, &new_flipped_face, &new_self_intersection})
    for (double& x : spot->point) x = std::ldexp(x, exponent);
  message = internal::verification_message(*this);
}

/// Whether two meshes have the same number of vertices and the same faces (as vertex index triples, in order).
template <class MeshA, class MeshB>
bool are_compatible(const MeshA& a, const MeshB& b) {
  return num_vertices(a) == num_vertices(b) && internal::face_list(a) == internal::face_list(b);
}

/// \brief The faces of a remeshing of the source that do not tile the input face they lie in: given by their
/// corners in barycentric coordinates of that input face (`Compatible_remesher::source_face_locations()`,
/// `Multi_remesher::source_face_locations()`), a face counts when its corners there are collinear (no area on
/// the source) or turn the other way than the faces tiling that input face do. The orientation of a face is an
/// exact test on the coordinates as stored (the sign of the determinant of its three barycentric vectors, which
/// needs no coordinate sum to be 1); the tiling's is the sign of the sum of the signed areas of the input face's
/// faces (plus or minus the input face's own area in these coordinates, whatever the input face's shape in space:
/// its corners are listed in the input's order, which may turn either way). Such a face folds the source-shaped
/// output over the source, or makes two of its vertices one point of the source, so that the source-shaped and
/// the target-shaped outputs are no longer one to one; a valid remeshing has none.
inline std::size_t source_tiling_defects(const std::vector<Input_face_location>& locations) {
  using P = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
  auto orientation = [](const Input_face_location& l) {
    const auto& c = l.corners;
    return CGAL::orientation(P(CGAL::ORIGIN), P(c[0][0], c[0][1], c[0][2]), P(c[1][0], c[1][1], c[1][2]),
                             P(c[2][0], c[2][1], c[2][2]));
  };
  std::map<std::size_t, double> area; // per input face: the sum of its faces' signed areas
  for (const Input_face_location& l : locations) {
    const auto& c = l.corners;
    area[l.face] += (c[1][1] - c[0][1]) * (c[2][2] - c[0][2]) - (c[2][1] - c[0][1]) * (c[1][2] - c[0][2]);
  }
  std::size_t n = 0;
  for (const Input_face_location& l : locations) {
    const CGAL::Orientation o = orientation(l);
    n += o == CGAL::COLLINEAR || (o == CGAL::POSITIVE) != (area[l.face] > 0);
  }
  return n;
}

/// \brief Checks the two outputs of a compatible remeshing against the inputs. `tolerance` is the promised
/// bound in percent of the target's diagonal; `source_bound` the bound for the source side (default 1e-6 %).
/// The Hausdorff distances are computed with CGAL's bounded-error algorithm to 1% of the tolerance.
/// Scale-free: the meshes are checked as copies scaled by the power of two that brings the largest bounding-box
/// diagonal into [1, 2) (exact), and every distance is reported in percent of a diagonal.
///
/// Kernel: that of `Mesh`'s points (`CGAL::Kernel_traits` of its `vertex_point` value type), used by the AABB
/// tree, the Hausdorff distances and the normals; no `geom_traits` named parameter is taken.
template <class Mesh>
Remeshing_verification verify_compatible_remeshing(const Mesh& src, const Mesh& tgt, const Mesh& out_source,
                                                   const Mesh& out_target, double tolerance,
                                                   double source_bound = 1e-6) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  if (const int k = unit_scale_exponent<Mesh>({&src, &tgt, &out_source, &out_target}); k != 0) {
    Mesh s = src, t = tgt, os = out_source, ot = out_target;
    for (Mesh* m : {&s, &t, &os, &ot}) scale_by_power_of_two(*m, k);
    Remeshing_verification r = verify_compatible_remeshing(s, t, os, ot, tolerance, source_bound);
    r.scale_places_by_power_of_two(-k); // the places in the meshes' own coordinates
    return r;
  }
  Remeshing_verification r;
  r.tolerance = tolerance;
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
  // Flips: the normal of each output face against the target's normal at the point nearest its centroid.
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
  // The target's own folds, its faces on creases or in self-intersecting pairs: there the target's two sides
  // come closer than any tolerance, its normal is no reference, and an output within the tolerance of the
  // target may be flipped against it, or intersect itself, where it folds.
  const auto pairs_in = internal::self_intersecting_pairs(tgt);
  const std::vector<CGAL::Bbox_3> target_folds = internal::fold_face_boxes(tgt, pairs_in);
  const double grow = tolerance / 100 * dt;
  double area = 0, weighted = 0, above = 0;
  std::size_t face_counter = 0;
  for (auto f : faces(out_target)) {
    const std::size_t fi = face_counter++;
    auto h = halfedge(f, out_target);
    const auto a = get(CGAL::vertex_point, out_target, source(h, out_target));
    const auto b = get(CGAL::vertex_point, out_target, target(h, out_target));
    const auto c = get(CGAL::vertex_point, out_target, target(next(h, out_target), out_target));
    // The target's normal at the point of the target nearest the centroid; a degenerate output face (no
    // normal) is counted by the self-intersection test.
    const auto nearest = tree.closest_point_and_primitive(CGAL::centroid(a, b, c));
    const auto n = internal::triangle_normal(a, b, c), nt = target_normal(nearest.second);
    const double ln = std::sqrt(n.squared_length()), lt = std::sqrt(nt.squared_length());
    if (!(ln > 0 && lt > 0)) continue;
    const double angle = std::acos(std::max(-1.0, std::min(1.0, (n * nt) / (ln * lt)))) * 180 / CGAL_PI;
    if (n * nt < 0) {
      ++r.flipped_faces;
      const bool at_fold = internal::meets_grown(nearest.first.bbox(), grow, target_folds);
      r.flipped_at_target_folds += at_fold;
      if (!at_fold && !r.new_flipped_face.found)
        r.new_flipped_face = internal::spot(fi, CGAL::centroid(a, b, c), 0);
    }
    r.faces_above_30 += angle > 30;
    area += ln, weighted += ln * angle, above += angle > 30 ? ln : 0;
  }
  if (area > 0) r.normal_deviation_mean = weighted / area, r.normal_deviation_above_30 = 100 * above / area;
  r.creases_output = internal::count_creases(out_target, internal::crease_degrees);
  r.creases_target = internal::count_creases(tgt, internal::crease_degrees);
  // Self-intersections: the output's, less those near the target's own folds (a target that intersects itself,
  // or folds onto itself at a crease so that its two sides are closer than the tolerance, is approximated
  // within the tolerance by an output that may intersect itself there).
  const auto pairs_out = internal::self_intersecting_pairs(out_target);
  r.self_intersections_output = pairs_out.size();
  r.self_intersections_target = pairs_in.size();
  for (const auto& p : pairs_out) {
    const bool is_new = !internal::meets_grown(
        internal::face_bbox(out_target, p.first) + internal::face_bbox(out_target, p.second), grow, target_folds);
    r.new_self_intersections += is_new;
    if (is_new && !r.new_self_intersection.found) {
      const auto g = halfedge(p.first, out_target);
      r.new_self_intersection = internal::spot(
          std::size_t(std::distance(faces(out_target).first, std::find(faces(out_target).first, faces(out_target).second, p.first))),
          CGAL::centroid(get(CGAL::vertex_point, out_target, source(g, out_target)),
                         get(CGAL::vertex_point, out_target, target(g, out_target)),
                         get(CGAL::vertex_point, out_target, target(next(g, out_target), out_target))),
          0);
    }
  }
  // The vertex samples of the two one-sided distances: where the output is farthest from the target and the
  // target from the output.
  {
    Tree out_tree(faces(out_target).first, faces(out_target).second, out_target);
    out_tree.accelerate_distance_queries();
    auto farthest = [dt](const Mesh& from, const Tree& to) {
      Remeshing_verification::Spot s;
      std::size_t i = 0;
      for (auto v : vertices(from)) {
        const auto p = get(CGAL::vertex_point, from, v);
        const double d = 100 * std::sqrt(CGAL::to_double(to.squared_distance(p))) / dt;
        if (!s.found || d > s.distance) s = internal::spot(i, p, d);
        ++i;
      }
      return s;
    };
    r.farthest_target_vertex = farthest(tgt, out_tree);
    r.farthest_output_vertex = farthest(out_target, tree);
  }
  r.valid = r.compatible && r.hausdorff_target <= tolerance && r.hausdorff_source <= source_bound &&
            r.new_flipped_faces() == 0 && r.new_self_intersections == 0;
  r.message = internal::verification_message(r);
  return r;
}

} // namespace crossparam

#endif // CROSSPARAM_REMESHING_VERIFICATION_H

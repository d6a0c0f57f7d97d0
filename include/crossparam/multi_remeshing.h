// SPDX-License-Identifier: GPL-3.0-or-later
// One common connectivity for N meshes (Kraevoy & Sheffer 2004, §2.3): N >= 2 closed meshes of one genus, a
// correspondence with one column per mesh; one mesh is the source. The source is mapped onto every other mesh
// (a Cross_parameterization each); the common mesh starts as the compatible remeshing of the source and the
// first other mesh (§5), whose outputs it keeps, then takes every further mesh in turn: each vertex goes to that
// mesh through its map, and the common mesh is refined where it does not yet approximate it.
//
// Every refinement is an edge split at the midpoint of a common edge, measured on the source: every common face
// lies inside one input source face, so the midpoint lies on the source exactly (up to rounding) and the source
// is still reproduced. On the mesh being fitted the new vertex goes through that mesh's map; on every other mesh
// already placed, where that mesh's compatible surface has the edge's midpoint, moved to the nearest point of the
// mesh. So all N outputs always share one face list, and the placed meshes only get closer to their inputs.
//
// The fit to a mesh splits, in rounds, the common edges whose midpoint is farther from the mesh than the
// tolerance, the longest edge of each face whose centroid is, and that of the face nearest each vertex of the
// mesh farther from the common mesh than the tolerance. Faces flipped against the mesh (the rule of the
// remeshing verification) are untangled along the mesh, as the last step of the remeshing does: their corners
// move to the point of the mesh nearest the centroid of their neighbours, while that lowers the flips around
// them. A final pass refits every mesh, since a split for one mesh adds vertices to all.
//
// The driver, Multi_remesher, keeps the common mesh as a face list with, per face, the input source face it lies
// in and its corners' barycentric coordinates there (Input_face_location); a split updates both exactly.
#ifndef CROSSPARAM_MULTI_REMESHING_H
#define CROSSPARAM_MULTI_REMESHING_H

#include <crossparam/compatible_remeshing.h>
#include <crossparam/cross_parameterization.h>
#include <crossparam/errors.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace crossparam {

/// Features of N meshes: row k is feature k, its entry m the vertex (0-based, input order) of mesh m.
using Multi_feature_correspondence = std::vector<std::vector<std::size_t>>;

/// Value of the named parameter `source_mesh` that picks the mesh with the most vertices as the source.
constexpr std::size_t finest_mesh = std::size_t(-1);

/// Figures of one N-way remeshing. Errors in percent of each mesh's bounding-box diagonal.
struct Multi_remeshing_statistics {
  std::size_t source = 0;                   ///< index of the source mesh
  std::vector<std::size_t> input_vertices;  ///< per mesh
  std::size_t output_vertices = 0, output_faces = 0;
  std::size_t two_way_vertices = 0;         ///< after the compatible remeshing with the first other mesh
  std::vector<std::size_t> splits;          ///< per mesh: common edges split to fit it (0 for the source)
  std::vector<double> max_chord_error;      ///< per mesh, at the end: the largest edge-midpoint or centroid chord
  std::vector<std::size_t> flipped_faces;   ///< per mesh, at the end, by the verification's rule
  std::vector<std::size_t> untangle_moves;  ///< per mesh: vertex moves along it that removed folds
  std::vector<double> seconds_map;          ///< per mesh: its cross-parameterization (0 for the source)
  std::vector<double> seconds_fit;          ///< per mesh: the remeshing (first other mesh) or the fit
  double seconds_total = 0;
  bool converged = false;                   ///< every chord within the tolerance and no flipped face
};

namespace internal {

/// The image under a map of points of the source given against the source as the user gave it.
class Source_point_mapper {
public:
  using CP = Cross_parameterization<Surface_mesh, Surface_mesh>;
  explicit Source_point_mapper(const CP& cp) : cp_(cp) {
    const Refined_mesh& m = cp.working_mesh(Mesh_side::source);
    by_input_face_.resize(cp.input_faces(Mesh_side::source));
    for (Refined_face f : m.faces()) {
      Piece p;
      p.face = f;
      for (int i = 0; i < 3; ++i) {
        Refined_location l;
        l.face = f;
        l.b[std::size_t(i)] = 1;
        const Input_location il = cp.to_input(Mesh_side::source, l);
        p.corners[std::size_t(i)] = il.b;
        p.input_face = il.face;
      }
      by_input_face_[p.input_face].push_back(p);
    }
  }

  /// The point of the source at `l` as a point of the map's refined source.
  Refined_location refined(const Input_location& l) const {
    Refined_location best;
    double best_min = -HUGE_VAL;
    for (const Piece& p : by_input_face_.at(l.face)) {
      const std::array<double, 3> c = solve(p.corners, l.b);
      const double mn = std::min({c[0], c[1], c[2]});
      if (mn > best_min) best_min = mn, best.face = p.face, best.b = c;
    }
    if (best_min == -HUGE_VAL) throw Algorithm_error("internal error: a source point in no refined face");
    double sum = 0;
    for (double& x : best.b) sum += (x = std::max(0.0, x));
    for (double& x : best.b) x /= sum;
    return best;
  }

  /// F of the source point `l`, against the target as given.
  Input_location to_target(const Input_location& l) const {
    return cp_.to_input(Mesh_side::target, cp_.image(Mesh_side::source, refined(l)));
  }

  const CP& map() const { return cp_; }

  /// Coordinates of `b` in the frame of the three points `corners` (all barycentric coordinates of one
  /// triangle): the affine solve on the first two coordinates.
  static std::array<double, 3> solve(const std::array<std::array<double, 3>, 3>& corners, const std::array<double, 3>& b) {
    const double a00 = corners[0][0] - corners[2][0], a01 = corners[1][0] - corners[2][0];
    const double a10 = corners[0][1] - corners[2][1], a11 = corners[1][1] - corners[2][1];
    const double r0 = b[0] - corners[2][0], r1 = b[1] - corners[2][1];
    const double det = a00 * a11 - a01 * a10;
    if (det == 0) return {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    const double c0 = (r0 * a11 - a01 * r1) / det, c1 = (a00 * r1 - r0 * a10) / det;
    return {c0, c1, 1 - c0 - c1};
  }

private:
  struct Piece {
    Refined_face face;
    std::size_t input_face = 0;
    std::array<std::array<double, 3>, 3> corners{};
  };
  const CP& cp_;
  std::vector<std::vector<Piece>> by_input_face_;
};

} // namespace internal

/// \brief Brings N closed meshes to one connectivity (paper §2.3): N outputs with one face list, the source
/// reproduced exactly, every other output within the tolerance of its input.
///
/// \tparam TriangleMesh a model of `FaceListGraph` with a `vertex_point` map (read in `vertices()` order)
///
/// Named parameters: `crossparam::parameters::source_mesh` (index of the source, default 0; `finest_mesh`
/// picks the mesh with the most vertices); `crossparam::parameters::tolerance` (percent of each mesh's
/// bounding-box diagonal, default 0.5); `crossparam::parameters::max_rounds` (refinement rounds per fit, default
/// 30); `crossparam::parameters::progress`; `crossparam::parameters::number_of_threads`; and those of
/// `Cross_parameterization` and `Compatible_remesher`, passed on to every map and to the first remeshing.
template <class TriangleMesh>
class Multi_remesher {
public:
  /// \param meshes the N >= 2 input meshes, closed, of one genus
  /// \param features one row per feature, one vertex per mesh in each row
  /// \param np the named parameters (see above)
  /// \throws Input_error for fewer than two meshes, a row of features with another number of entries than
  ///         meshes, a source index out of range, a bad tolerance; and what the maps and the remeshing throw
  template <typename NP = CGAL::parameters::Default_named_parameters>
  Multi_remesher(const std::vector<TriangleMesh>& meshes, const Multi_feature_correspondence& features,
                 const NP& np = CGAL::parameters::default_values()) {
    using CGAL::parameters::choose_parameter;
    using CGAL::parameters::get_parameter;
    const auto t0 = clock::now();
    const std::size_t n = meshes.size();
    if (n < 2) throw Input_error("N-way remeshing: at least two meshes are needed");
    for (std::size_t k = 0; k < features.size(); ++k)
      if (features[k].size() != n)
        throw Input_error("N-way remeshing: feature " + std::to_string(k) + " has " + std::to_string(features[k].size()) +
                          " vertices for " + std::to_string(n) + " meshes");
    tolerance_ = choose_parameter(get_parameter(np, internal_np::tolerance_t()), 0.5);
    if (!(tolerance_ > 0) || !std::isfinite(tolerance_))
      throw Input_error("remeshing tolerance must be a positive number of percent");
    max_rounds_ = choose_parameter(get_parameter(np, internal_np::max_rounds_t()), 30u);
    progress_ = choose_parameter(get_parameter(np, internal_np::progress_t()), std::function<void(const std::string&)>());
    inputs_.resize(n);
    stats_.input_vertices.resize(n);
    for (std::size_t m = 0; m < n; ++m) {
      internal::copy_in_order(meshes[m], get_const_property_map(CGAL::vertex_point, meshes[m]), inputs_[m]);
      stats_.input_vertices[m] = inputs_[m].number_of_vertices();
    }
    std::size_t s = choose_parameter(get_parameter(np, internal_np::source_mesh_t()), std::size_t(0));
    if (s == finest_mesh)
      s = std::size_t(std::max_element(stats_.input_vertices.begin(), stats_.input_vertices.end()) - stats_.input_vertices.begin());
    if (s >= n) throw Input_error("N-way remeshing: source mesh " + std::to_string(s) + " of " + std::to_string(n));
    stats_.source = s;
    stats_.splits.assign(n, 0);
    stats_.max_chord_error.assign(n, 0);
    stats_.flipped_faces.assign(n, 0);
    stats_.seconds_map.assign(n, 0);
    stats_.seconds_fit.assign(n, 0);
    stats_.untangle_moves.assign(n, 0);
    points_.resize(n);
    order_.clear();
    for (std::size_t m = 0; m < n; ++m)
      if (m != s) order_.push_back(m);

    // The maps, source -> each other mesh, on copies (a map refines its meshes).
    maps_.resize(n);
    for (std::size_t m : order_) {
      const auto tm = clock::now();
      Feature_correspondence pairs;
      for (const auto& row : features) pairs.push_back({row[s], row[m]});
      auto& slot = maps_[m];
      slot.source = std::make_unique<Surface_mesh>(inputs_[s]);
      slot.target = std::make_unique<Surface_mesh>(inputs_[m]);
      slot.cp = std::make_unique<CP>(*slot.source, *slot.target, pairs, np);
      slot.mapper = std::make_unique<internal::Source_point_mapper>(*slot.cp);
      stats_.seconds_map[m] = sec(tm, clock::now());
      say("n-way: map of mesh " + std::to_string(s) + " onto mesh " + std::to_string(m) + " (" +
          fmt(stats_.seconds_map[m]) + " s)");
    }

    // The common mesh: the compatible remeshing with the first other mesh.
    const std::size_t first = order_[0];
    {
      const auto tf = clock::now();
      const Compatible_remesher<Surface_mesh, Surface_mesh> r(*maps_[first].cp, np);
      faces_ = r.faces();
      floc_ = r.source_face_locations();
      points_[s] = r.source_points();
      points_[first] = r.target_points();
      vloc_.assign(points_[s].size(), Input_location());
      std::vector<char> seen(points_[s].size(), 0);
      for (std::size_t g = 0; g < faces_.size(); ++g)
        for (int c = 0; c < 3; ++c) {
          const std::size_t v = faces_[g][std::size_t(c)];
          if (seen[v]) continue;
          seen[v] = 1;
          vloc_[v] = {floc_[g].face, floc_[g].corners[std::size_t(c)]};
        }
      stats_.two_way_vertices = points_[s].size();
      stats_.seconds_fit[first] = sec(tf, clock::now());
      say("n-way: compatible remeshing with mesh " + std::to_string(first) + ": " + std::to_string(points_[s].size()) +
          " vertices");
    }
    fitted_.assign(n, 0);
    fitted_[s] = fitted_[first] = 1;
    for (std::size_t m : order_) prepare_mesh(m);
    // Each further mesh: its points through its map, then refinement where it is not yet approximated.
    for (std::size_t i = 1; i < order_.size(); ++i) {
      const std::size_t m = order_[i];
      const auto tf = clock::now();
      points_[m].resize(vloc_.size());
      for (std::size_t v = 0; v < vloc_.size(); ++v) points_[m][v] = map_point(m, vloc_[v]);
      fitted_[m] = 1;
      fit(m);
      stats_.seconds_fit[m] += sec(tf, clock::now());
    }
    // A final pass: the splits made for later meshes added vertices to the earlier ones.
    for (std::size_t m : order_) {
      const auto tf = clock::now();
      fit(m);
      stats_.seconds_fit[m] += sec(tf, clock::now());
    }
    stats_.converged = true;
    for (std::size_t m : order_) {
      const Measure e = measure(m, nullptr);
      stats_.max_chord_error[m] = 100 * e.max_chord / diagonal_[m];
      stats_.flipped_faces[m] = e.flipped;
      stats_.converged = stats_.converged && e.max_chord <= eps(m) && e.flipped == 0 && e.uncovered == 0;
    }
    stats_.output_vertices = vloc_.size();
    stats_.output_faces = faces_.size();
    stats_.seconds_total = sec(t0, clock::now());
  }

  /// The common face list (indices into every point list), oriented as the source.
  const std::vector<std::array<std::size_t, 3>>& faces() const { return faces_; }
  /// The points of output `mesh` (input order of the meshes): on that mesh; for the source, its vertices first,
  /// exactly, then points on its faces.
  const std::vector<std::array<double, 3>>& points(std::size_t mesh) const { return points_.at(mesh); }
  /// Per common face, the input source face holding it and its corners there.
  const std::vector<Input_face_location>& source_face_locations() const { return floc_; }
  /// The number of meshes.
  std::size_t number_of_meshes() const { return points_.size(); }
  /// The map of the source onto mesh `mesh` (not the source): for transfers and landmark queries.
  const Cross_parameterization<Surface_mesh, Surface_mesh>& map(std::size_t mesh) const {
    if (!maps_.at(mesh).cp) throw Input_error("N-way remeshing: the source has no map onto itself");
    return *maps_[mesh].cp;
  }
  const Multi_remeshing_statistics& statistics() const { return stats_; }

  /// Copies output `mesh` into `out`, any MutableFaceGraph.
  template <class OutputMesh>
  void copy_to(std::size_t mesh, OutputMesh& out) const {
    using P3 = typename boost::property_traits<
        typename boost::property_map<OutputMesh, CGAL::vertex_point_t>::type>::value_type;
    std::vector<P3> pts;
    for (const auto& p : points(mesh)) pts.emplace_back(p[0], p[1], p[2]);
    std::vector<std::vector<std::size_t>> polys;
    for (const auto& f : faces_) polys.push_back({f[0], f[1], f[2]});
    clear(out);
    CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(pts, polys, out);
  }

private:
  using clock = std::chrono::steady_clock;
  using CP = Cross_parameterization<Surface_mesh, Surface_mesh>;
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<Surface_mesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  /// Share of the tolerance the fit aims at: the chords it measures are samples (edge midpoints, centroids,
  /// the mesh's vertices), the verification's Hausdorff distance is the supremum over the surfaces.
  static constexpr double tolerance_margin = 0.8;
  /// The fit stops adding vertices beyond this many times the largest input's vertex count.
  static constexpr std::size_t max_growth = 8;
  /// The fit of one mesh stops after this many rounds in a row that lower none of the largest chord, the
  /// number of uncovered vertices and the number of flipped faces.
  static constexpr unsigned max_stale_rounds = 3;
  /// Passes of the untangling over the regions around flipped faces, at most.
  static constexpr unsigned untangle_passes = 40;
  /// The untangling stops after this many passes in a row that do not lower the number of flipped faces.
  static constexpr unsigned untangle_patience = 4;

  struct Map_slot {
    std::unique_ptr<Surface_mesh> source, target;
    std::unique_ptr<CP> cp;
    std::unique_ptr<internal::Source_point_mapper> mapper;
  };
  struct Measure {
    double max_chord = 0;
    std::size_t flipped = 0, uncovered = 0;
  };

  double eps(std::size_t m) const { return tolerance_margin * tolerance_ / 100 * diagonal_[m]; }

  void prepare_mesh(std::size_t m) {
    if (trees_.size() < inputs_.size()) trees_.resize(inputs_.size()), diagonal_.resize(inputs_.size(), 1);
    const CGAL::Bbox_3 b = CGAL::Polygon_mesh_processing::bbox(inputs_[m]);
    diagonal_[m] = std::sqrt(CGAL::square(b.xmax() - b.xmin()) + CGAL::square(b.ymax() - b.ymin()) + CGAL::square(b.zmax() - b.zmin()));
    trees_[m] = std::make_unique<Tree>(inputs_[m].faces().begin(), inputs_[m].faces().end(), inputs_[m]);
    trees_[m]->accelerate_distance_queries();
  }

  /// The point of mesh m that its map gives to the source point `l` (for the source, `l` itself).
  std::array<double, 3> map_point(std::size_t m, const Input_location& l) const {
    if (m == stats_.source) return source_point(l);
    const CP& cp = *maps_[m].cp;
    return cp.input_point(Mesh_side::target, maps_[m].mapper->to_target(l));
  }
  std::array<double, 3> source_point(const Input_location& l) const {
    std::array<double, 3> p{{0, 0, 0}};
    const Surface_mesh& src = inputs_[stats_.source];
    const auto& fv = maps_[order_[0]].cp->input_face_vertices(Mesh_side::source, l.face);
    for (int i = 0; i < 3; ++i) {
      if (l.b[std::size_t(i)] == 0) continue; // exact on an edge or at a vertex
      const Point_3& q = src.point(Surface_mesh::Vertex_index(Surface_mesh::size_type(fv[std::size_t(i)])));
      for (int k = 0; k < 3; ++k) p[std::size_t(k)] += l.b[std::size_t(i)] * q[k];
    }
    return p;
  }

  static std::uint64_t key(std::size_t a, std::size_t b) { return (std::uint64_t(a) << 32) | std::uint64_t(b); }
  static double dist(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::sqrt(CGAL::square(a[0] - b[0]) + CGAL::square(a[1] - b[1]) + CGAL::square(a[2] - b[2]));
  }
  static Point_3 pt(const std::array<double, 3>& a) { return Point_3(a[0], a[1], a[2]); }

  /// The longest edge of face g on mesh m, as (corner, next corner).
  std::pair<std::size_t, std::size_t> longest_edge(std::size_t m, std::size_t g) const {
    int best = 0;
    double len = -1;
    for (int c = 0; c < 3; ++c) {
      const double l = dist(points_[m][faces_[g][std::size_t(c)]], points_[m][faces_[g][std::size_t((c + 1) % 3)]]);
      if (l > len) len = l, best = c;
    }
    return {faces_[g][std::size_t(best)], faces_[g][std::size_t((best + 1) % 3)]};
  }

  /// The point of mesh m nearest `p`.
  std::array<double, 3> project(std::size_t m, const std::array<double, 3>& p) const {
    const Point_3 q = trees_[m]->closest_point(pt(p));
    return {q.x(), q.y(), q.z()};
  }
  double distance_to_mesh(std::size_t m, const std::array<double, 3>& p) const {
    return std::sqrt(trees_[m]->squared_distance(pt(p)));
  }
  bool flipped(std::size_t m, std::size_t g) const {
    const Surface_mesh& t = inputs_[m];
    auto normal = [&t](Surface_mesh::Face_index f) {
      auto h = t.halfedge(f);
      return internal::triangle_normal(t.point(t.source(h)), t.point(t.target(h)), t.point(t.target(t.next(h))));
    };
    const auto& P = points_[m];
    const auto& f = faces_[g];
    return internal::flipped_against_nearest(*trees_[m], normal, pt(P[f[0]]), pt(P[f[1]]), pt(P[f[2]]));
  }

  /// The chords, uncovered vertices and flips of mesh m; with `marked`, the edges to split (as (a, b) with
  /// a < b): those whose midpoint is farther from the mesh than the tolerance, the longest edge of each face
  /// whose centroid is, and the longest edge of the face nearest each vertex of the mesh farther from the common
  /// mesh than the tolerance.
  Measure measure(std::size_t m, std::vector<std::pair<std::size_t, std::size_t>>* marked) const {
    Measure r;
    const double e = eps(m);
    std::unordered_map<std::uint64_t, char> mark;
    auto add = [&](std::size_t a, std::size_t b) {
      if (a > b) std::swap(a, b);
      if (marked && mark.emplace(key(a, b), 1).second) marked->push_back({a, b});
    };
    const auto& P = points_[m];
    std::vector<Kernel::Triangle_3> triangles;
    triangles.reserve(faces_.size());
    for (std::size_t g = 0; g < faces_.size(); ++g) {
      const auto& f = faces_[g];
      triangles.emplace_back(pt(P[f[0]]), pt(P[f[1]]), pt(P[f[2]]));
      for (int c = 0; c < 3; ++c) {
        const std::size_t a = f[std::size_t(c)], b = f[std::size_t((c + 1) % 3)];
        if (a > b) continue;
        const double d = distance_to_mesh(m, {0.5 * (P[a][0] + P[b][0]), 0.5 * (P[a][1] + P[b][1]), 0.5 * (P[a][2] + P[b][2])});
        r.max_chord = std::max(r.max_chord, d);
        if (d > e) add(a, b);
      }
      std::array<double, 3> cen{0, 0, 0};
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) cen[std::size_t(k)] += P[f[std::size_t(c)]][std::size_t(k)] / 3;
      const double d = distance_to_mesh(m, cen);
      r.max_chord = std::max(r.max_chord, d);
      if (d > e) {
        const auto le = longest_edge(m, g);
        add(le.first, le.second);
      }
      if (flipped(m, g)) ++r.flipped;
    }
    // The mesh's vertices: each within the tolerance of the common mesh.
    using Primitive_t = CGAL::AABB_triangle_primitive<Kernel, std::vector<Kernel::Triangle_3>::const_iterator>;
    using Tree_t = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive_t>>;
    Tree_t common(triangles.cbegin(), triangles.cend());
    common.accelerate_distance_queries();
    for (auto v : inputs_[m].vertices()) {
      const Point_3& x = inputs_[m].point(v);
      const auto near = common.closest_point_and_primitive(x);
      if (std::sqrt(CGAL::squared_distance(near.first, x)) > e) {
        ++r.uncovered;
        const auto le = longest_edge(m, std::size_t(near.second - triangles.cbegin()));
        add(le.first, le.second);
      }
    }
    return r;
  }

  /// Removes folds of output m by tangential smoothing along mesh m around its flipped faces: each corner of a
  /// flipped face and each neighbour of one moves, in turn, to the point of mesh m nearest the centroid of its
  /// neighbours, a move kept unless it leaves more flipped faces around the vertex. The source's points, and so
  /// the face list, are untouched. Returns the moves kept.
  std::size_t untangle(std::size_t m) {
    std::vector<std::vector<std::size_t>> star(vloc_.size()), ring(vloc_.size());
    for (std::size_t g = 0; g < faces_.size(); ++g)
      for (int c = 0; c < 3; ++c) {
        star[faces_[g][std::size_t(c)]].push_back(g);
        ring[faces_[g][std::size_t(c)]].push_back(faces_[g][std::size_t((c + 1) % 3)]);
      }
    auto flips_around = [&](std::size_t v) {
      std::size_t n = 0;
      for (std::size_t g : star[v]) n += flipped(m, g);
      return n;
    };
    std::size_t moves = 0, best = std::size_t(-1);
    unsigned stale = 0;
    auto& P = points_[m];
    for (unsigned pass = 0; pass < untangle_passes; ++pass) {
      std::vector<std::size_t> region;
      std::size_t count = 0;
      for (std::size_t g = 0; g < faces_.size(); ++g)
        if (flipped(m, g)) {
          ++count;
          for (std::size_t v : faces_[g]) {
            region.push_back(v);
            region.insert(region.end(), ring[v].begin(), ring[v].end());
          }
        }
      if (count == 0) break;
      if (count < best) best = count, stale = 0;
      else if (++stale == untangle_patience) break;
      std::sort(region.begin(), region.end());
      region.erase(std::unique(region.begin(), region.end()), region.end());
      for (std::size_t v : region) {
        const std::size_t before = flips_around(v);
        std::array<double, 3> c{0, 0, 0};
        for (std::size_t u : ring[v])
          for (int k = 0; k < 3; ++k) c[std::size_t(k)] += P[u][std::size_t(k)] / double(ring[v].size());
        const std::array<double, 3> old = P[v];
        P[v] = project(m, c);
        if (flips_around(v) > before) P[v] = old;
        else ++moves;
      }
    }
    return moves;
  }

  /// Refines the common mesh until mesh m is approximated, or the rounds or the growth bound are spent; folds
  /// are untangled after every round.
  void fit(std::size_t m) {
    std::size_t largest = 0;
    for (std::size_t x : stats_.input_vertices) largest = std::max(largest, x);
    Measure best;
    best.max_chord = HUGE_VAL;
    best.flipped = best.uncovered = std::size_t(-1);
    unsigned stale = 0;
    fitting_ = m;
    stats_.untangle_moves[m] += untangle(m);
    for (unsigned round = 0; round < max_rounds_; ++round) {
      std::vector<std::pair<std::size_t, std::size_t>> marked;
      const Measure e = measure(m, &marked);
      const bool better = e.max_chord < best.max_chord || e.flipped < best.flipped || e.uncovered < best.uncovered;
      best.max_chord = std::min(best.max_chord, e.max_chord);
      best.flipped = std::min(best.flipped, e.flipped), best.uncovered = std::min(best.uncovered, e.uncovered);
      say("n-way: mesh " + std::to_string(m) + ", round " + std::to_string(round + 1) + ": max chord " +
          fmt(100 * e.max_chord / diagonal_[m]) + "%, " + std::to_string(e.uncovered) + " vertices uncovered, " +
          std::to_string(e.flipped) + " flipped, " + std::to_string(marked.size()) + " edges to split");
      if (marked.empty()) return;
      if ((stale = better ? 0 : stale + 1) == max_stale_rounds) {
        say("n-way: stopped refining mesh " + std::to_string(m) + ": " + std::to_string(max_stale_rounds) +
            " rounds without progress");
        return;
      }
      if (vloc_.size() > max_growth * largest) {
        say("n-way: stopped refining at " + std::to_string(max_growth) + " times the largest input's vertex count");
        return;
      }
      build_edge_index();
      for (const auto& ab : marked) split(ab.first, ab.second);
      stats_.splits[m] += marked.size();
      stats_.untangle_moves[m] += untangle(m);
    }
  }

  void build_edge_index() {
    edge_face_.clear();
    edge_face_.reserve(3 * faces_.size());
    for (std::size_t g = 0; g < faces_.size(); ++g)
      for (int c = 0; c < 3; ++c) edge_face_[key(faces_[g][std::size_t(c)], faces_[g][std::size_t((c + 1) % 3)])] = g;
  }

  /// Splits common edge (a, b) at its midpoint on the source; the new vertex takes its point on every mesh
  /// fitted so far through that mesh's map. An edge already split this round is found no more and skipped.
  void split(std::size_t a, std::size_t b) {
    const auto i1 = edge_face_.find(key(a, b)), i2 = edge_face_.find(key(b, a));
    if (i1 == edge_face_.end() || i2 == edge_face_.end()) return;
    const std::size_t g1 = i1->second, g2 = i2->second;
    const std::size_t v = vloc_.size();
    // The new vertex in g1's input face.
    auto corner = [&](std::size_t g, std::size_t x) {
      for (int c = 0; c < 3; ++c)
        if (faces_[g][std::size_t(c)] == x) return c;
      throw Algorithm_error("internal error: N-way split of an edge not in its face");
    };
    auto halve = [&](std::size_t g) {
      const auto& fl = floc_[g];
      std::array<double, 3> b3{};
      const int ca = corner(g, a), cb = corner(g, b);
      for (int i = 0; i < 3; ++i)
        b3[std::size_t(i)] = 0.5 * (fl.corners[std::size_t(ca)][std::size_t(i)] + fl.corners[std::size_t(cb)][std::size_t(i)]);
      return b3;
    };
    const std::array<double, 3> m1 = halve(g1), m2 = halve(g2);
    vloc_.push_back({floc_[g1].face, m1});
    for (std::size_t m = 0; m < points_.size(); ++m) {
      if (!fitted_[m]) continue;
      if (m == stats_.source || m == fitting_) {
        points_[m].push_back(map_point(m, vloc_.back()));
      } else {
        const auto& pa = points_[m][a];
        const auto& pb = points_[m][b];
        points_[m].push_back(project(m, {0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.5 * (pa[2] + pb[2])}));
      }
    }
    // Face g (with edge x -> y) becomes (x, v, z) and a new face (v, y, z).
    auto cut = [&](std::size_t g, std::size_t x, std::size_t y, const std::array<double, 3>& mb) {
      const int cx = corner(g, x), cy = corner(g, y), cz = 3 - cx - cy;
      const std::size_t z = faces_[g][std::size_t(cz)];
      Input_face_location lo = floc_[g], hi = floc_[g];
      const std::array<double, 3> bx = floc_[g].corners[std::size_t(cx)], by = floc_[g].corners[std::size_t(cy)],
                                  bz = floc_[g].corners[std::size_t(cz)];
      faces_[g] = {x, v, z};
      lo.corners = {bx, mb, bz};
      floc_[g] = lo;
      const std::size_t h = faces_.size();
      faces_.push_back({v, y, z});
      hi.corners = {mb, by, bz};
      floc_.push_back(hi);
      edge_face_.erase(key(x, y));
      edge_face_[key(x, v)] = g;
      edge_face_[key(v, z)] = g;
      edge_face_[key(z, x)] = g;
      edge_face_[key(v, y)] = h;
      edge_face_[key(y, z)] = h;
      edge_face_[key(z, v)] = h;
    };
    cut(g1, a, b, m1);
    cut(g2, b, a, m2);
  }

  static double sec(clock::time_point a, clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }
  static std::string fmt(double x) {
    std::ostringstream s;
    s.precision(4);
    s << x;
    return s.str();
  }
  void say(const std::string& s) const {
    if (progress_) progress_(s);
  }

  double tolerance_ = 0.5;
  unsigned max_rounds_ = 30;
  std::function<void(const std::string&)> progress_;
  std::vector<Surface_mesh> inputs_;
  std::vector<std::size_t> order_; ///< the other meshes, in input order
  std::vector<Map_slot> maps_;     ///< per mesh; empty for the source
  std::vector<std::unique_ptr<Tree>> trees_;
  std::vector<double> diagonal_;
  std::vector<char> fitted_;
  std::size_t fitting_ = std::size_t(-1); ///< the mesh being fitted: its new vertices go through its map
  std::vector<std::array<std::size_t, 3>> faces_;
  std::vector<Input_face_location> floc_;
  std::vector<Input_location> vloc_;
  std::vector<std::vector<std::array<double, 3>>> points_;
  std::unordered_map<std::uint64_t, std::size_t> edge_face_;
  Multi_remeshing_statistics stats_;
};

} // namespace crossparam

#endif // CROSSPARAM_MULTI_REMESHING_H

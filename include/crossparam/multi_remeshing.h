// SPDX-License-Identifier: GPL-3.0-or-later
// One common connectivity for N meshes (Kraevoy & Sheffer 2004, §2.3): N >= 2 closed meshes of one genus, a
// correspondence with one column per mesh; one mesh is the source. The source is mapped onto every other mesh
// (a Cross_parameterization each) and compatibly remeshed with it (a Compatible_remesher each, §5, with its
// adaptive smoothing, refinement, untangling and surface-distance steps), so every other mesh gets a
// target-shaped mesh fitted to it.
//
// Each of those remeshings refines the source by splits only: each of its faces lies inside one input face of
// the source. The common connectivity is their common refinement (internal/remeshing/common_refinement.h):
// every input face of the source is triangulated so that each triangle lies inside one face of every
// remeshing; where two or more remeshings subdivide an input face differently, by a constrained Delaunay
// triangulation in exact arithmetic with all their edges as constraints. Output k places each vertex on
// remeshing k's target-shaped mesh, by linear interpolation in the face holding it: the output is that surface
// itself, subdivided, so it keeps the remeshing's distance to mesh k and its normals, and every vertex of the
// remeshing keeps its place. The source output lies on the source exactly, its vertices first.
//
// Last, each output is repaired on its own (internal/remeshing/output_repair.h): a part of a good face of a
// remeshing can be bad by the verifier's definitions (the flip rule tests it at its own centroid; a sliver's
// normal is rounding), and the outputs share the face list only, so moving points of one output changes no other.
//
// This is §2.3's incremental construction with the fits made independently of each other: a vertex added for
// mesh k gets its place on every other mesh through that mesh's fitted surface (within the tolerance of the
// mesh) rather than through that mesh's map, which would undo the fit's smoothing and untangling there.
#ifndef CROSSPARAM_MULTI_REMESHING_H
#define CROSSPARAM_MULTI_REMESHING_H

#include <crossparam/compatible_remeshing.h>
#include <crossparam/cross_parameterization.h>
#include <crossparam/errors.h>
#include <crossparam/internal/remeshing/common_refinement.h>
#include <crossparam/internal/remeshing/output_repair.h>
#include <crossparam/remeshing_verification.h>
#include <crossparam/types.h>

#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace crossparam {

/// Value of the named parameter `source_mesh` that picks the mesh with the most vertices as the source.
constexpr std::size_t finest_mesh = std::size_t(-1);

/// Figures of one N-way remeshing. Errors in percent of each mesh's bounding-box diagonal.
struct Multi_remeshing_statistics {
  std::size_t source = 0;                   ///< index of the source mesh
  std::vector<std::size_t> input_vertices;  ///< per mesh
  std::size_t output_vertices = 0, output_faces = 0;
  std::vector<std::size_t> fitted_vertices; ///< per mesh: vertices of its compatible remeshing (0 for the source)
  std::vector<double> max_chord_error;      ///< per mesh: that remeshing's largest chord error
  std::vector<std::size_t> flipped_faces;   ///< per mesh: that remeshing's flipped faces (its own count)
  std::vector<char> fit_converged;          ///< per mesh: that remeshing met its bounds (1 for the source)
  std::size_t retriangulated_faces = 0;     ///< source faces that two or more remeshings subdivide differently
  std::size_t flipped_caps = 0;             ///< triangles with a vertex within rounding of the opposite edge, flipped
  std::size_t merged_needles = 0;           ///< edges within rounding of zero length, collapsed
  std::vector<double> seconds_map;          ///< per mesh: its cross-parameterization (0 for the source)
  std::vector<double> seconds_fit;          ///< per mesh: its compatible remeshing (0 for the source)
  std::vector<std::size_t> bad_faces_before_repair; ///< per mesh: its output's bad faces (flipped, degenerate, intersecting) before the output repair
  std::vector<std::size_t> bad_faces_after_repair;  ///< and after it (the repair's own count; the verifier decides)
  std::vector<std::size_t> repair_moves;            ///< per mesh: points the output repair moved one at a time
  std::vector<std::size_t> repair_disks;            ///< per mesh: disks around a bad face it embedded anew
  double seconds_common = 0;                ///< the common refinement
  double seconds_repair = 0;                ///< the output repair, all outputs
  double seconds_total = 0;
  bool converged = false;                   ///< every remeshing met its bounds
};

/// \brief Brings N closed meshes to one connectivity (paper §2.3): N outputs with one face list, the source
/// reproduced exactly, every other output the surface of its own compatible remeshing with the source.
///
/// \tparam TriangleMesh a model of `FaceListGraph` with a `vertex_point` map (read in `vertices()` order)
///
/// Named parameters: `crossparam::parameters::source_mesh` (index of the source, default 0; `finest_mesh`
/// picks the mesh with the most vertices); `crossparam::parameters::tolerance` (percent of each mesh's
/// bounding-box diagonal, default 0.5); `crossparam::parameters::progress`; and those of
/// `Cross_parameterization` and `Compatible_remesher`, passed on to every map and every remeshing (a
/// `time_limit` holds for each of them).
template <class TriangleMesh>
class Multi_remesher {
public:
  /// \param meshes the N >= 2 input meshes, closed, of one genus
  /// \param features one row per feature, one vertex per mesh in each row
  /// \param np the named parameters (see above)
  /// \throws Input_error for fewer than two meshes, a row of features with another number of entries than
  ///         meshes, a source index out of range, a bad tolerance; and what the maps and the remeshings throw
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
    const double tolerance = choose_parameter(get_parameter(np, internal_np::tolerance_t()), 0.5);
    if (!(tolerance > 0) || !std::isfinite(tolerance))
      throw Input_error("remeshing tolerance must be a positive number of percent");
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
    stats_.fitted_vertices.assign(n, 0);
    stats_.max_chord_error.assign(n, 0);
    stats_.flipped_faces.assign(n, 0);
    stats_.fit_converged.assign(n, 1);
    stats_.seconds_map.assign(n, 0);
    stats_.seconds_fit.assign(n, 0);

    // Per other mesh: the map (on copies: a map refines its meshes) and the compatible remeshing with it.
    maps_.resize(n);
    std::vector<Fit> fits(n);
    std::vector<internal::Fitted_remeshing> fitted;
    std::vector<std::size_t> order;
    for (std::size_t m = 0; m < n; ++m) {
      if (m == s) continue;
      const auto tm = clock::now();
      Feature_correspondence pairs;
      for (const auto& row : features) pairs.push_back({row[s], row[m]});
      auto& slot = maps_[m];
      slot.source = std::make_unique<Surface_mesh>(inputs_[s]);
      slot.target = std::make_unique<Surface_mesh>(inputs_[m]);
      slot.cp = std::make_unique<CP>(*slot.source, *slot.target, pairs, np);
      stats_.seconds_map[m] = sec(tm, clock::now());
      say("n-way: map of mesh " + std::to_string(s) + " onto mesh " + std::to_string(m) + " (" +
          fmt(stats_.seconds_map[m]) + " s)");
      const auto tf = clock::now();
      const Compatible_remesher<Surface_mesh, Surface_mesh> r(*slot.cp, np);
      Fit& fit = fits[m];
      fit.faces = r.faces();
      fit.locations = r.source_face_locations();
      // The common refinement needs each remeshing to tile every input face of the source (its faces each
      // with area there, oriented as the tiling): checked here rather than trusted.
      if (const std::size_t bad = source_tiling_defects(fit.locations); bad > 0)
        throw Algorithm_error("N-way remeshing: the remeshing with mesh " + std::to_string(m) + " has " +
                              std::to_string(bad) + " faces that do not tile their face of the source");
      fit.target_points = r.target_points();
      const Remeshing_statistics& R = r.statistics();
      stats_.fitted_vertices[m] = R.output_vertices;
      stats_.max_chord_error[m] = R.max_chord_error;
      stats_.flipped_faces[m] = R.flipped_faces;
      stats_.fit_converged[m] = R.converged;
      stats_.seconds_fit[m] = sec(tf, clock::now());
      say("n-way: compatible remeshing with mesh " + std::to_string(m) + ": " + std::to_string(R.output_vertices) +
          " vertices (" + fmt(stats_.seconds_fit[m]) + " s)");
      order.push_back(m);
    }
    for (std::size_t m : order) fitted.push_back({&fits[m].faces, &fits[m].locations, &fits[m].target_points});

    // The common refinement of the remeshings.
    const auto tc = clock::now();
    std::vector<std::array<double, 3>> source_points;
    for (auto v : inputs_[s].vertices()) {
      const Point_3& p = inputs_[s].point(v);
      source_points.push_back({p.x(), p.y(), p.z()});
    }
    internal::Common_refinement c =
        internal::Common_refinement_builder(source_points, inputs_[s].number_of_faces(), fitted).result();
    {
      // The common connectivity must be a manifold mesh, or no output can be built from it: said here, with the
      // library's error, rather than by CGAL when an output is copied.
      std::vector<std::vector<std::size_t>> polygons;
      polygons.reserve(c.faces.size());
      for (const auto& f : c.faces) polygons.push_back({f[0], f[1], f[2]});
      if (!CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(polygons))
        throw Algorithm_error("the common refinement of the " + std::to_string(n) + " remeshings (" +
                              std::to_string(c.faces.size()) + " faces) is not a manifold mesh");
    }
    faces_ = std::move(c.faces);
    floc_ = std::move(c.locations);
    points_.resize(n);
    points_[s] = std::move(c.source_points);
    for (std::size_t i = 0; i < order.size(); ++i) points_[order[i]] = std::move(c.images[i]);
    stats_.retriangulated_faces = c.retriangulated_faces;
    stats_.flipped_caps = c.flipped_caps;
    stats_.merged_needles = c.merged_needles;
    stats_.seconds_common = sec(tc, clock::now());
    // The repair of each output (internal/remeshing/output_repair.h): its points only.
    const auto tr = clock::now();
    stats_.bad_faces_before_repair.assign(n, 0);
    stats_.bad_faces_after_repair.assign(n, 0);
    stats_.repair_moves.assign(n, 0);
    stats_.repair_disks.assign(n, 0);
    const std::size_t ns = inputs_[s].number_of_vertices();
    for (std::size_t m = 0; m < n; ++m) {
      std::vector<char> movable(points_[m].size(), 1);
      if (m == s)
        std::fill(movable.begin(), movable.begin() + std::ptrdiff_t(ns), 0);
      else
        for (const auto& row : features) movable.at(row[s]) = 0;
      const double eps = tolerance / 100 * internal::bbox_diagonal(inputs_[m]);
      const internal::Output_repair_result rr =
          internal::Output_repairer(faces_, points_[m], inputs_[m], eps, std::move(movable), m == s ? &floc_ : nullptr).run();
      stats_.bad_faces_before_repair[m] = rr.bad_before;
      stats_.bad_faces_after_repair[m] = rr.bad_after;
      stats_.repair_moves[m] = rr.moves;
      stats_.repair_disks[m] = rr.disks;
      say("n-way: output " + std::to_string(m) + " repaired: " + std::to_string(rr.bad_before) + " bad faces, " +
          std::to_string(rr.bad_after) + " left after " + std::to_string(rr.moves) + " moves and " +
          std::to_string(rr.disks) + " disks in " +
          std::to_string(rr.rounds) + " rounds");
    }
    stats_.seconds_repair = sec(tr, clock::now());
    stats_.converged = std::all_of(stats_.fit_converged.begin(), stats_.fit_converged.end(), [](char x) { return x != 0; });
    stats_.output_vertices = points_[s].size();
    stats_.output_faces = faces_.size();
    stats_.seconds_total = sec(t0, clock::now());
    say("n-way: one connectivity, " + std::to_string(stats_.output_vertices) + " vertices (" +
        std::to_string(stats_.retriangulated_faces) + " source faces triangulated anew, " +
        std::to_string(stats_.flipped_caps) + " caps flipped, " + std::to_string(stats_.merged_needles) +
        " needles collapsed, " + fmt(stats_.seconds_common) + " s)");
  }

  /// The common face list (indices into every point list), oriented as the source.
  const std::vector<std::array<std::size_t, 3>>& faces() const { return faces_; }
  /// The points of output `mesh` (input order of the meshes): for the source, its vertices first, exactly, then
  /// points on its faces; for every other mesh, points on its compatible remeshing's target-shaped surface.
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

  struct Map_slot {
    std::unique_ptr<Surface_mesh> source, target;
    std::unique_ptr<CP> cp;
  };
  /// The outputs of one compatible remeshing that the common refinement reads.
  struct Fit {
    std::vector<std::array<std::size_t, 3>> faces;
    std::vector<Input_face_location> locations;
    std::vector<std::array<double, 3>> target_points;
  };

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

  std::function<void(const std::string&)> progress_;
  std::vector<Surface_mesh> inputs_;
  std::vector<Map_slot> maps_; ///< per mesh; empty for the source
  std::vector<std::array<std::size_t, 3>> faces_;
  std::vector<Input_face_location> floc_;
  std::vector<std::vector<std::array<double, 3>>> points_;
  Multi_remeshing_statistics stats_;
};

} // namespace crossparam

#endif // CROSSPARAM_MULTI_REMESHING_H

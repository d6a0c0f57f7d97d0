// SPDX-License-Identifier: GPL-3.0-or-later
// Compatible remeshing (Kraevoy & Sheffer 2004, §5): two meshes with the connectivity of the (refined) source,
// one reproducing the source exactly, the other approximating the target within a user tolerance.
//
// The source connectivity is carried onto the target by the cross-parameterization F (the mesh M_st). Then,
// in a loop: the approximation error e(v) at the target vertices (Eq. 1), Gaussian-smoothed; adaptive smoothing
// of the source's parameterization with error-driven edge weights (Eq. 2) through the same Local_smoother as
// §4.2; refinement where the error stays high once smoothing stops helping (§5.3: edge splits, plus insertion of
// the preimages of the worst target vertices), with folds of M_st removed by vertex moves; finally "pseudo"
// edge flips (§5.4): edges whose flip would bring the faces' normals closer to the target's are split at the
// crossing of the two diagonals instead. Splits are applied to the source mesh and M_st together (they share
// connectivity); a new vertex lies on a source edge or inside a source face, and its image is F of it, on the
// target. No vertex is removed and no edge is flipped, so the source geometry is kept exactly, and every step
// keeps the parameterization one-to-one (exact orientation tests), which is certified again at the end. Folds of M_st left after the pseudo flips
// are untangled along the target, with a fold repair by splits first where that alone fails: there, and only
// there, a vertex of the target-shaped mesh is not F of its source vertex.
//
// The driver, Compatible_remesher, runs these steps in order on a state object (internal/remeshing/: the
// state with its measurement, split and checkpoints in remesh_state.h, one header per step).
#ifndef CROSSPARAM_COMPATIBLE_REMESHING_H
#define CROSSPARAM_COMPATIBLE_REMESHING_H

#include <crossparam/cross_parameterization.h>
#include <crossparam/internal/parallel.h>
#include <crossparam/internal/remeshing/fold_repair.h>
#include <crossparam/internal/remeshing/gap_refinement.h>
#include <crossparam/internal/remeshing/overlay.h>
#include <crossparam/internal/remeshing/overlay_decimation.h>
#include <crossparam/internal/remeshing/pseudo_flips.h>
#include <crossparam/internal/remeshing/refinement.h>
#include <crossparam/internal/remeshing/remesh_state.h>
#include <crossparam/internal/remeshing/strict_repair.h>
#include <crossparam/internal/remeshing/target_untangling.h>

#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <sstream>
#include <string>

namespace crossparam {

/// Weights policy of the adaptive smoothing (§5.2, Eq. 2): the weight of edge (u, v) is the running average
/// w_uv <- (e_uv + w_uv) / 2 of its error e_uv, so vertices are drawn towards badly approximated regions without
/// jumping back and forth. Multiplied by the shape-preserving mean-value weights of the source (§4.2), so that
/// where the error is uniform the smoothing keeps the low-distortion map instead of flattening it (the paper
/// uses the error weights alone; measured worse here: more added vertices for the same tolerance).
/// A model of `RemeshingWeights`: `prepare(mesh)` after every connectivity change, `update(mesh, e)` with the
/// error of every edge (indexed by edge), and `operator()(h)`, a positive weight, as `SmoothingWeights`.
class Error_driven_weights {
public:
  /// `shape`: whether to multiply by the mean-value weights (default true).
  explicit Error_driven_weights(bool shape = true) : shape_(shape) {}

  void prepare(const Refined_mesh& m) {
    if (shape_) mv_.prepare(m);
    w_.resize(m.number_of_edges(), -1.0);
  }
  void update(const Refined_mesh& m, const std::vector<double>& e) {
    w_.resize(m.number_of_edges(), -1.0);
    double mean = 0;
    for (double x : e) mean += x;
    mean /= double(std::max<std::size_t>(1, e.size()));
    const double floor = 0.1 * mean + 1e-12; // keeps every weight positive where the error vanishes
    for (std::size_t i = 0; i < e.size(); ++i) {
      const double x = (e[i] + floor) / (mean + 1e-300); // relative: the scale of the weights is irrelevant
      w_[i] = w_[i] < 0 ? x : 0.5 * (x + w_[i]);
    }
  }
  double operator()(Refined_halfedge h) const {
    const double w = w_[std::size_t(h) / 2];
    return shape_ ? w * mv_(h) : w;
  }

private:
  bool shape_;
  Mean_value_weights mv_;
  std::vector<double> w_;
};

/// Refinement rule of §5.3: split the edges whose error exceeds max(½ · the largest edge error, ε).
/// A model of `RefinementRule`: `double threshold(double max_edge_error, double epsilon)`.
struct Half_max_refinement {
  double threshold(double max_edge_error, double epsilon) const { return std::max(0.5 * max_edge_error, epsilon); }
};

/// Figures of one compatible remeshing. Errors are in percent of the target's bounding-box diagonal.
struct Remeshing_statistics {
  std::size_t source_vertices = 0, target_vertices = 0; ///< of the inputs
  std::size_t layout_vertices = 0;  ///< of the source after the layout and adjacency splits, less those undone (before §5)
  std::size_t layout_splits_undone = 0; ///< layout splits of the source undone before §5 (their edges restored)
  std::size_t output_vertices = 0, output_faces = 0;
  std::size_t refinement_splits = 0; ///< §5.3
  std::size_t pseudo_flips = 0;      ///< §5.4
  std::size_t gap_vertices = 0;      ///< vertices added where a sample of one mesh lay too far from the other
                                     ///< (the last step: gap_refinement.h)
  unsigned gap_rounds = 0;           ///< rounds of that step that added vertices
  double gap_before = 0;             ///< the largest sampled distance before it, percent
  std::size_t gap_samples_left = 0;  ///< samples its last round still found beyond 0.9 ε
  std::size_t unfold_moves = 0;      ///< vertex moves that removed folds of the target-shaped mesh
  std::size_t refinement_repairs_kept = 0; ///< refused chord splits made with a local fold repair (§5.3)
  std::size_t refinement_repairs_undone = 0; ///< such splits undone, or refused even with one fold of slack
  std::size_t fold_repair_splits = 0; ///< splits kept by the fold repair (after §5.4)
  std::size_t fold_repairs_kept = 0, fold_repairs_undone = 0; ///< fold-repair attempts kept and undone
  std::size_t untangled_folds = 0;   ///< folded faces that the untangling on the target removed
  std::size_t untangle_moves = 0;    ///< vertices of the target-shaped mesh it moved (off F, along the target)
  std::size_t standard_flips_untangled = 0; ///< faces flipped by the standard rule that its second pass removed
  std::size_t standard_flips_left = 0;      ///< faces of M_st flipped by the standard rule after the untangling
  std::size_t standard_untangle_moves = 0;  ///< vertices of the target-shaped mesh that second pass moved
  double standard_untangle_max_move = 0;    ///< its farthest move, percent of the target's diagonal
  double untangle_max_move = 0;      ///< the farthest such move, percent of the target's bounding-box diagonal
  std::size_t untangle_folds_not_tried = 0; ///< folds the untangling passes left untried at their work bound
  std::size_t strict_flipped_before = 0;      ///< faces flipped by the standard rule before the strict repair
  std::size_t strict_intersecting_before = 0; ///< faces in new self-intersecting pairs before it
  std::size_t strict_flipped_after = 0;       ///< and after it (the verifier decides: see remeshing_verification.h)
  std::size_t strict_intersecting_after = 0;
  std::size_t strict_flips = 0;               ///< edge flips the strict repair kept (the source's surface kept)
  std::size_t strict_disks = 0;               ///< disks of M_st the strict repair re-embedded on the target
  std::size_t strict_splits = 0;              ///< vertices the strict repair added
  unsigned strict_rounds = 0;                 ///< its refinement rounds
  bool strict_work_bound_reached = false;     ///< whether it stopped at its work bound (strict_repair.h)
  bool overlay_used = false;                  ///< whether the result is the decimated overlay
  std::size_t overlay_vertices = 0;           ///< vertices of the overlay before its decimation (0: not built)
  std::size_t overlay_refused = 0;            ///< inserts and splits of the overlay refused by their exact test
  /// Target vertices the overlay inserted at their own location over the base mesh, where the location
  /// interpolated in the face that holds them has its image off them (a part of the target that the map
  /// squeezes, whose coordinates over the base mesh rounding blurs)
  std::size_t overlay_exact = 0;
  /// Crossings of target edges that the overlay made with edges of the source nearly along them over the base
  /// mesh but not on the target (internal::Overlay_crossing::along; where the map squeezes the target)
  std::size_t overlay_along_crossed = 0;
  /// Where they are: points of the target, in its input coordinates. A refused insert leaves that target
  /// vertex or edge out of the overlay, so the output can miss the target there: the map compresses that part
  /// of the target into a piece of the source too small for the exact tests in double precision.
  std::vector<std::array<double, 3>> overlay_refused_points;
  std::size_t overlay_flips = 0;              ///< edge flips of the overlay: to insert target edges, then Lawson's
  /// Overlays built: 0, 1, or 2 where the first one's decimated result failed the strict checks and a second
  /// one was built with no flip that makes a sliver on the source (Remesh_state::refuse_source_slivers)
  std::size_t overlay_attempts = 0;
  bool overlay_refusing_slivers = false;      ///< whether the result is that second overlay (the figures above are its)
  bool overlay_complete = false;              ///< whether every target vertex and edge is in the overlay
  std::size_t overlay_collapses = 0;          ///< vertices the decimation removed
  bool overlay_work_bound_reached = false;    ///< whether the decimation stopped at its work bound
  std::size_t overlay_needles_removed = 0;     ///< collapses of the decimation's needle removal
  std::size_t overlay_needles_left = 0;        ///< faces thinner than the decimation's needle bounds it left
  std::size_t overlay_zippers_flipped = 0;     ///< faces with no area on the source flipped away (Remesh_state::flip_zipper())
  std::size_t overlay_zippers_folding = 0;     ///< of those, flipped although the flip folds a face of M_st, left to the strict repair
  std::size_t overlay_flipped = 0, overlay_intersecting = 0; ///< the strict figures of the decimated overlay
  std::size_t overlay_disks = 0;               ///< disks its strict repair re-embedded on the target
  /// Vertices added to the decimated overlay where a sample of one mesh lay beyond 0.9 ε of the other (the
  /// surface-distance step, gap_refinement.h: the faces the overlay left across a refused insert are not
  /// certified by the decimation), and the samples its last round still found beyond 0.9 ε
  std::size_t overlay_gap_vertices = 0, overlay_gap_samples_left = 0;
  double seconds_overlay_gaps = 0;           ///< the time of that step (part of seconds_overlay)
  unsigned smoothing_rounds = 0, refinement_rounds = 0;
  double tolerance = 0;              ///< ε, percent
  double max_error_initial = 0, l2_error_initial = 0; ///< e(v) of M_st right after the projection
  double max_error = 0, l2_error = 0; ///< e(v) of the result (max and root mean square over target vertices)
  double max_chord_error = 0;        ///< largest distance of an output edge midpoint or face centroid from the
                                     ///< image of the same source point on the target
  double psnr = 0;                   ///< 20 log10(diagonal / L2 error), as the paper's Table 2
  std::size_t flipped_faces = 0;     ///< output faces flipped by the standard rule (normal > 90° from the target's
                                     ///< at the point nearest the centroid), the remesher's own count
  bool converged = false;            ///< max error and max chord error <= tolerance, and no flipped face
  double seconds_cross_parameterization = 0, seconds_smoothing = 0, seconds_refinement = 0, seconds_flips = 0,
         seconds_gaps = 0, seconds_strict_repair = 0, seconds_overlay = 0, seconds_fold_repair = 0, seconds_untangle = 0, seconds_certificate = 0, seconds_total = 0;
};

/// \brief Compatible remeshing (paper §5) of the two meshes of a cross-parameterization.
///
/// Works on a copy of the source side of `cp` (the cross-parameterization itself is not changed). The results
/// are two meshes with one face list: `source_points()` reproduce the source (the first `source_vertices`
/// points are the input source vertices, exactly, in input order; the others lie on source edges or faces) and
/// `target_points()` lie on the target. Points are in input coordinates, faces oriented as the input source.
///
/// Named parameters: `tolerance` (percent, default 0.5), `normal_deviation` (degrees, default 30),
/// `max_rounds` (default 30), `remeshing_weights` (default `Error_driven_weights`), `refinement_rule` (default
/// `Half_max_refinement`), `progress` (callback, one line per step), `undo_layout_splits` (default true),
/// `number_of_threads` (default 0: one per hardware thread; the results do not depend on it), `time_limit`
/// (seconds, default none) and `best_effort` (default false).
///
/// Work bounds and the time budget: at most `max_rounds` smoothing-and-refinement rounds (each 3 smoothing
/// passes and at most one split per source edge and target vertex), refinement stopped at four times the
/// source's vertex count; one pseudo-flip pass over the edges; one fold repair attempt per folded face; one
/// local untangling per folded face, over rings of at most 8 faces around it; at most 8 rounds of the
/// surface-distance step, each adding at most one vertex per face; at most 8 passes of the strict repair, one
/// repair attempt (four kinds) per face the verifier's checks reject, not past four times the source's vertex
/// count. The `time_limit` is checked at every round and at every folded face; when it runs out the constructor
/// throws `Time_limit_error`, or, with `best_effort`, ends the step under way with the state reached, skips the
/// improving steps left (pseudo flips, fold repair, untangling, surface distance, strict repair) and certifies
/// and returns that result.
///
/// The steps, in order (the constructor runs them): the projection and its error (§5.1), adaptive smoothing
/// and refinement (§5.2-5.3), pseudo edge flips (§5.4), the untangling on the target with the fold repair, the
/// two-sided surface distance sampled on both meshes and closed where a sample lies beyond 0.9 ε, the strict
/// repair of the faces the verifier would reject (flipped by the standard rule, or in new self-intersecting
/// pairs), the certificate, the outputs. Each step is in `internal/remeshing/`, on one state object.
///
/// \tparam SourceMesh, TargetMesh the mesh types of the cross-parameterization
template <class SourceMesh, class TargetMesh>
class Compatible_remesher {
public:
  using Cross_param = Cross_parameterization<SourceMesh, TargetMesh>;

  /// Remeshes the two meshes of `cp` (which must outlive the construction only).
  /// \tparam NP a sequence of named parameters (see above)
  /// \param cp a cross-parameterization of the source and the target
  /// \param np the named parameters of the remeshing
  /// \throws Input_error if the tolerance is not a positive number; Algorithm_error if the remeshed source's
  ///         parameterization fails its certificate; Time_limit_error if the `time_limit` runs out (see above)
  template <typename NP = CGAL::parameters::Default_named_parameters>
  explicit Compatible_remesher(const Cross_param& cp, const NP& np = CGAL::parameters::default_values()) {
    using CGAL::parameters::choose_parameter;
    using CGAL::parameters::get_parameter;
    const auto t0 = clock::now();
    stats_.tolerance = choose_parameter(get_parameter(np, internal_np::tolerance_t()), 0.5);
    if (!(stats_.tolerance > 0) || !std::isfinite(stats_.tolerance))
      throw Input_error("remeshing tolerance must be a positive number of percent");
    const double max_dev = choose_parameter(get_parameter(np, internal_np::normal_deviation_t()), 30.0);
    const unsigned max_rounds = choose_parameter(get_parameter(np, internal_np::max_rounds_t()), 30u);
    const bool undo = choose_parameter(get_parameter(np, internal_np::undo_layout_splits_t()), true);
    const Remeshing_construction construction = choose_parameter(
        get_parameter(np, internal_np::remeshing_construction_t()), Remeshing_construction::automatic);
    progress_ = choose_parameter(get_parameter(np, internal_np::progress_t()), std::function<void(const std::string&)>());
    const unsigned threads = internal::thread_count(choose_parameter(get_parameter(np, internal_np::number_of_threads_t()), 0u));
    auto weights = choose_parameter(get_parameter(np, internal_np::remeshing_weights_t()), Error_driven_weights());
    const auto rule = choose_parameter(get_parameter(np, internal_np::refinement_rule_t()), Half_max_refinement());

    // Working coordinates have a unit bounding-box diagonal: ε in percent is ε / 100 there.
    internal::Remesh_state s(internal::map_view(cp), stats_.tolerance / 100.0, threads);
    s.budget = internal::Time_budget::from(np);
    project(s, undo);                                // M_st, the source's connectivity on the target (§5.1)
    // Out of time, each step left throws Time_limit_error, or with best effort is skipped.
    auto skip = [&s](const char* stage) { return s.budget.stop(stage, [] { return std::string("not started"); }); };
    bool repair_pending = false; // the refinement's strict repair waits for the overlay (below)
    if (construction != Remeshing_construction::overlay) {
      smooth_and_refine(s, weights, rule, max_rounds); // §5.2-5.3
      if (max_dev < 180 && !skip("the remeshing's pseudo flips")) pseudo_flip(s, max_dev); // §5.4
      if (!skip("the remeshing's untangling")) untangle(s); // folds left (additions to the paper)
      if (!skip("the remeshing's surface-distance step")) close_gaps(s); // the distance the verifier measures
      // Samples left beyond 0.9 ε: the refinement's result is not valid whatever the strict repair does (it
      // refines only at flipped and intersecting faces), and the automatic construction builds the overlay in any
      // case. The strict repair of the refinement's result, the costliest step where the map is hard (more than
      // twenty minutes on shrec/381_384), then waits: it runs only where the overlay's result is not strictly
      // valid, to keep the better of the two as before (the outputs are those of the other order).
      repair_pending = construction == Remeshing_construction::automatic && stats_.gap_samples_left > 0;
      if (!repair_pending && !skip("the remeshing's strict repair")) strict_repair(s); // the verifier's flip and intersection tests
    }
    // The decimated overlay, instead of the refinement or where the refinement's result fails the checks.
    State* result = &s;
    std::optional<State> o, o2;
    // Strictly valid as far as the remesher can tell: no face flipped or in a new self-intersecting pair, and no
    // sample of either surface left beyond 0.9 ε of the other (gap_refinement.h).
    const bool strict_ok = stats_.strict_flipped_after + stats_.strict_intersecting_after == 0 && stats_.gap_samples_left == 0;
    if (construction == Remeshing_construction::overlay ||
        (construction == Remeshing_construction::automatic && !strict_ok && !skip("the remeshing's overlay")))
      result = overlay_construction(s, cp, o, o2, max_dev, construction == Remeshing_construction::overlay, threads,
                                    repair_pending);
    if (repair_pending) {
      const bool overlay_valid = result != &s && overlay_bad() == 0 && stats_.overlay_gap_samples_left == 0;
      if (!overlay_valid && !skip("the remeshing's strict repair")) {
        say("remesh: the overlay fails the strict checks; the refinement's result gets its strict repair");
        strict_repair(s);
        if (result != &s && !overlay_beats_refined()) {
          result = &s, stats_.overlay_used = false, stats_.overlay_refusing_slivers = false;
          o.reset(), o2.reset();
        }
      }
    }
    if (s.budget.expired()) say("remesh: time limit reached (best effort): the steps left are skipped");
    certify(*result);                                // the parameterization is still one-to-one
    finish(*result, cp.statistics().seconds_total, t0);
  }

  /// The common face list (indices into both point lists), oriented as the input source.
  const std::vector<std::array<std::size_t, 3>>& faces() const { return out_.faces; }
  /// The source-shaped mesh's points, input coordinates; the first `statistics().source_vertices` are the
  /// input source's vertices exactly.
  const std::vector<std::array<double, 3>>& source_points() const { return out_.source_points; }
  /// The target-shaped mesh's points (on the target), input coordinates.
  const std::vector<std::array<double, 3>>& target_points() const { return out_.target_points; }
  /// Approximation error at each output vertex (percent of the target's diagonal): the smoothed e(v) field of
  /// the target read where the vertex lands (§5.1), for pictures.
  const std::vector<double>& vertex_error() const { return out_.vertex_error; }
  /// Where each output vertex lands on the target, against the target as given.
  const std::vector<Input_location>& target_locations() const { return out_.target_locations; }
  /// Per face of `faces()`, the input source face it lies in and its corners there (the source-shaped mesh is
  /// the source refined by splits: every face lies inside one input face).
  const std::vector<Input_face_location>& source_face_locations() const { return out_.source_faces; }
  const Remeshing_statistics& statistics() const { return stats_; }
  const Bijectivity_certificate& certificate() const { return cert_; }

  /// Copies the source-shaped (`Mesh_side::source`) or target-shaped (`Mesh_side::target`) result into `out`,
  /// any MutableFaceGraph.
  template <class OutputMesh>
  void copy_to(Mesh_side side, OutputMesh& out) const {
    using P3 = typename boost::property_traits<
        typename boost::property_map<OutputMesh, CGAL::vertex_point_t>::type>::value_type;
    std::vector<P3> pts;
    for (const auto& p : side == Mesh_side::source ? out_.source_points : out_.target_points) pts.emplace_back(p[0], p[1], p[2]);
    std::vector<std::vector<std::size_t>> polys;
    for (const auto& f : out_.faces) polys.push_back({f[0], f[1], f[2]});
    clear(out);
    CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(pts, polys, out);
  }

private:
  using clock = std::chrono::steady_clock;
  using State = internal::Remesh_state;

  /// §5.1: M_st, the image of the source's connectivity on the target, and its error; before that, the
  /// layout's splits that the smoothed map no longer needs are undone (with `undo`).
  void project(State& s, bool undo) {
    stats_.source_vertices = s.mesh.n_original_vertices;
    stats_.target_vertices = s.target.n_original_vertices;
    stats_.layout_vertices = s.mesh.m.number_of_vertices();
    s.measure();
    if (undo) {
      stats_.layout_splits_undone = internal::undo_layout_splits(s);
      if (stats_.layout_splits_undone > 0) {
        stats_.layout_vertices = s.mesh.m.number_of_vertices();
        s.measure();
      }
    }
    stats_.max_error_initial = 100 * s.max_e;
    stats_.l2_error_initial = 100 * s.l2_e;
    say("remesh: projected the source connectivity onto the target: max error " + fmt(100 * s.max_e) + "%, L2 " +
        fmt(100 * s.l2_e) + "% (tolerance " + fmt(stats_.tolerance) + "%), " + std::to_string(s.n_flipped) +
        " flipped faces, max chord " + fmt(100 * s.max_chord) + "%");
  }

  /// §5.2-5.3: adaptive smoothing while it lowers the error, edge splits when it stops doing so, and folds of
  /// M_st that the splits made removed by vertex moves. Refinement stops once three rounds in a row improve
  /// none of the figures the tolerance is about, or at four times the source's vertex count.
  template <class Weights, class Rule>
  void smooth_and_refine(State& s, Weights& weights, const Rule& rule, unsigned max_rounds) {
    weights.prepare(s.mesh.m);
    // A smoothing move must not fold M_st over against the target where it did not already.
    auto accept = [&s](internal::WV v, const Base_location& moved) { return s.accept_smoothing_move(v, moved); };
    internal::Local_smoother<Weights, decltype(accept)> smoother(s.param, weights, accept);
    Smoothing_report sr;
    double best_max = s.max_e, best_chord = s.max_chord, best_l2 = s.l2_e;
    std::size_t best_flipped = s.n_flipped;
    unsigned stale = 0;
    for (unsigned round = 0; round < max_rounds && !s.converged(); ++round) {
      if (s.budget.stop("the remeshing's smoothing and refinement", [&] {
            return "round " + std::to_string(round + 1) + " of at most " + std::to_string(max_rounds) + ", " +
                   std::to_string(s.mesh.m.number_of_vertices()) + " vertices";
          }))
        break; // best effort: keep the state reached
      const auto ts = clock::now();
      weights.update(s.mesh.m, s.edge_error);
      State::Locations before = s.locations();
      const double before_max = s.max_e, before_l2 = s.l2_e;
      for (int i = 0; i < 3; ++i) smoother.pass(sr);
      ++stats_.smoothing_rounds;
      s.measure();
      stats_.seconds_smoothing += sec(ts, clock::now());
      if (s.l2_e < 0.98 * before_l2 && s.max_e <= 1.05 * before_max) continue; // smoothing still helps
      if (s.l2_e > before_l2) { // it made things worse: undo the round
        s.restore(std::move(before));
        s.measure();
      }
      // Smoothing no longer lowers the error: refine.
      const auto tr = clock::now();
      const internal::Refinement_result refined = internal::refine(s, rule);
      stats_.refinement_splits += refined.splits;
      stats_.refinement_repairs_kept += refined.repairs_kept;
      stats_.refinement_repairs_undone += refined.repairs_undone;
      stats_.unfold_moves += internal::unfold(s);
      ++stats_.refinement_rounds;
      weights.prepare(s.mesh.m);
      s.measure();
      stats_.seconds_refinement += sec(tr, clock::now());
      say("remesh: round " + std::to_string(round + 1) + ": " + std::to_string(refined.splits) + " edge splits, " +
          std::to_string(s.mesh.m.number_of_vertices()) + " vertices, max error " + fmt(100 * s.max_e) + "%, L2 " +
          fmt(100 * s.l2_e) + "%, " + std::to_string(s.n_flipped) + " flipped, chord " + fmt(100 * s.max_chord) + "%");
      if (refined.splits == 0) break;
      const bool better = s.max_e < 0.99 * best_max || s.max_chord < 0.99 * best_chord || s.l2_e < 0.97 * best_l2 ||
                          s.n_flipped < best_flipped;
      best_max = std::min(best_max, s.max_e), best_chord = std::min(best_chord, s.max_chord);
      best_l2 = std::min(best_l2, s.l2_e), best_flipped = std::min(best_flipped, s.n_flipped);
      if ((stale = better ? 0 : stale + 1) == 3) {
        say("remesh: stopped refining: three rounds without progress");
        break;
      }
      if (s.mesh.m.number_of_vertices() > 4 * stats_.layout_vertices) {
        say("remesh: stopped refining at four times the source's vertex count");
        break;
      }
    }
  }

  /// §5.4: pseudo edge flips where faces deviate from the target's normal by more than `max_dev` degrees.
  void pseudo_flip(State& s, double max_dev) {
    const auto tf = clock::now();
    stats_.pseudo_flips = internal::pseudo_flips(s, std::cos(max_dev * CGAL_PI / 180.0));
    s.measure();
    say("remesh: " + std::to_string(stats_.pseudo_flips) + " pseudo edge flips, " + std::to_string(s.n_flipped) +
        " flipped faces, max chord " + fmt(100 * s.max_chord) + "%");
    stats_.seconds_flips = sec(tf, clock::now());
  }

  /// The last improving step (an addition to the paper): the two-sided distance between M_st and the target,
  /// sampled on both surfaces, brought within the tolerance by vertices added where a sample is too far
  /// (internal/remeshing/gap_refinement.h). At most 8 rounds, and not past four times the source's vertex
  /// count, the cap of the refinement.
  void close_gaps(State& s) {
    const auto tg = clock::now();
    const internal::Gap_snap_result g = internal::snap_surface_gaps(s, 8, 4 * stats_.layout_vertices);
    stats_.gap_vertices = g.vertices;
    stats_.gap_rounds = unsigned(g.rounds);
    stats_.gap_before = 100 * g.worst_before;
    stats_.gap_samples_left = g.left;
    stats_.seconds_gaps = sec(tg, clock::now());
    say("remesh: surface distance (sampled on both meshes): at most " + fmt(stats_.gap_before) + "% before; " +
        std::to_string(g.vertices) + " vertices added in " + std::to_string(g.rounds) + " rounds" +
        (g.left ? ", " + std::to_string(g.left) + " samples still beyond " +
                      fmt(internal::gap_sample_share * stats_.tolerance) + "%"
                : ", every sample within " + fmt(internal::gap_sample_share * stats_.tolerance) + "%"));
  }

  /// The last step (an addition to the paper): faces the verifier would reject (flipped by the standard
  /// rule, or intersecting other faces where the target does not intersect itself) refined in the target's
  /// metric and untangled (internal/remeshing/strict_repair.h). Not past four times the source's vertex count.
  void strict_repair(State& s) {
    const auto ts = clock::now();
    const internal::Strict_repair_result r = internal::strict_repair(s, 4 * stats_.layout_vertices);
    stats_.strict_flipped_before = r.flipped_before, stats_.strict_intersecting_before = r.intersecting_before;
    stats_.strict_flipped_after = r.flipped_after, stats_.strict_intersecting_after = r.intersecting_after;
    stats_.strict_splits = r.splits, stats_.strict_rounds = unsigned(r.rounds), stats_.strict_flips = r.flips;
    stats_.strict_disks = r.disks;
    stats_.strict_work_bound_reached = r.work_bound_reached;
    stats_.seconds_strict_repair = sec(ts, clock::now());
    say("remesh: strict repair: " + std::to_string(r.flipped_before) + " flipped and " +
        std::to_string(r.intersecting_before) + " intersecting faces before, " + std::to_string(r.flipped_after) +
        " and " + std::to_string(r.intersecting_after) + " after; " + std::to_string(r.flips) + " edge flips, " +
        std::to_string(r.disks) + " disks re-embedded, " + std::to_string(r.splits) + " vertices added in " +
        std::to_string(r.rounds) + " rounds" + (r.work_bound_reached ? " (stopped at its work bound)" : ""));
  }

  /// The decimated overlay (overlay()) in `o`, built on a fresh copy of the map's source; where it still fails
  /// the strict checks, a second one in `o2` whose flips make no sliver on the source
  /// (Remesh_state::refuse_source_slivers): a flip the exact test allows on rounding alone makes a face of no
  /// area there whose image's normal nothing controls, and a target vertex refused beside it leaves that face
  /// flipped. Refusing those flips everywhere would cost where nothing fails (the insertion splits instead:
  /// shrec/381_384's overlay grows from 261,000 to 684,000 vertices), so only a failed overlay is built again;
  /// the better of the two is kept. Returns the state whose result is kept: `refined` (the refinement's, unless
  /// `asked`) or one of the two overlays. `refined_pending`: the refinement's strict repair has not run yet, and
  /// its result counts as failing every check.
  State* overlay_construction(State& refined, const Cross_param& cp, std::optional<State>& o, std::optional<State>& o2,
                              double max_dev, bool asked, unsigned threads, bool refined_pending) {
    // Whether the overlay just decimated fails fewer strict checks than the refinement's result.
    auto beats_refined = [&] { return refined_pending || overlay_beats_refined(); };
    State* result = &refined;
    o.emplace(internal::map_view(cp), stats_.tolerance / 100.0, threads);
    o->budget = refined.budget;
    stats_.overlay_attempts = 1;
    const bool first_decimated = overlay(*o, max_dev, asked);
    if ((first_decimated && beats_refined()) || asked) result = &*o, stats_.overlay_used = true;
    if (!first_decimated || (overlay_bad() == 0 && stats_.overlay_gap_samples_left == 0) ||
        refined.budget.stop("the remeshing's second overlay", [] { return std::string("not started"); }))
      return result;
    const Remeshing_statistics first = stats_;
    const std::size_t bad_first = overlay_bad(), left_first = stats_.overlay_gap_samples_left;
    std::size_t cap = internal::overlay_second_growth * first.overlay_vertices;
    if (!asked) cap = std::min(cap, internal::overlay_max_growth * stats_.layout_vertices + 1);
    o2.emplace(internal::map_view(cp), stats_.tolerance / 100.0, threads);
    o2->budget = refined.budget;
    o2->refuse_source_slivers = true;
    say("remesh: the overlay fails the strict checks; again, with no flip that makes a sliver on the source");
    const bool second_decimated = overlay(*o2, max_dev, asked, cap);
    const bool better_than_first = second_decimated && (overlay_bad() < bad_first ||
                                   (overlay_bad() == bad_first && stats_.overlay_gap_samples_left < left_first));
    if (better_than_first && (beats_refined() || result == &*o)) {
      result = &*o2, stats_.overlay_used = true, stats_.overlay_refusing_slivers = true;
      o.reset();
    } else {
      stats_ = first;
    }
    stats_.overlay_attempts = 2;
    return result;
  }

  /// The overlay construction (an addition to the paper): the map's overlay with the target on a fresh copy of
  /// the source (internal/remeshing/overlay.h), decimated within the tolerance by collapses that keep the strict
  /// checks (internal/remeshing/overlay_decimation.h), then the strict repair for what the overlay could not
  /// make exact. Returns whether it was decimated; its strict figures are then in the statistics
  /// (overlay_bad(), overlay_beats_refined()). Unless `asked`, an overlay with more than
  /// overlay_max_growth times the source's vertices is not decimated, and the refinement's result is kept.
  /// `max_vertices`: where the overlay would have more vertices, it is abandoned (not decimated).
  bool overlay(State& o, double max_dev, bool asked, std::size_t max_vertices = std::size_t(-1)) {
    const auto ts = clock::now();
    o.measure();
    const std::size_t start = o.mesh.m.number_of_vertices();
    const internal::Overlay_result made =
        internal::Target_overlay(o).run(max_vertices > start ? max_vertices - start : 0);
    stats_.overlay_vertices = o.mesh.m.number_of_vertices();
    stats_.overlay_refused = made.refused;
    stats_.overlay_exact = made.exact;
    stats_.overlay_along_crossed = made.along_crossed;
    stats_.overlay_refused_points.clear();
    for (const Point_3& p : made.refused_at) stats_.overlay_refused_points.push_back(o.target.input_point(p));
    stats_.overlay_flips = made.flips + made.delaunay_flips;
    stats_.overlay_complete = made.complete;
    say("remesh: overlay: " + std::to_string(made.made.size()) + " vertices added (" + std::to_string(made.refused) +
        " refused, " + std::to_string(made.exact) + " at their own location, " + std::to_string(made.along_crossed) + " crossings nearly along), " + std::to_string(made.flips) + " edges flipped to insert target edges, " +
        std::to_string(made.delaunay_flips) + " Lawson flips" + (made.complete ? "" : ", incomplete") + " in " +
        fmt(sec(ts, clock::now())) + " s");
    if (o.mesh.m.number_of_vertices() >= max_vertices) {
      say("remesh: the overlay reached " + std::to_string(max_vertices) + " vertices; abandoned");
      stats_.seconds_overlay = sec(ts, clock::now());
      return false;
    }
    if (!asked && o.mesh.m.number_of_vertices() > internal::overlay_max_growth * stats_.layout_vertices) {
      say("remesh: the overlay has more than " + std::to_string(internal::overlay_max_growth) +
          " times the source's vertices; not decimated (--construction overlay would)");
      stats_.seconds_overlay = sec(ts, clock::now());
      return false;
    }
    const internal::Decimation_result d =
        internal::Overlay_decimator(o, max_dev, o.mesh.n_original_vertices).run();
    internal::compact(o);
    o.folded.assign(o.mesh.m.number_of_faces(), 0);
    o.measure();
    // Faces with no area on the source (Remesh_state::flip_zipper()): their edge flipped away where that keeps
    // the checks; until a pass flips none (each flip removes one and makes none). A zipper left then is flipped
    // away even where that folds one face of M_st (fold slack 1), for the strict repair below to mend (a fold it
    // cannot mend counts in the overlay's strict figures, as the verifier counts it): a face with no area on the
    // source has no normal there and no place in a common refinement with other remeshings (multi_remeshing.h),
    // while a folded face is what that repair is for.
    for (int slack : {0, 1}) {
      o.fold_slack = slack;
      for (std::size_t flipped_now = 1; flipped_now > 0;) {
        flipped_now = 0;
        for (internal::WF f : o.mesh.m.faces()) flipped_now += o.flip_zipper(f);
        stats_.overlay_zippers_flipped += flipped_now;
        if (slack > 0) stats_.overlay_zippers_folding += flipped_now;
      }
    }
    o.fold_slack = 0;
    // What the overlay could not make exact (a split refused by its exact test leaves a face across a target
    // edge) gets the strict repair, as the refinement's result does, but no repair that takes a face farther from
    // the target than the decimation's margin.
    const std::size_t repair_cap = 2 * o.mesh.m.number_of_vertices();
    auto repair = [&] { return internal::strict_repair(o, repair_cap, 8, internal::decimation_margin * o.eps); };
    internal::Strict_repair_result rep = repair();
    // The decimation certifies the distance of every face it makes; the faces the overlay made are within ε
    // where they lie in one target face, but not across a target vertex or edge it refused. The surface-distance
    // step samples both distances and adds vertices where a sample lies beyond 0.9 ε; what it adds gets the
    // strict repair again (its first pass finds nothing elsewhere to do).
    const auto tgap = clock::now();
    const internal::Gap_snap_result gaps = internal::snap_surface_gaps(o, 8, repair_cap);
    stats_.seconds_overlay_gaps = sec(tgap, clock::now());
    stats_.overlay_gap_vertices = gaps.vertices, stats_.overlay_gap_samples_left = gaps.left;
    if (gaps.vertices > 0) {
      const internal::Strict_repair_result again = repair();
      rep.flipped_after = again.flipped_after, rep.intersecting_after = again.intersecting_after;
      rep.splits += again.splits, rep.disks += again.disks;
    }
    const std::size_t flipped = rep.flipped_after, intersecting = rep.intersecting_after;
    stats_.overlay_collapses = d.collapses;
    stats_.overlay_work_bound_reached = d.work_bound_reached;
    stats_.overlay_needles_removed = d.needle_collapses, stats_.overlay_needles_left = d.needles_left;
    stats_.overlay_flipped = flipped, stats_.overlay_intersecting = intersecting;
    stats_.overlay_disks = rep.disks;
    stats_.seconds_overlay = sec(ts, clock::now());
    say("remesh: overlay decimated to " + std::to_string(o.mesh.m.number_of_vertices()) + " vertices (" +
        std::to_string(d.collapses) + " collapses of " + std::to_string(d.tried) + " tried; refused: " +
        std::to_string(d.refused_valence) + " valence, " + std::to_string(d.refused_link) + " link, " + std::to_string(d.refused_source) + " source, " +
        std::to_string(d.refused_needle) + " needle, " + std::to_string(d.refused_distance) + " distance, " +
        std::to_string(d.refused_normal) + " normal, " + std::to_string(d.refused_crease) + " crease, " + std::to_string(d.refused_coverage) + " coverage of the target, " +
        std::to_string(d.refused_intersection) + " intersection; " + std::to_string(d.face_pairs) + " face pairs tested" + (d.work_bound_reached ? ", stopped at its work bound" : "") + "; " +
        std::to_string(d.needles_found) + " needles, " + std::to_string(d.needle_collapses) + " collapsed by the needle removal, " +
        std::to_string(d.needles_left) + " left); " + std::to_string(stats_.overlay_zippers_flipped) +
        " faces with no area on the source flipped away (" + std::to_string(stats_.overlay_zippers_folding) +
        " folding a face for the strict repair); then " + std::to_string(rep.flipped_before) + " flipped and " +
        std::to_string(rep.intersecting_before) + " intersecting faces, " + std::to_string(flipped) + " and " +
        std::to_string(intersecting) + " after the strict repair (" + std::to_string(rep.splits) + " vertices added, " + std::to_string(rep.disks) +
        " disks re-embedded); surface distance: at most " + fmt(100 * gaps.worst_before) + "% sampled, " +
        std::to_string(gaps.vertices) + " vertices added in " + fmt(stats_.seconds_overlay_gaps) + " s" +
        (gaps.left ? ", " + std::to_string(gaps.left) + " samples still beyond 0.9 ε" : "") + "; " +
        fmt(stats_.seconds_overlay) + " s in all");
    return true;
  }

  /// Folds left (additions to the paper): untangled on the target, off F, which adds no vertex; where that
  /// leaves folds, the untangling is undone, the fold repair refines around those folds in the target's
  /// metric, and the untangling runs again.
  void untangle(State& s) {
    const auto tu = clock::now();
    internal::Target_untangler untangler(s);
    const State::Images before = s.images();
    record(s, untangler.run());
    if (s.n_flipped > 0 && !s.budget.stop("the remeshing's fold repair", [] { return std::string("not started"); })) {
      const std::vector<char> hard = s.corners_of_folded_faces();
      s.restore(before);
      const auto tr = clock::now();
      const internal::Fold_repair_result repaired = internal::repair_folds(s, &hard);
      stats_.fold_repair_splits = repaired.splits;
      stats_.fold_repairs_kept = repaired.kept;
      stats_.fold_repairs_undone = repaired.undone;
      s.measure();
      stats_.seconds_fold_repair = sec(tr, clock::now());
      say("remesh: fold repair: " + std::to_string(stats_.fold_repair_splits) + " splits (" +
          std::to_string(stats_.fold_repairs_kept) + " repairs kept, " + std::to_string(stats_.fold_repairs_undone) +
          " undone), " + std::to_string(s.n_flipped) + " flipped faces");
      record(s, untangler.run());
    }
    // Then the faces flipped by the standard rule (the centroid's nearest point alone), the verifier's, which the all-points
    // rule lets pass when one corner agrees: each untangling kept only where no face around a vertex it moved is
    // flipped by that rule, so no face is flipped by either rule that was not before.
    if (!s.budget.stop("the remeshing's untangling by the standard rule", [] { return std::string("not started"); })) {
      internal::Target_untangler standard(s, internal::Target_untangler::Rule::standard);
      const std::size_t verifier_before = untangler.count_flipped();
      const State::Images kept = s.images();
      internal::Untangle_result u = standard.run();
      const std::size_t verifier_after = untangler.count_flipped();
      // A guard (each kept untangling is checked around every vertex it moved, so this is not expected): a pass
      // that leaves more faces folded by the all-points rule than before is undone whole.
      if (verifier_after > verifier_before) s.restore(kept), u = internal::Untangle_result();
      untangler.mark_flipped();
      stats_.standard_flips_untangled = u.folds_removed;
      stats_.standard_flips_left = standard.count_flipped();
      stats_.standard_untangle_moves = u.moves;
      stats_.standard_untangle_max_move = u.max_move;
      stats_.untangle_folds_not_tried += u.folds_not_tried;
      say("remesh: untangling by the standard flip rule: " + std::to_string(u.folds_removed) + " removed, " +
          std::to_string(stats_.standard_flips_left) + " left" +
          not_tried(u));
    }
    stats_.seconds_untangle = sec(tu, clock::now()) - stats_.seconds_fold_repair;
  }
  /// What the progress line says of the folds an untangling pass left at its work bound.
  static std::string not_tried(const internal::Untangle_result& u) {
    return u.folds_not_tried ? " (" + std::to_string(u.folds_not_tried) + " not tried: the step's work bound)" : "";
  }
  void record(const State& s, const internal::Untangle_result& u) {
    stats_.untangle_folds_not_tried += u.folds_not_tried;
    stats_.untangled_folds = u.folds_removed;
    stats_.untangle_moves = u.moves;
    stats_.untangle_max_move = u.max_move;
    if (stats_.untangled_folds + s.n_flipped > 0)
      say("remesh: untangling: " + std::to_string(stats_.untangled_folds) + " folds removed, " +
          std::to_string(stats_.untangle_moves) + " vertices moved along the target (at most " +
          fmt(stats_.untangle_max_move) + "%), " + std::to_string(s.n_flipped) + " flipped faces" +
          not_tried(u));
  }

  /// The parameterization of the remeshed source must still be one-to-one.
  void certify(const State& s) {
    const auto tc = clock::now();
    cert_ = s.param.certify();
    if (!cert_.valid) throw Algorithm_error("remeshed source parameterization failed its certificate: " + cert_.message);
    stats_.seconds_certificate = sec(tc, clock::now());
  }

  /// The output meshes and the final figures.
  void finish(const State& s, double seconds_cross_parameterization, clock::time_point t0) {
    out_ = s.outputs();
    stats_.flipped_faces = s.n_flipped;
    stats_.max_error = 100 * s.max_e;
    stats_.l2_error = 100 * s.l2_e;
    stats_.max_chord_error = 100 * s.max_chord;
    stats_.psnr = s.l2_e > 0 ? 20 * std::log10(1.0 / s.l2_e) : HUGE_VAL;
    stats_.converged = s.converged();
    stats_.output_vertices = s.mesh.m.number_of_vertices();
    stats_.output_faces = s.mesh.m.number_of_faces();
    stats_.seconds_cross_parameterization = seconds_cross_parameterization;
    stats_.seconds_total = sec(t0, clock::now());
    say("remesh: " + std::to_string(stats_.output_vertices) + " vertices (source " +
        std::to_string(stats_.source_vertices) + "), max error " + fmt(stats_.max_error) + "%, L2 " +
        fmt(stats_.l2_error) + "%, PSNR " + fmt(stats_.psnr) + (stats_.converged ? "" : " (the e(v) bound not met everywhere; the verification decides)"));
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

  std::function<void(const std::string&)> progress_;
  internal::Remesh_outputs out_;
  Bijectivity_certificate cert_;
  Remeshing_statistics stats_;
  /// The last decimated overlay's faces flipped and in new self-intersecting pairs after its strict repair.
  std::size_t overlay_bad() const { return stats_.overlay_flipped + stats_.overlay_intersecting; }
  /// Whether the last decimated overlay fails fewer strict checks than the refinement's result after its strict
  /// repair: fewer flipped and intersecting faces, or as many and fewer samples left beyond 0.9 ε (the overlay
  /// is certified within 0.9 ε everywhere).
  bool overlay_beats_refined() const {
    const std::size_t refined = stats_.strict_flipped_after + stats_.strict_intersecting_after;
    return overlay_bad() < refined || (overlay_bad() == refined && stats_.overlay_gap_samples_left < stats_.gap_samples_left);
  }
};

/// \brief One-shot compatible remeshing: cross-parameterizes `source` and `target` (§3-4; the meshes are
/// refined in place as by `Cross_parameterization`), remeshes (§5), and writes the source-shaped and the
/// target-shaped results into `out_source` and `out_target` (any MutableFaceGraph; same face order, same
/// vertex order). `np` carries the named parameters of both stages.
template <class SourceMesh, class TargetMesh, class OutputMesh, typename NP = CGAL::parameters::Default_named_parameters>
Remeshing_statistics compatible_remesh(SourceMesh& source, TargetMesh& target, const Feature_correspondence& features,
                                       OutputMesh& out_source, OutputMesh& out_target,
                                       const NP& np = CGAL::parameters::default_values()) {
  Cross_parameterization<SourceMesh, TargetMesh> cp(source, target, features, np);
  Compatible_remesher<SourceMesh, TargetMesh> r(cp, np);
  r.copy_to(Mesh_side::source, out_source);
  r.copy_to(Mesh_side::target, out_target);
  return r.statistics();
}

} // namespace crossparam

#endif // CROSSPARAM_COMPATIBLE_REMESHING_H

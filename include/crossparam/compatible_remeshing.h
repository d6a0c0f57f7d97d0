// SPDX-License-Identifier: GPL-3.0-or-later
// Compatible remeshing (Kraevoy & Sheffer 2004, §5): two meshes with the connectivity of the (refined) source,
// one reproducing the source exactly, the other approximating the target within a user tolerance.
//
// The source connectivity is carried onto the target by the cross-parameterization F (the mesh M_st). Then,
// in a loop: the approximation error e(v) at the target vertices (Eq. 1), Gaussian-smoothed; adaptive smoothing
// of the source's parameterization with error-driven edge weights (Eq. 2) through the same Local_smoother as
// §4.2; refinement where the error stays high once smoothing stops helping (§5.3: edge splits, plus insertion of
// the preimages of the worst target vertices), with folds of M_st removed by vertex moves; finally "pseudo" edge flips
// (§5.4): edges whose flip would bring the faces' normals closer to the target's are split at the crossing of
// the two diagonals instead. Splits are applied to the source mesh and M_st together (they share connectivity);
// a new vertex lies on a source edge or inside a source face, and its image is F of it, on the target. No vertex is removed and no edge
// is flipped, so the source geometry is kept exactly, and every step keeps the parameterization one-to-one
// (exact orientation tests), which is certified again at the end. Folds of M_st left after the pseudo flips
// are untangled along the target (internal/untangle.h), with a fold repair by splits first where that alone
// fails: there, and only there, a vertex of the target-shaped mesh is not F of its source vertex.
#ifndef CROSSPARAM_COMPATIBLE_REMESHING_H
#define CROSSPARAM_COMPATIBLE_REMESHING_H

#include <crossparam/cross_parameterization.h>
#include <crossparam/internal/disk_chart.h>
#include <crossparam/internal/parallel.h>
#include <crossparam/internal/untangle.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <functional>
#include <map>
#include <set>

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

  void prepare(const internal::Work_mesh& m) {
    if (shape_) mv_.prepare(m);
    w_.resize(m.number_of_edges(), -1.0);
  }
  void update(const internal::Work_mesh& m, const std::vector<double>& e) {
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
  double operator()(internal::WH h) const {
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
  std::size_t unfold_moves = 0;      ///< vertex moves that removed folds of the target-shaped mesh
  std::size_t refinement_repairs_kept = 0; ///< refused chord splits made with a local fold repair (§5.3)
  std::size_t refinement_repairs_undone = 0; ///< such splits undone, or refused even with one fold of slack
  std::size_t fold_repair_splits = 0; ///< splits kept by the fold repair (after §5.4)
  std::size_t fold_repairs_kept = 0, fold_repairs_undone = 0; ///< fold-repair attempts kept and undone
  std::size_t untangled_folds = 0;   ///< folded faces that the untangling on the target removed
  std::size_t untangle_moves = 0;    ///< vertices of the target-shaped mesh it moved (off F, along the target)
  double untangle_max_move = 0;      ///< the farthest such move, percent of the target's bounding-box diagonal
  unsigned smoothing_rounds = 0, refinement_rounds = 0;
  double tolerance = 0;              ///< ε, percent
  double max_error_initial = 0, l2_error_initial = 0; ///< e(v) of M_st right after the projection
  double max_error = 0, l2_error = 0; ///< e(v) of the result (max and root mean square over target vertices)
  double max_chord_error = 0;        ///< largest distance of an output edge midpoint or face centroid from the
                                     ///< image of the same source point on the target
  double psnr = 0;                   ///< 20 log10(diagonal / L2 error), as the paper's Table 2
  std::size_t flipped_faces = 0;     ///< output faces whose normal opposes the target's where they land
  bool converged = false;            ///< max error and max chord error <= tolerance, and no flipped face
  double seconds_cross_parameterization = 0, seconds_smoothing = 0, seconds_refinement = 0, seconds_flips = 0,
         seconds_fold_repair = 0, seconds_untangle = 0, seconds_certificate = 0, seconds_total = 0;
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
/// `number_of_threads` (default 0: one per hardware thread; the results do not depend on it).
template <class SourceMesh, class TargetMesh>
class Compatible_remesher {
public:
  using Cross_param = Cross_parameterization<SourceMesh, TargetMesh>;

  template <typename NP = CGAL::parameters::Default_named_parameters>
  explicit Compatible_remesher(const Cross_param& cp, const NP& np = CGAL::parameters::default_values())
      : cp_(cp), T_(cp.work().side[1]), PT_(cp.parameterization(1)), locT_(cp.locator(1)) {
    using CGAL::parameters::choose_parameter;
    using CGAL::parameters::get_parameter;
    const auto t0 = clock::now();
    S_ = cp.work().side[0];
    P_ = cp.parameterization(0);
    P_.mesh = &S_;
    stats_.source_vertices = S_.n_original_vertices;
    stats_.target_vertices = T_.n_original_vertices;
    stats_.layout_vertices = S_.m.number_of_vertices();
    stats_.tolerance = choose_parameter(get_parameter(np, internal_np::tolerance_t()), 0.5);
    if (!(stats_.tolerance > 0) || !std::isfinite(stats_.tolerance))
      throw Input_error("remeshing tolerance must be a positive number of percent");
    const double max_dev = choose_parameter(get_parameter(np, internal_np::normal_deviation_t()), 30.0);
    const unsigned max_rounds = choose_parameter(get_parameter(np, internal_np::max_rounds_t()), 30u);
    progress_ = choose_parameter(get_parameter(np, internal_np::progress_t()), std::function<void(const std::string&)>());
    threads_ = internal::thread_count(choose_parameter(get_parameter(np, internal_np::number_of_threads_t()), 0u));
    auto weights = choose_parameter(get_parameter(np, internal_np::remeshing_weights_t()), Error_driven_weights());
    const auto rule = choose_parameter(get_parameter(np, internal_np::refinement_rule_t()), Half_max_refinement());
    // Working coordinates have a unit bounding-box diagonal: ε in percent is ε / 100 there.
    eps_ = stats_.tolerance / 100.0;

    measure();
    if (choose_parameter(get_parameter(np, internal_np::undo_layout_splits_t()), true) && undo_layout_splits() > 0)
      measure();
    stats_.max_error_initial = 100 * max_e_;
    stats_.l2_error_initial = 100 * l2_e_;
    say("remesh: projected the source connectivity onto the target: max error " + fmt(100 * max_e_) + "%, L2 " +
        fmt(100 * l2_e_) + "% (tolerance " + fmt(stats_.tolerance) + "%), " + std::to_string(flipped_) + " flipped faces, max chord " + fmt(100 * max_chord_) + "%");

    // §5.2-5.3: adaptive smoothing while it lowers the error, edge splits when it stops doing so.
    weights.prepare(S_.m);
    // A smoothing move must not fold M_st over against the target where it did not already.
    auto accept = [this](internal::WV v, const Base_location& moved) {
      const internal::Work_location lv = locT_.locate(moved);
      const Point_3 pv = target_point(lv);
      const auto& m = S_.m;
      for (internal::WH h : CGAL::halfedges_around_target(m.halfedge(v), m)) {
        if (m.is_border(h)) continue;
        internal::WV a = m.target(m.next(h)), b = m.target(m.next(m.next(h)));
        if (!flipped(pos_[v], img_[v].face, pos_[a], img_[a].face, pos_[b], img_[b].face) &&
            flipped(pv, lv.face, pos_[a], img_[a].face, pos_[b], img_[b].face))
          return false;
      }
      img_[v] = lv; // the move is accepted: keep M_st current for the next vertices
      pos_[v] = pv;
      return true;
    };
    internal::Local_smoother<decltype(weights), decltype(accept)> smoother(P_, weights, accept);
    Smoothing_report sr;
    // Refinement stops once three rounds in a row improve none of the figures the tolerance is about.
    double best_max = max_e_, best_chord = max_chord_, best_l2 = l2_e_;
    std::size_t best_flipped = flipped_;
    unsigned stale = 0;
    for (unsigned round = 0; round < max_rounds && !converged(); ++round) {
      const auto ts = clock::now();
      weights.update(S_.m, edge_error_);
      const std::vector<Base_location> before = P_.loc;
      Measure_cache measured_before = cache_;
      const double before_max = max_e_, before_l2 = l2_e_;
      for (int i = 0; i < 3; ++i) smoother.pass(sr);
      ++stats_.smoothing_rounds;
      measure();
      stats_.seconds_smoothing += sec(ts, clock::now());
      if (l2_e_ < 0.98 * before_l2 && max_e_ <= 1.05 * before_max) continue; // smoothing still helps
      if (l2_e_ > before_l2) { // it made things worse: undo the round
        P_.loc = before;
        cache_ = std::move(measured_before);
        measure();
      }
      // Smoothing no longer lowers the error: refine.
      const auto tr = clock::now();
      const std::size_t n = refine(rule);
      stats_.unfold_moves += unfold();
      ++stats_.refinement_rounds;
      weights.prepare(S_.m);
      measure();
      stats_.seconds_refinement += sec(tr, clock::now());
      say("remesh: round " + std::to_string(round + 1) + ": " + std::to_string(n) + " edge splits, " +
          std::to_string(S_.m.number_of_vertices()) + " vertices, max error " + fmt(100 * max_e_) + "%, L2 " +
          fmt(100 * l2_e_) + "%, " + std::to_string(flipped_) + " flipped, chord " + fmt(100 * max_chord_) + "%");
      if (n == 0) break;
      const bool better = max_e_ < 0.99 * best_max || max_chord_ < 0.99 * best_chord || l2_e_ < 0.97 * best_l2 ||
                          flipped_ < best_flipped;
      best_max = std::min(best_max, max_e_), best_chord = std::min(best_chord, max_chord_);
      best_l2 = std::min(best_l2, l2_e_), best_flipped = std::min(best_flipped, flipped_);
      if ((stale = better ? 0 : stale + 1) == 3) {
        say("remesh: stopped refining: three rounds without progress");
        break;
      }
      if (S_.m.number_of_vertices() > 4 * stats_.layout_vertices) {
        say("remesh: stopped refining at four times the source's vertex count");
        break;
      }
    }

    // §5.4: pseudo edge flips.
    const auto tf = clock::now();
    if (max_dev < 180) {
      stats_.pseudo_flips = pseudo_flips(std::cos(max_dev * CGAL_PI / 180.0));
      measure();
      say("remesh: " + std::to_string(stats_.pseudo_flips) + " pseudo edge flips, " + std::to_string(flipped_) + " flipped faces, max chord " + fmt(100 * max_chord_) + "%");
    }
    stats_.seconds_flips = sec(tf, clock::now());

    // Folds left (additions to the paper): untangled on the target, off F, which adds no vertex; where that
    // leaves folds, the untangling is undone, the fold repair refines around those folds in the target's
    // metric, and the untangling runs again.
    const auto tu = clock::now();
    auto say_untangled = [&] {
      if (stats_.untangled_folds + flipped_ > 0)
        say("remesh: untangling: " + std::to_string(stats_.untangled_folds) + " folds removed, " +
            std::to_string(stats_.untangle_moves) + " vertices moved along the target (at most " +
            fmt(stats_.untangle_max_move) + "%), " + std::to_string(flipped_) + " flipped faces");
    };
    Target_tree tree(CGAL::faces(T_.m).first, CGAL::faces(T_.m).second, T_.m);
    tree.accelerate_distance_queries();
    const std::vector<internal::Work_location> img_before = img_;
    const std::vector<Point_3> pos_before = pos_;
    const std::vector<char> folded_before = folded_;
    const std::size_t flipped_before = flipped_;
    untangle_folds(tree);
    say_untangled();
    if (flipped_ > 0) {
      const auto& m = S_.m;
      std::vector<char> hard(m.number_of_vertices(), 0);
      for (internal::WF f : m.faces())
        if (folded_[f])
          for (internal::WV v : CGAL::vertices_around_face(m.halfedge(f), m)) hard[v] = 1;
      img_ = img_before, pos_ = pos_before, folded_ = folded_before, flipped_ = flipped_before;
      stats_.untangled_folds = stats_.untangle_moves = 0, stats_.untangle_max_move = 0;
      const auto tr = clock::now();
      repair_folds(&hard);
      measure();
      stats_.seconds_fold_repair = sec(tr, clock::now());
      say("remesh: fold repair: " + std::to_string(stats_.fold_repair_splits) + " splits (" +
          std::to_string(stats_.fold_repairs_kept) + " repairs kept, " + std::to_string(stats_.fold_repairs_undone) +
          " undone), " + std::to_string(flipped_) + " flipped faces");
      untangle_folds(tree);
      say_untangled();
    }
    stats_.seconds_untangle = sec(tu, clock::now()) - stats_.seconds_fold_repair;

    // The parameterization of the remeshed source must still be one-to-one.
    const auto tc = clock::now();
    cert_ = P_.certify();
    if (!cert_.valid) throw Algorithm_error("remeshed source parameterization failed its certificate: " + cert_.message);
    stats_.seconds_certificate = sec(tc, clock::now());

    build_outputs();
    stats_.max_error = 100 * max_e_;
    stats_.l2_error = 100 * l2_e_;
    stats_.max_chord_error = 100 * max_chord_;
    stats_.psnr = l2_e_ > 0 ? 20 * std::log10(1.0 / l2_e_) : HUGE_VAL;
    stats_.converged = converged();
    stats_.output_vertices = S_.m.number_of_vertices();
    stats_.output_faces = S_.m.number_of_faces();
    stats_.seconds_cross_parameterization = cp.statistics().seconds_total;
    stats_.seconds_total = sec(t0, clock::now());
    say("remesh: " + std::to_string(stats_.output_vertices) + " vertices (source " +
        std::to_string(stats_.source_vertices) + "), max error " + fmt(stats_.max_error) + "%, L2 " +
        fmt(stats_.l2_error) + "%, PSNR " + fmt(stats_.psnr) + (stats_.converged ? "" : " (tolerance not reached)"));
  }

  /// The common face list (indices into both point lists), oriented as the input source.
  const std::vector<std::array<std::size_t, 3>>& faces() const { return faces_; }
  /// The source-shaped mesh's points, input coordinates; the first `statistics().source_vertices` are the
  /// input source's vertices exactly.
  const std::vector<std::array<double, 3>>& source_points() const { return src_pts_; }
  /// The target-shaped mesh's points (on the target), input coordinates.
  const std::vector<std::array<double, 3>>& target_points() const { return tgt_pts_; }
  /// Approximation error at each output vertex (percent of the target's diagonal): the smoothed e(v) field of
  /// the target read where the vertex lands (§5.1), for pictures.
  const std::vector<double>& vertex_error() const { return verr_; }
  /// Where each output vertex lands on the target, against the target as given.
  const std::vector<Input_location>& target_locations() const { return tgt_loc_; }
  const Remeshing_statistics& statistics() const { return stats_; }
  const Bijectivity_certificate& certificate() const { return cert_; }

  /// Copies the source-shaped (side 0) or target-shaped (side 1) result into `out`, any MutableFaceGraph.
  template <class OutputMesh>
  void copy_to(int side, OutputMesh& out) const {
    using P3 = typename boost::property_traits<
        typename boost::property_map<OutputMesh, CGAL::vertex_point_t>::type>::value_type;
    std::vector<P3> pts;
    for (const auto& p : side == 0 ? src_pts_ : tgt_pts_) pts.emplace_back(p[0], p[1], p[2]);
    std::vector<std::vector<std::size_t>> polys;
    for (const auto& f : faces_) polys.push_back({f[0], f[1], f[2]});
    clear(out);
    CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(pts, polys, out);
  }

private:
  using clock = std::chrono::steady_clock;
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
  bool converged() const { return max_e_ <= eps_ && max_chord_ <= eps_ && flipped_ == 0; }

  Point_3 target_point(const internal::Work_location& l) const { return internal::point_at(T_.m, l); }
  Kernel::Vector_3 target_normal(internal::WF f) const {
    const auto& m = T_.m;
    internal::WH h = m.halfedge(f);
    return internal::triangle_normal(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))));
  }
  /// Whether triangle (a, b, c) of M_st, its corners on target faces fa, fb, fc, is flipped: its normal opposes
  /// the target's at every corner (a face across a sharp crease agrees with one side of it: a chord). During
  /// the fold repair (`repairing_`), a corner on an edge or at a vertex of the target counts as opposing if any
  /// target face through it does, as an independent check with closest points may pick any of them.
  bool flipped(const Point_3& a, internal::WF fa, const Point_3& b, internal::WF fb, const Point_3& c,
               internal::WF fc) const {
    const Kernel::Vector_3 n = internal::triangle_normal(a, b, c);
    if (repairing_) return opposes(n, a, fa) && opposes(n, b, fb) && opposes(n, c, fc);
    return n * target_normal(fa) < 0 && n * target_normal(fb) < 0 && n * target_normal(fc) < 0;
  }
  /// Whether normal n opposes the target's normal at point p of target face f, or at another target face
  /// that p lies on (p at a corner or on an edge of f, to within 1e-9 of the unit diagonal).
  bool opposes(const Kernel::Vector_3& n, const Point_3& p, internal::WF f) const {
    if (n * target_normal(f) < 0) return true;
    const auto& m = T_.m;
    constexpr double tol2 = 1e-18;
    for (internal::WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
      const Point_3& q = m.point(m.target(h));
      if (CGAL::squared_distance(p, q) < tol2) {
        for (internal::WF g : CGAL::faces_around_target(h, m))
          if (g != internal::WF() && n * target_normal(g) < 0) return true;
        continue;
      }
      const internal::WH o = m.opposite(h);
      if (!m.is_border(o) && n * target_normal(m.face(o)) < 0 &&
          CGAL::squared_distance(p, Kernel::Segment_3(m.point(m.source(h)), q)) < tol2)
        return true;
    }
    return false;
  }
  bool face_folded(internal::WF f) const {
    const auto& m = S_.m;
    const internal::WH h = m.halfedge(f);
    const internal::WV x = m.source(h), y = m.target(h), z = m.target(m.next(h));
    return flipped(pos_[x], img_[x].face, pos_[y], img_[y].face, pos_[z], img_[z].face);
  }
  double target_field(const std::vector<double>& f, const internal::Work_location& l) const {
    const auto& m = T_.m;
    internal::WH h = m.halfedge(l.face);
    return l.b[0] * f[m.source(h)] + l.b[1] * f[m.target(h)] + l.b[2] * f[m.target(m.next(h))];
  }

  /// A corner of a planned face: base location, image on the target and its point.
  struct Corner {
    Base_location loc;
    internal::Work_location img;
    Point_3 pos;
  };
  /// Images of the source vertices (M_st), e(v) at the target vertices (Eq. 1) and its smoothed field, the
  /// error of every source edge (Eq. 2) and the global figures.
  void measure() {
    const auto& ms = S_.m;
    if (ms.has_garbage()) throw Algorithm_error("internal error: measure() on a mesh with removed elements");
    // Locating on the target is most of the cost; what the last measure() located for the same base locations
    // (vertices, and edges and faces whose corners and their locations are unchanged) is reused. Every element
    // is computed on its own (in parallel with `threads_`), the sums and maxima afterwards in index order, so
    // the figures do not depend on the number of threads.
    Measure_cache& mc = cache_;
    const std::size_t nv = ms.number_of_vertices();
    img_.resize(nv);
    pos_.resize(nv);
    mc.vertex.resize(nv);
    mc.same.assign(nv, 0);
    internal::parallel_for(nv, threads_, [&](std::size_t i) {
      const internal::WV v{internal::WV::size_type(i)};
      if (i < mc.valid && same_location(mc.vertex[v].loc, P_[v])) {
        mc.same[v] = 1;
        if (check_due(i)) check_reused(mc.vertex[v]);
      } else {
        mc.vertex[v] = corner_at(P_[v]);
      }
      img_[v] = mc.vertex[v].img;
      pos_[v] = mc.vertex[v].pos;
    });
    mc.valid = nv;
    // A face is unchanged if it has the same corners, in the same order, at unchanged locations.
    const std::size_t nf = ms.number_of_faces();
    mc.corners.resize(nf);
    mc.face_same.assign(nf, 0);
    for (internal::WF f : ms.faces()) {
      const internal::WH h = ms.halfedge(f);
      const std::array<internal::WV, 3> c{ms.source(h), ms.target(h), ms.target(ms.next(h))};
      mc.face_same[f] = std::size_t(f) < mc.valid_faces && c == mc.corners[f] && mc.same[c[0]] && mc.same[c[1]] && mc.same[c[2]];
      mc.corners[f] = c;
    }
    // e(v) = |F' F^-1 (v) - v|: the preimage of target vertex v on the source, carried to M_st linearly.
    locS_.build(P_);
    const auto& mt = T_.m;
    std::vector<double>& e = e_;
    e.assign(mt.number_of_vertices(), 0.0);
    pre_.resize(mt.number_of_vertices());
    internal::parallel_for(mt.number_of_vertices(), threads_, [&](std::size_t i) {
      const internal::WV v{internal::WV::size_type(i)};
      const internal::Work_location& l = pre_[v] = locS_.locate(PT_[v]);
      internal::WH h = ms.halfedge(l.face);
      const Point_3 &a = pos_[ms.source(h)], &b = pos_[ms.target(h)], &c = pos_[ms.target(ms.next(h))];
      const Point_3 q = internal::barycentric_point(a, b, c, l.b);
      e[v] = std::sqrt(CGAL::squared_distance(q, mt.point(v)));
    });
    max_e_ = 0;
    double sum2 = 0;
    for (internal::WV v : mt.vertices()) {
      max_e_ = std::max(max_e_, e[v]);
      sum2 += e[v] * e[v];
    }
    l2_e_ = std::sqrt(sum2 / double(std::max<std::size_t>(1, mt.number_of_vertices())));
    // Gaussian smoothing: each vertex averaged with its neighbours.
    es_.assign(mt.number_of_vertices(), 0.0);
    for (internal::WV v : mt.vertices()) {
      double s = e[v], n = 1;
      for (internal::WV w : CGAL::vertices_around_target(mt.halfedge(v), mt)) s += e[w], n += 1;
      es_[v] = s / n;
    }
    // Eq. 2 per source edge, with the chord deviation of M_st's edge from the target at the midpoint (the
    // other side of the Hausdorff distance, which e(v) at target vertices alone does not see).
    const std::size_t ne = ms.number_of_edges();
    edge_error_.assign(ne, 0.0);
    edge_chord_.assign(ne, 0.0);
    mc.edge.resize(ne);
    mc.mid.resize(ne);
    internal::parallel_for(ne, threads_, [&](std::size_t i) {
      const internal::WE ed{internal::WE::size_type(i)};
      internal::WH h = ms.halfedge(ed);
      internal::WV u = ms.source(h), v = ms.target(h);
      // P_.between() interpolates in the face of h: the same face unchanged gives the same point.
      const std::array<std::size_t, 3> key{std::size_t(u), std::size_t(v), std::size_t(ms.face(h))};
      if (!(i < mc.valid_edges && mc.edge[ed] == key && mc.face_same[ms.face(h)])) {
        mc.edge[ed] = key;
        mc.mid[ed] = corner_at(P_.between(u, v, 0.5));
      } else if (check_due(i + 1)) {
        check_reused(mc.mid[ed]);
      }
      const internal::Work_location& lm = mc.mid[ed].img;
      const double chord = std::sqrt(CGAL::squared_distance(CGAL::midpoint(pos_[u], pos_[v]), mc.mid[ed].pos));
      edge_chord_[ed] = chord;
      const double eu = target_field(es_, img_[u]), ev = target_field(es_, img_[v]);
      const double em = std::max(target_field(es_, lm), chord);
      edge_error_[ed] = 0.5 * (0.5 * (eu + ev) + em);
    });
    max_chord_ = 0;
    for (double c : edge_chord_) max_chord_ = std::max(max_chord_, c);
    // Per face of M_st: the chord deviation at the centroid (reported), and whether the face is flipped: its
    // normal opposes the target's under each corner and under the centroid.
    face_chord_.assign(nf, 0.0);
    mc.centroid.resize(nf);
    folded_.assign(nf, 0);
    internal::parallel_for(nf, threads_, [&](std::size_t i) {
      const internal::WF f{internal::WF::size_type(i)};
      internal::WH h = ms.halfedge(f);
      const internal::WV x = ms.source(h), y = ms.target(h), z = ms.target(ms.next(h));
      const Point_3 &a = pos_[x], &b = pos_[y], &c = pos_[z];
      if (!mc.face_same[f]) {
        mc.centroid[f] = corner_at(P_.at(f, {1.0 / 3, 1.0 / 3, 1.0 / 3}));
      } else if (check_due(i + 2)) {
        check_reused(mc.centroid[f]);
      }
      face_chord_[f] = std::sqrt(CGAL::squared_distance(CGAL::centroid(a, b, c), mc.centroid[f].pos));
      folded_[i] = flipped(a, img_[x].face, b, img_[y].face, c, img_[z].face) &&
                  internal::triangle_normal(a, b, c) * target_normal(mc.centroid[f].img.face) < 0;
    });
    flipped_ = 0;
    for (std::size_t i = 0; i < nf; ++i) {
      max_chord_ = std::max(max_chord_, face_chord_[i]);
      flipped_ += folded_[i];
    }
    mc.valid_edges = ne;
    mc.valid_faces = nf;
  }
  static bool same_location(const Base_location& a, const Base_location& b) { return a.tri == b.tri && a.b == b.b; }
  /// With assertions on (the tests' builds), the reused locations of one index in 61 are located afresh and
  /// must agree exactly: the reuse in measure() must never change a figure.
  static bool check_due(std::size_t index) {
#ifndef NDEBUG
    return index % 61 == 0;
#else
    (void)index;
    return false;
#endif
  }
  /// `kept` must be what corner_at() gives for its base location now.
  void check_reused(const Corner& kept) const {
    const internal::Work_location fresh = locT_.locate(kept.loc);
    if (fresh.face != kept.img.face || fresh.b != kept.img.b)
      throw Algorithm_error("internal error: measure() reused a stale location on the target");
  }

  Corner corner(internal::WV v) const { return {P_[v], img_[v], pos_[v]}; }
  Corner corner_at(const Base_location& w) const {
    const internal::Work_location l = locT_.locate(w);
    return {w, l, target_point(l)};
  }
  using Face_plan = std::array<const Corner*, 3>;
  /// Whether replacing faces `before` by `after` keeps the parameterization one-to-one (every new face
  /// positively oriented over the base mesh, exact test) and folds no more faces of M_st against the target
  /// (at most `fold_slack_` more, during the fold repair). Leaves the change in folded faces in `fold_change_`.
  template <std::size_t N, std::size_t M>
  bool acceptable(const std::array<Face_plan, N>& before, const std::array<Face_plan, M>& after) const {
    const internal::Base_mesh& B = *P_.base;
    for (const Face_plan& f : after)
      if (B.triangle_orientation(f[0]->loc, f[1]->loc, f[2]->loc) != CGAL::POSITIVE) return false;
    auto folds = [&](const Face_plan& f) {
      return int(flipped(f[0]->pos, f[0]->img.face, f[1]->pos, f[1]->img.face, f[2]->pos, f[2]->img.face));
    };
    int nb = 0, na = 0;
    for (const Face_plan& f : before) nb += folds(f);
    for (const Face_plan& f : after) na += folds(f);
    fold_change_ = na - nb;
    return na <= nb + fold_slack_;
  }
  /// Adds the new vertex of a split (the mesh already split) with its planned corner.
  void commit(internal::WV nw, const Corner& c) {
    if (std::size_t(nw) != P_.loc.size()) throw Algorithm_error("internal error: split vertex out of order");
    P_.loc.push_back(c.loc);
    img_.push_back(c.img);
    pos_.push_back(c.pos);
  }
  /// Marks the faces next to edge (u, v) as changed in this round.
  void touch(internal::WV u, internal::WV v) {
    const auto& m = S_.m;
    internal::WH h = m.halfedge(u, v);
    for (internal::WH g : {h, m.opposite(h)})
      if (std::size_t(m.face(g)) < dirty_.size()) dirty_[m.face(g)] = 1;
  }
  bool is_dirty(internal::WF f) const { return std::size_t(f) >= dirty_.size() || dirty_[f]; }

  /// Splits edge (u, v) of the source at parameter t, on the source and in its parameterization, if the four
  /// new faces stay positively oriented over the base mesh (exact test) and M_st gains no fold. Returns
  /// whether it split.
  bool split(internal::WV u, internal::WV v, double t) {
    const auto& m = S_.m;
    internal::WH h = m.halfedge(u, v);
    const internal::WV x = m.target(m.next(h)), y = m.target(m.next(m.opposite(h)));
    const Corner cu = corner(u), cv = corner(v), cx = corner(x), cy = corner(y), cw = corner_at(P_.between(u, v, t));
    if (!acceptable(std::array<Face_plan, 2>{{{&cu, &cv, &cx}, {&cv, &cu, &cy}}},
                    std::array<Face_plan, 4>{{{&cu, &cw, &cx}, {&cw, &cv, &cx}, {&cv, &cw, &cy}, {&cw, &cu, &cy}}}))
      return false;
    touch(u, v);
    const internal::WV w = S_.split_edge(u, v, t);
    commit(w, cw);
    if (repairing_) fold_total_ += fold_change_, made_.push_back(w);
    return true;
  }

  /// Inserts a vertex at the point of source face f with barycentrics b (in f's halfedge order) by two edge
  /// splits: edge (a, c) opposite corner k at the point s where the line from that corner through the point
  /// meets it, then edge (k, s) at the point. The new vertices lie in the source face, so the source geometry
  /// is kept; the image of the point is F of it, so a target vertex whose preimage it is becomes a vertex of
  /// M_st. Tries the three corners, the one opposite the longest edge of M_st first. Returns whether it did.
  bool insert(internal::WF f, const std::array<double, 3>& b) {
    const auto& m = S_.m;
    internal::WH h0 = m.halfedge(f);
    const internal::WV vs[3] = {m.source(h0), m.target(h0), m.target(m.next(h0))};
    {
      const Corner c0 = corner(vs[0]), c1 = corner(vs[1]), c2 = corner(vs[2]), cp = corner_at(P_.at(f, b));
      if (acceptable(std::array<Face_plan, 1>{{{&c0, &c1, &c2}}},
                     std::array<Face_plan, 3>{{{&c0, &c1, &cp}, {&c1, &c2, &cp}, {&c2, &c0, &cp}}})) {
        if (std::size_t(f) < dirty_.size()) dirty_[f] = 1;
        commit(S_.split_face(f, b), cp);
        return true;
      }
    }
    std::array<int, 3> order{{0, 1, 2}};
    auto opposite_length = [&](int k) { return CGAL::squared_distance(pos_[vs[(k + 1) % 3]], pos_[vs[(k + 2) % 3]]); };
    std::sort(order.begin(), order.end(), [&](int i, int j) { return opposite_length(i) > opposite_length(j); });
    for (int k : order) {
      const int i = (k + 1) % 3, j = (k + 2) % 3; // the edge (vs[i], vs[j]) is split at s
      const double bij = b[i] + b[j];
      if (!(bij > 1e-9) || !(b[k] > 1e-9)) continue; // the point is a corner or on the split edge
      const double t = b[j] / bij;      // s = (1 - t) vs[i] + t vs[j]
      const double t2 = bij;            // point = (1 - t2) vs[k] + t2 s
      const internal::WV a = vs[i], c = vs[j], kk = vs[k];
      internal::WH h = m.halfedge(a, c);
      const internal::WV y = m.target(m.next(m.opposite(h)));
      std::array<double, 3> bs{{0, 0, 0}};
      bs[i] = 1 - t, bs[j] = t;
      const Corner ca = corner(a), cc = corner(c), ck = corner(kk), cy = corner(y);
      const Corner cs = corner_at(P_.at(f, bs)), cp = corner_at(P_.at(f, b));
      if (!acceptable(std::array<Face_plan, 2>{{{&ca, &cc, &ck}, {&cc, &ca, &cy}}},
                      std::array<Face_plan, 6>{{{&ca, &cs, &cp}, {&ca, &cp, &ck}, {&cs, &cc, &cp}, {&cp, &cc, &ck},
                                                 {&cc, &cs, &cy}, {&cs, &ca, &cy}}}))
        continue;
      touch(a, c);
      const internal::WV s = S_.split_edge(a, c, t);
      commit(s, cs);
      commit(S_.split_edge(kk, s, t2), cp);
      return true;
    }
    return false;
  }

  /// split() at the midpoint of (u, v), or where that is refused, at the first of the next `points` - 1 of
  /// t = 0.375, 0.625, 0.25, 0.75, 0.125, 0.875 that is accepted. Returns whether it split.
  bool split_near_middle(internal::WV u, internal::WV v, int points) {
    static constexpr double ts[] = {0.5, 0.375, 0.625, 0.25, 0.75, 0.125, 0.875};
    for (int i = 0; i < points && i < 7; ++i)
      if (split(u, v, ts[i])) return true;
    return false;
  }

  /// §5.3, refinement of the source and M_st together, in two steps:
  ///  1. every target vertex whose error e(v) exceeds the rule's threshold (of the largest e(v), leaving out
  ///     target vertices whose insertion was refused in two rounds), largest first, has its preimage F^-1(v)
  ///     inserted into the source face holding it: v becomes a vertex of M_st and its error drops to zero.
  ///     Once per face and round (the located preimages of a changed face are stale), and not next to a
  ///     target vertex inserted in this round. Where the insertion would fold M_st, the face's longest edge is
  ///     split instead;
  ///  2. the paper's edge splits: edges whose Eq. 2 error exceeds the rule's threshold, edges whose midpoint
  ///     lies farther than ε from F(midpoint), and the longest edge of every face whose centroid lies farther
  ///     than ε from F(centroid), at the midpoint (or near it, where the midpoint would fold M_st). Edges of M_st
  ///     shorter than ε/2 are not split: a large error there comes from a spot where F changes abruptly (a
  ///     squeezed protrusion), which halving would chase forever; the insertions of step 1 reach it. An edge
  ///     with a chord beyond ε that every split point would fold is split with a local fold repair, as a
  ///     transaction (with_repair()).
  /// Returns the number of new vertices.
  template <class Rule>
  std::size_t refine(const Rule& rule) {
    const auto& m = S_.m;
    const auto& mt = T_.m;
    const std::size_t v0 = m.number_of_vertices();
    dirty_.assign(m.number_of_faces(), 0);
    // 1. Target vertices beyond the threshold.
    // The rule's largest error leaves out the vertices refused in two rounds: at a spot the refinement cannot
    // reach, half of their error would keep every error between ε and it from being refined.
    refused_.resize(mt.number_of_vertices(), 0);
    double max_free = 0;
    for (internal::WV v : mt.vertices())
      if (refused_[v] < 2) max_free = std::max(max_free, e_[v]);
    const double thr_v = rule.threshold(max_free, eps_);
    std::vector<internal::WV> worst;
    for (internal::WV v : mt.vertices())
      if (e_[v] > thr_v) worst.push_back(v);
    std::sort(worst.begin(), worst.end(), [&](internal::WV x, internal::WV y) { return e_[x] > e_[y]; });
    std::vector<char> near(mt.number_of_vertices(), 0);
    std::vector<std::pair<internal::WV, internal::WV>> fallback;
    for (internal::WV v : worst) {
      if (near[v] || is_dirty(pre_[v].face)) continue;
      if (!insert(pre_[v].face, pre_[v].b)) {
        // Cannot insert without folding M_st: split the face's longest edge instead (below).
        const internal::WH g = longest_edge(pre_[v].face);
        fallback.push_back({m.source(g), m.target(g)});
        if (refused_[v] < 2) ++refused_[v];
        continue;
      }
      near[v] = 1;
      for (internal::WV w : CGAL::vertices_around_target(mt.halfedge(v), mt)) near[w] = 1;
    }
    // 2. Edges.
    double emax = 0;
    for (double x : edge_error_) emax = std::max(emax, x);
    const double thr = rule.threshold(emax, eps_);
    std::vector<char> mark(m.number_of_edges(), 0);
    // Only the edges and faces measured before step 1 have figures (its splits made the others).
    for (internal::WE e : m.edges())
      if (std::size_t(e) < edge_chord_.size()) mark[e] = edge_chord_[e] > eps_ || edge_error_[e] > thr;
    for (internal::WF f : m.faces()) {
      if (std::size_t(f) >= face_chord_.size() || !(face_chord_[f] > eps_)) continue;
      mark[m.edge(longest_edge(f))] = 1;
    }
    std::vector<std::pair<internal::WV, internal::WV>> todo;
    for (internal::WE e : m.edges())
      if (mark[e]) todo.push_back({m.source(m.halfedge(e)), m.target(m.halfedge(e))});
    todo.insert(todo.end(), fallback.begin(), fallback.end());
    for (const auto& [u, v] : todo) {
      if (m.halfedge(u, v) == internal::WH()) continue; // already split
      if (!(CGAL::squared_distance(pos_[u], pos_[v]) > 0.25 * eps_ * eps_)) continue; // shorter than ε/2
      if (split_near_middle(u, v, 5)) continue;
      // A chord beyond ε that no split can reach without a fold: split it anyway and repair the fold.
      const internal::WE e = m.edge(m.halfedge(u, v));
      if (std::size_t(e) < edge_chord_.size() && edge_chord_[e] > eps_) {
        if (with_repair([&, u = u, v = v] { return split_near_middle(u, v, 5); })) ++stats_.refinement_repairs_kept;
        else ++stats_.refinement_repairs_undone;
      }
    }
    const std::size_t n = m.number_of_vertices() - v0;
    stats_.refinement_splits += n;
    return n;
  }

  /// Whether faces (u, v, x) and (v, u, y) of M_st, replacing the four faces of split vertex w, lie within `lim`
  /// of the target: the midpoint of (u, v), the two centroids and w's image, each against F of the same
  /// source point (w's image against the point of the two faces at w's base location).
  bool restored_faces_follow_target(const Corner& cu, const Corner& cv, const Corner& cx, const Corner& cy,
                                    const Corner& cw, double lim) const {
    const internal::Base_mesh& B = *P_.base;
    const double lim2 = lim * lim;
    Base_location mid;
    if (!B.interpolate({&cu.loc, &cv.loc, &cx.loc}, {0.5, 0.5, 0.0}, mid) ||
        CGAL::squared_distance(CGAL::midpoint(cu.pos, cv.pos), corner_at(mid).pos) > lim2)
      return false;
    for (const Corner* c : {&cx, &cy}) {
      Base_location ce;
      if (!B.interpolate({&cu.loc, &cv.loc, &c->loc}, {1.0 / 3, 1.0 / 3, 1.0 / 3}, ce) ||
          CGAL::squared_distance(CGAL::centroid(cu.pos, cv.pos, c->pos), corner_at(ce).pos) > lim2)
        return false;
    }
    std::array<const Base_location*, 5> ls{&cu.loc, &cv.loc, &cx.loc, &cy.loc, &cw.loc};
    std::array<internal::Point_2, 5> q;
    int fc, fn;
    if (!B.canonical_frame(ls, fc, fn, q)) return false;
    std::array<double, 3> b = internal::barycentric_2(q[0], q[1], q[2], q[4]);
    Point_3 on;
    if (b[0] >= 0 && b[1] >= 0 && b[2] >= 0) {
      on = internal::barycentric_point(cu.pos, cv.pos, cx.pos, b);
    } else {
      b = internal::barycentric_2(q[1], q[0], q[3], q[4]);
      on = internal::barycentric_point(cv.pos, cu.pos, cy.pos, b);
    }
    return CGAL::squared_distance(on, cw.pos) <= lim2;
  }

  /// Undoes the layout's edge splits of the source that the smoothed map no longer needs (an addition to the
  /// paper). The splits made paths into edge paths and met the adjacency constraint of §4.2; once the map is
  /// smoothed, a split vertex w of edge (u, v), still of degree 4 with its four faces, can go: edge (u, v) and
  /// its two faces come back, exactly the source's geometry (w lay on that edge), if both faces are positively
  /// oriented over the base mesh (exact test), fold no more faces of M_st than w's four, and follow the target
  /// within ε/4 (restored_faces_follow_target()). Latest splits
  /// first, so that a split of an edge of an earlier split vertex is undone before it. The mesh is then
  /// compacted: original vertices keep their indices, the remaining split vertices are renumbered after them
  /// (the mesh, the parameterization, the vertex records and the split list; M_st's `img_` and `pos_` are
  /// stale until the next measure()). Returns the number of splits undone.
  std::size_t undo_layout_splits() {
    auto& m = S_.m;
    std::size_t undone = 0;
    std::vector<char> gone(S_.splits.size(), 0);
    for (std::size_t k = S_.splits.size(); k-- > 0;) {
      const Edge_split& sp = S_.splits[k];
      const internal::WV w(internal::WV::size_type(sp.w)), u(internal::WV::size_type(sp.u)), v(internal::WV::size_type(sp.v));
      if (S_.vfeature[w] != internal::no_feature || m.degree(w) != 4) continue;
      const internal::WH uw = m.halfedge(u, w), vw = m.halfedge(v, w);
      if (uw == internal::WH() || vw == internal::WH() || m.halfedge(u, v) != internal::WH()) continue;
      // Faces (u, w, x) and (w, v, x) on one side, (v, w, y) and (w, u, y) on the other.
      const internal::WV x = m.target(m.next(uw)), y = m.target(m.next(vw));
      if (x == y || m.target(m.next(m.opposite(vw))) != x || m.target(m.next(m.opposite(uw))) != y) continue;
      const Corner cu = corner(u), cv = corner(v), cw = corner(w), cx = corner(x), cy = corner(y);
      if (!acceptable(std::array<Face_plan, 4>{{{&cu, &cw, &cx}, {&cw, &cv, &cx}, {&cv, &cw, &cy}, {&cw, &cu, &cy}}},
                      std::array<Face_plan, 2>{{{&cu, &cv, &cx}, {&cv, &cu, &cy}}}))
        continue;
      if (!restored_faces_follow_target(cu, cv, cx, cy, cw, 0.25 * eps_)) continue;
      // The original faces of the four (the two on each side share one).
      const int oa = S_.forig[m.face(uw)], ob = S_.forig[m.face(vw)];
      CGAL::Euler::remove_center_vertex(uw, m); // leaves the quad x -> u -> y -> v -> x
      const internal::WH nh = CGAL::Euler::split_face(m.halfedge(x, u), m.halfedge(y, v), m); // edge (u, v)
      for (internal::WH g : {nh, m.opposite(nh)}) {
        bool has_x = false;
        for (internal::WV z : CGAL::vertices_around_face(g, m)) has_x |= z == x;
        S_.forig[m.face(g)] = has_x ? oa : ob;
      }
      S_.epath[m.edge(nh)] = internal::no_path;
      gone[k] = 1;
      ++undone;
    }
    stats_.layout_splits_undone = undone;
    if (undone == 0) return 0;
    // Compaction: Surface_mesh moves the last live vertices into the holes; follow the old indices through it.
    auto old_index = m.add_property_map<internal::WV, std::uint32_t>("v:cp_old_index", 0).first;
    for (internal::WV z : m.vertices()) old_index[z] = std::uint32_t(z);
    m.collect_garbage();
    S_.bind_property_maps();
    const std::size_t n = m.number_of_vertices();
    std::vector<std::size_t> to_new(P_.loc.size(), std::size_t(-1));
    std::vector<Base_location> loc(n);
    std::vector<std::pair<int, std::array<double, 3>>> vrep(n);
    std::vector<std::vector<float>> desc(S_.desc.size() > n ? n : 0);
    for (internal::WV z : m.vertices()) {
      const std::size_t o = old_index[z];
      to_new[o] = std::size_t(z);
      loc[z] = P_.loc[o];
      vrep[z] = S_.vrep[o];
      if (!desc.empty()) desc[z] = S_.desc[o];
    }
    m.remove_property_map(old_index);
    P_.loc = std::move(loc);
    S_.vrep = std::move(vrep);
    if (!desc.empty()) S_.desc = std::move(desc);
    std::vector<Edge_split> splits;
    for (std::size_t k = 0; k < S_.splits.size(); ++k)
      if (!gone[k]) {
        Edge_split e = S_.splits[k];
        e.u = to_new[e.u], e.v = to_new[e.v], e.w = to_new[e.w];
        splits.push_back(e);
      }
    S_.splits = std::move(splits);
    stats_.layout_vertices = n;
    return undone;
  }

  /// The longest edge of face f of M_st.
  internal::WH longest_edge(internal::WF f) const {
    const auto& m = S_.m;
    internal::WH best = m.halfedge(f);
    double bl = -1;
    for (internal::WH g : CGAL::halfedges_around_face(m.halfedge(f), m)) {
      const double len = CGAL::squared_distance(pos_[m.source(g)], pos_[m.target(g)]);
      if (len > bl) bl = len, best = g;
    }
    return best;
  }

  /// Faces of M_st around source vertex v folded over against the target if v's image were `c`.
  int folds_around(internal::WV v, const Corner& c) const {
    const auto& m = S_.m;
    int n = 0;
    for (internal::WH h : CGAL::halfedges_around_target(m.halfedge(v), m)) {
      internal::WV a = m.target(m.next(h)), b = m.target(m.next(m.next(h)));
      n += flipped(c.pos, c.img.face, pos_[a], img_[a].face, pos_[b], img_[b].face);
    }
    return n;
  }

  /// Moves vertex v in the base domain along one of its edges (a quarter, half or three quarters of the way)
  /// to where the fewest faces around it fold, if fewer than now and its faces stay positively oriented over
  /// the base mesh (exact test). The source vertex stays where it is: only its image on the target moves.
  /// Returns the change in folded faces around v (0 if it did not move).
  int unfold_vertex(internal::WV v) {
    const auto& m = S_.m;
    const Corner now = corner(v);
    const int folds_now = folds_around(v, now);
    if (folds_now == 0) return 0;
    int best = folds_now;
    Corner chosen = now;
    for (internal::WV w : CGAL::vertices_around_target(m.halfedge(v), m))
      for (double t : {0.25, 0.5, 0.75}) {
        const Corner c = corner_at(P_.between(v, w, t));
        const int k = folds_around(v, c);
        if (k >= best) continue;
        P_[v] = c.loc;
        const bool valid = P_.star_positive(v);
        P_[v] = now.loc;
        if (valid) best = k, chosen = c;
      }
    if (best == folds_now) return 0;
    P_[v] = chosen.loc;
    img_[v] = chosen.img;
    pos_[v] = chosen.pos;
    return best - folds_now;
  }

  /// Removes folds of M_st by moving vertices: a corner of a folded face is moved in the base domain along
  /// one of its edges (a quarter, half or three quarters of the way) if that folds fewer faces around it and
  /// keeps its faces positively oriented over the base mesh (exact test, as the smoothing). The source geometry
  /// is unchanged: only where the vertex lands on the target moves. Returns the number of moves.
  std::size_t unfold() {
    const auto& m = S_.m;
    std::size_t moves = 0;
    for (int pass = 0; pass < 4; ++pass) {
      std::vector<internal::WV> todo;
      for (internal::WF f : m.faces())
        if (face_folded(f)) {
          const internal::WH h = m.halfedge(f);
          for (internal::WV v : {m.source(h), m.target(h), m.target(m.next(h))}) todo.push_back(v);
        }
      if (todo.empty()) break;
      std::size_t before_moves = moves;
      for (internal::WV v : todo)
        if (S_.vfeature[v] == internal::no_feature && unfold_vertex(v) < 0) ++moves;
      if (moves == before_moves) break;
    }
    return moves;
  }

  /// Fold repair, step of one folded face f: walks f's longest-edge propagation path (Rivara), with edge lengths
  /// measured on the target-shaped mesh, to its terminal edge and splits that (near its midpoint; other points
  /// on the edge where the midpoint is refused). With `any_edge`, if that split is refused, f's own edges are
  /// tried, longest first. Returns whether it split.
  bool repair_step(internal::WF f, bool any_edge) {
    const auto& m = S_.m;
    auto split_near_middle = [&](internal::WH h) { return this->split_near_middle(m.source(h), m.target(h), 7); };
    internal::WF t = f;
    for (int depth = 0; depth < 40; ++depth) {
      const internal::WH h = longest_edge(t), o = m.opposite(h);
      if (m.is_border(o) || m.edge(longest_edge(m.face(o))) == m.edge(h)) {
        if (split_near_middle(h)) return true;
        break;
      }
      t = m.face(o);
    }
    if (!any_edge) return false;
    std::vector<std::pair<double, internal::WH>> es;
    for (internal::WH g : CGAL::halfedges_around_face(m.halfedge(f), m))
      es.push_back({-CGAL::squared_distance(pos_[m.source(g)], pos_[m.target(g)]), g});
    std::sort(es.begin(), es.end());
    for (const auto& e : es)
      if (split_near_middle(e.second)) return true;
    return false;
  }

  /// unfold_vertex() for each of `vs` (the vertices the current repair made). Returns the change in folded
  /// faces.
  int unfold_vertices(const std::vector<internal::WV>& vs) {
    int change = 0;
    for (internal::WV v : vs) change += unfold_vertex(v);
    return change;
  }

  /// Fold repair (an addition to the paper). A face of M_st folds where F is so anisotropic that the face,
  /// well shaped on the source, is a needle on the target across a bend of the target's parameterization.
  /// Refining it towards well-shaped triangles *in the target's metric* removes the fold: each folded face gets
  /// longest-edge (LEPP) bisections with target-shaped lengths, each split allowed to fold one more face than
  /// it unfolds (two in the second mode), the split vertices moved as in unfold(), over up to 30 rounds on
  /// the faces the repair made or changed, at most 200 splits. A repair is kept only if it leaves fewer folded
  /// faces than before; otherwise the mesh and the maps are restored. Splits lie on source edges as
  /// everywhere else (the source geometry is kept) and are made only if every new face is positively
  /// oriented over the base mesh (exact test). The folds are counted with the strict test of flipped() (`repairing_`).
  /// Passes alternate two modes (slack 1, LEPP only; slack 2, the face's own edges too) until a pass of each
  /// mode in a row keeps nothing, at most six passes. With `near` (a flag per vertex), only the folded faces
  /// with a flagged corner or a corner the repair made are repaired.
  void repair_folds(const std::vector<char>* near = nullptr) {
    auto& m = S_.m;
    const std::size_t v0 = m.number_of_vertices();
    auto wanted = [&](internal::WF f) {
      if (!near) return true;
      for (internal::WV v : CGAL::vertices_around_face(m.halfedge(f), m))
        if (std::size_t(v) >= v0 || (*near)[v]) return true;
      return false;
    };
    repairing_ = true;
    constexpr int budget = 200, max_passes = 6;
    int idle = 0;
    for (int pass = 0; pass < max_passes && idle < 2; ++pass) {
      const bool second_mode = pass % 2 == 1;
      fold_slack_ = second_mode ? 2 : 1;
      std::vector<internal::WF> folded;
      for (internal::WF f : m.faces())
        if (face_folded(f) && wanted(f)) folded.push_back(f);
      if (folded.empty()) break;
      std::size_t kept = 0;
      for (internal::WF f0 : folded) {
        if (!face_folded(f0)) continue; // repaired with an earlier face
        const Checkpoint cp = checkpoint();
        fold_total_ = 0;
        repair_region({f0}, second_mode, budget);
        if (fold_total_ < 0) {
          ++kept;
          continue;
        }
        rollback(cp);
        ++stats_.fold_repairs_undone;
      }
      stats_.fold_repairs_kept += kept;
      idle = kept == 0 ? idle + 1 : 0;
    }
    repairing_ = false;
    fold_slack_ = 0;
    made_.clear();
    stats_.fold_repair_splits = m.number_of_vertices() - v0;
  }

  /// What a repair transaction restores: a repair appends vertices (with their records), changes faces of the
  /// source and moves only vertices it made, so undoing it restores the mesh and truncates the rest.
  struct Checkpoint {
    internal::Work_mesh m;
    std::size_t vertices, splits;
    std::vector<char> dirty;
  };
  Checkpoint checkpoint() const { return {S_.m, S_.m.number_of_vertices(), S_.splits.size(), dirty_}; }
  void rollback(const Checkpoint& cp) {
    S_.m = cp.m;
    S_.bind_property_maps();
    S_.vrep.resize(std::min(S_.vrep.size(), cp.vertices));
    if (S_.desc.size() > cp.vertices) S_.desc.resize(cp.vertices);
    S_.splits.resize(cp.splits);
    P_.loc.resize(cp.vertices);
    img_.resize(cp.vertices);
    pos_.resize(cp.vertices);
    dirty_ = cp.dirty;
  }

  /// The rounds of one repair (with `repairing_` set): LEPP steps on the folded faces among `seed` and the
  /// faces around the vertices the repair made, then those vertices unfolded, for up to 30 rounds and `budget`
  /// splits. Starts a new count of made vertices; leaves the change in folded faces in `fold_total_` (added to
  /// what it holds).
  void repair_region(const std::vector<internal::WF>& seed, bool second_mode, int budget) {
    const auto& m = S_.m;
    constexpr int rounds = 30;
    made_.clear();
    std::vector<internal::WF> region = seed;
    for (int r = 0; r < rounds; ++r) {
      std::vector<internal::WF> todo;
      for (internal::WF g : region)
        if (face_folded(g)) todo.push_back(g);
      if (todo.empty()) break;
      const std::size_t made_before = made_.size();
      for (internal::WF g : todo)
        for (int k = 0; k < 4 && made_.size() < std::size_t(budget) && face_folded(g); ++k)
          if (!repair_step(g, second_mode)) break;
      if (made_.size() == made_before || made_.size() >= std::size_t(budget)) break;
      fold_total_ += unfold_vertices(made_);
      // Every face a split changed is around a vertex the repair made.
      region = seed;
      for (internal::WV x : made_)
        for (internal::WF g : CGAL::faces_around_target(m.halfedge(x), m)) region.push_back(g);
      std::sort(region.begin(), region.end());
      region.erase(std::unique(region.begin(), region.end()), region.end());
    }
  }

  /// A refinement split refused because it would fold M_st, made anyway as a transaction: `step` (splits with
  /// `repairing_` set, allowed one more fold), then the fold repair of repair_region() around the new vertex,
  /// at most 50 splits; kept only if M_st has no more folded faces than before (strict test), undone
  /// otherwise. Returns whether it was kept (false also where `step` itself is refused: nothing changed).
  template <class Step>
  bool with_repair(Step step) {
    constexpr int budget = 50;
    const Checkpoint cp = checkpoint();
    repairing_ = true;
    fold_slack_ = 1;
    fold_total_ = 0;
    made_.clear();
    bool kept = false;
    if (step()) {
      const auto& m = S_.m;
      std::vector<internal::WF> seed;
      for (std::size_t i = cp.vertices; i < m.number_of_vertices(); ++i)
        for (internal::WF g : CGAL::faces_around_target(m.halfedge(internal::WV(i)), m)) seed.push_back(g);
      if (fold_total_ > 0) repair_region(seed, false, budget);
      kept = fold_total_ <= 0;
      if (!kept) rollback(cp);
    }
    repairing_ = false;
    fold_slack_ = 0;
    made_.clear();
    return kept;
  }

  /// §5.4: an edge (u, v) with opposite corners x, y whose faces deviate from the target's normal by more
  /// than the threshold, and whose flip (x, y) would deviate less, is split where the diagonals (u, v) and
  /// (x, y) cross in the base domain: the new vertex's image is the point of the target between x and y, which
  /// reproduces the flip's change of normals while the source keeps its geometry.
  std::size_t pseudo_flips(double cos_max) {
    const auto& m = S_.m;
    // Cosine between the normal of triangle (a, b, c) of M_st and the target's normal under its centroid.
    auto agreement = [&](internal::WV a, internal::WV b, internal::WV c) {
      Kernel::Vector_3 n = internal::triangle_normal(pos_[a], pos_[b], pos_[c]);
      double len = std::sqrt(n.squared_length());
      if (!(len > 0)) return -1.0;
      Base_location centroid;
      if (!P_.base->interpolate({&P_[a], &P_[b], &P_[c]}, {1.0 / 3, 1.0 / 3, 1.0 / 3}, centroid)) return -1.0;
      // The target's unit normal at the centroid's image: its face's (faces of the target are planar).
      const Kernel::Vector_3 nt = target_normal(locT_.locate(centroid).face);
      const double lt = std::sqrt(nt.squared_length());
      return lt > 0 ? (n / len) * (nt / lt) : 0.0;
    };
    struct Candidate {
      internal::WV u, v;
      double t;
      double gain;
    };
    std::vector<Candidate> cands;
    for (internal::WE e : m.edges()) {
      internal::WH h = m.halfedge(e);
      internal::WV u = m.source(h), v = m.target(h), x = m.target(m.next(h)), y = m.target(m.next(m.opposite(h)));
      const double now = std::min(agreement(u, v, x), agreement(v, u, y));
      if (now >= cos_max) continue;
      const double flipped = std::min(agreement(x, y, v), agreement(y, x, u));
      // A pseudo flip costs a vertex: made only where the flip brings both faces within the threshold.
      if (!(flipped > now && flipped >= cos_max)) continue;
      // Where the diagonals cross in the base domain, as a parameter along (u, v).
      std::array<const Base_location*, 4> ls{&P_[u], &P_[v], &P_[x], &P_[y]};
      std::array<internal::Point_2, 4> p;
      int fc, fn;
      if (!P_.base->canonical_frame(ls, fc, fn, p)) continue;
      if (CGAL::orientation(p[2], p[3], p[0]) == CGAL::orientation(p[2], p[3], p[1])) continue; // not convex
      const double d0 = CGAL::area(p[2], p[3], p[0]), d1 = CGAL::area(p[2], p[3], p[1]);
      const double t = d0 / (d0 - d1);
      if (!(t > 0.05 && t < 0.95)) continue;
      cands.push_back({u, v, t, flipped - now});
    }
    std::sort(cands.begin(), cands.end(), [](const Candidate& a, const Candidate& b) { return a.gain > b.gain; });
    // One split per face per pass: a split changes its neighbours' configuration.
    std::vector<char> touched(m.number_of_vertices(), 0);
    std::size_t n = 0;
    for (const Candidate& c : cands) {
      if (touched[c.u] || touched[c.v]) continue;
      internal::WH h = m.halfedge(c.u, c.v);
      if (h == internal::WH()) continue;
      if (!split(c.u, c.v, c.t)) continue;
      touched[c.u] = touched[c.v] = 1;
      touched.resize(m.number_of_vertices(), 1);
      ++n;
    }
    return n;
  }

  using Target_tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_face_graph_triangle_primitive<internal::Work_mesh>>>;

  /// Whether face f of M_st is flipped by the rule of the independent verifier (internal::flipped_against_nearest:
  /// its normal opposes the target's at the points of the target nearest its centroid and each corner), taken
  /// strictly: where such a point lies on an edge or at a vertex of the target, the verifier may take any face
  /// through it, so the point counts as opposing if one of them opposes (opposes()).
  bool flipped_on_target(const Target_tree& tree, internal::WF f) const {
    const auto& m = S_.m;
    const internal::WH h = m.halfedge(f);
    const Point_3 &a = pos_[m.source(h)], &b = pos_[m.target(h)], &c = pos_[m.target(m.next(h))];
    const Kernel::Vector_3 n = internal::triangle_normal(a, b, c);
    for (const Point_3& p : {CGAL::centroid(a, b, c), a, b, c}) {
      const auto nearest = tree.closest_point_and_primitive(p);
      if (!opposes(n, nearest.first, nearest.second)) return false;
    }
    return true;
  }

  /// Untangling on the target (an addition to the paper), for the folds left after §5.4; `tree` holds the
  /// target's faces. Every face is tested by the verifier's rule (flipped_on_target()), which also sets
  /// `folded_` and `flipped_`. Where F is this anisotropic, no M_st that is F of a one-to-one M_s avoids the
  /// fold (§10.5 of the manual), so these vertices of the target-shaped mesh leave F: they move along the
  /// target, their source vertices stay. Each folded face f is untangled in a chart of the target with the
  /// outline of a region around it and the feature vertices held: first in the plane of the mean target normal
  /// under the k-ring of f (k = 1 ... 8, while the ring is flat enough for a plane: untangle_ring()), then, if
  /// no ring works, in a flattened disk of the target around f, which follows the target where it bends
  /// (untangle_on_surface()).
  void untangle_folds(const Target_tree& tree) {
    const auto& m = S_.m;
    std::vector<char> moved(m.number_of_vertices(), 0);
    std::vector<internal::WF> folds;
    for (internal::WF f : m.faces())
      if (flipped_on_target(tree, f)) folds.push_back(f);
    for (internal::WF f : folds) {
      if (!flipped_on_target(tree, f)) continue; // untangled with an earlier one
      int r = untangle_in_rings(tree, f, moved);
      for (double size : {1.0, 1.5, 2.0})
        if (r <= 0) r = untangle_on_surface(tree, f, size, moved);
    }
    flipped_ = 0;
    for (internal::WF f : m.faces()) flipped_ += (folded_[f] = flipped_on_target(tree, f));
    for (internal::WF f : folds) stats_.untangled_folds += !folded_[f];
    for (char c : moved) stats_.untangle_moves += c;
  }

  /// untangle_ring() for k = 1 ... 8 until a ring is kept (1) or too curved (-1); 0 if none is kept.
  int untangle_in_rings(const Target_tree& tree, internal::WF f, std::vector<char>& moved) {
    int r = 0;
    for (int k = 1; k <= 8 && r == 0; ++k) r = untangle_ring(tree, f, k, moved);
    return r;
  }

  /// The planar chart: the k-ring of f0 projected onto the plane of the mean target normal under its vertices
  /// (only while every target normal there is within 72° of it), untangled from the present positions, moved
  /// points lifted back onto the target along the plane's normal (the hit nearest the plane point). 1 if
  /// kept, 0 if not (a larger k may work), -1 if the ring has become too curved for a plane.
  int untangle_ring(const Target_tree& tree, internal::WF f0, int k, std::vector<char>& moved) {
    const auto& m = S_.m;
    std::set<internal::WF> region{f0};
    std::set<internal::WV> ring;
    for (internal::WV v : CGAL::vertices_around_face(m.halfedge(f0), m)) ring.insert(v);
    for (int r = 0; r < k; ++r) {
      std::set<internal::WV> grown = ring;
      for (internal::WV v : ring)
        for (internal::WF f : CGAL::faces_around_target(m.halfedge(v), m)) {
          region.insert(f);
          for (internal::WV w : CGAL::vertices_around_face(m.halfedge(f), m)) grown.insert(w);
        }
      ring = std::move(grown);
    }
    auto unit_normal = [this](internal::WF f) {
      const Kernel::Vector_3 n = target_normal(f);
      return n / std::sqrt(n * n);
    };
    Kernel::Vector_3 normal(0, 0, 0);
    for (internal::WV v : ring) normal = normal + unit_normal(img_[v].face);
    const double length = std::sqrt(normal * normal);
    if (!(length > 0)) return -1; // normals that cancel out: no plane to project on
    normal = normal / length;
    for (internal::WV v : ring)
      if (unit_normal(img_[v].face) * normal < 0.3) return -1;
    const Kernel::Vector_3 u0 = std::abs(normal.x()) < 0.9 ? Kernel::Vector_3(1, 0, 0) : Kernel::Vector_3(0, 1, 0);
    Kernel::Vector_3 U = CGAL::cross_product(normal, u0);
    U = U / std::sqrt(U * U);
    const Kernel::Vector_3 W = CGAL::cross_product(normal, U);
    const Point_3 origin = pos_[*ring.begin()];
    auto to_chart = [&](internal::WV v) { return Eigen::Vector2d((pos_[v] - origin) * U, (pos_[v] - origin) * W); };
    auto from_chart = [&](internal::WV v, const Eigen::Vector2d& p, internal::Work_location& at) {
      const Eigen::Vector2d d = p - to_chart(v);
      const Point_3 g = pos_[v] + d.x() * U + d.y() * W;
      std::vector<typename Target_tree::template Intersection_and_primitive_id<Kernel::Line_3>::Type> hits;
      tree.all_intersections(Kernel::Line_3(g, normal), std::back_inserter(hits));
      double best = HUGE_VAL;
      for (const auto& hit : hits)
        if (const Point_3* q = boost::get<Point_3>(&hit.first)) { // (a segment: the line lies in a target face)
          const double d2 = CGAL::squared_distance(*q, g);
          if (d2 < best) best = d2, at = location_in(hit.second, *q);
        }
      return best < HUGE_VAL;
    };
    return untangle_in_chart(tree, region, to_chart, from_chart, false, moved);
  }

  /// The surface chart, for a fold inside a tangle too large or too curved for a planar ring (a fan of needles
  /// along a limb where F is squeezed): a disk of the target grown around f0 to `size` times f0's longest
  /// edge, over the faces within 78° of the target normal under f0 (the front of a limb, not around it), and
  /// flattened (internal::Disk_chart). The region is the connected set of faces around f0 whose corners lie on
  /// the disk and within 0.8 of its radius. Its inner vertices are laid out afresh by mean-value coordinates
  /// of the *source* shape (a local cross-parameterization of the source patch into the chart) and
  /// untangled, and they map back through the flattening, onto the target exactly. The chart's straight edges
  /// are not the target's, so a few faces may still be flipped on the target: those are given to
  /// untangle_ring(). Kept only if then no face around a vertex it moved is flipped; otherwise everything is
  /// restored. 1 if kept, 0 if not.
  int untangle_on_surface(const Target_tree& tree, internal::WF f0, double size, std::vector<char>& moved) {
    const auto& m = S_.m;
    const internal::WH h0 = longest_edge(f0);
    const double radius = size * std::sqrt(CGAL::squared_distance(pos_[m.source(h0)], pos_[m.target(h0)]));
    const Point_3 center = CGAL::centroid(pos_[m.source(h0)], pos_[m.target(h0)], pos_[m.target(m.next(h0))]);
    std::vector<internal::WF> seeds;
    Kernel::Vector_3 direction(0, 0, 0);
    for (internal::WV v : CGAL::vertices_around_face(h0, m)) {
      seeds.push_back(img_[v].face);
      const Kernel::Vector_3 n = target_normal(img_[v].face);
      direction = direction + n / std::sqrt(n * n);
    }
    if (!(direction * direction > 0)) return 0;
    direction = direction / std::sqrt(direction * direction);
    const std::optional<internal::Disk_chart> chart =
        internal::Disk_chart::grow(T_.m, seeds, center, radius, direction, std::cos(78 * CGAL_PI / 180));
    if (!chart) return 0;
    auto inside = [&](internal::WF f) {
      for (internal::WV v : CGAL::vertices_around_face(m.halfedge(f), m))
        if (!chart->contains(img_[v].face) || CGAL::squared_distance(pos_[v], center) > CGAL::square(0.8 * radius))
          return false;
      return true;
    };
    if (!inside(f0)) return 0;
    std::set<internal::WF> region{f0};
    for (std::vector<internal::WF> todo{f0}; !todo.empty();) {
      const internal::WF f = todo.back();
      todo.pop_back();
      for (internal::WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        const internal::WF g = m.face(m.opposite(h));
        if (g != internal::WF() && !region.count(g) && inside(g)) region.insert(g), todo.push_back(g);
      }
    }
    auto to_chart = [&](internal::WV v) { return chart->at(T_.m, img_[v]); };
    auto from_chart = [&](internal::WV, const Eigen::Vector2d& p, internal::Work_location& at) {
      return chart->locate(T_.m, p, at);
    };
    const std::vector<internal::Work_location> img_before = img_;
    const std::vector<Point_3> pos_before = pos_;
    const std::vector<char> moved_before = moved;
    const double max_move_before = stats_.untangle_max_move;
    if (untangle_in_chart(tree, region, to_chart, from_chart, true, moved) <= 0) return 0;
    for (internal::WF f : region)
      if (flipped_on_target(tree, f)) untangle_in_rings(tree, f, moved);
    for (std::size_t i = 0; i < moved.size(); ++i)
      if (moved[i] && !moved_before[i])
        for (internal::WF f : CGAL::faces_around_target(m.halfedge(internal::WV(i)), m))
          if (flipped_on_target(tree, f)) {
            img_ = img_before, pos_ = pos_before, moved = moved_before, stats_.untangle_max_move = max_move_before;
            return 0;
          }
    return 1;
  }

  /// What both charts share: the region's vertices are placed in the chart (`to_chart(v)`); the inner ones
  /// (not features, every face around them in the region) are free, the others held. With `relayout`, the
  /// free ones first get the mean-value layout of the source shape. They are moved by
  /// internal::Planar_untangler (reference shapes: a face's present shape where it is well shaped and not
  /// folded, else an equilateral triangle of the region's mean area; faces with no free corner cannot change
  /// and are left out) and mapped back onto the target (`from_chart(v, p, location)`, false if it cannot).
  /// The region is kept if every face of it stays within 0.9 ε of the target (centroid and edge midpoints,
  /// closest points) and, unless `relayout` (whose caller finishes and checks the region), if the untangler
  /// left no triangle inverted and none of the faces it moved is flipped by the independent verifier's rule;
  /// otherwise it is restored. 1 if kept, 0 if not.
  template <class ToChart, class FromChart>
  int untangle_in_chart(const Target_tree& tree, const std::set<internal::WF>& region, const ToChart& to_chart,
                        const FromChart& from_chart, bool relayout, std::vector<char>& moved) {
    const auto& m = S_.m;
    std::map<internal::WV, int> id;
    std::vector<internal::WV> verts;
    for (internal::WF f : region)
      for (internal::WV v : CGAL::vertices_around_face(m.halfedge(f), m))
        if (id.emplace(v, int(verts.size())).second) verts.push_back(v);
    std::vector<Eigen::Vector2d> xy;
    std::vector<char> is_free;
    std::size_t n_free = 0;
    for (internal::WV v : verts) {
      xy.push_back(to_chart(v));
      bool inner = S_.vfeature[v] == internal::no_feature;
      for (internal::WF f : CGAL::faces_around_target(m.halfedge(v), m)) inner = inner && region.count(f) > 0;
      is_free.push_back(inner);
      n_free += inner;
    }
    auto corners = [&](internal::WF f) {
      std::array<int, 3> c;
      int i = 0;
      for (internal::WV v : CGAL::vertices_around_face(m.halfedge(f), m)) c[i++] = id[v];
      return c;
    };
    auto moves = [&](const std::array<int, 3>& c) { return is_free[c[0]] || is_free[c[1]] || is_free[c[2]]; };
    double area = 0;
    for (internal::WF f : region) area += 0.5 * edge_matrix_of(xy, corners(f)).determinant();
    if (n_free == 0 || !(area > 0)) return 0;
    if (relayout) {
      std::vector<char> held(is_free.size());
      for (std::size_t i = 0; i < held.size(); ++i) held[i] = !is_free[i];
      if (!internal::mean_value_layout(m, verts, [&](internal::WV v) { return id.at(v); }, held, xy)) return 0;
    }
    const double side = std::sqrt(4 * area / double(region.size()) / std::sqrt(3.0));
    Eigen::Matrix2d equilateral;
    equilateral << side, side / 2, 0, side * std::sqrt(3.0) / 2;
    std::vector<internal::Untangle_triangle> tris;
    for (internal::WF f : region) {
      const auto c = corners(f);
      if (!moves(c)) continue;
      const Eigen::Matrix2d e = edge_matrix_of(xy, c);
      const double longest2 = std::max({e.col(0).squaredNorm(), e.col(1).squaredNorm(), (e.col(1) - e.col(0)).squaredNorm()});
      const bool good = e.determinant() > 0.2 * std::sqrt(3.0) / 4 * longest2 && !face_folded(f);
      tris.push_back({c, (good ? e : equilateral).inverse()});
    }
    internal::Planar_untangler untangler(xy, is_free, std::move(tris));
    if (!(untangler.run(0.3 * side) > 0) && !relayout) return 0;
    std::vector<std::pair<internal::WV, Corner>> old;
    auto restore = [&] {
      for (const auto& o : old) img_[o.first] = o.second.img, pos_[o.first] = o.second.pos;
    };
    for (std::size_t i = 0; i < verts.size(); ++i) {
      if (!is_free[i]) continue;
      internal::Work_location at;
      if (!from_chart(verts[i], untangler.point(i), at)) return restore(), 0;
      old.emplace_back(verts[i], corner(verts[i]));
      img_[verts[i]] = at, pos_[verts[i]] = target_point(at);
    }
    // Keep it only if the region follows the target and nothing it moved is flipped.
    const double bound2 = CGAL::square(0.9 * eps_);
    for (internal::WF f : region) {
      const internal::WH h = m.halfedge(f);
      const Point_3 &a = pos_[m.source(h)], &b = pos_[m.target(h)], &c = pos_[m.target(m.next(h))];
      for (const Point_3& p : {CGAL::centroid(a, b, c), CGAL::midpoint(a, b), CGAL::midpoint(b, c), CGAL::midpoint(c, a)})
        if (tree.squared_distance(p) > bound2) return restore(), 0;
      if (!relayout && moves(corners(f)) && flipped_on_target(tree, f)) return restore(), 0;
    }
    for (const auto& o : old) {
      moved[o.first] = 1;
      stats_.untangle_max_move =
          std::max(stats_.untangle_max_move, 100 * std::sqrt(CGAL::squared_distance(o.second.pos, pos_[o.first])));
    }
    return 1;
  }
  static Eigen::Matrix2d edge_matrix_of(const std::vector<Eigen::Vector2d>& xy, const std::array<int, 3>& c) {
    return internal::edge_matrix(xy[c[0]], xy[c[1]], xy[c[2]]);
  }
  /// The location on target face f of point p (on f's plane): barycentric coordinates from sub-areas.
  internal::Work_location location_in(internal::WF f, const Point_3& p) const {
    const auto& t = T_.m;
    const internal::WH h = t.halfedge(f);
    const Point_3 &a = t.point(t.source(h)), &b = t.point(t.target(h)), &c = t.point(t.target(t.next(h)));
    const Kernel::Vector_3 n = CGAL::cross_product(b - a, c - a);
    std::array<double, 3> w{CGAL::cross_product(c - b, p - b) * n, CGAL::cross_product(a - c, p - c) * n,
                            CGAL::cross_product(b - a, p - a) * n};
    double sum = 0;
    for (double& x : w) sum += (x = std::max(0.0, x));
    if (!(sum > 0)) w = {1.0 / 3, 1.0 / 3, 1.0 / 3}, sum = 1;
    for (double& x : w) x /= sum;
    return {f, w};
  }

  void build_outputs() {
    const auto& m = S_.m;
    faces_.clear();
    for (internal::WF f : m.faces()) {
      internal::WH h = m.halfedge(f);
      std::array<std::size_t, 3> t{std::size_t(m.source(h)), std::size_t(m.target(h)), std::size_t(m.target(m.next(h)))};
      if (S_.reversed) std::swap(t[1], t[2]);
      faces_.push_back(t);
    }
    src_pts_.clear();
    tgt_pts_.clear();
    tgt_loc_.clear();
    verr_.clear();
    for (internal::WV v : m.vertices()) {
      src_pts_.push_back(S_.input_position(v));
      const Input_location l = cp_.work_to_input(1, img_[v]);
      tgt_loc_.push_back(l);
      std::array<double, 3> q{{0, 0, 0}};
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) q[k] += l.b[i] * T_.input_points[T_.orig_tri[l.face][i]][k];
      tgt_pts_.push_back(q);
      verr_.push_back(100 * target_field(es_, img_[v]));
    }
    stats_.flipped_faces = flipped_;
  }

  const Cross_param& cp_;
  const internal::Layout_mesh& T_;
  const internal::Base_parameterization& PT_;
  const internal::Base_locator& locT_;
  internal::Layout_mesh S_;
  internal::Base_parameterization P_;
  internal::Base_locator locS_;
  std::vector<internal::Work_location> img_; ///< per source vertex: its image on the target (M_st)
  std::vector<Point_3> pos_;                 ///< per source vertex: M_st's point (working coordinates)
  std::vector<double> e_, es_;               ///< e(v) per target vertex, and smoothed
  std::vector<double> edge_error_;           ///< Eq. 2 per source edge
  std::vector<double> edge_chord_;           ///< per source edge: M_st's edge midpoint's distance from F(midpoint)
  std::vector<double> face_chord_;           ///< per source face: M_st's centroid's distance from F(centroid)
  std::vector<char> folded_;                 ///< per source face: M_st's face flipped against the target
  std::vector<internal::Work_location> pre_; ///< per target vertex: its preimage on the source, F^-1(v)
  /// What measure() located on the target (corner_at() of a base location), by vertex, edge midpoint and face
  /// centroid, with what it depends on.
  struct Measure_cache {
    std::size_t valid = 0, valid_edges = 0, valid_faces = 0; // entries below these are filled in
    std::vector<Corner> vertex;
    std::vector<char> same;                           // per vertex: location unchanged in this measure()
    std::vector<std::array<internal::WV, 3>> corners; // per face: corners from its halfedge
    std::vector<char> face_same;                      // per face: corners and their locations unchanged
    std::vector<Corner> centroid;
    std::vector<std::array<std::size_t, 3>> edge;     // per edge: source, target, face of its halfedge
    std::vector<Corner> mid;
  } cache_;
  unsigned threads_ = 1; ///< threads of measure() (named parameter `number_of_threads`)
  std::vector<char> dirty_;                  ///< per source face: changed by a split of the current round
  std::vector<unsigned char> refused_;       ///< per target vertex: rounds its insertion was refused (up to 2)
  std::size_t flipped_ = 0;
  double max_e_ = 0, l2_e_ = 0, max_chord_ = 0, eps_ = 0;
  std::function<void(const std::string&)> progress_;
  // State of the fold repair: whether it runs (the strict fold test, splits recorded), the folds a split may
  // add, the change in folded faces of the last acceptable() test and of the current repair, and the vertices
  // the current repair made.
  bool repairing_ = false;
  int fold_slack_ = 0;
  mutable int fold_change_ = 0;
  int fold_total_ = 0;
  std::vector<internal::WV> made_;
  std::vector<std::array<std::size_t, 3>> faces_;
  std::vector<std::array<double, 3>> src_pts_, tgt_pts_;
  std::vector<Input_location> tgt_loc_;
  std::vector<double> verr_;
  Bijectivity_certificate cert_;
  Remeshing_statistics stats_;
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
  r.copy_to(0, out_source);
  r.copy_to(1, out_target);
  return r.statistics();
}

} // namespace crossparam

#endif // CROSSPARAM_COMPATIBLE_REMESHING_H

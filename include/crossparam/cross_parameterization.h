// SPDX-License-Identifier: GPL-3.0-or-later
// Cross-parameterization (Kraevoy & Sheffer 2004, §4): the bijective map F = Ft^-1 . Fst . Fs between a source
// and a target mesh over their common base mesh, made low-distortion by local smoothing, certified one-to-one.
#ifndef CROSSPARAM_CROSS_PARAMETERIZATION_H
#define CROSSPARAM_CROSS_PARAMETERIZATION_H

#include <crossparam/certificate.h>
#include <crossparam/metrics.h>
#include <crossparam/patch_layout.h>
#include <crossparam/smoothing.h>
#include <crossparam/internal/map_smoothing.h>
#include <crossparam/types.h>
#include <crossparam/internal/base_locator.h>
#include <crossparam/internal/parallel.h>
#include <crossparam/internal/time_budget.h>

#include <CGAL/Polygon_mesh_processing/locate.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <numeric>
#include <set>

namespace crossparam {

/// Counts, figures and timings of one cross-parameterization.
struct Cross_parameterization_statistics {
  Layout_statistics layout;
  Smoothing_report smoothing_source, smoothing_target;
  unsigned smoothing_best_iteration = 0; ///< passes after which the kept (least distorted) state was reached
  Smoothing_report smoothing_map;        ///< the smoothing of F itself (`map_smoothing`), after the §4.2 smoothing
  unsigned smoothing_map_best_iteration = 0; ///< its passes up to the kept state (0: none improved F)
  /// The map smoothing's as-rigid-as-possible energy of F before it (internal/map_smoothing.h; 0 for a
  /// scaled rigid motion), and of the kept state; both 0 without map smoothing.
  double map_energy_initial = 0, map_energy = 0;
  std::size_t protrusion_warps = 0;  ///< base triangles re-aligned by align_protrusions (descriptor-guided)
  std::size_t protrusion_features = 0; ///< feature pairs added at squeezed protrusion tips (after the user's)
  std::size_t extremity_features = 0;  ///< feature pairs added at mis-mapped extremities (after those)
  std::size_t extremity_candidates = 0; ///< extremity pairs found by the probe (kept or not)
  /// With the extremity selection: the worst descriptor mismatch of the candidate maps made without and with
  /// the extremity pairs (0 when no candidate was made)
  double mismatch_without_extremities = 0, mismatch_with_extremities = 0;
  Distortion distortion_initial;  ///< of F right after the mean-value parameterization (§4.1)
  Distortion distortion;          ///< of the final F
  bool stretch_reweighted_source = false; ///< the mean-value weights needed stretch reweighting (§4.1 note)
  bool stretch_reweighted_target = false;
  /// Per mesh, the largest vertex stretch of its final parameterization over the median one (1 is even; a
  /// squeezed protrusion gives 10^3 and more, and the map is nearly singular there).
  double squeeze_source = 0, squeeze_target = 0;
  /// The map is one made on copies of the meshes while its features were chosen (the protrusion probe's or
  /// the selected candidate of the extremity selection: the same features, options and refined meshes), so
  /// §4.1-4.2 were not run again: their figures above are that map's, their seconds below are 0 and the time
  /// is in seconds_probe or seconds_selection.
  bool map_adopted = false;
  double seconds_probe = 0;            ///< the first map that finds the protrusion and extremity features (0 if none was made)
  double seconds_selection = 0;        ///< the two candidate maps of the extremity selection (0 if none was made)
  double seconds_parameterization = 0; ///< §4.1, both meshes
  double seconds_smoothing = 0;        ///< §4.2, both meshes, and the map smoothing
  double seconds_certificate = 0;
  double seconds_total = 0;            ///< layout included
};

namespace internal {
struct Cross_parameterization_access;

/// A map made on copies of the meshes (the protrusion probe, a candidate of the extremity selection), kept
/// so that the final map can adopt its smoothed parameterizations when it is the same map.
struct Made_map {
  bool made = false;
  Feature_correspondence features;
  bool map_smoothing = false;
  std::array<std::uint64_t, 2> refinement{{0, 0}}; ///< each refined mesh's fingerprint (Layout_mesh::fingerprint)
  std::array<std::vector<Base_location>, 2> loc;   ///< both parameterizations after the smoothing
  Cross_parameterization_statistics statistics;
};
} // namespace internal

/// \brief The cross-parameterization between a source and a target mesh (paper §3-4), kept for queries.
///
/// Construction computes the patch layouts (§3), splits edges for the adjacency constraint (§4.2), maps each
/// patch onto its base triangle by mean-value parameterization (§4.1), smooths both parameterizations (§4.2),
/// and proves both one-to-one (`certificate`); a failure throws `Algorithm_error`, never a silent result.
/// Both meshes are refined in place (new vertices appended); queries take and return
/// `CGAL::Polygon_mesh_processing::Face_location`s on the refined meshes, or `Input_location`s against the input.
///
/// Besides the user's meshes, the object keeps its own refined copy of each (`Refined_mesh`, types.h): the
/// same refinement in working coordinates, queried with `Mesh_side` and `Refined_location`s (`working_mesh`,
/// `locate`, `image`, `to_input`), or as plain arrays in the user's units (`refined_mesh`,
/// `base_atlas_coordinates`).
///
/// Kernel: every computation is made on those copies with the fixed kernel `crossparam::Kernel` (EPICK: exact
/// predicates, double constructions); the user's point type is read through `CGAL::to_double`, so any kernel's
/// points are accepted and no `geom_traits` named parameter is taken.
///
/// \tparam SourceMesh, TargetMesh models of `MutableFaceGraph` (e.g. `CGAL::Surface_mesh`, `CGAL::Polyhedron_3`).
/// Named parameters (source pack; those of `compute_patch_layouts` apply too):
///   - `CGAL::parameters::number_of_iterations` (unsigned, default 200): smoothing passes at most;
///   - `crossparam::parameters::smoothing_tolerance` (double, default 1e-4 base-edge units);
///   - `crossparam::parameters::smoothing_weights` (a `SmoothingWeights` model, default `Mean_value_weights`);
///   - `crossparam::parameters::apply_smoothing` (bool, default true);
///   - `crossparam::parameters::number_of_threads` (unsigned, default 0: one per hardware thread): the two
///     meshes are smoothed on a thread each, the distortion is measured on as many; the map does not depend on it;
///   - `crossparam::parameters::time_limit` (double, seconds, default none) and `best_effort` (bool, default
///     false): the constructor's time budget, checked between its steps, at every stretch-reweighting round
///     and every smoothing round; when it runs out it throws `Time_limit_error`, or with `best_effort`, during
///     the smoothing, keeps the best smoothing state reached and finishes (certificate included).
///
/// `crossparam::parameters::progress` (a callable with a `const std::string&`, default none) receives one line
/// after each step and each smoothing round.
///
/// Work bounds: the protrusion probe is one more map on copies; the layout traces one path per base edge;
/// the initial parameterization solves one linear system per patch, at most 12 more with stretch reweighting;
/// the smoothing makes at most `number_of_iterations` passes over the vertices.
template <class SourceMesh, class TargetMesh>
class Cross_parameterization {
public:
  /// Default of `extremity_persistence`, in units of sqrt(area). The fingertips of the hands of the wider
  /// bench rise 0.12-0.34 above their saddles, a horse's ears and hooves 0.10-0.12; the maxima made by the edge
  /// graph's jagged distances and by small bumps rise a few hundredths. Over the wider bench the accuracy is
  /// flat from 0.03 to 0.1 (mean 0.042-0.043) and falls apart at 0.2, where fingertips stop counting
  /// (doc/results.md); 0.05 is inside the flat range, at half the smallest tip that must count.
  static constexpr double default_extremity_persistence = 0.05;
  /// The extremity selection keeps the pairs only if their map's worst descriptor mismatch is below
  /// (1 - this) times that of the map without them: closer figures are a tie, and a tie keeps the map with
  /// the user's features (and the protrusion features) alone. On the built-in creatures the two figures differ
  /// by 4e-5 of their value, where the pairs repair nothing; where they do (a fingertip mapped onto the palm)
  /// the worst mismatch falls by 10-50 %. Over the wider bench the accuracy is flat for margins from 0 to 0.1
  /// (mean 0.0387-0.0390, doc/algorithms.md); 0.01 only separates ties.
  static constexpr double extremity_selection_margin = 0.01;

  using Source_location = CGAL::Polygon_mesh_processing::Face_location<SourceMesh, double>;
  using Target_location = CGAL::Polygon_mesh_processing::Face_location<TargetMesh, double>;

  template <typename NP_T1 = bool, typename NP_Tag1 = CGAL::internal_np::all_default_t,
            typename NP_Base1 = CGAL::internal_np::No_property, typename NP_T2 = bool,
            typename NP_Tag2 = CGAL::internal_np::all_default_t, typename NP_Base2 = CGAL::internal_np::No_property>
  Cross_parameterization(SourceMesh& tm_s, TargetMesh& tm_t, const Feature_correspondence& features,
                         const CGAL::Named_function_parameters<NP_T1, NP_Tag1, NP_Base1>& np_source =
                             CGAL::parameters::default_values(),
                         const CGAL::Named_function_parameters<NP_T2, NP_Tag2, NP_Base2>& np_target =
                             CGAL::parameters::default_values())
      : tm_s_(tm_s), tm_t_(tm_t) {
    using CGAL::parameters::choose_parameter;
    using CGAL::parameters::get_parameter;
    using clock = std::chrono::steady_clock;
    auto sec = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
    const auto t0 = clock::now();
    Smoothing_options so;
    so.max_iterations = choose_parameter(get_parameter(np_source, CGAL::internal_np::number_of_iterations), 200u);
    so.tolerance = choose_parameter(get_parameter(np_source, internal_np::smoothing_tolerance_t()), 1e-4);
    const bool smooth = choose_parameter(get_parameter(np_source, internal_np::apply_smoothing_t()), true);
    const bool smooth_map = choose_parameter(get_parameter(np_source, internal_np::map_smoothing_t()), false);
    const bool global_steps = choose_parameter(get_parameter(np_source, internal_np::map_smoothing_global_steps_t()), true);
    auto weights = choose_parameter(get_parameter(np_source, internal_np::smoothing_weights_t()), Mean_value_weights());
    const unsigned threads_requested = choose_parameter(get_parameter(np_source, internal_np::number_of_threads_t()), 0u);
    threads_ = internal::thread_count(threads_requested);
    const internal::Time_budget budget = internal::Time_budget::from(np_source);
    const auto progress = choose_parameter(get_parameter(np_source, internal_np::progress_t()),
                                           std::function<void(const std::string&)>());
    auto say = [&progress](const std::string& line) {
      if (progress) progress(line);
    };

    // Contracts first, once (the protrusion probe below is built from checked copies and skips them).
    if (!internal::are_inputs_checked(np_source)) internal::check_layout_inputs(tm_s, tm_t, features, np_source, np_target);

    // Protrusion features: a first map, on copies of the meshes, finds the protrusions it squeezes; a feature
    // pair at each tip makes the limb a corner of the base domain instead of a spot inside a patch. On request,
    // the same probe also gives pairs at the extremities it sends to the wrong place (extremity_tips).
    features_ = features;
    const bool protrusions = choose_parameter(get_parameter(np_source, internal_np::protrusion_features_t()), true);
    const bool extremities = choose_parameter(get_parameter(np_source, internal_np::extremity_features_t()), true);
    const bool select = choose_parameter(get_parameter(np_source, internal_np::select_extremity_features_t()), true);
    const double persistence = choose_parameter(get_parameter(np_source, internal_np::extremity_persistence_t()),
                                                default_extremity_persistence);
    if (!(persistence > 0) || !std::isfinite(persistence))
      throw Input_error("extremity_persistence must be a positive number, not " + std::to_string(persistence));
    // The maps made on copies while the features are chosen: the probe, the selection's candidates without
    // and with the extremity pairs. The final map adopts the one that is the same map (see map_adopted).
    std::array<internal::Made_map, 3> made;
    if (protrusions || extremities) {
      using CGAL::parameters::number_of_iterations;
      using namespace crossparam::parameters;
      const bool flips = choose_parameter(get_parameter(np_source, internal_np::apply_path_flips_t()), true);
      const bool consistent = choose_parameter(get_parameter(np_source, internal_np::consistent_paths_t()), true);
      const bool straighten = choose_parameter(get_parameter(np_source, internal_np::straighten_paths_t()), false);
      // A map with features `fc` and this map's options (neither protrusion nor extremity features), made on
      // copies of the inputs in the same vertex order, so that feature indices carry over (the copy assumes
      // the checked, closed manifold meshes), with or without map smoothing; returns use(map). The meshes passed
      // in are not touched.
      auto on_copies = [&](const Feature_correspondence& fc, unsigned threads, bool with_map_smoothing,
                           const auto& use) {
        Surface_mesh cs, ct;
        internal::copy_in_order(tm_s, choose_parameter(get_parameter(np_source, CGAL::internal_np::vertex_point),
                                                       get_const_property_map(CGAL::vertex_point, tm_s)), cs);
        internal::copy_in_order(tm_t, choose_parameter(get_parameter(np_target, CGAL::internal_np::vertex_point),
                                                       get_const_property_map(CGAL::vertex_point, tm_t)), ct);
        const Cross_parameterization<Surface_mesh, Surface_mesh> m(
            cs, ct, fc,
            internal::inputs_checked(protrusion_features(false, extremity_features(false, smoothing_weights(weights,
                smoothing_tolerance(so.tolerance, apply_smoothing(smooth, map_smoothing(with_map_smoothing,
                    map_smoothing_global_steps(global_steps, apply_path_flips(flips, consistent_paths(consistent,
                        straighten_paths(straighten, number_of_threads(threads, time_limit(budget.remaining(),
                            best_effort(budget.best_effort(), number_of_iterations(so.max_iterations))))))))))))))));
        return use(m);
      };
      Feature_correspondence tips, ends;
      double probe_mismatch = 0; // the probe's worst descriptor mismatch, for the selection below
      // The probe finds the protrusions from the squeeze of the paper's parameterizations: no map smoothing.
      on_copies(features, threads_requested, false, [&](const auto& probe) {
        if (protrusions) tips = probe.protrusion_tips();
        if (extremities) ends = probe.extremity_tips(tips, persistence);
        if (!ends.empty() && select && tips.empty() && !smooth_map)
          probe_mismatch = probe.max_descriptor_mismatch(features.size());
        made[0] = probe.made_map(false);
        return 0;
      });
      features_.insert(features_.end(), tips.begin(), tips.end());
      stats_.protrusion_features = tips.size();
      stats_.extremity_candidates = ends.size();
      stats_.seconds_probe = sec(t0, clock::now());
      say("map: protrusion probe: " + std::to_string(tips.size()) + " feature pairs added" +
          (extremities ? ", " + std::to_string(ends.size()) + " found at extremities" : std::string()));
      if (!ends.empty() && select) {
        // The extremity selection: a map with the pairs and one without, each on fresh copies of the inputs
        // (one thread each); the pairs stay if their map's worst disagreement with the distances to the
        // user's features is smaller, by more than extremity_selection_margin. The worst point, not the mean:
        // a pair fixes one limb mapped onto another, a gross local error that a mean over the whole surface
        // hides.
        const auto ts = clock::now();
        Feature_correspondence with = features_;
        with.insert(with.end(), ends.begin(), ends.end());
        // A candidate that fails (a layout the added pairs make impossible, say) counts as infinitely bad; the
        // time limit is not a failure of the candidate and ends the whole computation.
        auto candidate = [&](const Feature_correspondence& fc, unsigned threads, internal::Made_map& kept) -> double {
          try {
            return on_copies(fc, threads, smooth_map, [&](const auto& m) {
              kept = m.made_map(smooth_map);
              return m.max_descriptor_mismatch(features.size());
            });
          } catch (const Time_limit_error&) {
            throw;
          } catch (const Error&) {
            return HUGE_VAL;
          }
        };
        // Without protrusion pairs or map smoothing, the map without the extremity pairs is the probe itself:
        // its figure is taken, and only the map with them is made.
        double without = probe_mismatch, with_ends = 0;
        if (tips.empty() && !smooth_map) {
          with_ends = candidate(with, threads_requested, made[2]);
        } else {
          const unsigned each = threads_ >= 2 ? 1u : threads_;
          internal::parallel_invoke(
              threads_, [&] { without = candidate(features_, each, made[1]); },
              [&] { with_ends = candidate(with, each, made[2]); });
        }
        stats_.mismatch_without_extremities = without;
        stats_.mismatch_with_extremities = with_ends;
        stats_.seconds_selection = sec(ts, clock::now());
        if (!(with_ends < (1 - extremity_selection_margin) * without)) ends.clear();
        say("map: extremity selection: worst descriptor mismatch " + std::to_string(without) + " without, " +
            std::to_string(with_ends) + " with; " + (ends.empty() ? "not kept" : "kept"));
      }
      features_.insert(features_.end(), ends.begin(), ends.end());
      stats_.extremity_features = ends.size();
    }

    budget.check("the cross-parameterization", [] { return std::string("before the patch layouts"); });
    std::array<std::vector<int>, 2> work_tri;
    layout_ = internal::compute_patch_layouts_impl(tm_s, tm_t, features_, np_source, np_target, B_, true, &work_tri,
                                                   &link_s_, &link_t_);
    stats_.layout = layout_.statistics;
    {
      auto lengths = base_edge_lengths();
      base_.build(layout_.base_triangles, features_.size(),
                  [&](int a, int b) { return lengths.at({std::min(a, b), std::max(a, b)}); });
    }
    say("map: patch layouts: " + std::to_string(layout_.base_triangles.size()) + " base triangles");
    budget.check("the cross-parameterization", [] { return std::string("after the patch layouts"); });
    const auto t1 = clock::now();

    // A map made on copies while the features were chosen is this one when it has the same features and
    // options and its refinements are these meshes' (the steps are deterministic and do not depend on the
    // number of threads): its smoothed parameterizations are adopted, and §4.1-4.2 are not run again. The
    // certificates below are computed anew all the same.
    auto t2 = t1, t3 = t1;
    stats_.map_adopted = adopt(made, smooth_map);
    if (stats_.map_adopted) {
      say("map: the parameterizations of the map made while choosing the features adopted");
    } else {
      // §4.1: mean-value parameterization of every patch onto its base triangle.
      bool* fallback[2] = {&stats_.stretch_reweighted_source, &stats_.stretch_reweighted_target};
      const unsigned max_stretch_rounds = 12;
      for (int k = 0; k < 2; ++k) {
        P_[k].base = &base_;
        P_[k].mesh = &B_.side[k];
        P_[k].initialize(work_tri[k], B_.path_ends);
        Bijectivity_certificate c = P_[k].certify();
        // A long protrusion inside a patch is squeezed exponentially by any convex-combination map, until its
        // vertices collapse below double precision. Dividing the weights by the local stretch and solving again
        // (Yoshizawa et al. 2004) spreads it out while the weights stay positive, so the map stays one-to-one.
        std::vector<double> factor(B_.side[k].m.number_of_vertices(), 1.0);
        for (unsigned round = 0; !c.valid && round < max_stretch_rounds; ++round) {
          budget.check("the initial parameterization", [&] {
            return std::string(k ? "target" : "source") + ", stretch reweighting round " + std::to_string(round + 1) +
                   " of at most " + std::to_string(max_stretch_rounds);
          });
          *fallback[k] = true;
          std::vector<double> sigma = P_[k].vertex_stretch();
          double mean = 0;
          for (double x : sigma) mean += x;
          mean /= std::max<std::size_t>(1, sigma.size());
          for (std::size_t i = 0; i < factor.size(); ++i) factor[i] /= std::max(sigma[i] / mean, 1e-3);
          double fmean = 0;
          for (double x : factor) fmean += x;
          fmean /= std::max<std::size_t>(1, factor.size());
          for (double& x : factor) x /= fmean;
          P_[k].initialize(work_tri[k], B_.path_ends, &factor);
          c = P_[k].certify();
        }
        if (!c.valid)
          throw Algorithm_error(std::string(k ? "target" : "source") +
                                " initial parameterization is not one-to-one: " + c.message);
      }
      t2 = clock::now();
      locator_[1].build(P_[1]);
      stats_.distortion_initial = measure_distortion();
      say("map: initial parameterization: E_ang " + std::to_string(stats_.distortion_initial.angular));

      // §4.2: local smoothing with the weights policy, in rounds of 5 passes; F's angular distortion is measured
      // after each round and the best state of both parameterizations kept (`start`: the distortion before). The
      // averaging's fixed point is a harmonic-like map with point constraints at the features, which can be worse
      // than an intermediate state: stop after `patience` rounds without improvement, when the largest move of a
      // round's last pass is below the tolerance, or after `max_iterations` passes. `round(passes)` makes the
      // passes and returns that move; `score()` measures the state after a round (lower is better). The map
      // smoothing below runs in the same rounds, scored by its own energy.
      t3 = clock::now();
      auto in_rounds = [&](const char* what, Smoothing_report& report, unsigned& best_iteration, double start,
                           const auto& round, const auto& score) {
        std::array<std::vector<Base_location>, 2> best{P_[0].loc, P_[1].loc};
        double best_score = start;
        unsigned bad = 0, done = 0;
        const unsigned per_round = 5, patience = 2;
        while (done < so.max_iterations) {
          if (budget.stop(std::string("the map's ") + what, [&] {
                return std::to_string(done) + " of at most " + std::to_string(so.max_iterations) + " passes";
              }))
            break; // best effort: keep the best state so far
          const unsigned passes = std::min(per_round, so.max_iterations - done);
          const double moved = round(passes);
          done += passes;
          report.iterations = done;
          say(std::string("map: ") + what + ": " + std::to_string(done) + " passes");
          const double d = score();
          if (d < best_score) {
            best_score = d;
            best = {P_[0].loc, P_[1].loc};
            best_iteration = done;
            bad = 0;
          } else if (++bad >= patience) {
            break;
          }
          if (moved < so.tolerance) break;
        }
        P_[0].loc = std::move(best[0]);
        P_[1].loc = std::move(best[1]); // locator_[1] is rebuilt by the protrusion alignment, next
        return best_score;
      };
      if (smooth) {
        auto ws = weights, wt = weights;
        ws.prepare(B_.side[0].m);
        wt.prepare(B_.side[1].m);
        internal::Local_smoother<decltype(ws)> smooth_s(P_[0], ws);
        internal::Local_smoother<decltype(wt)> smooth_t(P_[1], wt);
        in_rounds("smoothing", stats_.smoothing_source, stats_.smoothing_best_iteration,
                  stats_.distortion_initial.angular,
                  [&](unsigned passes) {
          // The two meshes' passes are independent (each moves only its own vertices): one thread each.
          internal::parallel_invoke(
              threads_,
              [&] {
                for (unsigned i = 0; i < passes; ++i)
                  stats_.smoothing_source.last_max_move = smooth_s.pass(stats_.smoothing_source);
              },
              [&] {
                for (unsigned i = 0; i < passes; ++i)
                  stats_.smoothing_target.last_max_move = smooth_t.pass(stats_.smoothing_target);
              });
          return std::max(stats_.smoothing_source.last_max_move, stats_.smoothing_target.last_max_move);
        }, [&] {
          locator_[1].build(P_[1]);
          return measure_distortion().angular;
        });
        stats_.smoothing_target.iterations = stats_.smoothing_source.iterations;
      }
      {
        // Protrusion alignment, kept only if F stays less distorted than the initial map (with meaningless
        // descriptors, e.g. a wrong correspondence, the warps are unfounded).
        locator_[1].build(P_[1]);
        std::vector<Base_location> before = P_[0].loc;
        stats_.protrusion_warps = align_protrusions();
        if (stats_.protrusion_warps > 0) {
          const Distortion d = measure_distortion();
          if (!(d.angular < stats_.distortion_initial.angular && d.l2_stretch < stats_.distortion_initial.l2_stretch)) {
            P_[0].loc = std::move(before);
            stats_.protrusion_warps = 0;
          }
        }
      }
      if (smooth && smooth_map) {
        // The smoothing of F itself (internal/map_smoothing.h): the source's vertices move so that F is
        // as rigid as possible from the source onto the target, with the source's smoothing weights, each round
        // scored by that energy. locator_[1] is current: the protrusion alignment built it and moves the
        // source alone, as do these passes.
        auto ws = weights;
        ws.prepare(B_.side[0].m);
        internal::Map_smoother<decltype(ws)> smooth_f(P_[0], P_[1], locator_[1], ws, global_steps);
        stats_.map_energy_initial = smooth_f.energy();
        stats_.map_energy = in_rounds("map smoothing", stats_.smoothing_map, stats_.smoothing_map_best_iteration,
                  stats_.map_energy_initial,
                  [&](unsigned passes) {
          for (unsigned i = 0; i < passes; ++i)
            stats_.smoothing_map.last_max_move = smooth_f.pass(stats_.smoothing_map);
          return stats_.smoothing_map.last_max_move;
        }, [&] { return smooth_f.energy(); });
      }
    }
    const auto t4 = clock::now();
    (void)budget.stop("the cross-parameterization", [] { return std::string("before the certificates"); });
    for (int k = 0; k < 2; ++k) {
      cert_[k] = P_[k].certify();
      if (!cert_[k].valid)
        throw Algorithm_error(std::string(k ? "target" : "source") + " parameterization failed its certificate: " +
                              cert_[k].message);
    }
    const auto t5 = clock::now();
    locator_[0].build(P_[0]);
    locator_[1].build(P_[1]);
    stats_.distortion = measure_distortion();
    stats_.squeeze_source = squeeze(P_[0]);
    stats_.squeeze_target = squeeze(P_[1]);
    check_features(features_);
    stats_.seconds_parameterization = stats_.map_adopted ? 0 : sec(t1, t2);
    stats_.seconds_smoothing = stats_.map_adopted ? 0 : sec(t3, t4);
    stats_.seconds_certificate = sec(t4, t5);
    stats_.seconds_total = sec(t0, clock::now());
  }

  // ---- queries on the refined meshes ----

  /// F: the image on the target of a point of the (refined) source.
  Target_location to_target(const Source_location& p) const { return map<1>(p, link_s_, link_t_, face_index_s_); }
  /// F^-1: the image on the source of a point of the (refined) target.
  Source_location to_source(const Target_location& p) const { return map<0>(p, link_t_, link_s_, face_index_t_); }

  /// Image on the target of source vertex v (index in vertices(source) order), against the target as given.
  Input_location source_vertex_to_target_input(std::size_t v) const { return vertex_to_input(0, v); }
  /// Image on the source of target vertex v, against the source as given.
  Input_location target_vertex_to_source_input(std::size_t v) const { return vertex_to_input(1, v); }

  /// Base-domain location of vertex v (index in the refined `vertices(tm)` order) of mesh `side`.
  const Base_location& base_location(Mesh_side side, std::size_t v) const {
    return P_[internal::side_index(side)][internal::WV(internal::WV::size_type(v))];
  }

  const Patch_layout& layout() const { return layout_; }
  /// The bijectivity certificate of mesh `side`'s map onto the base mesh; always valid on a constructed object
  /// (the constructor throws otherwise), kept for reporting.
  const Bijectivity_certificate& certificate(Mesh_side side) const { return cert_[internal::side_index(side)]; }
  const Cross_parameterization_statistics& statistics() const { return stats_; }
  /// Vertex count of input mesh `side`, before any refinement.
  std::size_t input_vertices(Mesh_side side) const { return B_.side[internal::side_index(side)].n_original_vertices; }

  // ---- the refined meshes (types.h, "Refined meshes") ----

  /// The refined copy of mesh `side` in working coordinates (types.h, "Refined meshes"): vertex i is vertex i
  /// of the user's refined mesh; its faces are those of the user's refined mesh as vertex triples, in an order
  /// of their own, oriented outward. Smoothing-weights policies see this mesh; `Refined_location`s are on it.
  const Refined_mesh& working_mesh(Mesh_side side) const { return B_.side[internal::side_index(side)].m; }

  /// A point of `working_mesh(side)` in the user's coordinates (undoes the working translation and scale; the
  /// input vertices come back up to rounding, `input_point` gives exact positions).
  Point_3 to_input_units(Mesh_side side, const Point_3& p) const {
    const std::array<double, 3> q = B_.side[internal::side_index(side)].input_point(p);
    return Point_3(q[0], q[1], q[2]);
  }

  /// The refined mesh `side` in the user's units: the points of `working_mesh(side)` through `to_input_units`
  /// (original vertices first, in input order, then one per split), and per face of `working_mesh(side)` its
  /// corners in halfedge order, reversed if the user's faces point inward, so the faces are oriented as the
  /// input's.
  Indexed_triangle_mesh refined_mesh(Mesh_side side) const {
    const internal::Layout_mesh& L = B_.side[internal::side_index(side)];
    Indexed_triangle_mesh out;
    out.points.reserve(L.m.number_of_vertices());
    for (internal::WV v : L.m.vertices()) out.points.push_back(to_input_units(side, L.m.point(v)));
    out.faces.reserve(L.m.number_of_faces());
    for (internal::WF f : L.m.faces()) {
      const std::array<internal::WV, 3> vs = corners_as_input(L, f);
      out.faces.push_back({std::size_t(vs[0]), std::size_t(vs[1]), std::size_t(vs[2])});
    }
    return out;
  }

  /// \brief Texture coordinates of the map: per face of `refined_mesh(side)`, the (u, v) of its three corners
  /// (in that face's corner order) in an atlas of the base domain.
  ///
  /// The unit square is cut into `ceil(sqrt(T))` columns and as many rows of square tiles (T the number of
  /// base triangles); base triangle t owns tile t (row-major from (0, 0)), and its shape (edge lengths of the
  /// base domain) fills the tile inside a margin of a tenth of the tile. A face is placed in the frame of the
  /// base triangle it is parameterized over, with at most one neighbour unfolded beside it (a face across a base
  /// edge reaches into the neighbouring tile's margin). Corresponding points of the source and the target have
  /// the same coordinates, so one texture shows the correspondence on both meshes.
  std::vector<std::array<std::array<double, 2>, 3>> base_atlas_coordinates(Mesh_side side) const {
    // The part of a tile around the triangle's frame, and the part the frame's longest extent fills: each
    // base triangle is drawn at 1 - 2 * tile_margin of its tile.
    constexpr double tile_margin = 0.1, tile_extent = 0.8;
    const std::size_t nt = base_.tri.size();
    const int cols = int(std::ceil(std::sqrt(double(nt))));
    auto uv = [&](int t, const internal::Point_2& p) {
      double lo_x = HUGE_VAL, hi_x = -HUGE_VAL, lo_y = HUGE_VAL, hi_y = -HUGE_VAL;
      for (const auto& q : base_.q[t])
        lo_x = std::min(lo_x, q.x()), hi_x = std::max(hi_x, q.x()), lo_y = std::min(lo_y, q.y()), hi_y = std::max(hi_y, q.y());
      const double size = std::max(hi_x - lo_x, hi_y - lo_y);
      const double cell = 1.0 / cols;
      const double u = (t % cols + tile_margin + tile_extent * (p.x() - lo_x) / size) * cell;
      const double v = (t / cols + tile_margin + tile_extent * (p.y() - lo_y) / size) * cell;
      return std::array<double, 2>{u, v};
    };
    const int k = internal::side_index(side);
    const internal::Layout_mesh& L = B_.side[k];
    std::vector<std::array<std::array<double, 2>, 3>> out;
    out.reserve(L.m.number_of_faces());
    for (internal::WF f : L.m.faces()) {
      const std::array<internal::WV, 3> vs = corners_as_input(L, f);
      std::array<const Base_location*, 3> ls{&P_[k][vs[0]], &P_[k][vs[1]], &P_[k][vs[2]]};
      std::array<internal::Point_2, 3> q;
      int c, n;
      if (!base_.canonical_frame(ls, c, n, q)) throw Algorithm_error("internal error: face outside every chart");
      out.push_back({uv(c, q[0]), uv(c, q[1]), uv(c, q[2])});
    }
    return out;
  }

  /// The base location of the point `l` of `working_mesh(side)`: where the parameterization of that mesh
  /// sends it (interpolated in the face's chart).
  Base_location base_location(Mesh_side side, const Refined_location& l) const {
    return P_[internal::side_index(side)].at(l.face, l.b);
  }

  /// The point of `working_mesh(side)` whose base location is `b` (the inverse of the parameterization of
  /// that mesh). \pre `b` is a location of the base domain (`b.tri` a base triangle, barycentrics >= 0).
  Refined_location locate(Mesh_side side, const Base_location& b) const {
    return locator_[internal::side_index(side)].locate(b);
  }

  /// The image under the map of the point `l` of `working_mesh(side)`: a point of the other mesh's working
  /// mesh (F for the source, F^-1 for the target).
  Refined_location image(Mesh_side side, const Refined_location& l) const {
    return locate(other_side(side), base_location(side, l));
  }

  /// The point `l` of `working_mesh(side)` against input mesh `side` as the user gave it.
  Input_location to_input(Mesh_side side, const Refined_location& l) const {
    const internal::Layout_mesh& L = B_.side[internal::side_index(side)];
    const int o = L.forig[l.face];
    internal::WH h = L.m.halfedge(l.face);
    internal::WV vs[3] = {L.m.source(h), L.m.target(h), L.m.target(L.m.next(h))};
    Input_location r;
    r.face = std::size_t(o);
    for (int i = 0; i < 3; ++i) {
      std::array<double, 3> rep;
      if (!L.rep_in(vs[i], o, rep)) throw Algorithm_error("internal error: refined face outside its input face");
      for (int j = 0; j < 3; ++j) r.b[j] += l.b[i] * rep[j];
    }
    return r;
  }

  /// The point of input mesh `side` at `l`, in the user's coordinates, from the input's points as given.
  std::array<double, 3> input_point(Mesh_side side, const Input_location& l) const {
    const internal::Layout_mesh& L = B_.side[internal::side_index(side)];
    std::array<double, 3> q{{0, 0, 0}};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) q[k] += l.b[i] * L.input_points[L.orig_tri[l.face][i]][k];
    return q;
  }
  /// The vertices of input face `face` of mesh `side` (input vertex indices, in the face's input order): the
  /// corners that the barycentric coordinates of an `Input_location` on that face refer to.
  const std::array<std::size_t, 3>& input_face_vertices(Mesh_side side, std::size_t face) const {
    return B_.side[internal::side_index(side)].orig_tri.at(face);
  }
  /// Face count of input mesh `side`, before any refinement.
  std::size_t input_faces(Mesh_side side) const { return B_.side[internal::side_index(side)].orig_tri.size(); }
  /// The features of the map: the user's, then the protrusion features added (statistics().protrusion_features),
  /// then the extremity features kept (statistics().extremity_features).
  const Feature_correspondence& features() const { return features_; }

  /// \brief How far the map is from preserving the geodesic distances to the first `dims` features, on average.
  ///
  /// With d_k the edge-graph geodesic distance to feature k over sqrt(area), on each mesh, and the mismatch of
  /// a source vertex x the root mean square over k < `dims` of d_k(x) - d_k(F(x)) (the target's distances
  /// interpolated linearly at F(x)): its area-weighted mean over the source's vertices. Zero for an isometry
  /// that keeps the features; needs no ground truth. `dims` is clamped to the number of features (0 gives 0).
  double descriptor_mismatch(std::size_t dims) const { return mismatch_summary(dims).first; }
  /// \brief The largest mismatch of a source vertex (see descriptor_mismatch): where the map disagrees most
  /// with the distances to the first `dims` features. The extremity selection compares this figure.
  double max_descriptor_mismatch(std::size_t dims) const { return mismatch_summary(dims).second; }

  /// \brief Feature pairs that would remove this map's worst squeeze: one per protrusion tip.
  ///
  /// A protrusion without a feature inside one patch (a limb, a tail, an ear) is squeezed exponentially by
  /// the parameterization: its vertices' stretch is 10^4 to 10^8 times the median. Such a cluster (connected
  /// vertices above 100 times the median, at least `min_size` of them, peaking above `min_squeeze` times the
  /// median) is paired through its extremity (see extremity_tips) when that extremity and one of the other
  /// mesh are each other's nearest by geodesic-distance descriptor: the distances to the features and to this
  /// map's anchors (see anchor_distances), which tell mirror-symmetric limbs apart. Otherwise its
  /// tip, where the stretch peaks, is paired with the vertex of the other mesh with the nearest descriptor, or
  /// with the other mesh's tip if that vertex lies in a squeezed cluster there. Vertices are input vertices
  /// (the nearest one to a split vertex); no vertex already a feature is used again.
  Feature_correspondence protrusion_tips(double min_squeeze = 1e4, std::size_t min_size = 20) const {
    using internal::WV;
    struct Cluster {
      WV tip;
      double squeeze = 0;
      std::size_t size = 0;
    };
    std::array<std::vector<Cluster>, 2> clusters;
    std::array<std::vector<int>, 2> cluster_of;
    for (int k = 0; k < 2; ++k) {
      const internal::Work_mesh& m = B_.side[k].m;
      const std::vector<double> st = relative_stretch(P_[k]);
      if (st.empty()) return {};
      const double member = 100; // stretch of a cluster's vertices, over the median
      cluster_of[k].assign(m.number_of_vertices(), -1);
      for (WV v : m.vertices()) {
        if (cluster_of[k][v] >= 0 || !(st[v] >= member)) continue;
        const int id = int(clusters[k].size());
        Cluster c{v, 0, 0};
        std::vector<WV> queue{v};
        cluster_of[k][v] = id;
        for (std::size_t i = 0; i < queue.size(); ++i) {
          if (st[queue[i]] > c.squeeze) c = {queue[i], st[queue[i]], 0};
          for (WV w : CGAL::vertices_around_target(queue[i], m))
            if (cluster_of[k][w] < 0 && st[w] >= member) {
              cluster_of[k][w] = id;
              queue.push_back(w);
            }
        }
        c.size = queue.size();
        clusters[k].push_back(c);
      }
    }
    auto strong = [&](int k, int c) {
      return c >= 0 && clusters[k][c].squeeze >= min_squeeze && clusters[k][c].size >= min_size;
    };
    auto input_vertex = [&](int k, WV v) { return nearest_input_vertex(k, v); };
    // The input vertex of the other mesh whose descriptor is nearest to v's.
    auto partner = [&](int k, WV v) {
      const internal::Layout_mesh &A = B_.side[k], &B = B_.side[1 - k];
      double best = HUGE_VAL;
      WV arg(0);
      for (std::size_t i = 0; i < B.n_original_vertices; ++i) {
        const WV u{WV::size_type(i)};
        const double d = descriptor_distance(A.desc[v], B.desc[u]);
        if (d < best) {
          best = d;
          arg = u;
        }
      }
      return arg;
    };
    std::array<std::set<std::size_t>, 2> used;
    for (const Feature_pair& p : features_) {
      used[0].insert(p.source);
      used[1].insert(p.target);
    }
    Feature_correspondence out;
    auto add = [&](WV vs, WV vt) {
      const std::size_t a = std::size_t(input_vertex(0, vs)), b = std::size_t(input_vertex(1, vt));
      if (used[0].count(a) || used[1].count(b)) return;
      used[0].insert(a);
      used[1].insert(b);
      out.push_back({a, b});
    };
    // A cluster is paired through the extremities first: the extremity inside it (the most persistent) with
    // the extremity of the other mesh that is its mutual nearest by descriptor, a symmetric test, so that
    // neither mesh's choice is imposed on the other (a squeezed leg of one animal is otherwise paired with
    // whichever vertex of the other has the nearest descriptor, at times the tip of the tail). Extremities are
    // those of extremity_tips at the default persistence.
    const std::array<std::vector<std::pair<WV, double>>, 2> ext{extremities(0, default_extremity_persistence),
                                                                extremities(1, default_extremity_persistence)};
    // The distances to the features alone cannot tell a left limb from a right one when the features lie near
    // the plane of symmetry or are few (SHREC'07 animals with 11 features: a squeezed hind leg paired with the
    // other hind leg, or with the tail). This map can: away from its squeezes it is right and keeps the
    // orientation, so the distances to its anchors, as many as there are features, are compared as well.
    // They are made only if some cluster counts.
    bool any_strong = false;
    for (int k = 0; k < 2; ++k)
      for (std::size_t c = 0; c < clusters[k].size(); ++c) any_strong = any_strong || strong(k, int(c));
    const Anchor_distances anchors = any_strong ? anchor_distances(features_.size()) : Anchor_distances();
    // The pair (a on mesh k, b on the other) through the extremities of cluster c of mesh k, if there is one.
    auto through_extremities = [&](int k, int c, WV& a, WV& b) {
      std::size_t i = ext[k].size();
      for (std::size_t x = 0; x < ext[k].size(); ++x)
        if (cluster_of[k][ext[k][x].first] == c && (i == ext[k].size() || ext[k][x].second > ext[k][i].second)) i = x;
      if (i == ext[k].size()) return false;
      const std::size_t j = mutual_nearest_by_descriptor(ext, k, i, &anchors);
      if (j == ext[1 - k].size()) return false;
      a = ext[k][i].first;
      b = ext[1 - k][j].first;
      return true;
    };
    // Otherwise the tip's partner is the vertex of the other mesh with the nearest descriptor, or that mesh's
    // tip if the partner lies in a squeezed cluster of its own.
    std::vector<bool> paired(clusters[1].size(), false);
    for (std::size_t c = 0; c < clusters[0].size(); ++c) {
      if (!strong(0, int(c))) continue;
      WV s, t;
      if (through_extremities(0, int(c), s, t)) {
        if (cluster_of[1][t] >= 0) paired[std::size_t(cluster_of[1][t])] = true;
      } else {
        s = clusters[0][c].tip;
        t = partner(0, s);
        const int ct = cluster_of[1][t];
        if (strong(1, ct)) {
          t = clusters[1][ct].tip;
          paired[std::size_t(ct)] = true;
        }
      }
      add(s, t);
    }
    for (std::size_t c = 0; c < clusters[1].size(); ++c) {
      if (!strong(1, int(c)) || paired[c]) continue;
      WV s, t;
      if (!through_extremities(1, int(c), t, s)) {
        t = clusters[1][c].tip;
        s = partner(1, t);
      }
      add(s, t);
    }
    return out;
  }

  /// \brief Feature pairs at the extremities that this map sends to the wrong place.
  ///
  /// An extremity of a mesh is a local maximum of the geodesic distance to the nearest feature whose
  /// topological persistence (how far it rises above the saddle joining it to a higher maximum) is at least
  /// `min_persistence` √area: the tip of a finger, a limb or a tail without a feature. Extremities of the two
  /// meshes are paired when each is the other's nearest by geodesic-distance descriptor (a symmetric test);
  /// a pair is returned when the map sends the source extremity farther than `min_persistence` √area (of the
  /// target) from its partner and agrees with the descriptors better than F's image does. Vertices already
  /// features (the map's, or in `taken`) are not used again.
  Feature_correspondence extremity_tips(const Feature_correspondence& taken, double min_persistence) const {
    using internal::WV;
    // Per mesh, the extremities: working vertices (the layout's split vertices included, so that the paths do
    // not cut the vertex graph) with their persistence.
    const std::array<std::vector<std::pair<WV, double>>, 2> ext{extremities(0, min_persistence), extremities(1, min_persistence)};
    // Vertices already features (given or in `taken`) are not used again.
    std::array<std::set<std::size_t>, 2> used;
    for (const Feature_correspondence* fc : {&features_, &taken})
      for (const Feature_pair& p : *fc) {
        used[0].insert(p.source);
        used[1].insert(p.target);
      }
    const internal::Layout_mesh& Lt = B_.side[1];
    const double unit_t = std::sqrt(Lt.area());
    Feature_correspondence out;
    for (std::size_t i = 0; i < ext[0].size(); ++i) {
      const std::size_t j = mutual_nearest_by_descriptor(ext, 0, i);
      if (j == ext[1].size()) continue;
      const WV vs = ext[0][i].first, vt = ext[1][j].first;
      // How far F sends the source extremity from its partner, over sqrt(target area).
      const double e = std::sqrt(CGAL::squared_distance(internal::point_at(Lt.m, locator_[1].locate(P_[0][vs])),
                                                        Lt.m.point(vt))) / unit_t;
      // The pair must be needed (F misses the partner by at least the extremity scale) and agree with the
      // descriptors better than F's own image does.
      const double agree = descriptor_distance(B_.side[0].desc[vs], Lt.desc[vt]);
      if (e < min_persistence || !(agree < image_mismatch(vs))) continue;
      const std::size_t a = std::size_t(nearest_input_vertex(0, vs)), b = std::size_t(nearest_input_vertex(1, vt));
      if (used[0].count(a) || used[1].count(b)) continue;
      used[0].insert(a);
      used[1].insert(b);
      out.push_back({a, b});
    }
    return out;
  }


private:
  friend struct internal::Cross_parameterization_access;
  template <class, class> friend class Cross_parameterization; // the probe's and the candidates' made_map

  /// This map's features, options and smoothed parameterizations, for a map that may turn out to be the same.
  internal::Made_map made_map(bool with_map_smoothing) const {
    internal::Made_map m;
    m.made = true;
    m.features = features_;
    m.map_smoothing = with_map_smoothing;
    for (int k = 0; k < 2; ++k) {
      m.refinement[std::size_t(k)] = B_.side[k].fingerprint();
      m.loc[std::size_t(k)] = P_[k].loc;
    }
    m.statistics = stats_;
    return m;
  }

  /// Adopts the smoothed parameterizations and their figures of the map in `made` that is this map (the same
  /// features, map smoothing and refined meshes); false if there is none. The layouts and the base domain are
  /// this map's already.
  bool adopt(std::array<internal::Made_map, 3>& made, bool with_map_smoothing) {
    const std::array<std::uint64_t, 2> refinement{{B_.side[0].fingerprint(), B_.side[1].fingerprint()}};
    for (internal::Made_map& m : made) {
      if (!m.made || m.map_smoothing != with_map_smoothing || m.features != features_ || m.refinement != refinement)
        continue;
      for (int k = 0; k < 2; ++k) {
        P_[k].base = &base_;
        P_[k].mesh = &B_.side[k];
        P_[k].loc = std::move(m.loc[std::size_t(k)]);
      }
      const Cross_parameterization_statistics& S = m.statistics;
      stats_.smoothing_source = S.smoothing_source;
      stats_.smoothing_target = S.smoothing_target;
      stats_.smoothing_best_iteration = S.smoothing_best_iteration;
      stats_.smoothing_map = S.smoothing_map;
      stats_.smoothing_map_best_iteration = S.smoothing_map_best_iteration;
      stats_.map_energy_initial = S.map_energy_initial;
      stats_.map_energy = S.map_energy;
      stats_.protrusion_warps = S.protrusion_warps;
      stats_.distortion_initial = S.distortion_initial;
      stats_.stretch_reweighted_source = S.stretch_reweighted_source;
      stats_.stretch_reweighted_target = S.stretch_reweighted_target;
      m.made = false;
      return true;
    }
    return false;
  }

  /// Per mesh, per anchor, per working vertex: the graph-geodesic distance to the anchor over sqrt(area).
  using Anchor_distances = std::array<std::vector<std::vector<double>>, 2>;

  /// \brief Pairs of points that this map sends to the right place, for telling symmetric parts apart.
  ///
  /// Up to `count` source vertices where the map is reliable: not squeezed (relative stretch at most
  /// `anchor_max_stretch`, a tenth of a protrusion cluster's) and agreeing with the features' distances at
  /// least as well as half of the source does (image mismatch at most the median), chosen by farthest-point
  /// sampling from the features so that they spread over the shape; each is paired with the target vertex
  /// nearest to its image (the corner of largest barycentric coordinate). Returns the distances to the anchors
  /// on the source and to their images on the target.
  Anchor_distances anchor_distances(std::size_t count) const {
    using internal::WV;
    constexpr double anchor_max_stretch = 10;
    const internal::Layout_mesh &Ls = B_.side[0], &Lt = B_.side[1];
    Anchor_distances out;
    const std::vector<double> st = relative_stretch(P_[0]);
    if (st.empty() || count == 0 || Ls.m.number_of_vertices() == 0) return out;
    std::vector<double> mismatch(Ls.m.number_of_vertices());
    for (WV v : Ls.m.vertices()) mismatch[v] = image_mismatch(v);
    std::vector<double> sorted = mismatch;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double median = sorted[sorted.size() / 2];
    std::vector<double> far = Ls.graph_distances(Ls.feature_vertex);
    std::vector<WV> image; // per anchor, the target vertex at its image
    while (out[0].size() < count) {
      double best = 0;
      WV arg(0);
      for (WV v : Ls.m.vertices())
        if (st[v] <= anchor_max_stretch && mismatch[v] <= median && far[v] > best) {
          best = far[v];
          arg = v;
        }
      if (!(best > 0)) break;
      out[0].push_back(Ls.graph_distances({arg}));
      for (std::size_t i = 0; i < far.size(); ++i) far[i] = std::min(far[i], out[0].back()[i]);
      const internal::Work_location l = locator_[1].locate(P_[0][arg]);
      const internal::WH h = Lt.m.halfedge(l.face);
      const WV u[3] = {Lt.m.source(h), Lt.m.target(h), Lt.m.target(Lt.m.next(h))};
      const int c = int(std::max_element(l.b.begin(), l.b.end()) - l.b.begin());
      image.push_back(u[c]);
    }
    for (WV a : image) out[1].push_back(Lt.graph_distances({a}));
    for (int k = 0; k < 2; ++k) {
      const double area = B_.side[k].area();
      const double scale = area > 0 ? 1 / std::sqrt(area) : 1;
      for (std::vector<double>& d : out[k])
        for (double& x : d) x *= scale;
    }
    return out;
  }

  /// The distance between the descriptors of v on mesh k and u on the other mesh, with the anchor distances
  /// as further coordinates if `anchors` is given.
  double descriptor_distance(int k, internal::WV v, internal::WV u, const Anchor_distances* anchors) const {
    const double d = descriptor_distance(B_.side[k].desc[v], B_.side[1 - k].desc[u]);
    if (!anchors) return d;
    double s = d * d;
    for (std::size_t i = 0; i < (*anchors)[k].size(); ++i) {
      const double x = (*anchors)[k][i][v] - (*anchors)[1 - k][i][u];
      s += x * x;
    }
    return std::sqrt(s);
  }

  /// The index of the vertex of list[1-k] whose descriptor is nearest to that of list[k][i] (list[1-k].size()
  /// if that list is empty), with the anchor distances if given.
  template <class List>
  std::size_t nearest_by_descriptor(const std::array<List, 2>& list, int k, std::size_t i,
                                    const Anchor_distances* anchors = nullptr) const {
    std::size_t best = list[1 - k].size();
    double bd = HUGE_VAL;
    for (std::size_t j = 0; j < list[1 - k].size(); ++j) {
      const double dd = descriptor_distance(k, list[k][i].first, list[1 - k][j].first, anchors);
      if (dd < bd) {
        bd = dd;
        best = j;
      }
    }
    return best;
  }

  /// The index j of the vertex of list[1-k] such that list[k][i] and list[1-k][j] are each other's nearest by
  /// descriptor (nearest_by_descriptor both ways), or list[1-k].size() if there is none.
  template <class List>
  std::size_t mutual_nearest_by_descriptor(const std::array<List, 2>& list, int k, std::size_t i,
                                           const Anchor_distances* anchors = nullptr) const {
    const std::size_t j = nearest_by_descriptor(list, k, i, anchors);
    return j < list[1 - k].size() && nearest_by_descriptor(list, 1 - k, j, anchors) == i ? j : list[1 - k].size();
  }

  /// The extremities of mesh k: its working vertices where d(v), the distance to the nearest feature (the
  /// minimum of the descriptor), has a local maximum of persistence at least `min_persistence`, with that
  /// persistence (the global maximum's is infinite).
  std::vector<std::pair<internal::WV, double>> extremities(int k, double min_persistence) const {
    using internal::WV;
    std::vector<std::pair<WV, double>> out;
    const internal::Layout_mesh& L = B_.side[k];
    const std::size_t n = L.m.number_of_vertices();
    std::vector<double> d(n, HUGE_VAL);
    for (std::size_t i = 0; i < n; ++i)
      for (float x : L.desc[i]) d[i] = std::min(d[i], double(x));
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return d[a] > d[b] || (d[a] == d[b] && a < b); });
    // 0-dimensional persistence of the superlevel sets of d: vertices are added from the highest down; a
    // vertex with no neighbour added yet is a maximum and starts a component; where two components meet (at
    // a saddle), the one with the lower maximum dies, its persistence being its height above the saddle.
    std::vector<std::size_t> parent(n, n), top(n, n);
    auto find = [&](std::size_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    std::vector<double> persistence(n, -1);
    for (std::size_t v : order) {
      parent[v] = v;
      top[v] = v;
      for (WV w : CGAL::vertices_around_target(WV(WV::size_type(v)), L.m)) {
        const std::size_t u = std::size_t(w);
        if (parent[u] == n) continue; // not in the superlevel set yet
        std::size_t a = find(u), b = find(v);
        if (a == b) continue;
        if (d[top[a]] < d[top[b]] || (d[top[a]] == d[top[b]] && top[a] > top[b])) std::swap(a, b);
        if (top[b] != v) persistence[top[b]] = d[top[b]] - d[v];
        parent[b] = a;
      }
    }
    if (n > 0) persistence[top[find(order.front())]] = HUGE_VAL;
    for (std::size_t i = 0; i < n; ++i)
      if (persistence[i] >= min_persistence) out.push_back({WV(WV::size_type(i)), persistence[i]});
    return out;
  }

  /// The corners of face f of L's mesh in halfedge order, the last two swapped if the input faces point
  /// inward (L.reversed): the corner order of the user's face.
  static std::array<internal::WV, 3> corners_as_input(const internal::Layout_mesh& L, internal::WF f) {
    const internal::WH h = L.m.halfedge(f);
    std::array<internal::WV, 3> vs{L.m.source(h), L.m.target(h), L.m.target(L.m.next(h))};
    if (L.reversed) std::swap(vs[1], vs[2]);
    return vs;
  }

  /// Each vertex's stretch in a parameterization over the median one; empty if the median is not positive.
  static std::vector<double> relative_stretch(const internal::Base_parameterization& P) {
    std::vector<double> s = P.vertex_stretch(), sorted = s;
    if (s.empty()) return s;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double median = sorted[sorted.size() / 2];
    if (!(median > 0)) return {};
    for (double& x : s) x /= median;
    return s;
  }

  /// The largest vertex stretch of a parameterization over its median.
  static double squeeze(const internal::Base_parameterization& P) {
    if (P.mesh->m.number_of_vertices() == 0) return 1;
    const std::vector<double> s = relative_stretch(P);
    return s.empty() ? HUGE_VAL : *std::max_element(s.begin(), s.end());
  }

  /// Shape of the base domain: each base edge as long as its two paths, averaged over both meshes after
  /// scaling each mesh to unit area; then every base triangle is made to satisfy the triangle inequality
  /// with some slack by shortening its longest edge.
  std::map<std::pair<int, int>, double> base_edge_lengths() const {
    std::map<std::pair<int, int>, double> len;
    for (int k = 0; k < 2; ++k) {
      const internal::Layout_mesh& L = B_.side[k];
      const double area = L.area();
      const double scale = area > 0 ? 1.0 / std::sqrt(area) : 1.0;
      for (std::size_t p = 0; p < B_.path_ends.size(); ++p) {
        if (B_.path_ends[p][0] < 0) continue;
        const int a = B_.path_ends[p][0], b = B_.path_ends[p][1];
        len[{std::min(a, b), std::max(a, b)}] += 0.5 * scale * L.path_length(L.paths[p]);
      }
    }
    for (auto& [e, l] : len)
      if (!(l > 0)) l = 1e-3;
    // Triangle inequality with slack: the longest edge at most 0.9 of the two others together.
    for (bool changed = true; changed;) {
      changed = false;
      for (const auto& t : layout_.base_triangles) {
        std::array<double*, 3> e;
        for (int i = 0; i < 3; ++i) {
          int a = int(t[i]), b = int(t[(i + 1) % 3]);
          e[i] = &len.at({std::min(a, b), std::max(a, b)});
        }
        std::sort(e.begin(), e.end(), [](double* x, double* y) { return *x < *y; });
        if (*e[2] > 0.9 * (*e[0] + *e[1])) {
          *e[2] = 0.9 * (*e[0] + *e[1]);
          changed = true;
        }
      }
    }
    return len;
  }

  /// The input vertex of mesh k nearest (in edges) to working vertex v.
  internal::WV nearest_input_vertex(int k, internal::WV v) const {
    const internal::Layout_mesh& L = B_.side[k];
    std::vector<internal::WV> queue{v};
    std::set<internal::WV> seen{v};
    for (std::size_t i = 0; i < queue.size(); ++i) {
      if (std::size_t(queue[i]) < L.n_original_vertices) return queue[i];
      for (internal::WV w : CGAL::vertices_around_target(queue[i], L.m))
        if (seen.insert(w).second) queue.push_back(w);
    }
    return v;
  }

  /// Distance between two geodesic-distance descriptors (Layout_mesh::desc).
  static double descriptor_distance(const std::vector<float>& a, const std::vector<float>& b) {
    double s = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
      const double x = double(a[k]) - double(b[k]);
      s += x * x;
    }
    return std::sqrt(s);
  }

  /// The area-weighted mean and the maximum over the working source vertices of the descriptor mismatch over
  /// the first `dims` features, per feature (root mean square).
  std::pair<double, double> mismatch_summary(std::size_t dims) const {
    const internal::Layout_mesh& Ls = B_.side[0];
    dims = std::min(dims, features_.size());
    if (dims == 0) return {0.0, 0.0};
    const double norm = 1 / std::sqrt(double(dims));
    std::vector<double> x(Ls.m.number_of_vertices(), 0), w(Ls.m.number_of_vertices(), 0);
    for (internal::WV v : Ls.m.vertices()) x[v] = image_mismatch(v, dims) * norm;
    for (internal::WF f : Ls.m.faces()) {
      const internal::WH h = Ls.m.halfedge(f);
      const internal::WV c[3] = {Ls.m.source(h), Ls.m.target(h), Ls.m.target(Ls.m.next(h))};
      const double a = std::sqrt(CGAL::squared_area(Ls.m.point(c[0]), Ls.m.point(c[1]), Ls.m.point(c[2]))) / 3;
      for (internal::WV v : c) w[v] += a;
    }
    double sum = 0, weight = 0, worst = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      sum += w[i] * x[i];
      weight += w[i];
      worst = std::max(worst, x[i]);
    }
    return {weight > 0 ? sum / weight : 0.0, worst};
  }

  /// Descriptor disagreement between source vertex v and its image F(v) (target descriptors interpolated).
  double image_mismatch(internal::WV v, std::size_t dims = std::size_t(-1)) const {
    const internal::Layout_mesh& Ls = B_.side[0];
    const internal::Layout_mesh& Lt = B_.side[1];
    const internal::Work_location l = locator_[1].locate(P_[0][v]);
    const internal::WH h = Lt.m.halfedge(l.face);
    const internal::WV u[3] = {Lt.m.source(h), Lt.m.target(h), Lt.m.target(Lt.m.next(h))};
    double s = 0;
    for (std::size_t k = 0; k < std::min(dims, Ls.desc[v].size()); ++k) {
      const double x = Ls.desc[v][k] - (l.b[0] * Lt.desc[u[0]][k] + l.b[1] * Lt.desc[u[1]][k] + l.b[2] * Lt.desc[u[2]][k]);
      s += x * x;
    }
    return std::sqrt(s);
  }

  /// Featureless protrusions (a limb inside one patch) are squeezed by the parameterizations into tiny regions
  /// of their base triangle, and the two meshes' regions rarely coincide: F then sends the whole limb to one
  /// point. For every base triangle, the interior source vertex whose image disagrees most with it (geodesic-
  /// distance descriptors) is compared with the target vertices of the same triangle; if one agrees much
  /// better, the source vertices of the triangle are moved by a piecewise-affine homeomorphism of the
  /// triangle that fixes its sides and carries the source vertex onto that target vertex: an inner triangle
  /// around it is translated rigidly (the squeezed limb moves as a whole), the three trapezoids between it and
  /// the sides follow affinely. A warp that would flip a face (exact predicate) is undone. Returns the number
  /// of triangles warped. Needs the target's locator built.
  std::size_t align_protrusions() {
    using internal::Point_2;
    const internal::Layout_mesh& Ls = B_.side[0];
    const internal::Layout_mesh& Lt = B_.side[1];
    if (Ls.desc.empty() || Lt.desc.empty()) return 0;
    const double min_gain = 0.2;          // descriptor units (unit area); agreement is typically ~0.13
    const std::size_t candidates = 8;     // worst source vertices tried per base triangle
    auto interior = [](const Base_location& l) { return l.b[0] > 0 && l.b[1] > 0 && l.b[2] > 0; };
    const std::size_t nt = base_.tri.size();
    std::vector<std::vector<std::pair<double, internal::WV>>> worst(nt);
    for (internal::WV v : Ls.m.vertices())
      if (Ls.vfeature[v] == internal::no_feature && Ls.vpath[v] == internal::no_path && interior(P_[0][v]))
        worst[std::size_t(P_[0][v].tri)].push_back({image_mismatch(v), v});
    std::vector<std::vector<internal::WV>> target_in(nt);
    for (internal::WV u : Lt.m.vertices())
      if (Lt.vfeature[u] == internal::no_feature && interior(P_[1][u])) target_in[std::size_t(P_[1][u].tri)].push_back(u);
    std::vector<std::vector<internal::WV>> source_in(nt);
    for (internal::WV v : Ls.m.vertices()) source_in[std::size_t(P_[0][v].tri)].push_back(v);
    std::size_t warps = 0;
    for (std::size_t t = 0; t < nt; ++t) {
      auto& w = worst[t];
      const std::size_t n = std::min(candidates, w.size());
      std::partial_sort(w.begin(), w.begin() + std::ptrdiff_t(n), w.end(),
                        [](const auto& x, const auto& y) { return x.first > y.first; });
      double best = min_gain;
      internal::WV bv, bu;
      for (std::size_t i = 0; i < n; ++i)
        for (internal::WV u : target_in[t]) {
          const double gain = w[i].first - descriptor_distance(Ls.desc[w[i].second], Lt.desc[u]);
          if (gain > best) best = gain, bv = w[i].second, bu = u;
        }
      if (best <= min_gain) continue;
      for (double inner : {0.5, 0.25, 0.125})
        if (warp_triangle(int(t), source_in[t], P_[0][bv].b, P_[1][bu].b, inner)) {
          ++warps;
          break;
        }
    }
    return warps;
  }

  /// The homeomorphism of align_protrusions on base triangle t, carrying barycentrics `from` to `to`, applied
  /// to the source vertices `vs` located in t; `inner` scales the rigidly moved triangle. False (and nothing
  /// changed) if a piece or a mesh face would not be positively oriented.
  bool warp_triangle(int t, const std::vector<internal::WV>& vs, const std::array<double, 3>& from,
                     const std::array<double, 3>& to, double inner) {
    using internal::Point_2;
    // Affine frame of the triangle: a point with barycentrics b is (b1, b2).
    auto pt = [](const std::array<double, 3>& b) { return Point_2(b[1], b[2]); };
    const Point_2 P[3] = {Point_2(0, 0), Point_2(1, 0), Point_2(0, 1)};
    const Point_2 a = pt(from), b = pt(to);
    double s = 1;
    for (int j = 0; j < 3; ++j) s = std::min(s, to[j] / from[j]); // keeps the moved inner triangle inside t
    s *= inner;
    Point_2 I[3], J[3];
    for (int i = 0; i < 3; ++i) {
      I[i] = a + s * (P[i] - a);
      J[i] = I[i] + (b - a);
    }
    std::vector<std::array<Point_2, 3>> src{{I[0], I[1], I[2]}}, dst{{J[0], J[1], J[2]}};
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3;
      src.push_back({P[i], P[j], I[j]});
      dst.push_back({P[i], P[j], J[j]});
      src.push_back({P[i], I[j], I[i]});
      dst.push_back({P[i], J[j], J[i]});
    }
    for (std::size_t i = 0; i < src.size(); ++i)
      if (CGAL::orientation(src[i][0], src[i][1], src[i][2]) != CGAL::POSITIVE ||
          CGAL::orientation(dst[i][0], dst[i][1], dst[i][2]) != CGAL::POSITIVE)
        return false;
    std::vector<Base_location> saved;
    saved.reserve(vs.size());
    for (internal::WV x : vs) {
      Base_location& l = P_[0][x];
      saved.push_back(l);
      const Point_2 q = pt(l.b);
      // The piece holding q: the one where q's smallest barycentric is largest (pieces tile t).
      std::size_t piece = 0;
      double best = -HUGE_VAL;
      std::array<double, 3> c{};
      for (std::size_t i = 0; i < src.size(); ++i) {
        const std::array<double, 3> ci = internal::barycentric_2(src[i][0], src[i][1], src[i][2], q);
        const double mn = std::min({ci[0], ci[1], ci[2]});
        if (mn > best) best = mn, piece = i, c = ci;
      }
      const auto& D = dst[piece];
      const double x1 = c[0] * D[0].x() + c[1] * D[1].x() + c[2] * D[2].x();
      const double x2 = c[0] * D[0].y() + c[1] * D[1].y() + c[2] * D[2].y();
      std::array<double, 3> nb{1 - x1 - x2, x1, x2};
      for (int i = 0; i < 3; ++i)
        if (l.b[i] == 0 || nb[i] < 0) nb[i] = 0; // the sides are fixed
      const double sum = nb[0] + nb[1] + nb[2];
      for (double& y : nb) y /= sum;
      l.b = nb;
    }
    for (internal::WV x : vs)
      if (!P_[0].star_positive(x)) {
        for (std::size_t i = 0; i < vs.size(); ++i) P_[0][vs[i]] = saved[i];
        return false;
      }
    return true;
  }

  Input_location vertex_to_input(int side, std::size_t v) const {
    const internal::Layout_mesh& L = B_.side[side];
    const internal::WV wv{internal::WV::size_type(v)};
    const int f = L.vfeature[wv];
    if (f != internal::no_feature) { // features map exactly onto their partners
      internal::WV partner = B_.side[1 - side].feature_vertex[f];
      const auto& rep = B_.side[1 - side].vrep[partner];
      return {std::size_t(rep.first), rep.second};
    }
    return to_input(side ? Mesh_side::source : Mesh_side::target, locator_[1 - side].locate(P_[side][wv]));
  }

  template <int To, class LinkFrom, class LinkTo, class FaceIndex, class Loc>
  auto map(const Loc& p, const LinkFrom& from, const LinkTo& to, FaceIndex& index) const {
    constexpr int From = 1 - To;
    if (index.empty())
      for (std::size_t i = 0; i < from.face.size(); ++i) index[from.face[i]] = i;
    auto it = index.find(p.first);
    if (it == index.end()) throw Input_error("face location: the face is not a face of the mesh");
    // Barycentrics from the user's face order to the work face's halfedge order.
    internal::Work_location l;
    l.face = internal::WF(internal::WF::size_type(it->second));
    const auto& m = B_.side[From].m;
    internal::WH h = m.halfedge(l.face);
    const internal::WV wv[3] = {m.source(h), m.target(h), m.target(m.next(h))};
    const auto uv = user_face_vertices<From>(p.first);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (from.vertex[wv[j]] == uv[i]) l.b[j] = p.second[i];
    const internal::Work_location r = image(From ? Mesh_side::target : Mesh_side::source, l);
    // Back to the user's face order on the other mesh.
    const auto& m2 = B_.side[To].m;
    internal::WH h2 = m2.halfedge(r.face);
    const internal::WV wv2[3] = {m2.source(h2), m2.target(h2), m2.target(m2.next(h2))};
    const auto face = to.face[r.face];
    const auto uv2 = user_face_vertices<To>(face);
    std::array<double, 3> b{{0, 0, 0}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (to.vertex[wv2[j]] == uv2[i]) b[i] = r.b[j];
    return std::make_pair(face, b);
  }

  template <int Side>
  auto& mesh_ref() const {
    if constexpr (Side == 0) return tm_s_;
    else return tm_t_;
  }

  template <int Side, class Face>
  auto user_face_vertices(Face f) const {
    const auto& g = mesh_ref<Side>();
    auto h = halfedge(f, g);
    using V = typename boost::graph_traits<std::decay_t<decltype(g)>>::vertex_descriptor;
    return std::array<V, 3>{source(h, g), target(h, g), target(next(h, g), g)};
  }

  /// Distortion of F on the refined source: images of the source vertices on the target.
  Distortion measure_distortion() const {
    const auto& ms = B_.side[0].m;
    const auto& mt = B_.side[1].m;
    std::vector<Point_3> image(ms.number_of_vertices());
    internal::parallel_for(ms.number_of_vertices(), threads_, [&](std::size_t i) {
      const internal::WV v{internal::WV::size_type(i)};
      image[v] = internal::point_at(mt, locator_[1].locate(P_[0][v]));
    });
    std::vector<std::array<Point_3, 3>> from, to;
    from.reserve(ms.number_of_faces());
    to.reserve(ms.number_of_faces());
    for (internal::WF f : ms.faces()) {
      internal::WH h = ms.halfedge(f);
      internal::WV a = ms.source(h), b = ms.target(h), c = ms.target(ms.next(h));
      from.push_back({ms.point(a), ms.point(b), ms.point(c)});
      to.push_back({image[a], image[b], image[c]});
    }
    return triangle_map_distortion(from, to);
  }

  void check_features(const Feature_correspondence& f) const {
    for (std::size_t k = 0; k < f.size(); ++k) {
      for (int side = 0; side < 2; ++side) {
        internal::WV v = B_.side[side].feature_vertex[k];
        internal::Work_location l = locator_[1 - side].locate(P_[side][v]);
        const auto& m = B_.side[1 - side].m;
        internal::WH h = m.halfedge(l.face);
        internal::WV vs[3] = {m.source(h), m.target(h), m.target(m.next(h))};
        double at_partner = 0;
        for (int i = 0; i < 3; ++i)
          if (vs[i] == B_.side[1 - side].feature_vertex[k]) at_partner = l.b[i];
        if (!(at_partner > 1 - 1e-9))
          throw Algorithm_error("feature " + std::to_string(k) + " does not map onto its partner");
      }
    }
  }

  SourceMesh& tm_s_;
  TargetMesh& tm_t_;
  unsigned threads_ = 1; ///< threads of the smoothing and the distortion measurement (`number_of_threads`)
  Feature_correspondence features_;
  internal::Layout_builder B_;
  internal::Mesh_link<SourceMesh> link_s_;
  internal::Mesh_link<TargetMesh> link_t_;
  mutable std::map<typename boost::graph_traits<SourceMesh>::face_descriptor, std::size_t> face_index_s_;
  mutable std::map<typename boost::graph_traits<TargetMesh>::face_descriptor, std::size_t> face_index_t_;
  Patch_layout layout_;
  internal::Base_mesh base_;
  internal::Base_parameterization P_[2];
  internal::Base_locator locator_[2];
  Bijectivity_certificate cert_[2];
  Cross_parameterization_statistics stats_;
};

namespace internal {
/// The working state of a `Cross_parameterization`, for the library's own later stages (compatible
/// remeshing copies the source's layout mesh and parameterization and refines them further).
struct Cross_parameterization_access {
  template <class CP>
  static const Layout_mesh& layout_mesh(const CP& cp, Mesh_side side) { return cp.B_.side[side_index(side)]; }
  template <class CP>
  static const Base_parameterization& parameterization(const CP& cp, Mesh_side side) { return cp.P_[side_index(side)]; }
  template <class CP>
  static const Base_locator& locator(const CP& cp, Mesh_side side) { return cp.locator_[side_index(side)]; }
  template <class CP>
  static const Base_mesh& base_mesh(const CP& cp) { return cp.base_; }
};
} // namespace internal

} // namespace crossparam

#endif // CROSSPARAM_CROSS_PARAMETERIZATION_H

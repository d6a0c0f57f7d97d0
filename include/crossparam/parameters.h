// SPDX-License-Identifier: GPL-3.0-or-later
// crossparam's own named parameters. CGAL 5.5's list of parameter names is closed, so each new option is a
// tag plus a free function that prepends it to a CGAL parameter pack:
//   crossparam::parameters::edge_path_map(epm, CGAL::parameters::face_patch_map(fpm))
// Existing CGAL names (face_patch_map, vertex_point_map, number_of_iterations, verbose, ...) are reused as is.
#ifndef CROSSPARAM_PARAMETERS_H
#define CROSSPARAM_PARAMETERS_H

#include <CGAL/Named_function_parameters.h>
#include <CGAL/boost/graph/named_params_helper.h>

namespace crossparam {

/// How Compatible_remesher builds the target-shaped mesh (named parameter `remeshing_construction`).
enum class Remeshing_construction {
  automatic,  ///< the refinement; where its result fails the strict checks, the decimated overlay when that
              ///< fails fewer of them (none, on every case measured)
  refinement, ///< the paper's (§5): the source refined until its image F(M_s) is within the tolerance
  overlay     ///< the map's overlay with the target, decimated within the tolerance
};

namespace internal_np {
struct edge_path_map_t {};      ///< edge -> int: id of the layout path on the edge, or -1
struct vertex_feature_map_t {}; ///< vertex -> int: feature index of the vertex, or -1
struct apply_path_flips_t {};   ///< bool: run the path flips of §3.3 (default true)
struct consistent_paths_t {};   ///< bool: descriptor-guided consistent matching paths (default true)
struct straighten_paths_t {};   ///< bool: each finished path shortened inside its two patches (default false)
// Cross-parameterization (cross_parameterization.h)
struct smoothing_weights_t {};   ///< a model of SmoothingWeights (default Mean_value_weights)
struct smoothing_tolerance_t {}; ///< double, base-edge units (default 1e-4)
struct apply_smoothing_t {};     ///< bool (default true)
struct map_smoothing_t {};       ///< bool (default false)
struct map_smoothing_global_steps_t {}; ///< bool (default true)
struct protrusion_features_t {}; ///< bool (default true)
struct extremity_features_t {};  ///< bool (default true)
struct select_extremity_features_t {}; ///< bool (default true)
struct extremity_persistence_t {}; ///< double, units of sqrt(area) (default 0.05)
// Compatible remeshing (compatible_remeshing.h)
struct tolerance_t {};          ///< double, percent of the target's bounding-box diagonal (default 0.5)
struct normal_deviation_t {};   ///< double, degrees (default 30)
struct progress_t {};           ///< callable with a std::string (default none)
struct remeshing_weights_t {};  ///< a model of RemeshingWeights (default Error_driven_weights)
struct refinement_rule_t {};    ///< a model of RefinementRule (default Half_max_refinement)
struct max_rounds_t {};         ///< unsigned (default 30)
struct undo_layout_splits_t {}; ///< bool (default true)
struct number_of_threads_t {};  ///< unsigned (default 0: one per hardware thread)
// Every computation
struct time_limit_t {};         ///< double, seconds (default: none)
struct best_effort_t {};        ///< bool (default false)
struct remeshing_construction_t {}; ///< Remeshing_construction (default automatic)
// N-way remeshing (multi_remeshing.h)
struct source_mesh_t {};        ///< std::size_t: index of the source mesh (default 0; finest_mesh: the largest)
} // namespace internal_np

namespace parameters {

using CGAL::parameters::default_values;

#define CROSSPARAM_ADD_NAMED_PARAMETER(NAME)                                                                    \
  template <typename T, typename NP = CGAL::parameters::Default_named_parameters>                             \
  CGAL::Named_function_parameters<T, internal_np::NAME##_t, NP> NAME(                                         \
      const T& value, const NP& np = CGAL::parameters::default_values()) {                                    \
    return CGAL::Named_function_parameters<T, internal_np::NAME##_t, NP>(value, np);                          \
  }

/// \brief Output: `edge -> int` property map receiving the layout path id of each edge (-1 off paths).
CROSSPARAM_ADD_NAMED_PARAMETER(edge_path_map)
/// \brief Output: `vertex -> int` property map receiving the feature index of each vertex (-1 elsewhere).
CROSSPARAM_ADD_NAMED_PARAMETER(vertex_feature_map)
/// \brief `bool`, default `true`: whether to improve base-mesh valences by path flips (paper §3.3).
CROSSPARAM_ADD_NAMED_PARAMETER(apply_path_flips)
/// \brief `bool`, default `true`: trace each matching path pair so that the two paths agree in geodesic
/// distances to the features (an addition to the paper; see doc/algorithms.md).
CROSSPARAM_ADD_NAMED_PARAMETER(consistent_paths)
/// \brief `bool`, default `false`: once the layout is complete, replace each path, on each mesh, by the
/// shortest path between its two features inside the two patches beside it, where that is shorter (an
/// addition to the paper; see doc/algorithms.md: on the wider bench the map's mean error is lower with it,
/// but the compatible remeshing of some bench cases is worse).
CROSSPARAM_ADD_NAMED_PARAMETER(straighten_paths)

/// \brief The weights policy of the §4.2 smoothing, a model of `SmoothingWeights` (concept in smoothing.h);
/// default `Mean_value_weights`.
CROSSPARAM_ADD_NAMED_PARAMETER(smoothing_weights)
/// \brief `double`, default 1e-4: smoothing stops when no vertex moves farther (in base-triangle edge units).
CROSSPARAM_ADD_NAMED_PARAMETER(smoothing_tolerance)
/// \brief `bool`, default `true`: whether to smooth the parameterizations (§4.2).
CROSSPARAM_ADD_NAMED_PARAMETER(apply_smoothing)
/// \brief `bool`, default `false`: after the §4.2 smoothing, smooth the map itself towards an as-rigid-as-possible
/// map from the source onto the target (an addition to the paper; see doc/algorithms.md, "Map smoothing").
CROSSPARAM_ADD_NAMED_PARAMETER(map_smoothing)
/// \brief `bool`, default `true`: whether each pass of the map smoothing begins with a global step (all the
/// images' tangent displacements solved for at once) before its vertex-by-vertex step; without it the map
/// smoothing is local only (less accurate, and faster).
CROSSPARAM_ADD_NAMED_PARAMETER(map_smoothing_global_steps)
/// \brief `bool`, default `true`: add feature pairs at the tips of protrusions that a first map squeezes (an
/// addition to the paper; see doc/algorithms.md). The pairs added are appended to the user's.
CROSSPARAM_ADD_NAMED_PARAMETER(protrusion_features)
/// \brief `bool`, default `true`: try feature pairs at the extremities (tips of fingers, limbs, tails: the
/// geodesic extremities away from every feature) that a first map sends to the wrong place, each extremity
/// paired with the other mesh's extremity of nearest geodesic-distance descriptor when the choice is mutual (an
/// addition to the paper; see doc/algorithms.md). With `select_extremity_features` (the default) the pairs are
/// kept only if the map made with them disagrees less, at its worst point, with the geodesic distances to the
/// user's features (Cross_parameterization::max_descriptor_mismatch). Kept pairs are appended after the user's
/// and the protrusion features.
CROSSPARAM_ADD_NAMED_PARAMETER(extremity_features)
/// \brief `bool`, default `true`: with `extremity_features`, keep the extremity pairs only if they lower the
/// map's worst descriptor mismatch (two candidate maps are made, on copies); `false` keeps every pair found.
CROSSPARAM_ADD_NAMED_PARAMETER(select_extremity_features)
/// \brief `double`, default 0.05: with `extremity_features`, how far (in units of the square root of the mesh's
/// area) a local maximum of the distance to the features must rise above the saddle that joins it to a higher
/// one to count as an extremity; also the least map error at an extremity for which a pair is added.
CROSSPARAM_ADD_NAMED_PARAMETER(extremity_persistence)

/// \brief `double`, default 0.5: approximation tolerance ε of §5, in percent of the target's bounding-box diagonal.
CROSSPARAM_ADD_NAMED_PARAMETER(tolerance)
/// \brief `double`, default 30: pseudo edge flips (§5.4) for faces whose normal deviates from the target's by
/// more than this many degrees; 180 or more disables them.
CROSSPARAM_ADD_NAMED_PARAMETER(normal_deviation)
/// \brief A callable taking a `const std::string&`: one line of text per step of the map and of the remesher
/// (the library never prints).
CROSSPARAM_ADD_NAMED_PARAMETER(progress)
/// \brief The weights policy of the adaptive smoothing (§5.2), a model of `RemeshingWeights` (concept in
/// smoothing.h); default `Error_driven_weights`.
CROSSPARAM_ADD_NAMED_PARAMETER(remeshing_weights)
/// \brief The refinement rule (§5.3), a model of `RefinementRule`.
CROSSPARAM_ADD_NAMED_PARAMETER(refinement_rule)
/// \brief `unsigned`, default 30: smoothing-and-refinement rounds at most.
CROSSPARAM_ADD_NAMED_PARAMETER(max_rounds)
/// \brief `bool`, default true: undo, before §5, the layout's splits of the source that the smoothed map no
/// longer needs (an addition to the paper, fewer output vertices; see doc/algorithms.md).
CROSSPARAM_ADD_NAMED_PARAMETER(undo_layout_splits)
/// \brief `unsigned`, default 0 (one per hardware thread): threads for the map's smoothing (one per mesh) and
/// distortion measurement, and for the remesher's error measurement. The results do not depend on it: each mesh
/// is smoothed on its own, every measured element is computed on its own, sums and maxima in a fixed order.
CROSSPARAM_ADD_NAMED_PARAMETER(number_of_threads)

/// \brief `double`, seconds, default none (an infinite budget): the time budget of the Cross_parameterization
/// constructor, or of the Compatible_remesher constructor, from its start. It is checked between the steps and
/// inside every long loop; when it runs out the computation throws Time_limit_error naming the step and what it
/// had reached (or, with `best_effort`, stops improving; see there). Not a hard real-time bound: the check
/// comes at the end of the unit of work under way (one smoothing pass, one refinement split, one fold).
CROSSPARAM_ADD_NAMED_PARAMETER(time_limit)
/// \brief `bool`, default `false`: when the `time_limit` runs out during a step that only improves a result
/// that is already valid (the map's smoothing; the remesher's smoothing-and-refinement rounds, pseudo flips,
/// fold repair and untangling), stop that step, keep the result reached (certified as always) and go on to
/// the end of the computation, skipping the remaining improving steps. A step that must finish (the layout,
/// the initial parameterization, the certificates) still throws Time_limit_error.
CROSSPARAM_ADD_NAMED_PARAMETER(best_effort)
/// \brief `Remeshing_construction`, default `Remeshing_construction::automatic`: how the compatible remesher
/// builds the target-shaped mesh: by the paper's refinement, by the decimated overlay of the map, or by the
/// refinement with the decimated overlay where the refinement's result fails the strict checks (see
/// Compatible_remesher).
CROSSPARAM_ADD_NAMED_PARAMETER(remeshing_construction)
/// \brief `std::size_t`, default 0: which of the N meshes of an N-way remeshing is the source (its index);
/// `crossparam::finest_mesh` picks the one with the most vertices.
CROSSPARAM_ADD_NAMED_PARAMETER(source_mesh)

#undef CROSSPARAM_ADD_NAMED_PARAMETER

} // namespace parameters
} // namespace crossparam

#endif // CROSSPARAM_PARAMETERS_H

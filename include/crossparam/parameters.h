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
namespace internal_np {
struct edge_path_map_t {};      ///< edge -> int: id of the layout path on the edge, or -1
struct vertex_feature_map_t {}; ///< vertex -> int: feature index of the vertex, or -1
struct apply_path_flips_t {};   ///< bool: run the path flips of §3.3 (default true)
struct consistent_paths_t {};   ///< bool: descriptor-guided consistent matching paths (default true)
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
/// distances to the features (an addition to the paper; see the user manual).
CROSSPARAM_ADD_NAMED_PARAMETER(consistent_paths)

#undef CROSSPARAM_ADD_NAMED_PARAMETER

} // namespace parameters
} // namespace crossparam

#endif // CROSSPARAM_PARAMETERS_H

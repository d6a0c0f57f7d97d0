// SPDX-License-Identifier: GPL-3.0-or-later
// Morphing between compatible meshes (paper §1, §6): meshes with one face list, interpolated vertex by vertex.
#ifndef CROSSPARAM_MORPH_H
#define CROSSPARAM_MORPH_H

#include <crossparam/errors.h>
#include <crossparam/types.h>
#include <crossparam/validation.h> // check_compatible

#include <array>
#include <string>
#include <vector>

namespace crossparam {

namespace internal {

/// The blend of `blend()` on checked inputs: one weight per point list, all lists of one size.
inline std::vector<std::array<double, 3>> blend_points(const std::vector<const std::vector<std::array<double, 3>>*>& meshes,
                                                       const std::vector<double>& weights) {
  std::vector<std::array<double, 3>> out(meshes[0]->size(), {0, 0, 0});
  for (std::size_t m = 0; m < meshes.size(); ++m)
    for (std::size_t i = 0; i < out.size(); ++i)
      for (int k = 0; k < 3; ++k) out[i][k] += weights[m] * (*meshes[m])[i][k];
  return out;
}

} // namespace internal

/// Weighted blend of the points of several compatible meshes (weights are used as given; they normally sum to
/// 1): the N-way blend of §2.3.
/// \pre the meshes are compatible (check_compatible() for soups); only the point counts are checked here.
/// \throws Input_error unless there is one weight per point list (and at least one list);
///         Incompatible_inputs_error if the point lists differ in size.
inline std::vector<std::array<double, 3>> blend(const std::vector<const std::vector<std::array<double, 3>>*>& meshes,
                                                const std::vector<double>& weights) {
  if (meshes.empty() || meshes.size() != weights.size()) throw Input_error("blend: one weight per mesh is needed");
  for (const auto* m : meshes)
    if (m->size() != meshes[0]->size()) throw Incompatible_inputs_error("blend: the point lists differ in size");
  return internal::blend_points(meshes, weights);
}

/// The points of the morph at parameter t in [0, 1] between the points of two compatible meshes:
/// (1 - t) a + t b, vertex by vertex (the blend of the two with weights 1 - t and t).
/// \pre the meshes are compatible (check_compatible() for soups); only the point counts are checked here.
/// \throws Incompatible_inputs_error if the point lists differ in size.
inline std::vector<std::array<double, 3>> morph(const std::vector<std::array<double, 3>>& a,
                                                const std::vector<std::array<double, 3>>& b, double t) {
  if (a.size() != b.size()) throw Incompatible_inputs_error("morph: the point lists differ in size");
  return internal::blend_points({&a, &b}, {1 - t, t});
}

} // namespace crossparam

#endif // CROSSPARAM_MORPH_H

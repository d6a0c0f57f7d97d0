// SPDX-License-Identifier: GPL-3.0-or-later
// Morphing between compatible meshes (paper §1, §6): meshes with one face list, interpolated vertex by vertex.
#ifndef CROSSPARAM_MORPH_H
#define CROSSPARAM_MORPH_H

#include <crossparam/errors.h>
#include <crossparam/types.h>
#include <crossparam/validation.h> // check_compatible

#include <array>
#include <cmath>
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

/// How far from 1 the sum of affine weights may be (rounding of weights written in decimal).
constexpr double affine_weight_sum_tolerance = 1e-9;

/// Checks `n_meshes` affine weights: one per mesh, finite, summing to 1.
/// \throws Input_error naming `what` otherwise
inline void check_affine_weights(const std::vector<double>& weights, std::size_t n_meshes, const std::string& what) {
  if (weights.size() != n_meshes)
    throw Input_error(what + ": " + std::to_string(weights.size()) + " weights for " + std::to_string(n_meshes) +
                      " meshes (one weight per mesh is needed)");
  double sum = 0;
  for (double w : weights) {
    if (!std::isfinite(w)) throw Input_error(what + ": a weight is not a finite number");
    sum += w;
  }
  if (!(std::abs(sum - 1) <= affine_weight_sum_tolerance))
    throw Input_error(what + ": the weights sum to " + std::to_string(sum) + ", not 1 (an affine combination is needed)");
}

} // namespace internal

/// Affine blend of the points of several compatible meshes, sum over meshes of weight times point: the N-way
/// blend of §2.3 (the paper's Fig. 11).
/// \pre the meshes are compatible (check_compatible() for soups); only the point counts are checked here.
/// \throws Input_error unless there is one finite weight per point list (and at least one list) and the weights
///         sum to 1 (up to `internal::affine_weight_sum_tolerance`); Incompatible_inputs_error if the point lists
///         differ in size.
inline std::vector<std::array<double, 3>> blend(const std::vector<const std::vector<std::array<double, 3>>*>& meshes,
                                                const std::vector<double>& weights) {
  if (meshes.empty()) throw Input_error("blend: no mesh to blend");
  internal::check_affine_weights(weights, meshes.size(), "blend");
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

// SPDX-License-Identifier: GPL-3.0-or-later
// Morphing between compatible meshes (paper §1, §6): meshes with one face list, interpolated vertex by vertex.
#ifndef CROSSPARAM_MORPH_H
#define CROSSPARAM_MORPH_H

#include <crossparam/errors.h>
#include <crossparam/types.h>

#include <array>
#include <string>
#include <vector>

namespace crossparam {

/// Throws `Incompatible_inputs_error`, naming the first difference, unless the two soups are compatible:
/// the same number of points and the same triangles (as point index triples, in order).
inline void check_compatible(const Polygon_soup& a, const Polygon_soup& b, const std::string& name_a = "A",
                             const std::string& name_b = "B") {
  auto fail = [&](const std::string& what) {
    throw Incompatible_inputs_error(name_a + " and " + name_b + " are not compatible: " + what);
  };
  if (a.points.size() != b.points.size())
    fail(std::to_string(a.points.size()) + " vs " + std::to_string(b.points.size()) + " vertices");
  if (a.polygons.size() != b.polygons.size())
    fail(std::to_string(a.polygons.size()) + " vs " + std::to_string(b.polygons.size()) + " faces");
  for (std::size_t f = 0; f < a.polygons.size(); ++f) {
    if (a.polygons[f].size() != 3 || b.polygons[f].size() != 3) fail("face " + std::to_string(f) + " is not a triangle");
    if (a.polygons[f] != b.polygons[f]) fail("face " + std::to_string(f) + " has different vertices");
  }
  if (a.polygons.empty()) fail("no faces");
}

/// Weighted blend of the points of several compatible meshes (weights are used as given; they normally sum to
/// 1): the N-way blend of §2.3.
inline std::vector<std::array<double, 3>> blend(const std::vector<const std::vector<std::array<double, 3>>*>& meshes,
                                                const std::vector<double>& weights) {
  if (meshes.empty() || meshes.size() != weights.size()) throw Input_error("blend: one weight per mesh is needed");
  std::vector<std::array<double, 3>> out(meshes[0]->size(), {0, 0, 0});
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    if (meshes[m]->size() != out.size()) throw Incompatible_inputs_error("blend: the point lists differ in size");
    for (std::size_t i = 0; i < out.size(); ++i)
      for (int k = 0; k < 3; ++k) out[i][k] += weights[m] * (*meshes[m])[i][k];
  }
  return out;
}

/// The points of the morph at parameter t in [0, 1] between the points of two compatible meshes:
/// (1 - t) a + t b, vertex by vertex (the blend of the two with weights 1 - t and t).
inline std::vector<std::array<double, 3>> morph(const std::vector<std::array<double, 3>>& a,
                                                const std::vector<std::array<double, 3>>& b, double t) {
  if (a.size() != b.size()) throw Incompatible_inputs_error("morph: the point lists differ in size");
  return blend({&a, &b}, {1 - t, t});
}

} // namespace crossparam

#endif // CROSSPARAM_MORPH_H

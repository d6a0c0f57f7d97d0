// SPDX-License-Identifier: GPL-3.0-or-later
// Exact rescaling of meshes by a power of two. Multiplying a double by 2^k rounds nothing (far from overflow
// and underflow), so a mesh pair brought to a bounding-box diagonal in [1, 2) and the results scaled back
// are the computation at a fixed scale: the same, up to the rounding of the input's mantissas, for a pair
// given at any scale the readers accept (|x| <= 1e100). The CLI runs every computation this way; the
// verifier of <crossparam/remeshing_verification.h> checks on copies scaled this way.
#ifndef CROSSPARAM_SCALING_H
#define CROSSPARAM_SCALING_H

#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/number_utils.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>

namespace crossparam {

/// \brief The exponent k for which 2^k times the largest bounding-box diagonal of `meshes` lies in [1, 2); 0 if
/// no mesh has a positive, finite diagonal. The diagonal is computed from the extents divided by the largest
/// one, so that no square overflows or underflows for any finite coordinates.
/// \tparam Mesh a model of `FaceListGraph` with an internal `vertex_point` map
template <class Mesh>
int unit_scale_exponent(std::initializer_list<const Mesh*> meshes) {
  double largest = 0;
  for (const Mesh* m : meshes) {
    if (num_vertices(*m) == 0) continue;
    const CGAL::Bbox_3 b = CGAL::Polygon_mesh_processing::bbox(*m);
    const double e[3] = {b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()};
    const double big = std::max({e[0], e[1], e[2]});
    if (!(big > 0) || !std::isfinite(big)) continue;
    const double d = big * std::sqrt(CGAL::square(e[0] / big) + CGAL::square(e[1] / big) + CGAL::square(e[2] / big));
    if (std::isfinite(d)) largest = std::max(largest, d);
  }
  return largest > 0 ? -std::ilogb(largest) : 0;
}

/// \brief Multiplies every point of `m` by 2^exponent (exact for the doubles of the readers' range).
/// \tparam Mesh a model of `FaceListGraph` with an internal, writable `vertex_point` map whose points are
///         constructible from three doubles
template <class Mesh>
void scale_by_power_of_two(Mesh& m, int exponent) {
  if (exponent == 0) return;
  auto vpm = get(CGAL::vertex_point, m);
  using Point = typename boost::property_traits<decltype(vpm)>::value_type;
  for (auto v : vertices(m)) {
    const Point p = get(vpm, v);
    put(vpm, v, Point(std::ldexp(CGAL::to_double(p.x()), exponent), std::ldexp(CGAL::to_double(p.y()), exponent),
                      std::ldexp(CGAL::to_double(p.z()), exponent)));
  }
}

/// \brief `points` multiplied by 2^exponent (exact), e.g. a remesher's outputs brought back to the user's units.
template <class PointArrays>
PointArrays scaled_by_power_of_two(PointArrays points, int exponent) {
  if (exponent != 0)
    for (auto& p : points)
      for (auto& x : p) x = std::ldexp(x, exponent);
  return points;
}

} // namespace crossparam

#endif // CROSSPARAM_SCALING_H

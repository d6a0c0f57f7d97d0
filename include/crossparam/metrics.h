// SPDX-License-Identifier: GPL-3.0-or-later
// Distortion of a map between triangle meshes, measured per triangle on the piecewise-linear map that sends
// each source triangle to the triangle spanned by its vertices' images.
//
//  - Angular distortion E_ang (after Sheffer & de Sturler 2000): the area-weighted mean over triangles of
//    (1/3) sum_corners ((a' - a) / a)^2, a a source angle and a' its image. 0 for a conformal map.
//  - L2 stretch (Sander et al. 2001): sqrt( sum_T A_T (s1^2 + s2^2) / 2 / sum_T A_T ), s1, s2 the singular
//    values of the map on T, after scaling the image to the source's total area. 1 for an isometry up to scale,
//    larger otherwise.
// Triangles of zero area on either side are skipped (their share of the area is nil).
#ifndef CROSSPARAM_METRICS_H
#define CROSSPARAM_METRICS_H

#include <crossparam/types.h>

#include <array>
#include <cmath>
#include <vector>

namespace crossparam {

/// Distortion figures of a map (see metrics.h for definitions).
struct Distortion {
  double angular = 0;    ///< E_ang, 0 is ideal
  double l2_stretch = 1; ///< L2 stretch, 1 is ideal
  std::size_t triangles = 0; ///< triangles measured (non-degenerate on both sides)
};

namespace internal {
/// Corner angles of a 3D triangle.
inline std::array<double, 3> corner_angles(const std::array<Point_3, 3>& t) {
  std::array<double, 3> a{};
  for (int i = 0; i < 3; ++i) {
    Kernel::Vector_3 u = t[(i + 1) % 3] - t[i], v = t[(i + 2) % 3] - t[i];
    double c = u * v, s = std::sqrt(CGAL::cross_product(u, v).squared_length());
    a[i] = std::atan2(s, c);
  }
  return a;
}
/// The triangle in its own plane: (0,0), (x1,0), (x2,y2).
inline std::array<double, 3> planar(const std::array<Point_3, 3>& t) {
  Kernel::Vector_3 e1 = t[1] - t[0], e2 = t[2] - t[0];
  double l1 = std::sqrt(e1.squared_length());
  if (!(l1 > 0)) return {0, 0, 0};
  double x2 = (e1 * e2) / l1;
  double y2 = std::sqrt(CGAL::cross_product(e1, e2).squared_length()) / l1;
  return {l1, x2, y2};
}
} // namespace internal

/// Distortion of the map sending triangle from[i] onto triangle to[i] linearly, for all i. Points of the fixed
/// kernel `crossparam::Kernel`; the figures are computed in double precision.
inline Distortion triangle_map_distortion(const std::vector<std::array<Point_3, 3>>& from,
                                          const std::vector<std::array<Point_3, 3>>& to) {
  Distortion d;
  double area_from = 0, area_to = 0, ang = 0, stretch = 0, wsum = 0;
  std::vector<double> frob(from.size(), -1), area(from.size(), 0);
  for (std::size_t i = 0; i < from.size(); ++i) {
    auto p = internal::planar(from[i]), q = internal::planar(to[i]);
    double a = 0.5 * p[0] * p[2], b = 0.5 * q[0] * q[2];
    if (!(a > 1e-30) || !(b > 1e-30)) continue;
    auto as = internal::corner_angles(from[i]), at = internal::corner_angles(to[i]);
    double e = 0;
    for (int k = 0; k < 3; ++k) e += ((at[k] - as[k]) / as[k]) * ((at[k] - as[k]) / as[k]);
    ang += a * e / 3;
    // Jacobian J with J * [p1 p2] = [q1 q2] (columns: edge vectors in each plane).
    const double P11 = p[0], P12 = p[1], P22 = p[2];
    const double Q11 = q[0], Q12 = q[1], Q22 = q[2];
    const double det = P11 * P22;
    // inverse of [[P11, P12], [0, P22]]
    const double i11 = P22 / det, i12 = -P12 / det, i22 = P11 / det;
    const double J11 = Q11 * i11, J12 = Q11 * i12 + Q12 * i22, J21 = 0, J22 = Q22 * i22;
    frob[i] = J11 * J11 + J12 * J12 + J21 * J21 + J22 * J22;
    area[i] = a;
    area_from += a;
    area_to += b;
    wsum += a;
    ++d.triangles;
  }
  if (d.triangles == 0) return d;
  const double scale2 = area_from / area_to; // image scaled to the source's area: squared lengths scale by this
  for (std::size_t i = 0; i < from.size(); ++i)
    if (frob[i] >= 0) stretch += area[i] * frob[i] * scale2 / 2;
  d.angular = ang / wsum;
  d.l2_stretch = std::sqrt(stretch / wsum);
  return d;
}

} // namespace crossparam

#endif // CROSSPARAM_METRICS_H

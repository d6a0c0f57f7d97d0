// SPDX-License-Identifier: GPL-3.0-or-later
// Barycentric coordinates: moved between triangles of a simplicial complex through their shared corners, of a
// point in a triangle, and the point of given coordinates.
#ifndef CROSSPARAM_INTERNAL_BARYCENTRIC_H
#define CROSSPARAM_INTERNAL_BARYCENTRIC_H

#include <CGAL/number_utils.h>

#include <array>

namespace crossparam {
namespace internal {

/// A point with barycentrics `b` w.r.t. corners `from`, expressed w.r.t. corners `to`: possible exactly when
/// every corner with a non-zero coordinate is also a corner of `to` (the point lies on a shared vertex or edge,
/// or the triangles are the same). Zero coordinates are exact, so the test is exact too.
template <class Corner>
bool reexpress_barycentric(const std::array<Corner, 3>& from, const std::array<double, 3>& b,
                           const std::array<Corner, 3>& to, std::array<double, 3>& out) {
  out = {0, 0, 0};
  for (int j = 0; j < 3; ++j) {
    if (b[j] == 0) continue;
    int k = -1;
    for (int i = 0; i < 3; ++i)
      if (to[i] == from[j]) k = i;
    if (k < 0) return false;
    out[k] = b[j];
  }
  return true;
}

/// The point with barycentrics `b` w.r.t. corners a, b, c (any 3D point type with x(), y(), z()).
template <class Point>
Point barycentric_point(const Point& a, const Point& b, const Point& c, const std::array<double, 3>& w) {
  return Point(w[0] * a.x() + w[1] * b.x() + w[2] * c.x(), w[0] * a.y() + w[1] * b.y() + w[2] * c.y(),
               w[0] * a.z() + w[1] * b.z() + w[2] * c.z());
}

/// Barycentric coordinates w.r.t. corners a, b, c of p, a point on the triangle's plane (or near it), from
/// signed sub-areas: clamped to the triangle and normalised; the centroid for a degenerate triangle. (Any CGAL
/// kernel's Point_3.)
template <class Point>
std::array<double, 3> barycentric_in_triangle(const Point& a, const Point& b, const Point& c, const Point& p) {
  const auto n = CGAL::cross_product(b - a, c - a);
  std::array<double, 3> w{{CGAL::to_double(CGAL::cross_product(c - b, p - b) * n),
                           CGAL::to_double(CGAL::cross_product(a - c, p - c) * n),
                           CGAL::to_double(CGAL::cross_product(b - a, p - a) * n)}};
  double sum = 0;
  for (double& x : w) sum += (x = x > 0 ? x : 0.0);
  if (!(sum > 0)) return {{1.0 / 3, 1.0 / 3, 1.0 / 3}};
  for (double& x : w) x /= sum;
  return w;
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_BARYCENTRIC_H

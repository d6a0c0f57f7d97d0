// SPDX-License-Identifier: GPL-3.0-or-later
// Moving barycentric coordinates between triangles of a simplicial complex through their shared corners.
#ifndef CROSSPARAM_INTERNAL_BARYCENTRIC_H
#define CROSSPARAM_INTERNAL_BARYCENTRIC_H

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

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_BARYCENTRIC_H

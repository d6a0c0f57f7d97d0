// SPDX-License-Identifier: GPL-3.0-or-later
// SHIM, to be deleted: the one place where the CLI reaches inside the map. It stands in for two public members
// of Cross_parameterization that the library is gaining,
//
//   Indexed_triangle_mesh refined_mesh(Mesh_side side) const;
//   std::vector<std::array<std::array<double, 2>, 3>> base_atlas_coordinates(Mesh_side side) const;
//
// with `Indexed_triangle_mesh` and `Mesh_side` of crossparam/types.h. The stand-in types below have exactly
// their shapes and names; once the library has them, delete this header and replace the one call of
// refined_mesh_and_atlas_shim() (in outputs.h) by the two member calls. Nothing else changes.
#ifndef CROSSPARAM_CLI_MAP_SHIM_H
#define CROSSPARAM_CLI_MAP_SHIM_H

#include <crossparam/cross_parameterization.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace crossparam {
namespace cli {

/// Stand-in for crossparam::Mesh_side.
enum class Mesh_side { source, target };

/// Stand-in for crossparam::Indexed_triangle_mesh: points in the user's units, faces as vertex indices.
struct Indexed_triangle_mesh {
  std::vector<Point_3> points;
  std::vector<std::array<std::size_t, 3>> faces;
};

/// Per refined face, the atlas texture coordinates of its three corners.
using Atlas_coordinates = std::vector<std::array<std::array<double, 2>, 3>>;

/// What `cp.refined_mesh(side)` and `cp.base_atlas_coordinates(side)` will return: the refined mesh of one
/// side (original vertices first, faces in the refined mesh's face order, corners from the face's halfedge:
/// its source, its target, the next target) and, per face and corner, the base-domain atlas coordinates.
/// The atlas gives each base triangle a square tile of [0,1]^2 (ceil(sqrt(#base triangles)) tiles a row); a
/// face is drawn in the frame of its canonical base triangle (or pair), scaled into that triangle's tile with
/// a margin.
template <class Map>
std::pair<Indexed_triangle_mesh, Atlas_coordinates> refined_mesh_and_atlas_shim(const Map& cp, Mesh_side side) {
  const auto& base = cp.base_mesh();
  const int cols = int(std::ceil(std::sqrt(double(base.tri.size()))));
  auto uv = [&](int t, const internal::Point_2& p) {
    double lo_x = HUGE_VAL, hi_x = -HUGE_VAL, lo_y = HUGE_VAL, hi_y = -HUGE_VAL;
    for (const auto& q : base.q[t]) lo_x = std::min(lo_x, q.x()), hi_x = std::max(hi_x, q.x()), lo_y = std::min(lo_y, q.y()), hi_y = std::max(hi_y, q.y());
    double size = std::max(hi_x - lo_x, hi_y - lo_y);
    double cell = 1.0 / cols;
    double u = (t % cols + 0.1 + 0.8 * (p.x() - lo_x) / size) * cell;
    double v = (t / cols + 0.1 + 0.8 * (p.y() - lo_y) / size) * cell;
    return std::array<double, 2>{u, v};
  };
  const int s = side == Mesh_side::source ? 0 : 1;
  const auto& L = cp.work().side[s];
  const auto& P = cp.parameterization(s);
  std::pair<Indexed_triangle_mesh, Atlas_coordinates> out;
  for (auto v : L.m.vertices()) {
    const auto p = L.input_point(L.m.point(v));
    out.first.points.emplace_back(p[0], p[1], p[2]);
  }
  for (auto f : L.m.faces()) {
    auto h = L.m.halfedge(f);
    std::array<internal::WV, 3> vs{L.m.source(h), L.m.target(h), L.m.target(L.m.next(h))};
    std::array<const Base_location*, 3> ls{&P[vs[0]], &P[vs[1]], &P[vs[2]]};
    std::array<internal::Point_2, 3> q;
    int c, n;
    base.canonical_frame(ls, c, n, q);
    out.first.faces.push_back({std::size_t(vs[0]), std::size_t(vs[1]), std::size_t(vs[2])});
    out.second.push_back({uv(c, q[0]), uv(c, q[1]), uv(c, q[2])});
  }
  return out;
}

} // namespace cli
} // namespace crossparam

#endif // CROSSPARAM_CLI_MAP_SHIM_H

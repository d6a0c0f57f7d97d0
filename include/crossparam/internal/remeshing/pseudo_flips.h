// SPDX-License-Identifier: GPL-3.0-or-later
// Pseudo edge flips (paper §5.4): the flip that would bring faces of M_st closer to the target's normals is
// made by a split where the two diagonals cross, so that the source keeps its geometry.
#ifndef CROSSPARAM_INTERNAL_REMESHING_PSEUDO_FLIPS_H
#define CROSSPARAM_INTERNAL_REMESHING_PSEUDO_FLIPS_H

#include <crossparam/internal/remeshing/remesh_state.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace crossparam {
namespace internal {

/// §5.4: an edge (u, v) with opposite corners x, y whose faces deviate from the target's normal by more
/// than the threshold, and whose flip (x, y) would deviate less, is split where the diagonals (u, v) and
/// (x, y) cross in the base domain: the new vertex's image is the point of the target between x and y, which
/// reproduces the flip's change of normals while the source keeps its geometry.
inline std::size_t pseudo_flips(Remesh_state& s, double cos_max) {
  const auto& m = s.mesh.m;
  // Cosine between the normal of triangle (a, b, c) of M_st and the target's normal under its centroid.
  auto agreement = [&](WV a, WV b, WV c) {
    Kernel::Vector_3 n = triangle_normal(s.pos[a], s.pos[b], s.pos[c]);
    double len = std::sqrt(n.squared_length());
    if (!(len > 0)) return -1.0;
    Base_location centroid;
    if (!s.param.base->interpolate({&s.param[a], &s.param[b], &s.param[c]}, {1.0 / 3, 1.0 / 3, 1.0 / 3}, centroid)) return -1.0;
    // The target's unit normal at the centroid's image: its face's (faces of the target are planar).
    const Kernel::Vector_3 nt = s.target_normal(s.target_locator.locate(centroid).face);
    const double lt = std::sqrt(nt.squared_length());
    return lt > 0 ? (n / len) * (nt / lt) : 0.0;
  };
  struct Candidate {
    WV u, v;
    double t;
    double gain;
  };
  std::vector<Candidate> cands;
  for (WE e : m.edges()) {
    WH h = m.halfedge(e);
    WV u = m.source(h), v = m.target(h), x = m.target(m.next(h)), y = m.target(m.next(m.opposite(h)));
    const double now = std::min(agreement(u, v, x), agreement(v, u, y));
    if (now >= cos_max) continue;
    const double flipped = std::min(agreement(x, y, v), agreement(y, x, u));
    // A pseudo flip costs a vertex: made only where the flip brings both faces within the threshold.
    if (!(flipped > now && flipped >= cos_max)) continue;
    // Where the diagonals cross in the base domain, as a parameter along (u, v).
    std::array<const Base_location*, 4> ls{&s.param[u], &s.param[v], &s.param[x], &s.param[y]};
    std::array<Point_2, 4> p;
    int fc, fn;
    if (!s.param.base->canonical_frame(ls, fc, fn, p)) continue;
    if (CGAL::orientation(p[2], p[3], p[0]) == CGAL::orientation(p[2], p[3], p[1])) continue; // not convex
    const double d0 = CGAL::area(p[2], p[3], p[0]), d1 = CGAL::area(p[2], p[3], p[1]);
    const double t = d0 / (d0 - d1);
    if (!(t > 0.05 && t < 0.95)) continue;
    cands.push_back({u, v, t, flipped - now});
  }
  std::sort(cands.begin(), cands.end(), [](const Candidate& a, const Candidate& b) { return a.gain > b.gain; });
  // One split per face per pass: a split changes its neighbours' configuration.
  std::vector<char> touched(m.number_of_vertices(), 0);
  std::size_t n = 0;
  for (const Candidate& c : cands) {
    if (touched[c.u] || touched[c.v]) continue;
    WH h = m.halfedge(c.u, c.v);
    if (h == WH()) continue;
    if (!s.split(c.u, c.v, c.t)) continue;
    touched[c.u] = touched[c.v] = 1;
    touched.resize(m.number_of_vertices(), 1);
    ++n;
  }
  return n;
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_PSEUDO_FLIPS_H

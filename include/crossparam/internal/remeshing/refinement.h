// SPDX-License-Identifier: GPL-3.0-or-later
// Refinement of the remeshed mesh and M_st together (paper §5.3): insertion of the preimages of the worst
// target vertices and edge splits where the error is beyond the rule's threshold. Before §5, the layout's
// splits of the source that the smoothed map no longer needs are undone (an addition to the paper).
#ifndef CROSSPARAM_INTERNAL_REMESHING_REFINEMENT_H
#define CROSSPARAM_INTERNAL_REMESHING_REFINEMENT_H

#include <crossparam/internal/remeshing/fold_repair.h>
#include <crossparam/internal/remeshing/remesh_state.h>

#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace crossparam {
namespace internal {

/// What one refine() did.
struct Refinement_result {
  std::size_t splits = 0;         ///< new vertices
  std::size_t repairs_kept = 0;   ///< refused chord splits made with a local fold repair
  std::size_t repairs_undone = 0; ///< such splits undone, or refused even with one fold of slack
};
/// §5.3, refinement of the source and M_st together, in two steps:
///  1. every target vertex whose error e(v) exceeds the rule's threshold (of the largest e(v), leaving out
///     target vertices whose insertion was refused in two rounds), largest first, has its preimage F^-1(v)
///     inserted into the source face holding it: v becomes a vertex of M_st and its error drops to zero.
///     Once per face and round (the located preimages of a changed face are stale), and not next to a
///     target vertex inserted in this round. Where the insertion would fold M_st, the face's longest edge is
///     split instead;
///  2. the paper's edge splits: edges whose Eq. 2 error exceeds the rule's threshold, edges whose midpoint
///     lies farther than ε from F(midpoint), and the longest edge of every face whose centroid lies farther
///     than ε from F(centroid), at the midpoint (or near it, where the midpoint would fold M_st). Edges of M_st
///     shorter than ε/2 are not split: a large error there comes from a spot where F changes abruptly (a
///     squeezed protrusion), which halving would chase forever; the insertions of step 1 reach it. An edge
///     with a chord beyond ε that every split point would fold is split with a local fold repair, as a
///     transaction (with_repair()).
/// Returns the number of new vertices and of the splits made with a repair.
template <class Rule>
Refinement_result refine(Remesh_state& s, const Rule& rule) {
  const auto& m = s.mesh.m;
  const auto& mt = s.target.m;
  const std::size_t v0 = m.number_of_vertices();
  Refinement_result result;
  s.dirty.assign(m.number_of_faces(), 0);
  // 1. Target vertices beyond the threshold.
  // The rule's largest error leaves out the vertices refused in two rounds: at a spot the refinement cannot
  // reach, half of their error would keep every error between ε and it from being refined.
  s.refused.resize(mt.number_of_vertices(), 0);
  double max_free = 0;
  for (WV v : mt.vertices())
    if (s.refused[v] < 2) max_free = std::max(max_free, s.e[v]);
  const double thr_v = rule.threshold(max_free, s.eps);
  std::vector<WV> worst;
  for (WV v : mt.vertices())
    if (s.e[v] > thr_v) worst.push_back(v);
  std::sort(worst.begin(), worst.end(), [&](WV x, WV y) { return s.e[x] > s.e[y]; });
  std::vector<char> near(mt.number_of_vertices(), 0);
  std::vector<std::pair<WV, WV>> fallback;
  for (WV v : worst) {
    if (near[v] || s.is_dirty(s.pre[v].face)) continue;
    if (!s.insert(s.pre[v].face, s.pre[v].b)) {
      // Cannot insert without folding M_st: split the face's longest edge instead (below).
      const WH g = s.longest_edge(s.pre[v].face);
      fallback.push_back({m.source(g), m.target(g)});
      if (s.refused[v] < 2) ++s.refused[v];
      continue;
    }
    near[v] = 1;
    for (WV w : CGAL::vertices_around_target(mt.halfedge(v), mt)) near[w] = 1;
  }
  // 2. Edges.
  double emax = 0;
  for (double x : s.edge_error) emax = std::max(emax, x);
  const double thr = rule.threshold(emax, s.eps);
  std::vector<char> mark(m.number_of_edges(), 0);
  // Only the edges and faces measured before step 1 have figures (its splits made the others).
  for (WE e : m.edges())
    if (std::size_t(e) < s.edge_chord.size()) mark[e] = s.edge_chord[e] > s.eps || s.edge_error[e] > thr;
  for (WF f : m.faces()) {
    if (std::size_t(f) >= s.face_chord.size() || !(s.face_chord[f] > s.eps)) continue;
    mark[m.edge(s.longest_edge(f))] = 1;
  }
  std::vector<std::pair<WV, WV>> todo;
  for (WE e : m.edges())
    if (mark[e]) todo.push_back({m.source(m.halfedge(e)), m.target(m.halfedge(e))});
  todo.insert(todo.end(), fallback.begin(), fallback.end());
  for (const auto& [u, v] : todo) {
    if (m.halfedge(u, v) == WH()) continue; // already split
    if (!(CGAL::squared_distance(s.pos[u], s.pos[v]) > 0.25 * s.eps * s.eps)) continue; // shorter than ε/2
    if (s.split_near_middle(u, v, 5)) continue;
    // A chord beyond ε that no split can reach without a fold: split it anyway and repair the fold.
    const WE e = m.edge(m.halfedge(u, v));
    if (std::size_t(e) < s.edge_chord.size() && s.edge_chord[e] > s.eps) {
      if (with_repair(s, [&, u = u, v = v] { return s.split_near_middle(u, v, 5); })) ++result.repairs_kept;
      else ++result.repairs_undone;
    }
  }
  result.splits = m.number_of_vertices() - v0;
  return result;
}

/// Whether faces (u, v, x) and (v, u, y) of M_st, replacing the four faces of split vertex w, lie within `lim`
/// of the target: the midpoint of (u, v), the two centroids and w's image, each against F of the same
/// source point (w's image against the point of the two faces at w's base location).
inline bool restored_faces_follow_target(const Remesh_state& s, const Corner& cu, const Corner& cv, const Corner& cx,
                                         const Corner& cy, const Corner& cw, double lim) {
  if (!s.edge_faces_follow_target(cu, cv, cx, cy, lim)) return false;
  const Base_mesh& B = *s.param.base;
  const double lim2 = lim * lim;
  std::array<const Base_location*, 5> ls{&cu.loc, &cv.loc, &cx.loc, &cy.loc, &cw.loc};
  std::array<Point_2, 5> q;
  int fc, fn;
  if (!B.canonical_frame(ls, fc, fn, q)) return false;
  std::array<double, 3> b = barycentric_2(q[0], q[1], q[2], q[4]);
  Point_3 on;
  if (b[0] >= 0 && b[1] >= 0 && b[2] >= 0) {
    on = barycentric_point(cu.pos, cv.pos, cx.pos, b);
  } else {
    b = barycentric_2(q[1], q[0], q[3], q[4]);
    on = barycentric_point(cv.pos, cu.pos, cy.pos, b);
  }
  return CGAL::squared_distance(on, cw.pos) <= lim2;
}

/// Undoes the layout's edge splits of the source that the smoothed map no longer needs (an addition to the
/// paper). The splits made paths into edge paths and met the adjacency constraint of §4.2; once the map is
/// smoothed, a split vertex w of edge (u, v), still of degree 4 with its four faces, can go: edge (u, v) and
/// its two faces come back, exactly the source's geometry (w lay on that edge), if both faces are positively
/// oriented over the base mesh (exact test), fold no more faces of M_st than w's four, and follow the target
/// within ε/4 (restored_faces_follow_target()). Latest splits
/// first, so that a split of an edge of an earlier split vertex is undone before it. The mesh is then
/// compacted: original vertices keep their indices, the remaining split vertices are renumbered after them
/// (the mesh, the parameterization, the vertex records and the split list; M_st's `img` and `pos` are
/// stale until the next measure()). Returns the number of splits undone.
inline std::size_t undo_layout_splits(Remesh_state& s) {
  auto& m = s.mesh.m;
  std::size_t undone = 0;
  std::vector<char> gone(s.mesh.splits.size(), 0);
  for (std::size_t k = s.mesh.splits.size(); k-- > 0;) {
    const Edge_split& sp = s.mesh.splits[k];
    const WV w(WV::size_type(sp.w)), u(WV::size_type(sp.u)), v(WV::size_type(sp.v));
    if (s.mesh.vfeature[w] != no_feature || m.degree(w) != 4) continue;
    const WH uw = m.halfedge(u, w), vw = m.halfedge(v, w);
    if (uw == WH() || vw == WH() || m.halfedge(u, v) != WH()) continue;
    // Faces (u, w, x) and (w, v, x) on one side, (v, w, y) and (w, u, y) on the other.
    const WV x = m.target(m.next(uw)), y = m.target(m.next(vw));
    if (x == y || m.target(m.next(m.opposite(vw))) != x || m.target(m.next(m.opposite(uw))) != y) continue;
    const Corner cu = s.corner(u), cv = s.corner(v), cw = s.corner(w), cx = s.corner(x), cy = s.corner(y);
    if (!s.acceptable(std::array<Face_plan, 4>{{{&cu, &cw, &cx}, {&cw, &cv, &cx}, {&cv, &cw, &cy}, {&cw, &cu, &cy}}},
                    std::array<Face_plan, 2>{{{&cu, &cv, &cx}, {&cv, &cu, &cy}}}))
      continue;
    if (!restored_faces_follow_target(s, cu, cv, cx, cy, cw, 0.25 * s.eps)) continue;
    // The original faces of the four (the two on each side share one).
    const int oa = s.mesh.forig[m.face(uw)], ob = s.mesh.forig[m.face(vw)];
    CGAL::Euler::remove_center_vertex(uw, m); // leaves the quad x -> u -> y -> v -> x
    const WH nh = CGAL::Euler::split_face(m.halfedge(x, u), m.halfedge(y, v), m); // edge (u, v)
    for (WH g : {nh, m.opposite(nh)}) {
      bool has_x = false;
      for (WV z : CGAL::vertices_around_face(g, m)) has_x |= z == x;
      s.mesh.forig[m.face(g)] = has_x ? oa : ob;
    }
    s.mesh.epath[m.edge(nh)] = no_path;
    gone[k] = 1;
    ++undone;
  }
  if (undone == 0) return 0;
  // Compaction: Surface_mesh moves the last live vertices into the holes; follow the old indices through it.
  auto old_index = m.add_property_map<WV, std::uint32_t>("v:cp_old_index", 0).first;
  for (WV z : m.vertices()) old_index[z] = std::uint32_t(z);
  m.collect_garbage();
  s.mesh.bind_property_maps();
  const std::size_t n = m.number_of_vertices();
  std::vector<std::size_t> to_new(s.param.loc.size(), std::size_t(-1));
  std::vector<Base_location> loc(n);
  std::vector<std::pair<int, std::array<double, 3>>> vrep(n);
  std::vector<std::vector<float>> desc(s.mesh.desc.size() > n ? n : 0);
  for (WV z : m.vertices()) {
    const std::size_t o = old_index[z];
    to_new[o] = std::size_t(z);
    loc[z] = s.param.loc[o];
    vrep[z] = s.mesh.vrep[o];
    if (!desc.empty()) desc[z] = s.mesh.desc[o];
  }
  m.remove_property_map(old_index);
  s.param.loc = std::move(loc);
  s.mesh.vrep = std::move(vrep);
  if (!desc.empty()) s.mesh.desc = std::move(desc);
  std::vector<Edge_split> splits;
  for (std::size_t k = 0; k < s.mesh.splits.size(); ++k)
    if (!gone[k]) {
      Edge_split e = s.mesh.splits[k];
      e.u = to_new[e.u], e.v = to_new[e.v], e.w = to_new[e.w];
      splits.push_back(e);
    }
  s.mesh.splits = std::move(splits);
  return undone;
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_REFINEMENT_H

// SPDX-License-Identifier: GPL-3.0-or-later
// Folds of M_st (faces of the target-shaped mesh whose normal opposes the target's), removed without leaving
// F: by moving vertices in the base domain (unfold()), and by the fold repair (an addition to the paper),
// which refines around a fold in the target's metric as a transaction kept only if it removes folds
// (repair_folds(), and with_repair() for one refinement split that would fold).
#ifndef CROSSPARAM_INTERNAL_REMESHING_FOLD_REPAIR_H
#define CROSSPARAM_INTERNAL_REMESHING_FOLD_REPAIR_H

#include <crossparam/internal/remeshing/remesh_state.h>

#include <algorithm>
#include <utility>
#include <vector>

namespace crossparam {
namespace internal {

/// What repair_folds() did.
struct Fold_repair_result {
  std::size_t splits = 0; ///< splits kept
  std::size_t kept = 0;   ///< repairs kept
  std::size_t undone = 0; ///< repairs undone
};

/// Faces of M_st around source vertex v folded over against the target if v's image were `c`.
inline int folds_around(const Remesh_state& s, WV v, const Corner& c) {
  const auto& m = s.mesh.m;
  int n = 0;
  for (WH h : CGAL::halfedges_around_target(m.halfedge(v), m)) {
    WV a = m.target(m.next(h)), b = m.target(m.next(m.next(h)));
    n += s.flipped(c.pos, c.img.face, s.pos[a], s.img[a].face, s.pos[b], s.img[b].face);
  }
  return n;
}

/// Moves vertex v in the base domain along one of its edges (a quarter, half or three quarters of the way)
/// to where the fewest faces around it fold, if fewer than now and its faces stay positively oriented over
/// the base mesh (exact test). The source vertex stays where it is: only its image on the target moves.
/// Returns the change in folded faces around v (0 if it did not move).
inline int unfold_vertex(Remesh_state& s, WV v) {
  const auto& m = s.mesh.m;
  const Corner now = s.corner(v);
  const int folds_now = folds_around(s, v, now);
  if (folds_now == 0) return 0;
  int best = folds_now;
  Corner chosen = now;
  for (WV w : CGAL::vertices_around_target(m.halfedge(v), m))
    for (double t : {0.25, 0.5, 0.75}) {
      const Corner c = s.corner_at(s.param.between(v, w, t));
      const int k = folds_around(s, v, c);
      if (k >= best) continue;
      s.param[v] = c.loc;
      const bool valid = s.param.star_positive(v);
      s.param[v] = now.loc;
      if (valid) best = k, chosen = c;
    }
  if (best == folds_now) return 0;
  s.param[v] = chosen.loc;
  s.img[v] = chosen.img;
  s.pos[v] = chosen.pos;
  return best - folds_now;
}

/// Removes folds of M_st by moving vertices: a corner of a folded face is moved in the base domain along
/// one of its edges (a quarter, half or three quarters of the way) if that folds fewer faces around it and
/// keeps its faces positively oriented over the base mesh (exact test, as the smoothing). The source geometry
/// is unchanged: only where the vertex lands on the target moves. Returns the number of moves.
inline std::size_t unfold(Remesh_state& s) {
  const auto& m = s.mesh.m;
  std::size_t moves = 0;
  for (int pass = 0; pass < 4; ++pass) {
    std::vector<WV> todo;
    for (WF f : m.faces())
      if (s.face_folded(f)) {
        const WH h = m.halfedge(f);
        for (WV v : {m.source(h), m.target(h), m.target(m.next(h))}) todo.push_back(v);
      }
    if (todo.empty()) break;
    std::size_t before_moves = moves;
    for (WV v : todo)
      if (s.mesh.vfeature[v] == no_feature && unfold_vertex(s, v) < 0) ++moves;
    if (moves == before_moves) break;
  }
  return moves;
}

/// Fold repair, step of one folded face f: walks f's longest-edge propagation path (Rivara), with edge lengths
/// measured on the target-shaped mesh, to its terminal edge and splits that (near its midpoint; other points
/// on the edge where the midpoint is refused). With `any_edge`, if that split is refused, f's own edges are
/// tried, longest first. Returns whether it split.
inline bool repair_step(Remesh_state& s, WF f, bool any_edge) {
  const auto& m = s.mesh.m;
  auto split_near_middle = [&](WH h) { return s.split_near_middle(m.source(h), m.target(h), 7); };
  WF t = f;
  for (int depth = 0; depth < 40; ++depth) {
    const WH h = s.longest_edge(t), o = m.opposite(h);
    if (m.is_border(o) || m.edge(s.longest_edge(m.face(o))) == m.edge(h)) {
      if (split_near_middle(h)) return true;
      break;
    }
    t = m.face(o);
  }
  if (!any_edge) return false;
  std::vector<std::pair<double, WH>> es;
  for (WH g : CGAL::halfedges_around_face(m.halfedge(f), m))
    es.push_back({-CGAL::squared_distance(s.pos[m.source(g)], s.pos[m.target(g)]), g});
  std::sort(es.begin(), es.end());
  for (const auto& e : es)
    if (split_near_middle(e.second)) return true;
  return false;
}

/// unfold_vertex() for each of `vs` (the vertices the current repair made). Returns the change in folded
/// faces.
inline int unfold_vertices(Remesh_state& s, const std::vector<WV>& vs) {
  int change = 0;
  for (WV v : vs) change += unfold_vertex(s, v);
  return change;
}

/// The rounds of one repair (with `repairing` set): LEPP steps on the folded faces among `seed` and the
/// faces around the vertices the repair made, then those vertices unfolded, for up to 30 rounds and `budget`
/// splits. Starts a new count of made vertices; leaves the change in folded faces in `s.fold_total` (added to
/// what it holds).
inline void repair_region(Remesh_state& s, const std::vector<WF>& seed, bool second_mode, int budget) {
  const auto& m = s.mesh.m;
  constexpr int rounds = 30;
  s.made.clear();
  std::vector<WF> region = seed;
  for (int r = 0; r < rounds; ++r) {
    std::vector<WF> todo;
    for (WF g : region)
      if (s.face_folded(g)) todo.push_back(g);
    if (todo.empty()) break;
    const std::size_t made_before = s.made.size();
    for (WF g : todo)
      for (int k = 0; k < 4 && s.made.size() < std::size_t(budget) && s.face_folded(g); ++k)
        if (!repair_step(s, g, second_mode)) break;
    if (s.made.size() == made_before || s.made.size() >= std::size_t(budget)) break;
    s.fold_total += unfold_vertices(s, s.made);
    // Every face a split changed is around a vertex the repair made.
    region = seed;
    for (WV x : s.made)
      for (WF g : CGAL::faces_around_target(m.halfedge(x), m)) region.push_back(g);
    std::sort(region.begin(), region.end());
    region.erase(std::unique(region.begin(), region.end()), region.end());
  }
}

/// Fold repair (an addition to the paper). A face of M_st folds where F is so anisotropic that the face,
/// well shaped on the source, is a needle on the target across a bend of the target's parameterization.
/// Refining it towards well-shaped triangles *in the target's metric* removes the fold: each folded face gets
/// longest-edge (LEPP) bisections with target-shaped lengths, each split allowed to fold one more face than
/// it unfolds (two in the second mode), the split vertices moved as in unfold(), over up to 30 rounds on
/// the faces the repair made or changed, at most 200 splits. A repair is kept only if it leaves fewer folded
/// faces than before; otherwise the mesh and the maps are restored. Splits lie on source edges as
/// everywhere else (the source geometry is kept) and are made only if every new face is positively
/// oriented over the base mesh (exact test). The folds are counted with the verifier's rule (Remesh_state::flipped()).
/// Passes alternate two modes (slack 1, LEPP only; slack 2, the face's own edges too) until a pass of each
/// mode in a row keeps nothing, at most six passes. With `near` (a flag per vertex), only the folded faces
/// with a flagged corner or a corner the repair made are repaired.
inline Fold_repair_result repair_folds(Remesh_state& s, const std::vector<char>* near = nullptr) {
  auto& m = s.mesh.m;
  const std::size_t v0 = m.number_of_vertices();
  auto wanted = [&](WF f) {
    if (!near) return true;
    for (WV v : CGAL::vertices_around_face(m.halfedge(f), m))
      if (std::size_t(v) >= v0 || (*near)[v]) return true;
    return false;
  };
  Fold_repair_result result;
  s.repairing = true;
  constexpr int budget = 200, max_passes = 6;
  int idle = 0;
  for (int pass = 0; pass < max_passes && idle < 2; ++pass) {
    const bool second_mode = pass % 2 == 1;
    s.fold_slack = second_mode ? 2 : 1;
    std::vector<WF> folded;
    for (WF f : m.faces())
      if (s.face_folded(f) && wanted(f)) folded.push_back(f);
    if (folded.empty()) break;
    std::size_t kept = 0;
    for (WF f0 : folded) {
      if (!s.face_folded(f0)) continue; // repaired with an earlier face
      const Remesh_state::Checkpoint cp = s.checkpoint();
      s.fold_total = 0;
      repair_region(s, {f0}, second_mode, budget);
      if (s.fold_total < 0) {
        ++kept;
        continue;
      }
      s.rollback(cp);
      ++result.undone;
    }
    result.kept += kept;
    idle = kept == 0 ? idle + 1 : 0;
  }
  s.repairing = false;
  s.fold_slack = 0;
  s.made.clear();
  result.splits = m.number_of_vertices() - v0;
  return result;
}

/// A refinement split refused because it would fold M_st, made anyway as a transaction: `step` (splits with
/// `repairing` set, allowed one more fold), then the fold repair of repair_region() around the new vertex,
/// at most 50 splits; kept only if M_st has no more folded faces than before, undone
/// otherwise. Returns whether it was kept (false also where `step` itself is refused: nothing changed).
template <class Step>
bool with_repair(Remesh_state& s, Step step) {
  constexpr int budget = 50;
  const Remesh_state::Checkpoint cp = s.checkpoint();
  s.repairing = true;
  s.fold_slack = 1;
  s.fold_total = 0;
  s.made.clear();
  bool kept = false;
  if (step()) {
    const auto& m = s.mesh.m;
    std::vector<WF> seed;
    for (std::size_t i = cp.vertices; i < m.number_of_vertices(); ++i)
      for (WF g : CGAL::faces_around_target(m.halfedge(WV(i)), m)) seed.push_back(g);
    if (s.fold_total > 0) repair_region(s, seed, false, budget);
    kept = s.fold_total <= 0;
    if (!kept) s.rollback(cp);
  }
  s.repairing = false;
  s.fold_slack = 0;
  s.made.clear();
  return kept;
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_FOLD_REPAIR_H

// SPDX-License-Identifier: GPL-3.0-or-later
// The surface distance, the last improving step of the remeshing (an addition to the paper). The refinement of
// §5.3 measures the error at target vertices (e(v)), at edge midpoints and at face centroids of M_st; the
// remeshing's promise is a two-sided Hausdorff distance between M_st and the target over the whole of both
// surfaces. Between the points that §5.3 sees the two can differ (a target edge under the middle of an M_st
// face, a saddle of the target under a chord, vertices that the untangling moved off F). This step samples both
// one-sided distances on both surfaces and adds a vertex where a sample lies beyond the limit, in rounds.
#ifndef CROSSPARAM_INTERNAL_REMESHING_GAP_REFINEMENT_H
#define CROSSPARAM_INTERNAL_REMESHING_GAP_REFINEMENT_H

#include <crossparam/internal/barycentric.h>
#include <crossparam/internal/remeshing/distance_certificate.h>
#include <crossparam/internal/remeshing/fold_repair.h>
#include <crossparam/internal/remeshing/remesh_state.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace crossparam {
namespace internal {

/// The share of the tolerance that the samples must meet. A sample sees the distance at one point; between
/// samples on a face of M_st of diameter h, over a target of curvature κ, the distance can exceed the samples'
/// by about κ (h/8)² (the sagitta of the half-spacing of the sample grid); on the faces this step leaves, short
/// against the target's features, that is a few percent of ε, and the 10 % kept in reserve covers it.
constexpr double gap_sample_share = 0.9;

/// The sample points of a triangle whose longest edge is `length`, in three steps. The distance to a surface is
/// 1-Lipschitz, and every point of a triangle lies within its longest edge / √3 of one of its corners (the
/// circumradius of an acute triangle, at most half the longest edge otherwise). So the corners alone settle the
/// triangle when their largest distance plus length / √3 is within `limit`; failing that, the corners and edge
/// midpoints do when their largest distance plus length / (2√3) is (the four half-size triangles they make);
/// then nothing more is sampled. The corners' squared distances are given (`corner_d2`), not sampled. Otherwise a grid of
/// barycentric points (i, j, k) / n with i + j + k = n, n chosen so that neighbouring samples lie at most ε/2
/// apart (at least 4, at most `gap_max_subdivision`). `f(b, edge)` returns the squared distance at the point
/// with barycentric coordinates b, which lies on edge `edge` (0: corners 0-1, 1: 1-2, 2: 2-0) or inside (-1).
constexpr int gap_max_subdivision = 16;
template <class F>
void for_each_gap_sample(double length, double eps, double limit, const std::array<double, 3>& corner_d2, F f) {
  auto grid = [&f](int n, double worst2) {
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const int k = n - i - j;
        if (i == n || j == n || k == n) continue; // a corner: its distance is given
        const int edge = k == 0 ? 0 : i == 0 ? 1 : j == 0 ? 2 : -1;
        worst2 = std::max(worst2, f(std::array<double, 3>{double(i) / n, double(j) / n, double(k) / n}, edge));
      }
    return worst2;
  };
  const double corners = std::max({corner_d2[0], corner_d2[1], corner_d2[2]});
  if (std::sqrt(corners) + length / std::sqrt(3.0) <= limit) return;
  if (std::sqrt(grid(2, corners)) + length / (2 * std::sqrt(3.0)) <= limit) return;
  grid(std::max(4, std::min(gap_max_subdivision, int(std::ceil(2 * length / eps)))), corners);
}

/// What snap_surface_gaps() did.
struct Gap_snap_result {
  std::size_t vertices = 0;  ///< new vertices
  std::size_t rounds = 0;    ///< rounds that made some
  double worst_before = 0;   ///< largest sampled distance before (working coordinates)
  std::size_t left = 0;      ///< samples of the last round still beyond the limit
};

/// The last step of the remeshing (after the untangling, which places vertices of M_st off F): where a sample of
/// M_st lies farther than `gap_sample_share` ε from the target, or a sample of the target that far from M_st,
/// a vertex is added to the M_st face concerned, at the sample's place on the source (on the edge the sample
/// lies on, or inside the face), and placed on the target at the point that closes the gap: the target point
/// nearest the M_st sample, or the target sample itself; where that would fold M_st (the nearest point on the far
/// side of a part of the target thinner than the face), at F of the new source point, as a split of §5.3 does.
/// The source keeps its geometry (the new vertex lies on a source face); the new vertex of M_st lies on the
/// target, off F by at most the gap it closes. A vertex is
/// added only where the new faces are positively oriented over the base mesh (exact test), fold M_st no more
/// than before, lie closer to the target than the gap at their centroids and edge midpoints, and are none of
/// them flipped by the verifier's (standard) rule; one per face and round, the farthest first. Where neither
/// placement fits, the split at F is made with the fold repair (with_repair()), kept only if M_st ends with no
/// more folds and no face around a new vertex is flipped by the verifier's rule. At most `max_rounds` rounds, and not past
/// `vertex_cap` vertices. M_st's figures of measure() are not brought up to date (no measure() may follow).
inline Gap_snap_result snap_surface_gaps(Remesh_state& s, unsigned max_rounds, std::size_t vertex_cap) {
  using K = Kernel;
  Gap_snap_result r;
  auto& m = s.mesh.m;
  const auto& mt = s.target.m;
  const double limit = gap_sample_share * s.eps, limit2 = limit * limit;
  using T_primitive = CGAL::AABB_face_graph_triangle_primitive<Refined_mesh>;
  using T_tree = CGAL::AABB_tree<CGAL::AABB_traits<K, T_primitive>>;
  T_tree target_tree(faces(mt).first, faces(mt).second, mt);
  auto target_location = [&mt](WF tf, const Point_3& q) {
    const WH h = mt.halfedge(tf);
    return Work_location{tf, barycentric_in_triangle(mt.point(mt.source(h)), mt.point(mt.target(h)),
                                                     mt.point(mt.target(mt.next(h))), q)};
  };
  struct Gap {
    double d2 = -1;
    std::array<double, 3> b{{0, 0, 0}}; // on the M_st face
    Point_3 q;                          // on the target
    WF target_face;
  };
  // What a round samples: every face of M_st and of the target in the first; then the faces of M_st made or
  // changed by the round before (the others' distances to the fixed target are unchanged) and the target faces
  // with a far sample in the round before.
  std::vector<char> sample_mst(m.number_of_faces(), 1), sample_target(mt.number_of_faces(), 1);
  for (unsigned round = 0;; ++round) {
    const std::size_t nf = m.number_of_faces();
    sample_mst.resize(nf, 1);
    std::vector<char> far_target(mt.number_of_faces(), 0);
    std::vector<K::Triangle_3> tris(nf);
    for (WF f : m.faces()) {
      const WH h = m.halfedge(f);
      tris[f] = K::Triangle_3(s.pos[m.source(h)], s.pos[m.target(h)], s.pos[m.target(m.next(h))]);
    }
    using M_primitive = CGAL::AABB_triangle_primitive<K, std::vector<K::Triangle_3>::const_iterator>;
    using M_tree = CGAL::AABB_tree<CGAL::AABB_traits<K, M_primitive>>;
    M_tree mst_tree(tris.cbegin(), tris.cend());
    mst_tree.accelerate_distance_queries();
    std::vector<Gap> gap(nf);
    std::size_t far = 0;
    double worst2 = 0;
    auto record = [&](std::size_t f, double d2, const std::array<double, 3>& b, const Point_3& q, WF tf) {
      worst2 = std::max(worst2, d2);
      if (d2 > limit2) {
        ++far;
        if (d2 > gap[f].d2) gap[f] = Gap{d2, b, q, tf};
      }
      return d2;
    };
    for (std::size_t i = 0; i < nf; ++i) {
      if (!sample_mst[i]) continue;
      const K::Triangle_3& t = tris[i];
      // The search starts from a corner, which lies on the target (faster than a search from nowhere; the
      // closest point found is the same).
      const WH hi = m.halfedge(WF(static_cast<WF::size_type>(i)));
      const WV corner = m.source(hi);
      // Faces certified within the limit (distance_certificate.h: the usual case, a face over one flat part of
      // the target) need no sample: no point of theirs is beyond it.
      {
        std::pair<Point_3, WF> hint(s.pos[corner], s.img[corner].face);
        const Distance_probe a{t[0], 0, s.img[corner].face}, b{t[1], 0, s.img[m.target(hi)].face},
            c{t[2], 0, s.img[m.target(m.next(hi))].face};
        if (certified_within(target_tree, mt, a, b, c, limit, hint)) continue;
      }
      const typename T_tree::Point_and_primitive_id hint(s.pos[corner], s.img[corner].face);
      for_each_gap_sample(longest_side(t[0], t[1], t[2]), s.eps, limit, {0, 0, 0}, [&](const std::array<double, 3>& b, int) {
        const Point_3 p = barycentric_point(t[0], t[1], t[2], b);
        const auto hit = target_tree.closest_point_and_primitive(p, hint);
        return record(i, CGAL::squared_distance(p, hit.first), b, hit.first, hit.second);
      });
    }
    // A sample p of target face tf: its squared distance to M_st (and in `near`, if given, the M_st face nearest it).
    auto target_sample = [&](const Point_3& p, WF tf, std::size_t* near = nullptr) {
      const auto hit = mst_tree.closest_point_and_primitive(p);
      const std::size_t i = std::size_t(hit.second - tris.cbegin());
      if (near) *near = i;
      const K::Triangle_3& t = tris[i];
      const double d2 = CGAL::squared_distance(p, hit.first);
      if (d2 > limit2) far_target[tf] = 1;
      return record(i, d2, barycentric_in_triangle(t[0], t[1], t[2], hit.first), p, tf);
    };
    std::vector<double> vertex_d2(mt.number_of_vertices(), -1.0);
    std::vector<std::size_t> vertex_near(mt.number_of_vertices(), 0); // the M_st face nearest each target vertex
    for (WF tf : mt.faces()) {
      if (!sample_target[tf]) continue;
      for (WH h : CGAL::halfedges_around_face(mt.halfedge(tf), mt))
        if (vertex_d2[mt.target(h)] < 0)
          vertex_d2[mt.target(h)] = target_sample(mt.point(mt.target(h)), tf, &vertex_near[mt.target(h)]);
    }
    for (WF tf : mt.faces()) {
      if (!sample_target[tf]) continue;
      const WH h = mt.halfedge(tf);
      const WV x = mt.source(h), y = mt.target(h), z = mt.target(mt.next(h));
      const Point_3 &a = mt.point(x), &b = mt.point(y), &c = mt.point(z);
      // As for M_st's faces: target faces certified within the limit of M_st need no sample.
      {
        using Id = typename M_tree::Primitive_id;
        const Id nx = tris.cbegin() + vertex_near[x], ny = tris.cbegin() + vertex_near[y], nz = tris.cbegin() + vertex_near[z];
        std::pair<Point_3, Id> hint(a, nx);
        const Basic_distance_probe<Id> pa{a, std::sqrt(vertex_d2[x]), nx}, pb{b, std::sqrt(vertex_d2[y]), ny},
            pc{c, std::sqrt(vertex_d2[z]), nz};
        if (certified_within(mst_tree, [](Id i) { return *i; }, pa, pb, pc, limit, hint)) continue;
      }
      for_each_gap_sample(longest_side(a, b, c), s.eps, limit, {vertex_d2[x], vertex_d2[y], vertex_d2[z]},
                          [&](const std::array<double, 3>& w, int) { return target_sample(barycentric_point(a, b, c, w), tf); });
    }
    if (round == 0) r.worst_before = std::sqrt(worst2);
    r.left = far;
    if (far == 0 || round == max_rounds || m.number_of_vertices() >= vertex_cap) break;
    if (s.budget.stop("the remeshing's surface-distance snapping", [&] {
          return "round " + std::to_string(round + 1) + " of at most " + std::to_string(max_rounds) + ", " +
                 std::to_string(far) + " samples beyond the tolerance";
        }))
      break;
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < nf; ++i)
      if (gap[i].d2 > 0) order.push_back(i);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return gap[a].d2 > gap[b].d2; });
    std::vector<char> changed(nf, 0);
    const std::size_t v0 = m.number_of_vertices();
    // Whether the new faces `after` close the gap: at their centroids and edge midpoints they lie closer to the
    // target than `gap` (a vertex placed on a far sheet of a thin part would pull them away), and none of them
    // is flipped by the verifier's rule (its normal more than 90° from the target's at the point nearest its
    // centroid).
    auto closes = [&](const auto& after, double gap) {
      for (const Face_plan& f : after) {
        const Point_3 &a = f[0]->pos, &b = f[1]->pos, &c = f[2]->pos;
        const typename T_tree::Point_and_primitive_id hint(a, f[0]->img.face);
        for (const Point_3& p : {CGAL::midpoint(a, b), CGAL::midpoint(b, c), CGAL::midpoint(c, a)})
          if (!(CGAL::squared_distance(p, target_tree.closest_point(p, hint.first)) < gap * gap)) return false;
        const auto hit = target_tree.closest_point_and_primitive(CGAL::centroid(a, b, c), hint);
        if (!(CGAL::squared_distance(CGAL::centroid(a, b, c), hit.first) < gap * gap)) return false;
        if (triangle_normal(a, b, c) * s.target_normal(hit.second) < 0) return false;
      }
      return true;
    };
    // Where neither placement fits, the split at F is made as a transaction with the fold repair
    // (with_repair(): a split allowed one more fold, then refined around in the target's metric, kept only if
    // M_st ends with no more folds), and undone as well if any face around a vertex it made is flipped by
    // the verifier's rule. The next round samples the faces it made.
    auto repaired = [&](std::vector<char>& changed, auto step) {
      const Remesh_state::Checkpoint cp = s.checkpoint();
      if (!with_repair(s, step)) return;
      std::vector<WF> around; // every face the transaction changed is around a vertex it made
      for (std::size_t k = cp.vertices; k < m.number_of_vertices(); ++k)
        for (WF g : CGAL::faces_around_target(m.halfedge(WV(WV::size_type(k))), m)) around.push_back(g);
      for (WF g : around) {
        const WH gh = m.halfedge(g);
        const Point_3 &a = s.pos[m.source(gh)], &b = s.pos[m.target(gh)], &c = s.pos[m.target(m.next(gh))];
        const auto hit = target_tree.closest_point_and_primitive(CGAL::centroid(a, b, c));
        if (triangle_normal(a, b, c) * s.target_normal(hit.second) < 0) {
          s.rollback(cp);
          return;
        }
      }
      for (WF g : around)
        if (std::size_t(g) < nf) changed[g] = 1;
    };
    for (std::size_t i : order) {
      if (changed[i] || m.number_of_vertices() >= vertex_cap) continue;
      const WF f(static_cast<WF::size_type>(i));
      const Gap& g = gap[i];
      const WH h0 = m.halfedge(f);
      const WV vs[3] = {m.source(h0), m.target(h0), m.target(m.next(h0))};
      // A point within a thousandth of the face's barycentric range of an edge is put on that edge: a face split
      // there would make a needle.
      constexpr double on_edge = 1e-3;
      int zero = -1;
      for (int k = 0; k < 3; ++k)
        if (g.b[k] < on_edge && (zero < 0 || g.b[k] < g.b[zero])) zero = k;
      Corner cw{Base_location{}, target_location(g.target_face, g.q), g.q};
      if (zero >= 0) {
        const WV u = vs[(zero + 1) % 3], v = vs[(zero + 2) % 3];
        const double bu = g.b[(zero + 1) % 3], bv = g.b[(zero + 2) % 3];
        if (!(bu > 0 && bv > 0)) continue; // at a corner: nothing to add there
        const double t = bv / (bu + bv);
        const WH h = m.halfedge(u, v);
        const WV x = m.target(m.next(h)), y = m.target(m.next(m.opposite(h)));
        cw.loc = s.param.between(u, v, t);
        const Corner cu = s.corner(u), cv = s.corner(v), cx = s.corner(x), cy = s.corner(y);
        auto fits = [&](const Corner& c) {
          const std::array<Face_plan, 4> after{{{&cu, &c, &cx}, {&c, &cv, &cx}, {&cv, &c, &cy}, {&c, &cu, &cy}}};
          return s.split_keeps_source(u, v, x, y, t) &&
                 s.acceptable(std::array<Face_plan, 2>{{{&cu, &cv, &cx}, {&cv, &cu, &cy}}}, after) &&
                 closes(after, std::sqrt(g.d2));
        };
        if (!fits(cw) && !fits(cw = s.corner_at(cw.loc))) {
          repaired(changed, [&] { return s.split_near_middle(u, v, 7); });
          continue;
        }
        for (WH e : {h, m.opposite(h)})
          if (std::size_t(m.face(e)) < nf) changed[m.face(e)] = 1;
        s.commit(s.mesh.split_edge(u, v, t), cw);
      } else {
        cw.loc = s.param.at(f, g.b);
        const Corner c0 = s.corner(vs[0]), c1 = s.corner(vs[1]), c2 = s.corner(vs[2]);
        auto fits = [&](const Corner& c) {
          const std::array<Face_plan, 3> after{{{&c0, &c1, &c}, {&c1, &c2, &c}, {&c2, &c0, &c}}};
          return s.insert_keeps_source(f, g.b) && s.acceptable(std::array<Face_plan, 1>{{{&c0, &c1, &c2}}}, after) &&
                 closes(after, std::sqrt(g.d2));
        };
        if (!fits(cw) && !fits(cw = s.corner_at(cw.loc))) {
          repaired(changed, [&] { return s.insert(f, g.b); });
          continue;
        }
        changed[i] = 1;
        s.commit(s.mesh.split_face(f, g.b), cw);
      }
    }
    const std::size_t made = m.number_of_vertices() - v0;
    if (made == 0) break;
    r.vertices += made, ++r.rounds;
    sample_mst = std::move(changed);
    sample_target = std::move(far_target);
  }
  return r;
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_GAP_REFINEMENT_H

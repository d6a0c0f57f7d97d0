// SPDX-License-Identifier: GPL-3.0-or-later
// The map's overlay as a compatible remesh (an addition to the paper). Over the base mesh, the source's faces
// and the target's faces are two triangulations of one domain. Target_overlay makes every target vertex a vertex
// of M_s (Remesh_state::insert()) and every target edge a chain of edges of M_s, so that each face of M_s lies
// inside one target face over the base mesh. Its image M_st then lies inside that target face: on the target,
// with the target's normal, at distance zero, meeting another face only where the target meets itself. A target
// edge is inserted as a constrained edge is in a triangulation (Sloan 1993): the edges of M_s it crosses are
// flipped where that keeps the source (both faces in one source face, convex there) and the parameterization
// one-to-one (Remesh_state::flip_keeps_source()), and split at the crossing (Remesh_state::split()) where not:
// at a source edge, a layout path, or a quadrilateral that stays concave. Splitting every crossed edge instead
// adds a vertex per crossing with every edge an earlier split made, and the count grows with the square of the
// target vertices a source face holds (eiffel_g4: 3.56 million vertices, 412,000 with the flips). Lawson's flips
// (delaunay()) then fatten the faces inside each target face: the insertion's flips leave long thin ones whose
// normals rounding decides. The source-shaped mesh stays an exact copy of the source (every vertex lies in a
// source face, every face in one) and the parameterization one-to-one (the exact test of each split, insert and
// flip). Every face is positively oriented in its source face but for rounding: a vertex computed within
// rounding of a line of others can leave a face there reversed or with no area (tens in an overlay of a
// million faces); the decimation removes them and makes none (overlay_decimation.h), and the faces with no area
// that it leaves are flipped away after it (Remesh_state::flip_zipper()). On each face the correspondence is
// the affine map between its source triangle and its M_st triangle: F at the vertices. The overlay has many vertices; the decimation
// (overlay_decimation.h) removes those the checks do not need.
//
// Crossings are computed with exact predicates in the base mesh's frame that holds both edges
// (Base_mesh::canonical_frame()), or in the base triangle two frames share; a target vertex or edge within
// `conform_snap` of a vertex or edge of M_s is taken to pass through it where its image there is as near on
// the target (place(), passes_through()).
#ifndef CROSSPARAM_INTERNAL_REMESHING_OVERLAY_H
#define CROSSPARAM_INTERNAL_REMESHING_OVERLAY_H

#include <crossparam/internal/remeshing/remesh_state.h>
#include <crossparam/metrics.h>


#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <vector>

namespace crossparam {
namespace internal {

/// Relative distance (in barycentric coordinates of a face of M_s, or in the parameter along its edge) below
/// which a target vertex or a crossing with a target edge is taken to be at the vertex or on the edge of M_s
/// that it nearly touches. A face whose corner is that far across a target edge bends over it by at most this
/// fraction of its own size: a millionth, far below any angle the checks measure, while a split there would make
/// a face a million times thinner than its neighbours, whose normal rounding decides.
constexpr double conform_snap = 1e-6;

/// Share of the tolerance ε by which a snap (see conform_snap) may move a target vertex on the target, whatever
/// the target's edges there: a hundredth, a small part of the tenth of ε that the decimation leaves beside the
/// 0.9 ε it certifies (decimation_margin). A larger move is taken only if it is within conform_snap of the
/// shortest target edge at the vertex.
constexpr double overlay_snap_share = 0.01;

/// Distance in the base mesh's frames (whose triangles have edges of length about 1) below which a point is
/// on a line whatever the length of the edge it ends: a hundred times the rounding of coordinates near 1, so
/// that two points computed on one target edge in different frames are on it together.
constexpr double conform_floor = 1e-14;

/// Bound of the walk that finds the face of M_s holding a target vertex (faces visited): the walk starts in
/// the face the point locator gives, which holds the vertex up to rounding, so it ends within a few rings.
constexpr std::size_t overlay_walk_faces = 4096;

/// Largest ratio of the overlay's vertices to the source's (after the layout's splits, layout_vertices) for
/// which the automatic construction decimates it (Remeshing_construction::automatic; asked for, the overlay is
/// always decimated). The overlay has the source's and the target's vertices plus one per crossing that the
/// flips do not remove: 7.5-16 times the source's after the layout on the bench (lion_cat and yang_cat_horse
/// 16), 11 times on feline_g2, 37 times on eiffel_g4, whose map sends the part of the tower around its second
/// platform into a few faces of the pyramid. The decimation costs about 0.1-0.3 ms per overlay vertex on one
/// core (lion_cat's 98,000 in 15 s, eiffel_g4's 412,000 in 2 minutes): 128 times keeps it to a few minutes
/// for a source of ten thousand vertices, and the memory to about a gigabyte.
constexpr std::size_t overlay_max_growth = 128;

/// Largest ratio of the second overlay's vertices to the first's (Compatible_remesher: the overlay built again,
/// with no flip that makes a sliver on the source, where the first fails the strict checks). The second splits
/// where the first flipped on rounding; where many target edges pass through nearly one point of the source
/// those splits come in clusters whose count grows with the square of the edges through them, and so do the
/// construction's and the decimation's time (shrec/382_385: past 1.6 GB and ten minutes of construction where
/// the first took 18 s). eiffel_g4's second overlay at 1 % has 1.65 times the first's vertices; beyond twice,
/// the second is abandoned and the first kept.
constexpr std::size_t overlay_second_growth = 2;

/// Bound on the passes of flips that make a target edge a chain of edges of M_s (Target_overlay::run()). A pass
/// flips every edge the target edge crosses whose two faces allow it; an edge whose quadrilateral is concave
/// waits for a neighbour's flip. The passes end when one flips nothing; the bound only caps the time where
/// rounding would make flips undo each other. What is left is split at the crossings, which is always valid,
/// so the bound changes the overlay's size, never its exactness.
constexpr std::size_t overlay_flip_passes = 32;

/// Bound on Target_overlay::delaunay()'s flips, per edge of M_s. Lawson's flips end after finitely many (in a
/// plane each raises the sorted vector of the triangles' angles, and each flip is inside one target face);
/// this only bounds the time where rounding would make two flips undo each other.
constexpr std::size_t overlay_delaunay_work = 8;

/// How segment (c, d) (a target edge, in a frame of the base mesh) meets segment (a, z) (an edge of M_s).
enum class Overlay_crossing {
  none,     ///< it does not cross it, or runs along it
  at_first, ///< it crosses it within conform_snap of a (relative to |z - a|)
  at_second,///< ... of z
  inside,   ///< it crosses it farther from both ends, at a + t (z - a)
  along     ///< it crosses it (exact test), with both a and z within conform_snap of its line: nearly along it
};
/// How segment (c, d) meets segment (a, z): it crosses it when c and d are strictly on either side of the
/// line of (a, z) and a and z strictly on either side of the line of (c, d) (exact predicates); the crossing
/// is at an end when that end is within conform_snap times |z - a| of the line of (c, d), or t within
/// conform_snap of 0 or 1 (an edge of M_s that ends on the target edge, up to rounding); an edge of M_s whose
/// both ends are that near is nearly along the target edge (`along`: Target_overlay::crossing() decides on the
/// target whether it runs along it). t is computed from the two distances (well conditioned when the crossing
/// is inside).
inline Overlay_crossing overlay_crossing(const Point_2& a, const Point_2& z, const Point_2& c, const Point_2& d, double& t) {
  const CGAL::Orientation oc = CGAL::orientation(a, z, c), od = CGAL::orientation(a, z, d);
  if (oc == CGAL::ZERO || od == CGAL::ZERO || oc == od) return Overlay_crossing::none;
  const CGAL::Orientation oa = CGAL::orientation(c, d, a), oz = CGAL::orientation(c, d, z);
  if (oa == CGAL::ZERO || oz == CGAL::ZERO || oa == oz) return Overlay_crossing::none;
  const double dx = d.x() - c.x(), dy = d.y() - c.y(), len = std::sqrt(dx * dx + dy * dy);
  const double elen = std::sqrt(CGAL::squared_distance(a, z));
  if (!(len > 0) || !(elen > 0)) return Overlay_crossing::none;
  // Signed distances of a and z from the line of (c, d).
  const double da = ((a.x() - c.x()) * dy - (a.y() - c.y()) * dx) / len;
  const double dz = ((z.x() - c.x()) * dy - (z.y() - c.y()) * dx) / len;
  const double near = std::max(conform_snap * elen, conform_floor);
  const bool near_a = !(std::abs(da) > near), near_z = !(std::abs(dz) > near);
  t = da / (da - dz);
  if (near_a && near_z) {
    t = std::min(1 - conform_snap, std::max(conform_snap, t));
    return Overlay_crossing::along;
  }
  if (!(t > 0 && t < 1)) t = near_a ? 0 : 1;
  if (near_a || !(t > conform_snap)) return Overlay_crossing::at_first;
  if (near_z || !(t < 1 - conform_snap)) return Overlay_crossing::at_second;
  return Overlay_crossing::inside;
}

/// What Target_overlay::run() did.
struct Overlay_result {
  std::vector<WV> made;     ///< vertices it added
  std::size_t refused = 0;  ///< inserts and splits refused by the exact orientation test
  /// Target vertices inserted at their own location over the base mesh, not the one interpolated in the face
  /// of M_s that holds them, whose image was off the vertex by more than conform_snap of the target's edges there
  /// (where the map squeezes the target: Target_overlay::place())
  std::size_t exact = 0;
  /// Crossings with edges of M_s nearly along a target edge's line over the base mesh, but not along it on the
  /// target (Overlay_crossing::along)
  std::size_t along_crossed = 0;
  std::vector<Point_3> refused_at; ///< where on the target each of those is (working coordinates)
  std::size_t flips = 0;    ///< edges of M_s flipped to make target edges edges of M_s
  std::size_t delaunay_flips = 0; ///< edges flipped afterwards to fatten the faces (Target_overlay::delaunay())
  bool complete = false;    ///< whether every target vertex and edge was found and inserted
};

/// The overlay of M_s (in `state`) with the target.
class Target_overlay {
public:
  explicit Target_overlay(Remesh_state& state) : s(state), B(*state.param.base) {}

  /// Every vertex of M_s is put back at F (features are there already); then each target vertex is inserted
  /// in the face of M_s that holds it, and each target edge is split into M_s's edges at its crossings,
  /// adding at most `max_new` vertices. The crossings of a target edge are found from the vertices its ends
  /// became: a walk over the faces that meet the edge, from those around its ends, and one ring more.
  Overlay_result run(std::size_t max_new) {
    auto& m = s.mesh.m;
    const auto& tm = s.target.m;
    Overlay_result r;
    for (WV v : m.vertices())
      if (s.mesh.vfeature[v] == no_feature) {
        const Corner c = s.corner_at(s.param[v]);
        s.img[v] = c.img, s.pos[v] = c.pos;
      }
    const int slack = s.fold_slack;
    s.fold_slack = std::numeric_limits<int>::max() / 4;
    Base_locator locator;
    locator.build(s.param);
    std::vector<WV> rv(tm.number_of_vertices(), WV());
    std::vector<char> placed(tm.number_of_vertices(), 0); // rv[tv] stands for tv: no insert was refused
    auto put = [&](WF f, const std::array<double, 3>& b, WV tv) {
      const std::size_t refused = r.refused;
      rv[tv] = place(f, b, tv, r);
      placed[tv] = r.refused == refused;
    };
    std::vector<char> seen;
    // Target vertices, each in the piece of the face that held it when the walk began.
    for (WV tv : tm.vertices()) {
      if (r.made.size() >= max_new) break;
      const WF f0 = locator.locate(s.target_param[tv]).face;
      const int orig = s.mesh.forig[f0];
      std::vector<WF> queue{f0}, visited{f0};
      seen.assign(m.number_of_faces(), 0);
      seen[f0] = 1;
      while (!queue.empty()) {
        const WF f = queue.back();
        queue.pop_back();
        std::array<double, 3> b;
        const int where = inside(f, tv, b);
        if (where > 0) {
          put(f, b, tv);
          break;
        }
        if (visited.size() < overlay_walk_faces) {
          std::vector<WF> next;
          for (WV v : corners(f)) faces_of(v, next);
          for (WF g : next)
            if (!seen[g]) seen[g] = 1, visited.push_back(g), queue.insert(s.mesh.forig[g] == orig ? queue.end() : queue.begin(), g);
        }
      }
      if (rv[tv] == WV()) {
        // In no face exactly (a point on an edge that two frames round differently): the face where it is
        // least outside, its barycentrics clamped.
        WF best = WF();
        std::array<double, 3> bb{};
        double best_min = -HUGE_VAL;
        for (WF f : visited) {
          std::array<double, 3> b;
          if (!barycentrics(f, tv, b)) continue;
          const double mn = std::min({b[0], b[1], b[2]});
          if (mn > best_min) best_min = mn, best = f, bb = b;
        }
        if (best != WF() && best_min > -conform_snap) put(best, bb, tv);
      }
    }
    // Target edges, each made a chain of M_s's edges: by flips where M_s allows them, by splits at the
    // remaining crossings.
    std::size_t skipped = 0;
    std::set<std::array<WV, 2>> on_target; // edges of M_s along target edges already inserted
    auto key = [](WV u, WV v) { return std::array<WV, 2>{{std::min(u, v), std::max(u, v)}}; };
    for (WE te : tm.edges()) {
      if (r.made.size() >= max_new) break;
      const WV a = tm.vertex(te, 0), b = tm.vertex(te, 1);
      if (rv[a] == WV() || rv[b] == WV()) {
        ++skipped;
        continue;
      }
      // The edges of M_s at a vertex that stands for an end of the target edge meet it there only; at the
      // corner a refused insert fell back on, they may cross it.
      const WV ea = placed[a] ? rv[a] : WV(), eb = placed[b] ? rv[b] : WV();
      auto at_end = [&](WV u, WV v) { return u == ea || u == eb || v == ea || v == eb; };
      std::vector<Crossing> xs = crossings(a, b, rv[a], rv[b], seen, at_end);
      // Flips first (Sloan's insertion of a constrained edge): each crossed edge whose two faces form a
      // quadrilateral that flip_keeps_source() allows is flipped; its new diagonal, if it crosses too, and
      // the edges that cannot be flipped yet wait for the next pass. The other edges of M_s are untouched by
      // a flip, so the list stays complete.
      for (std::size_t pass = 0; pass < overlay_flip_passes && !xs.empty(); ++pass) {
        std::vector<Crossing> wait;
        std::size_t flips = 0;
        for (const Crossing& x : xs) {
          const WH h = m.halfedge(x.u, x.v);
          if (h == WH()) continue;
          if (on_target.count(key(x.u, x.v)) || !s.flip_keeps_source(h)) {
            wait.push_back(x);
            continue;
          }
          const WV p = m.target(m.next(h)), q = m.target(m.next(m.opposite(h)));
          s.touch(x.u, x.v);
          CGAL::Euler::flip_edge(h, m);
          ++flips;
          Crossing y;
          if (!at_end(p, q) && crossing(std::min(p, q), std::max(p, q), a, b, y)) wait.push_back(y);
        }
        r.flips += flips;
        xs = std::move(wait);
        if (flips == 0) break;
      }
      std::vector<WV> chain{rv[a], rv[b]};
      for (const Crossing& x : xs) {
        if (m.halfedge(x.u, x.v) == WH()) continue;
        const std::size_t n0 = m.number_of_vertices();
        if (s.split(x.u, x.v, x.t)) {
          for (std::size_t i = n0; i < m.number_of_vertices(); ++i) {
            r.made.push_back(WV(WV::size_type(i)));
            chain.push_back(WV(WV::size_type(i)));
          }
        } else {
          ++r.refused;
          r.refused_at.push_back(s.corner_at(s.param.between(x.u, x.v, x.t)).pos);
        }
      }
      // The edges of M_s between two of the chain's vertices lie along the target edge: none is flipped
      // for a later one.
      for (WV u : chain)
        for (WV w : CGAL::vertices_around_target(m.halfedge(u), m))
          if (std::find(chain.begin(), chain.end(), w) != chain.end()) on_target.insert(key(u, w));
    }
    r.along_crossed = along_crossed_;
    if (r.made.size() < max_new) r.delaunay_flips = delaunay(on_target); // an overlay cut short is abandoned
    s.fold_slack = slack;
    r.complete = skipped == 0 && r.refused == 0 && r.made.size() < max_new;
    return r;
  }


private:
  /// The vertex of M_s that target vertex tv at barycentrics b of face f (inside it, or outside by less than
  /// conform_snap) becomes: the corner of f it is at (two coordinates within conform_snap of zero), a new vertex
  /// on the edge it is on (one) or inside f (none). A snap to a corner or an edge moves the vertex on the
  /// target, to the image of the corner or of the point of the edge, and is taken only if that move is within
  /// overlay_snap_share ε, or within conform_snap of the shortest target edge at tv: where the map squeezes a
  /// part of the target into nearly one point of the source (a leg's tip), coordinates that small stand for
  /// distances on the target that the output must keep, and the vertex is inserted where it is (on an edge or
  /// at a corner only where its coordinates are exactly zero). If the exact test refuses the split or insert,
  /// the corner nearest to it, counted as refused.
  WV place(WF f, std::array<double, 3> b, WV tv, Overlay_result& r) {
    const auto& m = s.mesh.m;
    for (double& x : b) x = std::max(x, 0.0);
    const double sum = b[0] + b[1] + b[2];
    for (double& x : b) x /= sum;
    const std::array<WV, 3> fv = corners(f);
    const WV nearest = fv[std::size_t(std::max_element(b.begin(), b.end()) - b.begin())];
    int zero = -1, small = 0;
    for (int k = 0; k < 3; ++k)
      if (!(b[k] > conform_snap)) zero = k, ++small;
    const bool snap_kept = small >= 2 ? snap_keeps_target(s.pos[nearest], tv)
                           : small == 1 ? snap_keeps_target(s.corner_at(s.param.between(fv[(zero + 1) % 3], fv[(zero + 2) % 3], b[(zero + 2) % 3])).pos, tv)
                                        : true;
    if (!snap_kept) {
      small = 0;
      for (int k = 0; k < 3; ++k)
        if (b[k] == 0) zero = k, ++small;
      if (small >= 2) return refuse(r, tv), nearest; // at the corner exactly, but not there on the target
    }
    if (small >= 2) return nearest;
    const std::size_t n0 = m.number_of_vertices();
    // The new vertex's location over the base mesh: interpolated at b, or tv's own where the map squeezes the
    // target so much that the interpolation's rounding moves its image off tv (Overlay_result::exact).
    const Base_location interpolated = small == 0 ? s.param.at(f, b) : s.param.between(fv[(zero + 1) % 3], fv[(zero + 2) % 3], b[(zero + 2) % 3]);
    const bool own = !(std::sqrt(CGAL::squared_distance(s.corner_at(interpolated).pos, s.target.m.point(tv))) <=
                       conform_snap * shortest_edge(tv));
    const Base_location* at = own ? &s.target_param[tv] : &interpolated;
    r.exact += own;
    bool done = small == 0 ? s.insert(f, b, at) : s.split(fv[(zero + 1) % 3], fv[(zero + 2) % 3], b[(zero + 2) % 3], at);
    // At its own location tv may lie on an edge of f (an insert there would make a face with no area): a split
    // of that edge at the location, the edge nearest first.
    if (own)
      for (int k : by_coordinate(b)) {
        if (done) break;
        done = s.split(fv[(k + 1) % 3], fv[(k + 2) % 3], b[(k + 2) % 3] / std::max(b[(k + 1) % 3] + b[(k + 2) % 3], 1e-300), at);
      }
    if (!done) return refuse(r, tv), nearest;
    for (std::size_t i = n0; i < m.number_of_vertices(); ++i) r.made.push_back(WV(WV::size_type(i)));
    return WV(WV::size_type(m.number_of_vertices() - 1));
  }
  /// The corners of a face in increasing order of barycentric coordinates b (their opposite edges nearest first).
  static std::array<int, 3> by_coordinate(const std::array<double, 3>& b) {
    std::array<int, 3> k{{0, 1, 2}};
    std::sort(k.begin(), k.end(), [&b](int i, int j) { return b[std::size_t(i)] < b[std::size_t(j)]; });
    return k;
  }
  /// The length of the shortest target edge at target vertex tv.
  double shortest_edge(WV tv) const {
    const auto& tm = s.target.m;
    double shortest = HUGE_VAL;
    for (WH h : CGAL::halfedges_around_target(tm.halfedge(tv), tm))
      shortest = std::min(shortest, std::sqrt(CGAL::squared_distance(tm.point(tv), tm.point(tm.source(h)))));
    return shortest;
  }
  /// Counts a refused insert of target vertex tv, and where it is.
  void refuse(Overlay_result& r, WV tv) const {
    ++r.refused;
    r.refused_at.push_back(s.target.m.point(tv));
  }
  /// Whether snapping target vertex tv to a point of M_s whose image is `image` moves it on the target by at
  /// most overlay_snap_share ε or conform_snap times the shortest target edge at tv.
  bool snap_keeps_target(const Point_3& image, WV tv) const {
    return near_on_target(std::sqrt(CGAL::squared_distance(s.target.m.point(tv), image)), shortest_edge(tv));
  }
  /// Whether a snap that moves a point by `move` on the target, where the target's edges are `length` long,
  /// keeps it: within overlay_snap_share ε, or within conform_snap of that length.
  bool near_on_target(double move, double length) const {
    return move <= std::max(conform_snap * length, overlay_snap_share * s.eps);
  }

  struct Crossing {
    WV u, v;
    double t = 0;
  };
  mutable std::size_t along_crossed_ = 0; ///< Overlay_result::along_crossed
  /// Lawson's flips on M_st, after the target edges are in: an edge that lies along no target edge, whose
  /// two faces therefore lie in one target face (a plane), is flipped when the angles opposite it add up to
  /// more than a half turn there (by a relative 10^-9, so that four points on a circle, up to rounding, are
  /// left as they are) and flip_keeps_source() allows it. The flips of the insertion leave long
  /// thin faces along the target edges, whose normals rounding decides; these flips make the faces inside
  /// each target face as fat as the source and the target edges allow. At most overlay_delaunay_work flips
  /// per edge of M_s. Returns the number of flips.
  std::size_t delaunay(const std::set<std::array<WV, 2>>& fixed) {
    auto& m = s.mesh.m;
    auto angle = [&](WV apex, WV u, WV v) { return corner_angles({{s.pos[apex], s.pos[u], s.pos[v]}})[0]; };
    std::vector<WE> queue(m.edges().begin(), m.edges().end());
    std::vector<char> queued(m.number_of_edges(), 1);
    const std::size_t bound = overlay_delaunay_work * m.number_of_edges();
    std::size_t flips = 0;
    while (!queue.empty() && flips < bound) {
      const WE e = queue.back();
      queue.pop_back();
      queued[e] = 0;
      const WH h = m.halfedge(e), o = m.opposite(h);
      const WV u = m.source(h), v = m.target(h);
      if (fixed.count({{std::min(u, v), std::max(u, v)}}) || !s.flip_keeps_source(h)) continue;
      const WV x = m.target(m.next(h)), y = m.target(m.next(o));
      if (!(angle(x, u, v) + angle(y, v, u) > CGAL_PI * (1 + 1e-9))) continue;
      s.touch(u, v);
      CGAL::Euler::flip_edge(h, m);
      ++flips;
      for (WH g : {m.next(h), m.prev(h), m.next(o), m.prev(o)})
        if (!queued[m.edge(g)]) queued[m.edge(g)] = 1, queue.push_back(m.edge(g));
    }
    return flips;
  }

  /// The crossings of target edge (a, b), whose ends are vertices ra and rb of M_s, with M_s's edges but those
  /// that `skip` names: a walk over the faces that meet the edge, from those around its ends, and one ring more.
  template <class Skip>
  std::vector<Crossing> crossings(WV a, WV b, WV ra, WV rb, std::vector<char>& seen, const Skip& skip) const {
    const auto& m = s.mesh.m;
    std::vector<WF> queue, hit;
    faces_of(ra, queue);
    faces_of(rb, queue);
    seen.assign(m.number_of_faces(), 0);
    for (WF g : queue) seen[g] = 1;
    while (!queue.empty()) {
      const WF g = queue.back();
      queue.pop_back();
      if (!meets(g, a, b)) continue;
      hit.push_back(g);
      std::vector<WF> next;
      for (WV v : corners(g)) faces_of(v, next);
      for (WF k : next)
        if (!seen[k]) seen[k] = 1, queue.push_back(k);
    }
    {
      // One ring more: a face that frames place on the other side of the edge by rounding.
      std::vector<WF> ring;
      for (WF g : hit)
        for (WV v : corners(g)) faces_of(v, ring);
      hit.insert(hit.end(), ring.begin(), ring.end());
    }
    std::vector<std::array<WV, 2>> es;
    for (WF g : hit)
      for (WH h : CGAL::halfedges_around_face(m.halfedge(g), m))
        es.push_back({std::min(m.source(h), m.target(h)), std::max(m.source(h), m.target(h))});
    std::sort(es.begin(), es.end());
    es.erase(std::unique(es.begin(), es.end()), es.end());
    std::vector<Crossing> xs;
    for (const auto& e : es) {
      Crossing x;
      if (!skip(e[0], e[1]) && crossing(e[0], e[1], a, b, x)) xs.push_back(x);
    }
    return xs;
  }
  /// Whether target edge (a, b) crosses edge (u, v) of M_s at a point u + t (v - u), decided with exact
  /// predicates in the frame that holds the four. A crossing within conform_snap of u or v (see overlay_crossing()) is
  /// taken to pass through that vertex only if its image is as near the target edge on the target
  /// (passes_through()); where the map squeezes a part of the target into nearly one point of the source, a
  /// vertex that near in the parameter domain can be far from the edge on the target, and the edge is split there.
  bool crossing(WV u, WV v, WV a, WV b, Crossing& x) const {
    const std::array<const Base_location*, 4> ls{&s.param[u], &s.param[v], &s.target_param[a], &s.target_param[b]};
    std::array<Point_2, 4> p;
    int c, n;
    x.u = u, x.v = v;
    auto decide = [&](Overlay_crossing k) {
      if (k == Overlay_crossing::none) return false;
      if (k == Overlay_crossing::inside) return true;
      // Nearly along the target edge over the base mesh: along it, or through one of its ends, where an end's
      // image is near the edge on the target too. Where the map squeezes the target into a sliver of the base
      // mesh, an edge of M_s can be that near a target edge's line over the base mesh and cross it far from
      // both ends on the target: it is crossed (Overlay_result::along_crossed).
      if (k == Overlay_crossing::along) {
        if (passes_through(u, a, b) || passes_through(v, a, b)) return false;
        ++along_crossed_;
        return true;
      }
      return !passes_through(k == Overlay_crossing::at_first ? u : v, a, b);
    };
    if (B.canonical_frame(ls, c, n, p)) return decide(overlay_crossing(p[0], p[1], p[2], p[3], x.t));
    // No frame holds the two segments (each crosses a different edge of a base triangle they share): they
    // can only cross inside a base triangle of both, where each one's own frame gives the same coordinates.
    std::array<Point_2, 2> pu, pa;
    for (int T : shared_triangles<2, 2>({ls[0], ls[1]}, {ls[2], ls[3]})) {
      if (!in_triangle_frame<2>(T, {ls[0], ls[1]}, pu) || !in_triangle_frame<2>(T, {ls[2], ls[3]}, pa)) continue;
      if (!decide(overlay_crossing(pu[0], pu[1], pa[0], pa[1], x.t))) continue;
      const Point_2 X(pu[0].x() + x.t * (pu[1].x() - pu[0].x()), pu[0].y() + x.t * (pu[1].y() - pu[0].y()));
      const auto& q = B.q[std::size_t(T)];
      if (CGAL::orientation(q[0], q[1], X) != CGAL::NEGATIVE && CGAL::orientation(q[1], q[2], X) != CGAL::NEGATIVE &&
          CGAL::orientation(q[2], q[0], X) != CGAL::NEGATIVE)
        return true;
    }
    return false;
  }
  /// Whether vertex w of M_s, which a target edge (a, b) passes within conform_snap of in the parameter
  /// domain, may stand for a point of it: its image is within overlay_snap_share ε of the edge on the target, or
  /// within conform_snap of the edge's length (the test of place() for a target vertex).
  bool passes_through(WV w, WV a, WV b) const {
    const auto& tm = s.target.m;
    const Point_3 &pa = tm.point(a), &pb = tm.point(b);
    return near_on_target(std::sqrt(CGAL::squared_distance(s.pos[w], Kernel::Segment_3(pa, pb))),
                          std::sqrt(CGAL::squared_distance(pa, pb)));
  }
  /// The base triangles of the canonical frames of `l1` and of `l2` that both frames share.
  template <std::size_t N1, std::size_t N2>
  std::vector<int> shared_triangles(const std::array<const Base_location*, N1>& l1,
                                    const std::array<const Base_location*, N2>& l2) const {
    std::array<Point_2, N1> p1;
    std::array<Point_2, N2> p2;
    int c1, n1, c2, n2;
    std::vector<int> out;
    if (!B.canonical_frame(l1, c1, n1, p1) || !B.canonical_frame(l2, c2, n2, p2)) return out;
    const int a[2] = {c1, n1 >= 0 ? B.nb[c1][n1] : -1}, b[2] = {c2, n2 >= 0 ? B.nb[c2][n2] : -1};
    for (int x : a)
      if (x >= 0 && (x == b[0] || x == b[1])) out.push_back(x);
    return out;
  }
  /// The locations `ls` in base triangle T's frame, with the other triangle of their canonical frame unfolded
  /// beside it (false if T is not one of the frame's triangles).
  template <std::size_t N>
  bool in_triangle_frame(int T, const std::array<const Base_location*, N>& ls, std::array<Point_2, N>& p) const {
    int c, n;
    if (!B.canonical_frame(ls, c, n, p)) return false;
    int slot = -1;
    if (c == T) slot = n;
    else if (n >= 0 && B.nb[c][n] == T) slot = B.neighbour_index(T, c);
    else return false;
    for (std::size_t k = 0; k < N; ++k)
      if (!B.frame_point(T, slot, *ls[k], p[k])) return false;
    return true;
  }
  /// Where target vertex tv lies for face f: 0 outside it, 1 inside within conform_snap of its border (or on
  /// it), 2 inside beyond that, with its barycentrics in f's halfedge order in `b`.
  int inside(WF f, WV tv, std::array<double, 3>& b) const {
    const std::array<WV, 3> fv = corners(f);
    const std::array<const Base_location*, 4> ls{&s.param[fv[0]], &s.param[fv[1]], &s.param[fv[2]], &s.target_param[tv]};
    std::array<Point_2, 4> p;
    int c, n;
    if (!B.canonical_frame(ls, c, n, p)) return 0;
    if (CGAL::orientation(p[0], p[1], p[3]) == CGAL::NEGATIVE || CGAL::orientation(p[1], p[2], p[3]) == CGAL::NEGATIVE ||
        CGAL::orientation(p[2], p[0], p[3]) == CGAL::NEGATIVE)
      return 0;
    b = barycentric_2(p[0], p[1], p[2], p[3]);
    return std::min({b[0], b[1], b[2]}) > conform_snap ? 2 : 1;
  }
  /// Whether segment (a, z) meets the closed triangle (p, q, r) (false for a degenerate triangle or segment):
  /// no line through an edge of either separates them strictly (exact orientation predicates).
  static bool segment_meets_triangle(const Point_2& a, const Point_2& z, const Point_2& p, const Point_2& q,
                                     const Point_2& r) {
    const CGAL::Orientation o = CGAL::orientation(p, q, r);
    if (o == CGAL::COLLINEAR || a == z) return false;
    const CGAL::Orientation out = CGAL::opposite(o);
    const std::array<const Point_2*, 3> t{&p, &q, &r};
    for (int i = 0; i < 3; ++i) {
      const Point_2 &u = *t[std::size_t(i)], &v = *t[std::size_t((i + 1) % 3)];
      if (CGAL::orientation(u, v, a) == out && CGAL::orientation(u, v, z) == out) return false;
    }
    const CGAL::Orientation sp = CGAL::orientation(a, z, p), sq = CGAL::orientation(a, z, q), sr = CGAL::orientation(a, z, r);
    return !(sp != CGAL::COLLINEAR && sp == sq && sq == sr);
  }
  /// Whether face f of M_s meets target edge (a, b) over the base mesh (exact, in a frame that holds the five
  /// points; false if there is none).
  bool meets(WF f, WV a, WV b) const {
    const std::array<WV, 3> fv = corners(f);
    const std::array<const Base_location*, 5> ls{&s.param[fv[0]], &s.param[fv[1]], &s.param[fv[2]],
                                                 &s.target_param[a], &s.target_param[b]};
    std::array<Point_2, 5> p;
    int c, n;
    if (B.canonical_frame(ls, c, n, p)) return segment_meets_triangle(p[3], p[4], p[0], p[1], p[2]);
    std::array<Point_2, 3> pf;
    std::array<Point_2, 2> pe;
    for (int T : shared_triangles<3, 2>({ls[0], ls[1], ls[2]}, {ls[3], ls[4]})) {
      if (!in_triangle_frame<3>(T, {ls[0], ls[1], ls[2]}, pf) || !in_triangle_frame<2>(T, {ls[3], ls[4]}, pe)) continue;
      if (segment_meets_triangle(pe[0], pe[1], pf[0], pf[1], pf[2])) return true;
    }
    return false;
  }
  /// The barycentrics of target vertex tv in face f's frame (false if no frame holds the four).
  bool barycentrics(WF f, WV tv, std::array<double, 3>& b) const {
    const std::array<WV, 3> fv = corners(f);
    const std::array<const Base_location*, 4> ls{&s.param[fv[0]], &s.param[fv[1]], &s.param[fv[2]], &s.target_param[tv]};
    std::array<Point_2, 4> p;
    int c, n;
    if (!B.canonical_frame(ls, c, n, p)) return false;
    b = barycentric_2(p[0], p[1], p[2], p[3]);
    return true;
  }
  /// Appends the faces around vertex v of M_s to `out`.
  void faces_of(WV v, std::vector<WF>& out) const {
    const auto& m = s.mesh.m;
    for (WF g : CGAL::faces_around_target(m.halfedge(v), m))
      if (g != WF()) out.push_back(g);
  }
  std::array<WV, 3> corners(WF f) const {
    const auto& m = s.mesh.m;
    const WH h = m.halfedge(f);
    return {m.source(h), m.target(h), m.target(m.next(h))};
  }

  Remesh_state& s;
  const Base_mesh& B;
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_OVERLAY_H

// SPDX-License-Identifier: GPL-3.0-or-later
// Decimation of the map's overlay (an addition to the paper). The overlay (overlay.h) is a compatible remesh
// whose target-shaped mesh lies exactly on the target: every face inside one target face. It has many more
// vertices than a remesh needs. The decimation removes the vertices the overlay added, one edge collapse at a
// time, and keeps a collapse only if the result still passes the verifier's checks (remeshing_verification.h),
// judged on the faces it changes:
//  - the source-shaped mesh stays an exact copy of the source: every new face lies in one input source face
//    and keeps its orientation there (exact test on barycentric coordinates), so the faces of the star tile
//    the same part of the source surface;
//  - the parameterization stays one-to-one: every new face is positively oriented over the base mesh (exact);
//  - the target-shaped mesh stays within `decimation_margin` ε of the target both ways: sample points of each
//    new face against the target (AABB tree), and every target vertex the decimation has removed so far (a
//    witness, kept by the face nearest it) against the new faces;
//  - no new face deviates by more than the normal deviation (`normal_deviation`, 30° by default) from the
//    target's normal at the point of the target nearest its centroid (where the verifier measures it, so no
//    face is flipped), nor by more than `decimation_sample_deviation` times that (at most 90°) at the points
//    nearest its other samples;
//  - no more creases (edges whose faces' normals are more than crease_degrees apart) than the star had;
//  - no new face intersects another face of the target-shaped mesh (exact predicates; faces that share a
//    vertex or an edge intersect only beyond it), except near the target's own folds, as the verifier counts.
// Shortest edges first (on the target-shaped mesh): the overlay's slivers go first.
#ifndef CROSSPARAM_INTERNAL_REMESHING_OVERLAY_DECIMATION_H
#define CROSSPARAM_INTERNAL_REMESHING_OVERLAY_DECIMATION_H

#include <crossparam/internal/remeshing/remesh_state.h>
#include <crossparam/internal/remeshing/target_untangling.h>
#include <crossparam/remeshing_verification.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/intersections.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <queue>
#include <unordered_map>
#include <utility>
#include <vector>

namespace crossparam {
namespace internal {

/// Fraction of the tolerance ε that the decimation allows between the target-shaped mesh and the target,
/// both ways. Its checks sample the new faces at ten points and the target at the removed vertices, so the
/// true distance can exceed what they see by a little; the remaining fifth of ε covers that, and the verifier
/// measures the true distance.
constexpr double decimation_margin = 0.8;

/// Side, as a fraction of ε, of the cubic cells in which the removed target vertices one face holds are one
/// witness: the one kept is within the margin of the mesh, so the others are within the margin plus the
/// cell's diagonal (0.8 + 0.09 ε), and a face holds at most one witness per cell however fine the target.
/// The target between its vertices is flat; the crossings the overlay added on its edges are not witnesses.
constexpr double decimation_witness_spacing = 0.05;

/// Smallest ratio of a new face's area to the square of its longest edge on the target-shaped mesh (an
/// equilateral triangle has 0.43). Below it a face is a needle whose computed normal is rounding: its flip
/// test and its intersections would be decided by noise.
constexpr double decimation_min_shape = 1e-6;

/// Largest valence a collapse may give the vertex it keeps. The overlay has fans (a vertex of the source
/// facing an edge that many target edges cross); collapsing onto a fan's apex only makes longer, thinner faces,
/// and every new face there must be tested against all the apex's faces. The fans thin out as the crossings
/// along the opposite edge collapse onto each other; 16 is over twice a regular vertex's 6.
constexpr std::size_t decimation_max_valence = 16;

/// The decimation's work bound: grid entries scanned plus face pairs tested for intersection (most of its
/// time). Stopping early is safe, every collapse kept passed the checks: the result only keeps more
/// vertices. horse0_horse7's decimation, the largest on the bench that the automatic construction makes,
/// needs 2.4·10⁸ (40 s); lion_cat's overlay, asked for, several times the bound.
constexpr std::size_t decimation_work = 1000000000;

/// Factor of the normal deviation allowed at a new face's samples other than its centroid. The target's normal
/// varies between its faces, more on a fine or noisy target: asking the centroid's bound everywhere keeps
/// about twice the vertices on the bench (shrec_383_385: +108 % against +36 %) for faces that the verifier
/// already finds within the bound; the samples still stop a face from bending across a ridge of the target.
constexpr double decimation_sample_deviation = 2;

/// What the decimation did.
struct Decimation_result {
  std::size_t collapses = 0;      ///< vertices removed
  std::size_t tried = 0;          ///< collapses tested
  std::size_t refused_valence = 0; ///< the vertex kept would get more than decimation_max_valence neighbours
  std::size_t refused_link = 0;   ///< not a manifold collapse (the link condition)
  std::size_t refused_source = 0; ///< the source's surface or the parameterization would change
  std::size_t refused_needle = 0;   ///< a new face would be a needle (decimation_min_shape)
  std::size_t refused_distance = 0; ///< a new face would leave the target by more than the margin
  std::size_t refused_normal = 0;   ///< a new face would deviate from the target's normal by more than allowed
  std::size_t refused_crease = 0;   ///< the collapse would add an edge whose faces fold back (crease_degrees)
  std::size_t refused_witness = 0;      ///< a removed target vertex would be too far from the new faces
  std::size_t refused_intersection = 0; ///< a new face would intersect the target-shaped mesh
  std::size_t face_pairs = 0;           ///< pairs of a new face and a face near it tested for intersection
  std::size_t grid_entries = 0;         ///< grid entries those were found among
  bool work_bound_reached = false;      ///< whether it stopped at decimation_work
};

/// Removes vertices of `s` whose index is at least `first_removable` (and that are not features) by edge
/// collapses that keep the checks above; `max_deviation` is the normal deviation in degrees.
class Overlay_decimator {
public:
  using Target_tree = Target_untangler::Target_tree;

  /// `witness` flags the vertices whose removal leaves a witness (the target's vertices in the overlay).
  Overlay_decimator(Remesh_state& state, double max_deviation, std::size_t first_removable, std::vector<char> witness)
      : s(state), m(state.mesh.m), first_(first_removable), witness_(std::move(witness)),
        tree(CGAL::faces(state.target.m).first, CGAL::faces(state.target.m).second, state.target.m) {
    tree.accelerate_distance_queries();
    cos_dev_ = std::cos(std::min(max_deviation, 89.9) * CGAL_PI / 180);
    cos_crease_ = std::cos(crease_degrees * CGAL_PI / 180);
    cos_sample_ = std::cos(std::min(decimation_sample_deviation * max_deviation, 90.0) * CGAL_PI / 180);
    limit2_ = decimation_margin * s.eps * decimation_margin * s.eps;
    std::vector<std::pair<WF, WF>> pairs;
    CGAL::Polygon_mesh_processing::self_intersections(faces(s.target.m), s.target.m, std::back_inserter(pairs));
    target_folds_ = fold_face_boxes(s.target.m, pairs);
  }

  /// Runs the decimation to the end (no collapse left that passes) or until the time budget runs out.
  Decimation_result run() {
    Decimation_result r;
    witnesses_.assign(m.number_of_faces(), {});
    box_.assign(m.number_of_faces(), CGAL::Bbox_3());
    version_.assign(m.number_of_faces(), 0);
    degenerate_.assign(m.number_of_faces(), 0);
    stamp_.assign(m.number_of_faces(), 0);
    std::size_t live = m.number_of_vertices(), live_at_build = live;
    build_grid();
    using Item = std::pair<double, std::uint32_t>; // shortest edge on the target-shaped mesh, vertex
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    std::vector<double> key(m.number_of_vertices(), 0);
    auto push = [&](WV v) {
      if (!removable(v)) return;
      key[v] = shortest_edge(v);
      queue.push({key[v], std::uint32_t(v)});
    };
    for (WV v : m.vertices()) push(v);
    std::size_t since_check = 0;
    while (!queue.empty()) {
      const auto [k, vi] = queue.top();
      queue.pop();
      const WV u(vi);
      if (m.is_removed(u) || k != key[u]) continue;
      if (++since_check == 4096) {
        since_check = 0;
        if (r.grid_entries + r.face_pairs > decimation_work) {
          r.work_bound_reached = true;
          break;
        }
        if (s.budget.stop("the remeshing's overlay decimation", [&] { return std::to_string(r.collapses) + " vertices removed"; }))
          break;
      }
      // The neighbours of u, nearest on the target-shaped mesh first.
      std::vector<std::pair<double, WH>> outs;
      for (WH h : CGAL::halfedges_around_source(u, m)) outs.push_back({CGAL::squared_distance(s.pos[u], s.pos[m.target(h)]), h});
      std::sort(outs.begin(), outs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      for (const auto& o : outs) {
        ++r.tried;
        Plan plan;
        if (!test(o.second, plan, r)) continue;
        const WV w = m.target(o.second);
        apply(o.second, plan);
        ++r.collapses;
        if (--live <= live_at_build / 2) build_grid(), live_at_build = live, r.grid_entries += entries_;
        key[u] = -1;
        push(w);
        for (WV x : CGAL::vertices_around_target(m.halfedge(w), m)) push(x);
        break;
      }
    }
    return r;
  }

private:
  /// The faces a collapse makes: corners (u replaced by w), the input source face holding each.
  struct Plan {
    std::vector<std::array<WV, 3>> faces;
    std::vector<int> orig;
    std::vector<Point_3> witnesses; // the removed target vertices the star held, and u if it is one
    std::vector<int> owner;         // per witness: its new face
  };

  bool removable(WV v) const {
    return std::size_t(v) >= first_ && s.mesh.vfeature[v] == no_feature;
  }
  double shortest_edge(WV v) const {
    double best = HUGE_VAL;
    for (WV x : CGAL::vertices_around_target(m.halfedge(v), m)) best = std::min(best, CGAL::squared_distance(s.pos[v], s.pos[x]));
    return best;
  }
  std::array<WV, 3> corners(WF f) const {
    const WH h = m.halfedge(f);
    return {m.source(h), m.target(h), m.target(m.next(h))};
  }

  /// Whether collapsing halfedge h (u = source, removed, onto w = target) passes every check; fills `plan`.
  bool test(WH h, Plan& plan, Decimation_result& r) {
    const WV u = m.source(h), w = m.target(h);
    if (m.degree(u) + m.degree(w) - 4 > decimation_max_valence) return ++r.refused_valence, false;
    if (!CGAL::Euler::does_satisfy_link_condition(m.edge(h), m)) return ++r.refused_link, false;
    // The star of u: its faces, those with w go away, the others get w for u.
    std::vector<WF> star;
    for (WF f : CGAL::faces_around_target(m.halfedge(u), m)) star.push_back(f);
    // First what is cheap: w must lie on every input face that u's faces lie in (u on an input edge can only
    // move along it), and no new face may be a needle.
    std::array<double, 3> b;
    for (WF f : star)
      if (!s.mesh.rep_in(w, s.mesh.forig[f], b)) return ++r.refused_source, false;
    for (WF f : star) {
      std::array<WV, 3> c = corners(f);
      if (c[0] == w || c[1] == w || c[2] == w) continue;
      for (WV& x : c)
        if (x == u) x = w;
      if (needle(c)) return ++r.refused_needle, false;
      plan.faces.push_back(c);
    }
    // The source: each new face in an input face that held a face of the star, oriented as there.
    for (const auto& c : plan.faces) {
      int found = -1;
      for (WF f : star) {
        const int o = s.mesh.forig[f];
        if (in_input_face(c, o, f)) {
          found = o;
          break;
        }
      }
      if (found < 0) return ++r.refused_source, false;
      plan.orig.push_back(found);
    }
    // The parameterization: positive over the base mesh.
    const Base_mesh& B = *s.param.base;
    for (const auto& c : plan.faces)
      if (B.triangle_orientation(s.param[c[0]], s.param[c[1]], s.param[c[2]]) != CGAL::POSITIVE) return ++r.refused_source, false;
    // The target: shape, distance and normal at the samples.
    for (const bool centroid_only : {true, false}) // every face's centroid first: the cheapest refusals
      for (const auto& c : plan.faces)
        switch (follows_target(c, centroid_only)) {
        case Follow::far: return ++r.refused_distance, false;
        case Follow::steep: return ++r.refused_normal, false;
        case Follow::yes: break;
        }
    // Creases: no more edges whose faces fold back onto each other than the star had.
    if (creases_after(plan, u) > creases_before(star)) return ++r.refused_crease, false;
    // The witnesses: the removed target vertices the star held, and u if it is one, each within the limit of a
    // new face.
    std::vector<Kernel::Triangle_3> tris;
    for (const auto& c : plan.faces) tris.emplace_back(s.pos[c[0]], s.pos[c[1]], s.pos[c[2]]);
    if (std::size_t(u) < witness_.size() && witness_[u]) plan.witnesses.push_back(s.pos[u]);
    for (WF f : star) plan.witnesses.insert(plan.witnesses.end(), witnesses_[f].begin(), witnesses_[f].end());
    std::vector<CGAL::Bbox_3> grown;
    const double lim = std::sqrt(limit2_);
    for (const auto& t : tris) {
      const CGAL::Bbox_3 b = t.bbox();
      grown.emplace_back(b.xmin() - lim, b.ymin() - lim, b.zmin() - lim, b.xmax() + lim, b.ymax() + lim, b.zmax() + lim);
    }
    for (const Point_3& p : plan.witnesses) {
      int best = -1;
      double bd = limit2_;
      for (std::size_t i = 0; i < tris.size(); ++i) {
        if (!CGAL::do_overlap(grown[i], p.bbox())) continue;
        const double d = CGAL::squared_distance(p, tris[i]);
        if (d <= bd) bd = d, best = int(i);
      }
      if (best < 0) return ++r.refused_witness, false;
      plan.owner.push_back(best);
    }
    // Intersections: the new faces with each other and with the faces near them.
    for (std::size_t i = 0; i < plan.faces.size(); ++i)
      for (std::size_t j = i + 1; j < plan.faces.size(); ++j)
        if (intersect(plan.faces[i], plan.faces[j])) return ++r.refused_intersection, false;
    for (const auto& c : plan.faces) {
      // Each face near c once (a face is in several cells), the star's not at all: they are replaced.
      ++current_;
      for (WF f : star) stamp_[f] = current_;
      CGAL::Bbox_3 box = s.pos[c[0]].bbox() + s.pos[c[1]].bbox() + s.pos[c[2]].bbox();
      bool hit = false;
      for_cells(box, [&](std::uint64_t key) {
        auto it = grid_.find(key);
        if (hit || it == grid_.end()) return;
        r.grid_entries += it->second.size();
        for (const auto& [gi, version] : it->second) {
          const WF g(gi);
          if (version != version_[g] || stamp_[g] == current_ || m.is_removed(g)) continue;
          stamp_[g] = current_;
          if (!CGAL::do_overlap(box, box_[g])) continue;
          ++r.face_pairs;
          if (intersect(c, corners(g), degenerate_[g]) && !near_target_fold(box + box_[g])) {
            hit = true;
            return;
          }
        }
      });
      if (hit) return ++r.refused_intersection, false;
    }
    return true;
  }

  /// Whether triangles (a, b, c) and (b, a, d) of the target-shaped mesh meet at a crease (their normals more
  /// than crease_degrees apart, as the verifier counts them).
  bool crease(WV a, WV b, WV c, WV d) const {
    const Kernel::Vector_3 n1 = triangle_normal(s.pos[a], s.pos[b], s.pos[c]), n2 = triangle_normal(s.pos[b], s.pos[a], s.pos[d]);
    const double l1 = std::sqrt(n1.squared_length()), l2 = std::sqrt(n2.squared_length());
    return l1 > 0 && l2 > 0 && n1 * n2 < cos_crease_ * l1 * l2;
  }
  /// The third corner of the face of halfedge (a, b) of the mesh (none if there is no such halfedge).
  WV third(WV a, WV b) const {
    const WH h = m.halfedge(a, b);
    return h == WH() || m.is_border(h) ? WV() : m.target(m.next(h));
  }
  /// Creased edges of the faces of u's star now, each once.
  std::size_t creases_before(const std::vector<WF>& star) const {
    std::size_t n = 0;
    for (WF f : star)
      for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        const WV a = m.source(h), b = m.target(h);
        const WF g = m.face(m.opposite(h));
        const bool both_in = std::find(star.begin(), star.end(), g) != star.end();
        if (both_in && a > b) continue; // an edge inside the star: once
        const WV d = third(b, a);
        if (d != WV()) n += crease(a, b, m.target(m.next(h)), d);
      }
    return n;
  }
  /// Creased edges of the planned faces, each once, against each other and against the faces around them.
  std::size_t creases_after(const Plan& plan, WV u) const {
    std::size_t n = 0;
    for (const auto& c : plan.faces)
      for (int i = 0; i < 3; ++i) {
        const WV a = c[i], b = c[(i + 1) % 3], x = c[(i + 2) % 3];
        WV d = WV();
        for (const auto& e : plan.faces)
          for (int j = 0; j < 3; ++j)
            if (e[j] == b && e[(j + 1) % 3] == a) d = e[(j + 2) % 3];
        if (d != WV()) {
          if (a > b) continue; // between two planned faces: once
        } else {
          d = third(b, a);
          if (d == WV() || d == u) continue; // not expected: each edge of a planned face has a planned or an outside face
        }
        n += crease(a, b, x, d);
      }
    return n;
  }

  /// Whether corners c lie in input face o (exact) and keep the orientation that face f of the star has there.
  bool in_input_face(const std::array<WV, 3>& c, int o, WF f) const {
    std::array<Kernel::Point_2, 3> q, qf;
    const std::array<WV, 3> cf = corners(f);
    for (int i = 0; i < 3; ++i) {
      std::array<double, 3> b;
      if (!s.mesh.rep_in(c[i], o, b)) return false;
      q[i] = Kernel::Point_2(b[1], b[2]);
      if (!s.mesh.rep_in(cf[i], o, b)) return false;
      qf[i] = Kernel::Point_2(b[1], b[2]);
    }
    const CGAL::Orientation want = CGAL::orientation(qf[0], qf[1], qf[2]);
    return want != CGAL::COLLINEAR && CGAL::orientation(q[0], q[1], q[2]) == want;
  }

  /// Whether the triangle of the target-shaped mesh with corners `corner` (not a needle: test() checked)
  /// follows the target: at its centroid (`centroid_only`) or at its nine other samples (the edge midpoints and the points at
  /// the thirds of the edges) within the limit of the target, its normal within the normal deviation of the
  /// target's at the nearest point (at the centroid) or within decimation_sample_deviation times that.
  enum class Follow { yes, far, steep };
  /// Whether the triangle with corners c on the target-shaped mesh is a needle (decimation_min_shape).
  bool needle(const std::array<WV, 3>& c) const {
    const Point_3 &a = s.pos[c[0]], &b = s.pos[c[1]], &d = s.pos[c[2]];
    const double len2 = std::max({CGAL::squared_distance(a, b), CGAL::squared_distance(b, d), CGAL::squared_distance(d, a)});
    const double n2 = triangle_normal(a, b, d).squared_length();
    return !(n2 > 0) || !(std::sqrt(n2) > 2 * decimation_min_shape * len2); // |n| = 2 area
  }
  Follow follows_target(const std::array<WV, 3>& corner, bool centroid_only) const {
    const Point_3 &a = s.pos[corner[0]], &b = s.pos[corner[1]], &c = s.pos[corner[2]];
    const Kernel::Vector_3 n = triangle_normal(a, b, c);
    const double ln = std::sqrt(n.squared_length());
    // Each query starts from the last one's answer (the first from the first corner's own place on the
    // target): the samples are close together, so the search ends sooner; the answer is the nearest point.
    std::pair<Point_3, WF> near{a, s.img[corner[0]].face};
    auto check = [&](const Point_3& p, double cos_bound) {
      near = tree.closest_point_and_primitive(p, near);
      if (CGAL::squared_distance(p, near.first) > limit2_) return Follow::far;
      const Kernel::Vector_3 nt = s.target_normal(near.second);
      const double lt = std::sqrt(nt.squared_length());
      return lt > 0 && (n * nt) >= cos_bound * ln * lt ? Follow::yes : Follow::steep;
    };
    if (centroid_only) return check(CGAL::centroid(a, b, c), cos_dev_);
    auto at = [](const Point_3& p, const Point_3& q, double t) { return p + t * (q - p); };
    for (const Point_3& p : {CGAL::midpoint(a, b), CGAL::midpoint(b, c), CGAL::midpoint(c, a), at(a, b, 1.0 / 3),
                             at(a, b, 2.0 / 3), at(b, c, 1.0 / 3), at(b, c, 2.0 / 3), at(c, a, 1.0 / 3), at(c, a, 2.0 / 3)})
      if (const Follow f = check(p, cos_sample_); f != Follow::yes) return f;
    return Follow::yes;
  }

  /// Whether triangles with corners c and d of the target-shaped mesh intersect beyond the corners they share
  /// (exact predicates): none shared, any common point; one, the opposite edge of either meets the other; two,
  /// the other corners on one side of the shared edge in a common plane.
  bool intersect(const std::array<WV, 3>& c, const std::array<WV, 3>& d, bool d_degenerate = false) const {
    int shared = 0, ci = -1, di = -1;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (c[i] == d[j]) ++shared, ci = i, di = j;
    const auto P = [&](WV v) -> const Point_3& { return s.pos[v]; };
    if (d_degenerate) return false; // the verifier counts a degenerate face; new faces are not (no needles)
    // First in floating point: the corners of one face that it does not share, all strictly on one side of the
    // other's plane by far more than rounding, cannot meet the other face (but at a shared corner). Only the
    // faces this does not settle (near each other's planes) go to the exact predicates.
    if (shared < 3 && (one_side(c, d) || one_side(d, c))) return false;
    const Kernel::Triangle_3 tc(P(c[0]), P(c[1]), P(c[2])), td(P(d[0]), P(d[1]), P(d[2]));
    if (shared == 0) return CGAL::do_intersect(tc, td);
    if (shared == 1) {
      const Kernel::Segment_3 oc(P(c[(ci + 1) % 3]), P(c[(ci + 2) % 3])), od(P(d[(di + 1) % 3]), P(d[(di + 2) % 3]));
      return CGAL::do_intersect(oc, td) || CGAL::do_intersect(od, tc);
    }
    if (shared == 2) {
      int oc = -1, od = -1; // the corners not shared
      for (int i = 0; i < 3; ++i) {
        if (c[i] != d[0] && c[i] != d[1] && c[i] != d[2]) oc = i;
        if (d[i] != c[0] && d[i] != c[1] && d[i] != c[2]) od = i;
      }
      const Point_3 &p = P(c[(oc + 1) % 3]), &q = P(c[(oc + 2) % 3]), &r = P(c[oc]), &t = P(d[od]);
      return CGAL::coplanar(p, q, r, t) && CGAL::coplanar_orientation(p, q, r, t) == CGAL::POSITIVE;
    }
    return true; // the same face twice
  }

  /// Whether the corners of face e that face f does not share are all strictly on one side of f's plane, by
  /// more than 10⁻⁹ of the product of the lengths involved (rounding of the computation is about 10⁻¹⁵ of
  /// it, so the answer is certain); false when unsure or when e shares every corner.
  bool one_side(const std::array<WV, 3>& f, const std::array<WV, 3>& e) const {
    const Point_3 &a = s.pos[f[0]], &b = s.pos[f[1]], &c = s.pos[f[2]];
    const Kernel::Vector_3 n = CGAL::cross_product(b - a, c - a);
    const double ln = std::sqrt(n.squared_length());
    const double span = std::sqrt(CGAL::squared_distance(a, b)) + std::sqrt(CGAL::squared_distance(a, c));
    int side = 0;
    for (WV v : e) {
      if (v == f[0] || v == f[1] || v == f[2]) continue;
      const Kernel::Vector_3 x = s.pos[v] - a;
      const double dist = n * x, bound = 1e-9 * ln * (span + std::sqrt(x.squared_length()));
      const int sv = dist > bound ? 1 : dist < -bound ? -1 : 0;
      if (sv == 0 || (side != 0 && sv != side)) return false;
      side = sv;
    }
    return side != 0;
  }

  bool near_target_fold(const CGAL::Bbox_3& b) const { return meets_grown(b, s.eps, target_folds_); }

  /// Collapses h as planned: u's two faces with w go, its other faces get w; forig and the witnesses follow.
  void apply(WH h, const Plan& plan) {
    const WV u = m.source(h), w = m.target(h);
    std::vector<WF> star;
    for (WF f : CGAL::faces_around_target(m.halfedge(u), m)) star.push_back(f);
    std::vector<std::array<std::size_t, 3>> keys;
    for (const auto& c : plan.faces) keys.push_back(sorted(c));
    for (WF f : star) witnesses_[f].clear();
    const WH pt = m.opposite(m.prev(h)), qb = m.opposite(m.prev(m.opposite(h)));
    CGAL::Euler::join_face(pt, m);
    CGAL::Euler::join_face(qb, m);
    CGAL::Euler::join_vertex(h, m);
    for (WF f : CGAL::faces_around_target(m.halfedge(w), m)) {
      const auto k = sorted(corners(f));
      const auto it = std::find(keys.begin(), keys.end(), k);
      if (it == keys.end()) continue;
      const std::size_t i = std::size_t(it - keys.begin());
      s.mesh.forig[f] = plan.orig[i];
      // One witness per cell of decimation_witness_spacing ε.
      std::vector<std::pair<std::uint64_t, std::size_t>> cells;
      const double q = decimation_witness_spacing * s.eps;
      auto key = [q](const Point_3& p) {
        auto k = [q](double x) { return std::uint64_t(std::int64_t(std::floor(x / q)) + (std::int64_t(1) << 20)); };
        return (k(p.x()) << 42) ^ (k(p.y()) << 21) ^ k(p.z());
      };
      for (std::size_t j = 0; j < plan.witnesses.size(); ++j)
        if (plan.owner[j] == int(i)) cells.push_back({key(plan.witnesses[j]), j});
      std::sort(cells.begin(), cells.end());
      for (std::size_t j = 0; j < cells.size(); ++j)
        if (j == 0 || cells[j].first != cells[j - 1].first) witnesses_[f].push_back(plan.witnesses[cells[j].second]);
      grid_insert(f);
    }
  }
  static std::array<std::size_t, 3> sorted(const std::array<WV, 3>& c) {
    std::array<std::size_t, 3> k{std::size_t(c[0]), std::size_t(c[1]), std::size_t(c[2])};
    std::sort(k.begin(), k.end());
    return k;
  }

  // A uniform grid over the target-shaped mesh's faces, for the intersection tests. A face is entered, with its
  // version, in the cells its box meets each time a collapse changes it; entries of an older version are
  // skipped. The cells are twice the median face's extent, and the grid is built again (without the stale
  // entries, with larger cells) each time the decimation has halved the vertices: a face then meets a few
  // cells, and a cell holds a few faces, from the overlay's small faces to the decimated mesh's large ones.
  template <class F>
  void for_cells(const CGAL::Bbox_3& b, F&& f) const {
    auto idx = [this](double x) { return std::int64_t(std::floor(x / cell_)); };
    for (std::int64_t i = idx(b.xmin()); i <= idx(b.xmax()); ++i)
      for (std::int64_t j = idx(b.ymin()); j <= idx(b.ymax()); ++j)
        for (std::int64_t k = idx(b.zmin()); k <= idx(b.zmax()); ++k)
          f((std::uint64_t(i + (1 << 20)) << 42) | (std::uint64_t(j + (1 << 20)) << 21) | std::uint64_t(k + (1 << 20)));
  }
  void grid_insert(WF f) {
    const std::array<WV, 3> c = corners(f);
    box_[f] = s.pos[c[0]].bbox() + s.pos[c[1]].bbox() + s.pos[c[2]].bbox();
    degenerate_[f] = CGAL::collinear(s.pos[c[0]], s.pos[c[1]], s.pos[c[2]]);
    const std::uint32_t version = ++version_[f];
    for_cells(box_[f], [&](std::uint64_t key) { grid_[key].push_back({std::uint32_t(f), version}), ++entries_; });
  }
  void build_grid() {
    grid_.clear();
    std::vector<double> extent;
    for (WF f : m.faces()) {
      const std::array<WV, 3> c = corners(f);
      const CGAL::Bbox_3 b = s.pos[c[0]].bbox() + s.pos[c[1]].bbox() + s.pos[c[2]].bbox();
      extent.push_back(std::max({b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()}));
    }
    // Twice the median extent (the mean would follow the few large faces where the overlay has many small ones
    // and fill each cell with the small ones); not below 1e-5 of the unit diagonal: cell indices stay within
    // the keys' 21 bits.
    double median = 1;
    if (!extent.empty()) {
      std::nth_element(extent.begin(), extent.begin() + std::ptrdiff_t(extent.size() / 2), extent.end());
      median = extent[extent.size() / 2];
    }
    cell_ = std::max(2 * median, 1e-5);
    entries_ = 0;
    for (WF f : m.faces()) grid_insert(f);
  }

  Remesh_state& s;
  Work_mesh& m;
  std::size_t first_;
  std::vector<char> witness_;
  Target_tree tree;
  double cos_dev_ = 0, cos_sample_ = 0, cos_crease_ = -1, limit2_ = 0, cell_ = 1;
  std::vector<CGAL::Bbox_3> target_folds_;
  std::vector<std::vector<Point_3>> witnesses_;
  std::unordered_map<std::uint64_t, std::vector<std::pair<std::uint32_t, std::uint32_t>>> grid_; // face, version
  std::vector<CGAL::Bbox_3> box_;       ///< per face: its box as last entered
  std::vector<std::uint32_t> version_;  ///< per face: how often it was entered
  std::vector<char> degenerate_;        ///< per face: its corners collinear (exact), as last entered
  std::vector<std::uint64_t> stamp_;
  std::size_t entries_ = 0; ///< grid entries since the last build
  std::uint64_t current_ = 0;
};

/// Removes the elements that collapses left in `s.mesh` and renumbers the per-vertex records to match (the
/// vertices that stay keep their order; none below `s.mesh.n_original_vertices` is ever removed, so the input
/// vertices keep their indices). The layout's paths, split records and descriptors no longer apply and are cleared; what
/// measure() cached is dropped.
inline void compact(Remesh_state& s) {
  auto& L = s.mesh;
  auto& m = L.m;
  auto [old, added] = m.add_property_map<WV, std::uint32_t>("v:cp_old_index", 0);
  (void)added;
  for (WV v : m.vertices()) old[v] = std::uint32_t(v);
  m.collect_garbage();
  L.bind_property_maps();
  auto index = m.property_map<WV, std::uint32_t>("v:cp_old_index").first;
  const std::size_t n = m.number_of_vertices();
  std::vector<Base_location> loc(n);
  std::vector<Work_location> img(n);
  std::vector<Point_3> pos(n);
  std::vector<std::pair<int, std::array<double, 3>>> vrep(n);
  for (WV v : m.vertices()) {
    const std::size_t o = index[v];
    loc[v] = s.param.loc[o], img[v] = s.img[o], pos[v] = s.pos[o], vrep[v] = L.vrep[o];
  }
  m.remove_property_map(index);
  s.param.loc = std::move(loc), s.img = std::move(img), s.pos = std::move(pos), L.vrep = std::move(vrep);
  L.desc.clear();
  L.paths.clear();
  L.splits.clear();
  s.cache = Measure_cache();
  s.dirty.clear();
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_OVERLAY_DECIMATION_H

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
//  - the target-shaped mesh stays within `decimation_margin` ε of the target both ways, certified: every point
//    of a new face (the distance at its corners and at midpoints of a subdivision, plus the distance the
//    subdivision's pieces allow), and every point of the target that the new face stands for (the map is
//    linear on each face of the overlay, so the farthest such point is a corner of a new face clipped to an
//    overlay face);
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

#include <crossparam/internal/remeshing/distance_certificate.h>
#include <crossparam/internal/remeshing/remesh_state.h>
#include <crossparam/internal/remeshing/triangle_intersection.h>
#include <crossparam/remeshing_verification.h>

#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/intersections.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <queue>
#include <utility>
#include <vector>

namespace crossparam {
namespace internal {

/// Fraction of the tolerance ε within which the decimation keeps the target-shaped mesh from the target,
/// both ways, certified for every point, not only at samples (certified_within(), Overlay_decimator::covers()).
/// The verifier measures the Hausdorff distance to 1 % of ε, the strict repair that follows may move a vertex,
/// and positions are rounded: the remaining tenth of ε is for those.
constexpr double decimation_margin = 0.9;

/// Distance, as a fraction of ε, within which a corner of the target-shaped mesh counts as lying in a target
/// face for the intersection tests' shortcut (Overlay_decimator::home()): the overlay's vertices on target edges
/// are computed in one of the faces there, and lie on the others within rounding: 10⁻¹⁶ of the mesh's size,
/// against 10⁻¹² of it at ε = 0.1 %.
constexpr double decimation_home_snap = 1e-9;

/// Barycentric coordinate, in its own target face, below which Overlay_decimator::home() also tries the faces
/// around a face's first corner. Only which faces are tried depends on it (the distance test decides): the
/// overlay's corners on target edges have a coordinate of zero up to rounding, about 10⁻¹⁶; 10⁻³ is far above
/// that and still spares the search for corners well inside their face.
constexpr double home_border = 1e-3;

/// Passes of the needle removal (Overlay_decimator::remove_needles()) at most; each pass tries every needle
/// once and the passes end when one removes nothing (on eiffel_g4 at 1 % the second does).
constexpr unsigned needle_removal_passes = 16;

/// Largest valence a collapse may give the vertex it keeps. The overlay has fans (a vertex of the source
/// facing an edge that many target edges cross); collapsing onto a fan's apex only makes longer, thinner faces,
/// and every new face there must be tested against all the apex's faces. The fans thin out as the crossings
/// along the opposite edge collapse onto each other; 16 is over twice a regular vertex's 6.
constexpr std::size_t decimation_max_valence = 16;

/// The decimation's work bound: face pairs tested for intersection plus collapses tested (the two loops its
/// time goes to). Stopping early is safe, every collapse kept passed the checks: the result only keeps more
/// vertices. It is there so that no input can make the decimation run for hours; the bench's decimations
/// stay well below it (report.json's `overlay.work_bound_reached` says when one does not).
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
  std::size_t refused_coverage = 0;     ///< a point of the target would be too far from the new faces
  std::size_t refused_intersection = 0; ///< a new face would intersect the target-shaped mesh
  std::size_t face_pairs = 0;           ///< pairs of a new face and a face whose box meets it, tested for intersection
  std::size_t needles_found = 0;        ///< needles (decimation_min_shape, decimation_min_height) when the needle removal began
  std::size_t needle_collapses = 0;     ///< collapses of the needle removal (counted in `collapses` too)
  std::size_t needles_left = 0;         ///< needles when it ended
  bool work_bound_reached = false;      ///< whether it stopped at decimation_work
};

/// Removes vertices of `s` whose index is at least `first_removable` (and that are not features) by edge
/// collapses that keep the checks above; `max_deviation` is the normal deviation in degrees.
class Overlay_decimator {
public:
  /// `state` holds the overlay (overlay.h): each face of its mesh inside one target face.
  Overlay_decimator(Remesh_state& state, double max_deviation, std::size_t first_removable)
      : s(state), m(state.mesh.m), first_(first_removable),
        tree(CGAL::faces(state.target.m).first, CGAL::faces(state.target.m).second, state.target.m) {
    tree.accelerate_distance_queries();
    cos_dev_ = std::cos(std::min(max_deviation, 89.9) * CGAL_PI / 180);
    cos_crease_ = std::cos(crease_degrees * CGAL_PI / 180);
    cos_sample_ = std::cos(std::min(decimation_sample_deviation * max_deviation, 90.0) * CGAL_PI / 180);
    certified_ = decimation_margin * s.eps;
    limit2_ = certified_ * certified_;
    std::vector<std::pair<WF, WF>> pairs;
    CGAL::Polygon_mesh_processing::self_intersections(faces(s.target.m), s.target.m, std::back_inserter(pairs));
    target_folds_ = fold_face_boxes(s.target.m, pairs);
    record_overlay();
    for (WF t : s.target.m.faces()) {
      const WH th = s.target.m.halfedge(t);
      target_corners_.push_back({s.target.m.source(th), s.target.m.target(th), s.target.m.target(s.target.m.next(th))});
    }
  }

  /// Runs the decimation to the end (no collapse left that passes) or until the time budget runs out.
  Decimation_result run() {
    Decimation_result r;
    box_.assign(m.number_of_faces(), CGAL::Bbox_3());
    degenerate_.assign(m.number_of_faces(), 0);
    home_.assign(m.number_of_faces(), WF());
    stamp_.assign(m.number_of_faces(), 0);
    build_index();
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
        if (r.tried + r.face_pairs > decimation_work) {
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
        key[u] = -1;
        push(w);
        for (WV x : CGAL::vertices_around_target(m.halfedge(w), m)) push(x);
        break;
      }
    }
    remove_needles(r);
    return r;
  }

private:
  /// The needle removal, after the decimation: the needles it could not collapse (a collapse there makes new
  /// needles, or gives a fan's apex too many neighbours) are what the overlay leaves where the map sends many
  /// target edges through nearly one point, faces of 10⁻¹² of the mesh's size whose normals, once the points
  /// are rounded, point anywhere. Each needle's edges, shortest first, both ways, are tried with the checks of
  /// test() and three changes (`needle_mode_`): any valence; a new face may be a needle if the collapse leaves
  /// fewer needles than its star had (not collinear: the exact tests need a plane); and a needle's normal is
  /// not compared with the target's (it is rounding), its distance still is. Every collapse removes a vertex,
  /// so the passes end; at most needle_removal_passes.
  void remove_needles(Decimation_result& r) {
    needle_mode_ = true;
    auto needles = [this] {
      std::vector<WF> out;
      for (WF f : m.faces())
        if (needle(corners(f))) out.push_back(f);
      return out;
    };
    std::vector<WF> todo = needles();
    r.needles_found = todo.size();
    for (unsigned pass = 0; pass < needle_removal_passes && !todo.empty(); ++pass) {
      if (s.budget.stop("the remeshing's needle removal", [&] { return std::to_string(todo.size()) + " needles left"; })) break;
      std::size_t kept = 0;
      for (WF f : todo) {
        if (m.is_removed(f) || !needle(corners(f))) continue; // removed or reshaped by an earlier collapse
        std::vector<std::pair<double, WH>> tries;
        for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m))
          for (WH g : {h, m.opposite(h)})
            if (removable(m.source(g))) tries.push_back({CGAL::squared_distance(s.pos[m.source(g)], s.pos[m.target(g)]), g});
        std::stable_sort(tries.begin(), tries.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (const auto& t : tries) {
          ++r.tried;
          Plan plan;
          if (!test(t.second, plan, r)) continue;
          apply(t.second, plan);
          ++r.collapses, ++r.needle_collapses, ++kept;
          break;
        }
      }
      todo = needles();
      if (kept == 0) break;
    }
    r.needles_left = todo.size();
    needle_mode_ = false;
  }

  /// The faces a collapse makes: corners (u replaced by w), the input source face holding each.
  struct Plan {
    std::vector<std::array<WV, 3>> faces;
    std::vector<int> orig;
    std::vector<WF> home; ///< per new face: the target face holding it (home()), or none
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
    if (!needle_mode_ && m.degree(u) + m.degree(w) - 4 > decimation_max_valence) return ++r.refused_valence, false;
    if (!CGAL::Euler::does_satisfy_link_condition(m.edge(h), m)) return ++r.refused_link, false;
    // The star of u: its faces, those with w go away, the others get w for u.
    std::vector<WF> star;
    for (WF f : CGAL::faces_around_target(m.halfedge(u), m)) star.push_back(f);
    // First what is cheap: w must lie on every input face that u's faces lie in (u on an input edge can only
    // move along it), and no new face may be a needle (in the needle removal: fewer needles than before).
    std::array<double, 3> b;
    for (WF f : star)
      if (!s.mesh.rep_in(w, s.mesh.forig[f], b)) return ++r.refused_source, false;
    std::vector<WF> replaced; // per new face: the face of the star it replaces
    std::size_t needles_before = 0, needles_after = 0;
    if (needle_mode_)
      for (WF f : star) needles_before += needle(corners(f));
    for (WF f : star) {
      std::array<WV, 3> c = corners(f);
      if (c[0] == w || c[1] == w || c[2] == w) continue;
      for (WV& x : c)
        if (x == u) x = w;
      if (needle(c)) {
        if (!needle_mode_ || CGAL::collinear(s.pos[c[0]], s.pos[c[1]], s.pos[c[2]])) return ++r.refused_needle, false;
        ++needles_after;
      }
      plan.faces.push_back(c);
      replaced.push_back(f);
    }
    if (needles_after > 0 && needles_after >= needles_before) return ++r.refused_needle, false;
    // The source: each new face in an input face that held a face of the star, oriented as that face's tiling.
    for (const auto& c : plan.faces) {
      int found = -1;
      for (WF f : star) {
        const int o = s.mesh.forig[f];
        if (in_input_face(c, o)) {
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
    // Whether every new face stays in the target face of the star face it replaces (home()): see below.
    bool at_home = true;
    for (std::size_t i = 0; i < plan.faces.size(); ++i) {
      plan.home.push_back(home(plan.faces[i]));
      at_home = at_home && plan.home[i] != WF() && plan.home[i] == home_[replaced[i]];
    }
    // The target: shape, distance and normal at the samples. When every new face stays in its star face's
    // target face, the samples, the distance certificate and the coverage below are known to pass: there the
    // map is affine and one-to-one and the new faces are positive over the base mesh (checked above), so in
    // each target face they cover exactly what the star's faces there covered (u, if on a target edge, lies
    // between its two neighbours along it), at distance zero and with that face's normal. The centroid's
    // test, which also compares with the target faces around the nearest point, still runs.
    for (const bool centroid_only : {true, false}) // every face's centroid first: the cheapest refusals
      for (const auto& c : plan.faces) {
        if (!centroid_only && at_home) break;
        switch (follows_target(c, centroid_only)) {
        case Follow::far: return ++r.refused_distance, false;
        case Follow::steep: return ++r.refused_normal, false;
        case Follow::yes: break;
        }
      }
    // Creases: no more edges whose faces fold back onto each other than the star had.
    if (creases_after(plan, u) > creases_before(star)) return ++r.refused_crease, false;
    // The target: every point of it that a new face stands for, near that face.
    if (!at_home)
      for (std::size_t i = 0; i < plan.faces.size(); ++i)
        if (!covers(plan.faces[i], plan.orig[i])) return ++r.refused_coverage, false;
    // Intersections: the new faces with each other and with the faces near them.
    for (std::size_t i = 0; i < plan.faces.size(); ++i)
      for (std::size_t j = i + 1; j < plan.faces.size(); ++j)
        if (intersect(plan.faces[i], plan.faces[j])) return ++r.refused_intersection, false;
    ++current_;
    for (WF f : star) stamp_[f] = current_; // the star's faces are replaced: not tested
    for (const auto& c : plan.faces) {
      const CGAL::Bbox_3 box = s.pos[c[0]].bbox() + s.pos[c[1]].bbox() + s.pos[c[2]].bbox();
      const WF h = plan.home[std::size_t(&c - plan.faces.data())];
      for (auto it = index_.qbegin(boost::geometry::index::intersects(to_face_box(box))); it != index_.qend(); ++it) {
        const WF g(it->second);
        if (stamp_[g] == current_ || (h != WF() && home_[g] != WF() && touching_homes(h, home_[g]))) continue;
        ++r.face_pairs;
        if (intersect(c, corners(g), degenerate_[g]) && !near_target_fold(box + box_[g])) return ++r.refused_intersection, false;
      }
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

  /// Whether corners c lie in input face o and are oriented there as every face tiling it is (exact;
  /// Layout_mesh::orig_orientation: negative in its barycentric coordinates where the input is oriented
  /// inward): the source-shaped mesh stays an exact copy of the source, each face with area on it. Not the
  /// orientation of the star's face: the overlay can leave a face reversed or with no area on the source by
  /// rounding (a vertex computed within rounding of an edge), which a collapse may remove and must never enlarge.
  bool in_input_face(const std::array<WV, 3>& c, int o) const {
    return s.source_orientation(o, c[0], c[1], c[2]) == s.mesh.orig_orientation[o];
  }

  enum class Follow { yes, far, steep };
  /// Whether the triangle with corners c on the target-shaped mesh is a needle (needle_triangle()).
  bool needle(const std::array<WV, 3>& c) const { return needle_triangle(s.pos[c[0]], s.pos[c[1]], s.pos[c[2]], s.eps); }
  /// Whether the triangle of the target-shaped mesh with corners `corner` (not a needle, but in the needle
  /// removal, where a needle's normal is not compared) follows the target: at its centroid (`centroid_only`)
  /// or at its nine other samples (the edge midpoints and the points at the thirds of the edges) within the
  /// margin of the target, its normal within the normal
  /// deviation of the target's at the nearest point (at the centroid) or within decimation_sample_deviation
  /// times that; and then every point of it within the margin, certified (certified_within()).
  Follow follows_target(const std::array<WV, 3>& corner, bool centroid_only) const {
    const Point_3 &a = s.pos[corner[0]], &b = s.pos[corner[1]], &c = s.pos[corner[2]];
    const Kernel::Vector_3 n = triangle_normal(a, b, c);
    const double ln = std::sqrt(n.squared_length());
    const bool thin = needle_mode_ && needle(corner); // its normal is rounding
    // Each query starts from the last one's answer (the first from the first corner's own place on the
    // target): the samples are close together, so the search ends sooner; the answer is the nearest point.
    std::pair<Point_3, WF> near{a, s.img[corner[0]].face};
    auto check = [&](const Point_3& p, double cos_bound) {
      near = tree.closest_point_and_primitive(p, near);
      if (CGAL::squared_distance(p, near.first) > limit2_) return Follow::far;
      if (thin) return Follow::yes;
      const Kernel::Vector_3 nt = s.target_normal(near.second);
      const double lt = std::sqrt(nt.squared_length());
      return lt > 0 && (n * nt) >= cos_bound * ln * lt ? Follow::yes : Follow::steep;
    };
    if (centroid_only) {
      // At the centroid also as the strict repair counts a flip: where the nearest point is on a target edge
      // or vertex (above a ridge it is), against every target face there, so that the strict repair that
      // follows has nothing of the decimation's to undo.
      const Follow f = check(CGAL::centroid(a, b, c), cos_dev_);
      return f == Follow::yes && !thin && s.opposes(n, near.first, near.second) ? Follow::steep : f;
    }
    auto at = [](const Point_3& p, const Point_3& q, double t) { return p + t * (q - p); };
    for (const Point_3& p : {CGAL::midpoint(a, b), CGAL::midpoint(b, c), CGAL::midpoint(c, a), at(a, b, 1.0 / 3),
                             at(a, b, 2.0 / 3), at(b, c, 1.0 / 3), at(b, c, 2.0 / 3), at(c, a, 1.0 / 3), at(c, a, 2.0 / 3)})
      if (const Follow f = check(p, cos_sample_); f != Follow::yes) return f;
    // The corners lie on the target (at F, in the target face s.img names), up to rounding.
    const Distance_probe pa{a, 0, s.img[corner[0]].face}, pb{b, 0, s.img[corner[1]].face}, pc{c, 0, s.img[corner[2]].face};
    return certified_within(tree, s.target.m, pa, pb, pc, certified_, near) ? Follow::yes : Follow::far;
  }

  /// A face of the overlay: its corners, and their places in the input source face it lies in (the last two
  /// barycentric coordinates there). The map is linear on it: its points on the target are the linear
  /// interpolation of its corners' positions.
  struct Piece {
    std::array<WV, 3> v;
    std::array<std::array<double, 2>, 3> q;
  };
  /// Records the overlay's faces by input source face, before any collapse, each source face's in a k × k
  /// grid of its barycentric square (k about the square root of half their number: two per cell), so that a
  /// new face finds the few it meets among thousands where the map squeezes.
  void record_overlay() {
    std::size_t n = 0;
    for (WF f : m.faces()) n = std::max(n, std::size_t(s.mesh.forig[f]) + 1);
    piece_start_.assign(n + 1, 0);
    for (WF f : m.faces()) ++piece_start_[std::size_t(s.mesh.forig[f]) + 1];
    for (std::size_t o = 0; o < n; ++o) piece_start_[o + 1] += piece_start_[o];
    std::vector<std::size_t> next(piece_start_.begin(), piece_start_.end() - 1);
    pieces_.assign(m.number_of_faces(), Piece());
    unplaced_.assign(n, 0);
    for (WF f : m.faces()) {
      const int o = s.mesh.forig[f];
      Piece& p = pieces_[next[std::size_t(o)]++];
      p.v = corners(f);
      for (int i = 0; i < 3; ++i) {
        std::array<double, 3> b{1, 0, 0};
        // An overlay corner lies on its face's input face; were it not found there, no new face in that source
        // face could be certified (covers() refuses them).
        if (!s.mesh.rep_in(p.v[std::size_t(i)], o, b)) unplaced_[std::size_t(o)] = 1;
        p.q[std::size_t(i)] = {b[1], b[2]};
      }
    }
    grid_.assign(n, {0, 1});
    cell_start_.assign(1, 0);
    std::vector<std::vector<std::uint32_t>> cells;
    for (std::size_t o = 0; o < n; ++o) {
      const std::size_t first = piece_start_[o], count = piece_start_[o + 1] - first;
      const int k = std::max(1, int(std::sqrt(double(count) / 2)));
      grid_[o] = {cell_start_.size() - 1, k};
      cells.assign(std::size_t(k) * std::size_t(k), {});
      for (std::size_t i = first; i < first + count; ++i) {
        const auto [c0, c1, r0, r1] = cell_range(pieces_[i].q[0], pieces_[i].q[1], pieces_[i].q[2], k);
        for (int r = r0; r <= r1; ++r)
          for (int c = c0; c <= c1; ++c) cells[std::size_t(r * k + c)].push_back(std::uint32_t(i));
      }
      for (const auto& cell : cells) {
        cell_items_.insert(cell_items_.end(), cell.begin(), cell.end());
        cell_start_.push_back(cell_items_.size());
      }
    }
    piece_stamp_.assign(pieces_.size(), 0);
    vertex_stamp_.assign(m.number_of_vertices(), 0);
  }
  /// The cells (first and last column, first and last row) of a k × k grid over [0, 1]² that the box of three
  /// points meets.
  static std::array<int, 4> cell_range(const std::array<double, 2>& a, const std::array<double, 2>& b,
                                       const std::array<double, 2>& c, int k) {
    auto at = [k](double x) { return std::clamp(int(std::floor(x * k)), 0, k - 1); };
    return {at(std::min({a[0], b[0], c[0]})), at(std::max({a[0], b[0], c[0]})), at(std::min({a[1], b[1], c[1]})),
            at(std::max({a[1], b[1], c[1]}))};
  }

  /// Whether every point of the target that new face c (in input source face o) stands for lies within the
  /// margin of c. Those points are the images of c's part of the source face under the map; on each overlay
  /// face of o the map is linear, and the distance to the triangle c is convex, so over c's intersection with
  /// an overlay face the distance is largest at a corner of that intersection (a convex polygon, found by
  /// clipping the overlay face to c in the coordinates of o, each clipped corner's image interpolated along
  /// the overlay face's edge it lies on). Exact but for rounding: no sample is missed.
  bool covers(const std::array<WV, 3>& c, int o) const {
    if (unplaced_[std::size_t(o)]) return false;
    using P2 = std::array<double, 2>;
    std::array<P2, 3> q;
    for (int i = 0; i < 3; ++i) {
      std::array<double, 3> b;
      if (!s.mesh.rep_in(c[std::size_t(i)], o, b)) return false;
      q[std::size_t(i)] = {b[1], b[2]};
    }
    auto side = [](const P2& a, const P2& b, const P2& x) { return (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]); };
    const double sign = side(q[0], q[1], q[2]) > 0 ? 1 : -1;
    const Kernel::Triangle_3 T(s.pos[c[0]], s.pos[c[1]], s.pos[c[2]]);
    struct Corner {
      P2 x;
      Point_3 y; // its image on the target
    };
    std::vector<Corner> poly, clipped;
    const auto [first_cell, k] = grid_[std::size_t(o)];
    const auto [c0, c1, r0, r1] = cell_range(q[0], q[1], q[2], k);
    ++piece_visit_;
    std::vector<std::uint32_t> near;
    for (int row = r0; row <= r1; ++row)
      for (int col = c0; col <= c1; ++col) {
        const std::size_t cell = first_cell + std::size_t(row * k + col);
        for (std::size_t j = cell_start_[cell]; j < cell_start_[cell + 1]; ++j)
          if (piece_stamp_[cell_items_[j]] != piece_visit_) piece_stamp_[cell_items_[j]] = piece_visit_, near.push_back(cell_items_[j]);
      }
    for (const std::uint32_t pi : near) {
      const Piece& p = pieces_[pi];
      // Each corner against each edge of c: a piece wholly outside one edge is skipped, one wholly inside
      // needs only its corners (each vertex once per call: it is a corner of several pieces); the others are
      // clipped.
      bool outside = false, inside = true;
      for (int e = 0; e < 3 && !outside; ++e) {
        const P2 &a = q[std::size_t(e)], &b = q[std::size_t((e + 1) % 3)];
        int out = 0;
        for (const P2& x : p.q) out += sign * side(a, b, x) < 0;
        outside = out == 3;
        inside = inside && out == 0;
      }
      if (outside) continue;
      if (inside) {
        for (const WV v : p.v)
          if (vertex_stamp_[v] != piece_visit_) {
            vertex_stamp_[v] = piece_visit_;
            if (CGAL::squared_distance(s.pos[v], T) > limit2_) return false;
          }
        continue;
      }
      poly = {{p.q[0], s.pos[p.v[0]]}, {p.q[1], s.pos[p.v[1]]}, {p.q[2], s.pos[p.v[2]]}};
      for (int e = 0; e < 3 && !poly.empty(); ++e) { // Sutherland-Hodgman, one edge of c at a time
        const P2 &a = q[std::size_t(e)], &b = q[std::size_t((e + 1) % 3)];
        clipped.clear();
        for (std::size_t i = 0; i < poly.size(); ++i) {
          const Corner &u = poly[i], &w = poly[(i + 1) % poly.size()];
          const double su = sign * side(a, b, u.x), sw = sign * side(a, b, w.x);
          if (su >= 0) clipped.push_back(u);
          if ((su < 0 && sw > 0) || (su > 0 && sw < 0)) {
            const double t = su / (su - sw);
            clipped.push_back({{u.x[0] + t * (w.x[0] - u.x[0]), u.x[1] + t * (w.x[1] - u.x[1])}, u.y + t * (w.y - u.y)});
          }
        }
        poly.swap(clipped);
      }
      for (const Corner& x : poly)
        if (CGAL::squared_distance(x.y, T) > limit2_) return false;
    }
    return true;
  }

  /// Whether triangles with corners c and d of the target-shaped mesh intersect beyond the corners they share
  /// (faces_intersect(), exact predicates).
  bool intersect(const std::array<WV, 3>& c, const std::array<WV, 3>& d, bool d_degenerate = false) const {
    if (d_degenerate) return false; // the verifier counts a degenerate face; new faces are never collinear (test())
    return faces_intersect(c, d, [this](WV v) -> const Point_3& { return s.pos[v]; });
  }

  bool near_target_fold(const CGAL::Bbox_3& b) const { return meets_grown(b, s.eps, target_folds_); }

  /// Collapses h as planned: u's two faces with w go, its other faces get w; forig follows.
  void apply(WH h, const Plan& plan) {
    const WV u = m.source(h), w = m.target(h);
    std::vector<WF> star;
    for (WF f : CGAL::faces_around_target(m.halfedge(u), m)) star.push_back(f);
    std::vector<std::array<std::size_t, 3>> keys;
    for (const auto& c : plan.faces) keys.push_back(sorted(c));
    for (WF f : star) index_.remove(Face_box_entry(to_face_box(box_[f]), std::uint32_t(f)));
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
      enter(f);
    }
  }
  static std::array<std::size_t, 3> sorted(const std::array<WV, 3>& c) {
    std::array<std::size_t, 3> k{std::size_t(c[0]), std::size_t(c[1]), std::size_t(c[2])};
    std::sort(k.begin(), k.end());
    return k;
  }

  /// The target face that holds every corner of the face with corners c (each within decimation_home_snap ε
  /// of it), if one does: one of the corners' own target faces (s.img), or one around the first corner's when
  /// that corner is on its border (a corner on a target edge or vertex is located in any of the faces there,
  /// up to rounding); none otherwise. Two faces of the target-shaped mesh in one target
  /// face cannot intersect beyond what they share: there the map is an affine bijection, each is the image of
  /// its triangle in the base mesh, and those do not overlap (the parameterization is one-to-one, checked
  /// exactly). Where the map squeezes many faces into one target face, this spares the exact tests of coplanar
  /// pairs, the slowest.
  WF home(const std::array<WV, 3>& c) const {
    const double snap2 = decimation_home_snap * s.eps * decimation_home_snap * s.eps;
    const std::array<WF, 3> own{s.img[c[0]].face, s.img[c[1]].face, s.img[c[2]].face};
    auto holds = [&](WF t) {
      const Kernel::Triangle_3 T = target_triangle(s.target.m, t);
      for (std::size_t j = 0; j < 3; ++j)
        if (own[j] != t && CGAL::squared_distance(s.pos[c[j]], T) > snap2) return false;
      return true;
    };
    for (std::size_t i = 0; i < 3; ++i) {
      const WF t = own[i];
      if (std::find(own.begin(), own.begin() + std::ptrdiff_t(i), t) != own.begin() + std::ptrdiff_t(i)) continue; // tried
      if (holds(t)) return t;
    }
    // A face along a target edge may have every corner located in the faces beyond it (a corner on an edge
    // or a vertex is located in any face there). The face that holds it then holds its first corner too, so
    // it is one of the faces around that corner's target face, if that corner is on its border.
    const auto& b = s.img[c[0]].b;
    if (!(std::min({b[0], b[1], b[2]}) < home_border)) return WF();
    const auto& tm = s.target.m;
    for (WH h : CGAL::halfedges_around_face(tm.halfedge(own[0]), tm))
      for (WF t : CGAL::faces_around_target(h, tm))
        if (t != WF() && std::find(own.begin(), own.end(), t) == own.end() && holds(t)) return t;
    return WF();
  }
  /// Whether faces of the target-shaped mesh at home in target faces a and b need no intersection test: a and b
  /// are one face, or share a corner. In one target face, see home(). In two that share a corner, each face
  /// lies in its own target face, and the two target faces meet only at their common edge or corner (where
  /// they meet elsewhere, the target intersects itself there and the pair is excused anyway,
  /// near_target_fold()); on a common edge the faces of either side have the same vertices, those of the
  /// overlay on that edge, so they meet at shared corners or edges only. Where the map squeezes, most box
  /// overlaps are such pairs across a target edge, and their exact tests the slowest (nearly coplanar).
  bool touching_homes(WF a, WF b) const {
    if (a == b) return true;
    const auto &p = target_corners_[std::size_t(a)], &q = target_corners_[std::size_t(b)];
    for (WV x : p)
      if (x == q[0] || x == q[1] || x == q[2]) return true;
    return false;
  }
  /// Records f's box, degeneracy and home and returns its entry.
  Face_box_entry record(WF f) {
    const std::array<WV, 3> c = corners(f);
    home_[f] = home(c);
    box_[f] = s.pos[c[0]].bbox() + s.pos[c[1]].bbox() + s.pos[c[2]].bbox();
    degenerate_[f] = CGAL::collinear(s.pos[c[0]], s.pos[c[1]], s.pos[c[2]]);
    return Face_box_entry(to_face_box(box_[f]), std::uint32_t(f));
  }
  void enter(WF f) { index_.insert(record(f)); }
  void build_index() {
    std::vector<Face_box_entry> entries;
    for (WF f : m.faces()) entries.push_back(record(f));
    index_ = Face_box_index(entries.begin(), entries.end()); // bulk loading (packing): a better tree than inserting
  }

  Remesh_state& s;
  Work_mesh& m;
  std::size_t first_;
  Target_tree tree;
  double cos_dev_ = 0, cos_sample_ = 0, cos_crease_ = -1, limit2_ = 0, certified_ = 0;
  std::vector<CGAL::Bbox_3> target_folds_;
  std::vector<Piece> pieces_;            ///< the overlay's faces, grouped by the input source face they lie in
  std::vector<std::size_t> piece_start_; ///< per input source face o: its pieces are [piece_start_[o], piece_start_[o + 1])
  std::vector<char> unplaced_;           ///< per input source face: whether an overlay corner was not found on it
  std::vector<std::pair<std::size_t, int>> grid_; ///< per input source face: its first cell, and k
  std::vector<std::size_t> cell_start_;  ///< per cell: its pieces are cell_items_[cell_start_[c], cell_start_[c + 1])
  std::vector<std::uint32_t> cell_items_;
  mutable std::vector<std::uint64_t> piece_stamp_; ///< per piece: the covers() call that last met it
  mutable std::vector<std::uint64_t> vertex_stamp_; ///< per vertex of the overlay: the covers() call that last checked it
  mutable std::uint64_t piece_visit_ = 0;
  // The target-shaped mesh's faces in an R-tree of their boxes (Face_box_index), for the intersection tests:
  // it stays fast at any mix of face sizes (the overlay's many small faces where the map squeezes beside the
  // decimated mesh's large ones). A collapse takes its star's faces out and enters the faces it makes.
  Face_box_index index_;
  std::vector<CGAL::Bbox_3> box_;       ///< per face: its box as entered in the index
  std::vector<char> degenerate_;        ///< per face: its corners collinear (exact), as entered
  std::vector<WF> home_;                ///< per face: the target face holding it (home()), as entered
  std::vector<std::array<WV, 3>> target_corners_; ///< per target face: its corners
  std::vector<std::uint64_t> stamp_;    ///< per face: the test that last excluded it
  std::uint64_t current_ = 0;
  bool needle_mode_ = false; ///< in remove_needles()
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

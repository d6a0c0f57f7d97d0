// SPDX-License-Identifier: GPL-3.0-or-later
// Untangling on the target (an addition to the paper): folds of M_st left after the pseudo flips (§5.4) are
// removed by moving vertices of the target-shaped mesh along the target, off F, in a planar chart of a ring
// around the fold (untangle.h) or in a flattened disk of the target (disk_chart.h). The source vertices stay.
#ifndef CROSSPARAM_INTERNAL_REMESHING_TARGET_UNTANGLING_H
#define CROSSPARAM_INTERNAL_REMESHING_TARGET_UNTANGLING_H

#include <crossparam/internal/barycentric.h>
#include <crossparam/internal/remeshing/disk_chart.h>
#include <crossparam/internal/remeshing/distance_certificate.h>
#include <crossparam/internal/remeshing/remesh_state.h>
#include <crossparam/internal/remeshing/untangle.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <utility>
#include <vector>

namespace crossparam {
namespace internal {

/// What one Target_untangler::run() did.
struct Untangle_result {
  std::size_t folds_removed = 0; ///< folded faces that the untangling removed
  std::size_t moves = 0;         ///< vertices of the target-shaped mesh it moved (off F, along the target)
  double max_move = 0;           ///< the farthest such move, percent of the target's bounding-box diagonal
  std::size_t folds_not_tried = 0; ///< folded faces left untried when the run's work bound was reached
};

/// The untangling of M_st on the target, with the target's AABB tree built once for all its runs.
class Target_untangler {
public:
  using Target_tree = internal::Target_tree;

  /// The fold rules the untangling works to.
  enum class Rule {
    all_points, ///< a fold: the normal opposes the target's at the points nearest the centroid and every corner
    standard    ///< a flip by the standard rule, the verifier's: the normal opposes the target's at the point nearest the centroid
  };

  explicit Target_untangler(Remesh_state& state, Rule rule = Rule::all_points)
      : s(state), rule_(rule), tree(CGAL::faces(state.target.m).first, CGAL::faces(state.target.m).second, state.target.m) {
    tree.accelerate_distance_queries();
  }

  /// The faces of M_st flipped by this untangler's rule.
  std::size_t count_flipped() const {
    std::size_t n = 0;
    for (WF f : s.mesh.m.faces()) n += flipped_on_target(f);
    return n;
  }
  /// The untangling of run() around face f of M_st, flipped or not (a pleat: faces folded over each other with
  /// normals that agree with the target's): a planar chart of a ring around f, else a flattened disk. Returns
  /// whether an untangling was kept. Within the work bound of one fold, and all calls on this untangler
  /// within that of one run() together (work_per_fold, work_per_run). With `rings_only`, the planar charts
  /// of the rings alone.
  bool untangle_around(WF f, bool rings_only = false) {
    if (run_work_left_ == 0) return false; // the bound is shared by every call on this untangler
    std::vector<char> moved(s.mesh.m.number_of_vertices(), 0);
    fold_work_left_ = work_per_fold;
    int r = untangle_in_rings(f, moved);
    for (double size : {1.0, 1.5, 2.0})
      if (r <= 0 && !rings_only && !s.budget.expired()) r = untangle_on_surface(f, size, moved);
    return r > 0;
  }
  /// The point of the target nearest p, and its face.
  std::pair<Point_3, WF> nearest(const Point_3& p) const { return tree.closest_point_and_primitive(p); }
  /// The location on the target of the point of the target nearest p.
  Work_location nearest_location(const Point_3& p) const {
    const std::pair<Point_3, WF> n = nearest(p);
    return location_in(n.second, n.first);
  }
  /// Whether face f of M_st is flipped by this untangler's rule.
  bool flipped(WF f) const { return flipped_on_target(f); }
  /// Whether face f of M_st may have a point farther than `limit` from the target: not certified within it
  /// (certified_within(), from its corners' nearest points).
  bool far(WF f, double limit) const {
    const auto& m = s.mesh.m;
    const WH h = m.halfedge(f);
    const Point_3& pa = s.pos[m.source(h)];
    std::pair<Point_3, WF> hint = tree.closest_point_and_primitive(pa);
    const Distance_probe a{pa, std::sqrt(CGAL::squared_distance(pa, hint.first)), hint.second}; // the query above
    const Distance_probe b = probe(tree, s.pos[m.target(h)], hint), c = probe(tree, s.pos[m.target(m.next(h))], hint);
    return !certified_within(tree, s.target.m, a, b, c, limit, hint);
  }
  /// Sets `s.folded` and `s.n_flipped` by this untangler's rule.
  void mark_flipped() {
    s.n_flipped = 0;
    for (WF f : s.mesh.m.faces()) s.n_flipped += (s.folded[f] = flipped_on_target(f));
  }

  /// Untangles the folds of M_st along the target. Every face is tested by this untangler's rule
  /// (flipped_on_target()), which also sets `s.folded` and `s.n_flipped`. Where F is this anisotropic, no M_st that is F of a one-to-one M_s avoids the
  /// fold (doc/algorithms.md, "Where F is strongly anisotropic"), so these vertices of the target-shaped mesh leave F: they move along the
  /// target, their source vertices stay. Each folded face f is untangled in a chart of the target with the
  /// outline of a region around it and the feature vertices held: first in the plane of the mean target normal
  /// under the k-ring of f (k = 1 ... 8, while the ring is flat enough for a plane: untangle_ring()), then, if
  /// no ring works, in a flattened disk of the target around f, which follows the target where it bends
  /// (untangle_on_surface()).
  Untangle_result run() {
    const auto& m = s.mesh.m;
    max_move_ = 0;
    Untangle_result result;
    std::vector<char> moved(m.number_of_vertices(), 0);
    std::vector<WF> folds;
    for (WF f : m.faces())
      if (flipped_on_target(f)) folds.push_back(f);
    std::size_t done = 0;
    run_work_left_ = work_per_run;
    for (WF f : folds) {
      if (!flipped_on_target(f)) continue; // untangled with an earlier one
      if (run_work_left_ == 0) {
        ++result.folds_not_tried;
        continue;
      }
      if (s.budget.stop("the remeshing's untangling", [&] {
            return std::to_string(done) + " of " + std::to_string(folds.size()) + " folded faces";
          }))
        break; // best effort: every untangling so far is complete
      ++done;
      fold_work_left_ = work_per_fold;
      int r = untangle_in_rings(f, moved);
      for (double size : {1.0, 1.5, 2.0})
        if (r <= 0 && !s.budget.expired()) r = untangle_on_surface(f, size, moved);
    }
    s.n_flipped = 0;
    for (WF f : m.faces()) s.n_flipped += (s.folded[f] = flipped_on_target(f));
    for (WF f : folds) result.folds_removed += !s.folded[f];
    for (char c : moved) result.moves += c;
    result.max_move = max_move_;
    return result;
  }

private:
  /// Whether face f of M_st is flipped by this untangler's rule (its normal opposes the target's at the point of
  /// the target nearest its centroid, and with Rule::all_points at those nearest each corner too), taken
  /// strictly: where such a point lies on an edge or at a vertex of the target, the verifier may take any face
  /// through it, so the point counts as opposing if one of them opposes (Remesh_state::opposes()).
  bool flipped_on_target(WF f) const {
    const auto& m = s.mesh.m;
    const WH h = m.halfedge(f);
    const Point_3 &a = s.pos[m.source(h)], &b = s.pos[m.target(h)], &c = s.pos[m.target(m.next(h))];
    const Kernel::Vector_3 n = triangle_normal(a, b, c);
    for (const Point_3& p : {CGAL::centroid(a, b, c), a, b, c}) {
      const auto nearest = tree.closest_point_and_primitive(p);
      if (!s.opposes(n, nearest.first, nearest.second)) return false;
      if (rule_ == Rule::standard) return true; // the centroid alone
    }
    return true;
  }

  /// untangle_ring() for k = 1 ... 8 until a ring is kept (1) or too curved (-1); 0 if none is kept.
  int untangle_in_rings(WF f, std::vector<char>& moved) {
    int r = 0;
    for (int k = 1; k <= 8 && r == 0 && !s.budget.expired() && work_left() > 0; ++k) r = untangle_ring(f, k, moved);
    return r;
  }

  /// The planar chart: the k-ring of f0 projected onto the plane of the mean target normal under its vertices
  /// (only while every target normal there is within 72° of it), untangled from the present positions, moved
  /// points lifted back onto the target along the plane's normal (the hit nearest the plane point). 1 if
  /// kept, 0 if not (a larger k may work), -1 if the ring has become too curved for a plane.
  int untangle_ring(WF f0, int k, std::vector<char>& moved) {
    const auto& m = s.mesh.m;
    std::set<WF> region{f0};
    std::set<WV> ring;
    for (WV v : CGAL::vertices_around_face(m.halfedge(f0), m)) ring.insert(v);
    for (int r = 0; r < k; ++r) {
      std::set<WV> grown = ring;
      for (WV v : ring)
        for (WF f : CGAL::faces_around_target(m.halfedge(v), m)) {
          region.insert(f);
          for (WV w : CGAL::vertices_around_face(m.halfedge(f), m)) grown.insert(w);
        }
      ring = std::move(grown);
    }
    auto unit_normal = [this](WF f) {
      const Kernel::Vector_3 n = s.target_normal(f);
      return n / std::sqrt(n * n);
    };
    Kernel::Vector_3 normal(0, 0, 0);
    for (WV v : ring) normal = normal + unit_normal(s.img[v].face);
    const double length = std::sqrt(normal * normal);
    if (!(length > 0)) return -1; // normals that cancel out: no plane to project on
    normal = normal / length;
    for (WV v : ring)
      if (unit_normal(s.img[v].face) * normal < 0.3) return -1;
    const Kernel::Vector_3 u0 = std::abs(normal.x()) < 0.9 ? Kernel::Vector_3(1, 0, 0) : Kernel::Vector_3(0, 1, 0);
    Kernel::Vector_3 U = CGAL::cross_product(normal, u0);
    U = U / std::sqrt(U * U);
    const Kernel::Vector_3 W = CGAL::cross_product(normal, U);
    const Point_3 origin = s.pos[*ring.begin()];
    auto to_chart = [&](WV v) { return Eigen::Vector2d((s.pos[v] - origin) * U, (s.pos[v] - origin) * W); };
    auto from_chart = [&](WV v, const Eigen::Vector2d& p, Work_location& at) {
      const Eigen::Vector2d d = p - to_chart(v);
      const Point_3 g = s.pos[v] + d.x() * U + d.y() * W;
      std::vector<typename Target_tree::template Intersection_and_primitive_id<Kernel::Line_3>::Type> hits;
      tree.all_intersections(Kernel::Line_3(g, normal), std::back_inserter(hits));
      double best = HUGE_VAL;
      for (const auto& hit : hits)
        if (const Point_3* q = boost::get<Point_3>(&hit.first)) { // (a segment: the line lies in a target face)
          const double d2 = CGAL::squared_distance(*q, g);
          if (d2 < best) best = d2, at = location_in(hit.second, *q);
        }
      return best < HUGE_VAL;
    };
    return untangle_in_chart(region, to_chart, from_chart, false, moved);
  }

  /// The surface chart, for a fold inside a tangle too large or too curved for a planar ring (a fan of needles
  /// along a limb where F is squeezed): a disk of the target grown around f0 to `size` times f0's longest
  /// edge, over the faces within 78° of the target normal under f0 (the front of a limb, not around it), and
  /// flattened (Disk_chart). The region is the connected set of faces around f0 whose corners lie on
  /// the disk and within 0.8 of its radius. Its inner vertices are laid out afresh by mean-value coordinates
  /// of the *source* shape (a local cross-parameterization of the source patch into the chart) and
  /// untangled, and they map back through the flattening, onto the target exactly. The chart's straight edges
  /// are not the target's, so a few faces may still be flipped on the target: those are given to
  /// untangle_ring(). Kept only if then no face around a vertex it moved is flipped; otherwise everything is
  /// restored. 1 if kept, 0 if not.
  int untangle_on_surface(WF f0, double size, std::vector<char>& moved) {
    if (work_left() == 0) return 0;
    const auto& m = s.mesh.m;
    const WH h0 = s.longest_edge(f0);
    const double radius = size * std::sqrt(CGAL::squared_distance(s.pos[m.source(h0)], s.pos[m.target(h0)]));
    const Point_3 center = CGAL::centroid(s.pos[m.source(h0)], s.pos[m.target(h0)], s.pos[m.target(m.next(h0))]);
    std::vector<WF> seeds;
    Kernel::Vector_3 direction(0, 0, 0);
    for (WV v : CGAL::vertices_around_face(h0, m)) {
      seeds.push_back(s.img[v].face);
      const Kernel::Vector_3 n = s.target_normal(s.img[v].face);
      direction = direction + n / std::sqrt(n * n);
    }
    if (!(direction * direction > 0)) return 0;
    direction = direction / std::sqrt(direction * direction);
    const std::optional<Disk_chart> chart =
        Disk_chart::grow(s.target.m, seeds, center, radius, direction, std::cos(78 * CGAL_PI / 180));
    if (!chart) return 0;
    auto inside = [&](WF f) {
      for (WV v : CGAL::vertices_around_face(m.halfedge(f), m))
        if (!chart->contains(s.img[v].face) || CGAL::squared_distance(s.pos[v], center) > CGAL::square(0.8 * radius))
          return false;
      return true;
    };
    if (!inside(f0)) return 0;
    std::set<WF> region{f0};
    for (std::vector<WF> todo{f0}; !todo.empty();) {
      const WF f = todo.back();
      todo.pop_back();
      for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        const WF g = m.face(m.opposite(h));
        if (g != WF() && !region.count(g) && inside(g)) region.insert(g), todo.push_back(g);
      }
    }
    auto to_chart = [&](WV v) { return chart->at(s.target.m, s.img[v]); };
    auto from_chart = [&](WV, const Eigen::Vector2d& p, Work_location& at) {
      return chart->locate(s.target.m, p, at);
    };
    const std::vector<Work_location> img_before = s.img;
    const std::vector<Point_3> pos_before = s.pos;
    const std::vector<char> moved_before = moved;
    const double max_move_before = max_move_;
    if (untangle_in_chart(region, to_chart, from_chart, true, moved) <= 0) return 0;
    for (WF f : region)
      if (flipped_on_target(f)) untangle_in_rings(f, moved);
    // Every vertex this call moved, also one that an earlier untangling had moved already.
    for (std::size_t i = 0; i < moved.size(); ++i)
      if (s.pos[i] != pos_before[i])
        for (WF f : CGAL::faces_around_target(m.halfedge(WV(i)), m))
          if (flipped_on_target(f)) {
            s.img = img_before, s.pos = pos_before, moved = moved_before, max_move_ = max_move_before;
            return 0;
          }
    return 1;
  }

  /// What both charts share: the region's vertices are placed in the chart (`to_chart(v)`); the inner ones
  /// (not features, every face around them in the region) are free, the others held. With `relayout`, the
  /// free ones first get the mean-value layout of the source shape. They are moved by
  /// Planar_untangler (reference shapes: a face's present shape where it is well shaped and not
  /// folded, else an equilateral triangle of the region's mean area; faces with no free corner cannot change
  /// and are left out) and mapped back onto the target (`from_chart(v, p, location)`, false if it cannot).
  /// The region is kept if every face of it stays within 0.9 ε of the target (centroid and edge midpoints,
  /// closest points) and, unless `relayout` (whose caller finishes and checks the region), if the untangler
  /// left no triangle inverted and none of the faces it moved is flipped by this untangler's rule;
  /// otherwise it is restored. 1 if kept, 0 if not.
  template <class ToChart, class FromChart>
  int untangle_in_chart(const std::set<WF>& region, const ToChart& to_chart,
                        const FromChart& from_chart, bool relayout, std::vector<char>& moved) {
    if (work_left() == 0) return 0;
    const auto& m = s.mesh.m;
    std::map<WV, int> id;
    std::vector<WV> verts;
    for (WF f : region)
      for (WV v : CGAL::vertices_around_face(m.halfedge(f), m))
        if (id.emplace(v, int(verts.size())).second) verts.push_back(v);
    std::vector<Eigen::Vector2d> xy;
    std::vector<char> is_free;
    std::size_t n_free = 0;
    for (WV v : verts) {
      xy.push_back(to_chart(v));
      bool inner = s.mesh.vfeature[v] == no_feature;
      for (WF f : CGAL::faces_around_target(m.halfedge(v), m)) inner = inner && region.count(f) > 0;
      is_free.push_back(inner);
      n_free += inner;
    }
    auto corners = [&](WF f) {
      std::array<int, 3> c;
      int i = 0;
      for (WV v : CGAL::vertices_around_face(m.halfedge(f), m)) c[i++] = id[v];
      return c;
    };
    auto moves = [&](const std::array<int, 3>& c) { return is_free[c[0]] || is_free[c[1]] || is_free[c[2]]; };
    double area = 0;
    for (WF f : region) area += 0.5 * edge_matrix_of(xy, corners(f)).determinant();
    if (n_free == 0 || !(area > 0)) return 0;
    if (relayout) {
      std::vector<char> held(is_free.size());
      for (std::size_t i = 0; i < held.size(); ++i) held[i] = !is_free[i];
      if (!mean_value_layout(m, verts, [&](WV v) { return id.at(v); }, held, xy)) return 0;
    }
    const double side = std::sqrt(4 * area / double(region.size()) / std::sqrt(3.0));
    Eigen::Matrix2d equilateral;
    equilateral << side, side / 2, 0, side * std::sqrt(3.0) / 2;
    std::vector<Untangle_triangle> tris;
    for (WF f : region) {
      const auto c = corners(f);
      if (!moves(c)) continue;
      const Eigen::Matrix2d e = edge_matrix_of(xy, c);
      const double longest2 = std::max({e.col(0).squaredNorm(), e.col(1).squaredNorm(), (e.col(1) - e.col(0)).squaredNorm()});
      const bool good = e.determinant() > 0.2 * std::sqrt(3.0) / 4 * longest2 && !s.face_folded(f);
      tris.push_back({c, (good ? e : equilateral).inverse()});
    }
    Planar_untangler untangler(xy, is_free, std::move(tris));
    const double det = untangler.run(0.3 * side, 51, 400, &s.budget, work_left());
    spend(untangler.evaluations());
    if (!(det > 0) && (!relayout || s.budget.expired())) return 0; // a run cut short by the time limit is not kept
    std::vector<std::pair<WV, Corner>> old;
    auto restore = [&] {
      for (const auto& o : old) s.img[o.first] = o.second.img, s.pos[o.first] = o.second.pos;
    };
    for (std::size_t i = 0; i < verts.size(); ++i) {
      if (!is_free[i]) continue;
      Work_location at;
      if (!from_chart(verts[i], untangler.point(i), at)) return restore(), 0;
      old.emplace_back(verts[i], s.corner(verts[i]));
      s.img[verts[i]] = at, s.pos[verts[i]] = s.target_point(at);
    }
    // Keep it only if the region follows the target and nothing it moved is flipped.
    const double bound2 = CGAL::square(0.9 * s.eps);
    for (WF f : region) {
      const WH h = m.halfedge(f);
      const Point_3 &a = s.pos[m.source(h)], &b = s.pos[m.target(h)], &c = s.pos[m.target(m.next(h))];
      for (const Point_3& p : {CGAL::centroid(a, b, c), CGAL::midpoint(a, b), CGAL::midpoint(b, c), CGAL::midpoint(c, a)})
        if (tree.squared_distance(p) > bound2) return restore(), 0;
      if (!relayout && moves(corners(f)) && flipped_on_target(f)) return restore(), 0;
    }
    for (const auto& o : old) {
      moved[o.first] = 1;
      max_move_ = std::max(max_move_, 100 * std::sqrt(CGAL::squared_distance(o.second.pos, s.pos[o.first])));
    }
    return 1;
  }
  /// The work the present fold may still use (within its run's).
  std::size_t work_left() const { return std::min(fold_work_left_, run_work_left_); }
  void spend(std::size_t work) {
    fold_work_left_ -= std::min(fold_work_left_, work);
    run_work_left_ -= std::min(run_work_left_, work);
  }
  static Eigen::Matrix2d edge_matrix_of(const std::vector<Eigen::Vector2d>& xy, const std::array<int, 3>& c) {
    return edge_matrix(xy[c[0]], xy[c[1]], xy[c[2]]);
  }
  /// The location on target face f of point p (on f's plane): barycentric coordinates from sub-areas.
  Work_location location_in(WF f, const Point_3& p) const {
    const auto& t = s.target.m;
    const WH h = t.halfedge(f);
    return {f, barycentric_in_triangle(t.point(t.source(h)), t.point(t.target(h)), t.point(t.target(t.next(h))), p)};
  }

  /// The work bounds, in triangle energies evaluated by the planar untanglings (Planar_untangler::run(), about
  /// 40 ns each on one core): per fold (its rings, then its surface charts with the rings inside them) and per
  /// run() (or per untangler, for the calls of untangle_around()). On the bench the folds that are untangled
  /// use up to 6e7 (shrec_381_382; lion_cat 5e5, horse0_horse7 5e6), and a fold that cannot be untangled up
  /// to 7e7 (horse0_horse7); on feline_g2 and a pair of SHREC'07 animals, the first run alone went on for
  /// over ten minutes (1e10 in 400 s). The bounds keep every fold the bench untangles and cap the rest: a
  /// fold at about 6 s, a run at about 2 minutes.
  static constexpr std::size_t work_per_fold = 150000000, work_per_run = 3000000000;

  Remesh_state& s;
  Rule rule_;
  std::size_t fold_work_left_ = work_per_fold; ///< what the present fold may still use
  std::size_t run_work_left_ = work_per_run;   ///< what the present run() may still use
  Target_tree tree;     ///< the target's faces
  double max_move_ = 0; ///< the farthest move of this run (percent of the target's diagonal)
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_TARGET_UNTANGLING_H

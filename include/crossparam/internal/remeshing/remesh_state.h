// SPDX-License-Identifier: GPL-3.0-or-later
// The state of compatible remeshing (paper §5): the remeshed mesh M_s (a copy of the source's working mesh,
// refined by splits only), its parameterization over the base mesh, and its image M_st on the target (every
// vertex at F of it, except where the untangling moves it along the target), with the measurement of §5.1
// and the primitives the steps share: the fold test against the target, split and insert with their exact
// validity test, and checkpoints for the transactions of the fold repair. The steps live beside this header,
// one per file (refinement.h, pseudo_flips.h, fold_repair.h, target_untangling.h); the driver is
// Compatible_remesher in compatible_remeshing.h.
#ifndef CROSSPARAM_INTERNAL_REMESHING_REMESH_STATE_H
#define CROSSPARAM_INTERNAL_REMESHING_REMESH_STATE_H

#include <crossparam/cross_parameterization.h>
#include <crossparam/internal/parallel.h>
#include <crossparam/internal/time_budget.h>

#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

namespace crossparam {
namespace internal {

/// Smallest ratio of a face's area to the square of its longest edge on the target-shaped mesh (an
/// equilateral triangle has 0.43). Below it a face is a needle whose computed normal is rounding: its flip
/// test and its intersections would be decided by noise.
constexpr double decimation_min_shape = 1e-6;

/// Smallest height of a face of the target-shaped mesh (twice its area over its longest edge), as a fraction of
/// the tolerance ε, below which it is a needle too, whatever its shape. The overlay makes faces whose edges are
/// 10⁻¹³ of the mesh's size where the map sends many target edges through nearly one point (eiffel_g4): there
/// the output's coordinates, rounded after the conversion to input coordinates (about 10⁻¹⁶ of the
/// coordinates' size), decide the normal. 10⁻⁶ ε is far below anything the tolerance can see (10⁻⁹ of the
/// diagonal at ε = 0.1 %) and far above that rounding.
constexpr double decimation_min_height = 1e-6;

/// Height of a face of the source-shaped mesh (twice its area over its longest edge), as a fraction of that
/// edge, below which an edge flip that would make it is refused when the state refuses source slivers
/// (Remesh_state::refuse_source_slivers). The exact convexity test of a flip (flip_keeps_source()) decides on
/// barycentric coordinates computed with rounding: four vertices interpolated on one line of the source, each
/// off it by about 10⁻¹⁶, pass it by that rounding alone and make a face of area 10⁻¹⁷ whose image's
/// normal nothing controls. 10⁻⁹ is far above that rounding (relative 10⁻¹⁶) and far below any face the
/// overlay needs (the thinnest it keeps elsewhere are about 10⁻⁶ of their length: conform_snap).
constexpr double source_sliver_height = 1e-9;

/// The squared length of the longest edge of triangle (a, b, c), and that length.
inline double longest_side_squared(const Point_3& a, const Point_3& b, const Point_3& c) {
  return std::max({CGAL::squared_distance(a, b), CGAL::squared_distance(b, c), CGAL::squared_distance(c, a)});
}
inline double longest_side(const Point_3& a, const Point_3& b, const Point_3& c) {
  return std::sqrt(longest_side_squared(a, b, c));
}

/// Whether triangle (a, b, d) of the target-shaped mesh is a needle: its area below decimation_min_shape times its
/// longest edge squared, or its height below decimation_min_height ε. Its computed normal is rounding, and so
/// are the flip and intersection tests on it (the decimation makes none; the strict repair counts one as bad).
inline bool needle_triangle(const Point_3& a, const Point_3& b, const Point_3& d, double eps) {
  const double len2 = longest_side_squared(a, b, d);
  const double n2 = triangle_normal(a, b, d).squared_length(); // |n| = 2 area = height × longest edge
  const double min_height = decimation_min_height * eps;
  return !(n2 > 0) || !(std::sqrt(n2) > 2 * decimation_min_shape * len2) || !(n2 > min_height * min_height * len2);
}

/// Whether triangle (a, b, c) of the source-shaped mesh is a sliver: its height (twice its area over its longest
/// edge) below source_sliver_height times that edge, or no area at all. For working coordinates (unit diagonal).
inline bool source_sliver_triangle(const Point_3& a, const Point_3& b, const Point_3& c) {
  const double len2 = longest_side_squared(a, b, c);
  const double n = std::sqrt(triangle_normal(a, b, c).squared_length()); // height × longest edge
  return !(n > source_sliver_height * len2);
}

/// What stage 3 reads of a cross-parameterization: the source's working mesh and parameterization (copied
/// into the state and refined there), the target's working mesh, parameterization and point locator (read
/// only), and the conversion of a location on the target's working mesh to the target as given.
struct Map_view {
  const Layout_mesh& source;
  const Base_parameterization& source_parameterization;
  const Layout_mesh& target;
  const Base_parameterization& target_parameterization;
  const Base_locator& target_locator;
  std::function<Input_location(const Work_location&)> target_to_input;
};

/// The one place where stage 3 reaches into the cross-parameterization `cp` (which must outlive the view).
template <class CrossParameterization>
Map_view map_view(const CrossParameterization& cp) {
  using Access = Cross_parameterization_access;
  return {Access::layout_mesh(cp, Mesh_side::source), Access::parameterization(cp, Mesh_side::source),
          Access::layout_mesh(cp, Mesh_side::target), Access::parameterization(cp, Mesh_side::target),
          Access::locator(cp, Mesh_side::target),
          [&cp](const Work_location& l) { return cp.to_input(Mesh_side::target, l); }};
}

/// A corner of a planned face: base location, image on the target and its point.
struct Corner {
  Base_location loc;
  Work_location img;
  Point_3 pos;
};
using Face_plan = std::array<const Corner*, 3>;

/// What measure() located on the target (corner_at() of a base location), by vertex, edge midpoint and face
/// centroid, with what it depends on.
struct Measure_cache {
  std::size_t valid = 0, valid_edges = 0, valid_faces = 0; // entries below these are filled in
  std::vector<Corner> vertex;
  std::vector<char> same;                 // per vertex: location unchanged in this measure()
  std::vector<std::array<WV, 3>> corners; // per face: corners from its halfedge
  std::vector<char> face_same;            // per face: corners and their locations unchanged
  std::vector<Corner> centroid;
  std::vector<std::array<std::size_t, 3>> edge; // per edge: source, target, face of its halfedge
  std::vector<Corner> mid;
};

/// The two result meshes of one face list (see Compatible_remesher), in input coordinates.
struct Remesh_outputs {
  std::vector<std::array<std::size_t, 3>> faces;   ///< oriented as the input source
  std::vector<std::array<double, 3>> source_points; ///< the source-shaped mesh's points
  std::vector<std::array<double, 3>> target_points; ///< the target-shaped mesh's points, on the target
  std::vector<Input_location> target_locations;     ///< where each vertex lands on the target as given
  std::vector<double> vertex_error;                 ///< the smoothed e(v) where each vertex lands, percent
  std::vector<Input_face_location> source_faces;    ///< per face: the input source face holding it
};

/// The remeshed mesh and its image on the target. Not copyable: the parameterization points to the mesh.
class Remesh_state {
public:
  /// A copy of the source side of `map`; `tolerance` is ε in working coordinates (unit bounding-box
  /// diagonal), `n_threads` the threads of measure().
  Remesh_state(const Map_view& map, double tolerance, unsigned n_threads)
      : target(map.target), target_param(map.target_parameterization), target_locator(map.target_locator),
        target_to_input(map.target_to_input), mesh(map.source), param(map.source_parameterization), eps(tolerance),
        threads(n_threads) {
    param.mesh = &mesh;
  }
  Remesh_state(const Remesh_state&) = delete;
  Remesh_state& operator=(const Remesh_state&) = delete;

  // The target (read only).
  const Layout_mesh& target;
  const Base_parameterization& target_param;
  const Base_locator& target_locator;
  const std::function<Input_location(const Work_location&)> target_to_input;

  // The remeshed mesh and M_st.
  Layout_mesh mesh;            ///< the source-shaped mesh M_s (splits only: the source geometry is kept)
  Base_parameterization param; ///< its parameterization over the base mesh
  Base_locator mesh_locator;   ///< locates on `mesh` through `param` (built by measure())
  std::vector<Work_location> img; ///< per source vertex: its image on the target (M_st)
  std::vector<Point_3> pos;       ///< per source vertex: M_st's point (working coordinates)

  // The measurement (measure()).
  std::vector<double> e, es;         ///< e(v) per target vertex, and smoothed
  std::vector<double> edge_error;    ///< Eq. 2 per source edge
  std::vector<double> edge_chord;    ///< per source edge: M_st's edge midpoint's distance from F(midpoint)
  std::vector<double> face_chord;    ///< per source face: M_st's centroid's distance from F(centroid)
  std::vector<char> folded;          ///< per source face: M_st's face flipped against the target
  std::vector<Work_location> pre;    ///< per target vertex: its preimage on the source, F^-1(v)
  std::size_t n_flipped = 0;         ///< faces of M_st flipped against the target
  double max_e = 0, l2_e = 0, max_chord = 0; ///< largest and root-mean-square e(v), largest chord deviation
  Measure_cache cache;
  double eps = 0;       ///< the tolerance ε (working coordinates)
  unsigned threads = 1; ///< threads of measure() (named parameter `number_of_threads`)
  Time_budget budget;   ///< named parameters `time_limit` and `best_effort`, checked by the long steps

  // Bookkeeping of the steps.
  std::vector<char> dirty;            ///< per source face: changed by a split of the current round
  std::vector<unsigned char> refused; ///< per target vertex: rounds its insertion was refused (up to 2)
  // State of the fold repair: whether it runs (the strict fold test, splits recorded), the folds a split may
  // add, the change in folded faces of the last acceptable() test and of the current repair, and the vertices
  // the current repair made.
  bool repairing = false;
  int fold_slack = 0;
  /// Whether flip_keeps_source() refuses a flip that makes a face of M_s thinner than source_sliver_height
  /// (the overlay's second attempt where its first one fails the strict checks: Compatible_remesher).
  bool refuse_source_slivers = false;
  mutable int fold_change = 0;
  int fold_total = 0;
  std::vector<WV> made;

  bool converged() const { return max_e <= eps && max_chord <= eps && n_flipped == 0; }

  Point_3 target_point(const Work_location& l) const { return point_at(target.m, l); }
  Kernel::Vector_3 target_normal(WF f) const {
    const auto& m = target.m;
    WH h = m.halfedge(f);
    return triangle_normal(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))));
  }
  /// Whether triangle (a, b, c) of M_st, its corners on target faces fa, fb, fc, is flipped: its normal opposes
  /// the target's at every corner (a face across a sharp crease agrees with one side of it: a chord). During
  /// the fold repair (`repairing`), a corner on an edge or at a vertex of the target counts as opposing if any
  /// target face through it does, as an independent check with closest points may pick any of them.
  bool flipped(const Point_3& a, WF fa, const Point_3& b, WF fb, const Point_3& c,
               WF fc) const {
    const Kernel::Vector_3 n = triangle_normal(a, b, c);
    if (repairing) return opposes(n, a, fa) && opposes(n, b, fb) && opposes(n, c, fc);
    return n * target_normal(fa) < 0 && n * target_normal(fb) < 0 && n * target_normal(fc) < 0;
  }
  /// Whether normal n opposes the target's normal at point p of target face f, or at another target face
  /// that p lies on (p at a corner or on an edge of f, to within 1e-9 of the unit diagonal).
  bool opposes(const Kernel::Vector_3& n, const Point_3& p, WF f) const {
    if (n * target_normal(f) < 0) return true;
    const auto& m = target.m;
    constexpr double tol2 = 1e-18;
    for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
      const Point_3& q = m.point(m.target(h));
      if (CGAL::squared_distance(p, q) < tol2) {
        for (WF g : CGAL::faces_around_target(h, m))
          if (g != WF() && n * target_normal(g) < 0) return true;
        continue;
      }
      const WH o = m.opposite(h);
      if (!m.is_border(o) && n * target_normal(m.face(o)) < 0 &&
          CGAL::squared_distance(p, Kernel::Segment_3(m.point(m.source(h)), q)) < tol2)
        return true;
    }
    return false;
  }
  bool face_folded(WF f) const {
    const auto& m = mesh.m;
    const WH h = m.halfedge(f);
    const WV x = m.source(h), y = m.target(h), z = m.target(m.next(h));
    return flipped(pos[x], img[x].face, pos[y], img[y].face, pos[z], img[z].face);
  }
  double target_field(const std::vector<double>& f, const Work_location& l) const {
    const auto& m = target.m;
    WH h = m.halfedge(l.face);
    return l.b[0] * f[m.source(h)] + l.b[1] * f[m.target(h)] + l.b[2] * f[m.target(m.next(h))];
  }

  /// Whether moving vertex v to base location `moved` (a smoothing move) folds no face of M_st over against
  /// the target that was not folded before. If so, M_st is updated at v, current for the next vertices.
  bool accept_smoothing_move(WV v, const Base_location& moved) {
    const Work_location lv = target_locator.locate(moved);
    const Point_3 pv = target_point(lv);
    const auto& m = mesh.m;
    for (WH h : CGAL::halfedges_around_target(m.halfedge(v), m)) {
      if (m.is_border(h)) continue;
      WV a = m.target(m.next(h)), b = m.target(m.next(m.next(h)));
      if (!flipped(pos[v], img[v].face, pos[a], img[a].face, pos[b], img[b].face) &&
          flipped(pv, lv.face, pos[a], img[a].face, pos[b], img[b].face))
        return false;
    }
    img[v] = lv; // the move is accepted: keep M_st current for the next vertices
    pos[v] = pv;
    return true;
  }

  /// error of every source edge (Eq. 2) and the global figures.
  void measure() {
    const auto& ms = mesh.m;
    if (ms.has_garbage()) throw Algorithm_error("internal error: measure() on a mesh with removed elements");
    // Locating on the target is most of the cost; what the last measure() located for the same base locations
    // (vertices, and edges and faces whose corners and their locations are unchanged) is reused. Every element
    // is computed on its own (in parallel with `threads`), the sums and maxima afterwards in index order, so
    // the figures do not depend on the number of threads.
    Measure_cache& mc = cache;
    const std::size_t nv = ms.number_of_vertices();
    img.resize(nv);
    pos.resize(nv);
    mc.vertex.resize(nv);
    mc.same.assign(nv, 0);
    parallel_for(nv, threads, [&](std::size_t i) {
      const WV v{WV::size_type(i)};
      if (i < mc.valid && same_location(mc.vertex[v].loc, param[v])) {
        mc.same[v] = 1;
        if (check_due(i)) check_reused(mc.vertex[v]);
      } else {
        mc.vertex[v] = corner_at(param[v]);
      }
      img[v] = mc.vertex[v].img;
      pos[v] = mc.vertex[v].pos;
    });
    mc.valid = nv;
    // A face is unchanged if it has the same corners, in the same order, at unchanged locations.
    const std::size_t nf = ms.number_of_faces();
    mc.corners.resize(nf);
    mc.face_same.assign(nf, 0);
    for (WF f : ms.faces()) {
      const WH h = ms.halfedge(f);
      const std::array<WV, 3> c{ms.source(h), ms.target(h), ms.target(ms.next(h))};
      mc.face_same[f] = std::size_t(f) < mc.valid_faces && c == mc.corners[f] && mc.same[c[0]] && mc.same[c[1]] && mc.same[c[2]];
      mc.corners[f] = c;
    }
    // e(v) = |F' F^-1 (v) - v|: the preimage of target vertex v on the source, carried to M_st linearly.
    mesh_locator.build(param);
    const auto& mt = target.m;
    e.assign(mt.number_of_vertices(), 0.0);
    pre.resize(mt.number_of_vertices());
    parallel_for(mt.number_of_vertices(), threads, [&](std::size_t i) {
      const WV v{WV::size_type(i)};
      const Work_location& l = pre[v] = mesh_locator.locate(target_param[v]);
      WH h = ms.halfedge(l.face);
      const Point_3 &a = pos[ms.source(h)], &b = pos[ms.target(h)], &c = pos[ms.target(ms.next(h))];
      const Point_3 q = barycentric_point(a, b, c, l.b);
      e[v] = std::sqrt(CGAL::squared_distance(q, mt.point(v)));
    });
    max_e = 0;
    double sum2 = 0;
    for (WV v : mt.vertices()) {
      max_e = std::max(max_e, e[v]);
      sum2 += e[v] * e[v];
    }
    l2_e = std::sqrt(sum2 / double(std::max<std::size_t>(1, mt.number_of_vertices())));
    // Gaussian smoothing: each vertex averaged with its neighbours.
    es.assign(mt.number_of_vertices(), 0.0);
    for (WV v : mt.vertices()) {
      double s = e[v], n = 1;
      for (WV w : CGAL::vertices_around_target(mt.halfedge(v), mt)) s += e[w], n += 1;
      es[v] = s / n;
    }
    // Eq. 2 per source edge, with the chord deviation of M_st's edge from the target at the midpoint (the
    // other side of the Hausdorff distance, which e(v) at target vertices alone does not see).
    const std::size_t ne = ms.number_of_edges();
    edge_error.assign(ne, 0.0);
    edge_chord.assign(ne, 0.0);
    mc.edge.resize(ne);
    mc.mid.resize(ne);
    parallel_for(ne, threads, [&](std::size_t i) {
      const WE ed{WE::size_type(i)};
      WH h = ms.halfedge(ed);
      WV u = ms.source(h), v = ms.target(h);
      // param.between() interpolates in the face of h: the same face unchanged gives the same point.
      const std::array<std::size_t, 3> key{std::size_t(u), std::size_t(v), std::size_t(ms.face(h))};
      if (!(i < mc.valid_edges && mc.edge[ed] == key && mc.face_same[ms.face(h)])) {
        mc.edge[ed] = key;
        mc.mid[ed] = corner_at(param.between(u, v, 0.5));
      } else if (check_due(i + 1)) {
        check_reused(mc.mid[ed]);
      }
      const Work_location& lm = mc.mid[ed].img;
      const double chord = std::sqrt(CGAL::squared_distance(CGAL::midpoint(pos[u], pos[v]), mc.mid[ed].pos));
      edge_chord[ed] = chord;
      const double eu = target_field(es, img[u]), ev = target_field(es, img[v]);
      const double em = std::max(target_field(es, lm), chord);
      edge_error[ed] = 0.5 * (0.5 * (eu + ev) + em);
    });
    max_chord = 0;
    for (double c : edge_chord) max_chord = std::max(max_chord, c);
    // Per face of M_st: the chord deviation at the centroid (reported), and whether the face is flipped: its
    // normal opposes the target's under each corner and under the centroid.
    face_chord.assign(nf, 0.0);
    mc.centroid.resize(nf);
    folded.assign(nf, 0);
    parallel_for(nf, threads, [&](std::size_t i) {
      const WF f{WF::size_type(i)};
      WH h = ms.halfedge(f);
      const WV x = ms.source(h), y = ms.target(h), z = ms.target(ms.next(h));
      const Point_3 &a = pos[x], &b = pos[y], &c = pos[z];
      if (!mc.face_same[f]) {
        mc.centroid[f] = corner_at(param.at(f, {1.0 / 3, 1.0 / 3, 1.0 / 3}));
      } else if (check_due(i + 2)) {
        check_reused(mc.centroid[f]);
      }
      face_chord[f] = std::sqrt(CGAL::squared_distance(CGAL::centroid(a, b, c), mc.centroid[f].pos));
      folded[i] = flipped(a, img[x].face, b, img[y].face, c, img[z].face) &&
                  triangle_normal(a, b, c) * target_normal(mc.centroid[f].img.face) < 0;
    });
    n_flipped = 0;
    for (std::size_t i = 0; i < nf; ++i) {
      max_chord = std::max(max_chord, face_chord[i]);
      n_flipped += folded[i];
    }
    mc.valid_edges = ne;
    mc.valid_faces = nf;
  }
  static bool same_location(const Base_location& a, const Base_location& b) { return a.tri == b.tri && a.b == b.b; }
  /// With assertions on (the tests' builds), the reused locations of one index in 61 are located afresh and
  /// must agree exactly: the reuse in measure() must never change a figure.
  static bool check_due(std::size_t index) {
#ifndef NDEBUG
    return index % 61 == 0;
#else
    (void)index;
    return false;
#endif
  }
  /// `kept` must be what corner_at() gives for its base location now.
  void check_reused(const Corner& kept) const {
    const Work_location fresh = target_locator.locate(kept.loc);
    if (fresh.face != kept.img.face || fresh.b != kept.img.b)
      throw Algorithm_error("internal error: measure() reused a stale location on the target");
  }

  Corner corner(WV v) const { return {param[v], img[v], pos[v]}; }
  Corner corner_at(const Base_location& w) const {
    const Work_location l = target_locator.locate(w);
    return {w, l, target_point(l)};
  }
  /// Whether replacing faces `before` by `after` keeps the parameterization one-to-one (every new face
  /// positively oriented over the base mesh, exact test) and folds no more faces of M_st against the target
  /// (at most `fold_slack` more, during the fold repair). Leaves the change in folded faces in `fold_change`.
  template <std::size_t N, std::size_t M>
  bool acceptable(const std::array<Face_plan, N>& before, const std::array<Face_plan, M>& after) const {
    const Base_mesh& B = *param.base;
    for (const Face_plan& f : after)
      if (B.triangle_orientation(f[0]->loc, f[1]->loc, f[2]->loc) != CGAL::POSITIVE) return false;
    auto folds = [&](const Face_plan& f) {
      return int(flipped(f[0]->pos, f[0]->img.face, f[1]->pos, f[1]->img.face, f[2]->pos, f[2]->img.face));
    };
    int nb = 0, na = 0;
    for (const Face_plan& f : before) nb += folds(f);
    for (const Face_plan& f : after) na += folds(f);
    fold_change = na - nb;
    return na <= nb + fold_slack;
  }
  /// Whether a new vertex with barycentrics `r` in input face o (w.r.t. the input face's corners), joined to
  /// each edge (p, q) of `rim` (in the order of the face it replaces), makes faces (p, q, new) that are
  /// oriented in o's barycentric plane as `side`, the replaced face's orientation there (exact tests,
  /// barycentric_orientation()). Interpolating a new vertex's coordinates in a face that is a sliver on the
  /// source can round it onto an edge or a corner of that face, or past it: a face with no area, or folded,
  /// on the source-shaped mesh (its points would no longer be the source's surface one to one).
  template <std::size_t N>
  bool keeps_source_tiling(int o, const std::array<double, 3>& r, const std::array<std::array<WV, 2>, N>& rim,
                           CGAL::Orientation side) const {
    if (side == CGAL::COLLINEAR) return false;
    for (const auto& e : rim) {
      std::array<double, 3> rp, rq;
      if (!mesh.rep_in(e[0], o, rp) || !mesh.rep_in(e[1], o, rq) || barycentric_orientation(rp, rq, r) != side)
        return false;
    }
    return true;
  }
  /// The orientation of face (a, b, c) in input face o's barycentric plane (COLLINEAR if a corner is not on o).
  CGAL::Orientation source_orientation(int o, WV a, WV b, WV c) const {
    std::array<double, 3> ra, rb, rc;
    if (!mesh.rep_in(a, o, ra) || !mesh.rep_in(b, o, rb) || !mesh.rep_in(c, o, rc)) return CGAL::COLLINEAR;
    return barycentric_orientation(ra, rb, rc);
  }
  /// Whether splitting edge (u, v) at t, x and y the corners opposite it, keeps both of its faces' halves
  /// tiling them on the source (keeps_source_tiling()), with the new vertex's barycentrics as split_edge()
  /// computes them (Layout_mesh::split_rep()).
  bool split_keeps_source(WV u, WV v, WV x, WV y, double t) const {
    const auto& m = mesh.m;
    const WH h = m.halfedge(u, v);
    const int oa = mesh.forig[m.face(h)], ob = mesh.forig[m.face(m.opposite(h))];
    int o;
    std::array<double, 3> r;
    if (!mesh.split_rep(u, v, t, o, r)) return false;
    const auto& tri = mesh.orig_tri;
    std::array<double, 3> ra = r, rb = r;
    if (oa != o && !reexpress_barycentric(tri[o], r, tri[oa], ra)) return false;
    if (ob != o && !reexpress_barycentric(tri[o], r, tri[ob], rb)) return false;
    return keeps_source_tiling(oa, ra, std::array<std::array<WV, 2>, 2>{{{{v, x}}, {{x, u}}}}, source_orientation(oa, u, v, x)) &&
           keeps_source_tiling(ob, rb, std::array<std::array<WV, 2>, 2>{{{{u, y}}, {{y, v}}}}, source_orientation(ob, v, u, y));
  }
  /// Whether inserting a vertex at barycentrics b of face f keeps its three new faces tiling f on the source
  /// (keeps_source_tiling()), with the new vertex's barycentrics as split_face() computes them
  /// (Layout_mesh::insert_rep()).
  bool insert_keeps_source(WF f, const std::array<double, 3>& b) const {
    const auto& m = mesh.m;
    const WH h = m.halfedge(f);
    const WV vs[3] = {m.source(h), m.target(h), m.target(m.next(h))};
    const int o = mesh.forig[f];
    std::array<double, 3> r;
    return mesh.insert_rep(f, b, r) &&
           keeps_source_tiling(o, r, std::array<std::array<WV, 2>, 3>{{{{vs[0], vs[1]}}, {{vs[1], vs[2]}}, {{vs[2], vs[0]}}}},
                               source_orientation(o, vs[0], vs[1], vs[2]));
  }
  /// Adds the new vertex of a split (the mesh already split) with its planned corner.
  void commit(WV nw, const Corner& c) {
    if (std::size_t(nw) != param.loc.size()) throw Algorithm_error("internal error: split vertex out of order");
    param.loc.push_back(c.loc);
    img.push_back(c.img);
    pos.push_back(c.pos);
  }
  /// Marks the faces next to edge (u, v) as changed in this round.
  void touch(WV u, WV v) {
    const auto& m = mesh.m;
    WH h = m.halfedge(u, v);
    for (WH g : {h, m.opposite(h)})
      if (std::size_t(m.face(g)) < dirty.size()) dirty[m.face(g)] = 1;
  }
  bool is_dirty(WF f) const { return std::size_t(f) >= dirty.size() || dirty[f]; }

  /// Splits edge (u, v) of the source at parameter t, on the source and in its parameterization, if the four
  /// new faces stay positively oriented over the base mesh (exact test) and M_st gains no fold. Returns
  /// whether it split. `at`, if given, is the new vertex's location over the base mesh, instead of the one
  /// interpolated at t (the overlay's, for a target vertex: Target_overlay::place()).
  bool split(WV u, WV v, double t, const Base_location* at = nullptr) {
    const auto& m = mesh.m;
    WH h = m.halfedge(u, v);
    const WV x = m.target(m.next(h)), y = m.target(m.next(m.opposite(h)));
    const Corner cu = corner(u), cv = corner(v), cx = corner(x), cy = corner(y),
                 cw = corner_at(at ? *at : param.between(u, v, t));
    if (!split_keeps_source(u, v, x, y, t)) return false;
    if (!acceptable(std::array<Face_plan, 2>{{{&cu, &cv, &cx}, {&cv, &cu, &cy}}},
                    std::array<Face_plan, 4>{{{&cu, &cw, &cx}, {&cw, &cv, &cx}, {&cv, &cw, &cy}, {&cw, &cu, &cy}}}))
      return false;
    touch(u, v);
    const WV w = mesh.split_edge(u, v, t);
    commit(w, cw);
    if (repairing) fold_total += fold_change, made.push_back(w);
    return true;
  }

  /// Whether edge (u, v) of halfedge h can be flipped into (x, y), x and y its opposite corners, keeping the
  /// source's surface and the parameterization one-to-one: both faces lie in one input face (so the four
  /// vertices are coplanar on the source), the edge is on no layout path, both new faces are positively
  /// oriented in that input face's plane (exact test on the vertices' barycentric coordinates there: the
  /// quadrilateral is strictly convex) and over the base mesh (exact test).
  bool flip_keeps_source(WH h) const {
    const auto& m = mesh.m;
    const WH o = m.opposite(h);
    if (m.is_border(h) || m.is_border(o) || mesh.epath[m.edge(h)] != no_path) return false;
    const int orig = mesh.forig[m.face(h)];
    if (orig < 0 || mesh.forig[m.face(o)] != orig) return false;
    const WV u = m.source(h), v = m.target(h), x = m.target(m.next(h)), y = m.target(m.next(o));
    if (x == y || m.halfedge(x, y) != WH()) return false;
    // u, v, x, y in the input face's barycentric coordinates, oriented by barycentric_orientation() (which
    // needs no coordinate sum to be 1: interpolated coordinates are off 1 by rounding, and in a sliver that
    // rounding can decide a 2D test on two of them).
    std::array<std::array<double, 3>, 4> q;
    const WV vs[4] = {u, v, x, y};
    for (int i = 0; i < 4; ++i)
      if (!mesh.rep_in(vs[i], orig, q[i])) return false;
    const CGAL::Orientation side = barycentric_orientation(q[0], q[1], q[2]);
    if (side == CGAL::COLLINEAR || barycentric_orientation(q[1], q[0], q[3]) != side ||
        barycentric_orientation(q[0], q[3], q[2]) != side || barycentric_orientation(q[1], q[2], q[3]) != side)
      return false;
    if (refuse_source_slivers && (source_sliver(u, y, x) || source_sliver(v, x, y))) return false;
    const Base_mesh& B = *param.base;
    return B.triangle_orientation(param[u], param[y], param[x]) == CGAL::POSITIVE &&
           B.triangle_orientation(param[v], param[x], param[y]) == CGAL::POSITIVE;
  }

  /// Whether triangle (a, b, c) of M_s is a sliver on the source (source_sliver_triangle()).
  bool source_sliver(WV a, WV b, WV c) const {
    const auto& m = mesh.m;
    return source_sliver_triangle(m.point(a), m.point(b), m.point(c));
  }

  /// Removes face f if it is a zipper: a face of M_s whose corners lie on one line of the source (collinear in
  /// its input face, barycentric_orientation(), exact), one strictly between the other two, so that it has no
  /// area on the source although its image on M_st has. The overlay makes such faces where three of its vertices
  /// lie on one source edge that crosses a patch border (there the edge is not straight over the base mesh).
  /// The edge opposite the middle corner m is flipped into (m, x), x the corner beyond it: the two new faces
  /// tile the face beyond, on the source (m lies on its edge), so the source's surface is kept. Only if that
  /// edge is on no layout path, both new faces are positively oriented in the input face beyond (exact) and over
  /// the base mesh, M_st gains at most fold_slack folds (acceptable()) and the new faces follow the target within ε/2
  /// (edge_faces_follow_target()). Returns whether it flipped.
  bool flip_zipper(WF f) {
    auto& m = mesh.m;
    const int orig = mesh.forig[f];
    if (orig < 0) return false;
    const WH h0 = m.halfedge(f);
    const std::array<WV, 3> c{m.source(h0), m.target(h0), m.target(m.next(h0))};
    std::array<std::array<double, 3>, 3> q;
    for (int i = 0; i < 3; ++i)
      if (!mesh.rep_in(c[i], orig, q[i])) return false;
    if (barycentric_orientation(q[0], q[1], q[2]) != CGAL::COLLINEAR) return false;
    // The middle corner: strictly between the other two (normalized coordinates; ties leave the face alone).
    int k = 0;
    auto normalized = [&](int i) {
      const double s = q[i][0] + q[i][1] + q[i][2];
      return Kernel::Point_2(q[i][1] / s, q[i][2] / s);
    };
    while (k < 3 && !CGAL::collinear_are_strictly_ordered_along_line(normalized((k + 1) % 3), normalized(k), normalized((k + 2) % 3))) ++k;
    if (k == 3) return false; // two corners at one point of the source: a needle, not a zipper
    const WV mid = c[k], a = c[(k + 1) % 3], b = c[(k + 2) % 3];
    const WH h = m.halfedge(a, b), o = m.opposite(h);
    if (m.is_border(o) || mesh.epath[m.edge(h)] != no_path) return false;
    const WV x = m.target(m.next(o));
    if (x == mid || m.halfedge(mid, x) != WH()) return false;
    const int beyond = mesh.forig[m.face(o)];
    if (beyond < 0) return false;
    std::array<std::array<double, 3>, 4> r; // a, b, mid, x in the input face beyond
    const WV vs[4] = {a, b, mid, x};
    for (int i = 0; i < 4; ++i)
      if (!mesh.rep_in(vs[i], beyond, r[i])) return false;
    const CGAL::Orientation side = barycentric_orientation(r[1], r[0], r[3]); // the face beyond: (b, a, x)
    if (side == CGAL::COLLINEAR || barycentric_orientation(r[0], r[3], r[2]) != side ||
        barycentric_orientation(r[1], r[2], r[3]) != side)
      return false;
    if (!flip_if_target_follows(h)) return false;
    mesh.forig[m.face(h)] = mesh.forig[m.face(m.opposite(h))] = beyond;
    return true;
  }

  /// Whether faces (a, b, c) and (b, a, d) of M_st lie within `lim` of the target: the midpoint of (a, b) and
  /// both centroids, each against F of the same source point.
  bool edge_faces_follow_target(const Corner& a, const Corner& b, const Corner& c, const Corner& d, double lim) const {
    const Base_mesh& B = *param.base;
    const double lim2 = lim * lim;
    Base_location w;
    if (!B.interpolate({&a.loc, &b.loc, &c.loc}, {0.5, 0.5, 0.0}, w) ||
        CGAL::squared_distance(CGAL::midpoint(a.pos, b.pos), corner_at(w).pos) > lim2)
      return false;
    for (const Corner* k : {&c, &d})
      if (!B.interpolate({&a.loc, &b.loc, &k->loc}, {1.0 / 3, 1.0 / 3, 1.0 / 3}, w) ||
          CGAL::squared_distance(CGAL::centroid(a.pos, b.pos, k->pos), corner_at(w).pos) > lim2)
        return false;
    return true;
  }

  /// Flips edge (u, v) of halfedge h into (x, y) where flip_keeps_source(h), M_st gains no fold (acceptable())
  /// and the new faces follow the target within ε/2 (edge_faces_follow_target()), so that the flip brings no
  /// part of the output farther from the target. No vertex moves and none is added: F is kept at every vertex.
  /// Returns whether it flipped.
  bool flip(WH h) { return flip_keeps_source(h) && flip_if_target_follows(h); }

  /// The part of an edge flip that M_st judges: flips edge (u, v) of halfedge h into (x, y), x and y its
  /// opposite corners, if M_st gains no fold (acceptable()) and the new faces follow the target within ε/2
  /// (edge_faces_follow_target()). Returns whether it flipped.
  bool flip_if_target_follows(WH h) {
    auto& m = mesh.m;
    const WH o = m.opposite(h);
    const WV u = m.source(h), v = m.target(h), x = m.target(m.next(h)), y = m.target(m.next(o));
    const Corner cu = corner(u), cv = corner(v), cx = corner(x), cy = corner(y);
    if (!acceptable(std::array<Face_plan, 2>{{{&cu, &cv, &cx}, {&cv, &cu, &cy}}},
                    std::array<Face_plan, 2>{{{&cu, &cy, &cx}, {&cv, &cx, &cy}}}))
      return false;
    if (!edge_faces_follow_target(cx, cy, cu, cv, 0.5 * eps)) return false;
    touch(u, v);
    CGAL::Euler::flip_edge(h, m);
    return true;
  }

  /// Inserts a vertex at the point of source face f with barycentrics b (in f's halfedge order) by two edge
  /// splits: edge (a, c) opposite corner k at the point s where the line from that corner through the point
  /// meets it, then edge (k, s) at the point. The new vertices lie in the source face, so the source geometry
  /// is kept; the image of the point is F of it, so a target vertex whose preimage it is becomes a vertex of
  /// M_st. Tries the three corners, the one opposite the longest edge of M_st first. Returns whether it did.
  /// `at`, if given, is the point's location over the base mesh, instead of the one interpolated at b.
  bool insert(WF f, const std::array<double, 3>& b, const Base_location* at = nullptr) {
    const auto& m = mesh.m;
    WH h0 = m.halfedge(f);
    const WV vs[3] = {m.source(h0), m.target(h0), m.target(m.next(h0))};
    const Corner cp = corner_at(at ? *at : param.at(f, b));
    const int o = mesh.forig[f];
    if (insert_keeps_source(f, b)) {
      const Corner c0 = corner(vs[0]), c1 = corner(vs[1]), c2 = corner(vs[2]);
      if (acceptable(std::array<Face_plan, 1>{{{&c0, &c1, &c2}}},
                     std::array<Face_plan, 3>{{{&c0, &c1, &cp}, {&c1, &c2, &cp}, {&c2, &c0, &cp}}})) {
        if (std::size_t(f) < dirty.size()) dirty[f] = 1;
        commit(mesh.split_face(f, b), cp);
        return true;
      }
    }
    std::array<int, 3> order{{0, 1, 2}};
    auto opposite_length = [&](int k) { return CGAL::squared_distance(pos[vs[(k + 1) % 3]], pos[vs[(k + 2) % 3]]); };
    std::sort(order.begin(), order.end(), [&](int i, int j) { return opposite_length(i) > opposite_length(j); });
    for (int k : order) {
      const int i = (k + 1) % 3, j = (k + 2) % 3; // the edge (vs[i], vs[j]) is split at s
      const double bij = b[i] + b[j];
      if (!(bij > 1e-9) || !(b[k] > 1e-9)) continue; // the point is a corner or on the split edge
      const double t = b[j] / bij;      // s = (1 - t) vs[i] + t vs[j]
      const double t2 = bij;            // point = (1 - t2) vs[k] + t2 s
      const WV a = vs[i], c = vs[j], kk = vs[k];
      WH h = m.halfedge(a, c);
      const WV y = m.target(m.next(m.opposite(h)));
      std::array<double, 3> bs{{0, 0, 0}};
      bs[i] = 1 - t, bs[j] = t;
      {
        // On the source, as split_edge() computes them: s on (a, c) (in o: both are corners of f), then the
        // point on (kk, s), in o.
        int os;
        std::array<double, 3> rs, rk, rp, ra, rc;
        if (!split_keeps_source(a, c, kk, y, t) || !mesh.split_rep(a, c, t, os, rs) || os != o ||
            !mesh.rep_in(kk, o, rk) || !mesh.rep_in(a, o, ra) || !mesh.rep_in(c, o, rc))
          continue;
        for (int q = 0; q < 3; ++q) rp[q] = (1 - t2) * rk[q] + t2 * rs[q];
        const CGAL::Orientation side = barycentric_orientation(ra, rc, rk);
        if (barycentric_orientation(ra, rs, rp) != side || barycentric_orientation(ra, rp, rk) != side ||
            barycentric_orientation(rs, rc, rp) != side || barycentric_orientation(rp, rc, rk) != side)
          continue;
      }
      const Corner ca = corner(a), cc = corner(c), ck = corner(kk), cy = corner(y);
      const Corner cs = corner_at(param.at(f, bs));
      if (!acceptable(std::array<Face_plan, 2>{{{&ca, &cc, &ck}, {&cc, &ca, &cy}}},
                      std::array<Face_plan, 6>{{{&ca, &cs, &cp}, {&ca, &cp, &ck}, {&cs, &cc, &cp}, {&cp, &cc, &ck},
                                                 {&cc, &cs, &cy}, {&cs, &ca, &cy}}}))
        continue;
      touch(a, c);
      const WV s = mesh.split_edge(a, c, t);
      commit(s, cs);
      commit(mesh.split_edge(kk, s, t2), cp);
      return true;
    }
    return false;
  }

  /// split() at the midpoint of (u, v), or where that is refused, at the first of the next `points` - 1 of
  /// t = 0.375, 0.625, 0.25, 0.75, 0.125, 0.875 that is accepted. Returns whether it split.
  bool split_near_middle(WV u, WV v, int points) {
    static constexpr double ts[] = {0.5, 0.375, 0.625, 0.25, 0.75, 0.125, 0.875};
    for (int i = 0; i < points && i < 7; ++i)
      if (split(u, v, ts[i])) return true;
    return false;
  }

  /// The longest edge of face f of M_st.
  WH longest_edge(WF f) const {
    const auto& m = mesh.m;
    WH best = m.halfedge(f);
    double bl = -1;
    for (WH g : CGAL::halfedges_around_face(m.halfedge(f), m)) {
      const double len = CGAL::squared_distance(pos[m.source(g)], pos[m.target(g)]);
      if (len > bl) bl = len, best = g;
    }
    return best;
  }

  /// What a repair transaction restores: a repair appends vertices (with their records), changes faces of the
  /// source and moves only vertices it made, so undoing it restores the mesh and truncates the rest.
  struct Checkpoint {
    Work_mesh m;
    std::size_t vertices, splits;
    std::vector<char> dirty;
  };
  Checkpoint checkpoint() const { return {mesh.m, mesh.m.number_of_vertices(), mesh.splits.size(), dirty}; }
  void rollback(const Checkpoint& cp) {
    mesh.m = cp.m;
    mesh.bind_property_maps();
    mesh.vrep.resize(std::min(mesh.vrep.size(), cp.vertices));
    if (mesh.desc.size() > cp.vertices) mesh.desc.resize(cp.vertices);
    mesh.splits.resize(cp.splits);
    param.loc.resize(cp.vertices);
    img.resize(cp.vertices);
    pos.resize(cp.vertices);
    dirty = cp.dirty;
  }

  /// The parameterization and what measure() cached for it, to undo a smoothing round.
  struct Locations {
    std::vector<Base_location> loc;
    Measure_cache cache;
  };
  Locations locations() const { return {param.loc, cache}; }
  void restore(Locations&& l) {
    param.loc = std::move(l.loc);
    cache = std::move(l.cache);
  }

  /// M_st and its fold figures, to restore after an untangling that is not kept.
  struct Images {
    std::vector<Work_location> img;
    std::vector<Point_3> pos;
    std::vector<char> folded;
    std::size_t n_flipped;
  };
  Images images() const { return {img, pos, folded, n_flipped}; }
  void restore(const Images& i) { img = i.img, pos = i.pos, folded = i.folded, n_flipped = i.n_flipped; }
  /// A flag per vertex: whether it is a corner of a face in `folded`.
  std::vector<char> corners_of_folded_faces() const {
    const auto& m = mesh.m;
    std::vector<char> hard(m.number_of_vertices(), 0);
    for (WF f : m.faces())
      if (folded[f])
        for (WV v : CGAL::vertices_around_face(m.halfedge(f), m)) hard[v] = 1;
    return hard;
  }


  /// The result meshes: the remeshed mesh's faces and points, and M_st's points carried to the target as given.
  Remesh_outputs outputs() const {
    const auto& m = mesh.m;
    Remesh_outputs out;
    for (WF f : m.faces()) {
      WH h = m.halfedge(f);
      std::array<std::size_t, 3> t{std::size_t(m.source(h)), std::size_t(m.target(h)), std::size_t(m.target(m.next(h)))};
      if (mesh.reversed) std::swap(t[1], t[2]);
      out.faces.push_back(t);
      Input_face_location l;
      const int o = mesh.forig[f];
      l.face = std::size_t(o);
      l.vertices = mesh.orig_tri[std::size_t(o)];
      for (int c = 0; c < 3; ++c)
        if (!mesh.rep_in(WV(WV::size_type(t[c])), o, l.corners[c]))
          throw Algorithm_error("internal error: remeshed face outside its input face");
      out.source_faces.push_back(l);
    }
    for (WV v : m.vertices()) {
      out.source_points.push_back(mesh.input_position(v));
      const Input_location l = target_to_input(img[v]);
      out.target_locations.push_back(l);
      std::array<double, 3> q{{0, 0, 0}};
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) q[k] += l.b[i] * target.input_points[target.orig_tri[l.face][i]][k];
      out.target_points.push_back(q);
      out.vertex_error.push_back(100 * target_field(es, img[v]));
    }
    return out;
  }
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_REMESH_STATE_H

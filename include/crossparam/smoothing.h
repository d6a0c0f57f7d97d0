// SPDX-License-Identifier: GPL-3.0-or-later
// Local smoothing of a parameterization over the base mesh (Kraevoy & Sheffer 2004, §4.2), with the edge
// weights as a policy: mean-value weights of the original mesh for the shape-preserving map (§4.2), the
// error-driven weights of §5.2 for adaptive remeshing. The same code serves both.
//
// Each vertex is relocated in the 4-triangle chart of its base triangle (the triangle and its three neighbours
// unfolded around it, internal/base_domain.h) to the weighted average of its neighbours. A move is rejected if
// any incident triangle would leave a chart of two adjacent base triangles (the adjacency constraint) or would
// not be positively oriented there (exact predicate), so a one-to-one map stays one-to-one. Vertices migrate
// between base triangles freely under that rule; features never move.
#ifndef CROSSPARAM_SMOOTHING_H
#define CROSSPARAM_SMOOTHING_H

#include <crossparam/types.h>
#include <crossparam/internal/base_parameterization.h>

#include <vector>

namespace crossparam {

/*!
\cgalConcept SmoothingWeights

The edge weights of the local smoothing of a parameterization over the base mesh (paper §4.2): each vertex is
moved to the weighted average of its neighbours' base-domain positions, with the weight of neighbour
`target(h)` in the average for `source(h)` given by the policy. Passed with the named parameter
`crossparam::parameters::smoothing_weights` to `Cross_parameterization`; copied once per mesh.

Everything a model sees is public (types.h): the refined mesh of one side in working coordinates (the input
translated and scaled to a unit bounding-box diagonal, faces oriented outward; its vertex i is input vertex i for
the input's vertices, then the split vertices) and its halfedges. The geometry is the mesh's 3D geometry,
which smoothing never changes: only the vertices' base locations move.

\cgalHasModel `crossparam::Mean_value_weights` (the default)

Required types: none. A model is `CopyConstructible`: each mesh is smoothed with its own copy of the policy.

Required member functions (`w` a model, `cw` a const one, `m` a `const crossparam::Refined_mesh&`,
`h` a `crossparam::Refined_halfedge` of `m`):
- `w.prepare(m)`: called on each mesh's copy once, before the first smoothing pass, with that mesh (the source's
  copy, then the target's). Computes whatever the weights need; `m` outlives the smoothing. With
  `protrusion_features` (default on), a first map on copies of the meshes prepares copies of its own too.
- `double cw(h)`: the weight of vertex `target(h, m)` in the average for vertex `source(h, m)`; must be
  positive and finite. Called during every pass, for each outgoing halfedge of each vertex that is not a
  feature, from the pass's thread (one thread per mesh); it must not modify the model.
*/

/*!
\cgalConcept RemeshingWeights

\cgalRefines `SmoothingWeights`

The edge weights of the adaptive smoothing of compatible remeshing (paper §5.2): like `SmoothingWeights`, but
the mesh changes (the remeshing splits edges of the source's refined mesh) and the weights follow the
approximation error. Passed with `crossparam::parameters::remeshing_weights` to `Compatible_remesher`.

\cgalHasModel `crossparam::Error_driven_weights` (the default, compatible_remeshing.h)

Required member functions, in addition to those of `SmoothingWeights` (`m`: the source's refined mesh as the
remeshing has refined it so far, working coordinates; `e` a `const std::vector<double>&`):
- `w.prepare(m)`: called before the first round and again after every round that changed the connectivity
  (edge splits add vertices, edges and faces at the end of the index ranges; none is removed);
- `w.update(m, e)`: called before every smoothing round with the current error of every edge, `e[i]` the error
  of edge `Refined_edge(i)` (in units of the unit bounding-box diagonal); `e.size() == m.number_of_edges()`;
- `double cw(h)`: as in `SmoothingWeights`, for the current mesh.
*/

/// Options of the local smoothing; every field has a default.
struct Smoothing_options {
  unsigned max_iterations = 200; ///< passes over all vertices at most
  /// Stop when no vertex moved farther than this in a pass, in units of a base-triangle edge.
  double tolerance = 1e-4;
};

/// What a smoothing run did.
struct Smoothing_report {
  unsigned iterations = 0;
  double last_max_move = 0;     ///< largest move in the last pass, in base-edge units
  std::size_t moves = 0;        ///< accepted moves
  std::size_t rejected = 0;     ///< moves rejected by the flip or adjacency test
  std::size_t migrations = 0;   ///< accepted moves into another base triangle
};

/// \cgalModels `SmoothingWeights`
///
/// Weights policy of the shape-preserving smoothing (§4.2): mean-value weights computed once on the 3D
/// geometry of the refined mesh (Floater 2003): for h = (i -> j), (tan(a/2) + tan(b/2)) / |x_j - x_i| with a, b
/// the angles at i of the two faces of the edge; 1 / (mean edge length) where that is undefined (coincident
/// points), so every weight is positive.
class Mean_value_weights {
public:
  /// Computes the weight of every halfedge of `m`.
  void prepare(const Refined_mesh& m) {
    const double fallback = internal::mean_value_fallback(m);
    w_.assign(m.number_of_halfedges(), 0.0);
    for (auto h : m.halfedges()) w_[h] = internal::mean_value_weight(m, h, fallback);
  }
  /// The weight of target(h) in the average for source(h).
  double operator()(Refined_halfedge h) const { return w_[h]; }

private:
  std::vector<double> w_;
};

namespace internal {

/// Acceptance policy of the local smoother that accepts every move the exact flip test allows.
struct Accept_all {
  bool operator()(WV, const Base_location&) const { return true; }
};

/// The local smoother of §4.2 over one mesh's base parameterization. `Accept` may veto a move that is valid
/// over the base mesh (the remeshing uses it to keep the target-shaped mesh from folding over in 3D); it is
/// called with the vertex and its proposed location once the exact test has passed.
template <class Weights, class Accept = Accept_all>
class Local_smoother {
public:
  Local_smoother(Base_parameterization& p, const Weights& w, Accept accept = Accept()) : p_(p), w_(w), accept_(accept) {}

  /// One pass over all vertices. Returns the largest move (base-edge units).
  double pass(Smoothing_report& r) {
    const Work_mesh& m = p_.mesh->m;
    const Base_mesh& B = *p_.base;
    double max_move = 0;
    std::vector<int> centers;
    std::vector<Point_2> nbr;
    std::vector<double> wts;
    for (WV v : m.vertices()) {
      if (p_.mesh->vfeature[v] != no_feature) continue;
      B.containing(p_[v], centers);
      for (int c : centers) {
        // Neighbours in the 4-triangle chart of c.
        nbr.clear();
        wts.clear();
        bool ok = true;
        for (WH h : CGAL::halfedges_around_source(v, m)) {
          Point_2 q;
          if (!B.chart_point(c, p_[m.target(h)], q)) {
            ok = false;
            break;
          }
          nbr.push_back(q);
          wts.push_back(w_(h));
        }
        if (!ok) continue;
        double sx = 0, sy = 0, sw = 0;
        for (std::size_t i = 0; i < nbr.size(); ++i) {
          sx += wts[i] * nbr[i].x();
          sy += wts[i] * nbr[i].y();
          sw += wts[i];
        }
        if (!(sw > 0)) break;
        Point_2 target(sx / sw, sy / sw), old;
        B.chart_point(c, p_[v], old);
        Base_location moved;
        if (!B.locate_in_chart(c, target, moved)) {
          ++r.rejected;
          break;
        }
        const Base_location before = p_[v];
        p_[v] = moved;
        if (!p_.star_positive(v) || !accept_(v, moved)) {
          p_[v] = before;
          ++r.rejected;
          break;
        }
        double d = std::sqrt(CGAL::squared_distance(old, target));
        max_move = std::max(max_move, d);
        ++r.moves;
        if (moved.tri != before.tri) ++r.migrations;
        break;
      }
    }
    return max_move;
  }

  Smoothing_report run(const Smoothing_options& o) {
    Smoothing_report r;
    for (unsigned it = 0; it < o.max_iterations; ++it) {
      r.last_max_move = pass(r);
      r.iterations = it + 1;
      if (r.last_max_move < o.tolerance) break;
    }
    return r;
  }

private:
  Base_parameterization& p_;
  const Weights& w_;
  Accept accept_;
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_SMOOTHING_H

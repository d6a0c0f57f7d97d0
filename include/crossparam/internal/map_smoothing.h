// SPDX-License-Identifier: GPL-3.0-or-later
// Smoothing of the map F itself (an addition to the paper's §4.2): the source's vertices move over the base
// domain so that F approaches a harmonic map from the source onto the target, with the source's smoothing
// weights. The paper's smoothing makes each parameterization harmonic-like onto the base domain on its own; two
// such maps composed are not harmonic from one surface to the other, and where the two meshes are laid out on
// the base domain differently (large patches, few features) F slides along the target.
//
// A pass visits the source's free vertices in index order (Gauss-Seidel). For vertex v, with y_j the images of
// its neighbours and y_v its own (exact point location on the target's parameterization), the target of the move
// is ȳ = Σ w_j y_j / Σ w_j, w_j the policy's weights on the source; the 3D displacement ȳ - y_v is projected onto
// the plane of the target face that holds y_v and pulled back into a base chart around v through the target's
// piecewise-linear parameterization in that face: δ = E (DᵀD)⁻¹ Dᵀ (ȳ - y_v), D the face's two 3D edge vectors,
// E the same edges in the chart (the Gauss-Newton step of Σ w_j |F(v) - y_j|² in that face). The move is tried at
// full, half and quarter length with the same exact tests as the paper's smoothing (every triangle around v
// keeps a canonical frame and positive orientation), so the map stays one-to-one. The target's parameterization
// does not move, so its point location stays valid throughout.
#ifndef CROSSPARAM_INTERNAL_MAP_SMOOTHING_H
#define CROSSPARAM_INTERNAL_MAP_SMOOTHING_H

#include <crossparam/smoothing.h>
#include <crossparam/internal/base_locator.h>

#include <vector>

namespace crossparam {
namespace internal {

template <class Weights>
class Map_smoother {
  using Vector_2 = Kernel::Vector_2;
  using Vector_3 = Kernel::Vector_3;

public:
  /// Step lengths tried in turn, as fractions of a vertex's step: the linearisation holds within the target
  /// face of the vertex's image, so a long step can leave the chart or fold a triangle; halving twice keeps
  /// most of those vertices moving, more halvings were not worth their exact tests.
  static constexpr double step_fractions[3] = {1.0, 0.5, 0.25};

  Map_smoother(Base_parameterization& source, const Base_parameterization& target, const Base_locator& target_locator,
               const Weights& w)
      : s_(source), t_(target), lt_(target_locator), w_(w) {}

  /// One Gauss-Seidel pass over the source's free vertices (see the header). Returns the largest move, in
  /// base-edge units.
  double pass(Smoothing_report& r) {
    const Work_mesh& ms = s_.mesh->m;
    if (image_.size() != ms.number_of_vertices()) {
      at_.resize(ms.number_of_vertices());
      image_.resize(ms.number_of_vertices());
      for (WV v : ms.vertices()) relocate(v);
    }
    double max_move = 0;
    for (WV v : ms.vertices()) {
      if (s_.mesh->vfeature[v] != no_feature) continue;
      double sw = 0;
      Vector_3 d(0, 0, 0);
      for (WH h : CGAL::halfedges_around_source(v, ms)) {
        const double w = w_(h);
        sw += w;
        d = d + w * (image_[ms.target(h)] - image_[v]);
      }
      if (!(sw > 0)) continue;
      if (move(v, d / sw, max_move, r)) {
        ++r.moves;
        relocate(v);
      } else {
        ++r.rejected;
      }
    }
    return max_move;
  }

private:
  /// Where F(v) is on the target, and the point.
  void relocate(WV v) {
    at_[v] = lt_.locate(s_[v]);
    image_[v] = point_at(t_.mesh->m, at_[v]);
  }

  /// Moves source vertex v so that its image moves by z (a vector in the plane of the target face that holds
  /// it), pulled back into a base chart around v; the exact acceptance test of the smoothing. Returns whether
  /// v moved.
  bool move(WV v, const Vector_3& z, double& max_move, Smoothing_report& r) {
    const Work_mesh& mt = t_.mesh->m;
    const Base_mesh& B = *s_.base;
    const WH ht = mt.halfedge(at_[v].face);
    const WV tv[3] = {mt.source(ht), mt.target(ht), mt.target(mt.next(ht))};
    const Vector_3 d1 = mt.point(tv[1]) - mt.point(tv[0]), d2 = mt.point(tv[2]) - mt.point(tv[0]);
    const double g11 = d1 * d1, g12 = d1 * d2, g22 = d2 * d2, det = g11 * g22 - g12 * g12;
    if (!(det > 0)) return false;
    const double r1 = d1 * z, r2 = d2 * z;
    const double s1 = (g22 * r1 - g12 * r2) / det, s2 = (g11 * r2 - g12 * r1) / det;
    B.containing(s_[v], centers_);
    for (int c : centers_) {
      Point_2 p0, q[3];
      if (!B.chart_point(c, s_[v], p0)) continue;
      bool ok = true;
      for (int k = 0; k < 3 && ok; ++k) ok = B.chart_point(c, t_[tv[k]], q[k]);
      if (!ok) continue;
      const Vector_2 step = s1 * (q[1] - q[0]) + s2 * (q[2] - q[0]);
      const Base_location before = s_[v];
      for (double f : step_fractions) {
        Base_location l;
        if (!B.locate_in_chart(c, p0 + f * step, l)) continue;
        s_[v] = l;
        if (s_.star_positive(v)) {
          if (l.tri != before.tri) ++r.migrations;
          max_move = std::max(max_move, f * std::sqrt(step.squared_length()));
          return true;
        }
        s_[v] = before;
      }
      return false;
    }
    return false;
  }

  Base_parameterization& s_;
  const Base_parameterization& t_;
  const Base_locator& lt_;
  const Weights& w_;
  std::vector<int> centers_;
  std::vector<Work_location> at_; ///< where F of every source vertex is on the target, kept current
  std::vector<Point_3> image_;    ///< and the point
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_MAP_SMOOTHING_H

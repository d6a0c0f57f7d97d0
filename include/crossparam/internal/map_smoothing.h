// SPDX-License-Identifier: GPL-3.0-or-later
// Smoothing of the map F itself (an addition to the paper's §4.2): the source's vertices move over the base
// domain so that F approaches an as-rigid-as-possible map from the source onto the target (Sorkine and Alexa,
// "As-rigid-as-possible surface modeling", 2007), with the source's smoothing weights. The paper's smoothing
// makes each parameterization harmonic-like onto the base domain on its own; two such maps composed are not
// close to an isometry from one surface to the other, and where the two meshes are laid out on the base domain
// differently (large patches, few features) F slides along the target.
//
// The energy is E = Σ_v Σ_j w_vj |(y_j - y_v) - s R_v (x_j - x_v)|², x the source's points, y = F(x) their images
// on the target, w the policy's weights on the source, s = sqrt(target area / source area) the one scale between
// the two surfaces, R_v the rotation that best takes v's edges onto their images (3D Procrustes).
//
// A pass is a global step, then a local one (Sorkine and Alexa's alternation of rotations and positions, with
// the positions restricted to the target surface), each with the rotations fitted to the current map first:
// - global: the tangent displacements a_v of all free vertices' images at once, in the plane of the target face
//   that holds each (orthonormal basis T_v), minimising Σ_edges w |(y_j + T_j a_j) - (y_v + T_v a_v)
//   - s (R_v + R_j)/2 (x_j - x_v)|² (the Gauss-Newton step of E on the surface; one sparse solve, which moves
//   the low frequencies a vertex-by-vertex step is slow to move);
// - local: the free vertices in index order (Gauss-Seidel), each aiming at ȳ = Σ w_j (y_j + s (R_v + R_j)/2
//   (x_v - x_j)) / Σ w_j, the update of Sorkine and Alexa (with symmetric weights, the minimiser of E over y_v
//   with the rotations fixed).
// Every vertex's 3D displacement z (in the plane of the target face that holds y_v) is pulled back into a base
// chart around v through the target's piecewise-linear parameterization in that face: δ = C (DᵀD)⁻¹ Dᵀ z, D the
// face's two 3D edge vectors, C the same edges in the chart. The move is tried at full, half and quarter length
// with the same exact tests as the paper's smoothing (every triangle around v keeps a canonical frame and
// positive orientation), so the map stays one-to-one. The target's parameterization does not move, so its point
// location stays valid throughout.
#ifndef CROSSPARAM_INTERNAL_MAP_SMOOTHING_H
#define CROSSPARAM_INTERNAL_MAP_SMOOTHING_H

#include <crossparam/smoothing.h>
#include <crossparam/internal/base_locator.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <array>
#include <cmath>
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
  /// Added to the global step's diagonal, relative to the largest edge weight: small enough to leave the
  /// solution unchanged where the system is definite (features fixed), nonzero so that it always is.
  static constexpr double regularization = 1e-9;

  Map_smoother(Base_parameterization& source, const Base_parameterization& target, const Base_locator& target_locator,
               const Weights& w, bool global_steps = true)
      : s_(source), t_(target), lt_(target_locator), w_(w), global_(global_steps),
        scale_(std::sqrt(CGAL::Polygon_mesh_processing::area(target.mesh->m) /
                         CGAL::Polygon_mesh_processing::area(source.mesh->m))) {}

  /// One pass (see the header): a global step (unless the smoother was made without them), then a local one.
  /// Returns the largest move, in base-edge units.
  double pass(Smoothing_report& r) {
    double max_move = 0;
    if (global_) global_step(max_move, r);
    local_step(max_move, r);
    return max_move;
  }

  /// E for the current map (see the header), divided by Σ w_vj |s (x_j - x_v)|² so that it does not depend on
  /// the mesh's size: 0 for a map that is a rigid motion scaled by s.
  double energy() {
    const Work_mesh& ms = s_.mesh->m;
    fit_rotations();
    double e = 0, n = 0;
    for (WV v : ms.vertices())
      for (WH h : CGAL::halfedges_around_source(v, ms)) {
        const WV j = ms.target(h);
        const double w = w_(h);
        const Eigen::Vector3d x = scale_ * eigen(ms.point(j) - ms.point(v));
        e += w * (eigen(image_[j] - image_[v]) - rotation_[v] * x).squaredNorm();
        n += w * x.squaredNorm();
      }
    return n > 0 ? e / n : 0;
  }

private:
  static Eigen::Vector3d eigen(const Vector_3& a) { return {a.x(), a.y(), a.z()}; }

  /// s (R_v + R_j)/2 (x_j - x_v): where the edge v -> j would go under the mean of its ends' rotations, scaled.
  Eigen::Vector3d rigid_edge(WV v, WV j) const {
    const Work_mesh& ms = s_.mesh->m;
    return 0.5 * scale_ * (rotation_[v] + rotation_[j]) * eigen(ms.point(j) - ms.point(v));
  }

  /// The global step: the rotations fitted, the tangent displacements a_v of every free vertex's image (in the
  /// plane of the target face that holds it, orthonormal basis T_v) that minimise
  /// Σ_edges w |(y_j + T_j a_j) - (y_v + T_v a_v) - s (R_v + R_j)/2 (x_j - x_v)|² are solved for at once (a sparse
  /// symmetric positive definite system, w the mean of the edge's two halfedge weights), and each vertex is moved
  /// by T_v a_v with the exact test. Skipped if the factorization fails or the solution is not finite.
  void global_step(double& max_move, Smoothing_report& r) {
    const Work_mesh& ms = s_.mesh->m;
    const Work_mesh& mt = t_.mesh->m;
    fit_rotations();
    std::vector<int> index(ms.number_of_vertices(), -1);
    int n = 0;
    for (WV v : ms.vertices())
      if (s_.mesh->vfeature[v] == no_feature) index[v] = n++;
    if (n == 0) return;
    tangent_.resize(ms.number_of_vertices());
    for (WV v : ms.vertices()) {
      const WH ht = mt.halfedge(at_[v].face);
      Eigen::Vector3d a = eigen(mt.point(mt.target(ht)) - mt.point(mt.source(ht)));
      Eigen::Vector3d c = a.cross(eigen(mt.point(mt.target(mt.next(ht))) - mt.point(mt.source(ht))));
      if (!(c.norm() > 0)) {
        tangent_[v] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}; // a degenerate face: the image stays
        continue;
      }
      a.normalize();
      tangent_[v] = {a, c.normalized().cross(a)};
    }
    auto basis = [&](WV v) {
      Eigen::Matrix<double, 3, 2> t;
      t << tangent_[v][0], tangent_[v][1];
      return t;
    };
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * n);
    auto add = [&](int i, int j, const Eigen::Matrix2d& m) {
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) entries.emplace_back(2 * i + a, 2 * j + b, m(a, b));
    };
    double largest_weight = 0;
    for (WE e : ms.edges()) {
      const WH h = ms.halfedge(e);
      const WV v = ms.source(h), j = ms.target(h);
      const double w = 0.5 * (w_(h) + w_(ms.opposite(h)));
      largest_weight = std::max(largest_weight, w);
      const Eigen::Matrix<double, 3, 2> tv = basis(v), tj = basis(j);
      const Eigen::Vector3d res = eigen(image_[j] - image_[v]) - rigid_edge(v, j);
      const int iv = index[v], ij = index[j];
      if (iv >= 0) {
        add(iv, iv, w * tv.transpose() * tv);
        rhs.segment<2>(2 * iv) += w * tv.transpose() * res;
      }
      if (ij >= 0) {
        add(ij, ij, w * tj.transpose() * tj);
        rhs.segment<2>(2 * ij) -= w * tj.transpose() * res;
      }
      if (iv >= 0 && ij >= 0) {
        add(iv, ij, -w * tv.transpose() * tj);
        add(ij, iv, -w * tj.transpose() * tv);
      }
    }
    // A vanishing diagonal term keeps the matrix definite where a degenerate face left a vertex without basis.
    for (int i = 0; i < 2 * n; ++i) entries.emplace_back(i, i, regularization * largest_weight);
    Eigen::SparseMatrix<double> H(2 * n, 2 * n);
    H.setFromTriplets(entries.begin(), entries.end());
    // The matrix's pattern (the free vertices and the edges) is the same at every step: analysed once.
    if (!analysed_) {
      solver_.analyzePattern(H);
      analysed_ = true;
    }
    solver_.factorize(H);
    if (solver_.info() != Eigen::Success) return;
    const Eigen::VectorXd a = solver_.solve(rhs);
    if (solver_.info() != Eigen::Success || !a.allFinite()) return;
    for (WV v : ms.vertices()) {
      if (index[v] < 0) continue;
      const Eigen::Vector3d z = basis(v) * a.segment<2>(2 * index[v]);
      step(v, Vector_3(z(0), z(1), z(2)), max_move, r);
    }
  }

  /// The local step: the rotations fitted again, then each free vertex in index order (Gauss-Seidel) moved
  /// towards ȳ (see the header) with the exact test.
  void local_step(double& max_move, Smoothing_report& r) {
    const Work_mesh& ms = s_.mesh->m;
    fit_rotations();
    for (WV v : ms.vertices()) {
      if (s_.mesh->vfeature[v] != no_feature) continue;
      double sw = 0;
      Vector_3 d(0, 0, 0);
      for (WH h : CGAL::halfedges_around_source(v, ms)) {
        const WV j = ms.target(h);
        const double w = w_(h);
        sw += w;
        const Eigen::Vector3d rx = rigid_edge(v, j);
        d = d + w * (image_[j] - image_[v] - Vector_3(rx(0), rx(1), rx(2)));
      }
      if (sw > 0) step(v, d / sw, max_move, r);
    }
  }

  /// Locates every image the first time, then fits R_v for every vertex: the rotation R maximising
  /// Σ_j w_vj (y_j - y_v)ᵀ R (x_j - x_v), from the SVD of that covariance, its last axis turned if needed to
  /// make it a rotation rather than a reflection.
  void fit_rotations() {
    const Work_mesh& ms = s_.mesh->m;
    if (image_.size() != ms.number_of_vertices()) {
      at_.resize(ms.number_of_vertices());
      image_.resize(ms.number_of_vertices());
      rotation_.resize(ms.number_of_vertices());
      for (WV v : ms.vertices()) relocate(v);
    }
    for (WV v : ms.vertices()) {
      Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
      for (WH h : CGAL::halfedges_around_source(v, ms))
        c += w_(h) * eigen(ms.point(ms.target(h)) - ms.point(v)) * eigen(image_[ms.target(h)] - image_[v]).transpose();
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(c, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix3d u = svd.matrixU();
      if ((svd.matrixV() * u.transpose()).determinant() < 0) u.col(2) *= -1;
      rotation_[v] = svd.matrixV() * u.transpose();
    }
  }

  /// Moves v by z if the exact test allows (see move()), counted in the report; its image located again.
  void step(WV v, const Vector_3& z, double& max_move, Smoothing_report& r) {
    if (move(v, z, max_move, r)) {
      ++r.moves;
      relocate(v);
    } else {
      ++r.rejected;
    }
  }

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
  std::vector<Eigen::Matrix3d> rotation_; ///< R_v of every source vertex, fitted at the start of each step
  std::vector<std::array<Eigen::Vector3d, 2>> tangent_; ///< T_v: the plane of the target face of v's image
  bool global_;  ///< whether a pass begins with a global step
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_; ///< the global step's, its pattern analysed once
  bool analysed_ = false;
  double scale_; ///< s: the one scale between the two surfaces
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_MAP_SMOOTHING_H

// SPDX-License-Identifier: GPL-3.0-or-later
// Untangling a planar triangle mesh with some vertices held fixed: the free vertices are moved until every
// triangle is positively oriented, by minimising a barrier energy whose barrier is relaxed at first and then
// tightened (the approach of Garanzha, Kaporin, Kudryavtseva, Protais, Ray and Sokolov, "Foldover-free maps in
// 50 lines of code", 2021). Each triangle t compares its shape with a reference triangle through the Jacobian
// J of the affine map between them:
//
//     f_ε(J) = ((1 − λ) |J|² + λ (det J² + 1)) / χ(det J, ε),   χ(D, ε) = (D + √(ε² + D²)) / 2.
//
// χ is positive for every D, so the energy is finite on tangled meshes; as ε → 0 it tends to D for D > 0 and
// to 0 for D < 0, so a small ε makes inverted triangles expensive. Minimised with L-BFGS for each ε, and ε
// lowered by the schedule of the paper until no triangle is inverted.
#ifndef CROSSPARAM_INTERNAL_REMESHING_UNTANGLE_H
#define CROSSPARAM_INTERNAL_REMESHING_UNTANGLE_H

#include <crossparam/internal/time_budget.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <vector>

namespace crossparam {
namespace internal {

/// A triangle of the planar mesh: its corners (indices into the points) and the inverse of its reference
/// shape's edge matrix [b − a, c − a].
struct Untangle_triangle {
  std::array<int, 3> v;
  Eigen::Matrix2d reference_inverse;
};

/// The edge matrix [b − a, c − a] of a planar triangle.
inline Eigen::Matrix2d edge_matrix(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  Eigen::Matrix2d e;
  e.col(0) = b - a;
  e.col(1) = c - a;
  return e;
}

class Planar_untangler {
public:
  /// `points`: two coordinates per vertex; `is_free`: per vertex, whether it may move.
  Planar_untangler(std::vector<Eigen::Vector2d> points, std::vector<char> is_free, std::vector<Untangle_triangle> triangles)
      : x_(2 * points.size()), free_(std::move(is_free)), tris_(std::move(triangles)) {
    for (std::size_t i = 0; i < points.size(); ++i) x_.segment<2>(2 * i) = points[i];
  }

  /// Runs the untangling; `max_step` bounds how far one step moves a coordinate (a fraction of the reference
  /// edge length keeps the line search in the range where the energy is meaningful). Returns the smallest
  /// det J at the end: positive if every triangle is positively oriented. At most `outer_rounds` values of ε:
  /// where no positive embedding exists, the smallest det J stalls well before 51 rounds. Stops early, between
  /// two rounds, once `budget` (if any) has run out, and between two iterations once `max_evaluations`
  /// triangle energies have been evaluated (a bound on the work, the same on every machine).
  double run(double max_step, int outer_rounds = 51, int inner_iterations = 400, const Time_budget* budget = nullptr,
             std::size_t max_evaluations = std::size_t(-1)) {
    max_evaluations_ = max_evaluations;
    double eps = 1, previous = energy(eps, nullptr);
    for (int round = 0; round < outer_rounds && !(budget && budget->expired()) && evaluations_ < max_evaluations_;
         ++round) {
      minimise(eps, inner_iterations, max_step);
      const double e = energy(eps, nullptr), d = min_det();
      if (d > 0 && round >= 2) break;
      // The schedule of the paper: ε shrinks with the relative decrease of the energy, and stays above the
      // scale of the most inverted triangle so that the barrier does not stall the minimisation.
      const double sigma = std::max(1 - e / previous, 0.1);
      const double mu = (1 - sigma) * chi(d, eps);
      eps = d < mu ? std::max(1e-12, 2 * std::sqrt(mu * (mu - d))) : 1e-12;
      previous = e;
    }
    return min_det();
  }

  Eigen::Vector2d point(std::size_t i) const { return x_.segment<2>(2 * i); }
  /// The work done so far: triangle energies evaluated.
  std::size_t evaluations() const { return evaluations_; }

  double min_det() const {
    double m = HUGE_VAL;
    for (const Untangle_triangle& t : tris_) m = std::min(m, jacobian(x_, t).determinant());
    return m;
  }

private:
  static constexpr double lambda = 0.5; // shape against area
  static double chi(double d, double eps) { return 0.5 * (d + std::sqrt(eps * eps + d * d)); }
  static double chi_derivative(double d, double eps) { return 0.5 * (1 + d / std::sqrt(eps * eps + d * d)); }
  static Eigen::Matrix2d jacobian(const Eigen::VectorXd& x, const Untangle_triangle& t) {
    return edge_matrix(x.segment<2>(2 * t.v[0]), x.segment<2>(2 * t.v[1]), x.segment<2>(2 * t.v[2])) *
           t.reference_inverse;
  }

  /// The energy at x, and its gradient (zero on fixed coordinates) if `g` is given.
  double energy(const Eigen::VectorXd& x, double eps, Eigen::VectorXd* g) const {
    evaluations_ += tris_.size();
    double total = 0;
    if (g) g->setZero(x.size());
    for (const Untangle_triangle& t : tris_) {
      const Eigen::Matrix2d J = jacobian(x, t);
      const double d = J.determinant(), c = chi(d, eps);
      const double num = (1 - lambda) * J.squaredNorm() + lambda * (d * d + 1);
      total += num / c;
      if (!g) continue;
      Eigen::Matrix2d cofactor; // d(det J)/dJ
      cofactor << J(1, 1), -J(1, 0), -J(0, 1), J(0, 0);
      const Eigen::Matrix2d dJ =
          (2 * (1 - lambda) / c) * J + (2 * lambda * d / c - num * chi_derivative(d, eps) / (c * c)) * cofactor;
      const Eigen::Matrix2d dE = dJ * t.reference_inverse.transpose(); // by the edge matrix's columns
      g->segment<2>(2 * t.v[1]) += dE.col(0);
      g->segment<2>(2 * t.v[2]) += dE.col(1);
      g->segment<2>(2 * t.v[0]) -= dE.col(0) + dE.col(1);
    }
    if (g)
      for (std::size_t i = 0; i < free_.size(); ++i)
        if (!free_[i]) g->segment<2>(2 * i).setZero();
    return total;
  }
  double energy(double eps, Eigen::VectorXd* g) const { return energy(x_, eps, g); }

  /// L-BFGS (8 pairs) with a backtracking line search.
  void minimise(double eps, int iterations, double max_step) {
    constexpr std::size_t pairs = 8;
    std::deque<Eigen::VectorXd> S, Y;
    Eigen::VectorXd g, gn, xn;
    double e = energy(eps, &g);
    for (int it = 0; it < iterations && evaluations_ < max_evaluations_; ++it) {
      Eigen::VectorXd q = g;
      std::vector<double> alpha(S.size());
      for (std::size_t k = S.size(); k-- > 0;) {
        alpha[k] = S[k].dot(q) / Y[k].dot(S[k]);
        q -= alpha[k] * Y[k];
      }
      if (!S.empty()) q *= S.back().dot(Y.back()) / Y.back().dot(Y.back());
      for (std::size_t k = 0; k < S.size(); ++k) q += (alpha[k] - Y[k].dot(q) / Y[k].dot(S[k])) * S[k];
      Eigen::VectorXd d = -q;
      if (!(d.dot(g) < 0)) d = -g, S.clear(), Y.clear();
      const double largest = d.cwiseAbs().maxCoeff();
      if (!(largest > 0)) return;
      double step = std::min(1.0, max_step / largest), en = 0;
      bool decreased = false;
      for (int k = 0; k < 80 && !decreased; ++k) { // Armijo backtracking
        xn = x_ + step * d;
        en = energy(xn, eps, &gn);
        decreased = en <= e + 1e-4 * step * d.dot(g);
        if (!decreased) step *= 0.5;
      }
      if (!decreased) return;
      const Eigen::VectorXd s = xn - x_, y = gn - g;
      if (s.dot(y) > 1e-300) {
        S.push_back(s), Y.push_back(y);
        if (S.size() > pairs) S.pop_front(), Y.pop_front();
      }
      x_ = xn;
      g = gn;
      const double drop = e - en;
      e = en;
      if (drop <= 1e-12 * std::abs(e)) return;
    }
  }

  mutable std::size_t evaluations_ = 0; ///< triangle energies evaluated so far
  std::size_t max_evaluations_ = std::size_t(-1);
  Eigen::VectorXd x_;
  std::vector<char> free_;
  std::vector<Untangle_triangle> tris_;
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_UNTANGLE_H

// SPDX-License-Identifier: GPL-3.0-or-later
// Re-embedding of a disk of faces in space (an addition to the paper), shared by the repairs of the two-mesh
// remeshing (strict_repair.h) and of the N-way outputs (output_repair.h): a set of faces that is a topological
// disk keeps its boundary corners (and any others held) and every other corner goes to the average of its
// neighbours, Tutte's embedding with uniform weights solved in space (one sparse SPD system, the boundary on the
// right-hand side). Tutte's no-fold guarantee holds for a convex planar boundary only; the callers project the
// result onto their surface and judge it by their own checks, keeping it only where it is better.
#ifndef CROSSPARAM_INTERNAL_REMESHING_DISK_EMBEDDING_H
#define CROSSPARAM_INTERNAL_REMESHING_DISK_EMBEDDING_H

#include <crossparam/types.h>

#include <Eigen/Sparse>

#include <algorithm>
#include <array>
#include <cstddef>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

namespace crossparam {
namespace internal {

/// The corners and edges of a set of faces given by their corners.
struct Disk_faces {
  std::vector<std::size_t> corners;                          ///< sorted, each once
  std::vector<std::pair<std::size_t, std::size_t>> edges;    ///< (smaller, larger), sorted, each once
  std::size_t boundary_edges = 0;                            ///< edges of one face only
};

/// The corners and edges of `faces` if they form a topological disk: Euler characteristic 1 with a boundary
/// (for faces that are connected, as a ring grown around a face is, that is a disk); empty otherwise.
inline std::optional<Disk_faces> disk_of(const std::vector<std::array<std::size_t, 3>>& faces) {
  Disk_faces d;
  std::vector<std::pair<std::size_t, std::size_t>> all;
  for (const auto& c : faces)
    for (std::size_t i = 0; i < 3; ++i) {
      d.corners.push_back(c[i]);
      all.push_back(std::minmax(c[i], c[(i + 1) % 3]));
    }
  std::sort(d.corners.begin(), d.corners.end());
  d.corners.erase(std::unique(d.corners.begin(), d.corners.end()), d.corners.end());
  std::sort(all.begin(), all.end());
  for (std::size_t i = 0; i < all.size();) {
    std::size_t j = i;
    while (j < all.size() && all[j] == all[i]) ++j;
    d.boundary_edges += (j - i == 1);
    d.edges.push_back(all[i]);
    i = j;
  }
  if (d.boundary_edges == 0 || long(d.corners.size()) - long(d.edges.size()) + long(faces.size()) != 1) return std::nullopt;
  return d;
}

/// Tutte's embedding in space with uniform weights: the positions of the corners `free` (sorted) at which each is
/// the average of its neighbours along `edges`, the other corners held at `point(v)`. Empty if the system cannot
/// be solved (a free corner with no held corner in its component).
template <class PointOf>
std::optional<std::vector<Point_3>> tutte_in_space(const std::vector<std::size_t>& free,
                                                   const std::vector<std::pair<std::size_t, std::size_t>>& edges,
                                                   const PointOf& point) {
  const auto slot = [&](std::size_t v) {
    const auto it = std::lower_bound(free.begin(), free.end(), v);
    return it != free.end() && *it == v ? std::ptrdiff_t(it - free.begin()) : std::ptrdiff_t(-1);
  };
  const std::ptrdiff_t n = std::ptrdiff_t(free.size());
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
  for (const auto& e : edges) {
    const std::ptrdiff_t a = slot(e.first), b = slot(e.second);
    for (const auto& [i, j, other] : {std::tuple{a, b, e.second}, std::tuple{b, a, e.first}}) {
      if (i < 0) continue;
      entries.emplace_back(i, i, 1.0);
      if (j >= 0) {
        entries.emplace_back(i, j, -1.0);
      } else {
        const Point_3& p = point(other);
        for (int k = 0; k < 3; ++k) rhs(i, k) += p[k];
      }
    }
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) return std::nullopt;
  const Eigen::MatrixXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) return std::nullopt;
  std::vector<Point_3> out;
  out.reserve(free.size());
  for (std::ptrdiff_t i = 0; i < n; ++i) out.emplace_back(x(i, 0), x(i, 1), x(i, 2));
  return out;
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_DISK_EMBEDDING_H

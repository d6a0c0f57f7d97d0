// SPDX-License-Identifier: GPL-3.0-or-later
// Point location on the base domain: which face of a parameterized mesh covers a base point, and where.
// Each face is registered in the (at most two) base triangles its image touches, with its corners in that
// triangle's frame, and found through a uniform grid per base triangle; containment is decided with exact
// orientation predicates.
#ifndef CROSSPARAM_INTERNAL_BASE_LOCATOR_H
#define CROSSPARAM_INTERNAL_BASE_LOCATOR_H

#include <crossparam/internal/base_parameterization.h>

#include <vector>

namespace crossparam {
namespace internal {

/// A point of a working mesh: the public `Refined_location` (face and barycentrics in halfedge order).
using Work_location = Refined_location;

/// The point of mesh m at location l.
inline Point_3 point_at(const Work_mesh& m, const Work_location& l) {
  const WH h = m.halfedge(l.face);
  return barycentric_point(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))), l.b);
}

class Base_locator {
public:
  void build(const Base_parameterization& P) {
    P_ = &P;
    const Base_mesh& B = *P.base;
    const Work_mesh& m = P.mesh->m;
    cells_.assign(B.tri.size(), {});
    struct Entry {
      int t;
      WF f;
      std::array<Point_2, 3> p;
    };
    std::vector<Entry> entries;
    std::vector<std::size_t> count(B.tri.size(), 0);
    for (WF f : m.faces()) {
      WH h = m.halfedge(f);
      std::array<const Base_location*, 3> ls{&P[m.source(h)], &P[m.target(h)], &P[m.target(m.next(h))]};
      std::array<Point_2, 3> p;
      int c, n;
      if (!B.canonical_frame(ls, c, n, p)) throw Algorithm_error("internal error: face outside every chart");
      entries.push_back({c, f, p});
      ++count[c];
      if (n >= 0) {
        int u = B.nb[c][n];
        int back = B.neighbour_index(u, c);
        std::array<Point_2, 3> pu;
        for (int k = 0; k < 3; ++k) B.frame_point(u, back, *ls[k], pu[k]);
        entries.push_back({u, f, pu});
        ++count[u];
      }
    }
    box_.assign(B.tri.size(), {0, 1, 0, 1});
    for (std::size_t t = 0; t < B.tri.size(); ++t) {
      auto& bx = box_[t];
      bx = {HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL};
      for (const Point_2& c : B.q[t]) {
        bx[0] = std::min(bx[0], c.x()), bx[1] = std::max(bx[1], c.x());
        bx[2] = std::min(bx[2], c.y()), bx[3] = std::max(bx[3], c.y());
      }
    }
    res_.assign(B.tri.size(), 1);
    for (std::size_t t = 0; t < B.tri.size(); ++t) {
      res_[t] = std::max(1, int(std::sqrt(double(count[t]) / 2.0)));
      cells_[t].assign(std::size_t(res_[t]) * res_[t], {});
    }
    items_.clear();
    for (const Entry& e : entries) {
      std::size_t id = items_.size();
      items_.push_back({e.f, e.p});
      double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
      for (const Point_2& q : e.p) {
        x0 = std::min(x0, q.x()), x1 = std::max(x1, q.x());
        y0 = std::min(y0, q.y()), y1 = std::max(y1, q.y());
      }
      int i0 = cell_x(e.t, x0), i1 = cell_x(e.t, x1), j0 = cell_y(e.t, y0), j1 = cell_y(e.t, y1);
      for (int i = i0; i <= i1; ++i)
        for (int j = j0; j <= j1; ++j) cells_[e.t][std::size_t(j) * res_[e.t] + i].push_back(id);
    }
  }

  /// The face covering base location l and the barycentrics of l in it. Exact containment first; if
  /// rounding leaves the point in no face (on a shared edge), the face with the largest smallest barycentric.
  Work_location locate(const Base_location& l) const {
    const Base_mesh& B = *P_->base;
    Point_2 q;
    B.frame_point(l.tri, -1, l, q);
    const int t = l.tri;
    const auto& cell = cells_[t][std::size_t(cell_y(t, q.y())) * res_[t] + cell_x(t, q.x())];
    Work_location best;
    double best_min = -HUGE_VAL;
    for (std::size_t id : cell) {
      const Item& it = items_[id];
      std::array<double, 3> b = barycentric(it.p, q);
      double mn = std::min({b[0], b[1], b[2]});
      // The exact test only where q is not certainly outside (a side's orientation negative beyond any
      // rounding of the floating-point determinant), where it would only confirm it.
      if (!certainly_outside(it.p, q)) {
        CGAL::Orientation o0 = CGAL::orientation(it.p[1], it.p[2], q), o1 = CGAL::orientation(it.p[2], it.p[0], q),
                          o2 = CGAL::orientation(it.p[0], it.p[1], q);
        if (o0 != CGAL::NEGATIVE && o1 != CGAL::NEGATIVE && o2 != CGAL::NEGATIVE) {
          if (o0 == CGAL::ZERO) b[0] = 0;
          if (o1 == CGAL::ZERO) b[1] = 0;
          if (o2 == CGAL::ZERO) b[2] = 0;
          Base_mesh::normalise(b);
          return {it.f, b};
        }
      }
      if (mn > best_min) {
        best_min = mn;
        best = {it.f, b};
        Base_mesh::normalise(best.b);
      }
    }
    if (best_min == -HUGE_VAL) {
      // Empty cell: cannot happen for a map that covers the base mesh; search the whole triangle.
      for (const auto& c : cells_[t])
        for (std::size_t id : c) {
          std::array<double, 3> b = barycentric(items_[id].p, q);
          double mn = std::min({b[0], b[1], b[2]});
          if (mn > best_min) {
            best_min = mn;
            best = {items_[id].f, b};
          }
        }
      Base_mesh::normalise(best.b);
    }
    return best;
  }

private:
  struct Item {
    WF f;
    std::array<Point_2, 3> p;
  };
  /// Whether q is on the negative side of an edge of triangle p by more than the rounding error of the
  /// orientation determinant in doubles (a static filter, bound far above Shewchuk's 3.4e-16 relative).
  static bool certainly_outside(const std::array<Point_2, 3>& p, const Point_2& q) {
    for (int i = 0; i < 3; ++i) {
      const Point_2 &a = p[(i + 1) % 3], &b = p[(i + 2) % 3];
      const double l = (b.x() - a.x()) * (q.y() - a.y()), r = (b.y() - a.y()) * (q.x() - a.x());
      if (l - r < -1e-12 * (std::abs(l) + std::abs(r))) return true;
    }
    return false;
  }
  static std::array<double, 3> barycentric(const std::array<Point_2, 3>& p, const Point_2& q) {
    double det = (p[1].x() - p[0].x()) * (p[2].y() - p[0].y()) - (p[2].x() - p[0].x()) * (p[1].y() - p[0].y());
    if (det == 0) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
    double l1 = ((q.x() - p[0].x()) * (p[2].y() - p[0].y()) - (p[2].x() - p[0].x()) * (q.y() - p[0].y())) / det;
    double l2 = ((p[1].x() - p[0].x()) * (q.y() - p[0].y()) - (q.x() - p[0].x()) * (p[1].y() - p[0].y())) / det;
    return {1 - l1 - l2, l1, l2};
  }
  // The grid of a base triangle covers the bounding box of its own frame's triangle.
  int cell_x(int t, double x) const {
    int i = int(std::floor((x - box_[t][0]) / (box_[t][1] - box_[t][0]) * res_[t]));
    return std::min(std::max(i, 0), res_[t] - 1);
  }
  int cell_y(int t, double y) const {
    int j = int(std::floor((y - box_[t][2]) / (box_[t][3] - box_[t][2]) * res_[t]));
    return std::min(std::max(j, 0), res_[t] - 1);
  }
  std::vector<std::array<double, 4>> box_;

  const Base_parameterization* P_ = nullptr;
  std::vector<std::vector<std::vector<std::size_t>>> cells_;
  std::vector<int> res_;
  std::vector<Item> items_;
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_BASE_LOCATOR_H

// SPDX-License-Identifier: GPL-3.0-or-later
// The base domain of paper §4: the base mesh as an abstract surface of planar triangles, locations
// <base triangle, barycentrics> on it, and the local charts in which maps are evaluated.
//
// Geometry. Every base triangle has a planar shape given by its three edge lengths (shared edges have one
// length), placed in its own frame as Q0 = (0,0), Q1 = (l01, 0), Q2 above the x axis, corners in base-triangle
// order. Two adjacent base triangles unfold isometrically into one plane, so a segment between points of
// adjacent triangles is straight in either triangle's frame: the 4-triangle chart of §4.2 is a triangle's frame
// with its three neighbours unfolded around it. (The paper maps the four triangles to the quarters of an
// equilateral triangle; true shapes keep the base domain's metric close to the meshes', see doc/.)
//
// The piecewise-linear map from a mesh to the base domain sends each mesh triangle to the straight triangle
// spanned by its vertices' locations in a frame that holds all three: the frame of a base triangle c with at
// most one neighbour n of c unfolded ("two adjacent base triangles"). A mesh triangle needing more than that
// is not allowed: this is our form of the adjacency constraint, slightly stricter than the paper's at base
// vertices of valence 3, where three pairwise adjacent base triangles do not unfold into one plane.
// Orientation decisions use the exact orientation predicate on the frame coordinates of a canonical frame
// (lowest c, then lowest n), so the smoothing's acceptance test and the certificate see the same numbers.
#ifndef CROSSPARAM_INTERNAL_BASE_DOMAIN_H
#define CROSSPARAM_INTERNAL_BASE_DOMAIN_H

#include <crossparam/errors.h>
#include <crossparam/internal/barycentric.h>
#include <crossparam/types.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

namespace crossparam {
namespace internal {

using Point_2 = Kernel::Point_2;

constexpr double sqrt3_2 = 0.86602540378443864676;

/// Barycentric coordinates of p with respect to triangle (a, b, c).
inline std::array<double, 3> barycentric_2(const Point_2& a, const Point_2& b, const Point_2& c, const Point_2& p) {
  double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
  double l1 = ((p.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (p.y() - a.y())) / det;
  double l2 = ((b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y())) / det;
  return {1.0 - l1 - l2, l1, l2};
}

/// The third corner X of a triangle on edge (a, b) with |X - a| = la and |X - b| = lb, left of a->b.
inline Point_2 third_corner(const Point_2& a, const Point_2& b, double la, double lb) {
  double dx = b.x() - a.x(), dy = b.y() - a.y();
  double d = std::sqrt(dx * dx + dy * dy);
  double x = (la * la - lb * lb + d * d) / (2 * d);
  double h = std::sqrt(std::max(la * la - x * x, 0.0));
  return Point_2(a.x() + (x * dx - h * dy) / d, a.y() + (x * dy + h * dx) / d);
}

/// The base mesh with adjacency.
struct Base_mesh {
  static constexpr int any_quarter = 3; ///< locate_in_chart: search every quarter of the chart
  std::vector<std::array<int, 3>> tri; ///< feature ids, counter-clockwise
  std::vector<std::array<int, 3>> nb;  ///< nb[t][i]: triangle across edge (tri[t][i], tri[t][i+1])
  std::vector<std::vector<int>> around; ///< base triangles at each feature
  std::vector<std::array<Point_2, 3>> q;  ///< corners of each triangle in its own frame
  std::vector<std::array<Point_2, 3>> far; ///< far[t][i]: far corner of nb[t][i] unfolded into t's frame

  /// Builds adjacency and frames. `edge_length(a, b)` gives the length of base edge (a, b) (features);
  /// with none, all triangles are equilateral with unit edges.
  template <class EdgeLength>
  void build(const std::vector<std::array<std::size_t, 3>>& tris, std::size_t nfeatures, EdgeLength edge_length) {
    build(tris, nfeatures);
    for (std::size_t t = 0; t < tri.size(); ++t) {
      const double l01 = edge_length(tri[t][0], tri[t][1]), l12 = edge_length(tri[t][1], tri[t][2]),
                   l20 = edge_length(tri[t][2], tri[t][0]);
      q[t] = {Point_2(0, 0), Point_2(l01, 0), third_corner(Point_2(0, 0), Point_2(l01, 0), l20, l12)};
    }
    compute_unfoldings();
  }

  void build(const std::vector<std::array<std::size_t, 3>>& tris, std::size_t nfeatures) {
    tri.clear();
    for (const auto& t : tris) tri.push_back({int(t[0]), int(t[1]), int(t[2])});
    std::map<std::pair<int, int>, int> directed;
    for (int t = 0; t < int(tri.size()); ++t)
      for (int i = 0; i < 3; ++i) directed[{tri[t][i], tri[t][(i + 1) % 3]}] = t;
    nb.assign(tri.size(), {-1, -1, -1});
    around.assign(nfeatures, {});
    for (int t = 0; t < int(tri.size()); ++t)
      for (int i = 0; i < 3; ++i) {
        auto it = directed.find({tri[t][(i + 1) % 3], tri[t][i]});
        if (it == directed.end()) throw Algorithm_error("internal error: base mesh is not closed");
        nb[t][i] = it->second;
        around[tri[t][i]].push_back(t);
      }
    q.assign(tri.size(), {Point_2(0, 0), Point_2(1, 0), Point_2(0.5, sqrt3_2)});
    compute_unfoldings();
  }

  void compute_unfoldings() {
    far.assign(tri.size(), {Point_2(0, 0), Point_2(0, 0), Point_2(0, 0)});
    for (int t = 0; t < int(tri.size()); ++t)
      for (int i = 0; i < 3; ++i) {
        const int u = nb[t][i];
        const int fa = tri[t][i], fb = tri[t][(i + 1) % 3];
        const int ka = corner_index(u, fa), kb = corner_index(u, fb), kc = 3 - ka - kb;
        const double la = std::sqrt(CGAL::squared_distance(q[u][ka], q[u][kc]));
        const double lb = std::sqrt(CGAL::squared_distance(q[u][kb], q[u][kc]));
        // u lies on the right of t's edge fa -> fb, i.e. left of fb -> fa.
        far[t][i] = third_corner(q[t][(i + 1) % 3], q[t][i], lb, la);
      }
  }

  /// Barycentrics of a frame point with respect to triangle t's corners.
  std::array<double, 3> frame_barycentric(int t, const Point_2& p) const {
    return barycentric_2(q[t][0], q[t][1], q[t][2], p);
  }

  int corner_index(int t, int feature) const {
    for (int i = 0; i < 3; ++i)
      if (tri[t][i] == feature) return i;
    return -1;
  }

  /// Index i such that nb[t][i] == u, or -1.
  int neighbour_index(int t, int u) const {
    for (int i = 0; i < 3; ++i)
      if (nb[t][i] == u) return i;
    return -1;
  }

  /// Expresses location l in base triangle x, if l's point belongs to x (all its non-zero corners are x's).
  bool convert(const Base_location& l, int x, std::array<double, 3>& bx) const {
    if (l.tri == x) {
      bx = l.b;
      return true;
    }
    return reexpress_barycentric(tri[l.tri], l.b, tri[x], bx);
  }

  /// Base triangles that contain location l (one inside a triangle, two on an edge, all around a corner).
  void containing(const Base_location& l, std::vector<int>& out) const {
    out.clear();
    int nz = 0, last = -1;
    for (int j = 0; j < 3; ++j)
      if (l.b[j] != 0) ++nz, last = j;
    if (nz == 1) {
      out = around[tri[l.tri][last]];
      return;
    }
    out.push_back(l.tri);
    if (nz == 2)
      for (int j = 0; j < 3; ++j)
        if (l.b[j] == 0) out.push_back(nb[l.tri][(j + 1) % 3]); // edge opposite corner j
  }

  /// Coordinates of l in the frame of base triangle c, with neighbour slot n (0..2) unfolded, or only c if
  /// n < 0. Returns false if l is in neither.
  bool frame_point(int c, int n, const Base_location& l, Point_2& p) const {
    const auto& qc = q[c];
    std::array<double, 3> bx;
    if (convert(l, c, bx)) {
      p = Point_2(bx[0] * qc[0].x() + bx[1] * qc[1].x() + bx[2] * qc[2].x(),
                  bx[0] * qc[0].y() + bx[1] * qc[1].y() + bx[2] * qc[2].y());
      return true;
    }
    if (n < 0) return false;
    int u = nb[c][n];
    if (!convert(l, u, bx)) return false;
    // Corners of u placed in c's frame: the shared edge keeps its place, the far corner is unfolded.
    const int fa = tri[c][n], fb = tri[c][(n + 1) % 3];
    double x = 0, y = 0;
    for (int j = 0; j < 3; ++j) {
      const int f = tri[u][j];
      const Point_2& pos = f == fa ? qc[n] : (f == fb ? qc[(n + 1) % 3] : far[c][n]);
      x += bx[j] * pos.x();
      y += bx[j] * pos.y();
    }
    p = Point_2(x, y);
    return true;
  }

  /// Coordinates of l in the 4-triangle chart of c (c's frame, its three neighbours unfolded around it): c
  /// itself first, then the neighbour slots in order. Returns false if l is in none of the four.
  bool chart_point(int c, const Base_location& l, Point_2& p) const {
    if (frame_point(c, -1, l, p)) return true;
    for (int n = 0; n < 3; ++n)
      if (frame_point(c, n, l, p)) return true;
    return false;
  }

  /// The canonical frame of a set of locations: their common stored triangle if they share one; otherwise
  /// the lowest base triangle c, then the lowest slot n (-1, i.e.
  /// c alone, first), such that every location is in c or in neighbour nb[c][n], and the straight image stays
  /// inside c and that neighbour: every segment from a point of c only to a point of the neighbour only crosses
  /// the line of the shared edge within the edge (exact predicates; the two unfolded triangles need not form
  /// a convex quadrilateral). Returns false if no such frame exists.
  template <std::size_t N>
  bool canonical_frame(const std::array<const Base_location*, N>& ls, int& c_out, int& n_out,
                       std::array<Point_2, N>& pts) const {
    // Fast path, the common case: every location stored in the same base triangle.
    bool same = true;
    for (const Base_location* l : ls) same &= l->tri == ls[0]->tri;
    if (same) {
      for (std::size_t k = 0; k < N; ++k) frame_point(ls[0]->tri, -1, *ls[k], pts[k]);
      c_out = ls[0]->tri;
      n_out = -1;
      return true;
    }
    std::vector<int> cand, tmp;
    for (const Base_location* l : ls) {
      containing(*l, tmp);
      cand.insert(cand.end(), tmp.begin(), tmp.end());
    }
    std::sort(cand.begin(), cand.end());
    cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
    std::array<double, 3> bx;
    std::array<char, N> in_c{}, in_n{};
    for (int c : cand) {
      for (std::size_t k = 0; k < N; ++k) in_c[k] = convert(*ls[k], c, bx);
      bool all_c = true;
      for (std::size_t k = 0; k < N; ++k) all_c &= bool(in_c[k]);
      if (all_c) {
        for (std::size_t k = 0; k < N; ++k) frame_point(c, -1, *ls[k], pts[k]);
        c_out = c;
        n_out = -1;
        return true;
      }
      for (int n = 0; n < 3; ++n) {
        bool ok = true;
        for (std::size_t k = 0; k < N && ok; ++k) {
          in_n[k] = convert(*ls[k], nb[c][n], bx);
          ok = in_c[k] || in_n[k];
        }
        if (!ok) continue;
        for (std::size_t k = 0; k < N; ++k) frame_point(c, n, *ls[k], pts[k]);
        const Point_2 &A = q[c][n], &B = q[c][(n + 1) % 3];
        for (std::size_t i = 0; i < N && ok; ++i)
          for (std::size_t j = 0; j < N && ok; ++j) {
            if (!(in_c[i] && !in_n[i] && in_n[j] && !in_c[j])) continue;
            CGAL::Orientation oa = CGAL::orientation(pts[i], pts[j], A), ob = CGAL::orientation(pts[i], pts[j], B);
            ok = !(oa == ob && oa != CGAL::ZERO);
          }
        if (!ok) continue;
        c_out = c;
        n_out = n;
        if constexpr (N == 3) prefer_holding_triangle(ls, cand, c_out, n_out, pts);
        return true;
      }
    }
    return false;
  }

  /// A triangle of three locations all on base edges or corners (a face of a patch without interior vertices,
  /// e.g. a whole base triangle) may fit an unfolded pair of base triangles other than the one that holds it,
  /// drawn there as a different triangle. If a base triangle among `cand` holds all three and the triangle's
  /// orientation there differs from that in the frame (c, n), that triangle is the frame.
  void prefer_holding_triangle(const std::array<const Base_location*, 3>& ls, const std::vector<int>& cand, int& c,
                               int& n, std::array<Point_2, 3>& pts) const {
    for (const Base_location* l : ls)
      if (l->b[0] != 0 && l->b[1] != 0 && l->b[2] != 0) return;
    std::array<double, 3> bx;
    for (int h : cand) {
      bool all = true;
      for (std::size_t k = 0; k < 3 && all; ++k) all = convert(*ls[k], h, bx);
      if (!all) continue;
      std::array<Point_2, 3> in_h;
      for (std::size_t k = 0; k < 3; ++k) frame_point(h, -1, *ls[k], in_h[k]);
      if (CGAL::orientation(in_h[0], in_h[1], in_h[2]) == CGAL::orientation(pts[0], pts[1], pts[2])) return;
      c = h;
      n = -1;
      pts = in_h;
      return;
    }
  }

  /// The point with barycentrics `b` of the straight triangle spanned by three locations in their canonical
  /// frame: the piecewise-linear map inside a mesh triangle. False if the locations fit no frame.
  bool interpolate(const std::array<const Base_location*, 3>& ls, const std::array<double, 3>& b,
                   Base_location& out) const {
    std::array<Point_2, 3> p;
    int c, n;
    if (!canonical_frame(ls, c, n, p)) return false;
    const Point_2 q(b[0] * p[0].x() + b[1] * p[1].x() + b[2] * p[2].x(), b[0] * p[0].y() + b[1] * p[1].y() + b[2] * p[2].y());
    // q is in the frame's one or two triangles (up to rounding): only those may hold it, the quarter of another
    // neighbour can overlap them.
    return locate_in_chart(c, q, out, n);
  }

  /// Orientation of the image of a mesh triangle, decided exactly in its canonical frame.
  /// Returns CGAL::ZERO as well when the triangle fits in no frame (the caller treats it as invalid).
  CGAL::Orientation triangle_orientation(const Base_location& a, const Base_location& b, const Base_location& c,
                                         bool* fits = nullptr) const {
    std::array<const Base_location*, 3> ls{&a, &b, &c};
    std::array<Point_2, 3> p;
    int fc, fn;
    bool ok = canonical_frame(ls, fc, fn, p);
    if (fits) *fits = ok;
    if (!ok) return CGAL::ZERO;
    return CGAL::orientation(p[0], p[1], p[2]);
  }

  /// Location of a point given in the frame of c with neighbour slots unfolded (the 4-triangle chart):
  /// finds the quarter that contains it with exact predicates. Triangles keep their true shapes, so two
  /// unfolded neighbours overlap where the base angles around a corner of c add up to more than a full turn:
  /// a point in two neighbour quarters is ambiguous, and refused. Returns false outside the chart and for an
  /// ambiguous point.
  /// `only`, the slot of a canonical frame, restricts the search to c and the quarter of neighbour slot `only`
  /// (-1: c alone). The point is then known to be in those triangles up to rounding, so one just outside them
  /// is clamped onto the nearer one, and the call always succeeds.
  bool locate_in_chart(int c, const Point_2& p, Base_location& out, int only = any_quarter) const {
    const auto& qc = q[c];
    auto inside = [&](const Point_2& a, const Point_2& b, const Point_2& d, std::array<CGAL::Orientation, 3>& o) {
      o = {CGAL::orientation(b, d, p), CGAL::orientation(d, a, p), CGAL::orientation(a, b, p)};
      return o[0] != CGAL::NEGATIVE && o[1] != CGAL::NEGATIVE && o[2] != CGAL::NEGATIVE;
    };
    auto in_c = [&](const std::array<CGAL::Orientation, 3>& o) {
      out.tri = c;
      out.b = frame_barycentric(c, p);
      for (int i = 0; i < 3; ++i)
        if (o[i] == CGAL::ZERO) out.b[i] = 0;
      normalise(out.b);
      return true;
    };
    auto in_quarter = [&](int n, const std::array<CGAL::Orientation, 3>& o) {
      // Quarter of neighbour n: corners (Q_{n+1}, Q_n, far) counter-clockwise.
      std::array<double, 3> lam = barycentric_2(qc[(n + 1) % 3], qc[n], far[c][n], p);
      for (int i = 0; i < 3; ++i)
        if (o[i] == CGAL::ZERO) lam[i] = 0;
      const int u = nb[c][n];
      const int fa = tri[c][(n + 1) % 3], fb = tri[c][n];
      out.tri = u;
      out.b = {0, 0, 0};
      for (int j = 0; j < 3; ++j) {
        const int f = tri[u][j];
        out.b[j] = f == fa ? lam[0] : (f == fb ? lam[1] : lam[2]);
      }
      normalise(out.b);
      return true;
    };
    std::array<CGAL::Orientation, 3> o, oc;
    if (inside(qc[0], qc[1], qc[2], oc) || only == -1) return in_c(oc);
    if (only != any_quarter) {
      if (inside(qc[(only + 1) % 3], qc[only], far[c][only], o)) return in_quarter(only, o);
      // Rounding put p just outside both: the triangle whose smallest barycentric is the larger.
      const auto bc = barycentric_2(qc[0], qc[1], qc[2], p);
      const auto bn = barycentric_2(qc[(only + 1) % 3], qc[only], far[c][only], p);
      if (std::min({bc[0], bc[1], bc[2]}) >= std::min({bn[0], bn[1], bn[2]})) return in_c(oc);
      return in_quarter(only, o);
    }
    int found = -1;
    std::array<CGAL::Orientation, 3> of;
    for (int n = 0; n < 3; ++n) {
      if (!inside(qc[(n + 1) % 3], qc[n], far[c][n], o)) continue;
      if (found >= 0) return false; // in two overlapping quarters
      found = n, of = o;
    }
    return found >= 0 && in_quarter(found, of);
  }

  static void normalise(std::array<double, 3>& b) {
    for (double& x : b)
      if (x < 0) x = 0;
    double s = b[0] + b[1] + b[2];
    if (s > 0)
      for (double& x : b) x /= s;
  }
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_BASE_DOMAIN_H

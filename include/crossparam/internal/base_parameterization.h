// SPDX-License-Identifier: GPL-3.0-or-later
// The parameterization of one mesh over the base domain (paper §4.1): a Base_location per vertex, initialised
// patch by patch by mean-value parameterization onto the base triangle (Floater 2003) with the patch boundary
// laid on the triangle's sides by arc length, and the exact certificate that the resulting piecewise-linear
// map is one-to-one.
#ifndef CROSSPARAM_INTERNAL_BASE_PARAMETERIZATION_H
#define CROSSPARAM_INTERNAL_BASE_PARAMETERIZATION_H

#include <crossparam/certificate.h>
#include <crossparam/internal/base_domain.h>
#include <crossparam/internal/layout_builder.h>

#include <Eigen/Sparse>
#include <Eigen/SparseLU>

#include <string>
#include <vector>

namespace crossparam {

namespace internal {

/// Mean-value weight of halfedge h = (i -> j) for vertex i (Floater 2003): (tan(a/2) + tan(b/2)) / |xj - xi|,
/// a and b the angles at i of the two triangles on either side. Always positive; falls back to 1/|mean edge|
/// on degenerate geometry (coincident points), where the formula is undefined.
inline double mean_value_weight(const Work_mesh& m, WH h, double fallback) {
  const Point_3& xi = m.point(m.source(h));
  const Point_3& xj = m.point(m.target(h));
  auto tan_half = [&](const Point_3& a, const Point_3& b) { // angle at xi between a - xi and b - xi
    Kernel::Vector_3 e1 = a - xi, e2 = b - xi;
    double l1 = std::sqrt(e1.squared_length()), l2 = std::sqrt(e2.squared_length());
    double den = l1 * l2 + e1 * e2;
    double num = std::sqrt(CGAL::cross_product(e1, e2).squared_length());
    return den > 0 ? num / den : HUGE_VAL;
  };
  const Point_3& xk = m.point(m.target(m.next(h)));
  const Point_3& xl = m.point(m.target(m.next(m.opposite(h))));
  double len = std::sqrt(CGAL::squared_distance(xi, xj));
  double w = (tan_half(xj, xk) + tan_half(xl, xj)) / len;
  if (!std::isfinite(w) || !(w > 0)) return fallback;
  return w;
}

/// The weight used by mean_value_weight where the formula is undefined: 1 / mean edge length.
inline double mean_value_fallback(const Work_mesh& m) {
  double mean_edge = 0;
  for (WE e : m.edges())
    mean_edge += std::sqrt(CGAL::squared_distance(m.point(m.source(m.halfedge(e))), m.point(m.target(m.halfedge(e)))));
  mean_edge /= double(std::max<std::size_t>(1, m.number_of_edges()));
  return mean_edge > 0 ? 1.0 / mean_edge : 1.0;
}

/// Convex-combination layout (Tutte's, with Floater's mean-value weights of m's geometry): every vertex
/// vertices[i] that is not `fixed` gets the point uv[i] that is the weighted mean of its neighbours',
/// sum_j w_ij (uv_i - uv_j) = 0, one sparse LU solve for both coordinates. `slot(v)` is v's index in
/// `vertices`; every neighbour of a vertex that is not fixed must have one. `vertex_factor`, if given,
/// multiplies the weight of every edge pointing to a vertex. False if the solve fails.
template <class Slot>
bool mean_value_layout(const Work_mesh& m, const std::vector<WV>& vertices, const Slot& slot,
                       const std::vector<char>& fixed, std::vector<Eigen::Vector2d>& uv,
                       const std::vector<double>* vertex_factor = nullptr) {
  const std::size_t n = vertices.size();
  std::vector<int> unknown(n, -1);
  int n_unknown = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (!fixed[i]) unknown[i] = n_unknown++;
  if (n_unknown == 0) return true;
  const double fallback = mean_value_fallback(m);
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(n_unknown, 2);
  for (std::size_t i = 0; i < n; ++i) {
    if (fixed[i]) continue;
    const int r = unknown[i];
    double diagonal = 0;
    for (WH h : CGAL::halfedges_around_source(m.opposite(m.halfedge(vertices[i])), m)) {
      double w = mean_value_weight(m, h, fallback);
      if (vertex_factor) w *= (*vertex_factor)[m.target(h)];
      const int j = slot(m.target(h));
      diagonal += w;
      if (fixed[j]) rhs.row(r) += w * uv[j].transpose();
      else entries.emplace_back(r, unknown[j], -w);
    }
    entries.emplace_back(r, r, diagonal);
  }
  Eigen::SparseMatrix<double> A(n_unknown, n_unknown);
  A.setFromTriplets(entries.begin(), entries.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(A);
  if (lu.info() != Eigen::Success) return false;
  const Eigen::MatrixX2d x = lu.solve(rhs);
  if (lu.info() != Eigen::Success || !x.allFinite()) return false;
  for (std::size_t i = 0; i < n; ++i)
    if (!fixed[i]) uv[i] = x.row(unknown[i]).transpose();
  return true;
}

/// One mesh parameterized over the base mesh.
struct Base_parameterization {
  const Base_mesh* base = nullptr;
  Layout_mesh* mesh = nullptr;
  std::vector<Base_location> loc; ///< per vertex

  Base_location& operator[](WV v) { return loc[v]; }
  const Base_location& operator[](WV v) const { return loc[v]; }

  CGAL::Orientation face_orientation(WF f, bool* fits = nullptr) const {
    WH h = mesh->m.halfedge(f);
    return base->triangle_orientation(loc[mesh->m.source(h)], loc[mesh->m.target(h)],
                                      loc[mesh->m.target(mesh->m.next(h))], fits);
  }

  /// Whether every face around vertex v is positively oriented over the base mesh (exact test).
  bool star_positive(WV v) const {
    for (WF f : CGAL::faces_around_target(mesh->m.halfedge(v), mesh->m))
      if (face_orientation(f) != CGAL::POSITIVE) return false;
    return true;
  }

  /// The base location of a point given by barycentrics `b` (halfedge order of face f: source(h), target(h),
  /// target(next(h)), h = halfedge(f)) on a mesh face: the piecewise-linear map evaluated in the face's chart.
  Base_location at(WF f, const std::array<double, 3>& b) const {
    const Work_mesh& m = mesh->m;
    WH h = m.halfedge(f);
    WV vs[3] = {m.source(h), m.target(h), m.target(m.next(h))};
    for (int i = 0; i < 3; ++i)
      if (b[i] == 1.0) return loc[vs[i]];
    Base_location out;
    if (!base->interpolate({&loc[vs[0]], &loc[vs[1]], &loc[vs[2]]}, b, out))
      throw Algorithm_error("internal error: face outside every chart");
    return out;
  }

  /// The base location of the point u + t (v - u) of mesh edge (u, v).
  Base_location between(WV u, WV v, double t) const {
    const Work_mesh& m = mesh->m;
    WH h = m.halfedge(u, v);
    if (m.face(h) == Work_mesh::null_face()) h = m.opposite(h);
    WH hf = m.halfedge(m.face(h));
    std::array<double, 3> b{{0, 0, 0}};
    WV vs[3] = {m.source(hf), m.target(hf), m.target(m.next(hf))};
    for (int i = 0; i < 3; ++i) b[i] = vs[i] == u ? 1 - t : (vs[i] == v ? t : 0.0);
    return at(m.face(h), b);
  }

  /// §4.1: boundary by arc length on the base triangle sides, interior by mean-value coordinates, one sparse
  /// LU factorization per patch solved for both coordinates. `face_tri` is the base triangle of each face
  /// (the patch labels of the layout); `path_ends` the features of each path id.
  /// `vertex_factor`, if given, multiplies the weight of every edge pointing to a vertex (stretch reweighting).
  void initialize(const std::vector<int>& face_tri, const std::vector<std::array<int, 2>>& path_ends,
                  const std::vector<double>* vertex_factor = nullptr) {
    const Work_mesh& m = mesh->m;
    const Base_mesh& B = *base;
    loc.assign(m.number_of_vertices(), Base_location{});
    std::vector<char> fixed(m.number_of_vertices(), 0);
    // Features at their corners.
    for (std::size_t k = 0; k < mesh->feature_vertex.size(); ++k) {
      WV v = mesh->feature_vertex[k];
      int t = B.around[k].front();
      loc[v].tri = t;
      loc[v].b = {0, 0, 0};
      loc[v].b[B.corner_index(t, int(k))] = 1.0;
      fixed[v] = 1;
    }
    // Path vertices by arc length along their base edge.
    for (std::size_t p = 0; p < path_ends.size(); ++p) {
      const auto& hp = mesh->paths[p];
      if (path_ends[p][0] < 0 || hp.empty()) continue;
      const int a = path_ends[p][0], b = path_ends[p][1];
      int t = -1;
      for (int x : B.around[a]) {
        int i = B.corner_index(x, a);
        if (B.tri[x][(i + 1) % 3] == b) t = x;
      }
      if (t < 0) throw Algorithm_error("internal error: a path is not a base edge");
      const int ia = B.corner_index(t, a), ib = B.corner_index(t, b);
      double total = 0;
      for (WH h : hp) total += mesh->edge_length(h);
      double acc = 0;
      for (std::size_t i = 0; i + 1 < hp.size(); ++i) {
        acc += mesh->edge_length(hp[i]);
        double s = total > 0 ? acc / total : double(i + 1) / double(hp.size());
        s = std::min(std::max(s, 1e-12), 1 - 1e-12); // strictly between the corners
        WV v = m.target(hp[i]);
        loc[v].tri = t;
        loc[v].b = {0, 0, 0};
        loc[v].b[ia] = 1 - s;
        loc[v].b[ib] = s;
        fixed[v] = 1;
      }
    }
    // Interior vertices, patch by patch.
    std::vector<std::vector<WV>> interior(B.tri.size());
    std::vector<int> row(m.number_of_vertices(), -1);
    for (WV v : m.vertices()) {
      if (fixed[v]) continue;
      int t = face_tri[m.face(m.halfedge(v))];
      row[v] = int(interior[t].size());
      interior[t].push_back(v);
    }
    // Each patch: its interior vertices, then their neighbours on its boundary at their points of its frame.
    std::vector<int> slot(m.number_of_vertices(), -1);
    for (std::size_t t = 0; t < B.tri.size(); ++t) {
      const auto& q = B.q[t];
      std::vector<WV> vs = interior[t];
      if (vs.empty()) continue;
      std::vector<Eigen::Vector2d> uv(vs.size());
      std::vector<char> held(vs.size(), 0);
      for (WV v : vs) slot[v] = row[v];
      for (std::size_t r = 0; r < interior[t].size(); ++r)
        for (WH h : CGAL::halfedges_around_source(interior[t][r], m)) {
          const WV u = m.target(h);
          if (row[u] >= 0 || slot[u] >= 0) continue;
          std::array<double, 3> bx;
          if (!B.convert(loc[u], int(t), bx))
            throw Algorithm_error("internal error: a patch boundary vertex is off its base triangle");
          slot[u] = int(vs.size());
          vs.push_back(u);
          uv.emplace_back(bx[0] * q[0].x() + bx[1] * q[1].x() + bx[2] * q[2].x(),
                          bx[0] * q[0].y() + bx[1] * q[1].y() + bx[2] * q[2].y());
          held.push_back(1);
        }
      if (!mean_value_layout(m, vs, [&slot](WV v) { return slot[v]; }, held, uv, vertex_factor))
        throw Algorithm_error("mean-value system of patch " + std::to_string(t) + " could not be solved");
      for (std::size_t r = 0; r < interior[t].size(); ++r) {
        loc[vs[r]].tri = int(t);
        loc[vs[r]].b = B.frame_barycentric(int(t), Point_2(uv[r].x(), uv[r].y()));
      }
      for (WV v : vs) slot[v] = -1;
    }
  }

  /// Per-vertex L2 stretch (Sander et al. 2001) of the map from the base frames back to the mesh: large where
  /// the parameterization squeezes the surface. Only meaningful while every face lies in one base triangle.
  std::vector<double> vertex_stretch() const {
    const Work_mesh& m = mesh->m;
    std::vector<double> num(m.number_of_vertices(), 0), den(m.number_of_vertices(), 0);
    const double cap = 1e8;
    for (WF f : m.faces()) {
      WH h = m.halfedge(f);
      WV v[3] = {m.source(h), m.target(h), m.target(m.next(h))};
      std::array<const Base_location*, 3> ls{&loc[v[0]], &loc[v[1]], &loc[v[2]]};
      std::array<Point_2, 3> q;
      int c, n;
      double sigma2 = cap * cap;
      const Point_3 &p1 = m.point(v[0]), &p2 = m.point(v[1]), &p3 = m.point(v[2]);
      const double a3 = std::sqrt(CGAL::squared_area(p1, p2, p3));
      if (base->canonical_frame(ls, c, n, q)) {
        const double s1 = q[0].x(), t1 = q[0].y(), s2 = q[1].x(), t2 = q[1].y(), s3 = q[2].x(), t3 = q[2].y();
        const double A = ((s2 - s1) * (t3 - t1) - (s3 - s1) * (t2 - t1)) / 2;
        if (A > 0) {
          Kernel::Vector_3 Ss = ((p1 - CGAL::ORIGIN) * (t2 - t3) + (p2 - CGAL::ORIGIN) * (t3 - t1) + (p3 - CGAL::ORIGIN) * (t1 - t2)) / (2 * A);
          Kernel::Vector_3 St = ((p1 - CGAL::ORIGIN) * (s3 - s2) + (p2 - CGAL::ORIGIN) * (s1 - s3) + (p3 - CGAL::ORIGIN) * (s2 - s1)) / (2 * A);
          sigma2 = std::min(cap * cap, (Ss.squared_length() + St.squared_length()) / 2);
        }
      }
      for (WV x : v) {
        num[x] += a3 * sigma2;
        den[x] += a3;
      }
    }
    std::vector<double> out(m.number_of_vertices(), 1.0);
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = den[i] > 0 ? std::sqrt(num[i] / den[i]) : 1.0;
    return out;
  }

  /// Proves with exact predicates that the map from the mesh to the base mesh is one-to-one: every face is
  /// positively oriented in its canonical chart (so the map is a local homeomorphism away from vertices, a
  /// branched covering of the base surface), and a probe point of the base mesh is covered by exactly one face (so
  /// the covering has degree 1, hence no branching: a bijection).
  Bijectivity_certificate certify() const {
    Bijectivity_certificate c;
    const Work_mesh& m = mesh->m;
    c.faces = m.number_of_faces();
    for (WF f : m.faces()) {
      bool fits = true;
      CGAL::Orientation o = face_orientation(f, &fits);
      if (!fits) ++c.not_in_a_chart;
      else if (o != CGAL::POSITIVE) ++c.not_positive;
    }
    // Probe points inside base triangle 0; a probe on a face boundary is ambiguous, so try another.
    const std::array<std::array<double, 3>, 4> probes{{{0.3141, 0.3317, 0.3542}, {0.2718, 0.4142, 0.3140},
                                                       {0.4472, 0.2236, 0.3292}, {0.1732, 0.5477, 0.2791}}};
    bool decided = false;
    for (const auto& pb : probes) {
      Base_location probe{0, pb};
      std::size_t count = 0;
      bool ambiguous = false;
      for (WF f : m.faces()) {
        WH h = m.halfedge(f);
        std::array<const Base_location*, 4> ls{&loc[m.source(h)], &loc[m.target(h)], &loc[m.target(m.next(h))], &probe};
        std::array<Point_2, 4> p;
        int fc, fn;
        if (!base->canonical_frame(ls, fc, fn, p)) continue; // face does not reach the probe's triangle
        CGAL::Orientation o0 = CGAL::orientation(p[1], p[2], p[3]), o1 = CGAL::orientation(p[2], p[0], p[3]),
                          o2 = CGAL::orientation(p[0], p[1], p[3]);
        if (o0 == CGAL::NEGATIVE || o1 == CGAL::NEGATIVE || o2 == CGAL::NEGATIVE) continue;
        if (o0 == CGAL::ZERO || o1 == CGAL::ZERO || o2 == CGAL::ZERO) {
          ambiguous = true;
          break;
        }
        ++count;
      }
      if (ambiguous) continue;
      c.coverage = count;
      decided = true;
      break;
    }
    c.valid = decided && c.not_positive == 0 && c.not_in_a_chart == 0 && c.coverage == 1;
    if (!c.valid) {
      c.message = std::to_string(c.not_positive) + " of " + std::to_string(c.faces) +
                  " faces flipped or degenerate, " + std::to_string(c.not_in_a_chart) +
                  " outside any chart, probe covered " + std::to_string(c.coverage) + " times" +
                  (decided ? "" : " (probe undecided)");
    }
    return c;
  }
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_BASE_PARAMETERIZATION_H

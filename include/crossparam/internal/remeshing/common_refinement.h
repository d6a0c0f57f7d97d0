// SPDX-License-Identifier: GPL-3.0-or-later
// The common refinement of several compatible remeshings of one source (the N-way remeshing, paper §2.3).
//
// Every compatible remeshing refines the source by splits only, so each of its faces lies inside one input face
// of the source (Input_face_location), and inside an input face f the remeshing's faces tile f. The common
// refinement triangulates every input face so that each of its triangles lies inside one face of every
// remeshing:
//  - where at most one remeshing subdivides f (or all that do subdivide it the same way), that subdivision is
//    taken as it is;
//  - elsewhere, a constrained Delaunay triangulation of f with every remeshing's edges as constraints, in exact
//    arithmetic (CGAL's Epeck, exact intersections), in an isometric flattening of f.
// A vertex on an edge of f is shared with the neighbouring face through its key (the edge's end vertices and its
// barycentric coordinate, exact: the remeshings keep zero coordinates exact), so the faces fit together.
//
// The image of a point on remeshing j's target-shaped mesh is the linear interpolation inside the face of j that
// holds it. Each triangle of the common refinement lies inside one face of j, so output j is geometrically the
// target-shaped mesh of j itself, subdivided: the same surface, the same distance to the target, the same
// normals. The vertices of remeshing j keep their images exactly.
#ifndef CROSSPARAM_INTERNAL_REMESHING_COMMON_REFINEMENT_H
#define CROSSPARAM_INTERNAL_REMESHING_COMMON_REFINEMENT_H

#include <crossparam/errors.h>
#include <crossparam/types.h>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <iterator>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>
#include <vector>

namespace crossparam {
namespace internal {

/// One compatible remeshing of the source, as the common refinement reads it (pointers into its outputs).
struct Fitted_remeshing {
  const std::vector<std::array<std::size_t, 3>>* faces = nullptr;
  const std::vector<Input_face_location>* locations = nullptr; ///< per face, where it lies on the source
  const std::vector<std::array<double, 3>>* target_points = nullptr;
};

/// The common refinement: one face list, the source-shaped points and the points on each remeshing's
/// target-shaped mesh (in the order of the remeshings given).
struct Common_refinement {
  std::vector<std::array<std::size_t, 3>> faces;
  std::vector<Input_face_location> locations;
  std::vector<std::array<double, 3>> source_points;
  std::vector<std::vector<std::array<double, 3>>> images;
  std::size_t retriangulated_faces = 0; ///< input faces subdivided differently by two or more remeshings
  std::size_t flipped_caps = 0;         ///< caps (a vertex within rounding of the opposite edge) flipped away
  std::size_t merged_needles = 0;       ///< needles (an edge within rounding of zero length) collapsed
};

/// Coordinates of `b` in the frame of the three points `corners` (barycentric coordinates of one triangle):
/// the affine solve on the first two coordinates; -inf for a degenerate frame.
inline std::array<double, 3> barycentric_in_frame(const std::array<std::array<double, 3>, 3>& corners,
                                                  const std::array<double, 3>& b) {
  const double a00 = corners[0][0] - corners[2][0], a01 = corners[1][0] - corners[2][0];
  const double a10 = corners[0][1] - corners[2][1], a11 = corners[1][1] - corners[2][1];
  const double r0 = b[0] - corners[2][0], r1 = b[1] - corners[2][1];
  const double det = a00 * a11 - a01 * a10;
  if (det == 0) return {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  const double c0 = (r0 * a11 - a01 * r1) / det, c1 = (a00 * r1 - r0 * a10) / det;
  return {c0, c1, 1 - c0 - c1};
}

class Common_refinement_builder {
public:
  /// `source_points`: the input source's vertices, in input order; `input_faces`: its number of faces.
  Common_refinement_builder(const std::vector<std::array<double, 3>>& source_points, std::size_t input_faces,
                            const std::vector<Fitted_remeshing>& remeshings)
      : src_(source_points), r_(remeshings), by_face_(remeshings.size()) {
    for (std::size_t j = 0; j < r_.size(); ++j) {
      by_face_[j].assign(input_faces, {});
      for (std::size_t g = 0; g < r_[j].faces->size(); ++g) by_face_[j].at((*r_[j].locations)[g].face).push_back(g);
    }
    out_.images.resize(r_.size());
    for (std::size_t j = 0; j < r_.size(); ++j) image_side_.push_back(longest_side(*r_[j].target_points));
    // The source's vertices keep their indices: every remeshing starts with them, in input order.
    for (std::size_t v = 0; v < src_.size(); ++v) new_vertex(src_[v]);
    for (std::size_t j = 0; j < r_.size(); ++j)
      for (std::size_t v = 0; v < src_.size(); ++v) out_.images[j][v] = (*r_[j].target_points).at(v);
    for (std::size_t f = 0; f < input_faces; ++f) face(f);
    merge_needles();
    // Points that two remeshings gave with different coordinates but that are the same point, and the ends of
    // needles: one vertex each; the faces between them go.
    compact();
  }

  Common_refinement result() && { return std::move(out_); }

private:
  using K = CGAL::Epeck;
  static constexpr std::size_t none = std::size_t(-1);
  /// Info of a vertex of the triangulation of one input face: its index in that face's list of points (`none`
  /// for a vertex the triangulation made where two constraints cross).
  struct Slot {
    std::size_t i = none;
  };
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<Slot, K>;
  using Fb = CGAL::Constrained_triangulation_face_base_2<K>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  // The "plus" hierarchy keeps each constraint's input end points, so crossings are computed from them, not
  // from earlier crossings (no cascade of ever longer exact numbers).
  using CDT = CGAL::Constrained_triangulation_plus_2<CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_intersections_tag>>;

  /// A point of input face f met in f: its vertex and its barycentric coordinates in f.
  struct Local {
    std::size_t id = none;
    std::array<double, 3> b{};
  };

  std::size_t new_vertex(const std::array<double, 3>& p) {
    out_.source_points.push_back(p);
    for (auto& img : out_.images) img.push_back({0, 0, 0});
    parent_.push_back(parent_.size());
    return parent_.size() - 1;
  }
  std::size_t find(std::size_t v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }

  /// The vertex of the point of input face f (corners `tri`) at `b`, created on first use: corners and points
  /// on edges are keyed so that the neighbouring face finds the same vertex.
  std::size_t vertex_at(std::size_t f, const std::array<std::size_t, 3>& tri, const std::array<double, 3>& b) {
    int zeros = 0;
    for (double x : b) zeros += x == 0;
    if (zeros >= 2) {
      for (int i = 0; i < 3; ++i)
        if (b[i] != 0) return tri[i];
      throw Algorithm_error("internal error: a remeshed vertex with zero barycentric coordinates");
    }
    std::size_t* slot;
    if (zeros == 1) {
      int a = -1, c = -1;
      for (int i = 0; i < 3; ++i)
        if (b[i] != 0) (a < 0 ? a : c) = i;
      if (tri[a] > tri[c]) std::swap(a, c);
      slot = &edge_points_[std::make_tuple(tri[a], tri[c], b[a], b[c])];
    } else {
      slot = &face_points_[std::make_tuple(f, b[0], b[1], b[2])];
    }
    if (*slot == 0) {
      std::array<double, 3> p{0, 0, 0};
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) p[k] += b[i] * src_[tri[i]][k];
      *slot = new_vertex(p) + 1;
      place(f, b, *slot - 1);
    }
    return *slot - 1;
  }

  /// The images of new vertex v at `b` in input face f: inside the face of each remeshing that holds it.
  void place(std::size_t f, const std::array<double, 3>& b, std::size_t v) {
    for (std::size_t j = 0; j < r_.size(); ++j) {
      double best = -HUGE_VAL;
      std::array<double, 3> c{};
      std::size_t g_best = none;
      for (std::size_t g : by_face_[j][f]) {
        const std::array<double, 3> x = barycentric_in_frame((*r_[j].locations)[g].corners, b);
        const double mn = std::min({x[0], x[1], x[2]});
        if (mn > best) best = mn, c = x, g_best = g;
      }
      if (g_best == none) throw Algorithm_error("internal error: a source point in no face of a remeshing");
      double sum = 0;
      for (double& x : c) sum += (x = std::max(0.0, x));
      std::array<double, 3> q{0, 0, 0};
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) q[k] += c[i] / sum * (*r_[j].target_points)[(*r_[j].faces)[g_best][i]][k];
      out_.images[j][v] = q;
    }
  }

  /// Remeshing j's own vertices in input face f keep their images exactly (they may have been met first
  /// through another remeshing, and placed by interpolation).
  void keep_exact_in(std::size_t f, const std::array<std::size_t, 3>& tri, std::size_t j) {
    for (std::size_t g : by_face_[j][f])
      for (int c = 0; c < 3; ++c)
        out_.images[j][find(vertex_at(f, tri, (*r_[j].locations)[g].corners[c]))] =
            (*r_[j].target_points)[(*r_[j].faces)[g][c]];
  }

  /// A triangle whose height is below this share of its longest edge is a cap: a vertex within rounding of
  /// the opposite edge (two remeshings computed the same point of a shared edge with different roundings). Its
  /// normal on the outputs, computed from rounded coordinates, would be noise (angles of rounding / share, here
  /// 1e-6 rad at most); the cap's longest edge is flipped, which moves nothing: the vertex is then on the
  /// edge, as meant. A triangle is a cap when it is one on the source and on every remeshing's target-shaped
  /// mesh (there, its vertex within this share of the edge's length, or within needle_share of the mesh's
  /// diagonal, of the edge): a flip where the vertex is off the edge on some output would fold that output.
  static constexpr double cap_height_share = 1e-10;

  /// Whether vertex v lies within rounding of the segment (p, w) on every remeshing's target-shaped mesh.
  bool on_segment_in_every_image(std::size_t v, std::size_t p, std::size_t w) {
    for (std::size_t j = 0; j < out_.images.size(); ++j) {
      const auto& P = out_.images[j][find(p)];
      const auto& W = out_.images[j][find(w)];
      const auto& V = out_.images[j][find(v)];
      std::array<double, 3> d, x;
      double dd = 0, t = 0;
      for (int k = 0; k < 3; ++k) d[k] = W[k] - P[k], x[k] = V[k] - P[k], dd += d[k] * d[k], t += d[k] * x[k];
      t = dd > 0 ? std::clamp(t / dd, 0.0, 1.0) : 0.0;
      double h2 = 0;
      for (int k = 0; k < 3; ++k) h2 += (x[k] - t * d[k]) * (x[k] - t * d[k]);
      const double h = std::sqrt(h2), bound = std::max(cap_height_share * std::sqrt(dd), needle_share * image_side_[j]);
      if (!(h <= bound)) return false;
    }
    return true;
  }

  /// Flips the longest edge of every cap whose flip leaves both new triangles positive (exact orientation
  /// tests). `local`: the output vertex of each triangulation vertex. Returns the number of flips.
  std::size_t flip_caps(CDT& cdt, const std::vector<Local>& local) {
    // One flip at a time (a flip changes the faces around it), at most a few per face: each flip removes a cap
    // and makes two triangles of which at most one is a cap again.
    const std::size_t limit = 4 * cdt.number_of_faces();
    std::size_t flips = 0;
    while (flips < limit) {
      bool flipped = false;
      for (auto t = cdt.finite_faces_begin(); t != cdt.finite_faces_end() && !flipped; ++t) {
        std::array<std::array<double, 2>, 3> q;
        for (int i = 0; i < 3; ++i) q[i] = {CGAL::to_double(t->vertex(i)->point().x()), CGAL::to_double(t->vertex(i)->point().y())};
        const double area2 = std::abs((q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[2][0] - q[0][0]) * (q[1][1] - q[0][1]));
        int i = 0;
        double longest = -1;
        for (int k = 0; k < 3; ++k) {
          const auto& a = q[(k + 1) % 3];
          const auto& b = q[(k + 2) % 3];
          const double l2 = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
          if (l2 > longest) longest = l2, i = k;
        }
        // height / longest edge = area2 / longest².
        if (!(longest > 0) || area2 >= cap_height_share * longest) continue;
        const auto n = t->neighbor(i);
        if (cdt.is_infinite(n)) continue; // the cap's long edge is on the outline of the input face
        const auto v = t->vertex(i), p = t->vertex(CDT::ccw(i)), w = t->vertex(CDT::cw(i));
        const auto r = n->vertex(n->index(typename CDT::Face_handle(t)));
        if (CGAL::orientation(v->point(), p->point(), r->point()) != CGAL::LEFT_TURN ||
            CGAL::orientation(v->point(), r->point(), w->point()) != CGAL::LEFT_TURN)
          continue;
        if (!on_segment_in_every_image(local[v->info().i].id, local[p->info().i].id, local[w->info().i].id)) continue;
        cdt.tds().flip(t, i);
        flipped = true;
      }
      if (!flipped) break;
      ++flips;
    }
    return flips;
  }

  static double signed_area(const std::array<std::array<double, 3>, 3>& c) {
    return (c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1]);
  }

  void emit(std::size_t f, const std::array<std::size_t, 3>& tri, std::array<Local, 3> t, bool reversed) {
    if (reversed) std::swap(t[1], t[2]);
    out_.faces.push_back({t[0].id, t[1].id, t[2].id});
    Input_face_location l;
    l.face = f;
    l.vertices = tri;
    for (int c = 0; c < 3; ++c) l.corners[c] = t[c].b;
    out_.locations.push_back(l);
  }

  void face(std::size_t f) {
    // The remeshings that subdivide f, and whether they all do it the same way.
    std::vector<std::size_t> subdividing;
    const std::array<std::size_t, 3>* tri = nullptr;
    for (std::size_t j = 0; j < r_.size(); ++j) {
      if (by_face_[j][f].empty()) throw Algorithm_error("internal error: an input face that a remeshing does not cover");
      tri = &(*r_[j].locations)[by_face_[j][f].front()].vertices;
      if (by_face_[j][f].size() > 1) subdividing.push_back(j);
    }
    bool same = true;
    for (std::size_t k = 1; k < subdividing.size() && same; ++k) same = same_subdivision(f, subdividing[0], subdividing[k]);
    const std::size_t j0 = subdividing.empty() ? 0 : subdividing[0];
    if (same) {
      // Taken as it is: the faces of a remeshing are oriented as the source.
      for (std::size_t g : by_face_[j0][f]) {
        Input_face_location l = (*r_[j0].locations)[g];
        std::array<std::size_t, 3> t;
        for (int c = 0; c < 3; ++c) t[c] = vertex_at(f, *tri, l.corners[c]);
        out_.faces.push_back(t);
        l.vertices = *tri;
        out_.locations.push_back(l);
      }
      for (std::size_t j : subdividing) keep_exact_in(f, *tri, j);
      return;
    }
    // Orientation of the remeshed faces in the frame of f's corners (all of one sign: they tile f).
    double area = 0;
    for (std::size_t g : by_face_[j0][f]) area += signed_area((*r_[j0].locations)[g].corners);
    ++out_.retriangulated_faces;
    retriangulate(f, *tri, subdividing, area < 0);
  }

  /// Whether remeshings j and k have the same faces in input face f (same corners, as sets of points).
  bool same_subdivision(std::size_t f, std::size_t j, std::size_t k) const {
    if (by_face_[j][f].size() != by_face_[k][f].size()) return false;
    auto faces_of = [&](std::size_t r) {
      std::vector<std::array<std::array<double, 3>, 3>> out;
      for (std::size_t g : by_face_[r][f]) {
        auto c = (*r_[r].locations)[g].corners;
        std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
        out.push_back(c);
      }
      std::sort(out.begin(), out.end());
      return out;
    };
    return faces_of(j) == faces_of(k);
  }

  void retriangulate(std::size_t f, const std::array<std::size_t, 3>& tri, const std::vector<std::size_t>& subdividing,
                     bool reversed) {
    // An isometric flattening of f, scaled to a unit first edge (no underflow at any input scale); the reference
    // triangle where f is degenerate.
    std::array<double, 3> u, w;
    for (int k = 0; k < 3; ++k) u[k] = src_[tri[1]][k] - src_[tri[0]][k], w[k] = src_[tri[2]][k] - src_[tri[0]][k];
    const double scale = std::max({std::abs(u[0]), std::abs(u[1]), std::abs(u[2]), std::abs(w[0]), std::abs(w[1]), std::abs(w[2])});
    double bx = 1, cx = 0, cy = 1;
    if (scale > 0 && std::isfinite(scale)) {
      for (int k = 0; k < 3; ++k) u[k] /= scale, w[k] /= scale;
      const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2], uw = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
      const std::array<double, 3> n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
      const double nn = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      const double lu = std::sqrt(uu), ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
      // Degenerate when the area is below 1e-6 of the squared longest edge: the flattening's rounding would then
      // decide the orientation of the triangles.
      if (lu > 0 && nn > 1e-6 * std::max(uu, ww)) bx = lu, cx = uw / lu, cy = nn / lu;
    }
    const K::FT BX(bx), CX(cx), CY(cy);
    auto at = [&](const std::array<double, 3>& b) {
      const K::FT s = K::FT(b[0]) + K::FT(b[1]) + K::FT(b[2]);
      return K::Point_2((K::FT(b[1]) * BX + K::FT(b[2]) * CX) / s, (K::FT(b[2]) * CY) / s);
    };
    CDT cdt;
    std::vector<Local> local; // info of a CDT vertex: index here
    auto insert = [&](const std::array<double, 3>& b, std::size_t id) {
      const auto vh = cdt.insert(at(b));
      if (vh->info().i == none) {
        vh->info().i = local.size();
        local.push_back({id, b});
      } else if (find(local[vh->info().i].id) != find(id)) {
        // The same point given twice with other coordinates: one vertex.
        parent_[find(id)] = find(local[vh->info().i].id);
      }
      return vh;
    };
    for (int c = 0; c < 3; ++c) {
      std::array<double, 3> b{0, 0, 0};
      b[c] = 1;
      insert(b, tri[c]);
    }
    for (std::size_t j : subdividing)
      for (std::size_t g : by_face_[j][f]) {
        const Input_face_location& l = (*r_[j].locations)[g];
        std::array<CDT::Vertex_handle, 3> vh;
        for (int c = 0; c < 3; ++c) {
          vh[c] = insert(l.corners[c], vertex_at(f, tri, l.corners[c]));
        }
        for (int c = 0; c < 3; ++c)
          if (vh[c] != vh[(c + 1) % 3]) cdt.insert_constraint(vh[c], vh[(c + 1) % 3]);
      }
    for (std::size_t j : subdividing) keep_exact_in(f, tri, j);
    // Vertices made by crossing constraints: new vertices inside f.
    for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
      if (v->info().i != none) continue;
      const K::Point_2& p = v->point();
      const K::FT b2 = p.y() / CY, b1 = (p.x() - b2 * CX) / BX;
      const std::array<double, 3> b{CGAL::to_double(1 - b1 - b2), CGAL::to_double(b1), CGAL::to_double(b2)};
      std::array<double, 3> x{0, 0, 0};
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) x[k] += b[i] * src_[tri[i]][k];
      const std::size_t id = new_vertex(x);
      place(f, b, id);
      v->info().i = local.size();
      local.push_back({id, b});
    }
    out_.flipped_caps += flip_caps(cdt, local);
    for (auto t = cdt.finite_faces_begin(); t != cdt.finite_faces_end(); ++t) {
      std::array<Local, 3> c;
      for (int i = 0; i < 3; ++i) c[i] = local[t->vertex(i)->info().i];
      emit(f, tri, c, reversed);
    }
  }

  /// An edge shorter than this share of the bounding-box diagonal, on the source and on every remeshing's
  /// target-shaped mesh (each against its own diagonal), is a needle: two points within rounding of each other
  /// on every output (a crossing of two constraints next to a vertex, or one point given by two remeshings with
  /// different roundings). Normals computed across it would be noise (rounding / share, below 1e-6 rad), so
  /// its ends are merged. An edge short on the source alone is kept: a remeshing built from the map's overlay
  /// has such edges where the map sends a stretch of the target through nearly one point of the source, and
  /// merging their ends would cut that stretch out of the output.
  static constexpr double needle_share = 1e-10;

  /// The longest side of the bounding box of `points` (no overflow at any scale).
  static double longest_side(const std::vector<std::array<double, 3>>& points) {
    std::array<double, 3> lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const auto& p : points)
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    double d = 0;
    for (int k = 0; k < 3; ++k) d = std::max(d, hi[k] - lo[k]);
    return d;
  }

  /// Merges the ends of every needle whose collapse keeps the mesh manifold (the link condition: the vertices
  /// next to both ends are exactly the apexes of the edge's two faces). The lower index stays: source vertices
  /// first, so the source's own vertices never move.
  void merge_needles() {
    const double limit = needle_share * longest_side(src_);
    auto length = [](const std::vector<std::array<double, 3>>& points, std::size_t a, std::size_t b) {
      double m = 0;
      for (int k = 0; k < 3; ++k) m = std::max(m, std::abs(points[a][k] - points[b][k]));
      return m;
    };
    auto needle = [&](std::size_t a, std::size_t b) {
      if (!(length(out_.source_points, a, b) < limit)) return false;
      for (std::size_t j = 0; j < out_.images.size(); ++j)
        if (!(length(out_.images[j], a, b) < needle_share * image_side_[j])) return false;
      return true;
    };
    std::vector<std::pair<std::size_t, std::size_t>> needles;
    for (const auto& t : out_.faces)
      for (int c = 0; c < 3; ++c)
        if (needle(t[c], t[(c + 1) % 3])) needles.push_back({t[c], t[(c + 1) % 3]});
    if (needles.empty()) return;
    std::vector<std::vector<std::size_t>> faces_of(parent_.size());
    for (std::size_t g = 0; g < out_.faces.size(); ++g)
      for (std::size_t v : out_.faces[g]) faces_of[v].push_back(g);
    auto neighbours = [&](std::size_t v) {
      std::vector<std::size_t> out;
      for (std::size_t g : faces_of[v]) {
        std::array<std::size_t, 3> t;
        for (int c = 0; c < 3; ++c) t[c] = find(out_.faces[g][c]);
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue; // already gone
        for (std::size_t x : t)
          if (x != v) out.push_back(x);
      }
      std::sort(out.begin(), out.end());
      out.erase(std::unique(out.begin(), out.end()), out.end());
      return out;
    };
    for (auto [a0, b0] : needles) {
      std::size_t a = find(a0), b = find(b0);
      if (a == b) continue;
      if (a > b) std::swap(a, b);
      if (b < src_.size()) continue; // two vertices of the source itself (a zero-length edge of the input) stay
      // The apexes of the edge's faces, and the vertices next to both ends.
      std::vector<std::size_t> apexes;
      for (std::size_t g : faces_of[a]) {
        std::array<std::size_t, 3> t;
        for (int c = 0; c < 3; ++c) t[c] = find(out_.faces[g][c]);
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        if (std::find(t.begin(), t.end(), b) == t.end()) continue;
        for (std::size_t x : t)
          if (x != a && x != b) apexes.push_back(x);
      }
      const std::vector<std::size_t> na = neighbours(a), nb = neighbours(b);
      std::vector<std::size_t> common;
      std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(common));
      std::sort(apexes.begin(), apexes.end());
      if (apexes.size() != 2 || common != apexes) continue; // the collapse would pinch the mesh
      parent_[b] = a;
      faces_of[a].insert(faces_of[a].end(), faces_of[b].begin(), faces_of[b].end());
      ++out_.merged_needles;
    }
  }

  /// Renumbers the vertices left after merging, and drops the faces that merging made degenerate.
  void compact() {
    std::vector<std::size_t> id(parent_.size(), none);
    std::size_t n = 0;
    for (std::size_t v = 0; v < parent_.size(); ++v)
      if (find(v) == v) id[v] = n++;
    if (n == parent_.size()) return;
    Common_refinement c;
    c.source_points.resize(n);
    c.images.assign(out_.images.size(), std::vector<std::array<double, 3>>(n));
    for (std::size_t v = 0; v < parent_.size(); ++v)
      if (id[v] != none) {
        c.source_points[id[v]] = out_.source_points[v];
        for (std::size_t j = 0; j < c.images.size(); ++j) c.images[j][id[v]] = out_.images[j][v];
      }
    for (std::size_t g = 0; g < out_.faces.size(); ++g) {
      std::array<std::size_t, 3> t;
      for (int k = 0; k < 3; ++k) t[k] = id[find(out_.faces[g][k])];
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      c.faces.push_back(t);
      c.locations.push_back(out_.locations[g]);
    }
    out_.faces = std::move(c.faces);
    out_.locations = std::move(c.locations);
    out_.source_points = std::move(c.source_points);
    out_.images = std::move(c.images);
  }

  const std::vector<std::array<double, 3>>& src_;
  const std::vector<Fitted_remeshing>& r_;
  std::vector<std::vector<std::vector<std::size_t>>> by_face_; ///< per remeshing, per input face: its faces there
  std::map<std::tuple<std::size_t, std::size_t, double, double>, std::size_t> edge_points_; ///< vertex + 1
  std::map<std::tuple<std::size_t, double, double, double>, std::size_t> face_points_;      ///< vertex + 1
  std::vector<std::size_t> parent_;
  std::vector<double> image_side_; ///< per remeshing: the longest side of its target-shaped mesh's bounding box
  Common_refinement out_;
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_COMMON_REFINEMENT_H

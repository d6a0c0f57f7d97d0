// SPDX-License-Identifier: GPL-3.0-or-later
// One mesh of a partial patch layout: the working copy of the mesh, which of its edges and vertices carry
// layout paths, and the local operations of paper §3 (sectors, constrained Dijkstra, face-path tracing with
// edge splits, flood fills). Everything here is combinatorial: a sector at a feature, a side of a path and a
// patch are read off the mesh's halfedge structure, so no decision depends on rounded coordinates.
#ifndef CROSSPARAM_INTERNAL_LAYOUT_MESH_H
#define CROSSPARAM_INTERNAL_LAYOUT_MESH_H

#include <crossparam/errors.h>
#include <crossparam/layout_types.h>
#include <crossparam/types.h>
#include <crossparam/internal/barycentric.h>

#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <string>
#include <utility>
#include <vector>

namespace crossparam {
namespace internal {

/// The working mesh of every stage is the public `Refined_mesh` (types.h); short names for its descriptors.
using Work_mesh = Refined_mesh;
using WV = Refined_vertex;
using WH = Refined_halfedge;
using WE = Refined_edge;
using WF = Refined_face;

constexpr int no_path = -1;     ///< edge or vertex not on any path
constexpr int no_feature = -1;  ///< vertex that is not a feature
constexpr int isolated_corner = -1; ///< sector id of a feature that no path reaches yet

/// Splits edge (u,v) of `tm` at u + t (v - u) and re-triangulates its two faces by connecting the new vertex
/// to the opposite corners. Works on any MutableFaceGraph; the same call replays a split on a user's mesh.
/// Returns the new vertex.
template <class TriangleMesh, class VertexPointMap, class Point>
typename boost::graph_traits<TriangleMesh>::vertex_descriptor
split_edge_and_triangulate(TriangleMesh& tm, VertexPointMap vpm,
                           typename boost::graph_traits<TriangleMesh>::vertex_descriptor u,
                           typename boost::graph_traits<TriangleMesh>::vertex_descriptor v, const Point& p) {
  auto hf = halfedge(u, v, tm);
  if (!hf.second) throw Algorithm_error("internal error: split of an edge that does not exist");
  auto h = hf.first;                              // u -> v
  auto hnew = CGAL::Euler::split_edge(h, tm);     // u -> w, followed by h: w -> v
  auto w = target(hnew, tm);
  put(vpm, w, p);
  // Face on the side of h: u->w, w->v, v->x, x->u. Connect w with x.
  if (!is_border(h, tm)) CGAL::Euler::split_face(hnew, next(h, tm), tm);
  // Other side: v->w (opposite(h)), w->u (opposite(hnew)), u->y, y->v. Connect w with y.
  auto ho = opposite(h, tm);
  auto hno = opposite(hnew, tm);
  if (!is_border(ho, tm)) CGAL::Euler::split_face(ho, next(hno, tm), tm);
  return w;
}

/// Orientation of the triangle whose corners have barycentric coordinates a, b, c in one triangle, exact: the
/// sign of the determinant of the three coordinate vectors, which is the orientation of the triangle of the
/// normalized coordinates (every vector's sum is positive). Unlike a test on two of the coordinates, it needs no
/// sum to be exactly 1: three points with one coordinate exactly 0 are on one edge of the triangle, collinear.
inline CGAL::Orientation barycentric_orientation(const std::array<double, 3>& a, const std::array<double, 3>& b,
                                                 const std::array<double, 3>& c) {
  using P = Kernel::Point_3;
  return CGAL::orientation(P(CGAL::ORIGIN), P(a[0], a[1], a[2]), P(b[0], b[1], b[2]), P(c[0], c[1], c[2]));
}

/// A path of the layout on one mesh: halfedges from its first feature to its second.
using Halfedge_path = std::vector<WH>;

/// The plain data of a Layout_mesh: everything a member-wise copy copies correctly.
struct Layout_mesh_data {
  Work_mesh m;
  std::vector<WV> feature_vertex;            ///< vertex of each feature
  std::vector<Edge_split> splits;            ///< splits in the order performed
  std::vector<Halfedge_path> paths;          ///< per path id (empty once a path is removed)
  std::size_t n_original_vertices = 0;
  std::size_t n_original_faces = 0;
  /// Working coordinates are (p - center) / scale: a unit bounding-box diagonal whatever the input scale.
  std::array<double, 3> center{{0, 0, 0}};
  double scale = 1;
  /// The input vertices exactly as given (input coordinates, input order).
  std::vector<std::array<double, 3>> input_points;
  /// Whether the working faces are oriented opposite to the input's faces (the working copy faces outward).
  bool reversed = false;
  /// Corners of each original face in the user's order (file order), as vertex indices.
  std::vector<std::array<std::size_t, 3>> orig_tri;
  /// The orientation that each original face's work face has in that face's barycentric coordinates
  /// (w.r.t. orig_tri, in the user's order): POSITIVE, or NEGATIVE where the work mesh is the input reversed
  /// (an input oriented inward, make_work_mesh()). Every face that tiles an original face has its orientation.
  std::vector<CGAL::Orientation> orig_orientation;
  /// Every vertex as a point of the original mesh: original face and barycentrics w.r.t. orig_tri.
  std::vector<std::pair<int, std::array<double, 3>>> vrep;
  /// Per vertex: approximate geodesic distance (edge-graph Dijkstra, scaled to unit area) to every feature.
  /// Corresponding points of two similar meshes have similar descriptors (Layout_builder::consistency).
  std::vector<std::vector<float>> desc;
};

/// The working copy of one input mesh with its partial layout.
class Layout_mesh : public Layout_mesh_data {
public:
  Layout_mesh() = default;
  /// Copies rebind the property maps to the copy's own mesh.
  Layout_mesh(const Layout_mesh& o) : Layout_mesh_data(o) { bind_property_maps(); }
  Layout_mesh& operator=(const Layout_mesh& o) {
    Layout_mesh_data::operator=(o);
    bind_property_maps();
    return *this;
  }

  Work_mesh::Property_map<WV, int> vfeature; ///< feature id of a vertex, or no_feature
  Work_mesh::Property_map<WV, int> vpath;    ///< path id if the vertex is interior to a path, else no_path
  Work_mesh::Property_map<WE, int> epath;    ///< path id of an edge, or no_path
  /// Original face of every face: faces keep their index, split faces inherit it.
  Work_mesh::Property_map<WF, int> forig;
  /// Points the property maps at this mesh's own (named) properties.
  void bind_property_maps() {
    vfeature = m.property_map<WV, int>("v:cp_feature").first;
    vpath = m.property_map<WV, int>("v:cp_path").first;
    epath = m.property_map<WE, int>("e:cp_path").first;
    forig = m.property_map<WF, int>("f:cp_orig").first;
  }

  /// A working point back in input coordinates.
  std::array<double, 3> input_point(const Point_3& p) const {
    return {p.x() * scale + center[0], p.y() * scale + center[1], p.z() * scale + center[2]};
  }
  /// Vertex v in input coordinates, computed from its input face and barycentrics: exact for input vertices,
  /// on the input face for split vertices.
  std::array<double, 3> input_position(WV v) const {
    const auto& r = vrep[v];
    std::array<double, 3> p{{0, 0, 0}};
    for (int i = 0; i < 3; ++i) {
      if (r.second[i] == 0) continue;
      const auto& q = input_points[orig_tri[r.first][i]];
      for (int k = 0; k < 3; ++k) p[k] += r.second[i] * q[k];
    }
    return p;
  }

  /// A fingerprint of the refined mesh: FNV-1a over its vertices' coordinates (their bits) and its faces'
  /// corners, in storage order. Two refinements made by the same steps from the same input are equal.
  std::uint64_t fingerprint() const {
    std::uint64_t h = 14695981039346656037ull;
    auto mix = [&h](const void* data, std::size_t bytes) {
      const unsigned char* c = static_cast<const unsigned char*>(data);
      for (std::size_t i = 0; i < bytes; ++i) h = (h ^ c[i]) * 1099511628211ull;
    };
    for (WV v : m.vertices()) {
      const double xyz[3] = {m.point(v).x(), m.point(v).y(), m.point(v).z()};
      mix(xyz, sizeof xyz);
    }
    for (WF f : m.faces()) {
      const WH e = m.halfedge(f);
      const std::uint32_t c[3] = {std::uint32_t(m.source(e)), std::uint32_t(m.target(e)),
                                  std::uint32_t(m.target(m.next(e)))};
      mix(c, sizeof c);
    }
    return h;
  }

  /// Total surface area (working coordinates).
  double area() const {
    double a = 0;
    for (WF f : m.faces()) {
      WH h = m.halfedge(f);
      a += std::sqrt(CGAL::squared_area(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h)))));
    }
    return a;
  }

  void compute_descriptors() {
    const double area = this->area();
    const double sc = area > 0 ? 1.0 / std::sqrt(area) : 1.0;
    const std::size_t nf = feature_vertex.size();
    desc.assign(m.number_of_vertices(), std::vector<float>(nf, 0.f));
    for (std::size_t k = 0; k < nf; ++k) {
      const std::vector<double> d = graph_distances({feature_vertex[k]});
      for (WV v : m.vertices()) desc[v][k] = float(d[v] * sc);
    }
  }

  /// Per vertex, the length of the shortest edge path to the nearest of `seeds` (Dijkstra on the edge graph).
  std::vector<double> graph_distances(const std::vector<WV>& seeds) const {
    std::vector<double> d(m.number_of_vertices(), HUGE_VAL);
    using QE = std::pair<double, std::uint32_t>;
    std::priority_queue<QE, std::vector<QE>, std::greater<QE>> q;
    for (WV s : seeds) {
      d[s] = 0;
      q.push({0.0, std::uint32_t(s)});
    }
    while (!q.empty()) {
      auto [dd, vi] = q.top();
      q.pop();
      WV v(vi);
      if (dd > d[v]) continue;
      for (WH h : CGAL::halfedges_around_source(v, m)) {
        WV w = m.target(h);
        double nd = dd + edge_length(h);
        if (nd < d[w]) {
          d[w] = nd;
          q.push({nd, std::uint32_t(w)});
        }
      }
    }
    return d;
  }

  /// Distance from the descriptor of v to the nearest of `ref` (descriptors of a path on the other mesh).
  double descriptor_distance(WV v, const std::vector<std::vector<float>>& ref) const {
    double best = HUGE_VAL;
    const auto& a = desc[v];
    for (const auto& r : ref) {
      double s = 0;
      for (std::size_t k = 0; k < a.size() && s < best; ++k) { // abandon once worse than the best
        double x = double(a[k]) - double(r[k]);
        s += x * x;
      }
      best = std::min(best, s);
    }
    return std::sqrt(best);
  }

  /// `tris`: the original faces in user order (face k = work face k).
  void init(const std::vector<std::array<std::size_t, 3>>& tris) {
    vfeature = m.add_property_map<WV, int>("v:cp_feature", no_feature).first;
    vpath = m.add_property_map<WV, int>("v:cp_path", no_path).first;
    epath = m.add_property_map<WE, int>("e:cp_path", no_path).first;
    forig = m.add_property_map<WF, int>("f:cp_orig", -1).first;
    n_original_vertices = m.number_of_vertices();
    n_original_faces = m.number_of_faces();
    orig_tri = tris;
    vrep.assign(n_original_vertices, {-1, {0, 0, 0}});
    orig_orientation.assign(tris.size(), CGAL::POSITIVE);
    for (std::size_t f = 0; f < tris.size(); ++f) {
      forig[WF(WF::size_type(f))] = int(f);
      // The work face's corners are a rotation of the user's (positive) or of their reverse (negative).
      const WH h = m.halfedge(WF(WF::size_type(f)));
      const std::size_t a = std::size_t(m.source(h)), b = std::size_t(m.target(h));
      const auto& t = tris[f];
      const bool same = (a == t[0] && b == t[1]) || (a == t[1] && b == t[2]) || (a == t[2] && b == t[0]);
      orig_orientation[f] = same ? CGAL::POSITIVE : CGAL::NEGATIVE;
      for (int i = 0; i < 3; ++i)
        if (vrep[tris[f][i]].first < 0) {
          vrep[tris[f][i]].first = int(f);
          vrep[tris[f][i]].second[i] = 1.0;
        }
    }
  }

  /// Vertex v expressed in original face o (barycentrics w.r.t. orig_tri[o]), if it lies on that face.
  bool rep_in(WV v, int o, std::array<double, 3>& out) const {
    const auto& r = vrep[v];
    if (r.first == o) {
      out = r.second;
      return true;
    }
    return reexpress_barycentric(orig_tri[r.first], r.second, orig_tri[o], out);
  }

  // ---- navigation around a vertex (outward orientation: counter-clockwise seen from outside) ----
  WH cw(WH h) const { return m.next(m.opposite(h)); }  ///< next outgoing halfedge clockwise around source(h)
  WH ccw(WH h) const { return m.opposite(m.prev(h)); } ///< next outgoing halfedge counter-clockwise
  WH out_halfedge(WV v) const { return m.opposite(m.halfedge(v)); }
  int path_of(WH h) const { return epath[m.edge(h)]; }
  bool is_free(WV v) const { return vfeature[v] == no_feature && vpath[v] == no_path; }

  /// The sector (corner) containing outgoing halfedge h of a feature: the id of the first path met turning
  /// clockwise from h, h included; isolated_corner if no path leaves the vertex. The sector of path p is the
  /// wedge on p's counter-clockwise side, up to the next path.
  int corner_of_outgoing(WH h) const {
    WH g = h;
    do {
      int p = path_of(g);
      if (p != no_path) return p;
      g = cw(g);
    } while (g != h);
    return isolated_corner;
  }

  /// Faces of sector `corner` at feature vertex v, counter-clockwise.
  std::vector<WF> sector_faces(WV v, int corner) const {
    std::vector<WF> out;
    WH start = sector_first_halfedge(v, corner);
    WH g = start;
    do {
      out.push_back(m.face(g));
      g = ccw(g);
    } while (g != start && path_of(g) == no_path);
    return out;
  }

  /// The outgoing halfedge at v that bounds sector `corner` on its clockwise side.
  WH sector_first_halfedge(WV v, int corner) const {
    WH h0 = out_halfedge(v);
    WH g = h0;
    do {
      if (corner == isolated_corner || path_of(g) == corner) return g;
      g = ccw(g);
    } while (g != h0);
    throw Algorithm_error("internal error: sector not found at a feature vertex");
  }

  /// Path ids leaving feature vertex v, counter-clockwise.
  std::vector<int> rotation(WV v) const {
    std::vector<int> out;
    WH h0 = out_halfedge(v);
    WH g = h0;
    do {
      int p = path_of(g);
      if (p != no_path) out.push_back(p);
      g = ccw(g);
    } while (g != h0);
    return out;
  }

  double edge_length(WH h) const {
    return std::sqrt(CGAL::squared_distance(m.point(m.source(h)), m.point(m.target(h))));
  }

  // ---- marking paths ----
  void mark_path(int id, const Halfedge_path& hp) {
    if (paths.size() <= std::size_t(id)) paths.resize(id + 1);
    paths[id] = hp;
    for (std::size_t i = 0; i < hp.size(); ++i) {
      epath[m.edge(hp[i])] = id;
      if (i > 0) vpath[m.source(hp[i])] = id;
    }
  }
  void unmark_path(int id) {
    for (std::size_t i = 0; i < paths[id].size(); ++i) {
      epath[m.edge(paths[id][i])] = no_path;
      if (i > 0) vpath[m.source(paths[id][i])] = no_path;
    }
    paths[id].clear();
  }

  /// Whether a stored candidate path is still usable: interior vertices free, no edge on a path.
  bool path_still_free(const Halfedge_path& hp) const {
    for (std::size_t i = 0; i < hp.size(); ++i) {
      if (path_of(hp[i]) != no_path) return false;
      if (i > 0 && !is_free(m.source(hp[i]))) return false;
    }
    return true;
  }

  double path_length(const Halfedge_path& hp) const {
    double l = 0;
    for (WH h : hp) l += edge_length(h);
    return l;
  }

  // ---- Dijkstra on the edge graph of the free part of the mesh ----
  struct Dijkstra_scratch {
    std::vector<double> dist;
    std::vector<WH> pred;
    std::vector<std::uint32_t> stamp;
    std::uint32_t current = 0;
    void reset(std::size_t n) {
      if (dist.size() < n) {
        dist.resize(n);
        pred.resize(n);
        stamp.resize(n, 0);
      }
      if (++current == 0) {
        std::fill(stamp.begin(), stamp.end(), 0);
        current = 1;
      }
    }
    bool seen(std::size_t i) const { return stamp[i] == current; }
    double d(std::size_t i) const { return seen(i) ? dist[i] : std::numeric_limits<double>::infinity(); }
    void set(std::size_t i, double v, WH p) { stamp[i] = current; dist[i] = v; pred[i] = p; }
  };
  mutable Dijkstra_scratch scratch;

  Halfedge_path trace_back(WV from, WV to) const {
    Halfedge_path hp;
    WV v = to;
    while (v != from) {
      WH h = scratch.pred[v];
      hp.push_back(h);
      v = m.source(h);
    }
    std::reverse(hp.begin(), hp.end());
    return hp;
  }

  /// Shortest edge paths from feature a to every feature it can reach through free vertices.
  /// Result: for each feature id, the path (empty if unreachable, or if the feature is a itself).
  std::vector<Halfedge_path> shortest_paths_from(int a) const {
    const std::size_t nf = feature_vertex.size();
    std::vector<Halfedge_path> out(nf);
    WV va = feature_vertex[a];
    scratch.reset(m.number_of_vertices());
    using QE = std::pair<double, std::uint32_t>;
    std::priority_queue<QE, std::vector<QE>, std::greater<QE>> q;
    scratch.set(va, 0.0, WH());
    q.push({0.0, std::uint32_t(va)});
    std::size_t found = 0;
    std::vector<char> done(m.number_of_vertices(), 0);
    while (!q.empty()) {
      auto [d, vi] = q.top();
      q.pop();
      WV v(vi);
      if (done[vi]) continue;
      done[vi] = 1;
      if (v != va && vfeature[v] != no_feature) { // a feature ends a path, never lies inside one
        out[vfeature[v]] = trace_back(va, v);
        if (++found + 1 == nf) break;
        continue;
      }
      for (WH h : CGAL::halfedges_around_source(v, m)) {
        if (path_of(h) != no_path) continue;
        WV w = m.target(h);
        if (!is_free(w) && vfeature[w] == no_feature) continue;
        if (w == va) continue;
        double nd = d + edge_length(h);
        if (nd < scratch.d(w)) {
          scratch.set(w, nd, h);
          q.push({nd, std::uint32_t(w)});
        }
      }
    }
    return out;
  }

  /// Shortest edge path from feature a to feature b through free vertices, leaving a inside sector
  /// `corner_a` and entering b inside sector `corner_b` (pass any_corner for no constraint).
  static constexpr int any_corner = -2;
  /// With `guide` (descriptors of the matching path on the other mesh) every edge costs
  /// length * (1 + guide_weight * descriptor distance of its target): the path most like the other one.
  Halfedge_path shortest_path(int a, int b, int corner_a, int corner_b,
                              const std::vector<std::vector<float>>* guide = nullptr, double guide_weight = 0) const {
    WV va = feature_vertex[a], vb = feature_vertex[b];
    std::vector<double> penalty_cache;
    if (guide) penalty_cache.assign(m.number_of_vertices(), -1.0);
    auto cost = [&](WH h) {
      double l = edge_length(h);
      if (!guide) return l;
      WV w = m.target(h);
      double& c = penalty_cache[w];
      if (c < 0) c = descriptor_distance(w, *guide);
      return l * (1 + guide_weight * c);
    };
    scratch.reset(m.number_of_vertices());
    using QE = std::pair<double, std::uint32_t>;
    std::priority_queue<QE, std::vector<QE>, std::greater<QE>> q;
    auto arrival_ok = [&](WH h) { // h: x -> b
      if (corner_b == any_corner) return true;
      return corner_of_outgoing(m.opposite(h)) == corner_b;
    };
    for (WH h : CGAL::halfedges_around_source(va, m)) {
      if (path_of(h) != no_path) continue;
      if (corner_a != any_corner && corner_of_outgoing(h) != corner_a) continue;
      WV w = m.target(h);
      double d = cost(h);
      if (w == vb) {
        if (!arrival_ok(h)) continue;
      } else if (!is_free(w)) {
        continue;
      }
      if (d < scratch.d(w)) {
        scratch.set(w, d, h);
        q.push({d, std::uint32_t(w)});
      }
    }
    while (!q.empty()) {
      auto [d, vi] = q.top();
      q.pop();
      WV v(vi);
      if (d > scratch.d(v)) continue;
      if (v == vb) return trace_back(va, vb);
      for (WH h : CGAL::halfedges_around_source(v, m)) {
        if (path_of(h) != no_path) continue;
        WV w = m.target(h);
        if (w == vb) {
          if (!arrival_ok(h)) continue;
        } else if (!is_free(w)) {
          continue;
        }
        double nd = d + cost(h);
        if (nd < scratch.d(w)) {
          scratch.set(w, nd, h);
          q.push({nd, std::uint32_t(w)});
        }
      }
    }
    return {};
  }

  /// Descriptors of (at most `max_samples` evenly spaced) vertices of a path.
  std::vector<std::vector<float>> path_descriptors(const Halfedge_path& hp, std::size_t max_samples = 0) const {
    const std::size_t n = hp.size() + 1;
    const std::size_t step = max_samples > 0 && n > max_samples ? (n + max_samples - 1) / max_samples : 1;
    std::vector<std::vector<float>> out;
    for (std::size_t i = 0; i < n; i += step) out.push_back(desc[i == 0 ? m.source(hp.front()) : m.target(hp[i - 1])]);
    out.push_back(desc[m.target(hp.back())]);
    return out;
  }

  // ---- flood fills over faces, not crossing path edges ----

  /// Labels every face with its patch (connected set of faces across non-path edges). Returns the count.
  int label_patches(std::vector<int>& label) const {
    label.assign(m.number_of_faces(), -1);
    int n = 0;
    std::vector<WF> stack;
    for (WF f0 : m.faces()) {
      if (label[f0] >= 0) continue;
      label[f0] = n;
      stack.push_back(f0);
      while (!stack.empty()) {
        WF f = stack.back();
        stack.pop_back();
        for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
          if (path_of(h) != no_path) continue;
          WF g = m.face(m.opposite(h));
          if (label[g] < 0) {
            label[g] = n;
            stack.push_back(g);
          }
        }
      }
      ++n;
    }
    return n;
  }

  /// What lies on the left of a candidate path inside its patch: the ids of paths bounding the faces reached
  /// (the candidate excluded), the isolated features reached, and whether the right side was reached too
  /// (then the path does not split its patch). Paper §3, blocking test by fronts from the same side.
  struct Side_signature {
    bool splits = false;
    std::vector<int> paths;    ///< sorted
    std::vector<int> isolated; ///< sorted
  };
  Side_signature left_side_signature(const Halfedge_path& hp, int tmp_id,
                                     const std::vector<int>& feature_degree) const {
    auto& self = const_cast<Layout_mesh&>(*this);
    for (WH h : hp) self.epath[m.edge(h)] = tmp_id;
    std::vector<char> seen(m.number_of_faces(), 0);
    std::vector<WF> stack{m.face(hp.front())};
    seen[m.face(hp.front())] = 1;
    std::vector<int> ps, iso;
    while (!stack.empty()) {
      WF f = stack.back();
      stack.pop_back();
      for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        int p = path_of(h);
        WV v = m.target(h);
        if (vfeature[v] != no_feature && feature_degree[vfeature[v]] == 0) iso.push_back(vfeature[v]);
        if (p != no_path) {
          if (p != tmp_id) ps.push_back(p);
          continue;
        }
        WF g = m.face(m.opposite(h));
        if (!seen[g]) {
          seen[g] = 1;
          stack.push_back(g);
        }
      }
    }
    Side_signature s;
    s.splits = !seen[m.face(m.opposite(hp.front()))];
    for (WH h : hp) self.epath[m.edge(h)] = no_path;
    std::sort(ps.begin(), ps.end());
    ps.erase(std::unique(ps.begin(), ps.end()), ps.end());
    std::sort(iso.begin(), iso.end());
    iso.erase(std::unique(iso.begin(), iso.end()), iso.end());
    s.paths = std::move(ps);
    s.isolated = std::move(iso);
    return s;
  }

  // ---- topology of regions bounded by paths (genus > 0, paper §3.1 rule 4) ----

  /// Euler characteristic V - E + F of every region of faces (label[f] in [0, n), -1 for faces outside every
  /// region), each region taken as a surface cut open along the path edges: a path edge bounding a region
  /// counts once per side it shows, and a vertex counts once per fan of faces between consecutive path edges
  /// around it (once if no path edge reaches it).
  std::vector<long> euler_characteristics(const std::vector<int>& label, int n) const {
    std::vector<long> faces_(std::size_t(n), 0), half_edges2(std::size_t(n), 0), fans(std::size_t(n), 0);
    std::vector<char> counted(m.number_of_vertices(), 0);
    for (WF f : m.faces()) {
      const int r = label[f];
      if (r < 0) continue;
      ++faces_[r];
      for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        half_edges2[r] += path_of(h) != no_path ? 2 : 1; // a cut edge shows this side only
        if (path_of(m.next(h)) != no_path) ++fans[r];    // the fan at target(h) starting at this face
        const WV v = m.target(h);
        if (counted[v]) continue;
        counted[v] = 1;
        bool on_path = false;
        for (WH g : CGAL::halfedges_around_target(v, m)) on_path |= path_of(g) != no_path;
        if (!on_path) ++fans[r];
      }
    }
    std::vector<long> chi(static_cast<std::size_t>(n), 0);
    for (int r = 0; r < n; ++r) chi[r] = fans[r] - half_edges2[r] / 2 + faces_[r];
    return chi;
  }

  /// One side of a candidate path: the path sides bounding the region (dart 2p: the left side of path p, 2p + 1:
  /// its right side; sorted), the isolated features inside and the region's Euler characteristic.
  struct Region_signature {
    std::vector<int> darts;
    std::vector<int> isolated;
    long euler = 0;
    bool operator==(const Region_signature& o) const {
      return darts == o.darts && isolated == o.isolated && euler == o.euler;
    }
  };
  /// Both sides of a candidate path `hp` (id `tmp_id`) inside its patch: whether it splits the patch and, if it
  /// does, the signatures of its left and right parts. Meshes of genus > 0 (paper §3.1 rule 4.2): parts that
  /// match in their bounding darts and isolated features must match in genus too, compared by Euler
  /// characteristic.
  struct Split_signature {
    bool splits = false;
    Region_signature left, right;
  };
  Split_signature split_signature(const Halfedge_path& hp, int tmp_id, const std::vector<int>& feature_degree) const {
    auto& self = const_cast<Layout_mesh&>(*this);
    for (WH h : hp) self.epath[m.edge(h)] = tmp_id;
    std::vector<int> label(m.number_of_faces(), -1);
    auto fill = [&](WF f0, int r) {
      std::vector<WF> stack{f0};
      label[f0] = r;
      while (!stack.empty()) {
        WF f = stack.back();
        stack.pop_back();
        for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
          if (path_of(h) != no_path) continue;
          WF g = m.face(m.opposite(h));
          if (label[g] < 0) {
            label[g] = r;
            stack.push_back(g);
          }
        }
      }
    };
    const WF fl = m.face(hp.front()), fr = m.face(m.opposite(hp.front()));
    fill(fl, 0);
    Split_signature s;
    s.splits = label[fr] < 0;
    if (s.splits) {
      fill(fr, 1);
      const std::vector<long> chi = euler_characteristics(label, 2);
      Region_signature* sides[2] = {&s.left, &s.right};
      for (int r = 0; r < 2; ++r) sides[r]->euler = chi[r];
      auto side_of = [&](const Halfedge_path& p, int id) {
        const int l = label[m.face(p.front())], r = label[m.face(m.opposite(p.front()))];
        if (l >= 0) sides[l]->darts.push_back(2 * id);
        if (r >= 0) sides[r]->darts.push_back(2 * id + 1);
      };
      for (std::size_t p = 0; p < paths.size(); ++p)
        if (!paths[p].empty() && int(p) != tmp_id) side_of(paths[p], int(p));
      side_of(hp, tmp_id);
      for (std::size_t k = 0; k < feature_vertex.size(); ++k) {
        if (feature_degree[k] != 0) continue;
        const int r = label[m.face(out_halfedge(feature_vertex[k]))];
        if (r >= 0) sides[r]->isolated.push_back(int(k));
      }
    }
    for (WH h : hp) self.epath[m.edge(h)] = no_path;
    return s;
  }

  /// The region of patch `patch` (faces with label[f] == patch) with its boundary collapsed to one point S, and
  /// a tree-cotree decomposition of it (Eppstein): T spans the free vertices from S over non-path edges, C spans
  /// the faces over the non-path edges not in T. Each remaining ("leftover") edge closes a cycle of faces in C
  /// that crosses a handle of the patch; there are twice as many as the patch has handles. Used to cut handles
  /// and to point at them.
  struct Handle_cycles {
    std::vector<WE> leftover;             ///< non-path edges of the patch in neither tree
    std::vector<WH> cotree_parent;        ///< per face: the halfedge (in the face) crossed from its parent in C
    std::vector<int> depth;               ///< per vertex: edges of T from S (-1 outside the patch)
  };
  Handle_cycles handle_cycles(const std::vector<int>& label, int patch) const {
    Handle_cycles hc;
    const std::size_t nv = m.number_of_vertices();
    hc.depth.assign(nv, -1);
    std::vector<char> in_tree(m.number_of_edges(), 0);
    std::vector<WV> queue;
    auto face_in = [&](WH h) { return !m.is_border(h) && label[m.face(h)] == patch; };
    for (WF f : m.faces()) // S: every boundary (non-free) vertex of the patch
      if (label[f] == patch)
        for (WV v : CGAL::vertices_around_face(m.halfedge(f), m))
          if (!is_free(v) && hc.depth[v] < 0) {
            hc.depth[v] = 0;
            queue.push_back(v);
          }
    for (std::size_t i = 0; i < queue.size(); ++i) {
      const WV v = queue[i];
      for (WH h : CGAL::halfedges_around_source(v, m)) {
        if (path_of(h) != no_path || !face_in(h)) continue;
        const WV w = m.target(h);
        if (!is_free(w) || hc.depth[w] >= 0) continue;
        hc.depth[w] = hc.depth[v] + 1;
        in_tree[m.edge(h)] = 1;
        queue.push_back(w);
      }
    }
    hc.cotree_parent.assign(m.number_of_faces(), WH());
    std::vector<char> reached(m.number_of_faces(), 0), in_cotree(m.number_of_edges(), 0);
    for (WF f0 : m.faces()) {
      if (label[f0] != patch) continue;
      std::vector<WF> fq{f0};
      reached[f0] = 1;
      for (std::size_t i = 0; i < fq.size(); ++i)
        for (WH h : CGAL::halfedges_around_face(m.halfedge(fq[i]), m)) {
          if (path_of(h) != no_path || in_tree[m.edge(h)]) continue;
          const WF g = m.face(m.opposite(h));
          if (reached[g]) continue;
          reached[g] = 1;
          hc.cotree_parent[g] = m.opposite(h);
          in_cotree[m.edge(h)] = 1;
          fq.push_back(g);
        }
      break; // the patch is connected
    }
    for (WE e : m.edges()) {
      const WH h = m.halfedge(e);
      if (path_of(h) == no_path && face_in(h) && !in_tree[e] && !in_cotree[e]) hc.leftover.push_back(e);
    }
    return hc;
  }

  /// A simple edge path through free vertices of one patch from sector `corner_a` of feature a to sector
  /// `corner_b` of feature b that crosses the cycle of faces closed by leftover edge `cycle` of `hc` an odd
  /// number of times: such a path cannot split its patch (a closed curve meets it once, mod 2), so it cuts a
  /// handle. Shortest such path (parity-doubled Dijkstra); empty if none exists or the shortest is not simple.
  Halfedge_path handle_cutting_path(int a, int b, int corner_a, int corner_b, const Handle_cycles& hc,
                                    WE cycle) const {
    std::vector<char> flips(m.number_of_edges(), 0);
    flips[cycle] ^= 1;
    for (WH side : {m.halfedge(cycle), m.opposite(m.halfedge(cycle))})
      for (WF f = m.face(side); hc.cotree_parent[f] != WH(); f = m.face(m.opposite(hc.cotree_parent[f])))
        flips[m.edge(hc.cotree_parent[f])] ^= 1;
    const WV va = feature_vertex[a], vb = feature_vertex[b];
    const std::size_t nv = m.number_of_vertices();
    std::vector<double> dist(2 * nv, HUGE_VAL);
    std::vector<WH> pred(2 * nv, WH());
    using QE = std::pair<double, std::size_t>;
    std::priority_queue<QE, std::vector<QE>, std::greater<QE>> q;
    auto state = [&](WV v, int parity) { return 2 * std::size_t(v) + std::size_t(parity); };
    auto relax = [&](WH h, int parity, double d) {
      const WV w = m.target(h);
      if (w == vb) {
        if (corner_of_outgoing(m.opposite(h)) != corner_b) return;
      } else if (!is_free(w)) {
        return;
      }
      const int np = parity ^ flips[m.edge(h)];
      const double nd = d + edge_length(h);
      if (nd < dist[state(w, np)]) {
        dist[state(w, np)] = nd;
        pred[state(w, np)] = h;
        q.push({nd, state(w, np)});
      }
    };
    for (WH h : CGAL::halfedges_around_source(va, m))
      if (path_of(h) == no_path && corner_of_outgoing(h) == corner_a) relax(h, 0, 0);
    const std::size_t goal = state(vb, 1);
    while (!q.empty()) {
      auto [d, st] = q.top();
      q.pop();
      if (d > dist[st]) continue;
      if (st == goal) break;
      const WV v(WV::size_type(st / 2));
      if (v == vb) continue;
      for (WH h : CGAL::halfedges_around_source(v, m))
        if (path_of(h) == no_path) relax(h, int(st % 2), d);
    }
    if (dist[goal] == HUGE_VAL) return {};
    Halfedge_path hp;
    std::vector<char> used(nv, 0);
    for (std::size_t st = goal;;) {
      const WH h = pred[st];
      hp.push_back(h);
      const WV s = m.source(h);
      if (s == va) break;
      if (used[s]) return {}; // visits a vertex in both parities: not simple
      used[s] = 1;
      st = state(s, int(st % 2) ^ flips[m.edge(h)]);
    }
    std::reverse(hp.begin(), hp.end());
    return hp;
  }

  /// An input vertex at or next to working vertex v (a split vertex is replaced by an end of its split edge).
  std::size_t input_vertex_near(WV v) const {
    std::size_t i = std::size_t(v);
    for (auto it = splits.rbegin(); it != splits.rend() && i >= n_original_vertices; ++it)
      if (it->w == i) i = it->u;
    return i;
  }

  // ---- face paths (paper §3.2, Fig. 3) ----

  Point_3 face_centroid(WF f) const {
    WH h = m.halfedge(f);
    return CGAL::centroid(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))));
  }

  /// The new vertex of split_edge(u, v, t) as a point of the original mesh: the original face o (of the faces
  /// at halfedge (u, v), then at its opposite, the first that holds both ends) and its barycentrics r there.
  bool split_rep(WV u, WV v, double t, int& o, std::array<double, 3>& r) const {
    const WH h = m.halfedge(u, v);
    std::array<double, 3> ru, rv;
    for (const int c : {forig[m.face(h)], forig[m.face(m.opposite(h))]})
      if (rep_in(u, c, ru) && rep_in(v, c, rv)) {
        o = c;
        for (int k = 0; k < 3; ++k) r[k] = (1 - t) * ru[k] + t * rv[k];
        return true;
      }
    return false;
  }
  /// The new vertex of split_face(f, b) as barycentrics r in f's original face.
  bool insert_rep(WF f, const std::array<double, 3>& b, std::array<double, 3>& r) const {
    const WH h = m.halfedge(f);
    const WV vs[3] = {m.source(h), m.target(h), m.target(m.next(h))};
    r = {0, 0, 0};
    for (int i = 0; i < 3; ++i) {
      std::array<double, 3> ri;
      if (!rep_in(vs[i], forig[f], ri)) return false;
      for (int k = 0; k < 3; ++k) r[k] += b[i] * ri[k];
    }
    return true;
  }

  /// Splits edge (u, v) at u + t (v - u) (the midpoint by default), keeping every bookkeeping up to date.
  WV split_edge(WV u, WV v, double t = 0.5) {
    const Point_3 &pu = m.point(u), &pv = m.point(v);
    Point_3 p = t == 0.5 ? CGAL::midpoint(pu, pv)
                         : Point_3(pu.x() + t * (pv.x() - pu.x()), pu.y() + t * (pv.y() - pu.y()), pu.z() + t * (pv.z() - pu.z()));
    WH h = m.halfedge(u, v);
    const int oa = forig[m.face(h)], ob = forig[m.face(m.opposite(h))];
    const WV xa = m.target(m.next(h)); // opposite corner on h's side: its faces inherit oa, the others ob
    int o;
    std::array<double, 3> r;
    if (!split_rep(u, v, t, o, r)) throw Algorithm_error("internal error: split edge lies in no original face");
    WV w = split_edge_and_triangulate(m, m.points(), u, v, p);
    splits.push_back({std::size_t(u), std::size_t(v), std::size_t(w), t});
    record_new_vertex(w, o, r, std::array<WV, 2>{{u, v}}, std::array<double, 2>{{1 - t, t}});
    for (WF f : CGAL::faces_around_target(m.halfedge(w), m)) {
      bool has_a = false;
      for (WV x : CGAL::vertices_around_face(m.halfedge(f), m)) has_a |= (x == xa);
      forig[f] = has_a ? oa : ob;
    }
    return w;
  }

  /// Splits face f into three at the point with barycentrics b (in f's halfedge order: source(h), target(h),
  /// target(next(h)), h = halfedge(f)); returns the new vertex (the last one). Not recorded in `splits`: used by
  /// the remeshing, whose meshes are not replayed on the user's.
  WV split_face(WF f, const std::array<double, 3>& b) {
    WH h = m.halfedge(f);
    const WV vs[3] = {m.source(h), m.target(h), m.target(m.next(h))};
    const int o = forig[f];
    std::array<double, 3> r;
    if (!insert_rep(f, b, r)) throw Algorithm_error("internal error: split face lies in no original face");
    const Point_3 q = barycentric_point(m.point(vs[0]), m.point(vs[1]), m.point(vs[2]), b);
    WH hc = CGAL::Euler::add_center_vertex(h, m);
    WV w = m.target(hc);
    m.point(w) = q;
    for (WF g : CGAL::faces_around_target(hc, m)) forig[g] = o;
    record_new_vertex(w, o, r, std::array<WV, 3>{{vs[0], vs[1], vs[2]}}, b);
    return w;
  }

  /// Records a new vertex w as the point with barycentrics r of original face o, and its descriptor as the
  /// blend of its corners' `from` with weights `wts`.
  template <std::size_t N>
  void record_new_vertex(WV w, int o, const std::array<double, 3>& r, const std::array<WV, N>& from,
                         const std::array<double, N>& wts) {
    if (!desc.empty()) {
      std::vector<float> dm(desc[from[0]].size());
      for (std::size_t k = 0; k < dm.size(); ++k) {
        double x = 0;
        for (std::size_t i = 0; i < N; ++i) x += wts[i] * desc[from[i]][k];
        dm[k] = float(x);
      }
      if (desc.size() <= std::size_t(w)) desc.resize(std::size_t(w) + 1);
      desc[w] = std::move(dm);
    }
    if (vrep.size() <= std::size_t(w)) vrep.resize(std::size_t(w) + 1);
    vrep[w] = {o, r};
  }

  /// The edges crossed by a shortest path through the faces of one patch, from sector `corner_a` of
  /// feature a to sector `corner_b` of feature b, as vertex pairs (stable under splits of other edges).
  /// Throws Algorithm_error if the sectors do not share a patch.
  std::vector<std::pair<WV, WV>> face_path_crossings(int a, int b, int corner_a, int corner_b) const {
    WV va = feature_vertex[a], vb = feature_vertex[b];
    std::vector<WF> src = sector_faces(va, corner_a);
    std::vector<WF> dst = sector_faces(vb, corner_b);
    const std::size_t nfaces = m.number_of_faces();
    std::vector<double> dist(nfaces, std::numeric_limits<double>::infinity());
    std::vector<WH> pred(nfaces, WH()); // halfedge crossed to enter the face (in the face entered)
    std::vector<char> is_dst(nfaces, 0), done(nfaces, 0);
    for (WF f : dst) is_dst[f] = 1;
    using QE = std::pair<double, std::uint32_t>;
    std::priority_queue<QE, std::vector<QE>, std::greater<QE>> q;
    for (WF f : src) {
      dist[f] = 0;
      q.push({0.0, std::uint32_t(f)});
    }
    WF reached;
    bool ok = false;
    while (!q.empty()) {
      auto [d, fi] = q.top();
      q.pop();
      WF f(fi);
      if (done[fi]) continue;
      done[fi] = 1;
      if (is_dst[fi]) {
        reached = f;
        ok = true;
        break;
      }
      Point_3 cf = face_centroid(f);
      for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        if (path_of(h) != no_path) continue;
        WH ho = m.opposite(h);
        WF g = m.face(ho);
        if (done[g]) continue;
        // Crossing an edge with no free endpoint costs a split: prefer the faces of free vertices.
        double w = std::sqrt(CGAL::squared_distance(cf, face_centroid(g)));
        if (!is_free(m.source(h)) && !is_free(m.target(h))) w *= 2;
        double nd = d + w + 1e-12;
        if (nd < dist[g]) {
          dist[g] = nd;
          pred[g] = ho;
          q.push({nd, std::uint32_t(g)});
        }
      }
    }
    if (!ok) throw Algorithm_error("internal error: no face path between two sectors of one patch");
    std::vector<std::pair<WV, WV>> crossed;
    for (WF f = reached; pred[f] != WH(); f = m.face(m.opposite(pred[f])))
      crossed.push_back({m.source(pred[f]), m.target(pred[f])});
    std::reverse(crossed.begin(), crossed.end());
    return crossed;
  }

  /// Turns a face path into an edge path (paper Fig. 3): each crossed edge is passed through one of its free
  /// endpoints when there is one, otherwise split at its midpoint. With `dry_run` nothing is changed and only
  /// the number of splits needed is returned in `split_count`. Returns the vertices of the path.
  std::vector<WV> walk_face_path(int a, int b, const std::vector<std::pair<WV, WV>>& crossed, bool dry_run,
                                 std::size_t& split_count) {
    WV va = feature_vertex[a], vb = feature_vertex[b];
    std::vector<WV> verts{va};
    std::vector<char> on_new_path; // by vertex index, grows with splits
    auto visited = [&](WV v) { return std::size_t(v) < on_new_path.size() && on_new_path[v]; };
    auto visit = [&](WV v) {
      if (on_new_path.size() <= std::size_t(v)) on_new_path.resize(std::size_t(v) + 1, 0);
      on_new_path[v] = 1;
    };
    visit(va);
    split_count = 0;
    WV c = va;
    for (std::size_t i = 0; i < crossed.size(); ++i) {
      auto [p, q2] = crossed[i];
      if (c == p || c == q2) continue;
      auto usable = [&](WV x) { return is_free(x) && !visited(x); };
      WV next_v;
      bool have = false;
      // Prefer an endpoint that also bounds the next crossed edge: the path then skips that edge.
      if (i + 1 < crossed.size()) {
        for (WV x : {p, q2})
          if (!have && usable(x) && (x == crossed[i + 1].first || x == crossed[i + 1].second)) {
            next_v = x;
            have = true;
          }
      }
      for (WV x : {p, q2})
        if (!have && usable(x)) {
          next_v = x;
          have = true;
        }
      if (!have) {
        ++split_count;
        if (dry_run) {
          c = WV(); // a new vertex: never an endpoint of a later crossed edge
          continue;
        }
        next_v = split_edge(p, q2);
      }
      visit(next_v);
      verts.push_back(next_v);
      c = next_v;
    }
    verts.push_back(vb);
    return verts;
  }

  std::vector<WV> trace_face_path(int a, int b, int corner_a, int corner_b) {
    std::size_t n = 0;
    return walk_face_path(a, b, face_path_crossings(a, b, corner_a, corner_b), false, n);
  }

  /// Number of edge splits `trace_face_path` would need, without changing anything.
  std::size_t face_path_split_count(int a, int b, int corner_a, int corner_b) {
    std::size_t n = 0;
    walk_face_path(a, b, face_path_crossings(a, b, corner_a, corner_b), true, n);
    return n;
  }

  Halfedge_path halfedges_of(const std::vector<WV>& verts) const {
    Halfedge_path hp;
    for (std::size_t i = 0; i + 1 < verts.size(); ++i) {
      auto h = m.halfedge(verts[i], verts[i + 1]);
      if (h == WH()) throw Algorithm_error("internal error: traced path uses a missing edge");
      hp.push_back(h);
    }
    return hp;
  }
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_LAYOUT_MESH_H

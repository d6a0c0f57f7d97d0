// SPDX-License-Identifier: GPL-3.0-or-later
// Independent check that two patch layouts are topologically identical triangular layouts over one base
// mesh. It trusts nothing of the builder: it reads the refined meshes, the per-face base-triangle ids and
// the path vertex lists, and proves
//   1. the base mesh is a simple, closed, consistently oriented triangulation of the meshes' surface (its
//      Euler characteristic V - E + F = 2 - 2g is the meshes', which must agree), every base edge carried by
//      exactly one path id;
//   2. on each mesh every path is a simple edge path between its two features, paths are disjoint except
//      at shared endpoints and never pass through a feature;
//   3. on each mesh two faces across a non-path edge lie in the same patch, and across an edge of path
//      (a,b) the face on the left of a->b lies in the base triangle containing a->b and the face on the
//      right in the one containing b->a (this fixes the cyclic order of paths at every corner);
//   4. every patch is non-empty, connected and a topological disk (Euler characteristic 1).
// With one base mesh for both meshes, 1-4 mean the layouts are topologically identical: the same neighbours and
// the same cyclic orders of paths at every feature, every patch a disk on both meshes (for genus g > 0 too:
// then no patch may keep a handle, which 4 rules out).
#ifndef CROSSPARAM_LAYOUT_VERIFICATION_H
#define CROSSPARAM_LAYOUT_VERIFICATION_H

#include <crossparam/layout_types.h>

#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/number_utils.h>

#include <boost/graph/graph_traits.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <string>

namespace crossparam {

namespace internal {

/// Euler characteristic V - E + F of a closed face graph.
template <class FaceGraph>
long euler_characteristic(const FaceGraph& tm) {
  return long(std::distance(vertices(tm).begin(), vertices(tm).end())) -
         long(std::distance(edges(tm).begin(), edges(tm).end())) +
         long(std::distance(faces(tm).begin(), faces(tm).end()));
}

inline bool verify_base_mesh(const Patch_layout& L, std::size_t nfeat, long euler, std::string& msg) {
  std::map<std::pair<std::size_t, std::size_t>, int> directed; // directed edge -> triangle
  std::set<std::array<std::size_t, 3>> seen;
  std::vector<char> used(nfeat, 0);
  for (std::size_t t = 0; t < L.base_triangles.size(); ++t) {
    const auto& tri = L.base_triangles[t];
    for (int i = 0; i < 3; ++i) {
      if (tri[i] >= nfeat) return msg = "base triangle " + std::to_string(t) + " uses a missing feature", false;
      used[tri[i]] = 1;
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      return msg = "base triangle " + std::to_string(t) + " repeats a feature", false;
    auto sorted = tri;
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(sorted).second) return msg = "two base triangles have the same corners", false;
    for (int i = 0; i < 3; ++i)
      if (!directed.insert({{tri[i], tri[(i + 1) % 3]}, int(t)}).second)
        return msg = "base mesh is not consistently oriented at edge " + std::to_string(tri[i]) + "-" +
                     std::to_string(tri[(i + 1) % 3]),
               false;
  }
  for (auto& [e, t] : directed)
    if (!directed.count({e.second, e.first}))
      return msg = "base mesh is open at edge " + std::to_string(e.first) + "-" + std::to_string(e.second), false;
  for (std::size_t f = 0; f < nfeat; ++f)
    if (!used[f]) return msg = "feature " + std::to_string(f) + " is not a corner of the base mesh", false;
  const long V = long(nfeat), E = long(directed.size() / 2), F = long(L.base_triangles.size());
  if (V - E + F != euler)
    return msg = "base mesh has Euler characteristic " + std::to_string(V - E + F) + ", the meshes " +
                 std::to_string(euler),
           false;
  if (L.base_edges.size() != std::size_t(E))
    return msg = "number of paths (" + std::to_string(L.base_edges.size()) + ") differs from base edges (" +
                 std::to_string(E) + ")",
           false;
  std::set<std::pair<std::size_t, std::size_t>> carried;
  for (std::size_t p = 0; p < L.base_edges.size(); ++p) {
    auto [a, b] = L.base_edges[p];
    if (!directed.count({a, b})) return msg = "path " + std::to_string(p) + " is not a base edge", false;
    if (!carried.insert({std::min(a, b), std::max(a, b)}).second)
      return msg = "two paths carry base edge " + std::to_string(a) + "-" + std::to_string(b), false;
  }
  return true;
}

template <class TriangleMesh>
bool verify_mesh_layout(const TriangleMesh& tm, const Patch_layout& L, const Mesh_layout& M, const char* name,
                        std::string& msg) {
  using vertex_descriptor = typename boost::graph_traits<TriangleMesh>::vertex_descriptor;
  using halfedge_descriptor = typename boost::graph_traits<TriangleMesh>::halfedge_descriptor;
  using face_descriptor = typename boost::graph_traits<TriangleMesh>::face_descriptor;
  std::vector<vertex_descriptor> V(vertices(tm).begin(), vertices(tm).end());
  std::vector<face_descriptor> Fs(faces(tm).begin(), faces(tm).end());
  std::map<vertex_descriptor, std::size_t> vid;
  for (std::size_t i = 0; i < V.size(); ++i) vid[V[i]] = i;
  std::map<face_descriptor, std::size_t> fid;
  for (std::size_t i = 0; i < Fs.size(); ++i) fid[Fs[i]] = i;
  auto fail = [&](const std::string& m) {
    msg = std::string(name) + ": " + m;
    return false;
  };
  if (M.face_triangle.size() != Fs.size()) return fail("face labels do not match the face count");
  for (int t : M.face_triangle)
    if (t < 0 || std::size_t(t) >= L.base_triangles.size()) return fail("a face has an invalid base triangle id");
  const std::size_t nfeat = M.feature_vertices.size();
  std::vector<int> feature_of(V.size(), -1);
  for (std::size_t k = 0; k < nfeat; ++k) {
    if (M.feature_vertices[k] >= V.size()) return fail("feature vertex out of range");
    feature_of[M.feature_vertices[k]] = int(k);
  }
  // Directed base edge -> triangle id.
  std::map<std::pair<std::size_t, std::size_t>, int> tri_of;
  for (std::size_t t = 0; t < L.base_triangles.size(); ++t)
    for (int i = 0; i < 3; ++i) tri_of[{L.base_triangles[t][i], L.base_triangles[t][(i + 1) % 3]}] = int(t);

  // 2. Paths.
  if (M.paths.size() != L.base_edges.size()) return fail("path count differs from the base mesh");
  std::vector<int> vertex_path(V.size(), -1);
  std::map<halfedge_descriptor, std::pair<int, int>> path_halfedge; // h -> (path, +1 along / -1 against)
  for (std::size_t p = 0; p < M.paths.size(); ++p) {
    const auto& vs = M.paths[p];
    const std::string ps = "path " + std::to_string(p);
    if (vs.size() < 2) return fail(ps + " is empty");
    if (vs.front() != M.feature_vertices[L.base_edges[p][0]] || vs.back() != M.feature_vertices[L.base_edges[p][1]])
      return fail(ps + " does not join its features");
    for (std::size_t i = 0; i < vs.size(); ++i) {
      if (vs[i] >= V.size()) return fail(ps + " has a vertex out of range");
      if (i > 0 && i + 1 < vs.size()) {
        if (feature_of[vs[i]] >= 0) return fail(ps + " passes through feature " + std::to_string(feature_of[vs[i]]));
        if (vertex_path[vs[i]] >= 0) return fail(ps + " crosses path " + std::to_string(vertex_path[vs[i]]));
        vertex_path[vs[i]] = int(p);
      }
      if (i + 1 < vs.size()) {
        auto h = halfedge(V[vs[i]], V[vs[i + 1]], tm);
        if (!h.second) return fail(ps + " uses a missing edge");
        if (path_halfedge.count(h.first) || path_halfedge.count(opposite(h.first, tm)))
          return fail(ps + " shares an edge with another path");
        path_halfedge[h.first] = {int(p), +1};
        path_halfedge[opposite(h.first, tm)] = {int(p), -1};
      }
    }
  }

  // 3. Labels across edges. Base triangles are counter-clockwise seen from outside; a mesh oriented inward
  // (negative signed volume) sees every patch from the other side.
  double volume = 0;
  {
    // Signed volume in coordinates scaled to the bounding box: meaningful at any input scale.
    auto vpm = get(CGAL::vertex_point, tm);
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (auto v : vertices(tm)) {
      const auto& p = get(vpm, v);
      double c[3] = {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
      for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], c[i]), hi[i] = std::max(hi[i], c[i]);
    }
    double scale = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    if (!(scale > 0)) scale = 1;
    auto P = [&](auto v, double out[3]) {
      const auto& p = get(vpm, v);
      out[0] = (CGAL::to_double(p.x()) - lo[0]) / scale;
      out[1] = (CGAL::to_double(p.y()) - lo[1]) / scale;
      out[2] = (CGAL::to_double(p.z()) - lo[2]) / scale;
    };
    for (auto f : faces(tm)) {
      auto h = halfedge(f, tm);
      double a[3], b[3], c[3];
      P(source(h, tm), a);
      P(target(h, tm), b);
      P(target(next(h, tm), tm), c);
      volume += a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
  }
  const bool inward = volume < 0;
  for (auto h : halfedges(tm)) {
    if (is_border(h, tm) || is_border(opposite(h, tm), tm)) return fail("mesh is not closed");
    int tl = M.face_triangle[fid[face(h, tm)]];
    int tr = M.face_triangle[fid[face(opposite(h, tm), tm)]];
    auto it = path_halfedge.find(h);
    if (it == path_halfedge.end()) {
      if (tl != tr) return fail("two patches meet along an edge that is on no path");
      continue;
    }
    auto [p, dir] = it->second;
    std::size_t a = L.base_edges[p][0], b = L.base_edges[p][1];
    if ((dir < 0) != inward) std::swap(a, b);
    auto expected = tri_of.find({a, b});
    if (expected == tri_of.end() || expected->second != tl)
      return fail("the face left of path " + std::to_string(p) + " is not in the base triangle of that side");
  }

  // 4. Each patch non-empty, connected, a disk.
  const std::size_t nt = L.base_triangles.size();
  std::vector<long> fcount(nt, 0), ecount2(nt, 0), vcount(nt, 0);
  std::vector<char> reached(Fs.size(), 0);
  std::vector<int> first_face(nt, -1);
  for (std::size_t f = 0; f < Fs.size(); ++f) {
    int t = M.face_triangle[f];
    ++fcount[t];
    if (first_face[t] < 0) first_face[t] = int(f);
  }
  for (std::size_t t = 0; t < nt; ++t) {
    if (first_face[t] < 0) return fail("base triangle " + std::to_string(t) + " has no faces");
    // Connectivity by flood fill inside the label.
    std::vector<std::size_t> stack{std::size_t(first_face[t])};
    reached[first_face[t]] = 1;
    long n = 0;
    while (!stack.empty()) {
      std::size_t f = stack.back();
      stack.pop_back();
      ++n;
      for (auto h : CGAL::halfedges_around_face(halfedge(Fs[f], tm), tm)) {
        std::size_t g = fid[face(opposite(h, tm), tm)];
        if (!reached[g] && M.face_triangle[g] == int(t)) {
          reached[g] = 1;
          stack.push_back(g);
        }
      }
    }
    if (n != fcount[t]) return fail("patch " + std::to_string(t) + " is not connected");
  }
  // Euler characteristic of each closed patch: V - E + F over the elements touching it.
  for (auto h : halfedges(tm)) {
    int t = M.face_triangle[fid[face(h, tm)]];
    int to = M.face_triangle[fid[face(opposite(h, tm), tm)]];
    ecount2[t] += (t == to) ? 1 : 2; // interior edges are seen twice, boundary edges once per side
  }
  for (auto v : vertices(tm)) {
    std::set<int> ts;
    for (auto f : CGAL::faces_around_target(halfedge(v, tm), tm)) ts.insert(M.face_triangle[fid[f]]);
    for (int t : ts) ++vcount[t];
  }
  for (std::size_t t = 0; t < nt; ++t) {
    long chi = vcount[t] - ecount2[t] / 2 + fcount[t];
    if (chi != 1) return fail("patch " + std::to_string(t) + " is not a disk (Euler characteristic " + std::to_string(chi) + ")");
  }
  return true;
}

} // namespace internal

/// \brief Checks, without trusting the builder, that `layout` describes topologically identical
/// triangular patch layouts of the refined meshes `tm_s` and `tm_t` (see the file comment for what is proved).
///
/// \tparam SourceMesh, TargetMesh models of `FaceListGraph` with an internal `vertex_point` property map (e.g.
///         `CGAL::Surface_mesh`, `CGAL::Polyhedron_3` with item ids).
/// \param layout the layouts as `compute_patch_layouts` returns them, for `tm_s` and `tm_t` as refined.
/// \returns `valid`, or the first problem found. Purely combinatorial (coordinates only name problems).
template <class SourceMesh, class TargetMesh>
Layout_verification verify_patch_layouts(const SourceMesh& tm_s, const TargetMesh& tm_t, const Patch_layout& layout) {
  Layout_verification r;
  if (layout.source.feature_vertices.size() != layout.target.feature_vertices.size()) {
    r.valid = false;
    r.message = "feature counts differ";
    return r;
  }
  const long euler = internal::euler_characteristic(tm_s);
  if (internal::euler_characteristic(tm_t) != euler) {
    r.valid = false;
    r.message = "the meshes have different Euler characteristics";
    return r;
  }
  if (!internal::verify_base_mesh(layout, layout.source.feature_vertices.size(), euler, r.message) ||
      !internal::verify_mesh_layout(tm_s, layout, layout.source, "source", r.message) ||
      !internal::verify_mesh_layout(tm_t, layout, layout.target, "target", r.message))
    r.valid = false;
  return r;
}

} // namespace crossparam

#endif // CROSSPARAM_LAYOUT_VERIFICATION_H

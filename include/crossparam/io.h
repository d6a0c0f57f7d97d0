// SPDX-License-Identifier: GPL-3.0-or-later
// Input and output: robust mesh reading and validation, feature correspondences, atomic file writing.
//
// Reading never hands a file to CGAL's readers (they crash on malformed input, see NOTES-CGAL.md): our own
// readers (internal/soup_readers.h) produce a polygon soup, soup_to_triangle_mesh() validates it completely
// and only then builds the mesh, with vertex k = point k and face k = polygon k.
#ifndef CROSSPARAM_IO_H
#define CROSSPARAM_IO_H

#include <crossparam/errors.h>
#include <crossparam/internal/soup_readers.h>
#include <crossparam/types.h>

#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/boost/graph/named_params_helper.h>
#include <CGAL/boost/graph/properties.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numeric>
#include <ostream>
#include <random>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace crossparam {

/// Reads an OFF (also COFF/NOFF/CNOFF/STOFF), OBJ, PLY (ascii/binary) or STL (ascii/binary) file as a polygon
/// soup, chosen by the (case-insensitive) extension. Throws Input_error("<path>: [line N: ]<problem>") for any
/// defect; never crashes and never allocates more than the file size justifies.
inline Polygon_soup read_polygon_soup(const std::string& path) {
  return internal::soup_io::read_polygon_soup(path);
}

/// What validation found (besides errors, which throw).
struct Mesh_check_report {
  std::size_t reoriented_faces = 0;   ///< faces whose orientation was flipped to make it consistent
  int genus = 0;                      ///< from the Euler characteristic V - E + F = 2 - 2g
  std::vector<std::string> warnings;  ///< human-readable, each starts with the mesh name
};

namespace internal {

struct Union_find {
  std::vector<std::size_t> parent;
  explicit Union_find(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t(0)); }
  std::size_t find(std::size_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

/// Numbers the vertices (or faces) of a mesh 0, 1, ... in iteration order. Works for meshes with removed
/// elements (a Surface_mesh with garbage), unlike the mesh's own index map.
template <class Range>
auto number_in_order(const Range& range) {
  using Descriptor = std::decay_t<decltype(*std::begin(range))>;
  std::unordered_map<Descriptor, std::size_t> index;
  std::size_t i = 0;
  for (const Descriptor d : range) index.emplace(d, i++);
  return index;
}

inline std::string edge_name(std::size_t a, std::size_t b) {
  return "(" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

} // namespace internal

/// Validates `soup` as a closed, edge- and vertex-manifold, connected, orientable triangle mesh with finite
/// coordinates and no unused points, and builds it into `tm` (cleared first): vertex k of `tm` (in vertices(tm)
/// order; for Surface_mesh the vertex index) is point k and face k is polygon k. Inconsistently oriented faces
/// are flipped (the minority, counted in reoriented_faces, with a warning). Zero-area faces are accepted.
/// Throws Input_error("<name>: <problem>").
template <class TriangleMesh>
Mesh_check_report soup_to_triangle_mesh(const Polygon_soup& soup, TriangleMesh& tm, const std::string& name) {
  using internal::edge_name;
  using std::to_string;
  auto fail = [&](const std::string& msg) { throw Input_error(name + ": " + msg); };
  const std::size_t nv = soup.points.size();
  const std::size_t nf = soup.polygons.size();
  if (nf == 0) fail("the mesh has no faces");

  for (std::size_t i = 0; i < nv; ++i) {
    const std::string problem = internal::soup_io::coordinates_problem(soup.points[i]);
    if (!problem.empty()) fail("vertex " + to_string(i) + ": " + problem);
  }

  // Triangles, indices, degenerate faces.
  std::vector<std::array<std::size_t, 3>> tris(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const std::vector<std::size_t>& poly = soup.polygons[f];
    if (poly.size() != 3)
      fail("face " + to_string(f) + " has " + to_string(poly.size()) +
           " vertices: only triangle meshes are supported (non-triangle face)");
    for (int k = 0; k < 3; ++k) {
      if (poly[k] >= nv)
        fail("face " + to_string(f) + " refers to vertex " + to_string(poly[k]) + " but there are only " +
             to_string(nv) + " vertices (index out of range)");
      tris[f][k] = poly[k];
    }
    for (int k = 0; k < 3; ++k)
      if (tris[f][k] == tris[f][(k + 1) % 3])
        fail("face " + to_string(f) + " is degenerate: it uses vertex " + to_string(tris[f][k]) + " twice");
  }

  // Unused points.
  {
    std::vector<char> used(nv, 0);
    for (const auto& t : tris)
      for (std::size_t v : t) used[v] = 1;
    const std::size_t unused = static_cast<std::size_t>(std::count(used.begin(), used.end(), char(0)));
    if (unused > 0) {
      const std::size_t first = static_cast<std::size_t>(std::find(used.begin(), used.end(), char(0)) - used.begin());
      fail("vertex " + to_string(first) + " is not used by any face (unused vertex" +
           (unused > 1 ? "; " + to_string(unused) + " unused vertices in total)" : std::string(")")));
    }
  }

  // Duplicate faces (same vertex set).
  {
    std::vector<std::pair<std::array<std::size_t, 3>, std::size_t>> sorted(nf);
    for (std::size_t f = 0; f < nf; ++f) {
      sorted[f].first = tris[f];
      std::sort(sorted[f].first.begin(), sorted[f].first.end());
      sorted[f].second = f;
    }
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 1; i < nf; ++i)
      if (sorted[i].first == sorted[i - 1].first) {
        const auto& t = sorted[i].first;
        fail("faces " + to_string(sorted[i - 1].second) + " and " + to_string(sorted[i].second) +
             " are duplicate faces (both use vertices " + to_string(t[0]) + ", " + to_string(t[1]) + ", " +
             to_string(t[2]) + ")");
      }
  }

  // Edges: every face side as (min, max, face, local index k: side from corner k to corner k+1).
  struct Side {
    std::size_t a, b, f;
    int k;
    bool operator<(const Side& o) const {
      if (a != o.a) return a < o.a;
      if (b != o.b) return b < o.b;
      return f < o.f;
    }
  };
  std::vector<Side> sides;
  sides.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const std::size_t u = tris[f][k], w = tris[f][(k + 1) % 3];
      sides.push_back(Side{std::min(u, w), std::max(u, w), f, k});
    }
  std::sort(sides.begin(), sides.end());
  std::vector<std::pair<std::size_t, std::size_t>> groups;  // [begin, end) in sides, one per undirected edge
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i + 1;
    while (j < sides.size() && sides[j].a == sides[i].a && sides[j].b == sides[i].b) ++j;
    groups.emplace_back(i, j);
    i = j;
  }
  {
    std::size_t non_manifold = 0, boundary = 0;
    const std::pair<std::size_t, std::size_t>*first_nm = nullptr, *first_boundary = nullptr;
    for (const auto& g : groups) {
      const std::size_t n = g.second - g.first;
      if (n > 2 && non_manifold++ == 0) first_nm = &g;
      if (n == 1 && boundary++ == 0) first_boundary = &g;
    }
    if (non_manifold > 0) {
      const Side& s = sides[first_nm->first];
      std::string faces;
      for (std::size_t i = first_nm->first; i < first_nm->second; ++i)
        faces += (i == first_nm->first ? "" : ", ") + to_string(sides[i].f);
      fail("non-manifold edge " + edge_name(s.a, s.b) + " is shared by " + to_string(first_nm->second - first_nm->first) +
           " faces (" + faces + ")" +
           (non_manifold > 1 ? "; " + to_string(non_manifold) + " non-manifold edges in total" : std::string()));
    }
    if (boundary > 0) {
      const Side& s = sides[first_boundary->first];
      fail("the mesh is open: it has " + to_string(boundary) + " boundary edge" + (boundary > 1 ? "s" : "") +
           ", e.g. edge " + edge_name(s.a, s.b) + " of face " + to_string(s.f) + " (only closed meshes are supported)");
    }
  }
  const std::size_t ne = groups.size();

  // Non-manifold vertices: corners (3f + k) at the same vertex are joined across the edges they share; a
  // manifold vertex ends up with exactly one fan.
  {
    auto corner = [&](std::size_t f, std::size_t v) -> std::size_t {
      for (std::size_t k = 0; k < 3; ++k)
        if (tris[f][k] == v) return 3 * f + k;
      return 3 * f;  // unreachable
    };
    internal::Union_find corners(3 * nf);
    for (const auto& g : groups) {
      const Side& s1 = sides[g.first];
      const Side& s2 = sides[g.first + 1];
      corners.unite(corner(s1.f, s1.a), corner(s2.f, s1.a));
      corners.unite(corner(s1.f, s1.b), corner(s2.f, s1.b));
    }
    const std::size_t none = static_cast<std::size_t>(-1);
    std::vector<std::size_t> fan(nv, none);
    std::vector<char> bad(nv, 0);
    for (std::size_t c = 0; c < 3 * nf; ++c) {
      const std::size_t v = tris[c / 3][c % 3];
      const std::size_t r = corners.find(c);
      if (fan[v] == none) fan[v] = r;
      else if (fan[v] != r) bad[v] = 1;
    }
    const std::size_t n_bad = static_cast<std::size_t>(std::count(bad.begin(), bad.end(), char(1)));
    if (n_bad > 0) {
      const std::size_t v = static_cast<std::size_t>(std::find(bad.begin(), bad.end(), char(1)) - bad.begin());
      fail("non-manifold vertex " + to_string(v) + ": the faces around it form more than one fan" +
           (n_bad > 1 ? " (" + to_string(n_bad) + " non-manifold vertices in total)" : std::string()));
    }
  }

  // Face adjacency: neighbour across side k, and whether both faces run the edge in the same direction.
  std::vector<std::array<std::size_t, 3>> neighbour(nf);
  std::vector<std::array<bool, 3>> same_direction(nf);
  for (const auto& g : groups) {
    const Side& s1 = sides[g.first];
    const Side& s2 = sides[g.first + 1];
    const bool d1 = tris[s1.f][s1.k] == s1.a;  // runs a -> b
    const bool d2 = tris[s2.f][s2.k] == s2.a;
    neighbour[s1.f][s1.k] = s2.f;
    neighbour[s2.f][s2.k] = s1.f;
    same_direction[s1.f][s1.k] = same_direction[s2.f][s2.k] = (d1 == d2);
  }

  // Connected components.
  {
    internal::Union_find comp(nf);
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) comp.unite(f, neighbour[f][k]);
    std::size_t n_comp = 0;
    for (std::size_t f = 0; f < nf; ++f)
      if (comp.find(f) == f) ++n_comp;
    if (n_comp > 1)
      fail("the mesh has " + to_string(n_comp) + " connected components (only a single connected surface is supported)");
  }

  // Orientation: breadth-first from face 0.
  std::size_t flipped = 0;
  {
    std::vector<signed char> flip(nf, -1);
    std::vector<std::size_t> queue;
    queue.reserve(nf);
    flip[0] = 0;
    queue.push_back(0);
    for (std::size_t qi = 0; qi < queue.size(); ++qi) {
      const std::size_t f = queue[qi];
      for (int k = 0; k < 3; ++k) {
        const std::size_t g = neighbour[f][k];
        const signed char want = static_cast<signed char>(flip[f] ^ (same_direction[f][k] ? 1 : 0));
        if (flip[g] < 0) {
          flip[g] = want;
          queue.push_back(g);
        } else if (flip[g] != want) {
          fail("the surface is not orientable (e.g. a Moebius strip or Klein bottle): faces " + to_string(f) +
               " and " + to_string(g) + " cannot be oriented consistently");
        }
      }
    }
    flipped = static_cast<std::size_t>(std::count(flip.begin(), flip.end(), static_cast<signed char>(1)));
    const bool invert = 2 * flipped > nf;
    if (invert) flipped = nf - flipped;
    for (std::size_t f = 0; f < nf; ++f)
      if ((flip[f] == 1) != invert) std::swap(tris[f][1], tris[f][2]);
  }

  Mesh_check_report report;
  report.reoriented_faces = flipped;
  if (flipped > 0)
    report.warnings.push_back(name + ": reoriented " + to_string(flipped) + " of " + to_string(nf) +
                              " faces to make the orientation consistent");
  const long long chi = static_cast<long long>(nv) - static_cast<long long>(ne) + static_cast<long long>(nf);
  report.genus = static_cast<int>((2 - chi) / 2);

  // Build the halfedge structure directly: the full connectivity is known and valid, so no incremental
  // add_face (which can fail on intermediate non-manifold configurations) is needed.
  using GT = boost::graph_traits<TriangleMesh>;
  using vertex_descriptor = typename GT::vertex_descriptor;
  using halfedge_descriptor = typename GT::halfedge_descriptor;
  using face_descriptor = typename GT::face_descriptor;
  if (num_vertices(tm) != 0 || num_halfedges(tm) != 0 || num_faces(tm) != 0) CGAL::clear(tm);
  auto vpm = get(CGAL::vertex_point, tm);
  using Point = typename boost::property_traits<decltype(vpm)>::value_type;
  std::vector<vertex_descriptor> vds(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    vds[i] = add_vertex(tm);
    put(vpm, vds[i], Point(soup.points[i][0], soup.points[i][1], soup.points[i][2]));
  }
  std::vector<face_descriptor> fds(nf);
  for (std::size_t f = 0; f < nf; ++f) fds[f] = add_face(tm);
  // Halfedge of face f running from corner k to corner k+1 (after reorientation).
  std::vector<std::array<halfedge_descriptor, 3>> fh(nf);
  for (const auto& g : groups) {
    const Side& s1 = sides[g.first];
    const Side& s2 = sides[g.first + 1];
    const halfedge_descriptor h = halfedge(add_edge(tm), tm);
    auto side_index = [&](const Side& s) {  // local index of the side after a possible swap of corners 1, 2
      for (int k = 0; k < 3; ++k) {
        const std::size_t u = tris[s.f][k], w = tris[s.f][(k + 1) % 3];
        if (std::min(u, w) == s.a && std::max(u, w) == s.b) return k;
      }
      return 0;  // unreachable
    };
    fh[s1.f][side_index(s1)] = h;
    fh[s2.f][side_index(s2)] = opposite(h, tm);
  }
  for (std::size_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const halfedge_descriptor h = fh[f][k];
      const vertex_descriptor v = vds[tris[f][(k + 1) % 3]];
      set_target(h, v, tm);
      set_halfedge(v, h, tm);
      set_face(h, fds[f], tm);
      set_next(h, fh[f][(k + 1) % 3], tm);
    }
    set_halfedge(fds[f], fh[f][2], tm);  // vertices_around_face() then starts at corner 0
  }
  if (!CGAL::is_valid_polygon_mesh(tm))
    throw Algorithm_error(name + ": internal error: the mesh built from a validated soup is not valid");
  // Initialises internal index properties (e.g. Polyhedron_items_with_id_3) in iteration order.
  CGAL::get_initialized_vertex_index_map(tm);
  CGAL::get_initialized_halfedge_index_map(tm);
  CGAL::get_initialized_face_index_map(tm);
  return report;
}

/// read_polygon_soup(path) followed by soup_to_triangle_mesh(soup, tm, path).
template <class TriangleMesh>
Mesh_check_report read_triangle_mesh(const std::string& path, TriangleMesh& tm) {
  return soup_to_triangle_mesh(read_polygon_soup(path), tm, path);
}

/// Validates a mesh built by the caller: valid halfedge structure, triangles only, closed, no isolated or
/// non-manifold vertices, one connected component, finite coordinates with |x| <= 1e100. Returns the genus.
/// Throws Input_error("<name>: <problem>").
template <class TriangleMesh>
Mesh_check_report check_triangle_mesh(const TriangleMesh& tm, const std::string& name) {
  using std::to_string;
  using GT = boost::graph_traits<TriangleMesh>;
  using halfedge_descriptor = typename GT::halfedge_descriptor;
  auto fail = [&](const std::string& msg) { throw Input_error(name + ": " + msg); };

  if (num_faces(tm) == 0) fail("the mesh has no faces");
  const auto vindex = internal::number_in_order(vertices(tm));
  const auto findex = internal::number_in_order(faces(tm));
  auto vim = [&](auto v) { return vindex.at(v); };
  auto fim = [&](auto f) { return findex.at(f); };
  const std::size_t nv = static_cast<std::size_t>(num_vertices(tm));
  const std::size_t nf = static_cast<std::size_t>(num_faces(tm));
  const std::size_t ne = static_cast<std::size_t>(num_edges(tm));

  // CGAL's validity check rejects isolated and pinched (non-manifold) vertices without saying so: look for
  // those first, guarding every step, so that the message names the problem.
  for (auto v : vertices(tm))
    if (halfedge(v, tm) == GT::null_halfedge())
      fail("vertex " + to_string(vim(v)) + " is isolated (unused vertex)");
  std::vector<std::size_t> degree(nv, 0);
  bool pointers_sane = true;
  for (auto h : halfedges(tm)) {
    const auto it = vindex.find(target(h, tm));
    if (it == vindex.end() || next(h, tm) == GT::null_halfedge()) {
      pointers_sane = false;
      break;
    }
    ++degree[it->second];
  }
  if (pointers_sane) {
    for (auto v : vertices(tm)) {
      const std::size_t i = vim(v);
      // A manifold vertex is the target of exactly the halfedges of one cycle around it.
      std::size_t cycle = 0;
      halfedge_descriptor h = halfedge(v, tm);
      do {
        if (target(h, tm) != v || ++cycle > degree[i]) break;
        h = opposite(next(h, tm), tm);
      } while (h != halfedge(v, tm) && vindex.count(target(h, tm)) != 0 && next(h, tm) != GT::null_halfedge());
      if (cycle < degree[i])
        fail("non-manifold vertex " + to_string(i) + ": the faces around it form more than one fan");
    }
  }
  if (!pointers_sane || !CGAL::is_valid_polygon_mesh(tm))
    fail("the mesh is not a valid polygon mesh (inconsistent halfedge connectivity)");

  {
    std::size_t fi = 0;
    for (auto f : faces(tm)) {
      std::size_t deg = 0;
      for (auto h : CGAL::halfedges_around_face(halfedge(f, tm), tm)) {
        (void)h;
        ++deg;
      }
      if (deg != 3) fail("face " + to_string(fi) + " has " + to_string(deg) + " vertices: only triangle meshes are supported (non-triangle face)");
      const halfedge_descriptor h = halfedge(f, tm);
      const auto a = target(h, tm), b = target(next(h, tm), tm), c = source(h, tm);
      if (a == b || b == c || a == c) fail("face " + to_string(fi) + " is degenerate: it uses a vertex twice");
      ++fi;
    }
  }
  {
    std::size_t border = 0;
    for (auto h : halfedges(tm))
      if (CGAL::is_border(h, tm)) ++border;
    if (border > 0)
      fail("the mesh is open: it has " + to_string(border) + " boundary edge" + (border > 1 ? "s" : "") +
           " (only closed meshes are supported)");
  }
  auto vpm = get(CGAL::vertex_point, tm);
  for (auto v : vertices(tm)) {
    const auto& p = get(vpm, v);
    const std::array<double, 3> q{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
    const std::string problem = internal::soup_io::coordinates_problem(q);
    if (!problem.empty()) fail("vertex " + to_string(vim(v)) + ": " + problem);
  }
  {
    internal::Union_find comp(nf);
    for (auto h : halfedges(tm)) {
      const auto f = face(h, tm), g = face(opposite(h, tm), tm);
      comp.unite(fim(f), fim(g));
    }
    std::size_t n_comp = 0;
    for (std::size_t f = 0; f < nf; ++f)
      if (comp.find(f) == f) ++n_comp;
    if (n_comp > 1)
      fail("the mesh has " + to_string(n_comp) + " connected components (only a single connected surface is supported)");
  }
  Mesh_check_report report;
  const long long chi = static_cast<long long>(nv) - static_cast<long long>(ne) + static_cast<long long>(nf);
  report.genus = static_cast<int>((2 - chi) / 2);
  return report;
}

// ---------------------------------------------------------------------------------------------- features

namespace internal {

/// Checks range, duplicates and count; `lines` (optional) gives the file line of each feature.
inline void validate_feature_pairs_impl(const Feature_correspondence& fc, std::size_t ns, std::size_t nt,
                                        const std::string& context, const std::vector<std::size_t>* lines) {
  using std::to_string;
  auto where = [&](std::size_t k) {
    return context + ": " + (lines ? "line " + to_string((*lines)[k]) : "feature " + to_string(k)) + ": ";
  };
  auto label = [&](std::size_t k) {
    return lines ? "line " + to_string((*lines)[k]) : "feature " + to_string(k);
  };
  const std::size_t none = static_cast<std::size_t>(-1);
  for (std::size_t k = 0; k < fc.size(); ++k) {
    if (fc[k].source >= ns)
      throw Feature_error(where(k) + "source vertex " + to_string(fc[k].source) +
                          " is out of range (the source mesh has " + to_string(ns) + " vertices)");
    if (fc[k].target >= nt)
      throw Feature_error(where(k) + "target vertex " + to_string(fc[k].target) +
                          " is out of range (the target mesh has " + to_string(nt) + " vertices)");
  }
  std::vector<std::size_t> by_source(ns, none), by_target(nt, none);
  for (std::size_t k = 0; k < fc.size(); ++k) {
    std::size_t& s = by_source[fc[k].source];
    if (s != none)
      throw Feature_error(where(k) + "source vertex " + to_string(fc[k].source) + " is used twice (duplicate): by " +
                          label(s) + " and by " + label(k));
    s = k;
    std::size_t& t = by_target[fc[k].target];
    if (t != none)
      throw Feature_error(where(k) + "target vertex " + to_string(fc[k].target) + " is used twice (duplicate): by " +
                          label(t) + " and by " + label(k));
    t = k;
  }
  if (fc.size() < 4)
    throw Feature_error(context + ": only " + to_string(fc.size()) + " feature" + (fc.size() == 1 ? "" : "s") +
                        " given, at least 4 are needed (too few features)");
}

} // namespace internal

/// Checks a feature correspondence built by the caller: every index in range, no source or target vertex used
/// twice, at least 4 features. Throws Feature_error("<context>: feature k: <problem>").
inline void validate_feature_pairs(const Feature_correspondence& fc, std::size_t n_source_vertices,
                                   std::size_t n_target_vertices, const std::string& context) {
  internal::validate_feature_pairs_impl(fc, n_source_vertices, n_target_vertices, context, nullptr);
}

/// Reads feature pairs: one "source_vertex target_vertex" pair (0-based) per line, '#' starts a comment, blank
/// lines are ignored; the k-th pair is feature k. Validated as by validate_feature_pairs().
/// Throws Feature_error("<path>: line N: <problem>").
inline Feature_correspondence read_feature_pairs(const std::string& path, std::size_t n_source_vertices,
                                                 std::size_t n_target_vertices) {
  namespace sio = internal::soup_io;
  const std::string bytes = sio::read_whole_file<Feature_error>(path);
  const sio::Reporter<Feature_error> rep{path};
  sio::Line_cursor lc{bytes};
  std::string_view line;
  std::vector<std::string_view> toks;
  Feature_correspondence fc;
  std::vector<std::size_t> lines;
  while (lc.next(line)) {
    sio::split(line, toks, true);
    if (toks.empty()) continue;
    std::array<std::uint64_t, 2> v{};
    bool ok = toks.size() == 2;
    for (std::size_t i = 0; ok && i < 2; ++i) {
      const std::string_view t = toks[i];
      ok = !t.empty() && std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; }) &&
           sio::parse_count(t, v[i]);
    }
    if (!ok) {
      std::string shown(line.substr(0, line.find('#')));
      while (!shown.empty() && sio::is_space(shown.back())) shown.pop_back();
      rep.fail_line(lc.line, "malformed line " + sio::quote(shown) +
                                 ": expected exactly two non-negative integers 'source_vertex target_vertex'");
    }
    fc.push_back(Feature_pair{static_cast<std::size_t>(v[0]), static_cast<std::size_t>(v[1])});
    lines.push_back(lc.line);
  }
  internal::validate_feature_pairs_impl(fc, n_source_vertices, n_target_vertices, path, &lines);
  return fc;
}

// ---------------------------------------------------------------------------------------------- writing

/// Writes a file via `write` into "<path>.tmp-XXXXXXXX" in the same directory, then renames it over `path`, so
/// readers never see a partial file. If `write` throws, the temporary file is removed and the exception
/// propagates. The stream has precision 17 (doubles round-trip). Throws Input_error if the file cannot be written.
inline void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  namespace fs = std::filesystem;
  if (path.empty()) throw Input_error("(empty file name): no output file name given");
  const fs::path target(path);
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Input_error(path + ": cannot write: directory '" + dir.string() + "' does not exist");
  if (fs::is_directory(target, ec)) throw Input_error(path + ": cannot write: it is a directory");

  thread_local std::mt19937_64 rng(
      static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
      static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(&ec)));
  static const char* hex = "0123456789abcdef";
  std::string tmp;
  std::ofstream os;
  for (int attempt = 0; attempt < 100 && !os.is_open(); ++attempt) {
    std::uint64_t r = rng();
    tmp = path + ".tmp-";
    for (int i = 0; i < 8; ++i, r >>= 4) tmp += hex[r & 15];
    if (fs::exists(tmp, ec)) continue;
    os.open(tmp, std::ios::binary | std::ios::trunc);
    if (!os.is_open())
      throw Input_error(path + ": cannot write: cannot create a file in directory '" + dir.string() + "' (" +
                        std::strerror(errno) + ")");
  }
  if (!os.is_open()) throw Input_error(path + ": cannot write: no free temporary file name");
  os.precision(17);
  try {
    write(os);
    os.flush();
    if (!os) throw Input_error(path + ": write error (disk full?)");
    os.close();
    if (os.fail()) throw Input_error(path + ": write error while closing the file (disk full?)");
    fs::rename(tmp, target, ec);
    if (ec) throw Input_error(path + ": cannot replace the file: " + ec.message());
  } catch (...) {
    if (os.is_open()) os.close();
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

namespace internal {

inline void check_points_and_triangles(const std::string& path, const std::vector<std::array<double, 3>>& points,
                                       const std::vector<std::array<std::size_t, 3>>& triangles) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string problem = soup_io::coordinates_problem(points[i]);
    if (!problem.empty()) throw Error(path + ": cannot write vertex " + std::to_string(i) + ": " + problem);
  }
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (std::size_t v : triangles[f])
      if (v >= points.size())
        throw Error(path + ": cannot write triangle " + std::to_string(f) + ": vertex " + std::to_string(v) +
                    " is out of range (" + std::to_string(points.size()) + " points)");
}

template <class Color>
void write_ply_impl(const std::string& path, const std::vector<std::array<double, 3>>& points,
                    const std::vector<std::array<std::size_t, 3>>& triangles, const std::vector<Color>* face_colors,
                    const std::vector<Color>* vertex_colors) {
  check_points_and_triangles(path, points, triangles);
  if (face_colors && face_colors->size() != triangles.size())
    throw Error(path + ": " + std::to_string(face_colors->size()) + " face colours for " +
                std::to_string(triangles.size()) + " triangles");
  if (vertex_colors && vertex_colors->size() != points.size())
    throw Error(path + ": " + std::to_string(vertex_colors->size()) + " vertex colours for " +
                std::to_string(points.size()) + " vertices");
  write_file_atomically(path, [&](std::ostream& os) {
    os << "ply\nformat ascii 1.0\ncomment written by crossparam\n"
       << "element vertex " << points.size() << "\nproperty double x\nproperty double y\nproperty double z\n";
    if (vertex_colors) os << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    os << "element face " << triangles.size() << "\nproperty list uchar uint vertex_indices\n";
    if (face_colors) os << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    os << "end_header\n";
    for (std::size_t i = 0; i < points.size(); ++i) {
      os << points[i][0] << ' ' << points[i][1] << ' ' << points[i][2];
      if (vertex_colors)
        for (unsigned char c : (*vertex_colors)[i]) os << ' ' << static_cast<unsigned>(c);
      os << '\n';
    }
    for (std::size_t f = 0; f < triangles.size(); ++f) {
      os << "3 " << triangles[f][0] << ' ' << triangles[f][1] << ' ' << triangles[f][2];
      if (face_colors)
        for (unsigned char c : (*face_colors)[f]) os << ' ' << static_cast<unsigned>(c);
      os << '\n';
    }
  });
}

} // namespace internal

/// Writes an OFF file (atomically, 17 significant digits).
inline void write_off(const std::string& path, const std::vector<std::array<double, 3>>& points,
                      const std::vector<std::array<std::size_t, 3>>& triangles) {
  internal::check_points_and_triangles(path, points, triangles);
  write_file_atomically(path, [&](std::ostream& os) {
    os << "OFF\n" << points.size() << ' ' << triangles.size() << " 0\n";
    for (const auto& p : points) os << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const auto& t : triangles) os << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  });
}

/// Writes a face graph as OFF: vertices in vertices(tm) order, faces in faces(tm) order (any face degree).
template <class TriangleMesh>
void write_off(const std::string& path, const TriangleMesh& tm) {
  const auto vindex = internal::number_in_order(vertices(tm));
  auto vim = [&](auto v) { return vindex.at(v); };
  const auto vpm = get(CGAL::vertex_point, tm);
  std::vector<std::array<double, 3>> points(static_cast<std::size_t>(num_vertices(tm)));
  for (auto v : vertices(tm)) {
    const auto& p = get(vpm, v);
    points[vim(v)] = {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string problem = internal::soup_io::coordinates_problem(points[i]);
    if (!problem.empty()) throw Error(path + ": cannot write vertex " + std::to_string(i) + ": " + problem);
  }
  std::vector<std::vector<std::size_t>> polys;
  polys.reserve(static_cast<std::size_t>(num_faces(tm)));
  for (auto f : faces(tm)) {
    polys.emplace_back();
    for (auto v : CGAL::vertices_around_face(halfedge(f, tm), tm)) polys.back().push_back(vim(v));
  }
  write_file_atomically(path, [&](std::ostream& os) {
    os << "OFF\n" << points.size() << ' ' << polys.size() << " 0\n";
    for (const auto& p : points) os << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const auto& poly : polys) {
      os << poly.size();
      for (std::size_t v : poly) os << ' ' << v;
      os << '\n';
    }
  });
}

/// Writes an ascii PLY with one red/green/blue (uchar) colour per face (atomically, 17 significant digits).
inline void write_ply_colored(const std::string& path, const std::vector<std::array<double, 3>>& points,
                              const std::vector<std::array<std::size_t, 3>>& triangles,
                              const std::vector<std::array<unsigned char, 3>>& face_colors) {
  internal::write_ply_impl(path, points, triangles, &face_colors, static_cast<decltype(&face_colors)>(nullptr));
}

/// Writes an ascii PLY with one red/green/blue (uchar) colour per vertex (atomically, 17 significant digits).
inline void write_ply_vertex_colored(const std::string& path, const std::vector<std::array<double, 3>>& points,
                                     const std::vector<std::array<std::size_t, 3>>& triangles,
                                     const std::vector<std::array<unsigned char, 3>>& vertex_colors) {
  internal::write_ply_impl(path, points, triangles, static_cast<decltype(&vertex_colors)>(nullptr), &vertex_colors);
}

} // namespace crossparam

#endif // CROSSPARAM_IO_H

// SPDX-License-Identifier: GPL-3.0-or-later
// Input validation: the checks of meshes, feature correspondences and compatible meshes that crossparam runs
// on its inputs, and what they report. The readers of <crossparam/io.h> validate what they read with them, and
// every public entry point checks its inputs with them once, before any work:
//   - compute_patch_layouts, the Cross_parameterization constructor and compatible_remesh (through the
//     constructor): both meshes by check_triangle_mesh(), equal genus, the features by
//     validate_feature_pairs(), non-degenerate bounding boxes (internal::check_layout_inputs());
//   - Compatible_remesher: its map was checked when it was built; only the options are checked;
//   - morph and blend: the point lists (morph.h); check_compatible() for two soups to be morphed;
//   - verify_patch_layouts and verify_compatible_remeshing: they check results and report what they find.
// A failed check throws one of the exception types of <crossparam/errors.h>, whose what() names the input and
// the problem. No file is read or written here.
#ifndef CROSSPARAM_VALIDATION_H
#define CROSSPARAM_VALIDATION_H

#include <crossparam/errors.h>
#include <crossparam/types.h>

#include <CGAL/Named_function_parameters.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/boost/graph/named_params_helper.h>
#include <CGAL/boost/graph/properties.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <numeric>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace crossparam {

/// What a mesh check found besides errors (which throw).
struct Mesh_check_report {
  std::size_t reoriented_faces = 0;   ///< faces whose orientation was flipped to make it consistent
  int genus = 0;                      ///< from the Euler characteristic V - E + F = 2 - 2g
  std::vector<std::string> warnings;  ///< human-readable, each starts with the mesh name
};

namespace internal {

/// Coordinates beyond this magnitude are rejected: exact predicates overflow to inf/NaN inside GMP there.
constexpr double max_abs_coordinate = 1e100;

/// The shortest decimal text that reads back as `v`.
inline std::string format_double(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

/// Empty when `v` is a usable coordinate, otherwise the problem.
inline std::string coordinate_problem(double v) {
  if (!std::isfinite(v)) return "non-finite coordinate: " + format_double(v);
  if (std::abs(v) > max_abs_coordinate)
    return "coordinate out of supported range: " + format_double(v) + " (|x| must be <= 1e100)";
  return std::string();
}

/// Empty when all three coordinates of `p` are usable, otherwise the problem of the first that is not.
inline std::string coordinates_problem(const std::array<double, 3>& p) {
  for (double c : p) {
    std::string problem = coordinate_problem(c);
    if (!problem.empty()) return problem;
  }
  return std::string();
}

/// Disjoint sets over 0..n-1 (path halving; the smaller index is the root): components and vertex fans.
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

/// An edge as "(a, b)" in messages.
inline std::string edge_name(std::size_t a, std::size_t b) {
  return "(" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

} // namespace internal

// ---------------------------------------------------------------------------------------------- meshes

/// \brief Validates `soup` as a closed, edge- and vertex-manifold, connected, orientable triangle mesh with
/// finite coordinates and no unused points, and builds it into `tm` (cleared first): vertex k of `tm` (in
/// vertices(tm) order; for Surface_mesh the vertex index) is point k and face k is polygon k. Inconsistently
/// oriented faces are flipped (the minority, counted in reoriented_faces, with a warning). Zero-area faces are
/// accepted. The mesh is built only once the whole soup has passed: if a check fails, `tm` is left as it was.
/// \tparam TriangleMesh a model of `MutableFaceGraph` with an internal `vertex_point` property map
/// \param name names the mesh in messages and warnings (the readers pass the file name)
/// \pre none: every defect of `soup` is reported.
/// \returns the genus and the number of reoriented faces.
/// \throws Input_error("<name>: <problem>") for the first defect found (no faces, non-finite or out-of-range
///         coordinates, non-triangle, out-of-range or degenerate faces, unused points, duplicate faces,
///         non-manifold edges or vertices, boundary edges, several connected components, non-orientable).
/// \throws Algorithm_error if the mesh built from the validated soup is not valid (a bug).
template <class TriangleMesh>
Mesh_check_report soup_to_triangle_mesh(const Polygon_soup& soup, TriangleMesh& tm, const std::string& name) {
  using internal::edge_name;
  using std::to_string;
  auto fail = [&](const std::string& msg) { throw Input_error(name + ": " + msg); };
  const std::size_t nv = soup.points.size();
  const std::size_t nf = soup.polygons.size();
  if (nf == 0) fail("the mesh has no faces");

  for (std::size_t i = 0; i < nv; ++i) {
    const std::string problem = internal::coordinates_problem(soup.points[i]);
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

/// \brief Validates a mesh built by the caller: valid halfedge structure, triangles only, closed, no isolated or
/// non-manifold vertices, one connected component, finite coordinates with |x| <= 1e100. The coordinates
/// checked are those of the mesh's internal `vertex_point` property map.
/// \tparam TriangleMesh a model of `FaceListGraph` and `HalfedgeListGraph` with an internal `vertex_point` map
/// \param name names the mesh in messages
/// \pre none: every defect listed is reported.
/// \returns the genus (from the Euler characteristic); `reoriented_faces` is 0 and `warnings` empty.
/// \throws Input_error("<name>: <problem>") for the first defect found.
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
    const std::string problem = internal::coordinates_problem(q);
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

/// \brief Checks a feature correspondence built by the caller: every index in range, no source or target
/// vertex used twice, at least 4 features.
/// \param n_source_vertices, n_target_vertices the vertex counts of the two meshes
/// \param context names the correspondence in messages
/// \pre none.
/// \throws Feature_error("<context>: feature k: <problem>"), or Feature_error("<context>: only N features
///         given, ...") when there are fewer than 4.
inline void validate_feature_pairs(const Feature_correspondence& fc, std::size_t n_source_vertices,
                                   std::size_t n_target_vertices, const std::string& context) {
  internal::validate_feature_pairs_impl(fc, n_source_vertices, n_target_vertices, context, nullptr);
}

// ---------------------------------------------------------------------------------------------- compatible meshes

/// \brief Checks that two soups are compatible, i.e. can be morphed or blended vertex by vertex: the same
/// number of points and the same triangles (as point index triples, in order).
/// \param name_a, name_b name the two soups in messages
/// \pre none.
/// \throws Incompatible_inputs_error("<name_a> and <name_b> are not compatible: <first difference>").
inline void check_compatible(const Polygon_soup& a, const Polygon_soup& b, const std::string& name_a = "A",
                             const std::string& name_b = "B") {
  auto fail = [&](const std::string& what) {
    throw Incompatible_inputs_error(name_a + " and " + name_b + " are not compatible: " + what);
  };
  if (a.points.size() != b.points.size())
    fail(std::to_string(a.points.size()) + " vs " + std::to_string(b.points.size()) + " vertices");
  if (a.polygons.size() != b.polygons.size())
    fail(std::to_string(a.polygons.size()) + " vs " + std::to_string(b.polygons.size()) + " faces");
  for (std::size_t f = 0; f < a.polygons.size(); ++f) {
    if (a.polygons[f].size() != 3 || b.polygons[f].size() != 3) fail("face " + std::to_string(f) + " is not a triangle");
    if (a.polygons[f] != b.polygons[f]) fail("face " + std::to_string(f) + " has different vertices");
  }
  if (a.polygons.empty()) fail("no faces");
}


// ---------------------------------------------------------------------------------------------- entry points

namespace internal_np {
/// `bool`, internal: the inputs carried with this parameter pack were checked by the entry point that built it
/// (a public entry point called from inside another one does not check them again).
struct inputs_checked_t {};
} // namespace internal_np

namespace internal {

/// `np` marked as carrying inputs that have been checked (see `inputs_checked_t`).
template <typename NP>
CGAL::Named_function_parameters<bool, internal_np::inputs_checked_t, NP> inputs_checked(const NP& np) {
  return CGAL::Named_function_parameters<bool, internal_np::inputs_checked_t, NP>(true, np);
}

/// Whether `np` was marked by `inputs_checked()`.
template <typename NP>
bool are_inputs_checked(const NP& np) {
  return CGAL::parameters::choose_parameter(CGAL::parameters::get_parameter(np, internal_np::inputs_checked_t()),
                                            false);
}

/// \brief Checks that the points of `vpm` span a bounding box with a positive, finite diagonal (the working
/// copies of the meshes are scaled by it).
/// \pre `tm` has passed check_triangle_mesh() (the points of its internal map are finite).
/// \throws Input_error("<name>: mesh has a degenerate bounding box").
template <class TriangleMesh, class VertexPointMap>
void check_bounding_box(const TriangleMesh& tm, VertexPointMap vpm, const std::string& name = "mesh") {
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (auto v : vertices(tm)) {
    const auto& p = get(vpm, v);
    const double q[3] = {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], q[i]);
      hi[i] = std::max(hi[i], q[i]);
    }
  }
  double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                          (hi[2] - lo[2]) * (hi[2] - lo[2]));
  if (!(diag > 0) || !std::isfinite(diag))
    throw Input_error(name + ": the mesh has a degenerate bounding box (all its vertices are at one point)");
}

/// \brief The input checks of compute_patch_layouts, the Cross_parameterization constructor and
/// compatible_remesh, in this order: each mesh by check_triangle_mesh() ("source mesh", "target mesh"), the
/// same genus, the features by validate_feature_pairs() ("feature correspondence"), then the bounding
/// box of each mesh's points (`vertex_point` of `np_source` / `np_target`) by check_bounding_box().
/// \pre none: every violation is reported.
/// \throws Input_error for a mesh, Incompatible_inputs_error for the genus, Feature_error for the features.
template <class SourceMesh, class TargetMesh, class NPS, class NPT>
void check_layout_inputs(const SourceMesh& tm_s, const TargetMesh& tm_t, const Feature_correspondence& features,
                         const NPS& np_source, const NPT& np_target) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  const Mesh_check_report rs = check_triangle_mesh(tm_s, "source mesh");
  const Mesh_check_report rt = check_triangle_mesh(tm_t, "target mesh");
  if (rs.genus != rt.genus)
    throw Incompatible_inputs_error("the source mesh has genus " + std::to_string(rs.genus) +
                                    " but the target mesh has genus " + std::to_string(rt.genus));
  const std::size_t ns = std::size_t(std::distance(vertices(tm_s).begin(), vertices(tm_s).end()));
  const std::size_t nt = std::size_t(std::distance(vertices(tm_t).begin(), vertices(tm_t).end()));
  validate_feature_pairs(features, ns, nt, "feature correspondence");
  check_bounding_box(tm_s, choose_parameter(get_parameter(np_source, CGAL::internal_np::vertex_point),
                                            get_const_property_map(CGAL::vertex_point, tm_s)), "source mesh");
  check_bounding_box(tm_t, choose_parameter(get_parameter(np_target, CGAL::internal_np::vertex_point),
                                            get_const_property_map(CGAL::vertex_point, tm_t)), "target mesh");
}

} // namespace internal

} // namespace crossparam

#endif // CROSSPARAM_VALIDATION_H

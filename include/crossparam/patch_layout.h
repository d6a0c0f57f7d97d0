// SPDX-License-Identifier: GPL-3.0-or-later
// Common base domain (Kraevoy & Sheffer 2004, §3): topologically identical triangular patch layouts of two
// closed triangle meshes of the same genus from matching feature vertices.
#ifndef CROSSPARAM_PATCH_LAYOUT_H
#define CROSSPARAM_PATCH_LAYOUT_H

#include <crossparam/errors.h>
#include <crossparam/layout_types.h>
#include <crossparam/layout_verification.h>
#include <crossparam/validation.h>
#include <crossparam/parameters.h>
#include <crossparam/types.h>
#include <crossparam/internal/layout_builder.h>

#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Kernel_traits.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>

#include <boost/property_map/property_map.hpp>

#include <array>
#include <string>
#include <vector>

namespace crossparam {

namespace internal {

/// A Surface_mesh copy of a validated triangle mesh, built as a soup so that vertex k of the copy is the k-th
/// vertex of vertices(tm) and face f the f-th of faces(tm), with its corners in vertices_around_face order
/// (the file order for meshes we read). Both orders are checked. Returns the soup (the points as given).
struct Triangle_soup {
  std::vector<Point_3> points;
  std::vector<std::array<std::size_t, 3>> tris;
};
template <class TriangleMesh, class VertexPointMap>
Triangle_soup copy_in_order(const TriangleMesh& tm, VertexPointMap vpm, Surface_mesh& out) {
  using vertex_descriptor = typename boost::graph_traits<TriangleMesh>::vertex_descriptor;
  std::vector<vertex_descriptor> order(vertices(tm).begin(), vertices(tm).end());
  std::map<vertex_descriptor, std::size_t> index;
  Triangle_soup soup;
  std::vector<Point_3>& points = soup.points;
  std::vector<std::array<std::size_t, 3>>& tris = soup.tris;
  for (std::size_t i = 0; i < order.size(); ++i) {
    index[order[i]] = i;
    const auto& p = get(vpm, order[i]);
    points.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  }
  for (auto f : faces(tm)) {
    auto h = halfedge(f, tm);
    tris.push_back({index[target(h, tm)], index[target(next(h, tm), tm)], index[source(h, tm)]});
  }
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, tris, out);
  if (out.number_of_vertices() != points.size() || out.number_of_faces() != tris.size())
    throw Algorithm_error("internal error: mesh copy changed the element counts");
  for (std::size_t i = 0; i < points.size(); ++i)
    if (out.point(WV(WV::size_type(i))) != points[i])
      throw Algorithm_error("internal error: mesh copy did not keep the vertex order");
  for (std::size_t f = 0; f < tris.size(); ++f) {
    std::array<std::size_t, 3> got;
    int i = 0;
    for (WV v : CGAL::vertices_around_face(out.halfedge(WF(WF::size_type(f))), out)) got[i++] = std::size_t(v);
    std::array<std::size_t, 3> a = got, b = tris[f];
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    if (a != b) throw Algorithm_error("internal error: mesh copy did not keep the face order");
  }
  return soup;
}

/// Copies a user's mesh into a working Surface_mesh with coordinates scaled into a unit box (predicates
/// stay safe at any input scale), oriented outward. Vertex k of the copy is the k-th vertex of vertices(tm).
template <class TriangleMesh, class VertexPointMap>
void make_work_mesh(const TriangleMesh& tm, VertexPointMap vpm, Layout_mesh& out) {
  const Triangle_soup soup = copy_in_order(tm, vpm, out.m);
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (WV v : out.m.vertices())
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], out.m.point(v)[i]);
      hi[i] = std::max(hi[i], out.m.point(v)[i]);
    }
  double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                          (hi[2] - lo[2]) * (hi[2] - lo[2]));
  CGAL_precondition(diag > 0 && std::isfinite(diag)); // internal::check_bounding_box
  out.center = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  out.scale = diag;
  for (WV v : out.m.vertices()) {
    const Point_3& p = out.m.point(v);
    out.m.point(v) = Point_3((p.x() - 0.5 * (lo[0] + hi[0])) / diag, (p.y() - 0.5 * (lo[1] + hi[1])) / diag,
                             (p.z() - 0.5 * (lo[2] + hi[2])) / diag);
  }
  // Signed volume decides the orientation; sectors and base triangles are read counter-clockwise from outside.
  double vol = 0;
  for (WF f : out.m.faces()) {
    WH h = out.m.halfedge(f);
    const Point_3 &a = out.m.point(out.m.source(h)), &b = out.m.point(out.m.target(h)),
                  &c = out.m.point(out.m.target(out.m.next(h)));
    vol += CGAL::scalar_product(a - CGAL::ORIGIN, CGAL::cross_product(b - CGAL::ORIGIN, c - CGAL::ORIGIN));
  }
  out.reversed = vol < 0;
  if (vol < 0) CGAL::Polygon_mesh_processing::reverse_face_orientations(out.m);
  out.init(soup.tris);
  out.input_points.clear();
  for (const Point_3& p : soup.points) out.input_points.push_back({p.x(), p.y(), p.z()});
}

template <class TriangleMesh>
std::vector<typename boost::graph_traits<TriangleMesh>::vertex_descriptor> vertex_list(const TriangleMesh& tm) {
  return {vertices(tm).begin(), vertices(tm).end()};
}

/// Replays the splits of a layout on the user's mesh and returns, for each face of the working mesh, the
/// matching face of the user's mesh (found by its vertices, so orientation does not matter).
template <class TriangleMesh, class VertexPointMap>
std::vector<typename boost::graph_traits<TriangleMesh>::face_descriptor>
replay_splits(TriangleMesh& tm, VertexPointMap vpm, const Layout_mesh& L,
              std::vector<typename boost::graph_traits<TriangleMesh>::vertex_descriptor>& desc) {
  using Point = typename boost::property_traits<VertexPointMap>::value_type;
  for (const Edge_split& s : L.splits) {
    if (desc.size() != s.w) throw Algorithm_error("internal error: split replay out of order");
    Point p = CGAL::barycenter(get(vpm, desc[s.u]), 1 - s.t, get(vpm, desc[s.v]), s.t);
    desc.push_back(split_edge_and_triangulate(tm, vpm, desc[s.u], desc[s.v], p));
  }
  using face_descriptor = typename boost::graph_traits<TriangleMesh>::face_descriptor;
  std::vector<face_descriptor> fmap(L.m.number_of_faces());
  for (WF f : L.m.faces()) {
    WH h = L.m.halfedge(f);
    auto a = desc[L.m.source(h)], b = desc[L.m.target(h)], c = desc[L.m.target(L.m.next(h))];
    auto hu = halfedge(a, b, tm);
    if (!hu.second) throw Algorithm_error("internal error: replayed mesh lacks an edge");
    auto h1 = hu.first;
    if (target(next(h1, tm), tm) == c && !is_border(h1, tm))
      fmap[f] = face(h1, tm);
    else if (!is_border(opposite(h1, tm), tm) && target(next(opposite(h1, tm), tm), tm) == c)
      fmap[f] = face(opposite(h1, tm), tm);
    else
      throw Algorithm_error("internal error: replayed mesh lacks a face");
  }
  return fmap;
}

/// Links between a working mesh and the user's refined mesh.
template <class TriangleMesh>
struct Mesh_link {
  std::vector<typename boost::graph_traits<TriangleMesh>::vertex_descriptor> vertex; ///< work vertex -> user vertex
  std::vector<typename boost::graph_traits<TriangleMesh>::face_descriptor> face;     ///< work face -> user face
};

template <class TriangleMesh, class NamedParameters>
void write_layout_outputs(TriangleMesh& tm, const NamedParameters& np, const Layout_mesh& L,
                          const std::vector<int>& work_face_triangle, const std::vector<int>& path_id_remap,
                          Mesh_layout& out, Mesh_link<TriangleMesh>* link = nullptr) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  using CGAL::parameters::is_default_parameter;
  auto vpm = choose_parameter(get_parameter(np, CGAL::internal_np::vertex_point), get_property_map(CGAL::vertex_point, tm));
  auto desc = vertex_list(tm);
  out.original_vertices = desc.size();
  out.original_faces = std::size_t(std::distance(faces(tm).begin(), faces(tm).end()));
  auto fmap = replay_splits(tm, vpm, L, desc);
  out.splits = L.splits;
  // Face order of the refined user mesh.
  using face_descriptor = typename boost::graph_traits<TriangleMesh>::face_descriptor;
  std::map<face_descriptor, int> tri_of;
  for (WF f : L.m.faces()) tri_of[fmap[f]] = work_face_triangle[f];
  out.face_triangle.clear();
  for (face_descriptor f : faces(tm)) out.face_triangle.push_back(tri_of.at(f));
  // Paths, renumbered.
  std::size_t np_count = 0;
  for (int r : path_id_remap) np_count += (r >= 0);
  out.paths.assign(np_count, {});
  for (std::size_t p = 0; p < L.paths.size(); ++p) {
    if (p >= path_id_remap.size() || path_id_remap[p] < 0) continue;
    auto& vs = out.paths[path_id_remap[p]];
    vs.push_back(std::size_t(L.m.source(L.paths[p].front())));
    for (WH h : L.paths[p]) vs.push_back(std::size_t(L.m.target(h)));
  }
  out.feature_vertices.clear();
  for (WV v : L.feature_vertex) out.feature_vertices.push_back(std::size_t(v));
  if (link) {
    link->vertex = desc;
    link->face = fmap;
  }

  // Property maps requested by the caller.
  auto fpm = get_parameter(np, CGAL::internal_np::face_patch);
  if constexpr (!std::is_same_v<decltype(fpm), CGAL::internal_np::Param_not_found>) {
    std::size_t i = 0;
    for (face_descriptor f : faces(tm)) put(fpm, f, out.face_triangle[i++]);
  }
  auto epm = get_parameter(np, internal_np::edge_path_map_t());
  if constexpr (!std::is_same_v<decltype(epm), CGAL::internal_np::Param_not_found>) {
    for (auto e : edges(tm)) put(epm, e, -1);
    for (std::size_t p = 0; p < out.paths.size(); ++p)
      for (std::size_t i = 0; i + 1 < out.paths[p].size(); ++i)
        put(epm, edge(halfedge(desc[out.paths[p][i]], desc[out.paths[p][i + 1]], tm).first, tm), int(p));
  }
  auto vfm = get_parameter(np, internal_np::vertex_feature_map_t());
  if constexpr (!std::is_same_v<decltype(vfm), CGAL::internal_np::Param_not_found>) {
    for (auto v : vertices(tm)) put(vfm, v, -1);
    for (std::size_t k = 0; k < out.feature_vertices.size(); ++k) put(vfm, desc[out.feature_vertices[k]], int(k));
  }
}

} // namespace internal

/// \brief Computes topologically identical triangular patch layouts of a source and a target mesh whose
/// feature vertices correspond (paper §3: PathMatch with the blocking test and Update, face paths with
/// make-simple, triangulation and edge splits, path flips).
///
/// Both meshes are refined in place by edge splits: original vertices keep their positions in
/// `vertices(tm)`, new vertices are appended, each at the midpoint of the edge it splits.
///
/// \tparam SourceMesh, TargetMesh models of `MutableFaceGraph` (e.g. `CGAL::Surface_mesh`,
///         `CGAL::Polyhedron_3` with item ids); the two may differ.
/// \param features corresponding vertex indices (positions in `vertices(tm)` order), at least 4 pairs.
/// \param np_source, np_target optional named parameters per mesh:
///   - `vertex_point_map` (default: the mesh's internal point map),
///   - `face_patch_map` (output, face -> integer): base-triangle id of each face,
///   - `crossparam::parameters::edge_path_map` (output, edge -> int): path id of each edge, -1 off paths,
///   - `crossparam::parameters::vertex_feature_map` (output, vertex -> int): feature id, -1 elsewhere,
///   - `crossparam::parameters::apply_path_flips` (bool, default true; read from `np_source`),
///   - `crossparam::parameters::consistent_paths` (bool, default true; read from `np_source`): trace
///     matching paths that agree in geodesic distances to the features (an addition to the paper),
///   - `crossparam::parameters::straighten_paths` (bool, default false; read from `np_source`): once the
///     layout is complete, shorten each path inside its two patches (an addition to the paper).
/// \pre both meshes closed, manifold, connected triangle meshes of the same genus with finite coordinates;
///      features distinct and in range. Each is checked: violations throw `Input_error` (or `Feature_error`,
///      `Incompatible_inputs_error`) naming the problem. For genus g > 0 the features must also be enough to cut
///      every handle (about four around each) and to carry a simple triangulation of genus g (at least 7
///      features for g = 1, 10 for g = 2, 12 for g = 3); otherwise `Insufficient_features_error` names the patch
///      that still carries a handle and vertices near it where a feature would help.
/// \returns the base mesh, both layouts and statistics. The result is verified before it is returned
///          (`verify_patch_layouts`); a failed verification throws `Algorithm_error`.
///
/// Kernel: the layout is computed on working copies with the fixed kernel `crossparam::Kernel` (EPICK); the
/// user's points are read through `CGAL::to_double` (any kernel), and no `geom_traits` named parameter is
/// taken. The split points written back to the user's meshes are computed with the user's kernel
/// (`CGAL::barycenter` of the edge's end points).
template <class SourceMesh, class TargetMesh, typename CGAL_NP_TEMPLATE_PARAMETERS_1,
          typename CGAL_NP_TEMPLATE_PARAMETERS_2>
Patch_layout compute_patch_layouts(SourceMesh& tm_s, TargetMesh& tm_t, const Feature_correspondence& features,
                                   const CGAL_NP_CLASS_1& np_source = CGAL::parameters::default_values(),
                                   const CGAL_NP_CLASS_2& np_target = CGAL::parameters::default_values());

namespace internal {
template <class SourceMesh, class TargetMesh, typename NP_T1, typename NP_Tag1, typename NP_Base1,
          typename NP_T2, typename NP_Tag2, typename NP_Base2>
Patch_layout compute_patch_layouts_impl(SourceMesh& tm_s, TargetMesh& tm_t, const Feature_correspondence& features,
                                        const CGAL::Named_function_parameters<NP_T1, NP_Tag1, NP_Base1>& np_source,
                                        const CGAL::Named_function_parameters<NP_T2, NP_Tag2, NP_Base2>& np_target,
                                        Layout_builder& B, bool adjacency_splits,
                                        std::array<std::vector<int>, 2>* work_tri_out = nullptr,
                                        Mesh_link<SourceMesh>* link_s = nullptr,
                                        Mesh_link<TargetMesh>* link_t = nullptr) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  auto vpm_s = choose_parameter(get_parameter(np_source, CGAL::internal_np::vertex_point),
                                get_property_map(CGAL::vertex_point, tm_s));
  auto vpm_t = choose_parameter(get_parameter(np_target, CGAL::internal_np::vertex_point),
                                get_property_map(CGAL::vertex_point, tm_t));
  const bool flips = choose_parameter(get_parameter(np_source, internal_np::apply_path_flips_t()), true);
  const bool consistent = choose_parameter(get_parameter(np_source, internal_np::consistent_paths_t()), true);
  const bool straighten = choose_parameter(get_parameter(np_source, internal_np::straighten_paths_t()), false);

  // The inputs were checked by the public entry point (internal::check_layout_inputs).
  B.do_flips = flips;
  B.consistent_paths = consistent;
  B.do_straighten = straighten;
  make_work_mesh(tm_s, vpm_s, B.side[0]);
  make_work_mesh(tm_t, vpm_t, B.side[1]);
  // Both meshes have this genus (internal::check_layout_inputs): V - E + F = 2 - 2 genus.
  const Work_mesh& ms = B.side[0].m;
  B.genus = int((2 - (long(ms.number_of_vertices()) - long(ms.number_of_edges()) + long(ms.number_of_faces()))) / 2);
  for (std::size_t k = 0; k < features.size(); ++k) {
    WV vs(WV::size_type(features[k].source)), vt(WV::size_type(features[k].target));
    B.side[0].feature_vertex.push_back(vs);
    B.side[1].feature_vertex.push_back(vt);
    B.side[0].vfeature[vs] = int(k);
    B.side[1].vfeature[vt] = int(k);
  }
  B.run();
  if (adjacency_splits) {
    B.stats.adjacency_splits_source = B.split_for_adjacency(0);
    B.stats.adjacency_splits_target = B.split_for_adjacency(1);
    B.stats.splits_source = B.side[0].splits.size();
    B.stats.splits_target = B.side[1].splits.size();
  }

  // Base mesh: the loops of the final layout, all triangles. Ids in a canonical order.
  Patch_layout out;
  auto comb = B.combinatorics();
  std::vector<int> remap(B.path_ends.size(), -1);
  for (std::size_t p = 0; p < B.path_ends.size(); ++p)
    if (B.path_ends[p][0] >= 0) {
      remap[p] = int(out.base_edges.size());
      out.base_edges.push_back({std::size_t(B.path_ends[p][0]), std::size_t(B.path_ends[p][1])});
    }
  std::vector<std::pair<std::array<std::size_t, 3>, std::size_t>> tris; // canonical triangle, loop index
  for (std::size_t l = 0; l < comb.loops.size(); ++l) {
    const auto& loop = comb.loops[l];
    if (loop.size() != 3) throw Algorithm_error("internal error: a patch is not triangular");
    std::array<std::size_t, 3> t{std::size_t(loop[0].from), std::size_t(loop[1].from), std::size_t(loop[2].from)};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    tris.push_back({t, l});
  }
  std::sort(tris.begin(), tris.end());
  std::vector<int> tri_of_loop(comb.loops.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    out.base_triangles.push_back(tris[i].first);
    tri_of_loop[tris[i].second] = int(i);
  }
  // Face labels on each working mesh: patch of the face left of each loop's first dart.
  std::array<std::vector<int>, 2> work_tri;
  for (int s = 0; s < 2; ++s) {
    std::vector<int> label;
    int np = B.side[s].label_patches(label);
    if (std::size_t(np) != comb.loops.size())
      throw Algorithm_error("internal error: patch count differs from the base triangle count");
    std::vector<int> tri_of_patch(np, -1);
    for (std::size_t l = 0; l < comb.loops.size(); ++l) {
      int pl = label[B.side[s].m.face(B.dart_halfedge(s, comb.loops[l][0]))];
      if (tri_of_patch[pl] >= 0) throw Algorithm_error("internal error: two base triangles share a patch");
      tri_of_patch[pl] = tri_of_loop[l];
    }
    work_tri[s].resize(label.size());
    for (std::size_t f = 0; f < label.size(); ++f) work_tri[s][f] = tri_of_patch[label[f]];
  }
  out.statistics = B.stats;
  write_layout_outputs(tm_s, np_source, B.side[0], work_tri[0], remap, out.source, link_s);
  write_layout_outputs(tm_t, np_target, B.side[1], work_tri[1], remap, out.target, link_t);
  if (work_tri_out) *work_tri_out = work_tri;

  Layout_verification check = verify_patch_layouts(tm_s, tm_t, out);
  if (!check.valid) throw Algorithm_error("patch layout failed verification: " + check.message);
  return out;
}

} // namespace internal

template <class SourceMesh, class TargetMesh, typename NP_T1, typename NP_Tag1, typename NP_Base1,
          typename NP_T2, typename NP_Tag2, typename NP_Base2>
Patch_layout compute_patch_layouts(SourceMesh& tm_s, TargetMesh& tm_t, const Feature_correspondence& features,
                                   const CGAL::Named_function_parameters<NP_T1, NP_Tag1, NP_Base1>& np_source,
                                   const CGAL::Named_function_parameters<NP_T2, NP_Tag2, NP_Base2>& np_target) {
  internal::check_layout_inputs(tm_s, tm_t, features, np_source, np_target);
  internal::Layout_builder B;
  return internal::compute_patch_layouts_impl(tm_s, tm_t, features, np_source, np_target, B, false);
}

} // namespace crossparam

#endif // CROSSPARAM_PATCH_LAYOUT_H

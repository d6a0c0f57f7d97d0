// SPDX-License-Identifier: GPL-3.0-or-later
// Local blends of compatible meshes (paper §6, Fig. 10): weights that vary from vertex to vertex, so that one
// region of the result follows one model and the rest another ("one model's head on another's body"). The
// weights are given per vertex, or built from a region: everything within a geodesic distance of a feature,
// with a smooth falloff to the rest.
#ifndef CROSSPARAM_BLENDING_H
#define CROSSPARAM_BLENDING_H

#include <crossparam/errors.h>
#include <crossparam/morph.h>
#include <crossparam/types.h>

#include <CGAL/Heat_method_3/Surface_mesh_geodesic_distances_3.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>

#include <boost/graph/dijkstra_shortest_paths.hpp>
#include <boost/property_map/property_map.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace crossparam {

/// How far beyond the two bounds that every geodesic distance obeys (the straight-line distance below, the
/// shortest path along edges above) the heat method's estimate may lie and still be taken (region_weights()):
/// a quarter. The heat method's error is a few percent on meshes of reasonable triangles; on a mesh with
/// slivers, such as the source-shaped output of an N-way remeshing, its intrinsic Delaunay mode can return
/// every distance at the largest double, and that, or any estimate this far off, is rejected.
constexpr double heat_distance_slack = 0.25;

namespace internal {
/// Whether the estimates `d` from vertex `center` of `m` lie within heat_distance_slack of the straight-line
/// distances below and of the edge-path distances `path` above.
inline bool plausible_geodesic_distances(const Surface_mesh& m, Surface_mesh::Vertex_index center,
                                         const std::vector<double>& d, const std::vector<double>& path) {
  double scale = 0; // the longest edge path: rounding of distances is relative to it
  for (double p : path)
    if (std::isfinite(p)) scale = std::max(scale, p);
  for (auto v : m.vertices()) {
    const double x = d[std::size_t(v)], lower = std::sqrt(CGAL::squared_distance(m.point(v), m.point(center)));
    if (!std::isfinite(x) || x < (1 - heat_distance_slack) * lower - 1e-9 * scale ||
        x > (1 + heat_distance_slack) * path[std::size_t(v)])
      return false;
  }
  return true;
}
} // namespace internal

/// \brief Local blend: vertex v of the result is the sum over meshes m of `vertex_weights[v][m]` times vertex v
/// of mesh m.
/// \param meshes the point lists of compatible meshes (one face list)
/// \param vertex_weights one row per vertex, one weight per mesh in each row, each row summing to 1
/// \throws Input_error for no mesh, a number of rows other than the vertex count, or a row with another number
///         of weights than meshes, or not summing to 1; Incompatible_inputs_error if the point lists differ in size
inline std::vector<std::array<double, 3>> local_blend(const std::vector<const std::vector<std::array<double, 3>>*>& meshes,
                                                      const std::vector<std::vector<double>>& vertex_weights) {
  if (meshes.empty()) throw Input_error("local blend: no mesh to blend");
  for (const auto* m : meshes)
    if (m->size() != meshes[0]->size()) throw Incompatible_inputs_error("local blend: the point lists differ in size");
  if (vertex_weights.size() != meshes[0]->size())
    throw Input_error("local blend: " + std::to_string(vertex_weights.size()) + " weight rows for meshes of " +
                      std::to_string(meshes[0]->size()) + " vertices (one row per vertex is needed)");
  std::vector<std::array<double, 3>> out(meshes[0]->size(), {0, 0, 0});
  for (std::size_t v = 0; v < out.size(); ++v) {
    internal::check_affine_weights(vertex_weights[v], meshes.size(), "local blend, vertex " + std::to_string(v));
    for (std::size_t m = 0; m < meshes.size(); ++m)
      for (int k = 0; k < 3; ++k) out[v][std::size_t(k)] += vertex_weights[v][m] * (*meshes[m])[v][std::size_t(k)];
  }
  return out;
}

/// \brief A weight per vertex that is 1 within geodesic distance `radius` of vertex `center`, falls smoothly
/// (C1, a smoothstep of the distance) to 0 over the next `falloff`, and is 0 beyond. Geodesic distances by the
/// heat method (CGAL `Heat_method_3`), on the intrinsic Delaunay triangulation, or directly on the mesh if that
/// estimate is implausible (see heat_distance_slack) and no face is degenerate; else the shortest paths along
/// edges (an upper bound, exact along edges; Boost's Dijkstra).
/// \param points, faces a closed triangle mesh (faces index `points`)
/// \param center the vertex the region is around
/// \param radius, falloff distances in the mesh's units; `falloff` 0 gives a sharp border
/// \throws Input_error if `center` is not a vertex, or `radius` or `falloff` is negative or not finite
inline std::vector<double> region_weights(const std::vector<std::array<double, 3>>& points,
                                          const std::vector<std::array<std::size_t, 3>>& faces, std::size_t center,
                                          double radius, double falloff) {
  if (center >= points.size())
    throw Input_error("region: vertex " + std::to_string(center) + " is not a vertex of a mesh of " +
                      std::to_string(points.size()));
  if (!(radius >= 0) || !std::isfinite(radius) || !(falloff >= 0) || !std::isfinite(falloff))
    throw Input_error("region: the radius and the falloff must be non-negative numbers");
  Surface_mesh m;
  for (const auto& p : points) m.add_vertex(Point_3(p[0], p[1], p[2]));
  for (const auto& f : faces)
    if (m.add_face(Surface_mesh::Vertex_index(Surface_mesh::size_type(f[0])), Surface_mesh::Vertex_index(Surface_mesh::size_type(f[1])),
                   Surface_mesh::Vertex_index(Surface_mesh::size_type(f[2]))) == Surface_mesh::null_face())
      throw Input_error("region: the faces do not form a manifold mesh");
  const Surface_mesh::Vertex_index c{Surface_mesh::size_type(center)};
  // Edge paths: the upper bound, and the last resort.
  auto length = m.add_property_map<Surface_mesh::Edge_index, double>("e:crossparam_length", 0.0).first;
  for (auto e : m.edges()) length[e] = std::sqrt(CGAL::squared_distance(m.point(m.vertex(e, 0)), m.point(m.vertex(e, 1))));
  std::vector<double> path(points.size(), HUGE_VAL);
  boost::dijkstra_shortest_paths(m, c, boost::distance_map(boost::make_iterator_property_map(path.begin(), get(boost::vertex_index, m)))
                                           .weight_map(length));
  std::vector<double> distance(points.size(), 0.0), estimate(points.size(), 0.0);
  auto heat = [&](auto mode) {
    auto map = boost::make_iterator_property_map(estimate.begin(), get(boost::vertex_index, m));
    CGAL::Heat_method_3::estimate_geodesic_distances(m, map, c, mode);
    return internal::plausible_geodesic_distances(m, c, estimate, path);
  };
  // The direct mode needs every face non-degenerate (its cotangents); the intrinsic Delaunay mode does not.
  bool degenerate = false;
  for (auto f : m.faces()) degenerate = degenerate || CGAL::Polygon_mesh_processing::is_degenerate_triangle_face(f, m);
  if (heat(CGAL::Heat_method_3::Intrinsic_Delaunay()) || (!degenerate && heat(CGAL::Heat_method_3::Direct())))
    distance = estimate;
  else
    distance = path;
  std::vector<double> w(points.size(), 0.0);
  for (auto v : m.vertices()) {
    const double d = distance[std::size_t(v)];
    if (d <= radius) w[std::size_t(v)] = 1;
    else if (falloff > 0 && d < radius + falloff) {
      const double t = 1 - (d - radius) / falloff; // 1 at the radius, 0 at the end of the falloff
      w[std::size_t(v)] = t * t * (3 - 2 * t);
    }
  }
  return w;
}

/// \brief region_weights() around feature `feature` of a compatible mesh: `feature_vertices[k]` is the vertex
/// of feature k on that mesh (the source's feature vertices on a remeshing's outputs: they keep the source's
/// vertex indices).
/// \throws Input_error if there is no feature `feature`, and as region_weights()
inline std::vector<double> feature_region_weights(const std::vector<std::array<double, 3>>& points,
                                                  const std::vector<std::array<std::size_t, 3>>& faces,
                                                  const std::vector<std::size_t>& feature_vertices, std::size_t feature,
                                                  double radius, double falloff) {
  if (feature >= feature_vertices.size())
    throw Input_error("region: there is no feature " + std::to_string(feature) + " (features 0 to " +
                      std::to_string(feature_vertices.size()) + " - 1)");
  return region_weights(points, faces, feature_vertices[feature], radius, falloff);
}

/// \brief The weight rows of a two-mesh local blend: mesh 1 inside the region (weight `region[v]`), mesh 0
/// elsewhere (1 - `region[v]`), for local_blend().
inline std::vector<std::vector<double>> two_mesh_weights(const std::vector<double>& region) {
  std::vector<std::vector<double>> rows;
  rows.reserve(region.size());
  for (double w : region) rows.push_back({1 - w, w});
  return rows;
}

} // namespace crossparam

#endif // CROSSPARAM_BLENDING_H

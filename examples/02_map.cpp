// SPDX-License-Identifier: GPL-3.0-or-later
// Example 02: the cross-parameterization F between two meshes (paper §4), and evaluating F and F^-1.
//
//   example_02_map        two generated creatures
//
// Builds the map, prints its certificate and distortion, sends points of the source to the target with F and
// back with F^-1 (the round trip must come back to where it started), and reports a source vertex against the
// target as given (input face index and barycentric coordinates).
#include <crossparam/cross_parameterization.h>
#include <support/shapes.h>

#include <CGAL/Polygon_mesh_processing/locate.h>

#include <algorithm>
#include <cmath>
#include <iostream>

using Surface_mesh = crossparam::Surface_mesh;
using Map = crossparam::Cross_parameterization<Surface_mesh, Surface_mesh>;
namespace PMP = CGAL::Polygon_mesh_processing;

int main() try {
  Surface_mesh source = crossparam::shapes::creature_a(), target = crossparam::shapes::creature_b();
  const crossparam::Feature_correspondence features = crossparam::shapes::creature_features(source, target);
  const std::size_t source_vertices = source.number_of_vertices();

  // Layout, parameterization and smoothing; both meshes are refined in place (new vertices appended).
  Map map(source, target, features);
  const auto& s = map.statistics();
  std::cout << "map: " << features.size() << " features, " << map.layout().base_triangles.size()
            << " base triangles; certified one-to-one: " << (map.certificate(crossparam::Mesh_side::source).valid && map.certificate(crossparam::Mesh_side::target).valid ? "yes" : "no")
            << "; angular distortion " << s.distortion.angular << ", L2 stretch " << s.distortion.l2_stretch << "; "
            << s.seconds_total << " s\n";

  // F then F^-1 on the centroid of every source face: back on the same point, up to rounding.
  const CGAL::Bbox_3 box = PMP::bbox(source);
  const double diagonal = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                    CGAL::square(box.zmax() - box.zmin()));
  double worst = 0;
  std::size_t n = 0;
  for (auto f : source.faces()) {
    const Map::Source_location p{f, {{1.0 / 3, 1.0 / 3, 1.0 / 3}}};
    const Map::Target_location q = map.to_target(p); // F(p), a point of the target
    const Map::Source_location r = map.to_source(q); // F^-1(F(p)), a point of the source again
    worst = std::max(worst, std::sqrt(CGAL::squared_distance(PMP::construct_point(p, source),
                                                             PMP::construct_point(r, source))));
    ++n;
  }
  std::cout << "round trip F^-1(F(p)) on " << n << " face centroids: largest distance " << 100 * worst / diagonal
            << "% of the source's diagonal\n";

  // A feature maps onto its partner exactly; any source vertex can be reported against the target as given.
  const crossparam::Input_location nose = map.source_vertex_to_target_input(features[0].source);
  const crossparam::Input_location v = map.source_vertex_to_target_input(source_vertices / 2);
  std::cout << "F(source vertex " << features[0].source << ", feature 0) = target face " << nose.face << " at ("
            << nose.b[0] << ", " << nose.b[1] << ", " << nose.b[2] << "); target vertex " << features[0].target
            << " is its partner\n";
  std::cout << "F(source vertex " << source_vertices / 2 << ") = target face " << v.face << " at (" << v.b[0] << ", "
            << v.b[1] << ", " << v.b[2] << ")\n";
  return worst <= 1e-6 * diagonal ? 0 : 1;
} catch (const crossparam::Error& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 1;
}

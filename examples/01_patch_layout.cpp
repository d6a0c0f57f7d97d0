// SPDX-License-Identifier: GPL-3.0-or-later
// Example 01: topologically identical patch layouts of two meshes (paper §3).
//
//   example_01_patch_layout                       two generated creatures
//   example_01_patch_layout SOURCE TARGET FEATURES  your own meshes and feature file
//
// Shows the generic API: a Polyhedron_3 source, a Surface_mesh target, outputs through property maps.
#include <crossparam/io.h>
#include <crossparam/patch_layout.h>
#include <support/shapes.h>

#include <CGAL/Polyhedron_3.h>
#include <CGAL/Polyhedron_items_with_id_3.h>
#include <CGAL/boost/graph/helpers.h>

#include <iostream>
#include <map>

using Kernel = crossparam::Kernel;
using Polyhedron = CGAL::Polyhedron_3<Kernel, CGAL::Polyhedron_items_with_id_3>;
using Surface_mesh = crossparam::Surface_mesh;

int main(int argc, char** argv) try {
  Polyhedron source;
  Surface_mesh target;
  crossparam::Feature_correspondence features;
  if (argc == 4) {
    crossparam::read_triangle_mesh(argv[1], source); // validated: closed, manifold, finite, ...
    crossparam::read_triangle_mesh(argv[2], target);
    features = crossparam::read_feature_pairs(argv[3], num_vertices(source), num_vertices(target));
  } else {
    Surface_mesh a = crossparam::shapes::creature_a();
    target = crossparam::shapes::creature_b();
    features = crossparam::shapes::creature_features(a, target);
    crossparam::Polygon_soup soup; // copy creature A into the Polyhedron, keeping vertex order
    for (auto v : a.vertices()) soup.points.push_back({a.point(v).x(), a.point(v).y(), a.point(v).z()});
    for (auto f : a.faces()) {
      soup.polygons.emplace_back();
      for (auto v : CGAL::vertices_around_face(a.halfedge(f), a)) soup.polygons.back().push_back(std::size_t(v));
    }
    crossparam::soup_to_triangle_mesh(soup, source, "creature A");
  }

  // Outputs through property maps: base triangle per face, path id per edge, feature per vertex.
  std::map<Polyhedron::Facet_handle, int> source_patch;
  auto target_patch = target.add_property_map<Surface_mesh::Face_index, int>("f:patch", -1).first;
  auto target_path = target.add_property_map<Surface_mesh::Edge_index, int>("e:path", -1).first;

  crossparam::Patch_layout layout = crossparam::compute_patch_layouts(
      source, target, features,
      CGAL::parameters::face_patch_map(boost::make_assoc_property_map(source_patch)),
      crossparam::parameters::edge_path_map(target_path, CGAL::parameters::face_patch_map(target_patch)));

  // compute_patch_layouts verified the result already; the verifier can be called on its own too.
  crossparam::Layout_verification check = crossparam::verify_patch_layouts(source, target, layout);
  std::cout << "base mesh: " << layout.base_triangles.size() << " triangles over " << features.size()
            << " features; verified: " << (check.valid ? "yes" : check.message) << "\n";
  std::cout << "source: " << layout.source.original_vertices << " -> " << num_vertices(source) << " vertices ("
            << layout.source.splits.size() << " splits); target: " << layout.target.original_vertices << " -> "
            << target.number_of_vertices() << " vertices\n";
  const auto& s = layout.statistics;
  std::cout << "paths: " << s.edge_paths << " on edges, " << s.face_paths << " through faces, " << s.flips
            << " flipped; " << s.seconds_total * 1000 << " ms\n";
  std::size_t on_paths = 0;
  for (auto e : target.edges()) on_paths += target_path[e] >= 0;
  std::cout << "target edges on paths: " << on_paths << "; first source face lies in base triangle "
            << source_patch.at(*faces(source).first) << "\n";
  return check.valid ? 0 : 1;
} catch (const crossparam::Error& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 1;
}

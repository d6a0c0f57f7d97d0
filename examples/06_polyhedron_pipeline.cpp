// SPDX-License-Identifier: GPL-3.0-or-later
// Example 06: a user mesh type, CGAL::Polyhedron_3, through the whole pipeline: patch layout, map, compatible
// remeshing, verification.
//
//   example_06_polyhedron_pipeline        two generated creatures
//
// Every stage takes any model of MutableFaceGraph. Feature indices are positions in vertices(mesh) order, and
// the results depend on the order of the input (vertices, faces, and each face's corners from halfedge(f)), not
// on the mesh type: the same pipeline on Surface_mesh copies in the same order gives the same outputs, bit for
// bit, which this example checks.
//
// Building the Polyhedron from a polygon soup (as crossparam::read_triangle_mesh does) keeps the order.
// CGAL::copy_face_graph does not keep the vertex order: after it, translate the feature indices through its
// vertex_to_vertex_output_iterator, or the features name other vertices than intended.
#include <crossparam/compatible_remeshing.h>
#include <crossparam/io.h>
#include <crossparam/remeshing_verification.h>
#include <support/shapes.h>

#include <CGAL/Polyhedron_3.h>
#include <CGAL/Polyhedron_items_with_id_3.h>
#include <CGAL/boost/graph/iterator.h>

#include <iostream>

using Kernel = crossparam::Kernel;
using Polyhedron = CGAL::Polyhedron_3<Kernel, CGAL::Polyhedron_items_with_id_3>;
using Surface_mesh = crossparam::Surface_mesh;

// `m` as a Polyhedron_3 with the same vertex order, face order and face corners.
Polyhedron to_polyhedron(const Surface_mesh& m, const std::string& name) {
  crossparam::Polygon_soup soup;
  for (auto v : m.vertices()) soup.points.push_back({m.point(v).x(), m.point(v).y(), m.point(v).z()});
  for (auto f : m.faces()) {
    soup.polygons.emplace_back();
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) soup.polygons.back().push_back(std::size_t(v));
  }
  Polyhedron p;
  crossparam::soup_to_triangle_mesh(soup, p, name); // validates, sets the item ids
  return p;
}

struct Outputs {
  std::vector<std::array<std::size_t, 3>> faces;
  std::vector<std::array<double, 3>> source_points, target_points;
  bool valid = false;
};

// Layout, map, remeshing and verification on meshes of type Mesh; prints what each stage computed.
template <class Mesh>
Outputs pipeline(const Mesh& source_input, const Mesh& target_input, const crossparam::Feature_correspondence& features,
                 const char* name, double tolerance) {
  Mesh source = source_input, target = target_input; // the map refines its meshes in place
  crossparam::Cross_parameterization<Mesh, Mesh> map(source, target, features);
  const crossparam::Patch_layout& layout = map.layout();
  const crossparam::Layout_verification layout_check = crossparam::verify_patch_layouts(source, target, layout);
  std::cout << name << ": layout of " << layout.base_triangles.size() << " base triangles, " << layout.source.splits.size()
            << " + " << layout.target.splits.size() << " edge splits, verified: " << (layout_check.valid ? "yes" : layout_check.message)
            << "\n";
  std::cout << name << ": map certified one-to-one: " << (map.certificate(crossparam::Mesh_side::source).valid && map.certificate(crossparam::Mesh_side::target).valid ? "yes" : "no")
            << ", angular distortion " << map.statistics().distortion.angular << "\n";

  crossparam::Compatible_remesher<Mesh, Mesh> remesher(map, crossparam::parameters::tolerance(tolerance));
  Mesh source_shaped, target_shaped;
  remesher.copy_to(crossparam::Mesh_side::source, source_shaped);
  remesher.copy_to(crossparam::Mesh_side::target, target_shaped);
  const crossparam::Remeshing_verification v =
      crossparam::verify_compatible_remeshing(source_input, target_input, source_shaped, target_shaped, tolerance);
  std::cout << name << ": remeshed to " << num_vertices(target_shaped) << " vertices, " << num_faces(target_shaped)
            << " faces; verified: " << (v.valid ? "yes" : v.message) << " (Hausdorff to the target " << v.hausdorff_target
            << "%, tolerance " << tolerance << "%)\n";
  return {remesher.faces(), remesher.source_points(), remesher.target_points(), v.valid && layout_check.valid};
}

int main() try {
  const Surface_mesh a = crossparam::shapes::creature_a(), b = crossparam::shapes::creature_b();
  const crossparam::Feature_correspondence features = crossparam::shapes::creature_features(a, b);
  const double tolerance = 1.0; // percent of the target's bounding-box diagonal

  const Outputs p = pipeline(to_polyhedron(a, "creature A"), to_polyhedron(b, "creature B"), features, "Polyhedron_3", tolerance);
  const Outputs s = pipeline(a, b, features, "Surface_mesh", tolerance);
  const bool same = p.faces == s.faces && p.source_points == s.source_points && p.target_points == s.target_points;
  std::cout << "Polyhedron_3 and Surface_mesh outputs identical (faces and points, bit for bit): " << (same ? "yes" : "no")
            << "\n";
  return p.valid && s.valid && same ? 0 : 1;
} catch (const crossparam::Error& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 1;
}

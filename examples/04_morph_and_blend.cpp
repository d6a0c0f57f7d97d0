// SPDX-License-Identifier: GPL-3.0-or-later
// Example 04: morphing between two compatible meshes and an N-way blend of three (paper §1, §2.3).
//
//   example_04_morph_and_blend        three generated creatures
//
// Compatible meshes share one face list, so a morph or a blend is a weighted average of their points, vertex by
// vertex. Creature A is remeshed compatibly with creature B (example 03); a third creature C then gets A's remeshed
// connectivity too: the map from the remeshed A to C sends every vertex onto C. Morph frames between A and B and
// blends of A, B and C are printed as the volume each encloses.
#include <crossparam/compatible_remeshing.h>
#include <crossparam/morph.h>
#include <support/shapes.h>

#include <CGAL/boost/graph/iterator.h>

#include <iostream>

using Surface_mesh = crossparam::Surface_mesh;
using Map = crossparam::Cross_parameterization<Surface_mesh, Surface_mesh>;
using Points = std::vector<std::array<double, 3>>;

// Volume enclosed by the closed mesh with these points and the common face list.
double volume(const Points& p, const std::vector<std::array<std::size_t, 3>>& faces) {
  double v = 0;
  for (const auto& f : faces) {
    const auto &a = p[f[0]], &b = p[f[1]], &c = p[f[2]];
    v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
  }
  return v;
}

int main() try {
  namespace shapes = crossparam::shapes;
  shapes::Creature_params params_c = shapes::creature_a_params(); // a third animal: long neck and tail, short legs
  params_c.neck_length = 0.8;
  params_c.neck_elevation_deg = 55;
  params_c.leg_length = 0.55;
  params_c.tail_length = 0.9;
  params_c.tail_bend_deg = 90;
  Surface_mesh a = shapes::creature_a(), b = shapes::creature_b(), c = shapes::make_creature(params_c);
  const crossparam::Feature_correspondence features_ab = shapes::creature_features(a, b);
  const crossparam::Feature_correspondence features_ac = shapes::creature_features(a, shapes::creature_a_params(), c, params_c);

  // A and B compatible: one face list, A's points exactly on A, B's within 1 % of B's diagonal.
  Map map_ab(a, b, features_ab);
  crossparam::Compatible_remesher<Surface_mesh, Surface_mesh> remesher(map_ab, crossparam::parameters::tolerance(1.0));
  const auto& faces = remesher.faces();
  const Points& pa = remesher.source_points();
  const Points& pb = remesher.target_points();
  std::cout << "A and B remeshed compatibly: " << pa.size() << " vertices, " << faces.size() << " faces\n";

  // C with the same connectivity: F maps every vertex of the remeshed A onto C. The first vertices of the
  // remeshed A are A's own, so the feature indices still hold.
  Surface_mesh a_remeshed, c_input = c;
  remesher.copy_to(crossparam::Mesh_side::source, a_remeshed);
  Map map_ac(a_remeshed, c, features_ac);
  Points pc;
  for (std::size_t v = 0; v < pa.size(); ++v) {
    const crossparam::Input_location l = map_ac.source_vertex_to_target_input(v); // against C as given
    std::array<double, 3> p{0, 0, 0};
    int i = 0;
    for (auto w : CGAL::vertices_around_face(c_input.halfedge(Surface_mesh::Face_index(Surface_mesh::size_type(l.face))), c_input)) {
      for (int k = 0; k < 3; ++k) p[k] += l.b[i] * c_input.point(w)[k];
      ++i;
    }
    pc.push_back(p);
  }
  std::cout << "C mapped onto the same connectivity (F of each vertex, not refined for C)\n";

  // The morph A -> B at five times, and blends of all three.
  crossparam::Polygon_soup soup_a{pa, {}}, soup_b{pb, {}};
  for (const auto& f : faces) soup_a.polygons.push_back({f[0], f[1], f[2]});
  soup_b.polygons = soup_a.polygons;
  crossparam::check_compatible(soup_a, soup_b, "A", "B");
  std::cout << "volume of the morph A -> B:";
  for (double t : {0.0, 0.25, 0.5, 0.75, 1.0}) std::cout << "  t = " << t << ": " << volume(crossparam::morph(pa, pb, t), faces);
  std::cout << "\n";
  for (const std::vector<double>& w : {std::vector<double>{1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.5, 0.25, 0.25}, {0.2, 0.2, 0.6}})
    std::cout << "blend " << w[0] << " A + " << w[1] << " B + " << w[2] << " C: volume "
              << volume(crossparam::blend({&pa, &pb, &pc}, w), faces) << "\n";
  return 0;
} catch (const crossparam::Error& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 1;
}

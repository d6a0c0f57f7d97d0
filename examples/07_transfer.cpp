// SPDX-License-Identifier: GPL-3.0-or-later
// Example 07: transfer through the map (paper §6): per-vertex data of one model onto another model's own
// vertices, and a texture's coordinates onto the other model's shape.
//
//   example_07_transfer        two generated creatures
//
// The data is the source's height (a linear field: it arrives exactly, up to rounding) and a label per vertex
// (which half of the body it is on, front or back: carried by the nearest corner). The "texture" gives every
// source face its own chart (a seam at every edge): the target-shaped compatible mesh takes, corner by corner,
// the coordinates of the source face it lies in, and is written as an OBJ with its MTL.
#include <crossparam/attribute_transfer.h>
#include <crossparam/compatible_remeshing.h>
#include <crossparam/textured_obj.h>
#include <support/shapes.h>

#include <CGAL/boost/graph/iterator.h>

#include <filesystem>
#include <iostream>

using Surface_mesh = crossparam::Surface_mesh;
using Map = crossparam::Cross_parameterization<Surface_mesh, Surface_mesh>;

int main() try {
  namespace shapes = crossparam::shapes;
  const Surface_mesh a0 = shapes::creature_a(), b0 = shapes::creature_b();
  Surface_mesh a = a0, b = b0;
  const Map map(a, b, shapes::creature_features(a, b));

  // Height and front/back label of every vertex of A, carried onto B's vertices.
  crossparam::Vertex_data height;
  std::vector<long> front;
  for (auto v : a0.vertices()) {
    height.push_back({a0.point(v).z()});
    front.push_back(a0.point(v).x() > 0 ? 1 : 0);
  }
  const crossparam::Vertex_data height_on_b = crossparam::transfer_vertex_data(map, crossparam::Mesh_side::source, height);
  const std::vector<long> front_on_b = crossparam::transfer_vertex_labels(map, crossparam::Mesh_side::source, front);
  std::size_t front_count = 0;
  for (long x : front_on_b) front_count += std::size_t(x);
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (const auto& row : height_on_b) lo = std::min(lo, row[0]), hi = std::max(hi, row[0]);
  std::cout << "A's height on B's " << height_on_b.size() << " vertices: from " << lo << " to " << hi << "; "
            << front_count << " of them take the label 'front half of A'\n";

  // Texture coordinates, one chart per face of A: u, v from the position plus an offset per face.
  crossparam::Mesh_uvs uv;
  std::size_t fi = 0;
  for (auto f : a0.faces()) {
    std::array<std::size_t, 3> vs{}, ts{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(a0.halfedge(f), a0)) {
      vs[std::size_t(k)] = std::size_t(v);
      ts[std::size_t(k++)] = uv.uvs.size();
      uv.uvs.push_back({0.5 + 0.3 * a0.point(v).x(), 0.5 + 0.3 * a0.point(v).z() + 1e-3 * double(fi % 2)});
    }
    uv.face_vertices.push_back(vs);
    uv.face_uvs.push_back(ts);
    ++fi;
  }
  const crossparam::Compatible_remesher<Surface_mesh, Surface_mesh> r(map, crossparam::parameters::tolerance(1.0));
  const std::vector<crossparam::Corner_uvs> uvs = crossparam::transfer_corner_uvs(r.source_face_locations(), uv);
  const std::string path = (std::filesystem::temp_directory_path() / "crossparam_example_07.obj").string();
  crossparam::write_textured_obj(path, r.target_points(), r.faces(), uvs, "texture.png");
  std::cout << "B's shape with A's texture coordinates: " << r.faces().size() << " faces, written to " << path << "\n";
  std::filesystem::remove(path);
  std::filesystem::remove(std::filesystem::path(path).replace_extension(".mtl"));
  return uvs.size() == r.faces().size() && front_count > 0 && front_count < front_on_b.size() ? 0 : 1;
} catch (const crossparam::Error& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 1;
}

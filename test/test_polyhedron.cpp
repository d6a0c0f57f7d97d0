// SPDX-License-Identifier: GPL-3.0-or-later
// A user mesh type through the whole pipeline: CGAL::Polyhedron_3 (with item ids) gets the same results as
// CGAL::Surface_mesh when its input order is the same (vertices, faces, and each face's corners from
// halfedge(f)): the same layout, the same refined meshes, the same map, the same remeshed outputs, bit for bit.
#include <crossparam/compatible_remeshing.h>
#include <crossparam/io.h>
#include <crossparam/remeshing_verification.h>
#include <support/shapes.h>

#include <CGAL/Polyhedron_3.h>
#include <CGAL/Polyhedron_items_with_id_3.h>
#include <CGAL/boost/graph/iterator.h>

#include <gtest/gtest.h>

#include "bench_cases.h"

#include <map>
#include <optional>
#include <type_traits>

using namespace crossparam;
using Polyhedron = CGAL::Polyhedron_3<Kernel, CGAL::Polyhedron_items_with_id_3>;

namespace {

/// `m` as a Polyhedron_3 in the same vertex order, face order and face corners.
Polyhedron to_polyhedron(const Surface_mesh& m) {
  Polygon_soup soup;
  for (auto v : m.vertices()) soup.points.push_back({m.point(v).x(), m.point(v).y(), m.point(v).z()});
  for (auto f : m.faces()) {
    soup.polygons.emplace_back();
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) soup.polygons.back().push_back(std::size_t(v));
  }
  Polyhedron p;
  soup_to_triangle_mesh(soup, p, "polyhedron copy");
  return p;
}

/// A mesh as plain data: points in vertices() order, faces in faces() order as corner indices from halfedge(f).
struct Mesh_data {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<std::size_t, 3>> faces;
  bool operator==(const Mesh_data& o) const { return points == o.points && faces == o.faces; }
};

template <class Mesh>
Mesh_data data_of(const Mesh& m) {
  Mesh_data d;
  std::map<typename boost::graph_traits<Mesh>::vertex_descriptor, std::size_t> index;
  for (auto v : vertices(m)) {
    index.emplace(v, d.points.size());
    const auto& p = get(CGAL::vertex_point, m, v);
    d.points.push_back({p.x(), p.y(), p.z()});
  }
  for (auto f : faces(m)) {
    std::array<std::size_t, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(halfedge(f, m), m)) t[std::size_t(k++)] = index.at(v);
    d.faces.push_back(t);
  }
  return d;
}

/// Everything the pipeline computes that does not depend on the mesh type (timings left out).
struct Pipeline_outputs {
  Patch_layout layout;
  Mesh_data refined_source, refined_target;                ///< after the map's splits
  std::vector<Input_location> source_images, target_images; ///< F and F^-1 of every vertex
  std::vector<std::array<std::size_t, 3>> faces;            ///< of the remeshing
  std::vector<std::array<double, 3>> source_points, target_points;
  std::vector<Input_location> target_locations;
  std::vector<double> vertex_error;
  Remeshing_verification verification;
};

template <class SourceMesh, class TargetMesh>
Pipeline_outputs run_pipeline(const SourceMesh& source, const TargetMesh& target, const Feature_correspondence& f,
                              double tolerance, bool verify) {
  Pipeline_outputs o;
  {
    SourceMesh s = source;
    TargetMesh t = target;
    o.layout = compute_patch_layouts(s, t, f);
  }
  SourceMesh s = source;
  TargetMesh t = target;
  Cross_parameterization<SourceMesh, TargetMesh> cp(s, t, f);
  EXPECT_TRUE(cp.certificate(crossparam::Mesh_side::source).valid && cp.certificate(crossparam::Mesh_side::target).valid);
  o.refined_source = data_of(s);
  o.refined_target = data_of(t);
  for (std::size_t v = 0; v < o.refined_source.points.size(); ++v) o.source_images.push_back(cp.source_vertex_to_target_input(v));
  for (std::size_t v = 0; v < o.refined_target.points.size(); ++v) o.target_images.push_back(cp.target_vertex_to_source_input(v));
  Compatible_remesher<SourceMesh, TargetMesh> r(cp, crossparam::parameters::tolerance(tolerance));
  o.faces = r.faces();
  o.source_points = r.source_points();
  o.target_points = r.target_points();
  o.target_locations = r.target_locations();
  o.vertex_error = r.vertex_error();
  if constexpr (std::is_same_v<SourceMesh, TargetMesh>) { // the verifier takes one mesh type
    if (verify) {
      SourceMesh os, ot;
      r.copy_to(crossparam::Mesh_side::source, os);
      r.copy_to(crossparam::Mesh_side::target, ot);
      o.verification = verify_compatible_remeshing(source, target, os, ot, tolerance);
    }
  }
  return o;
}

bool same_locations(const std::vector<Input_location>& a, const std::vector<Input_location>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].face != b[i].face || a[i].b != b[i].b) return false;
  return true;
}

bool same_mesh_layout(const Mesh_layout& a, const Mesh_layout& b) {
  if (a.splits.size() != b.splits.size()) return false;
  for (std::size_t i = 0; i < a.splits.size(); ++i)
    if (a.splits[i].u != b.splits[i].u || a.splits[i].v != b.splits[i].v || a.splits[i].w != b.splits[i].w ||
        a.splits[i].t != b.splits[i].t)
      return false;
  return a.original_vertices == b.original_vertices && a.original_faces == b.original_faces &&
         a.face_triangle == b.face_triangle && a.paths == b.paths && a.feature_vertices == b.feature_vertices;
}

void expect_same(const Pipeline_outputs& a, const Pipeline_outputs& b) {
  EXPECT_EQ(a.layout.base_triangles, b.layout.base_triangles);
  EXPECT_EQ(a.layout.base_edges, b.layout.base_edges);
  EXPECT_TRUE(same_mesh_layout(a.layout.source, b.layout.source));
  EXPECT_TRUE(same_mesh_layout(a.layout.target, b.layout.target));
  EXPECT_TRUE(a.refined_source == b.refined_source);
  EXPECT_TRUE(a.refined_target == b.refined_target);
  EXPECT_TRUE(same_locations(a.source_images, b.source_images));
  EXPECT_TRUE(same_locations(a.target_images, b.target_images));
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.source_points, b.source_points);
  EXPECT_EQ(a.target_points, b.target_points);
  EXPECT_TRUE(same_locations(a.target_locations, b.target_locations));
  EXPECT_EQ(a.vertex_error, b.vertex_error);
}

} // namespace

// A generated pair (no shared data): Polyhedron_3 on both sides, and a Polyhedron_3 source with a Surface_mesh
// target, against Surface_mesh on both sides; the Polyhedron_3 outputs pass the independent verification.
TEST(Polyhedron, GeneratedPairSameAsSurfaceMesh) {
  const Surface_mesh a = shapes::make_deformed_sphere(3, 1500, false), b = shapes::make_deformed_sphere(11, 1200, true);
  const Feature_correspondence f = shapes::random_features(a, b, 8, 5, false);
  const double tolerance = 1.0;
  const Pipeline_outputs sm = run_pipeline(a, b, f, tolerance, false);
  const Pipeline_outputs poly = run_pipeline(to_polyhedron(a), to_polyhedron(b), f, tolerance, true);
  expect_same(poly, sm);
  EXPECT_TRUE(poly.verification.valid) << poly.verification.message;
  const Pipeline_outputs mixed = run_pipeline(to_polyhedron(a), b, f, tolerance, false);
  expect_same(mixed, sm);
}

// A bench pair in both mesh types, the Polyhedron_3 source copied from the Surface_mesh in the same order, the
// Polyhedron_3 target read from its file: layout, map and remeshing give the same outputs.
TEST(Polyhedron, BenchPairSameAsSurfaceMesh) {
  const std::string name = "wolf0_wolf2";
  std::optional<test_bench::Case> c = test_bench::load(name);
  if (!c) GTEST_SKIP() << test_bench::absent(name);
  const double tolerance = 0.5;
  Polyhedron target;
  read_triangle_mesh((c->dir / "target.off").string(), target);
  const Pipeline_outputs sm = run_pipeline(c->source, c->target, c->features, tolerance, false);
  const Pipeline_outputs poly = run_pipeline(to_polyhedron(c->source), target, c->features, tolerance, false);
  expect_same(poly, sm);
  EXPECT_FALSE(poly.faces.empty());
}

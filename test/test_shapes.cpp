// SPDX-License-Identifier: GPL-3.0-or-later
// The generated inputs (shapes.h) are what the self-contained tests and the demo stand on: closed, valid,
// one component, the right genus, outward, deterministic.
#include <crossparam/io.h>
#include <crossparam/shapes.h>

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>

#include <gtest/gtest.h>

#include <set>

using namespace crossparam;
namespace PMP = CGAL::Polygon_mesh_processing;

namespace {

void expect_closed_surface(const Surface_mesh& m, int genus, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_TRUE(CGAL::is_valid_polygon_mesh(m));
  EXPECT_TRUE(CGAL::is_closed(m));
  EXPECT_TRUE(CGAL::is_triangle_mesh(m));
  Mesh_check_report r = check_triangle_mesh(m, what); // one component, manifold, finite: throws otherwise
  EXPECT_EQ(r.genus, genus);
  EXPECT_GT(PMP::volume(m), 0.0) << "outward oriented";
  std::size_t degenerate = 0;
  for (auto f : m.faces()) degenerate += PMP::is_degenerate_triangle_face(f, m);
  EXPECT_EQ(degenerate, 0u);
}

bool same(const Surface_mesh& a, const Surface_mesh& b) {
  if (a.number_of_vertices() != b.number_of_vertices() || a.number_of_faces() != b.number_of_faces()) return false;
  for (auto v : a.vertices())
    if (a.point(v) != b.point(v)) return false;
  for (auto f : a.faces()) {
    auto ha = a.halfedge(f), hb = b.halfedge(f);
    if (a.target(ha) != b.target(hb) || a.target(a.next(ha)) != b.target(b.next(hb))) return false;
  }
  return true;
}

} // namespace

TEST(Shapes, Creatures) {
  Surface_mesh a = shapes::creature_a(), b = shapes::creature_b();
  expect_closed_surface(a, 0, "creature A");
  expect_closed_surface(b, 0, "creature B");
  EXPECT_NE(a.number_of_vertices(), b.number_of_vertices()) << "different connectivity";
  EXPECT_GT(a.number_of_vertices(), 1000u);
  EXPECT_GT(b.number_of_vertices(), 1000u);
  EXPECT_TRUE(same(a, shapes::creature_a())) << "deterministic";
  Feature_correspondence f = shapes::creature_features(a, b);
  EXPECT_GE(f.size(), 8u);
  EXPECT_NO_THROW(validate_feature_pairs(f, a.number_of_vertices(), b.number_of_vertices(), "creature features"));
}

TEST(Shapes, DeformedSpheres) {
  for (unsigned seed : {1u, 2u, 3u}) {
    for (bool irregular : {false, true}) {
      Surface_mesh m = shapes::make_deformed_sphere(seed, 800, irregular);
      expect_closed_surface(m, 0, "sphere " + std::to_string(seed));
      EXPECT_GT(m.number_of_vertices(), 300u);
      EXPECT_LT(m.number_of_vertices(), 2000u);
      EXPECT_TRUE(same(m, shapes::make_deformed_sphere(seed, 800, irregular))) << "deterministic";
    }
  }
  // Different seeds, different connectivity.
  EXPECT_NE(shapes::make_deformed_sphere(1, 800, true).number_of_faces(),
            shapes::make_deformed_sphere(2, 800, true).number_of_faces());
}

TEST(Shapes, RandomFeatures) {
  Surface_mesh a = shapes::make_deformed_sphere(5, 600, true), b = shapes::make_deformed_sphere(6, 700, true);
  for (bool permute : {false, true}) {
    Feature_correspondence f = shapes::random_features(a, b, 25, 7, permute);
    ASSERT_EQ(f.size(), 25u);
    EXPECT_NO_THROW(validate_feature_pairs(f, a.number_of_vertices(), b.number_of_vertices(), "random features"));
  }
}

TEST(Shapes, Torus) {
  Surface_mesh t = shapes::make_torus(1.0, 0.3, 24, 12);
  expect_closed_surface(t, 1, "torus");
  EXPECT_EQ(t.number_of_vertices(), 24u * 12u);
}

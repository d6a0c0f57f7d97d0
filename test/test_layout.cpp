// SPDX-License-Identifier: GPL-3.0-or-later
// Patch layouts (paper §3): randomized property tests on generated genus-0 meshes, generic mesh types,
// property-map outputs, bad input, and the verifier's ability to reject broken layouts.
#include <crossparam/patch_layout.h>
#include <support/shapes.h>

#include <CGAL/Polyhedron_3.h>
#include <CGAL/Polyhedron_items_with_id_3.h>
#include <CGAL/boost/graph/generators.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/boost/graph/copy_face_graph.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>

using namespace crossparam;
using Polyhedron = CGAL::Polyhedron_3<Kernel, CGAL::Polyhedron_items_with_id_3>;

namespace {

std::size_t env_or(const char* name, std::size_t fallback) {
  const char* v = std::getenv(name);
  return v ? std::size_t(std::strtoul(v, nullptr, 10)) : fallback;
}

/// Checks everything a layout promises beyond the verifier: counts of a sphere triangulation, original
/// vertices untouched and first, features where they were.
void expect_layout_invariants(const Surface_mesh& before_s, const Surface_mesh& before_t, const Surface_mesh& s,
                              const Surface_mesh& t, const Feature_correspondence& f, const Patch_layout& L) {
  const std::size_t n = f.size();
  EXPECT_EQ(L.base_triangles.size(), 2 * n - 4);
  EXPECT_EQ(L.base_edges.size(), 3 * n - 6);
  ASSERT_GE(s.number_of_vertices(), before_s.number_of_vertices());
  ASSERT_GE(t.number_of_vertices(), before_t.number_of_vertices());
  EXPECT_EQ(s.number_of_vertices() - before_s.number_of_vertices(), L.source.splits.size());
  EXPECT_EQ(t.number_of_vertices() - before_t.number_of_vertices(), L.target.splits.size());
  for (auto v : before_s.vertices()) ASSERT_EQ(before_s.point(v), s.point(v));
  for (auto v : before_t.vertices()) ASSERT_EQ(before_t.point(v), t.point(v));
  for (std::size_t k = 0; k < n; ++k) {
    EXPECT_EQ(L.source.feature_vertices[k], f[k].source);
    EXPECT_EQ(L.target.feature_vertices[k], f[k].target);
  }
  Layout_verification check = verify_patch_layouts(s, t, L);
  EXPECT_TRUE(check.valid) << check.message;
}

} // namespace

// At least 200 trials on generated meshes of different shape and connectivity, 4 to 40 features, a third
// of them with randomly permuted ("twisted") correspondences. CROSSPARAM_LAYOUT_TRIALS=N runs longer.
TEST(Layout, RandomizedGenusZero) {
  const std::size_t trials = env_or("CROSSPARAM_LAYOUT_TRIALS", 200);
  std::mt19937 rng(20261121);
  std::size_t twisted = 0, face_paths = 0, flips = 0;
  for (std::size_t trial = 0; trial < trials; ++trial) {
    const unsigned seed = unsigned(rng());
    const std::size_t nv_a = 150 + rng() % 1500, nv_b = 150 + rng() % 1500;
    Surface_mesh a = shapes::make_deformed_sphere(seed, nv_a, trial % 2 == 0);
    Surface_mesh b = shapes::make_deformed_sphere(seed + 1, nv_b, true);
    const std::size_t nf = 4 + rng() % 37;
    const bool permute = trial % 3 == 0;
    twisted += permute;
    Feature_correspondence f = shapes::random_features(a, b, nf, seed + 2, permute);
    Surface_mesh a0 = a, b0 = b;
    SCOPED_TRACE("trial " + std::to_string(trial) + " seed " + std::to_string(seed) + " features " +
                 std::to_string(nf) + (permute ? " twisted" : ""));
    Patch_layout L;
    ASSERT_NO_THROW(L = compute_patch_layouts(a, b, f));
    expect_layout_invariants(a0, b0, a, b, f, L);
    face_paths += L.statistics.face_paths;
    flips += L.statistics.flips;
  }
  EXPECT_GE(twisted, trials / 3);
  EXPECT_GT(face_paths, 0u); // the face-path stage was exercised
  EXPECT_GT(flips, 0u);      // and so were path flips
}

namespace {
/// The length of every path of a layout, on one mesh.
double total_path_length(const Surface_mesh& m, const Mesh_layout& L) {
  double total = 0;
  for (const auto& p : L.paths)
    for (std::size_t i = 0; i + 1 < p.size(); ++i)
      total += std::sqrt(CGAL::squared_distance(m.point(Surface_mesh::Vertex_index(Surface_mesh::size_type(p[i]))),
                                                m.point(Surface_mesh::Vertex_index(Surface_mesh::size_type(p[i + 1])))));
  return total;
}
} // namespace

// Straightening (parameters::straighten_paths): the same layout as without it, its paths replaced by shorter ones
// inside their two patches: verified, the same base mesh and splits, and the paths of both meshes together no
// longer on any trial, shorter on most.
TEST(Layout, StraighteningShortensPaths) {
  std::mt19937 rng(20261127);
  std::size_t straightened = 0, shorter = 0;
  const std::size_t trials = 30;
  for (std::size_t trial = 0; trial < trials; ++trial) {
    const unsigned seed = unsigned(rng());
    Surface_mesh a = shapes::make_deformed_sphere(seed, 300 + rng() % 1200, trial % 2 == 0);
    Surface_mesh b = shapes::make_deformed_sphere(seed + 1, 300 + rng() % 1200, true);
    const Feature_correspondence f = shapes::random_features(a, b, 6 + rng() % 30, seed + 2, trial % 3 == 0);
    SCOPED_TRACE("trial " + std::to_string(trial) + " seed " + std::to_string(seed));
    Surface_mesh a0 = a, b0 = b, a2 = a, b2 = b;
    const Patch_layout plain = compute_patch_layouts(a, b, f);
    Patch_layout L;
    ASSERT_NO_THROW(L = compute_patch_layouts(a2, b2, f, parameters::straighten_paths(true), CGAL::parameters::default_values()));
    expect_layout_invariants(a0, b0, a2, b2, f, L);
    EXPECT_EQ(L.base_triangles, plain.base_triangles);
    EXPECT_EQ(L.source.splits.size(), plain.source.splits.size()); // no vertex added
    EXPECT_EQ(L.target.splits.size(), plain.target.splits.size());
    const double before = total_path_length(a, plain.source) + total_path_length(b, plain.target);
    const double after = total_path_length(a2, L.source) + total_path_length(b2, L.target);
    EXPECT_LE(after, before * (1 + 1e-12));
    EXPECT_EQ(plain.statistics.straightened, 0u);
    straightened += L.statistics.straightened;
    shorter += after < before;
  }
  EXPECT_GT(straightened, 0u);
  EXPECT_GE(shorter, trials / 2);
}

// The smallest case: 4 features give a tetrahedral base mesh.
TEST(Layout, FourFeaturesTetrahedron) {
  Surface_mesh a = shapes::make_deformed_sphere(1, 300, false), b = shapes::make_deformed_sphere(2, 500, true);
  Feature_correspondence f = shapes::random_features(a, b, 4, 3, false);
  Surface_mesh a0 = a, b0 = b;
  Patch_layout L = compute_patch_layouts(a, b, f);
  expect_layout_invariants(a0, b0, a, b, f, L);
  EXPECT_EQ(L.base_triangles.size(), 4u);
}

// Generic mesh types: a Polyhedron_3 source and a Surface_mesh target, with all property-map outputs.
TEST(Layout, PolyhedronAndPropertyMaps) {
  Surface_mesh a_sm = shapes::make_deformed_sphere(7, 800, true), b = shapes::make_deformed_sphere(8, 600, true);
  Polyhedron a;
  CGAL::copy_face_graph(a_sm, a);
  // The feature indices refer to vertices(a) order: rebuild them from positions.
  std::vector<Polyhedron::Vertex_handle> av(vertices(a).begin(), vertices(a).end());
  std::map<Point_3, std::size_t> index_of;
  for (std::size_t i = 0; i < av.size(); ++i) index_of[av[i]->point()] = i;
  Feature_correspondence f = shapes::random_features(a_sm, b, 12, 9, false);
  for (auto& p : f) p.source = index_of.at(a_sm.point(Surface_mesh::Vertex_index(Surface_mesh::size_type(p.source))));

  std::map<Polyhedron::Facet_handle, int> pa_face;
  std::map<Polyhedron::Halfedge_handle, int> dummy;
  boost::associative_property_map<std::map<Polyhedron::Facet_handle, int>> fpm(pa_face);
  auto b_face = b.add_property_map<Surface_mesh::Face_index, int>("f:patch", -1).first;
  auto b_edge = b.add_property_map<Surface_mesh::Edge_index, int>("e:path", -2).first;
  auto b_vert = b.add_property_map<Surface_mesh::Vertex_index, int>("v:feature", -2).first;

  Patch_layout L = compute_patch_layouts(
      a, b, f, CGAL::parameters::face_patch_map(fpm),
      crossparam::parameters::edge_path_map(b_edge, crossparam::parameters::vertex_feature_map(
                                                        b_vert, CGAL::parameters::face_patch_map(b_face))));
  Layout_verification check = verify_patch_layouts(a, b, L);
  ASSERT_TRUE(check.valid) << check.message;
  // Polyhedron face map agrees with the returned labels, face by face in faces(a) order.
  std::size_t i = 0;
  for (auto fh : faces(a)) EXPECT_EQ(pa_face.at(fh), L.source.face_triangle[i++]);
  // Surface_mesh maps agree too.
  i = 0;
  for (auto fh : b.faces()) EXPECT_EQ(b_face[fh], L.target.face_triangle[i++]);
  std::size_t path_edges = 0;
  for (const auto& p : L.target.paths) path_edges += p.size() - 1;
  std::size_t marked = 0;
  for (auto e : b.edges()) {
    EXPECT_GE(b_edge[e], -1);
    marked += b_edge[e] >= 0;
  }
  EXPECT_EQ(marked, path_edges);
  std::size_t features = 0;
  for (auto v : b.vertices())
    if (b_vert[v] >= 0) {
      ++features;
      EXPECT_EQ(std::size_t(v), f[b_vert[v]].target);
    }
  EXPECT_EQ(features, f.size());
}

// Orientation and scale do not matter: an inward-oriented target and tiny or huge coordinates.
TEST(Layout, InwardOrientationAndExtremeScales) {
  for (double scale : {1.0, 1e-150, 1e-90, 1e90}) {
    Surface_mesh a = shapes::make_deformed_sphere(11, 700, true), b = shapes::make_deformed_sphere(12, 900, true);
    for (auto v : b.vertices()) b.point(v) = Point_3(b.point(v).x() * scale, b.point(v).y() * scale, b.point(v).z() * scale);
    CGAL::Polygon_mesh_processing::reverse_face_orientations(b);
    Feature_correspondence f = shapes::random_features(a, b, 15, 13, false);
    Surface_mesh a0 = a, b0 = b;
    Patch_layout L;
    ASSERT_NO_THROW(L = compute_patch_layouts(a, b, f)) << "scale " << scale;
    expect_layout_invariants(a0, b0, a, b, f, L);
  }
}

// Zero-area and needle triangles in an otherwise valid mesh do not break the layout.
TEST(Layout, DegenerateTriangles) {
  Surface_mesh a = shapes::make_deformed_sphere(21, 900, false), b = shapes::make_deformed_sphere(22, 900, true);
  // Move every 7th vertex onto the midpoint of one of its edges: its fan then has zero-area triangles.
  std::size_t moved = 0;
  for (auto v : a.vertices()) {
    if (std::size_t(v) % 7) continue;
    auto h = a.halfedge(v);
    a.point(v) = CGAL::midpoint(a.point(a.source(h)), a.point(a.target(a.next(h))));
    ++moved;
  }
  ASSERT_GT(moved, 10u);
  Feature_correspondence f = shapes::random_features(a, b, 20, 23, false);
  Surface_mesh a0 = a, b0 = b;
  Patch_layout L;
  ASSERT_NO_THROW(L = compute_patch_layouts(a, b, f));
  expect_layout_invariants(a0, b0, a, b, f, L);
}

// Bad input at the library level: each gets its own exception and message.
TEST(Layout, BadInputIsReported) {
  Surface_mesh a = shapes::make_deformed_sphere(31, 400, false), b = shapes::make_deformed_sphere(32, 400, true);
  Feature_correspondence f = shapes::random_features(a, b, 6, 33, false);
  auto expect_error = [&](auto&& call, const std::string& words) {
    try {
      call();
      ADD_FAILURE() << "no exception, expected: " << words;
    } catch (const Input_error& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  {
    Surface_mesh a1 = a, b1 = b;
    Feature_correspondence g(f.begin(), f.begin() + 3);
    expect_error([&] { compute_patch_layouts(a1, b1, g); }, "3");
  }
  {
    Surface_mesh a1 = a, b1 = b;
    Feature_correspondence g = f;
    g[1].source = g[0].source;
    expect_error([&] { compute_patch_layouts(a1, b1, g); }, "source");
  }
  {
    Surface_mesh a1 = a, b1 = b;
    Feature_correspondence g = f;
    g[2].target = b.number_of_vertices() + 5;
    expect_error([&] { compute_patch_layouts(a1, b1, g); }, "range");
  }
  {
    Surface_mesh a1 = a, torus = shapes::make_torus(1.0, 0.3, 24, 12);
    Feature_correspondence g = f;
    for (auto& p : g) p.target %= torus.number_of_vertices();
    try {
      compute_patch_layouts(a1, torus, g);
      ADD_FAILURE() << "genus mismatch not reported";
    } catch (const Incompatible_inputs_error& e) {
      EXPECT_NE(std::string(e.what()).find("genus"), std::string::npos) << e.what();
    }
  }
  {
    Surface_mesh a1 = a, b1 = b;
    b1.point(*b1.vertices().begin()) = Point_3(std::nan(""), 0, 0);
    expect_error([&] { compute_patch_layouts(a1, b1, f); }, "target");
  }
}

// The verifier does not trust the builder: it rejects layouts broken in different ways.
TEST(Layout, VerifierRejectsBrokenLayouts) {
  Surface_mesh a = shapes::make_deformed_sphere(41, 800, true), b = shapes::make_deformed_sphere(42, 800, true);
  Feature_correspondence f = shapes::random_features(a, b, 10, 43, false);
  Patch_layout L = compute_patch_layouts(a, b, f);
  ASSERT_TRUE(verify_patch_layouts(a, b, L).valid);
  {
    Patch_layout B = L; // a face moved to another patch
    B.target.face_triangle[0] = (B.target.face_triangle[0] + 1) % int(B.base_triangles.size());
    EXPECT_FALSE(verify_patch_layouts(a, b, B).valid);
  }
  {
    Patch_layout B = L; // two corners of a base triangle swapped: orientation broken
    std::swap(B.base_triangles[0][1], B.base_triangles[0][2]);
    EXPECT_FALSE(verify_patch_layouts(a, b, B).valid);
  }
  {
    Patch_layout B = L; // a path reversed but not its base edge
    std::reverse(B.source.paths[0].begin(), B.source.paths[0].end());
    EXPECT_FALSE(verify_patch_layouts(a, b, B).valid);
  }
  {
    Patch_layout B = L; // a path dropped
    B.source.paths.pop_back();
    EXPECT_FALSE(verify_patch_layouts(a, b, B).valid);
  }
  {
    Patch_layout B = L; // two paths of one mesh exchanged: the patches no longer meet along them
    std::swap(B.target.paths[0], B.target.paths[1]);
    EXPECT_FALSE(verify_patch_layouts(a, b, B).valid);
  }
}

// Ids are deterministic: the same input gives the same layout.
TEST(Layout, Deterministic) {
  Surface_mesh a = shapes::make_deformed_sphere(51, 900, true), b = shapes::make_deformed_sphere(52, 700, true);
  Feature_correspondence f = shapes::random_features(a, b, 18, 53, true);
  Surface_mesh a2 = a, b2 = b;
  Patch_layout L1 = compute_patch_layouts(a, b, f), L2 = compute_patch_layouts(a2, b2, f);
  EXPECT_EQ(L1.base_triangles, L2.base_triangles);
  EXPECT_EQ(L1.source.face_triangle, L2.source.face_triangle);
  EXPECT_EQ(L1.target.paths, L2.target.paths);
}

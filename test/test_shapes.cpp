// SPDX-License-Identifier: GPL-3.0-or-later
// The generated inputs (shapes.h) are what the self-contained tests and the demo stand on: closed, valid,
// one component, the right genus, outward, deterministic.
#include <crossparam/io.h>
#include <support/shapes.h>

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/boost/graph/helpers.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <vector>

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using crossparam::Feature_correspondence;
using crossparam::Point_3;
using crossparam::Surface_mesh;
namespace shapes = crossparam::shapes;
using VI = Surface_mesh::Vertex_index;

std::size_t components(const Surface_mesh& m) {
  std::vector<char> seen(m.number_of_vertices(), 0);
  std::size_t n = 0;
  for (auto v0 : m.vertices()) {
    if (seen[v0]) continue;
    ++n;
    std::vector<VI> stack{v0};
    seen[v0] = 1;
    while (!stack.empty()) {
      VI v = stack.back();
      stack.pop_back();
      for (auto w : CGAL::vertices_around_target(v, m))
        if (!seen[w]) {
          seen[w] = 1;
          stack.push_back(w);
        }
    }
  }
  return n;
}

double min_angle_deg(const Surface_mesh& m) {
  double best = 180;
  for (auto f : m.faces()) {
    auto h = m.halfedge(f);
    const Point_3 p[3] = {m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h)))};
    for (int i = 0; i < 3; ++i) {
      const auto u = p[(i + 1) % 3] - p[i];
      const auto w = p[(i + 2) % 3] - p[i];
      const double c = (u * w) / std::sqrt(u.squared_length() * w.squared_length());
      best = std::min(best, std::acos(std::max(-1.0, std::min(1.0, c))) * 180.0 / 3.14159265358979323846);
    }
  }
  return best;
}

/// Every property the cross-parameterization needs of an input mesh.
void expect_closed_surface(const Surface_mesh& m, int genus, double min_angle = 1.0) {
  ASSERT_FALSE(m.has_garbage());
  ASSERT_GT(m.number_of_vertices(), 0u);
  EXPECT_TRUE(CGAL::is_valid_polygon_mesh(m));
  EXPECT_TRUE(CGAL::is_triangle_mesh(m));
  EXPECT_TRUE(CGAL::is_closed(m));
  const long chi = static_cast<long>(m.number_of_vertices()) - static_cast<long>(m.number_of_edges()) +
                   static_cast<long>(m.number_of_faces());
  EXPECT_EQ(chi, 2 - 2 * genus);
  EXPECT_EQ(components(m), 1u);
  // The library's own input check (one component, manifold, finite; throws otherwise).
  crossparam::Mesh_check_report r;
  EXPECT_NO_THROW(r = crossparam::check_triangle_mesh(m, "generated mesh"));
  EXPECT_EQ(r.genus, genus);
  EXPECT_EQ(r.reoriented_faces, 0u);
  EXPECT_TRUE(PMP::is_outward_oriented(m));
  EXPECT_GT(PMP::volume(m), 0.0);
  std::size_t degenerate = 0;
  for (auto f : m.faces())
    if (PMP::is_degenerate_triangle_face(f, m)) ++degenerate;
  EXPECT_EQ(degenerate, 0u);
  EXPECT_GT(min_angle_deg(m), min_angle);
}

bool identical(const Surface_mesh& a, const Surface_mesh& b) {
  if (a.number_of_vertices() != b.number_of_vertices() || a.number_of_faces() != b.number_of_faces()) return false;
  for (auto v : a.vertices())
    if (a.point(v) != b.point(v)) return false;  // bit-identical coordinates
  auto fb = b.faces().begin();
  for (auto f : a.faces()) {
    std::vector<std::size_t> va, vb;
    for (auto v : CGAL::vertices_around_face(a.halfedge(f), a)) va.push_back(v);
    for (auto v : CGAL::vertices_around_face(b.halfedge(*fb), b)) vb.push_back(v);
    if (va != vb) return false;
    ++fb;
  }
  return true;
}

/// Same vertex count and the same set of triangles (as sorted vertex triples)?
bool same_connectivity(const Surface_mesh& a, const Surface_mesh& b) {
  if (a.number_of_vertices() != b.number_of_vertices()) return false;
  auto triples = [](const Surface_mesh& m) {
    std::set<std::vector<std::size_t>> t;
    for (auto f : m.faces()) {
      std::vector<std::size_t> v;
      for (auto x : CGAL::vertices_around_face(m.halfedge(f), m)) v.push_back(x);
      std::sort(v.begin(), v.end());
      t.insert(v);
    }
    return t;
  };
  return triples(a) == triples(b);
}

void expect_valid_features(const Feature_correspondence& fc, std::size_t count, const Surface_mesh& a,
                           const Surface_mesh& b) {
  ASSERT_EQ(fc.size(), count);
  std::set<std::size_t> s, t;
  for (const auto& p : fc) {
    EXPECT_LT(p.source, a.number_of_vertices());
    EXPECT_LT(p.target, b.number_of_vertices());
    s.insert(p.source);
    t.insert(p.target);
  }
  EXPECT_EQ(s.size(), count);
  EXPECT_EQ(t.size(), count);
  if (count >= 4) {  // the library's check wants at least 4 features
    EXPECT_NO_THROW(crossparam::validate_feature_pairs(fc, a.number_of_vertices(), b.number_of_vertices(), "features"));
  }
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The creatures are expensive-ish (about a second each): build them once.
class Creatures : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    auto t0 = std::chrono::steady_clock::now();
    a_ = new Surface_mesh(shapes::creature_a());
    const double ta = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    b_ = new Surface_mesh(shapes::creature_b());
    const double tb = seconds_since(t0);
    std::cout << "creature_a: " << a_->number_of_vertices() << " vertices, " << ta << " s; creature_b: "
              << b_->number_of_vertices() << " vertices, " << tb << " s\n";
  }
  static void TearDownTestSuite() {
    delete a_;
    delete b_;
    a_ = b_ = nullptr;
  }
  static Surface_mesh* a_;
  static Surface_mesh* b_;
};
Surface_mesh* Creatures::a_ = nullptr;
Surface_mesh* Creatures::b_ = nullptr;

TEST_F(Creatures, AreClosedGenusZeroOutwardSurfaces) {
  expect_closed_surface(*a_, 0, 15.0);
  expect_closed_surface(*b_, 0, 15.0);
  std::cout << "min angles: a " << min_angle_deg(*a_) << ", b " << min_angle_deg(*b_) << " degrees\n";
}

TEST_F(Creatures, VertexCountsInRangeAndDifferent) {
  EXPECT_GE(a_->number_of_vertices(), 3000u);
  EXPECT_LE(a_->number_of_vertices(), 6000u);
  EXPECT_GE(b_->number_of_vertices(), 3000u);
  EXPECT_LE(b_->number_of_vertices(), 6000u);
  EXPECT_NE(a_->number_of_vertices(), b_->number_of_vertices());
  EXPECT_FALSE(same_connectivity(*a_, *b_));
}

TEST_F(Creatures, AreDeterministic) {
  // Built after other meshes: the result must not depend on memory addresses or CGAL's default random.
  EXPECT_TRUE(identical(*a_, shapes::creature_a()));
  EXPECT_TRUE(identical(*b_, shapes::creature_b()));
  EXPECT_TRUE(identical(*a_, shapes::make_creature(shapes::creature_a_params())));
}

TEST_F(Creatures, HaveExpectedSize) {
  // Body length 2 plus head and tail: the bounding box is about 3 units long; the feet are the lowest points.
  const auto box_a = CGAL::bbox_3(a_->points().begin(), a_->points().end());
  const auto box_b = CGAL::bbox_3(b_->points().begin(), b_->points().end());
  EXPECT_GT(box_a.xmax() - box_a.xmin(), 2.5);
  EXPECT_LT(box_a.xmax() - box_a.xmin(), 3.5);
  EXPECT_GT(box_b.xmax() - box_b.xmin(), 2.5);
  EXPECT_LT(box_b.xmax() - box_b.xmin(), 4.0);
  // creature_b: fatter body, shorter legs, higher head.
  EXPECT_GT(box_b.ymax() - box_b.ymin(), box_a.ymax() - box_a.ymin());
  EXPECT_GT(box_b.zmin(), box_a.zmin());
  EXPECT_GT(box_b.zmax(), box_a.zmax());
}

TEST_F(Creatures, LegsAreSeparate) {
  // A horizontal cut through the middle of the legs meets four separate leg cross-sections: the vertices in a
  // thin slab around it fall into four clusters, one per leg (checked by their x and y signs).
  for (const auto* m : {a_, b_}) {
    const auto params = (m == a_) ? shapes::creature_a_params() : shapes::creature_b_params();
    const auto anchors = shapes::creature_anchors(params);
    const double z_feet = anchors[2].z();
    const double z_cut = z_feet + 0.25 * params.leg_length;
    int quadrant_count[4] = {0, 0, 0, 0};
    std::size_t near_mid_plane = 0;
    for (auto v : m->vertices()) {
      const Point_3& p = m->point(v);
      if (std::abs(p.z() - z_cut) > 0.02) continue;
      quadrant_count[(p.x() > 0 ? 0 : 2) + (p.y() > 0 ? 0 : 1)]++;
      if (std::abs(p.y()) < 0.05 || std::abs(p.x()) < 0.2) ++near_mid_plane;
    }
    for (int q = 0; q < 4; ++q) EXPECT_GT(quadrant_count[q], 5) << "quadrant " << q;
    EXPECT_EQ(near_mid_plane, 0u);
  }
}

TEST_F(Creatures, FeaturesAreSemantic) {
  const Feature_correspondence fc = shapes::creature_features(*a_, *b_);
  expect_valid_features(fc, shapes::creature_feature_names().size(), *a_, *b_);
  ASSERT_GE(fc.size(), 8u);
  ASSERT_LE(fc.size(), 12u);
  const auto anchors_a = shapes::creature_anchors(shapes::creature_a_params());
  const auto anchors_b = shapes::creature_anchors(shapes::creature_b_params());
  for (std::size_t k = 0; k < fc.size(); ++k) {
    const double da = std::sqrt(CGAL::squared_distance(a_->point(VI(fc[k].source)), anchors_a[k]));
    const double db = std::sqrt(CGAL::squared_distance(b_->point(VI(fc[k].target)), anchors_b[k]));
    // The anchors lie on the implicit surface; the mesh vertices are at most about one edge length away.
    EXPECT_LT(da, 0.04) << shapes::creature_feature_names()[k];
    EXPECT_LT(db, 0.04) << shapes::creature_feature_names()[k];
  }
  // Nose tip: (nearly) the frontmost vertex. Feet: (nearly) the lowest, on the correct side and end.
  for (const auto* m : {a_, b_}) {
    const bool is_a = (m == a_);
    const auto box = CGAL::bbox_3(m->points().begin(), m->points().end());
    auto pt = [&](std::size_t k) { return m->point(VI(is_a ? fc[k].source : fc[k].target)); };
    EXPECT_GT(pt(0).x(), box.xmax() - 0.05);
    for (std::size_t k = 2; k < 6; ++k) {
      EXPECT_LT(pt(k).z(), box.zmin() + 0.05);
      EXPECT_EQ(pt(k).y() > 0, k % 2 == 0);  // left feet first
      EXPECT_EQ(pt(k).x() > 0, k < 4);       // front feet first
    }
    EXPECT_GT(pt(1).z(), pt(0).z());  // top of head above the nose
    EXPECT_LT(pt(6).x(), -1.0);        // tail tip behind the body
    EXPECT_GT(pt(7).z(), 0.3);         // back
    EXPECT_LT(pt(8).z(), -0.3);        // belly
  }
  // Deterministic.
  EXPECT_EQ(fc, shapes::creature_features(*a_, *b_));
}

TEST(DeformedSphere, RegularIsClosedGenusZeroAndDeterministic) {
  for (unsigned seed : {1u, 2u, 77u}) {
    const Surface_mesh m = shapes::make_deformed_sphere(seed, 2000, false);
    expect_closed_surface(m, 0, 10.0);
    EXPECT_EQ(m.number_of_vertices(), 1962u);  // 10 n^2 + 2 with n = 14
    EXPECT_TRUE(identical(m, shapes::make_deformed_sphere(seed, 2000, false)));
  }
  // Same connectivity, different geometry for different seeds.
  const Surface_mesh m1 = shapes::make_deformed_sphere(1, 2000, false);
  const Surface_mesh m2 = shapes::make_deformed_sphere(2, 2000, false);
  EXPECT_TRUE(same_connectivity(m1, m2));
  EXPECT_FALSE(identical(m1, m2));
}

TEST(DeformedSphere, IrregularHasDifferentConnectivityPerSeed) {
  std::set<std::size_t> counts;
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    const Surface_mesh m = shapes::make_deformed_sphere(seed, 2000, true);
    expect_closed_surface(m, 0, 1.0);
    EXPECT_GE(m.number_of_vertices(), 1300u);
    EXPECT_LE(m.number_of_vertices(), 1962u);
    EXPECT_TRUE(identical(m, shapes::make_deformed_sphere(seed, 2000, true)));
    counts.insert(m.number_of_vertices());
  }
  EXPECT_EQ(counts.size(), 4u);
  const Surface_mesh regular = shapes::make_deformed_sphere(5, 2000, false);
  const Surface_mesh irregular = shapes::make_deformed_sphere(5, 2000, true);
  EXPECT_FALSE(same_connectivity(regular, irregular));
}

TEST(DeformedSphere, SizeRange) {
  for (std::size_t target : {std::size_t(12), std::size_t(100), std::size_t(500), std::size_t(20000)}) {
    for (bool irregular : {false, true}) {
      const auto t0 = std::chrono::steady_clock::now();
      const Surface_mesh m = shapes::make_deformed_sphere(42, target, irregular);
      const double t = seconds_since(t0);
      SCOPED_TRACE(::testing::Message() << "target " << target << " irregular " << irregular);
      expect_closed_surface(m, 0, irregular ? 0.5 : 5.0);
      EXPECT_GE(static_cast<double>(m.number_of_vertices()), 0.6 * static_cast<double>(target));
      EXPECT_LE(static_cast<double>(m.number_of_vertices()), 1.25 * static_cast<double>(target) + 10);
      if (target == 20000) std::cout << "deformed sphere 20000 irregular=" << irregular << ": "
                                     << m.number_of_vertices() << " vertices, " << t << " s\n";
    }
  }
}

TEST(RandomFeatures, CorrespondingAndDistinct) {
  const Surface_mesh a = shapes::make_deformed_sphere(1, 1000, false);
  const Surface_mesh b = shapes::make_deformed_sphere(2, 3000, true);
  for (std::size_t count : {std::size_t(1), std::size_t(4), std::size_t(10), std::size_t(40)}) {
    const Feature_correspondence fc = shapes::random_features(a, b, count, 7, false);
    expect_valid_features(fc, count, a, b);
    EXPECT_EQ(fc, shapes::random_features(a, b, count, 7, false));
    EXPECT_NE(fc, shapes::random_features(a, b, count, 8, false));
  }
  // All vertices of a small mesh.
  const Surface_mesh tiny = shapes::make_deformed_sphere(3, 12, false);
  ASSERT_EQ(tiny.number_of_vertices(), 12u);
  expect_valid_features(shapes::random_features(tiny, tiny, 12, 1, false), 12, tiny, tiny);
  EXPECT_THROW(shapes::random_features(tiny, a, 13, 1, false), crossparam::Feature_error);
}

TEST(RandomFeatures, UnpermutedFeaturesPointTheSameWay) {
  // Undeformed directions: both meshes are star-shaped around their centroid, so feature k lies in roughly the
  // same direction on both.
  const Surface_mesh a = shapes::make_deformed_sphere(10, 2000, false);
  const Surface_mesh b = shapes::make_deformed_sphere(10, 2500, true);
  const Feature_correspondence fc = shapes::random_features(a, b, 12, 3, false);
  auto centroid = [](const Surface_mesh& m) {
    double x = 0, y = 0, z = 0;
    for (auto v : m.vertices()) {
      x += m.point(v).x();
      y += m.point(v).y();
      z += m.point(v).z();
    }
    const double n = static_cast<double>(m.number_of_vertices());
    return Point_3(x / n, y / n, z / n);
  };
  const Point_3 ca = centroid(a), cb = centroid(b);
  for (const auto& p : fc) {
    auto da = a.point(VI(p.source)) - ca;
    auto db = b.point(VI(p.target)) - cb;
    const double c = (da * db) / std::sqrt(da.squared_length() * db.squared_length());
    EXPECT_GT(c, 0.95);
  }
}

TEST(RandomFeatures, PermutedIsANonIdentityPermutation) {
  const Surface_mesh a = shapes::make_deformed_sphere(4, 800, true);
  const Surface_mesh b = shapes::make_deformed_sphere(5, 1200, true);
  for (std::size_t count : {std::size_t(2), std::size_t(3), std::size_t(8), std::size_t(20)}) {
    const Feature_correspondence plain = shapes::random_features(a, b, count, 11, false);
    const Feature_correspondence twisted = shapes::random_features(a, b, count, 11, true);
    expect_valid_features(twisted, count, a, b);
    std::vector<std::size_t> ta, tb;
    std::size_t moved = 0;
    for (std::size_t k = 0; k < count; ++k) {
      EXPECT_EQ(plain[k].source, twisted[k].source);
      ta.push_back(plain[k].target);
      tb.push_back(twisted[k].target);
      if (plain[k].target != twisted[k].target) ++moved;
    }
    std::sort(ta.begin(), ta.end());
    std::sort(tb.begin(), tb.end());
    EXPECT_EQ(ta, tb);
    EXPECT_GE(moved, 2u);
    EXPECT_EQ(twisted, shapes::random_features(a, b, count, 11, true));
  }
}

TEST(Torus, IsClosedGenusOne) {
  const Surface_mesh t = shapes::make_torus();
  expect_closed_surface(t, 1, 10.0);
  EXPECT_EQ(t.number_of_vertices(), 48u * 24u);
  EXPECT_NEAR(PMP::volume(t), 2.0 * 3.14159265358979323846 * 3.14159265358979323846 * 0.35 * 0.35, 0.05);
  EXPECT_TRUE(identical(t, shapes::make_torus()));
  const Surface_mesh small = shapes::make_torus(2.0, 0.5, 12, 6);
  expect_closed_surface(small, 1, 5.0);
  EXPECT_EQ(small.number_of_vertices(), 72u);
  EXPECT_THROW(shapes::make_torus(1.0, 1.5), crossparam::Input_error);
}

} // namespace

// SPDX-License-Identifier: GPL-3.0-or-later
// Robustness: the same figures for a pair at any scale (power-of-two normalisation, scaling.h), the verifier
// at any scale, small and degenerate but valid inputs through the whole pipeline, a mesh against itself, the
// time budget (time_limit, best_effort, Time_limit_error) and a feature file with a byte order mark.
#include <crossparam/compatible_remeshing.h>
#include <crossparam/io.h>
#include <crossparam/morph.h>
#include <crossparam/remeshing_verification.h>
#include <crossparam/scaling.h>
#include <support/shapes.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

using namespace crossparam;
using Map = Cross_parameterization<Surface_mesh, Surface_mesh>;
using Remesher = Compatible_remesher<Surface_mesh, Surface_mesh>;

namespace {

/// The figures of one run of the whole pipeline.
struct Figures {
  std::size_t output_vertices = 0, flipped = 0;
  double max_error = 0, l2_error = 0, hausdorff = 0, hausdorff_source = 0, angular = 0;
  bool valid = false, certified = false;
};

/// The points a run gives back: both outputs, and the map's image on the target of every source vertex.
struct Outputs {
  std::vector<std::array<double, 3>> source_points, target_points, images;
};

/// Map, remeshing and verification of (s, t) as given (no rescaling); the points it gives back in `out`.
Figures run_pipeline(Surface_mesh s, Surface_mesh t, const Feature_correspondence& f, double tolerance = 0.5,
                     Outputs* out = nullptr) {
  const Surface_mesh s0 = s, t0 = t;
  Map cp(s, t, f);
  const Remesher r(cp, crossparam::parameters::tolerance(tolerance));
  if (out) {
    out->source_points = r.source_points();
    out->target_points = r.target_points();
    out->images.clear();
    for (std::size_t v = 0; v < cp.input_vertices(Mesh_side::source); ++v)
      out->images.push_back(cp.input_point(Mesh_side::target, cp.source_vertex_to_target_input(v)));
  }
  Surface_mesh os, ot;
  r.copy_to(Mesh_side::source, os);
  r.copy_to(Mesh_side::target, ot);
  const Remeshing_verification check = verify_compatible_remeshing(s0, t0, os, ot, tolerance);
  Figures g;
  g.output_vertices = r.statistics().output_vertices;
  g.flipped = check.flipped_faces;
  g.max_error = r.statistics().max_error;
  g.l2_error = r.statistics().l2_error;
  g.hausdorff = check.hausdorff_target;
  g.hausdorff_source = check.hausdorff_source;
  g.angular = cp.statistics().distortion.angular;
  g.valid = check.valid;
  g.certified = r.certificate().valid && cp.certificate(Mesh_side::source).valid && cp.certificate(Mesh_side::target).valid;
  std::cout << "[ pipeline ] " << g.output_vertices << " vertices, max e " << g.max_error << "%, L2 " << g.l2_error
            << "%, Hausdorff " << g.hausdorff << "%, source " << g.hausdorff_source << "%, flipped " << g.flipped
            << ", E_ang " << g.angular << (g.valid ? ", valid" : ", NOT valid: " + check.message) << "\n";
  return g;
}

/// `m` with every coordinate multiplied by `factor` (rounded, as a user's scaled file would be).
Surface_mesh scaled(Surface_mesh m, double factor) {
  for (auto v : m.vertices()) {
    const Point_3 p = m.point(v);
    m.point(v) = Point_3(p.x() * factor, p.y() * factor, p.z() * factor);
  }
  return m;
}

/// As the CLI: the pair brought to a unit diagonal by a power of two (exact), then the pipeline.
Figures run_normalised(Surface_mesh s, Surface_mesh t, const Feature_correspondence& f) {
  const int k = unit_scale_exponent<Surface_mesh>({&s, &t});
  scale_by_power_of_two(s, k);
  scale_by_power_of_two(t, k);
  return run_pipeline(s, t, f);
}

/// Two figures equal up to the rounding of the inputs (relative, with a floor for figures near zero).
void expect_same(double a, double b, const char* what) {
  EXPECT_NEAR(a, b, 1e-6 * std::max({1.0, std::abs(a), std::abs(b)})) << what;
}

/// The figures of a run on the scaled pair are those of the reference run: the same counts and verdicts, the
/// same errors, distances and distortion up to rounding.
void expect_same_figures(const Figures& g, const Figures& ref) {
  EXPECT_EQ(g.valid, ref.valid);
  EXPECT_TRUE(g.certified);
  EXPECT_EQ(g.output_vertices, ref.output_vertices);
  EXPECT_EQ(g.flipped, ref.flipped);
  expect_same(g.max_error, ref.max_error, "max error");
  expect_same(g.l2_error, ref.l2_error, "L2 error");
  expect_same(g.hausdorff, ref.hausdorff, "Hausdorff distance");
  expect_same(g.hausdorff_source, ref.hausdorff_source, "Hausdorff distance to the source");
  expect_same(g.angular, ref.angular, "angular distortion");
}

Surface_mesh octahedron() {
  return shapes::internal_shapes::soup_to_mesh({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
                              {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}}, "test mesh");
}

Surface_mesh tetrahedron() {
  return shapes::internal_shapes::soup_to_mesh({{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}}, {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}}, "test mesh");
}

Feature_correspondence identity_features(std::size_t n) {
  Feature_correspondence f;
  for (std::size_t i = 0; i < n; ++i) f.push_back({i, i});
  return f;
}

} // namespace

// The pair at 1e-150 ... 1e90 gives the figures of the pair at its own scale, up to rounding.
TEST(Scale, SameFiguresAtEveryScale) {
  const Surface_mesh a = shapes::make_deformed_sphere(31, 500, true), b = shapes::make_deformed_sphere(32, 450, true);
  const Feature_correspondence f = shapes::random_features(a, b, 6, 33, false);
  const Figures ref = run_normalised(a, b, f);
  EXPECT_TRUE(ref.certified);
  for (double factor : {1e-150, 1e-100, 1e-40, 1e40, 1e90}) {
    SCOPED_TRACE("factor " + std::to_string(factor));
    expect_same_figures(run_normalised(scaled(a, factor), scaled(b, factor), f), ref);
  }
}

// The library called directly, the caller rescaling nothing: Cross_parameterization and Compatible_remesher work
// on copies with a unit bounding-box diagonal and give their outputs back in the caller's units, so the pair at
// 1e-150 ... 1e90 gives the figures of the pair at its own scale, and the outputs scale with the inputs.
TEST(Scale, LibraryWithoutRescalingByTheCaller) {
  const Surface_mesh a = shapes::make_deformed_sphere(31, 500, true), b = shapes::make_deformed_sphere(32, 450, true);
  const Feature_correspondence f = shapes::random_features(a, b, 6, 33, false);
  Outputs ref_out;
  const Figures ref = run_pipeline(a, b, f, 0.5, &ref_out);
  EXPECT_TRUE(ref.certified);
  // Valid by the independent verifier: on this pair e(v) met the tolerance while the two-sided
  // Hausdorff distance did not (0.570 %) until the remesher sampled the surface distance itself.
  EXPECT_TRUE(ref.valid);
  EXPECT_LE(ref.hausdorff, 0.5);
  const CGAL::Bbox_3 box = CGAL::Polygon_mesh_processing::bbox(b);
  const double diag = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                CGAL::square(box.zmax() - box.zmin()));
  for (double factor : {1e-150, 1e-100, 1e-40, 1e40, 1e90}) {
    SCOPED_TRACE("factor " + std::to_string(factor));
    Outputs out;
    expect_same_figures(run_pipeline(scaled(a, factor), scaled(b, factor), f, 0.5, &out), ref);

    // The outputs are in the caller's units: every point of both outputs is the reference's times the factor, up
    // to rounding, and finite; so are the map's images of the source vertices and a morph frame.
    ASSERT_EQ(out.target_points.size(), ref_out.target_points.size());
    double worst = 0;
    for (const auto& [pts, ref_pts] : {std::make_pair(&out.target_points, &ref_out.target_points),
                                       std::make_pair(&out.source_points, &ref_out.source_points)})
      for (std::size_t i = 0; i < pts->size(); ++i)
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(std::isfinite((*pts)[i][c]));
          worst = std::max(worst, std::abs((*pts)[i][c] / factor - (*ref_pts)[i][c]));
        }
    EXPECT_LT(worst, 1e-9 * diag) << "outputs not in the caller's units";
    for (const auto& p : out.images) ASSERT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]));
    for (const auto& p : morph(out.source_points, out.target_points, 0.5))
      ASSERT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]));
  }
}

// The verifier alone reports the same percentages for the same meshes at any scale.
TEST(Scale, VerifierIsScaleFree) {
  Surface_mesh a = shapes::make_deformed_sphere(41, 400, true), b = shapes::make_deformed_sphere(42, 380, true);
  const Feature_correspondence f = shapes::random_features(a, b, 6, 43, false);
  const Surface_mesh a0 = a, b0 = b;
  Map cp(a, b, f);
  const Remesher r(cp);
  Surface_mesh os, ot;
  r.copy_to(Mesh_side::source, os);
  r.copy_to(Mesh_side::target, ot);
  const Remeshing_verification ref = verify_compatible_remeshing(a0, b0, os, ot, 0.5);
  for (double factor : {1e-150, 1e-100, 1e90}) {
    SCOPED_TRACE("factor " + std::to_string(factor));
    const Remeshing_verification v =
        verify_compatible_remeshing(scaled(a0, factor), scaled(b0, factor), scaled(os, factor), scaled(ot, factor), 0.5);
    EXPECT_EQ(v.valid, ref.valid);
    EXPECT_EQ(v.flipped_faces, ref.flipped_faces);
    EXPECT_TRUE(std::isfinite(v.hausdorff_target));
    expect_same(v.hausdorff_target, ref.hausdorff_target, "Hausdorff distance");
  }
}

// The smallest closed meshes with 4 features, through the map, the remeshing and the verification.
TEST(Small, TetrahedronAndOctahedronWithFourFeatures) {
  const Figures t = run_pipeline(tetrahedron(), tetrahedron(), identity_features(4));
  EXPECT_TRUE(t.valid);
  EXPECT_TRUE(t.certified);
  const Feature_correspondence f{{0, 0}, {1, 1}, {2, 2}, {4, 4}};
  const Figures o = run_pipeline(octahedron(), octahedron(), f);
  EXPECT_TRUE(o.valid);
  EXPECT_TRUE(o.certified);
}

// A mesh against an identical copy of itself, and against itself with features that rotate it.
TEST(Small, SelfAgainstSelf) {
  const Surface_mesh a = shapes::make_deformed_sphere(51, 400, true);
  const Feature_correspondence f = shapes::random_features(a, a, 6, 52, false);
  const Figures g = run_pipeline(a, a, f);
  EXPECT_TRUE(g.valid);
  // The bounded-error Hausdorff distance is an upper bound within 1 % of the tolerance (0.005 % here).
  EXPECT_LE(g.hausdorff, 0.01 * 0.5 + 1e-12);
  // The octahedron onto itself turned a quarter around the z axis: 0 -> 2 -> 1 -> 3 -> 0, the poles fixed.
  const Feature_correspondence rot{{0, 2}, {2, 1}, {1, 3}, {4, 4}};
  const Figures r = run_pipeline(octahedron(), octahedron(), rot);
  EXPECT_TRUE(r.valid);
  EXPECT_TRUE(r.certified);
}

// Zero-length edges and zero-area faces are valid inputs.
TEST(Small, ZeroLengthEdgeAndZeroAreaFace) {
  // The octahedron with vertex 0 doubled: vertex 6 at the same point, on the zero-length edge 0-6.
  const Surface_mesh zero_edge = shapes::internal_shapes::soup_to_mesh(
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 0, 0}},
      {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 6, 4}, {6, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {6, 3, 5}, {0, 6, 5}}, "test mesh");
  const Feature_correspondence f{{0, 0}, {1, 1}, {2, 2}, {4, 4}};
  const Figures e = run_pipeline(zero_edge, octahedron(), f);
  EXPECT_TRUE(e.valid);
  EXPECT_TRUE(e.certified);
  // The octahedron with vertex 6 at the midpoint of edge 0-2 on the upper side only: the zero-area face
  // (6, 0, 2) closes the gap between the split upper faces and the unsplit lower face (2, 0, 5).
  const Surface_mesh zero_area = shapes::internal_shapes::soup_to_mesh(
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0.5, 0.5, 0}},
      {{0, 6, 4}, {6, 2, 4}, {6, 0, 2}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}}, "test mesh");
  const Figures a = run_pipeline(zero_area, octahedron(), f);
  EXPECT_TRUE(a.valid);
  EXPECT_TRUE(a.certified);
}

// The time budget: Time_limit_error names the stage; with best effort, a certified result.
TEST(TimeLimit, StopsWithTheStageOrReturnsTheBestResult) {
  Surface_mesh a = shapes::make_deformed_sphere(61, 600, true), b = shapes::make_deformed_sphere(62, 500, true);
  const Feature_correspondence f = shapes::random_features(a, b, 6, 63, false);
  {
    Surface_mesh s = a, t = b;
    try {
      Map cp(s, t, f, crossparam::parameters::time_limit(0.0));
      ADD_FAILURE() << "no Time_limit_error";
    } catch (const Time_limit_error& e) {
      EXPECT_NE(std::string(e.what()).find("time limit of 0 s reached during"), std::string::npos) << e.what();
      EXPECT_FALSE(e.stage().empty());
    }
  }
  Surface_mesh s = a, t = b;
  Map cp(s, t, f);
  try {
    Remesher r(cp, crossparam::parameters::time_limit(0.0));
    ADD_FAILURE() << "no Time_limit_error";
  } catch (const Time_limit_error& e) {
    EXPECT_NE(e.stage().find("remeshing"), std::string::npos) << e.what();
  }
  const Remesher r(cp, crossparam::parameters::time_limit(0.0, crossparam::parameters::best_effort(true)));
  EXPECT_TRUE(r.certificate().valid);
  EXPECT_EQ(r.statistics().refinement_rounds, 0u);
  // A map with best effort at a zero budget still refuses: its layout cannot be cut short.
  Surface_mesh s2 = a, t2 = b;
  EXPECT_THROW(Map(s2, t2, f, crossparam::parameters::time_limit(0.0, crossparam::parameters::best_effort(true))),
               Time_limit_error);
  EXPECT_THROW(Map(s2, t2, f, crossparam::parameters::time_limit(-1.0)), Input_error);
}

// A feature file that starts with a UTF-8 byte order mark.
TEST(Features, ByteOrderMark) {
  const std::string path = testing::TempDir() + "crossparam_bom_features.txt";
  {
    std::ofstream os(path, std::ios::binary);
    os << "\xEF\xBB\xBF# source target\n0 0\n1 1\n2 2\n3 3\n";
  }
  const Feature_correspondence f = read_feature_pairs(path, 10, 10);
  EXPECT_EQ(f.size(), 4u);
  std::remove(path.c_str());
}

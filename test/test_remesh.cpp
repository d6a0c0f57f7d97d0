// SPDX-License-Identifier: GPL-3.0-or-later
// Compatible remeshing (paper §5) and morphing: every result is checked by the independent verifier
// (remeshing_verification.h: one face list, CGAL's two-sided Hausdorff distance to the target, the source side
// on the source, no face flipped against the target), plus the certificate of the remeshed parameterization.
#include <crossparam/compatible_remeshing.h>
#include <crossparam/internal/remeshing/disk_embedding.h>
#include <crossparam/io.h>
#include <crossparam/morph.h>
#include <crossparam/remeshing_verification.h>
#include <support/shapes.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>

#include <gtest/gtest.h>

#include "bench_cases.h"
#include "wide_cases.h"

#include <algorithm>
#include <iostream>
#include <map>
#include <random>
#include <set>

using namespace crossparam;
using Map = Cross_parameterization<Surface_mesh, Surface_mesh>;
using Remesher = Compatible_remesher<Surface_mesh, Surface_mesh>;

namespace {

struct Outcome {
  Remeshing_statistics stats;
  Remeshing_verification check;
  bool certificate = false;
  bool source_prefix_exact = false;
  std::size_t standard_flips = 0; ///< target-shaped faces flipped by the standard rule, counted here
  std::size_t flat_on_source = 0; ///< faces with no area on the source or reversed there, counted here
};

// Faces of `out` flipped against `target` by the standard rule: the face's normal more than 90° from the
// target's at the point of the target nearest the face's centroid (counted independently of the remesher).
std::size_t standard_flips(const Surface_mesh& target, const Surface_mesh& out) {
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_face_graph_triangle_primitive<Surface_mesh>>>;
  Tree tree(faces(target).first, faces(target).second, target);
  std::size_t n = 0;
  auto normal = [](const Surface_mesh& m, Surface_mesh::Face_index f) {
    const auto h = m.halfedge(f);
    return internal::triangle_normal(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))));
  };
  for (auto f : out.faces()) {
    const auto h = out.halfedge(f);
    const Point_3 c = CGAL::centroid(out.point(out.source(h)), out.point(out.target(h)), out.point(out.target(out.next(h))));
    n += normal(out, f) * normal(target, tree.closest_point_and_primitive(c).second) < 0;
  }
  return n;
}

// The figures of a remeshing `r` of the inputs s0, t0 (as they were before the map refined them), verified.
Outcome outcome_of(const Remesher& r, const Surface_mesh& s0, const Surface_mesh& t0, double tolerance) {
  Outcome o;
  o.stats = r.statistics();
  o.certificate = r.certificate().valid;
  Surface_mesh os, ot;
  r.copy_to(Mesh_side::source, os);
  r.copy_to(Mesh_side::target, ot);
  o.check = verify_compatible_remeshing(s0, t0, os, ot, tolerance);
  o.standard_flips = standard_flips(t0, ot);
  o.flat_on_source = source_tiling_defects(r.source_face_locations());
  // The first points of the source-shaped output are the source's vertices, bit for bit.
  o.source_prefix_exact = r.source_points().size() >= s0.number_of_vertices();
  std::size_t i = 0;
  for (auto v : s0.vertices()) {
    const Point_3& p = s0.point(v);
    const auto& q = r.source_points()[i++];
    o.source_prefix_exact = o.source_prefix_exact && p.x() == q[0] && p.y() == q[1] && p.z() == q[2];
  }
  std::cout << "[ remesh ] " << o.stats.source_vertices << "/" << o.stats.target_vertices << " -> "
            << o.stats.output_vertices << " vertices, L2 " << o.stats.l2_error << "%, max e " << o.stats.max_error
            << "%, Hausdorff " << o.check.hausdorff_target << "% (" << o.check.hausdorff_to_target << " to, "
            << o.check.hausdorff_from_target << " from), flipped " << o.check.flipped_faces << ", flat on the source "
            << o.flat_on_source << ", "
            << o.stats.seconds_total << " s\n";
  return o;
}

Outcome remesh_and_verify(Surface_mesh s, Surface_mesh t, const Feature_correspondence& f, double tolerance,
                          Remeshing_construction construction = Remeshing_construction::automatic) {
  const Surface_mesh s0 = s, t0 = t;
  Map cp(s, t, f);
  namespace p = crossparam::parameters;
  return outcome_of(Remesher(cp, p::tolerance(tolerance, p::remeshing_construction(construction))), s0, t0, tolerance);
}

} // namespace

// The built-in example: everything the issue asks for holds.
TEST(Remesh, Creatures) {
  Surface_mesh a = shapes::creature_a(), b = shapes::creature_b();
  Feature_correspondence f = shapes::creature_features(a, b);
  Outcome o = remesh_and_verify(a, b, f, 0.5);
  EXPECT_TRUE(o.certificate);
  EXPECT_TRUE(o.check.compatible);
  EXPECT_TRUE(o.source_prefix_exact);
  EXPECT_LE(o.check.hausdorff_target, 0.5) << o.check.message;
  EXPECT_LE(o.check.hausdorff_source, 1e-6) << o.check.message;
  EXPECT_EQ(o.check.flipped_faces, 0u) << o.check.message;
  EXPECT_TRUE(o.check.valid) << o.check.message;
  // Few added vertices (the layout adds 6 % here once the splits the map no longer needs are undone), small
  // error.
  EXPECT_GT(o.stats.layout_splits_undone, 0u);
  EXPECT_LT(double(o.stats.output_vertices), 1.15 * double(o.stats.source_vertices));
  EXPECT_LT(o.stats.l2_error, 0.13);
  EXPECT_LT(o.stats.l2_error, o.stats.l2_error_initial);
}

// A tighter tolerance costs vertices and buys accuracy.
TEST(Remesh, ToleranceIsHonoured) {
  Surface_mesh a = shapes::make_deformed_sphere(3, 1500, false), b = shapes::make_deformed_sphere(11, 1200, true);
  Feature_correspondence f = shapes::random_features(a, b, 8, 5, false);
  Outcome loose = remesh_and_verify(a, b, f, 1.0);
  Outcome tight = remesh_and_verify(a, b, f, 0.25);
  for (const Outcome* o : {&loose, &tight}) {
    EXPECT_TRUE(o->certificate);
    EXPECT_TRUE(o->check.compatible);
    EXPECT_TRUE(o->source_prefix_exact);
    EXPECT_LE(o->check.hausdorff_source, 1e-6);
    EXPECT_EQ(o->check.flipped_faces, 0u);
  }
  EXPECT_LE(loose.check.hausdorff_target, 1.0) << loose.check.message;
  EXPECT_LE(tight.check.hausdorff_target, 0.25) << tight.check.message;
  EXPECT_GE(tight.stats.output_vertices, loose.stats.output_vertices);
}

// Undoing the layout splits the smoothed map no longer needs saves vertices and keeps every guarantee.
TEST(Remesh, UndoesLayoutSplits) {
  Surface_mesh a = shapes::make_deformed_sphere(3, 1500, false), b = shapes::make_deformed_sphere(11, 1200, true);
  Feature_correspondence f = shapes::random_features(a, b, 8, 5, false);
  const Surface_mesh a0 = a, b0 = b;
  Map cp(a, b, f);
  Outcome with_undo, without;
  for (bool undo : {true, false}) {
    Outcome& o = undo ? with_undo : without;
    o = outcome_of(Remesher(cp, crossparam::parameters::undo_layout_splits(undo, crossparam::parameters::tolerance(0.5))),
                   a0, b0, 0.5);
    EXPECT_TRUE(o.certificate);
    EXPECT_TRUE(o.check.valid) << o.check.message;
  }
  EXPECT_GT(with_undo.stats.layout_splits_undone, 0u);
  EXPECT_EQ(without.stats.layout_splits_undone, 0u);
  EXPECT_EQ(with_undo.stats.layout_vertices + with_undo.stats.layout_splits_undone, without.stats.layout_vertices);
  EXPECT_LT(with_undo.stats.output_vertices, without.stats.output_vertices);
}

// The result is a function of the inputs alone: the same remeshing repeated in one process, after another
// one has reused the heap, gives the same faces and points bit for bit (a read of stale memory once made it not).
TEST(Remesh, RepeatsExactly) {
  Surface_mesh a = shapes::make_deformed_sphere(3, 1500, false), b = shapes::make_deformed_sphere(11, 1200, true);
  Feature_correspondence f = shapes::random_features(a, b, 8, 5, false);
  Map cp(a, b, f);
  const Remesher first(cp, crossparam::parameters::tolerance(0.5));
  { const Remesher other(cp, crossparam::parameters::tolerance(0.25)); }
  const Remesher again(cp, crossparam::parameters::tolerance(0.5));
  EXPECT_GT(first.statistics().refinement_splits, 0u);
  EXPECT_EQ(first.faces(), again.faces());
  EXPECT_EQ(first.source_points(), again.source_points());
  EXPECT_EQ(first.target_points(), again.target_points());
}

TEST(Remesh, SameResultOnAnyNumberOfThreads) {
  // Large enough that measure() runs its edge and face loops on several threads (at least 2048 elements each).
  Surface_mesh a = shapes::make_deformed_sphere(5, 3000, false), b = shapes::make_deformed_sphere(6, 2500, true);
  Feature_correspondence f = shapes::random_features(a, b, 8, 7, false);
  Map cp(a, b, f);
  const Remesher one(cp, crossparam::parameters::number_of_threads(1u));
  const Remesher four(cp, crossparam::parameters::number_of_threads(4u));
  EXPECT_GT(one.statistics().output_faces, 2u * 2048u);
  EXPECT_EQ(one.faces(), four.faces());
  EXPECT_EQ(one.source_points(), four.source_points());
  EXPECT_EQ(one.target_points(), four.target_points());
  EXPECT_EQ(one.statistics().l2_error, four.statistics().l2_error);
}

TEST(Remesh, RejectsBadTolerance) {
  Surface_mesh a = shapes::make_deformed_sphere(1, 300, false), b = shapes::make_deformed_sphere(2, 300, false);
  Feature_correspondence f = shapes::random_features(a, b, 4, 1, false);
  Map cp(a, b, f);
  EXPECT_THROW(Remesher(cp, crossparam::parameters::tolerance(0.0)), Input_error);
  EXPECT_THROW(Remesher(cp, crossparam::parameters::tolerance(-1.0)), Input_error);
}

TEST(Morph, CompatibilityAndInterpolation) {
  Polygon_soup a, b;
  a.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  a.polygons = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  b = a;
  for (auto& p : b.points) p[0] += 2;
  EXPECT_NO_THROW(check_compatible(a, b));
  auto mid = morph(a.points, b.points, 0.5);
  EXPECT_DOUBLE_EQ(mid[1][0], 2.0);
  EXPECT_EQ(morph(a.points, b.points, 0.0), a.points);
  EXPECT_EQ(morph(a.points, b.points, 1.0), b.points);
  auto blended = blend({&a.points, &b.points, &a.points}, {0.25, 0.5, 0.25});
  EXPECT_DOUBLE_EQ(blended[0][0], 1.0);
  Polygon_soup c = b;
  c.polygons[2] = {1, 3, 2};
  EXPECT_THROW(check_compatible(a, c), Incompatible_inputs_error);
  c = b;
  c.points.push_back({0, 0, 0});
  EXPECT_THROW(check_compatible(a, c), Incompatible_inputs_error);
}

// The needle test that the decimation refuses and the strict repair counts as bad: area below 1e-6 of the
// longest edge squared, or height below 1e-6 eps, whatever the scale of the coordinates.
TEST(Remesh, NeedleTriangles) {
  using crossparam::Point_3;
  using crossparam::internal::needle_triangle;
  const double eps = 1e-3;
  EXPECT_FALSE(needle_triangle(Point_3(0, 0, 0), Point_3(1, 0, 0), Point_3(0.5, 0.8, 0), eps));
  EXPECT_TRUE(needle_triangle(Point_3(0, 0, 0), Point_3(1, 0, 0), Point_3(0.5, 1e-7, 0), eps));   // flat
  EXPECT_TRUE(needle_triangle(Point_3(0, 0, 0), Point_3(1, 0, 0), Point_3(2, 0, 0), eps));        // collinear
  EXPECT_TRUE(needle_triangle(Point_3(0, 0, 0), Point_3(0, 0, 0), Point_3(0, 1, 0), eps));        // two corners at one point
  // A well-shaped face 1e-10 across is a needle by its height (below 1e-6 eps = 1e-9) ...
  EXPECT_TRUE(needle_triangle(Point_3(0, 0, 0), Point_3(1e-10, 0, 0), Point_3(0, 1e-10, 0), eps));
  // ... and not with a tolerance that small.
  EXPECT_FALSE(needle_triangle(Point_3(0, 0, 0), Point_3(1e-10, 0, 0), Point_3(0, 1e-10, 0), 1e-12));
}

// The planar untangler behind the remesher's last step (internal/remeshing/untangle.h): a grid whose inner vertices
// are thrown across each other is untangled with its outline held; a fan whose outline has an empty kernel
// cannot be, and says so, also when its work bound stops it.
TEST(Untangle, GridWithCrossedVerticesBecomesPositive) {
  const int n = 6; // (n+1)^2 points of the unit square's grid
  std::vector<Eigen::Vector2d> p;
  std::vector<char> is_free;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      p.emplace_back(double(i) / n, double(j) / n);
      is_free.push_back(i > 0 && j > 0 && i < n && j < n);
    }
  auto at = [n](int i, int j) { return j * (n + 1) + i; };
  std::vector<internal::Untangle_triangle> tris;
  const Eigen::Matrix2d ref = internal::edge_matrix({0, 0}, {1.0 / n, 0}, {0, 1.0 / n}).inverse();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      tris.push_back({{at(i, j), at(i + 1, j), at(i + 1, j + 1)}, ref});
      tris.push_back({{at(i, j), at(i + 1, j + 1), at(i, j + 1)}, ref});
    }
  const std::vector<Eigen::Vector2d> original = p;
  std::swap(p[at(2, 2)], p[at(4, 3)]); // two inner vertices trade places: a badly tangled grid
  p[at(3, 3)] = {0.95, 0.1};
  internal::Planar_untangler tangled(p, is_free, tris);
  ASSERT_LT(tangled.min_det(), 0);
  internal::Planar_untangler u(p, is_free, tris);
  EXPECT_GT(u.run(0.3 / n), 0);
  EXPECT_GT(u.min_det(), 0);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!is_free[i]) {
      EXPECT_EQ(u.point(i), original[i]); // the outline did not move
    }
}

TEST(Untangle, ReportsWhenNoEmbeddingExists) {
  // A "C"-shaped outline around one free vertex: no point sees all its edges, so some fan triangle stays
  // inverted whatever the free vertex does.
  std::vector<Eigen::Vector2d> p{{0.5, 0.5}, {0, 0}, {1, 0}, {1, 0.2}, {0.2, 0.2}, {0.2, 0.8}, {1, 0.8}, {1, 1}, {0, 1}};
  std::vector<char> is_free{1, 0, 0, 0, 0, 0, 0, 0, 0};
  std::vector<internal::Untangle_triangle> tris;
  const Eigen::Matrix2d ref = internal::edge_matrix({0, 0}, {0.3, 0}, {0.15, 0.26}).inverse();
  for (int k = 1; k <= 8; ++k) tris.push_back({{0, k, k % 8 + 1}, ref});
  internal::Planar_untangler u(p, is_free, tris);
  EXPECT_LE(u.run(0.05), 0);
  // Its work bound: it stops within one L-BFGS iteration (at most 81 energies of the 8 triangles, the line
  // search's) of the bound, and says it failed.
  internal::Planar_untangler bounded(p, is_free, tris);
  EXPECT_LE(bounded.run(0.05, 51, 400, nullptr, 200), 0);
  EXPECT_GE(bounded.evaluations(), 200u);
  EXPECT_LE(bounded.evaluations(), 200u + 82 * 8);
  EXPECT_GT(u.evaluations(), 3 * bounded.evaluations()); // the unbounded run did much more
}

// The disk chart behind the untangling on the surface (internal/remeshing/disk_chart.h). On a torus, a disk grown around
// a point of the tube stays a topological disk however far it grows (it cannot close around the tube or the
// hole), its flattening is one-to-one (every face positive, exact predicate), the normal cone keeps it on the
// side facing out, and points go to the chart and back unchanged.
TEST(DiskChart, TorusPatchIsAOneToOneDisk) {
  const Surface_mesh t = shapes::make_torus(1.0, 0.35, 48, 24);
  internal::WF seed;
  double best = -HUGE_VAL;
  Point_3 center;
  for (internal::WF f : t.faces()) {
    const auto h = t.halfedge(f);
    const Point_3 c = CGAL::centroid(t.point(t.source(h)), t.point(t.target(h)), t.point(t.target(t.next(h))));
    if (c.x() > best) best = c.x(), seed = f, center = c;
  }
  const auto h0 = t.halfedge(seed);
  Kernel::Vector_3 direction = internal::triangle_normal(t.point(t.source(h0)), t.point(t.target(h0)), t.point(t.target(t.next(h0))));
  direction = direction / std::sqrt(direction * direction);
  for (double radius : {0.3, 1.0, 10.0})
    for (double min_cosine : {-2.0, 0.2}) {
      SCOPED_TRACE("radius " + std::to_string(radius) + ", min cosine " + std::to_string(min_cosine));
      const auto chart = internal::Disk_chart::grow(t, {seed}, center, radius, direction, min_cosine);
      ASSERT_TRUE(chart);
      const auto& faces = chart->faces();
      EXPECT_TRUE(chart->contains(seed));
      EXPECT_LT(faces.size(), t.number_of_faces());
      std::set<std::size_t> vertices, edges;
      for (internal::WF f : faces)
        for (auto h : CGAL::halfedges_around_face(t.halfedge(f), t)) vertices.insert(t.target(h)), edges.insert(t.edge(h));
      EXPECT_EQ(long(vertices.size()) - long(edges.size()) + long(faces.size()), 1); // a disk
      std::size_t off_cone = 0;
      for (internal::WF f : faces) {
        std::array<Kernel::Point_2, 3> q;
        for (int i = 0; i < 3; ++i) {
          std::array<double, 3> b{0, 0, 0};
          b[i] = 1;
          const Eigen::Vector2d p = chart->at(t, {f, b});
          q[i] = Kernel::Point_2(p.x(), p.y());
        }
        EXPECT_EQ(CGAL::orientation(q[0], q[1], q[2]), CGAL::POSITIVE);
        const auto h = t.halfedge(f);
        const auto n = internal::triangle_normal(t.point(t.source(h)), t.point(t.target(h)), t.point(t.target(t.next(h))));
        off_cone += n * direction < min_cosine * std::sqrt(n * n);
        const internal::Work_location l{f, {0.2, 0.3, 0.5}};
        internal::Work_location back;
        ASSERT_TRUE(chart->locate(t, chart->at(t, l), back));
        EXPECT_LT(CGAL::squared_distance(internal::point_at(t, l), internal::point_at(t, back)), 1e-20);
      }
      EXPECT_EQ(off_cone, 0u);
      if (radius == 10.0 && min_cosine < -1) {
        EXPECT_GT(faces.size(), t.number_of_faces() / 2);
      }
      internal::Work_location outside;
      EXPECT_FALSE(chart->locate(t, Eigen::Vector2d(2, 0), outside)); // beyond the unit disk
    }
}

// The disk re-embedding of the strict and the output repairs (internal/remeshing/disk_embedding.h). On a torus grid:
// the faces around one vertex form a disk, a band around the tube does not (Euler characteristic 0); Tutte's
// embedding of the grid's faces within 3 rings of a vertex, with the interior crumpled and the boundary held,
// puts each free corner at the average of its neighbours (the residual is rounding), and every face of the disk
// then faces the way it did on the torus.
TEST(DiskEmbedding, DisksAreRecognisedAndTutteAverages) {
  const std::size_t nu = 24, nv = 12;
  const auto id = [&](std::size_t i, std::size_t j) { return (i % nu) * nv + j % nv; };
  std::vector<std::array<std::size_t, 3>> all;
  for (std::size_t i = 0; i < nu; ++i)
    for (std::size_t j = 0; j < nv; ++j) {
      all.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      all.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  std::vector<Point_3> p(nu * nv);
  for (std::size_t i = 0; i < nu; ++i)
    for (std::size_t j = 0; j < nv; ++j) {
      const double u = 2 * CGAL_PI * double(i) / double(nu), v = 2 * CGAL_PI * double(j) / double(nv);
      p[id(i, j)] = Point_3((1 + 0.35 * std::cos(v)) * std::cos(u), (1 + 0.35 * std::cos(v)) * std::sin(u), 0.35 * std::sin(v));
    }
  // The faces whose corners are all within `r` grid steps of (i0, j0) (a square of the grid: a disk for small r).
  const auto within = [&](std::size_t r, std::size_t i0, std::size_t j0) {
    std::vector<std::array<std::size_t, 3>> out;
    const auto near = [&](std::size_t v) {
      const std::size_t i = v / nv, j = v % nv;
      const std::size_t di = std::min((i + nu - i0) % nu, (i0 + nu - i) % nu), dj = std::min((j + nv - j0) % nv, (j0 + nv - j) % nv);
      return di <= r && dj <= r;
    };
    for (const auto& f : all)
      if (near(f[0]) && near(f[1]) && near(f[2])) out.push_back(f);
    return out;
  };
  const auto star = internal::disk_of(within(1, 5, 5));
  ASSERT_TRUE(star);
  EXPECT_EQ(star->corners.size(), 9u);
  EXPECT_EQ(star->boundary_edges, 8u);
  std::vector<std::array<std::size_t, 3>> band;
  for (const auto& f : all)
    if (f[0] / nv == 3 && f[1] / nv == 4) band.push_back(f); // the faces between two rings of the tube
  EXPECT_FALSE(internal::disk_of(band));
  EXPECT_FALSE(internal::disk_of(all)); // closed

  const auto d = internal::disk_of(within(3, 10, 6));
  ASSERT_TRUE(d);
  std::vector<std::size_t> free;
  for (std::size_t v : d->corners) {
    const std::size_t i = v / nv, j = v % nv;
    if (std::max(std::min((i + nu - 10) % nu, (10 + nu - i) % nu), std::min((j + nv - 6) % nv, (6 + nv - j) % nv)) < 3)
      free.push_back(v);
  }
  ASSERT_EQ(free.size(), 25u);
  std::vector<Point_3> crumpled = p;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> offset(-0.5, 0.5);
  for (std::size_t v : free) crumpled[v] = p[v] + Kernel::Vector_3(offset(random), offset(random), offset(random));
  const auto x = internal::tutte_in_space(free, d->edges, [&](std::size_t v) -> const Point_3& { return crumpled[v]; });
  ASSERT_TRUE(x);
  ASSERT_EQ(x->size(), free.size());
  std::vector<Point_3> placed = crumpled;
  for (std::size_t k = 0; k < free.size(); ++k) placed[free[k]] = (*x)[k];
  for (std::size_t v : free) {
    Kernel::Vector_3 sum = CGAL::NULL_VECTOR;
    std::size_t n = 0;
    for (const auto& e : d->edges)
      if (e.first == v || e.second == v) sum = sum + (placed[e.first == v ? e.second : e.first] - CGAL::ORIGIN), ++n;
    EXPECT_EQ(n, 6u);
    EXPECT_LT(std::sqrt(CGAL::squared_distance(placed[v], CGAL::ORIGIN + sum / double(n))), 1e-12);
    EXPECT_GT(CGAL::squared_distance(placed[v], crumpled[v]), 0.0);
  }
  // Each face faces the way it did on the torus, against the tube's normal at its centroid.
  const auto facing = [](const std::vector<Point_3>& q, const std::array<std::size_t, 3>& f) {
    const Point_3 c = CGAL::centroid(q[f[0]], q[f[1]], q[f[2]]);
    const Kernel::Vector_3 radial(c.x(), c.y(), 0), tube = c - (CGAL::ORIGIN + radial / std::sqrt(radial * radial));
    return internal::triangle_normal(q[f[0]], q[f[1]], q[f[2]]) * tube > 0;
  };
  for (const auto& f : within(3, 10, 6)) EXPECT_EQ(facing(placed, f), facing(p, f));
}

// A UV sphere of radius 1 flattened to `thickness` along z: a thin disc whose rim is a crease (the faces just
// above and just below the equator have nearly opposite normals).
Surface_mesh flat_sphere(double thickness, std::size_t rings = 24, std::size_t segments = 48) {
  std::vector<Point_3> pts{Point_3(0, 0, thickness / 2)};
  for (std::size_t i = 1; i < rings; ++i)
    for (std::size_t j = 0; j < segments; ++j) {
      const double th = CGAL_PI * double(i) / double(rings), ph = 2 * CGAL_PI * double(j) / double(segments);
      pts.emplace_back(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th) * thickness / 2);
    }
  pts.emplace_back(0, 0, -thickness / 2);
  auto at = [&](std::size_t i, std::size_t j) { return 1 + (i - 1) * segments + j % segments; };
  std::vector<std::vector<std::size_t>> tris;
  for (std::size_t j = 0; j < segments; ++j) {
    tris.push_back({0, at(1, j), at(1, j + 1)});
    tris.push_back({pts.size() - 1, at(rings - 1, j + 1), at(rings - 1, j)});
    for (std::size_t i = 1; i + 1 < rings; ++i) {
      tris.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      tris.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  Surface_mesh m;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(pts, tris, m);
  return m;
}

// The verifier's flips at the target's own folds: an output that is the thin target moved down by 0.6 of its
// thickness has every upper face nearer the lower sheet, so flipped by the standard rule. Within the tolerance
// of the rim (a crease of the target), such a flip is the target's own; farther in, it is new.
TEST(Verifier, FlipsAtTheTargetsOwnFolds) {
  const double thickness = 2e-3;
  const Surface_mesh target = flat_sphere(thickness);
  Surface_mesh out = target;
  for (auto v : out.vertices()) out.point(v) = out.point(v) + Kernel::Vector_3(0, 0, -0.6 * thickness);
  ASSERT_GT(internal::count_creases(target, 150.0), 0u);
  const Remeshing_verification tight = verify_compatible_remeshing(out, target, out, out, 0.5);
  // The upper faces away from both poles' fans (whose nearest point can be the upper pole region) are flipped.
  EXPECT_GT(tight.flipped_faces, target.number_of_faces() / 3) << tight.message;
  EXPECT_GT(tight.flipped_at_target_folds, 0u);
  EXPECT_GT(tight.new_flipped_faces(), 0u);
  EXPECT_FALSE(tight.valid);
  EXPECT_NE(tight.message.find("away from the target's own folds"), std::string::npos) << tight.message;
  ASSERT_TRUE(tight.new_flipped_face.found);
  EXPECT_LT(tight.new_flipped_face.index, out.number_of_faces());
  EXPECT_NE(tight.message.find("flipped face " + std::to_string(tight.new_flipped_face.index) + " at ("), std::string::npos)
      << tight.message;
  // A tolerance wider than the disc: every flip lies within it of the rim, the surfaces are 0.6 thickness apart.
  const Remeshing_verification wide = verify_compatible_remeshing(out, target, out, out, 80.0);
  EXPECT_EQ(wide.flipped_faces, tight.flipped_faces);
  EXPECT_EQ(wide.flipped_at_target_folds, wide.flipped_faces);
  EXPECT_EQ(wide.new_flipped_faces(), 0u);
  EXPECT_TRUE(wide.valid) << wide.message;
  // The target against itself: nothing flipped.
  EXPECT_EQ(verify_compatible_remeshing(target, target, target, target, 0.5).flipped_faces, 0u);
}

// The verifier says where: an output that is the target with one vertex pushed out by 5 % of the diagonal is
// invalid at 0.5 %, and the output vertex farthest from the target is that one, at its place and distance, at
// any scale (1e-150: the check runs on a copy scaled by a power of two, the places are given back unscaled).
TEST(Verifier, SaysWhere) {
  const Surface_mesh target = shapes::make_deformed_sphere(7, 600, true);
  const double diagonal = internal::bbox_diagonal(target);
  Surface_mesh out = target;
  const Surface_mesh::Vertex_index moved(Surface_mesh::size_type(123));
  const Kernel::Vector_3 outward = out.point(moved) - CGAL::ORIGIN; // the sphere is centred at the origin
  out.point(moved) = out.point(moved) + outward * (0.05 * diagonal / std::sqrt(outward.squared_length()));
  for (const double scale : {1.0, 1e-150}) {
    Surface_mesh t = target, o = out;
    for (Surface_mesh* m : {&t, &o})
      for (auto v : m->vertices()) m->point(v) = Point_3(m->point(v).x() * scale, m->point(v).y() * scale, m->point(v).z() * scale);
    const Remeshing_verification r = verify_compatible_remeshing(t, t, t, o, 0.5);
    EXPECT_FALSE(r.valid);
    ASSERT_TRUE(r.farthest_output_vertex.found);
    EXPECT_EQ(r.farthest_output_vertex.index, 123u) << r.message;
    EXPECT_NEAR(r.farthest_output_vertex.distance, r.hausdorff_to_target, 0.05) << "the vertex is the farthest point";
    EXPECT_GT(r.farthest_output_vertex.distance, 1.0);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(r.farthest_output_vertex.point[std::size_t(i)], o.point(moved)[i], 1e-9 * scale * diagonal);
    ASSERT_TRUE(r.farthest_target_vertex.found);
    EXPECT_LE(r.farthest_target_vertex.distance, r.hausdorff_from_target + 1e-9);
    EXPECT_EQ(r.new_self_intersection.found, r.new_self_intersections > 0);
    EXPECT_NE(r.message.find("output vertex 123 at ("), std::string::npos) << r.message;
    // Valid: the places are still measured, and the message is empty.
    const Remeshing_verification same = verify_compatible_remeshing(t, t, t, t, 0.5);
    EXPECT_TRUE(same.valid) << same.message;
    EXPECT_TRUE(same.message.empty());
    EXPECT_TRUE(same.farthest_output_vertex.found);
    EXPECT_EQ(same.farthest_output_vertex.distance, 0.0);
    EXPECT_FALSE(same.new_flipped_face.found);
  }
}

// The bench cases of ../shared: outputs compatible, the source side exact, the remeshed parameterization
// certified, the target side within the tolerance (independent Hausdorff distance), and no flipped face.
class BenchRemesh : public ::testing::TestWithParam<std::string> {};

TEST_P(BenchRemesh, CompatibleAndClose) {
  std::optional<test_bench::Case> c = test_bench::load(GetParam());
  if (!c) GTEST_SKIP() << test_bench::absent(GetParam());
  Outcome o = remesh_and_verify(c->source, c->target, c->features, 0.5);
  RecordProperty("hausdorff_percent", std::to_string(o.check.hausdorff_target));
  RecordProperty("standard_flips", int(o.standard_flips));
  EXPECT_TRUE(o.certificate);
  EXPECT_TRUE(o.check.compatible);
  EXPECT_TRUE(o.source_prefix_exact);
  EXPECT_LE(o.check.hausdorff_source, 1e-6);
  EXPECT_LT(o.stats.l2_error, 0.4);
  EXPECT_LT(o.stats.l2_error, o.stats.l2_error_initial);
  // The bench figures (doc/results.md): Hausdorff within the tolerance 0.5 %; 13-46 % added vertices; normals
  // deviating more than 30° from the target's on 0.4-2.3 % of the area. The verifier's own count of flips must
  // agree with the one made here.
  EXPECT_LE(o.check.hausdorff_target, 0.5) << o.check.message;
  EXPECT_LE(o.check.flipped_faces, o.standard_flips + 5) << o.check.message;
  EXPECT_LE(o.standard_flips, o.check.flipped_faces + 5) << o.check.message;
  EXPECT_LT(o.check.normal_deviation_above_30, 3.0);
  // The strict checks (doc/results.md). Where the refinement's result has faces flipped by the standard rule
  // (at the target's own folds too) or in new self-intersecting pairs (horse0_horse7, lion_cat, shrec_383_385,
  // wolf0_wolf2: 7 flips at the target's folds, which the verifier lets pass), the decimated overlay is built;
  // none of the four overlays has such faces, and each is returned. The overlay inserts target edges by flips
  // where it can: lion_cat's has about 20 times the source's vertices (108 times when every crossed edge is
  // split).
  RecordProperty("flipped_faces", int(o.check.flipped_faces));
  RecordProperty("flipped_at_target_folds", int(o.check.flipped_at_target_folds));
  RecordProperty("new_self_intersections", int(o.check.new_self_intersections));
  const std::set<std::string> overlaid{"horse0_horse7", "lion_cat", "shrec_383_385", "wolf0_wolf2"};
  EXPECT_EQ(o.stats.overlay_used, overlaid.count(GetParam()) == 1);
  if (GetParam() == "lion_cat") {
    EXPECT_LT(o.stats.overlay_vertices, 25 * o.stats.source_vertices);
    EXPECT_GT(o.stats.overlay_flips, o.stats.overlay_vertices);
  }
  EXPECT_TRUE(o.check.valid) << o.check.message;
  EXPECT_EQ(o.check.new_flipped_faces(), 0u);
  EXPECT_EQ(o.check.new_self_intersections, 0u);
  // The decimation keeps each face within 30° of the target's normal at its centroid (a few faces differ
  // where the nearest point is on a target edge and the two sides' normals differ).
  if (o.stats.overlay_used) {
    EXPECT_LT(o.check.normal_deviation_above_30, 0.1);
  }
  // The folds left after §5.4: on yang_cat_horse the untangling on the target removes 34 (moves along the
  // target below 4.5 % of the diagonal) and the fold repair keeps 195 splits; on shrec_381_382 the untangling
  // removes 3, and the fold repair the rest with 9 splits.
  if (GetParam() == "yang_cat_horse") {
    EXPECT_EQ(o.stats.untangled_folds, 34u);
    EXPECT_EQ(o.stats.fold_repair_splits, 195u);
    EXPECT_GT(o.stats.untangle_moves, 0u);
    EXPECT_LT(o.stats.untangle_max_move, 4.5);
  }
  if (GetParam() == "shrec_381_382") {
    EXPECT_EQ(o.stats.untangled_folds, 3u);
    EXPECT_EQ(o.stats.fold_repair_splits, 9u);
    EXPECT_LT(o.stats.untangle_max_move, 7.0);
  }
  // Added vertices: 13-46 % by the refinement; the decimated overlay keeps more (horse0_horse7 +62 %,
  // shrec_383_385 +27 %, wolf0_wolf2 +82 %, lion_cat +138 %: the lion is coarse where the cat is detailed).
  EXPECT_LT(double(o.stats.output_vertices), (o.stats.overlay_used ? 2.5 : 1.5) * double(o.stats.source_vertices));
}

// At the paper's error (Table 2: L2 0.12-0.14 %; ε = 1 % gives 0.118 % here), the bench cases are within the
// tolerance and need about as many added vertices on average as the paper's four models: 37.4, 1.8, 13.5 and
// 1.7 %, mean 13.6 % (the strict repair's vertices included; the paper's outputs were not held to it). The
// paper's construction only (Remeshing_construction::refinement): the figures compare with the paper's.
TEST(BenchRemeshAtPaperError, AddedVerticesAsThePaper) {
  double added = 0, l2 = 0;
  std::size_t n = 0;
  for (const std::string& name : test_bench::names()) {
    std::optional<test_bench::Case> c = test_bench::load(name);
    if (!c) GTEST_SKIP() << test_bench::absent(name);
    Outcome o = remesh_and_verify(c->source, c->target, c->features, 1.0, Remeshing_construction::refinement);
    EXPECT_LE(o.check.hausdorff_target, 1.0) << name << ": " << o.check.message;
    EXPECT_TRUE(o.certificate) << name;
    EXPECT_LT(o.check.normal_deviation_above_30, 3.0) << name;
    added += 100.0 * (double(o.stats.output_vertices) / double(o.stats.source_vertices) - 1);
    l2 += o.stats.l2_error;
    ++n;
  }
  ASSERT_EQ(n, 6u);
  std::cout << "[ remesh ] at 1 %: mean added " << added / n << " %, mean L2 " << l2 / n << " %\n";
  EXPECT_LT(added / n, 14.5);  // measured: 12.9 %
  EXPECT_GT(l2 / n, 0.11);     // about the paper's error; measured: 0.118 %
  EXPECT_LT(l2 / n, 0.14);
}

// A family of generated pairs, none of them seen when the remesher was written: creatures with thin limbs
// whose proportions are drawn at random (12 features at their extremities and on the body), and deformed
// spheres of very different resolutions with 6-12 random features. Each goes through the whole pipeline at
// ε = 0.5 %, and each output is judged by the verifier's strict checks (no flipped face by the standard rule,
// no new self-intersection, the Hausdorff distance within ε).
TEST(RemeshFamily, StrictChecksOnGeneratedPairs) {
  std::mt19937 rng(20261126);
  auto draw = [&rng](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  struct Pair {
    std::string name;
    Surface_mesh a, b;
    Feature_correspondence f;
  };
  std::vector<Pair> pairs;
  for (int k = 0; k < 3; ++k) {
    shapes::Creature_params pa = shapes::creature_a_params(), pb = shapes::creature_b_params();
    for (shapes::Creature_params* p : {&pa, &pb}) {
      p->leg_length *= draw(0.8, 1.3);
      p->leg_radius_top *= draw(0.7, 1.1);
      p->leg_radius_bottom *= draw(0.6, 1.0);
      p->tail_bend_deg = draw(0.0, 150.0);
      p->neck_elevation_deg = draw(20.0, 65.0);
      p->facet_size *= draw(0.8, 1.3);
    }
    Pair q{"creatures " + std::to_string(k), shapes::make_creature(pa), shapes::make_creature(pb), {}};
    q.f = shapes::creature_features(q.a, pa, q.b, pb);
    pairs.push_back(std::move(q));
  }
  const std::array<std::array<std::size_t, 2>, 3> sizes{{{1500, 1200}, {3000, 700}, {700, 3500}}};
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    Pair q{"spheres " + std::to_string(sizes[k][0]) + "/" + std::to_string(sizes[k][1]),
           shapes::make_deformed_sphere(unsigned(31 + k), sizes[k][0], k % 2 == 1),
           shapes::make_deformed_sphere(unsigned(57 + k), sizes[k][1], k % 2 == 0), {}};
    q.f = shapes::random_features(q.a, q.b, 6 + 3 * k, unsigned(90 + k), false);
    pairs.push_back(std::move(q));
  }
  std::size_t valid = 0;
  for (const Pair& q : pairs) {
    const Outcome o = remesh_and_verify(q.a, q.b, q.f, 0.5);
    std::cout << "[ family ] " << q.name << ": " << (o.check.valid ? "valid" : "NOT valid: " + o.check.message) << "\n";
    EXPECT_TRUE(o.certificate) << q.name;
    EXPECT_TRUE(o.check.compatible) << q.name;
    EXPECT_TRUE(o.source_prefix_exact) << q.name;
    EXPECT_LE(o.check.hausdorff_target, 0.5) << q.name << ": " << o.check.message;
    EXPECT_EQ(o.check.flipped_faces, o.standard_flips) << q.name;
    EXPECT_TRUE(o.check.valid) << q.name << ": " << o.check.message; // measured: all six valid
    valid += o.check.valid;
  }
  std::cout << "[ family ] " << valid << " of " << pairs.size() << " valid\n";
}

// The decimated overlay, asked for (Remeshing_construction::overlay) on generated pairs: a creature pair with
// thin limbs, and deformed spheres of different resolutions with random features, at every tolerance from 1 %
// down to 0.1 %. Its collapses are kept only if they keep the strict checks, its distances certified for every
// point, so each output is valid, every face within the normal deviation (30°) of the target's at its
// centroid, and the vertex count grows as the tolerance shrinks, by no more than the 1/ε that linear triangles
// need on a curved surface (the overlay bounds it anyway).
TEST(RemeshOverlay, ValidByConstructionAtEveryTolerance) {
  struct Pair {
    std::string name;
    Surface_mesh a, b;
    Feature_correspondence f;
  };
  std::vector<Pair> pairs;
  {
    const shapes::Creature_params pa = shapes::creature_a_params(), pb = shapes::creature_b_params();
    Pair q{"creatures", shapes::make_creature(pa), shapes::make_creature(pb), {}};
    q.f = shapes::creature_features(q.a, pa, q.b, pb);
    pairs.push_back(std::move(q));
  }
  {
    Pair q{"spheres 1500/700", shapes::make_deformed_sphere(41, 1500, false), shapes::make_deformed_sphere(43, 700, true), {}};
    q.f = shapes::random_features(q.a, q.b, 9, 77, false);
    pairs.push_back(std::move(q));
  }
  const std::array<double, 4> tolerances{{1.0, 0.5, 0.2, 0.1}};
  for (const Pair& q : pairs) {
    std::array<std::size_t, 4> vertices{};
    for (std::size_t t = 0; t < tolerances.size(); ++t) {
      const double tol = tolerances[t];
      const std::string at = q.name + " at " + std::to_string(tol) + " %";
      const Outcome o = remesh_and_verify(q.a, q.b, q.f, tol, Remeshing_construction::overlay);
      std::cout << "[ overlay ] " << at << ": overlay " << o.stats.overlay_vertices << " vertices, "
                << o.stats.overlay_collapses << " collapses (" << o.stats.overlay_needles_removed << " by the needle removal, "
                << o.stats.overlay_needles_left << " needles left), " << o.stats.output_vertices << " left, Hausdorff "
                << o.check.hausdorff_target << " %; " << (o.check.valid ? "valid" : "NOT valid: " + o.check.message) << "\n";
      EXPECT_TRUE(o.stats.overlay_used) << at;
      EXPECT_TRUE(o.stats.overlay_complete) << at;
      EXPECT_TRUE(o.certificate) << at;
      EXPECT_TRUE(o.check.compatible) << at;
      EXPECT_TRUE(o.source_prefix_exact) << at;
      EXPECT_LE(o.check.hausdorff_source, 1e-6) << at;
      EXPECT_LE(o.check.hausdorff_target, tol) << at;
      EXPECT_EQ(o.check.flipped_faces, 0u) << at;
      EXPECT_EQ(o.standard_flips, 0u) << at;
      EXPECT_EQ(o.flat_on_source, 0u) << at; // every face has area on the source, oriented as it
      EXPECT_EQ(o.check.new_self_intersections, 0u) << at;
      EXPECT_EQ(o.check.faces_above_30, 0u) << at;
      EXPECT_TRUE(o.check.valid) << at << ": " << o.check.message;
      EXPECT_GT(o.stats.overlay_collapses, 0u) << at;
      EXPECT_LT(o.stats.output_vertices, o.stats.overlay_vertices) << at;
      // No face thinner than the decimation's needle bounds is left (their normals would be rounding).
      EXPECT_EQ(o.stats.overlay_needles_left, 0u) << at;
      vertices[t] = o.stats.output_vertices;
    }
    // Tighter tolerances keep more vertices, and ten times tighter at most ten times as many: a linear
    // triangle of size h on a surface of curvature κ is within about κh²/8 of it, so ε needs about κ/ε
    // vertices per unit area where the surface curves.
    for (std::size_t t = 1; t < tolerances.size(); ++t) EXPECT_GE(vertices[t], vertices[t - 1]) << q.name;
    EXPECT_LE(vertices[3], 10 * vertices[0]) << q.name;
  }
}

// Inputs oriented inward: the work meshes are the inputs reversed, so every face tiles its input face with a
// negative orientation in that face's barycentric coordinates (the user's corner order). The decimation must
// judge a collapse against that orientation, not against a positive one (which refused every collapse and
// left the whole overlay, with faces of rounding size flipped).
TEST(RemeshOverlay, InputsOrientedInward) {
  Surface_mesh a = shapes::make_deformed_sphere(41, 1500, false), b = shapes::make_deformed_sphere(43, 700, true);
  const Feature_correspondence f = shapes::random_features(a, b, 9, 77, false);
  CGAL::Polygon_mesh_processing::reverse_face_orientations(a);
  CGAL::Polygon_mesh_processing::reverse_face_orientations(b);
  const double tol = 0.5;
  const Outcome o = remesh_and_verify(a, b, f, tol, Remeshing_construction::overlay);
  std::cout << "[ overlay ] inward spheres: overlay " << o.stats.overlay_vertices << " vertices, "
            << o.stats.overlay_collapses << " collapses, " << o.stats.output_vertices << " left, Hausdorff "
            << o.check.hausdorff_target << " %; " << (o.check.valid ? "valid" : "NOT valid: " + o.check.message) << "\n";
  EXPECT_TRUE(o.stats.overlay_used);
  EXPECT_TRUE(o.certificate);
  EXPECT_TRUE(o.source_prefix_exact);
  EXPECT_EQ(o.flat_on_source, 0u);
  EXPECT_TRUE(o.check.valid) << o.check.message;
  // Decimated: at most twice the source's vertices (the outward pair keeps well under that).
  EXPECT_GT(o.stats.overlay_collapses, 0u);
  EXPECT_LE(o.stats.output_vertices, 2 * a.number_of_vertices());
}

// How the overlay classifies a target edge (c, d) against an edge (a, z) of the remeshed source, in a frame of
// the base mesh: a crossing within conform_snap (10^-6, relative to |z - a|) of an end is reported at that
// end, so that the overlay can ask whether the end's image lies on the target edge on the target too (where
// the map squeezes the target it need not, and the edge is split there instead); an edge with both ends that
// near its line is reported as nearly along it, for the overlay to decide on the target whether it runs along
// the target edge or crosses it (where the map squeezes the target into a sliver of the base mesh).
TEST(RemeshOverlay, CrossingsNearAnEndAreReportedAtThatEnd) {
  using crossparam::internal::Overlay_crossing;
  using crossparam::internal::overlay_crossing;
  using P2 = crossparam::internal::Point_2;
  const P2 a(0, 0), z(1, 0);
  double t = -1;
  EXPECT_EQ(overlay_crossing(a, z, P2(0.25, -1), P2(0.25, 1), t), Overlay_crossing::inside);
  EXPECT_NEAR(t, 0.25, 1e-15);
  EXPECT_EQ(overlay_crossing(a, z, P2(1e-8, -1), P2(1e-8, 1), t), Overlay_crossing::at_first);
  EXPECT_NEAR(t, 1e-8, 1e-20);
  EXPECT_EQ(overlay_crossing(a, z, P2(1 - 1e-9, 1), P2(1 - 1e-9, -1), t), Overlay_crossing::at_second);
  EXPECT_NEAR(t, 1 - 1e-9, 1e-15);
  // Twice the snap distance is an ordinary crossing.
  EXPECT_EQ(overlay_crossing(a, z, P2(2e-6, -1), P2(2e-6, 1), t), Overlay_crossing::inside);
  // Nearly along (a, z): a is 5e-8 above the line of (c, d), z 1.5e-7 below it; the lines meet a quarter of the
  // way along (a, z).
  EXPECT_EQ(overlay_crossing(a, z, P2(-1, -2.5e-7), P2(2, 3.5e-7), t), Overlay_crossing::along);
  EXPECT_NEAR(t, 0.25, 1e-6);
  // Not crossing: (c, d) ends before (a, z), or passes exactly through a.
  EXPECT_EQ(overlay_crossing(a, z, P2(0.5, 0.1), P2(0.5, 1), t), Overlay_crossing::none);
  EXPECT_EQ(overlay_crossing(a, z, P2(0, -1), P2(0, 1), t), Overlay_crossing::none);
}

// The overlay's second attempt (where its first fails the strict checks) refuses flips that make a sliver on
// the source: a face whose height is below source_sliver_height (10^-9) of its longest edge. Four vertices
// interpolated on one line of the source, off it by rounding (10^-16), make such faces; a thin face the
// overlay needs (10^-6 of its length: conform_snap) is not one.
TEST(RemeshOverlay, SliversOnTheSourceAreRecognised) {
  using crossparam::internal::source_sliver_triangle;
  using P3 = crossparam::Point_3;
  const P3 a(0, 0, 0), b(1, 0, 0);
  EXPECT_FALSE(source_sliver_triangle(a, b, P3(0.5, 0.5, 0)));
  EXPECT_FALSE(source_sliver_triangle(a, b, P3(0.3, 1e-6, 0)));
  EXPECT_FALSE(source_sliver_triangle(a, b, P3(0.3, 0, 2e-9)));
  EXPECT_TRUE(source_sliver_triangle(a, b, P3(0.3, 1e-16, 0)));
  EXPECT_TRUE(source_sliver_triangle(a, b, P3(0.3, 0, 5e-10)));
  EXPECT_TRUE(source_sliver_triangle(a, b, P3(0.3, 0, 0)));  // no area
  EXPECT_TRUE(source_sliver_triangle(a, a, P3(0.3, 0.2, 0))); // two corners at one point
  // Relative to the face's size (the working coordinates have a unit diagonal; faces are smaller or larger).
  for (double k : {1e-6, 1e3}) {
    EXPECT_FALSE(source_sliver_triangle(P3(0, 0, 0), P3(k, 0, 0), P3(0.3 * k, 1e-6 * k, 0))) << k;
    EXPECT_TRUE(source_sliver_triangle(P3(0, 0, 0), P3(k, 0, 0), P3(0.3 * k, 1e-16 * k, 0))) << k;
  }
}

// A pair whose map squeezes a protrusion of the target into a sliver of the base mesh: on shrec/381_385 of the
// wider bench (wide_cases.h) the target's long protrusion at its -x end is stretched about 10^8 times by its
// parameterization, so that its vertices are 10^-12 apart over the base mesh. There a target vertex's location
// interpolated in the face of the remeshed source that holds it has its image off the vertex by up to 0.35 % of
// the diagonal, and edges of the remeshed source lie within rounding of a target edge's line over the base mesh
// while crossing it far from their ends on the target. The overlay inserts such vertices at their own
// locations and crosses such edges (Remeshing_statistics::overlay_exact, overlay_along_crossed): the output is
// valid by the strict checks at 0.2 %, where it was 0.36 % from the target.
TEST(RemeshOverlay, TargetSqueezedIntoASliverOfTheBaseMesh) {
  const std::optional<wide_bench::Case> c = wide_bench::load("shrec/381_385");
  if (!c) GTEST_SKIP() << "needs ../shared/data/landmarks/shrec07_fourleg (absent)";
  const Outcome o = remesh_and_verify(c->source, c->target, c->features, 0.2, Remeshing_construction::overlay);
  std::cout << "[ squeezed ] " << o.stats.overlay_exact << " target vertices at their own location, "
            << o.stats.overlay_along_crossed << " crossings nearly along; "
            << (o.check.valid ? "valid" : "NOT valid: " + o.check.message) << "\n";
  EXPECT_GT(o.stats.overlay_exact, 0u);
  EXPECT_GT(o.stats.overlay_along_crossed, 0u);
  EXPECT_TRUE(o.certificate);
  EXPECT_TRUE(o.check.compatible);
  EXPECT_TRUE(o.source_prefix_exact);
  EXPECT_LE(o.check.hausdorff_source, 1e-6);
  EXPECT_LE(o.check.hausdorff_target, 0.2);
  EXPECT_EQ(o.check.flipped_faces, 0u);
  EXPECT_EQ(o.check.new_self_intersections, 0u);
  EXPECT_EQ(o.flat_on_source, 0u); // no vertex rounded onto or past an edge of a sliver face on the source
  EXPECT_TRUE(o.check.valid) << o.check.message;
}

INSTANTIATE_TEST_SUITE_P(Shared, BenchRemesh,
                         ::testing::ValuesIn(test_bench::names()),
                         [](const auto& info) { return info.param; });

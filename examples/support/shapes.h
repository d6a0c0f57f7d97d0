// SPDX-License-Identifier: GPL-3.0-or-later
// Self-contained input meshes generated in code (no files): two different "creatures" with semantically
// corresponding feature vertices, randomly deformed spheres with random feature correspondences, and a torus.
// Used by the CLI's demo, the tests and the examples (CMake target crossparam_shapes); not installed with the
// library.
//
// Every generator is deterministic: the same arguments give the same mesh (same vertex order, same faces,
// bit-identical coordinates) on every call and every run. Random numbers come from std::mt19937 raw outputs
// only (no std:: distributions, whose algorithms are implementation-defined).
#ifndef CROSSPARAM_EXAMPLES_SUPPORT_SHAPES_H
#define CROSSPARAM_EXAMPLES_SUPPORT_SHAPES_H

#include <crossparam/errors.h>
#include <crossparam/types.h>

#include <CGAL/Complex_2_in_triangulation_3.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh_default_criteria_3.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/make_surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace crossparam {
namespace shapes {

// ------------------------------------------------------------------------------------------------------------
// Creatures
// ------------------------------------------------------------------------------------------------------------

/// Parameters of a four-legged "creature": a smooth union of a body ellipsoid, a neck, a head with a snout,
/// four legs and a tail, meshed with CGAL's implicit surface mesher. Frame: +x forward (towards the head),
/// +y to the creature's left, +z up; the body centre is the origin. Lengths are in body units (~1).
struct Creature_params {
  std::array<double, 3> body_radii{1.0, 0.42, 0.38};  ///< semi-axes of the body ellipsoid
  double neck_length = 0.50;                          ///< from the neck base on the body to the head centre
  double neck_elevation_deg = 40.0;                   ///< neck angle above the horizontal
  double neck_radius_base = 0.20;
  double neck_radius_top = 0.15;
  std::array<double, 3> head_radii{0.28, 0.22, 0.22};  ///< semi-axes of the head ellipsoid
  double snout_length = 0.30;                          ///< from the head centre to the snout end centre
  double snout_droop_deg = 15.0;                       ///< snout angle below the horizontal
  double snout_radius_base = 0.15;
  double snout_radius_tip = 0.08;
  double leg_x_front = 0.62;  ///< x of the front legs, as a fraction of body_radii[0]
  double leg_x_hind = -0.62;  ///< x of the hind legs, as a fraction of body_radii[0]
  double leg_y = 0.55;        ///< |y| of the leg tops, as a fraction of body_radii[1]
  double leg_length = 0.75;   ///< from the leg top (inside the body) to the centre of the foot sphere
  double leg_radius_top = 0.13;
  double leg_radius_bottom = 0.08;
  double leg_splay_deg = 6.0;           ///< outward tilt of the legs
  double tail_length = 0.70;            ///< arc length of the tail centre line
  double tail_elevation_deg = 25.0;     ///< initial tail angle above the horizontal (pointing backwards)
  double tail_bend_deg = 20.0;          ///< total turning of the tail (positive: curls upwards)
  double tail_radius_base = 0.09;
  double tail_radius_tip = 0.045;
  int tail_segments = 8;
  double blend = 0.12;  ///< smooth-union radius between body parts
  // Mesher criteria (CGAL::Surface_mesh_default_criteria_3).
  double facet_angle_deg = 30.0;   ///< lower bound on facet angles
  double facet_size = 0.036;       ///< upper bound on surface Delaunay ball radii (controls the vertex count)
  double facet_distance = 0.005;   ///< upper bound on facet-to-surface distance
};

/// Parameters of creature_a(): a dog-like animal (slim body, medium neck, long legs, nearly straight tail).
inline Creature_params creature_a_params() { return Creature_params{}; }

/// Parameters of creature_b(): a different animal (fatter, longer body, long raised neck, short legs, strongly
/// bent tail, longer snout).
inline Creature_params creature_b_params() {
  Creature_params p;
  p.body_radii = {1.15, 0.56, 0.50};
  p.neck_length = 0.95;
  p.neck_elevation_deg = 58.0;
  p.neck_radius_base = 0.24;
  p.neck_radius_top = 0.13;
  p.head_radii = {0.30, 0.20, 0.19};
  p.snout_length = 0.36;
  p.snout_droop_deg = 25.0;
  p.snout_radius_base = 0.14;
  p.snout_radius_tip = 0.07;
  p.leg_x_front = 0.58;
  p.leg_x_hind = -0.60;
  p.leg_y = 0.50;
  p.leg_length = 0.48;
  p.leg_radius_top = 0.15;
  p.leg_radius_bottom = 0.10;
  p.leg_splay_deg = 10.0;
  p.tail_length = 0.95;
  p.tail_elevation_deg = 10.0;
  p.tail_bend_deg = 140.0;
  p.tail_radius_base = 0.10;
  p.tail_radius_tip = 0.05;
  p.tail_segments = 12;
  p.blend = 0.14;
  p.facet_size = 0.036;
  p.facet_distance = 0.005;
  return p;
}

/// Names of the creature features, in the order of creature_anchors() and creature_features().
inline const std::vector<std::string>& creature_feature_names() {
  static const std::vector<std::string> names{
      "nose tip",       "top of head",   "front left foot", "front right foot", "hind left foot", "hind right foot",
      "tail tip",       "back",          "belly",           "chest",            "left flank",     "right flank"};
  return names;
}

namespace internal_shapes {

struct V3 {
  double x = 0, y = 0, z = 0;
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double norm(V3 a) { return std::sqrt(dot(a, a)); }
inline V3 normalized(V3 a) {
  const double n = norm(a);
  return n > 0 ? (1.0 / n) * a : a;
}
inline double deg(double d) { return d * 3.14159265358979323846 / 180.0; }

/// Quadratic smooth minimum (C1), radius k.
inline double smin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - 0.25 * h * h * k;
}

/// Approximate signed distance to an axis-aligned ellipsoid (exact sign, good near the surface).
inline double sd_ellipsoid(V3 p, V3 c, V3 r) {
  const V3 q = p - c;
  const V3 a{q.x / r.x, q.y / r.y, q.z / r.z};
  const V3 b{q.x / (r.x * r.x), q.y / (r.y * r.y), q.z / (r.z * r.z)};
  const double k0 = norm(a);
  const double k1 = norm(b);
  if (k1 < 1e-12) return -std::min(r.x, std::min(r.y, r.z));
  return k0 * (k0 - 1.0) / k1;
}

/// Exact signed distance to a round cone (spheres of radii r1 at a and r2 at b, and their tangent cone).
inline double sd_round_cone(V3 p, V3 a, V3 b, double r1, double r2) {
  const V3 ba = b - a;
  const double l2 = dot(ba, ba);
  const double rr = r1 - r2;
  const double a2 = l2 - rr * rr;
  const double il2 = 1.0 / l2;
  const V3 pa = p - a;
  const double y = dot(pa, ba);
  const double z = y - l2;
  const V3 w = l2 * pa - y * ba;
  const double x2 = dot(w, w);
  const double y2 = y * y * l2;
  const double z2 = z * z * l2;
  const double k = (rr > 0 ? 1.0 : (rr < 0 ? -1.0 : 0.0)) * rr * rr * x2;
  if ((z > 0 ? 1.0 : (z < 0 ? -1.0 : 0.0)) * a2 * z2 > k) return std::sqrt(x2 + z2) * il2 - r2;
  if ((y > 0 ? 1.0 : (y < 0 ? -1.0 : 0.0)) * a2 * y2 < k) return std::sqrt(x2 + y2) * il2 - r1;
  return (std::sqrt(x2 * a2 * il2) + y * rr) * il2 - r1;
}

struct Round_cone {
  V3 a, b;
  double ra, rb;
};

/// The creature as explicit primitives, with its feature anchor points.
struct Creature_geometry {
  V3 body_radii;
  Round_cone neck;
  V3 head_center, head_radii;
  Round_cone snout;
  std::array<Round_cone, 4> legs;  // front left, front right, hind left, hind right
  std::vector<Round_cone> tail;
  double blend = 0.1;
  double tail_smooth = 0.05;
  std::vector<V3> anchors;  // in creature_feature_names() order
  double bounding_radius = 1;

  explicit Creature_geometry(const Creature_params& p) {
    body_radii = {p.body_radii[0], p.body_radii[1], p.body_radii[2]};
    blend = p.blend;
    const double rx = body_radii.x, ry = body_radii.y, rz = body_radii.z;
    // Neck: from a point on the front top of the body, raised by neck_elevation.
    const V3 neck_base{0.72 * rx, 0.0, 0.35 * rz};
    const double ne = deg(p.neck_elevation_deg);
    head_center = neck_base + p.neck_length * V3{std::cos(ne), 0.0, std::sin(ne)};
    neck = {neck_base, head_center, p.neck_radius_base, p.neck_radius_top};
    head_radii = {p.head_radii[0], p.head_radii[1], p.head_radii[2]};
    const double sd = deg(p.snout_droop_deg);
    const V3 snout_dir{std::cos(sd), 0.0, -std::sin(sd)};
    const V3 snout_end = head_center + p.snout_length * snout_dir;
    snout = {head_center, snout_end, p.snout_radius_base, p.snout_radius_tip};
    // Legs.
    const double splay = deg(p.leg_splay_deg);
    const double xs[4] = {p.leg_x_front * rx, p.leg_x_front * rx, p.leg_x_hind * rx, p.leg_x_hind * rx};
    const double side[4] = {1.0, -1.0, 1.0, -1.0};
    std::array<V3, 4> feet;
    for (int i = 0; i < 4; ++i) {
      const V3 top{xs[i], side[i] * p.leg_y * ry, -0.25 * rz};
      const V3 dir{0.0, side[i] * std::sin(splay), -std::cos(splay)};
      const V3 bottom = top + p.leg_length * dir;
      legs[i] = {top, bottom, p.leg_radius_top, p.leg_radius_bottom};
      feet[i] = bottom + p.leg_radius_bottom * dir;
    }
    // Tail: a circular arc in the xz plane, starting inside the rear of the body, pointing backwards.
    const int n = std::max(1, p.tail_segments);
    const double e0 = deg(p.tail_elevation_deg);
    const double bend = deg(p.tail_bend_deg);
    const double ds = p.tail_length / n;
    V3 q{-0.85 * rx, 0.0, 0.25 * rz};
    double r = p.tail_radius_base;
    V3 dir{};
    for (int i = 0; i < n; ++i) {
      // Direction at the middle of the segment; the tail points backwards (-x) and turns upwards.
      const double ang = e0 + bend * (i + 0.5) / n;
      dir = {-std::cos(ang), 0.0, std::sin(ang)};
      const V3 q2 = q + ds * dir;
      const double r2 = p.tail_radius_base + (p.tail_radius_tip - p.tail_radius_base) * (i + 1.0) / n;
      tail.push_back({q, q2, r, r2});
      q = q2;
      r = r2;
    }
    const V3 tail_tip = q + p.tail_radius_tip * dir;
    tail_smooth = 0.5 * std::min(p.tail_radius_base, p.tail_radius_tip);
    // Feature anchors (points on or near the surface of the corresponding part).
    const V3 nose = snout_end + p.snout_radius_tip * snout_dir;
    const V3 head_top = head_center + V3{0.0, 0.0, head_radii.z};
    anchors = {nose,
               head_top,
               feet[0],
               feet[1],
               feet[2],
               feet[3],
               tail_tip,
               V3{-0.15 * rx, 0.0, rz},
               V3{0.0, 0.0, -rz},
               V3{0.80 * rx, 0.0, -0.35 * rz},
               V3{-0.1 * rx, ry, 0.0},
               V3{-0.1 * rx, -ry, 0.0}};
    // Move the anchors onto the surface (a few Newton steps along the field gradient): some, like the chest,
    // lie inside a smooth blend.
    for (V3& a : anchors) {
      for (int it = 0; it < 20; ++it) {
        const double f = (*this)(a);
        const double e = 1e-6;
        const V3 g{((*this)(a + V3{e, 0, 0}) - (*this)(a - V3{e, 0, 0})) / (2 * e),
                   ((*this)(a + V3{0, e, 0}) - (*this)(a - V3{0, e, 0})) / (2 * e),
                   ((*this)(a + V3{0, 0, e}) - (*this)(a - V3{0, 0, e})) / (2 * e)};
        const double g2 = dot(g, g);
        if (g2 < 1e-12 || std::abs(f) < 1e-9) break;
        a = a - (f / g2) * g;
      }
    }
    double R = std::max(rx, std::max(ry, rz));
    auto grow = [&R](const Round_cone& c) {
      R = std::max(R, norm(c.a) + c.ra);
      R = std::max(R, norm(c.b) + c.rb);
    };
    grow(neck);
    grow(snout);
    for (const auto& l : legs) grow(l);
    for (const auto& t : tail) grow(t);
    R = std::max(R, norm(head_center) + std::max(head_radii.x, std::max(head_radii.y, head_radii.z)));
    bounding_radius = R + blend + 0.3;
  }

  /// Signed field: negative inside, positive outside (approximately a distance).
  double operator()(V3 p) const {
    double f = sd_ellipsoid(p, V3{}, body_radii);
    // Every union is smooth: a crease (hard min) on the surface makes the mesher over-refine along it.
    double legs_f = sd_round_cone(p, legs[0].a, legs[0].b, legs[0].ra, legs[0].rb);
    for (std::size_t i = 1; i < legs.size(); ++i)
      legs_f = smin(legs_f, sd_round_cone(p, legs[i].a, legs[i].b, legs[i].ra, legs[i].rb), 0.5 * blend);
    f = smin(f, legs_f, blend);
    double tail_f = sd_round_cone(p, tail[0].a, tail[0].b, tail[0].ra, tail[0].rb);
    for (std::size_t i = 1; i < tail.size(); ++i)
      tail_f = smin(tail_f, sd_round_cone(p, tail[i].a, tail[i].b, tail[i].ra, tail[i].rb), tail_smooth);
    f = smin(f, tail_f, 0.6 * blend);
    double head_f = smin(sd_ellipsoid(p, head_center, head_radii),
                         sd_round_cone(p, snout.a, snout.b, snout.ra, snout.rb), 0.6 * blend);
    head_f = smin(head_f, sd_round_cone(p, neck.a, neck.b, neck.ra, neck.rb), blend);
    return smin(f, head_f, blend);
  }

  /// Interior points of every part (used to seed the mesher on every part).
  std::vector<V3> part_centres() const {
    std::vector<V3> c{V3{}, head_center, 0.5 * (neck.a + neck.b), snout.b};
    for (const auto& l : legs) {
      c.push_back(0.5 * (l.a + l.b));
      c.push_back(l.b);
    }
    for (const auto& t : tail) c.push_back(t.b);
    return c;
  }
};

/// Adds a creation time stamp to a triangulation vertex or cell base. With it, CGAL orders handles in
/// std::set and friends by creation order instead of by address, which makes the surface mesher (whose
/// manifold-repair levels keep std::set<Vertex_handle>) deterministic. This is what Mesh_3 does.
template <class Base>
class With_time_stamp : public Base {
public:
  using Base::Base;
  typedef CGAL::Tag_true Has_timestamp;
  template <class TDS2>
  struct Rebind_TDS {
    typedef typename Base::template Rebind_TDS<TDS2>::Other Base2;
    typedef With_time_stamp<Base2> Other;
  };
  std::size_t time_stamp() const { return time_stamp_; }
  void set_time_stamp(const std::size_t& ts) { time_stamp_ = ts; }

private:
  std::size_t time_stamp_ = std::size_t(-1);
};

/// The surface mesher's default triangulation (CGAL::Surface_mesh_default_triangulation_3) with time stamps.
struct Mesher_triangulation {
  typedef CGAL::Robust_circumcenter_traits_3<Kernel> K;
  typedef With_time_stamp<CGAL::Surface_mesh_vertex_base_3<K>> Vb;
  typedef With_time_stamp<
      CGAL::Delaunay_triangulation_cell_base_with_circumcenter_3<K, CGAL::Surface_mesh_cell_base_3<K>>>
      Cb;
  typedef CGAL::Triangulation_data_structure_3<Vb, Cb> Tds;
  typedef CGAL::Delaunay_triangulation_3<K, Tds> type;
};

/// Restores CGAL's default random generator on scope exit (the mesher must not depend on the clock).
class Default_random_guard {
public:
  explicit Default_random_guard(unsigned seed) : saved_(CGAL::get_default_random()) {
    CGAL::get_default_random() = CGAL::Random(seed);
  }
  ~Default_random_guard() { CGAL::get_default_random() = saved_; }
  Default_random_guard(const Default_random_guard&) = delete;
  Default_random_guard& operator=(const Default_random_guard&) = delete;

private:
  CGAL::Random saved_;
};

/// Signed volume of a closed triangle mesh (positive when outward oriented).
inline double signed_volume(const Surface_mesh& m) {
  double v = 0;
  for (auto f : m.faces()) {
    auto h = m.halfedge(f);
    const Point_3& a = m.point(m.source(h));
    const Point_3& b = m.point(m.target(h));
    const Point_3& c = m.point(m.target(m.next(h)));
    v += a.x() * (b.y() * c.z() - b.z() * c.y()) - a.y() * (b.x() * c.z() - b.z() * c.x()) +
         a.z() * (b.x() * c.y() - b.y() * c.x());
  }
  return v / 6.0;
}

/// Number of connected components (through edges) of a mesh.
inline std::size_t count_components(const Surface_mesh& m) {
  std::vector<int> seen(m.number_of_vertices() + m.number_of_removed_vertices(), 0);
  std::size_t comps = 0;
  std::vector<Surface_mesh::Vertex_index> stack;
  for (auto v0 : m.vertices()) {
    if (seen[v0]) continue;
    ++comps;
    seen[v0] = 1;
    stack.push_back(v0);
    while (!stack.empty()) {
      auto v = stack.back();
      stack.pop_back();
      for (auto h : CGAL::halfedges_around_target(v, m)) {
        auto w = m.source(h);
        if (!seen[w]) {
          seen[w] = 1;
          stack.push_back(w);
        }
      }
    }
  }
  return comps;
}

/// Throws Algorithm_error unless `m` is a closed, single-component triangle mesh of the given genus with
/// positive volume. `what` names the generator.
inline void check_closed_surface(const Surface_mesh& m, int genus, const std::string& what) {
  for (auto h : m.halfedges())
    if (m.is_border(h)) throw Algorithm_error(what + ": generated mesh has a boundary");
  for (auto f : m.faces())
    if (CGAL::halfedges_around_face(m.halfedge(f), m).size() != 3)
      throw Algorithm_error(what + ": generated mesh has a non-triangular face");
  const long chi = static_cast<long>(m.number_of_vertices()) - static_cast<long>(m.number_of_edges()) +
                   static_cast<long>(m.number_of_faces());
  if (chi != 2 - 2 * genus)
    throw Algorithm_error(what + ": generated mesh has Euler characteristic " + std::to_string(chi) +
                          ", expected " + std::to_string(2 - 2 * genus));
  if (count_components(m) != 1) throw Algorithm_error(what + ": generated mesh is not connected");
  if (!(signed_volume(m) > 0)) throw Algorithm_error(what + ": generated mesh is not outward oriented");
}

/// Builds a Surface_mesh from a triangle soup; throws Algorithm_error if a face cannot be added (non-manifold).
inline Surface_mesh soup_to_mesh(const std::vector<Point_3>& points,
                                 const std::vector<std::array<std::size_t, 3>>& triangles, const std::string& what) {
  Surface_mesh m;
  m.reserve(points.size(), 3 * triangles.size() / 2, triangles.size());
  std::vector<Surface_mesh::Vertex_index> vs;
  vs.reserve(points.size());
  for (const auto& p : points) vs.push_back(m.add_vertex(p));
  for (const auto& t : triangles)
    if (m.add_face(vs[t[0]], vs[t[1]], vs[t[2]]) == Surface_mesh::null_face())
      throw Algorithm_error(what + ": generated triangles do not form a manifold surface");
  return m;
}

/// Uniform double in [0, 1) from raw mt19937 output (portable, unlike std::uniform_real_distribution).
inline double uniform01(std::mt19937& rng) { return (static_cast<double>(rng()) + 0.5) / 4294967296.0; }
inline double uniform(std::mt19937& rng, double lo, double hi) { return lo + (hi - lo) * uniform01(rng); }
inline V3 random_unit(std::mt19937& rng) {
  const double z = 2.0 * uniform01(rng) - 1.0;
  const double phi = 2.0 * 3.14159265358979323846 * uniform01(rng);
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}
inline V3 to_v3(const Point_3& p) { return {p.x(), p.y(), p.z()}; }

/// Index of the vertex of `m` nearest to `q` that is not in `used` (vertex indices are 0..n-1).
inline std::size_t nearest_unused_vertex(const Surface_mesh& m, V3 q, const std::vector<char>& used) {
  std::size_t best = m.number_of_vertices();
  double best_d = std::numeric_limits<double>::infinity();
  for (auto v : m.vertices()) {
    if (used[v]) continue;
    const V3 d = to_v3(m.point(v)) - q;
    const double dd = dot(d, d);
    if (dd < best_d) {
      best_d = dd;
      best = v;
    }
  }
  return best;
}

/// Geodesic icosphere of frequency n (10 n^2 + 2 unit-length vertices), outward oriented.
inline void geodesic_sphere(std::size_t n, std::vector<V3>& points, std::vector<std::array<std::size_t, 3>>& tris) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const V3 ico[12] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                      {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                            {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                            {3, 8, 9},   {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  points.clear();
  tris.clear();
  // A point is identified by its nonzero (corner, weight) pairs sorted by corner, so points shared by faces
  // get one index and bit-identical coordinates.
  std::map<std::array<long, 6>, std::size_t> index;
  const long N = static_cast<long>(n);
  auto point_index = [&](const int c[3], long i, long j) {
    std::array<std::pair<long, long>, 3> w{{{c[0], N - i - j}, {c[1], i}, {c[2], j}}};
    std::sort(w.begin(), w.end());
    std::array<long, 6> key{-1, -1, -1, -1, -1, -1};
    int k = 0;
    for (const auto& cw : w)
      if (cw.second != 0) {
        key[2 * k] = cw.first;
        key[2 * k + 1] = cw.second;
        ++k;
      }
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    V3 p{};
    for (int m = 0; m < k; ++m) p = p + static_cast<double>(key[2 * m + 1]) * ico[key[2 * m]];
    points.push_back(normalized(p));
    index.emplace(key, points.size() - 1);
    return points.size() - 1;
  };
  for (const auto& f : faces) {
    for (long i = 0; i < N; ++i)
      for (long j = 0; i + j < N; ++j) {
        tris.push_back({point_index(f, i, j), point_index(f, i + 1, j), point_index(f, i, j + 1)});
        if (i + j < N - 1)
          tris.push_back({point_index(f, i + 1, j), point_index(f, i + 1, j + 1), point_index(f, i, j + 1)});
      }
  }
}

/// Orientation of the triangle (a, b, c) of a sphere mesh seen from the origin: det(a, b, c) > 0 if outward.
inline double det3(V3 a, V3 b, V3 c) { return dot(a, cross(b, c)); }

/// Makes the geodesic sphere (`unit`, `tris`, frequency n) irregular, deterministically from `rng`:
/// 1. tangential jitter of every vertex (up to 0.3 edge lengths, never inverting a triangle);
/// 2. removal of a random subset of the vertices (up to 40%, with a density gradient over the sphere) by
///    collapsing each onto its nearest neighbour when the link condition holds and no triangle inverts;
/// 3. edge flips towards the convex hull of the points (the spherical Delaunay triangulation).
/// Only vertex indices and the mt19937 stream decide anything, so the result is the same in every run.
inline void irregular_sphere(std::size_t n, std::mt19937& rng, std::vector<V3>& unit,
                             std::vector<std::array<std::size_t, 3>>& tris) {
  using VI = Surface_mesh::Vertex_index;
  using HI = Surface_mesh::Halfedge_index;
  const double h = 1.05 / static_cast<double>(n);  // approximate edge length
  const double min_det = 0.05 * h * h;              // triangles kept clearly non-degenerate
  std::vector<Point_3> pts;
  for (const V3& u : unit) pts.emplace_back(u.x, u.y, u.z);
  Surface_mesh m = soup_to_mesh(pts, tris, "make_deformed_sphere");
  auto pos = [&m](VI v) { return to_v3(m.point(v)); };
  auto set_pos = [&m](VI v, V3 p) { m.point(v) = Point_3(p.x, p.y, p.z); };
  // Would moving v to p keep every triangle incident to v (other than those containing `skip`) outward?
  auto star_ok = [&](VI v, V3 p, VI skip) {
    for (HI hh : CGAL::halfedges_around_target(m.halfedge(v), m)) {
      const VI a = m.source(hh);                // previous vertex in the face (a, v, c)
      const VI c = m.target(m.next(hh));
      if (a == skip || c == skip) continue;
      if (!(det3(pos(a), p, pos(c)) > min_det)) return false;
    }
    return true;
  };

  // 1. Jitter.
  for (VI v : m.vertices()) {
    const V3 u = pos(v);
    V3 t = random_unit(rng);
    t = t - dot(t, u) * u;
    const double amp = 0.3 * h * uniform01(rng);
    const V3 p = normalized(u + amp * normalized(t));
    if (norm(t) > 1e-6 && star_ok(v, p, VI())) set_pos(v, p);
  }

  // 2. Vertex removal.
  const V3 density_dir = random_unit(rng);
  const double drop = uniform(rng, 0.05, 0.2);
  const std::size_t nv0 = m.number_of_vertices();
  std::size_t alive = nv0;
  for (std::size_t i = 0; i < nv0; ++i) {
    const double r = uniform01(rng);
    const VI v(static_cast<Surface_mesh::size_type>(i));
    if (m.is_removed(v) || alive <= 12) continue;
    const V3 u = pos(v);
    if (!(r < drop * (1.0 + dot(u, density_dir)))) continue;
    HI best;  // halfedge v -> w with w the nearest neighbour
    double best_d = std::numeric_limits<double>::infinity();
    for (HI hh : CGAL::halfedges_around_source(v, m)) {
      const double d = norm(pos(m.target(hh)) - u);
      if (d < best_d) {
        best_d = d;
        best = hh;
      }
    }
    const VI w = m.target(best);
    if (m.degree(v) + m.degree(w) > 16) continue;
    if (!CGAL::Euler::does_satisfy_link_condition(m.edge(best), m)) continue;
    const V3 pw = pos(w);
    if (!star_ok(v, pw, w)) continue;
    const VI kept = CGAL::Euler::collapse_edge(m.edge(best), m);
    set_pos(kept, pw);
    --alive;
  }

  // 3. Flips: an edge (a, b) with faces (a, b, c) and (b, a, d) is reflex if d lies outside the plane of
  // (a, b, c); flipping it to (c, d) makes the surface locally convex.
  std::vector<Surface_mesh::Edge_index> stack;
  std::vector<char> queued(m.number_of_edges() + m.number_of_removed_edges(), 0);
  for (auto e : m.edges()) {
    stack.push_back(e);
    queued[e] = 1;
  }
  const double reflex_eps = 1e-9 * h * h * h;
  std::size_t budget = 100 * m.number_of_edges();
  while (!stack.empty() && budget-- > 0) {
    const auto e = stack.back();
    stack.pop_back();
    queued[e] = 0;
    const HI hh = m.halfedge(e);
    const HI ho = m.opposite(hh);
    const VI a = m.source(hh), b = m.target(hh), c = m.target(m.next(hh)), d = m.target(m.next(ho));
    const V3 pa = pos(a), pb = pos(b), pc = pos(c), pd = pos(d);
    if (!(det3(pb - pa, pc - pa, pd - pa) > reflex_eps)) continue;
    if (c == d || m.halfedge(c, d) != Surface_mesh::null_halfedge()) continue;
    if (!(det3(pa, pd, pc) > min_det && det3(pd, pb, pc) > min_det)) continue;
    const HI around[4] = {m.next(hh), m.prev(hh), m.next(ho), m.prev(ho)};
    CGAL::Euler::flip_edge(hh, m);
    for (HI x : around)
      if (!queued[m.edge(x)]) {
        queued[m.edge(x)] = 1;
        stack.push_back(m.edge(x));
      }
  }

  m.collect_garbage();
  unit.clear();
  for (VI v : m.vertices()) unit.push_back(pos(v));
  tris.clear();
  for (auto f : m.faces()) {
    const HI hh = m.halfedge(f);
    tris.push_back({std::size_t(m.source(hh)), std::size_t(m.target(hh)), std::size_t(m.target(m.next(hh)))});
  }
}

} // namespace internal_shapes

/// Feature anchor points of a creature, in creature_feature_names() order.
inline std::vector<Point_3> creature_anchors(const Creature_params& params) {
  const internal_shapes::Creature_geometry g(params);
  std::vector<Point_3> out;
  for (const auto& a : g.anchors) out.emplace_back(a.x, a.y, a.z);
  return out;
}

/// Meshes the creature described by `params`: a closed, manifold, connected, genus-0, outward-oriented
/// triangle mesh. Deterministic. Throws Algorithm_error if the mesher's result is not such a surface (only
/// possible for unreasonable parameters, e.g. legs touching each other).
inline Surface_mesh make_creature(const Creature_params& params) {
  using namespace internal_shapes;
  using Tr = Mesher_triangulation::type;
  using C2t3 = CGAL::Complex_2_in_triangulation_3<Tr>;
  using GT = Tr::Geom_traits;
  using Tr_point = GT::Point_3;
  using Field = std::function<GT::FT(Tr_point)>;
  using Surface = CGAL::Implicit_surface_3<GT, Field>;

  const Creature_geometry geom(params);
  const Field field = [&geom](Tr_point p) { return geom(V3{p.x(), p.y(), p.z()}); };
  if (!(geom(V3{}) < 0)) throw Algorithm_error("make_creature: the body centre is not inside the creature");

  const double R = geom.bounding_radius;
  Default_random_guard guard(20240611u);
  Tr tr;
  C2t3 c2t3(tr);

  // Seed every part: from each part centre, march along 14 fixed directions to the surface and bisect.
  {
    const double s = 1.0 / std::sqrt(3.0);
    const V3 dirs[14] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {s, s, s},
                         {s, s, -s}, {s, -s, s}, {s, -s, -s}, {-s, s, s}, {-s, s, -s}, {-s, -s, s}, {-s, -s, -s}};
    Tr::Vertex_handle hint;
    std::vector<V3> seeds;
    for (const V3& c : geom.part_centres()) {
      if (!(geom(c) < 0)) continue;
      for (const V3& d : dirs) {
        double lo = 0, hi = 0;
        const double step = 0.01;
        bool found = false;
        for (double t = step; t < 2 * R; t += step) {
          if (geom(c + t * d) > 0) {
            hi = t;
            lo = t - step;
            found = true;
            break;
          }
        }
        if (!found) continue;
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (lo + hi);
          (geom(c + mid * d) > 0 ? hi : lo) = mid;
        }
        const V3 p = c + (0.5 * (lo + hi)) * d;
        // Seeds closer than the target facet size would leave tiny edges that the refinement grades around.
        bool far = true;
        for (const V3& q : seeds) far = far && norm(p - q) > params.facet_size;
        if (!far) continue;
        seeds.push_back(p);
        hint = tr.insert(Tr_point(p.x, p.y, p.z), hint == Tr::Vertex_handle() ? Tr::Cell_handle() : hint->cell());
      }
    }
  }

  const Surface surface(field, GT::Sphere_3(CGAL::ORIGIN, R * R), 1e-6);
  const CGAL::Surface_mesh_default_criteria_3<Tr> criteria(params.facet_angle_deg, params.facet_size,
                                                            params.facet_distance);
  CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_tag(), 0);

  // Deterministic conversion: vertices in triangulation order, facets oriented from the inside cell. Inside
  // and outside cells are found by flood fill from the infinite cells across facets not in the complex.
  std::set<Tr::Cell_handle> outside;
  {
    std::vector<Tr::Cell_handle> stack{tr.infinite_cell()};
    outside.insert(tr.infinite_cell());
    while (!stack.empty()) {
      auto c = stack.back();
      stack.pop_back();
      for (int i = 0; i < 4; ++i) {
        if (c2t3.face_status(c, i) != C2t3::NOT_IN_COMPLEX) continue;
        auto n = c->neighbor(i);
        if (outside.insert(n).second) stack.push_back(n);
      }
    }
  }
  std::map<Tr::Vertex_handle, std::size_t> vindex;
  std::vector<Point_3> points;
  for (auto v = tr.finite_vertices_begin(); v != tr.finite_vertices_end(); ++v) {
    if (!c2t3.is_in_complex(v)) continue;
    vindex.emplace(v, points.size());
    points.emplace_back(v->point().x(), v->point().y(), v->point().z());
  }
  std::vector<std::array<std::size_t, 3>> tris;
  for (auto c = tr.finite_cells_begin(); c != tr.finite_cells_end(); ++c) {
    if (outside.count(c)) continue;
    for (int i = 0; i < 4; ++i) {
      if (c2t3.face_status(c, i) == C2t3::NOT_IN_COMPLEX) continue;
      // Every facet is taken from its inside cell with the same vertex_triple_index convention, so all are
      // oriented alike; whether that is outward is settled below by the sign of the volume.
      tris.push_back({vindex.at(c->vertex(Tr::vertex_triple_index(i, 0))),
                      vindex.at(c->vertex(Tr::vertex_triple_index(i, 1))),
                      vindex.at(c->vertex(Tr::vertex_triple_index(i, 2)))});
    }
  }
  Surface_mesh m = soup_to_mesh(points, tris, "make_creature");
  if (signed_volume(m) < 0) {
    for (auto& t : tris) std::swap(t[1], t[2]);
    m = soup_to_mesh(points, tris, "make_creature");
  }
  check_closed_surface(m, 0, "make_creature");
  return m;
}

/// The first built-in creature (dog-like), make_creature(creature_a_params()).
inline Surface_mesh creature_a() { return make_creature(creature_a_params()); }
/// The second built-in creature (fatter body, long neck, short legs, bent tail), make_creature(creature_b_params()).
inline Surface_mesh creature_b() { return make_creature(creature_b_params()); }

/// Semantic feature correspondence between creature meshes `a` (made from `pa`) and `b` (made from `pb`):
/// for each anchor of creature_anchors() (nose tip, top of head, four feet, tail tip, back, belly, chest, left
/// and right flank), the nearest vertex not already used. Throws Feature_error if a mesh has too few vertices.
inline Feature_correspondence creature_features(const Surface_mesh& a, const Creature_params& pa,
                                                const Surface_mesh& b, const Creature_params& pb) {
  using namespace internal_shapes;
  const auto anchors_a = creature_anchors(pa);
  const auto anchors_b = creature_anchors(pb);
  if (a.number_of_vertices() < anchors_a.size() || b.number_of_vertices() < anchors_b.size() ||
      a.has_garbage() || b.has_garbage())
    throw Feature_error("creature_features: mesh has too few vertices or has garbage");
  std::vector<char> used_a(a.number_of_vertices(), 0), used_b(b.number_of_vertices(), 0);
  Feature_correspondence out;
  for (std::size_t k = 0; k < anchors_a.size(); ++k) {
    const std::size_t s = nearest_unused_vertex(a, to_v3(anchors_a[k]), used_a);
    const std::size_t t = nearest_unused_vertex(b, to_v3(anchors_b[k]), used_b);
    used_a[s] = 1;
    used_b[t] = 1;
    out.push_back({s, t});
  }
  return out;
}

/// creature_features(a, creature_a_params(), b, creature_b_params()): for a = creature_a(), b = creature_b().
inline Feature_correspondence creature_features(const Surface_mesh& a, const Surface_mesh& b) {
  return creature_features(a, creature_a_params(), b, creature_b_params());
}

// ------------------------------------------------------------------------------------------------------------
// Deformed spheres
// ------------------------------------------------------------------------------------------------------------

/// A randomly deformed sphere with about `target_vertices` vertices (at least 12).
///
/// The base is a geodesic icosphere of frequency n = round(sqrt((target_vertices - 2) / 10)), i.e. 10 n^2 + 2
/// vertices. If `irregular`, its vertices are jittered on the sphere, a seed-dependent fraction (up to 40%, varying
/// over the sphere) of them is removed by edge collapses, and edges are flipped towards the convex hull of the
/// remaining points (a spherical Delaunay triangulation), so different seeds give different connectivity and
/// vertex counts (see internal_shapes::irregular_sphere).
/// The unit-sphere mesh is then deformed radially by r(u) = 1 + sum of 3..6 Gaussian bumps and dents (so it stays
/// star-shaped from the origin and free of self-intersections), scaled anisotropically by factors in [0.75, 1.3]
/// and rotated. Closed, manifold, genus 0, outward oriented, deterministic per (seed, target, irregular).
inline Surface_mesh make_deformed_sphere(unsigned seed, std::size_t target_vertices, bool irregular) {
  using namespace internal_shapes;
  std::mt19937 rng(seed);
  const double tv = static_cast<double>(std::max<std::size_t>(target_vertices, 12));
  const std::size_t n = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(std::sqrt((tv - 2.0) / 10.0))));
  std::vector<V3> unit;
  std::vector<std::array<std::size_t, 3>> tris;
  geodesic_sphere(n, unit, tris);

  if (irregular) irregular_sphere(n, rng, unit, tris);

  // Radial deformation.
  const int bumps = 3 + static_cast<int>(rng() % 4u);
  std::vector<V3> centres;
  std::vector<double> amps, widths;
  double neg = 0;
  for (int k = 0; k < bumps; ++k) {
    centres.push_back(random_unit(rng));
    amps.push_back(uniform(rng, -0.3, 0.45));
    widths.push_back(uniform(rng, 0.35, 0.75));
    if (amps.back() < 0) neg -= amps.back();
  }
  if (neg > 0.5)
    for (double& a : amps)
      if (a < 0) a *= 0.5 / neg;
  const V3 scale{uniform(rng, 0.75, 1.3), uniform(rng, 0.75, 1.3), uniform(rng, 0.75, 1.3)};
  // Random rotation from a random unit quaternion-like frame (Gram-Schmidt of two random directions).
  const V3 e0 = random_unit(rng);
  V3 e1 = random_unit(rng);
  e1 = e1 - dot(e1, e0) * e0;
  if (norm(e1) < 1e-3) e1 = normalized(cross(e0, std::abs(e0.x) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0}));
  e1 = normalized(e1);
  const V3 e2 = cross(e0, e1);

  std::vector<Point_3> points;
  points.reserve(unit.size());
  for (const V3& u : unit) {
    double r = 1.0;
    for (int k = 0; k < bumps; ++k)
      r += amps[k] * std::exp(-(1.0 - dot(u, centres[k])) / (widths[k] * widths[k]));
    const V3 q{scale.x * r * u.x, scale.y * r * u.y, scale.z * r * u.z};
    const V3 p = q.x * e0 + q.y * e1 + q.z * e2;  // rotation (e0, e1, e2 is right-handed)
    points.emplace_back(p.x, p.y, p.z);
  }
  Surface_mesh m = soup_to_mesh(points, tris, "make_deformed_sphere");
  if (signed_volume(m) < 0) {
    for (auto& t : tris) std::swap(t[1], t[2]);
    m = soup_to_mesh(points, tris, "make_deformed_sphere");
  }
  check_closed_surface(m, 0, "make_deformed_sphere");
  return m;
}

/// `count` feature pairs between `a` and `b`, all sources distinct and all targets distinct.
/// Random, well-spread unit directions d_k are drawn from std::mt19937(seed); on each mesh, feature k is the
/// unused vertex whose direction from the mesh's vertex centroid is closest to d_k, so features roughly
/// correspond geometrically. If `permute`, the targets are additionally permuted by a random permutation other
/// than the identity (a "twisted" correspondence). Throws Feature_error if a mesh has fewer than `count`
/// vertices or has garbage.
inline Feature_correspondence random_features(const Surface_mesh& a, const Surface_mesh& b, std::size_t count,
                                              unsigned seed, bool permute) {
  using namespace internal_shapes;
  if (a.number_of_vertices() < count || b.number_of_vertices() < count || a.has_garbage() || b.has_garbage())
    throw Feature_error("random_features: " + std::to_string(count) + " features requested but a mesh has only " +
                        std::to_string(std::min(a.number_of_vertices(), b.number_of_vertices())) + " vertices");
  std::mt19937 rng(seed);
  // Well-spread directions: reject candidates closer than a spacing derived from the count (relaxed when stuck).
  std::vector<V3> dirs;
  double min_angle = 0.6 * std::sqrt(4.0 * 3.14159265358979323846 / std::max<std::size_t>(count, 1));
  int failures = 0;
  while (dirs.size() < count) {
    const V3 d = random_unit(rng);
    bool ok = true;
    for (const V3& e : dirs)
      if (std::acos(std::max(-1.0, std::min(1.0, dot(d, e)))) < min_angle) {
        ok = false;
        break;
      }
    if (ok) {
      dirs.push_back(d);
    } else if (++failures > 200) {
      min_angle *= 0.8;
      failures = 0;
    }
  }
  auto pick = [&dirs](const Surface_mesh& m) {
    V3 c{};
    for (auto v : m.vertices()) c = c + to_v3(m.point(v));
    c = (1.0 / static_cast<double>(m.number_of_vertices())) * c;
    std::vector<V3> dir_of(m.number_of_vertices());
    for (auto v : m.vertices()) dir_of[v] = normalized(to_v3(m.point(v)) - c);
    std::vector<char> used(m.number_of_vertices(), 0);
    std::vector<std::size_t> out;
    for (const V3& d : dirs) {
      std::size_t best = 0;
      double best_dot = -std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < dir_of.size(); ++i)
        if (!used[i] && dot(dir_of[i], d) > best_dot) {
          best_dot = dot(dir_of[i], d);
          best = i;
        }
      used[best] = 1;
      out.push_back(best);
    }
    return out;
  };
  const std::vector<std::size_t> sa = pick(a);
  std::vector<std::size_t> sb = pick(b);
  if (permute && count >= 2) {
    std::vector<std::size_t> perm(count);
    for (std::size_t i = 0; i < count; ++i) perm[i] = i;
    bool identity = true;
    while (identity) {
      for (std::size_t i = count - 1; i > 0; --i) std::swap(perm[i], perm[rng() % (i + 1)]);  // Fisher-Yates
      identity = true;
      for (std::size_t i = 0; i < count; ++i) identity = identity && perm[i] == i;
    }
    std::vector<std::size_t> permuted(count);
    for (std::size_t i = 0; i < count; ++i) permuted[i] = sb[perm[i]];
    sb = permuted;
  }
  Feature_correspondence out;
  for (std::size_t k = 0; k < count; ++k) out.push_back({sa[k], sb[k]});
  return out;
}

// ------------------------------------------------------------------------------------------------------------
// Torus (genus 1), for genus-mismatch tests
// ------------------------------------------------------------------------------------------------------------

/// A torus around the z axis with major radius R, minor radius r < R, nu x nv vertices (nu, nv >= 3).
/// Closed, manifold, genus 1, outward oriented.
inline Surface_mesh make_torus(double major_radius = 1.0, double minor_radius = 0.35, std::size_t nu = 48,
                               std::size_t nv = 24) {
  if (!(minor_radius > 0 && minor_radius < major_radius) || nu < 3 || nv < 3)
    throw Input_error("make_torus: need 0 < minor_radius < major_radius and nu, nv >= 3");
  const double two_pi = 2.0 * 3.14159265358979323846;
  std::vector<Point_3> points;
  for (std::size_t i = 0; i < nu; ++i)
    for (std::size_t j = 0; j < nv; ++j) {
      const double u = two_pi * static_cast<double>(i) / static_cast<double>(nu);
      const double v = two_pi * static_cast<double>(j) / static_cast<double>(nv);
      const double rr = major_radius + minor_radius * std::cos(v);
      points.emplace_back(rr * std::cos(u), rr * std::sin(u), minor_radius * std::sin(v));
    }
  std::vector<std::array<std::size_t, 3>> tris;
  auto id = [nu, nv](std::size_t i, std::size_t j) { return (i % nu) * nv + (j % nv); };
  for (std::size_t i = 0; i < nu; ++i)
    for (std::size_t j = 0; j < nv; ++j) {
      tris.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      tris.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  Surface_mesh m = internal_shapes::soup_to_mesh(points, tris, "make_torus");
  if (internal_shapes::signed_volume(m) < 0) {
    for (auto& t : tris) std::swap(t[1], t[2]);
    m = internal_shapes::soup_to_mesh(points, tris, "make_torus");
  }
  internal_shapes::check_closed_surface(m, 1, "make_torus");
  return m;
}

} // namespace shapes
} // namespace crossparam

#endif // CROSSPARAM_EXAMPLES_SUPPORT_SHAPES_H

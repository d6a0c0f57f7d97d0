// SPDX-License-Identifier: GPL-3.0-or-later
// The wider accuracy bench: cases built in code from the meshes and correspondences of ../shared/data (nothing
// is copied into the repository), plus the six cases of ../shared/bench as they are. Shared by
// benchmark/bench_accuracy.cpp and the tests that pin the bench's aggregate.
//
// Families (each case names its family before the first '/'):
//   - bench/NAME: the six cases of ../shared/bench, read from their files (features.txt, truth/).
//   - shrec/A_B: every pair of the five SHREC'07 four-legged animals (landmarks/shrec07_fourleg), lower number
//     as the source. Their NNN.vts files list 21 corresponding landmarks: the odd-numbered lines (1, 3, ..., 21)
//     are the features, the even-numbered ones are scored, as in bench/shrec_381_382 and bench/shrec_383_385
//     (those two pairs are the bench cases, so they are not built twice).
//   - hand/loo_K: the two hands (landmarks/hand_plain_vulcan), five pinned fingertips each; leave one out:
//     the other four are the features and landmark K (1-based) is scored.
//   - tosca/A_B_kK: every pose pair of the wolves (0, 1, 2) and horses (0, 5, 7) of correspondence/tosca. Poses
//     of one class share their triangles, so vertex i of the source corresponds to vertex i of the target:
//     dense truth. K features (6, 12 or 30) are placed by geodesic farthest-point sampling on the source and
//     paired with the vertex of the target nearest to the same index. The target is remeshed isotropically
//     first (as the bench/ tosca cases are), so that the two meshes do not share their triangles: the truth of
//     source vertex i is then the position of target vertex i before remeshing, on the target's surface.
//   - cross/A_B_kK: the cross-class pairs of correspondence/tosca/cross_class (dog0 with wolf0, horse0 and
//     cat0, both ways): different animals of different resolutions (wolf0 4344 vertices, horse0 19248, dog0
//     25290, cat0 27894) with BeCoS's dense template correspondence (a target face and barycentric weights per
//     source vertex) as the truth. dog0 and cat0 have two small holes each, closed by CGAL's hole
//     triangulation (no vertex added, the files' vertex numbering kept). K features by geodesic farthest-point
//     sampling on the source, each paired with the corner of its truth face of largest weight.
//
// The error of a scored point is |F(v) - truth(v)| / sqrt(area of the target), as in test_map's Shared tests.
#ifndef CROSSPARAM_TEST_WIDE_CASES_H
#define CROSSPARAM_TEST_WIDE_CASES_H

#include <crossparam/cross_parameterization.h>
#include <crossparam/errors.h>
#include <crossparam/io.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <queue>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace wide_bench {

using crossparam::Feature_correspondence;
using crossparam::Point_3;
using crossparam::Surface_mesh;
namespace fs = std::filesystem;

/// Feature counts of the generated tosca cases: few, the default, many.
inline const std::vector<std::size_t>& tosca_feature_counts() {
  static const std::vector<std::size_t> k{6, 12, 30};
  return k;
}
/// The SHREC'07 four-legged models.
inline const std::vector<int>& shrec_models() {
  static const std::vector<int> m{381, 382, 383, 384, 385};
  return m;
}
/// Poses per TOSCA class used (same connectivity within a class).
inline const std::vector<std::pair<std::string, std::vector<int>>>& tosca_classes() {
  static const std::vector<std::pair<std::string, std::vector<int>>> c{{"wolf", {0, 1, 2}}, {"horse", {0, 5, 7}}};
  return c;
}
/// Target edge length of the remeshed tosca targets over the input's mean edge length, per class (those of
/// bench/wolf0_wolf2 and bench/horse0_horse7: coarser than the source, as a user's second mesh would be).
inline double tosca_edge_factor(const std::string& cls) { return cls == "horse" ? 1.6 : 1.3; }
/// Passes of the isotropic remeshing of the tosca targets.
constexpr unsigned tosca_remeshing_iterations = 3;
/// The cross-class pairs (source, target) of correspondence/tosca/cross_class.
inline const std::vector<std::pair<std::string, std::string>>& cross_class_pairs() {
  static const std::vector<std::pair<std::string, std::string>> p{
      {"dog0", "wolf0"}, {"wolf0", "dog0"}, {"dog0", "horse0"}, {"horse0", "dog0"}, {"dog0", "cat0"}, {"cat0", "dog0"}};
  return p;
}
/// Features of the cross-class cases: the tosca cases' default count.
constexpr std::size_t cross_class_features = 12;
/// The pinned fingertips of each hand.
constexpr std::size_t hand_landmarks = 5;

/// The shared data: the environment variable CROSSPARAM_SHARED_DIR if set, else the directory the build names.
inline fs::path shared_dir() {
  const char* env = std::getenv("CROSSPARAM_SHARED_DIR");
  return fs::path(env && *env ? env : CROSSPARAM_SHARED_DIR);
}
inline fs::path data_dir() { return shared_dir() / "data"; }
inline fs::path bench_dir() { return shared_dir() / "bench"; }

/// Every case of the wider bench, in a fixed order.
inline std::vector<std::string> names() {
  std::vector<std::string> out;
  for (const char* b : {"horse0_horse7", "lion_cat", "shrec_381_382", "shrec_383_385", "wolf0_wolf2", "yang_cat_horse"})
    out.push_back(std::string("bench/") + b);
  const std::vector<int>& m = shrec_models();
  for (std::size_t i = 0; i < m.size(); ++i)
    for (std::size_t j = i + 1; j < m.size(); ++j) {
      const std::string pair = std::to_string(m[i]) + "_" + std::to_string(m[j]);
      if (pair != "381_382" && pair != "383_385") out.push_back("shrec/" + pair);
    }
  for (std::size_t k = 1; k <= hand_landmarks; ++k) out.push_back("hand/loo_" + std::to_string(k));
  for (const auto& [cls, poses] : tosca_classes())
    for (std::size_t i = 0; i < poses.size(); ++i)
      for (std::size_t j = i + 1; j < poses.size(); ++j)
        for (std::size_t k : tosca_feature_counts())
          out.push_back("tosca/" + cls + std::to_string(poses[i]) + "_" + cls + std::to_string(poses[j]) + "_k" +
                        std::to_string(k));
  for (const auto& [a, b] : cross_class_pairs())
    out.push_back("cross/" + a + "_" + b + "_k" + std::to_string(cross_class_features));
  return out;
}

/// The family of a case: the part of its name before '/'.
inline std::string family(const std::string& name) { return name.substr(0, name.find('/')); }

/// One case, loaded: the meshes as given, the features, and the truth.
struct Case {
  std::string name;
  Surface_mesh source, target;
  Feature_correspondence features;
  /// Dense truth: for every source vertex its true position on the target (empty for landmark cases).
  std::vector<Point_3> dense;
  /// Landmark truth: pairs (source vertex, target vertex) that correspond and are not features.
  std::vector<std::pair<std::size_t, std::size_t>> landmarks;
  bool is_dense() const { return !dense.empty(); }
};

inline Point_3 point(const Surface_mesh& m, std::size_t v) {
  return m.point(Surface_mesh::Vertex_index(Surface_mesh::size_type(v)));
}

/// The vertex indices of a SHREC'07 .vts file (one `index x y z` line per landmark), in file order.
inline std::vector<std::size_t> read_vts(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::size_t> out;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::size_t v;
    if (s >> v) out.push_back(v);
  }
  return out;
}

/// One vertex index per line.
inline std::vector<std::size_t> read_indices(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::size_t> out;
  std::size_t v;
  while (in >> v) out.push_back(v);
  return out;
}

/// K vertices of `m` by geodesic farthest-point sampling (Dijkstra distances along edges): the first is the
/// vertex farthest from vertex 0, each next one the vertex farthest from those chosen. Deterministic.
inline std::vector<std::size_t> farthest_point_sample(const Surface_mesh& m, std::size_t k) {
  const std::size_t n = m.number_of_vertices();
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  using Item = std::pair<double, std::size_t>;
  auto grow = [&](std::size_t from) {
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
    dist[from] = 0;
    q.push({0, from});
    while (!q.empty()) {
      auto [d, v] = q.top();
      q.pop();
      if (d > dist[v]) continue;
      const auto vi = Surface_mesh::Vertex_index(Surface_mesh::size_type(v));
      for (auto w : CGAL::vertices_around_target(m.halfedge(vi), m)) {
        const double dw = d + std::sqrt(CGAL::squared_distance(m.point(vi), m.point(w)));
        if (dw < dist[std::size_t(w)]) {
          dist[std::size_t(w)] = dw;
          q.push({dw, std::size_t(w)});
        }
      }
    }
  };
  auto farthest = [&] { return std::size_t(std::max_element(dist.begin(), dist.end()) - dist.begin()); };
  grow(0);
  std::vector<std::size_t> out{farthest()};
  std::fill(dist.begin(), dist.end(), std::numeric_limits<double>::infinity());
  grow(out[0]);
  while (out.size() < k) {
    out.push_back(farthest());
    grow(out.back());
  }
  return out;
}

/// Reads `path` as it is (not checked to be closed), then closes each hole by CGAL's hole triangulation, which
/// adds faces and no vertex: the file's vertices keep their numbers. Returns the file's faces (vertex indices
/// in file order), empty when the file is absent.
inline std::vector<std::vector<std::size_t>> read_and_close(const fs::path& path, Surface_mesh& m) {
  if (!fs::exists(path)) return {};
  crossparam::Polygon_soup soup = crossparam::read_polygon_soup(path.string());
  std::vector<Point_3> points;
  points.reserve(soup.points.size());
  for (const auto& p : soup.points) points.emplace_back(p[0], p[1], p[2]);
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, soup.polygons, m);
  std::vector<Surface_mesh::Halfedge_index> holes;
  CGAL::Polygon_mesh_processing::extract_boundary_cycles(m, std::back_inserter(holes));
  for (auto h : holes) CGAL::Polygon_mesh_processing::triangulate_hole(m, h, CGAL::Emptyset_iterator());
  return std::move(soup.polygons);
}

/// Case `name`, or nothing when its data is absent (../shared not there).
inline std::optional<Case> load(const std::string& name) {
  Case c;
  c.name = name;
  const std::string fam = family(name), rest = name.substr(name.find('/') + 1);
  auto read = [](const fs::path& p, Surface_mesh& m) {
    if (!fs::exists(p)) return false;
    crossparam::read_triangle_mesh(p.string(), m);
    return true;
  };
  if (fam == "bench") {
    const fs::path d = bench_dir() / rest;
    if (!read(d / "source.off", c.source) || !read(d / "target.off", c.target)) return std::nullopt;
    c.features = crossparam::read_feature_pairs((d / "features.txt").string(), c.source.number_of_vertices(),
                                                c.target.number_of_vertices());
    std::ifstream gt(d / "truth" / "gt_points.txt");
    if (gt) {
      double x, y, z;
      while (gt >> x >> y >> z) c.dense.emplace_back(x, y, z);
    } else {
      const std::vector<std::size_t> a = read_indices(d / "truth" / "eval_source.txt"),
                                     b = read_indices(d / "truth" / "eval_target.txt");
      for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) c.landmarks.emplace_back(a[i], b[i]);
    }
    return c;
  }
  if (fam == "shrec") {
    const fs::path d = data_dir() / "landmarks" / "shrec07_fourleg";
    const std::string a = rest.substr(0, rest.find('_')), b = rest.substr(rest.find('_') + 1);
    if (!read(d / (a + ".off"), c.source) || !read(d / (b + ".off"), c.target)) return std::nullopt;
    const std::vector<std::size_t> la = read_vts(d / (a + ".vts")), lb = read_vts(d / (b + ".vts"));
    // Line i (0-based) is odd-numbered when i is even: a feature; the others are scored.
    for (std::size_t i = 0; i < std::min(la.size(), lb.size()); ++i) {
      if (i % 2 == 0)
        c.features.push_back({la[i], lb[i]});
      else
        c.landmarks.emplace_back(la[i], lb[i]);
    }
    crossparam::validate_feature_pairs(c.features, c.source.number_of_vertices(), c.target.number_of_vertices(), name);
    return c;
  }
  if (fam == "hand") {
    const fs::path d = data_dir() / "landmarks" / "hand_plain_vulcan";
    if (!read(d / "hand_plain.obj", c.source) || !read(d / "hand_vulcan.obj", c.target)) return std::nullopt;
    const std::vector<std::size_t> la = read_indices(d / "hand_plain.pinned"), lb = read_indices(d / "hand_vulcan_0.pinned");
    const std::size_t out = std::stoul(rest.substr(rest.find('_') + 1)) - 1;
    for (std::size_t i = 0; i < std::min(la.size(), lb.size()); ++i) {
      if (i == out)
        c.landmarks.emplace_back(la[i], lb[i]);
      else
        c.features.push_back({la[i], lb[i]});
    }
    return c;
  }
  if (fam == "tosca") {
    const fs::path d = data_dir() / "correspondence" / "tosca";
    const std::size_t u1 = rest.find('_'), u2 = rest.rfind('_');
    const std::string a = rest.substr(0, u1), b = rest.substr(u1 + 1, u2 - u1 - 1);
    const std::size_t k = std::stoul(rest.substr(u2 + 2));
    if (!read(d / (a + ".off"), c.source) || !read(d / (b + ".off"), c.target)) return std::nullopt;
    for (std::size_t v = 0; v < c.target.number_of_vertices(); ++v) c.dense.push_back(point(c.target, v));
    double mean_edge = 0;
    for (auto e : c.target.edges()) mean_edge += std::sqrt(CGAL::Polygon_mesh_processing::squared_edge_length(e, c.target));
    mean_edge /= double(c.target.number_of_edges());
    const std::string cls = a.substr(0, a.find_first_of("0123456789"));
    CGAL::Polygon_mesh_processing::isotropic_remeshing(
        faces(c.target), tosca_edge_factor(cls) * mean_edge, c.target,
        CGAL::parameters::number_of_iterations(tosca_remeshing_iterations));
    c.target.collect_garbage();
    for (std::size_t v : farthest_point_sample(c.source, k)) {
      std::size_t near = 0;
      double best = std::numeric_limits<double>::infinity();
      for (auto w : c.target.vertices()) {
        const double d = CGAL::squared_distance(c.target.point(w), c.dense[v]);
        if (d < best) best = d, near = std::size_t(w);
      }
      c.features.push_back({v, near});
    }
    return c;
  }
  if (fam == "cross") {
    const fs::path d = data_dir() / "correspondence" / "tosca";
    const std::size_t u1 = rest.find('_'), u2 = rest.rfind('_');
    const std::string a = rest.substr(0, u1), b = rest.substr(u1 + 1, u2 - u1 - 1);
    const std::size_t k = std::stoul(rest.substr(u2 + 2));
    const fs::path corr = d / "cross_class" / ("tosca_" + a + "_tosca_" + b + "_corres.txt");
    if (!fs::exists(corr) || read_and_close(d / (a + ".off"), c.source).empty()) return std::nullopt;
    const std::vector<std::vector<std::size_t>> faces = read_and_close(d / (b + ".off"), c.target);
    if (faces.empty()) return std::nullopt;
    // Row v: the target face (0-based, in file order) and the weights of its three corners in the file's order.
    std::ifstream in(corr);
    std::vector<std::size_t> heaviest; // per source vertex, the corner of its truth face of largest weight
    std::size_t f;
    double w[3];
    while (in >> f >> w[0] >> w[1] >> w[2]) {
      if (f >= faces.size() || faces[f].size() != 3) throw crossparam::Input_error(corr.string() + ": bad face index");
      double x = 0, y = 0, z = 0;
      for (int i = 0; i < 3; ++i) {
        const Point_3 p = point(c.target, faces[f][std::size_t(i)]);
        x += w[i] * p.x(), y += w[i] * p.y(), z += w[i] * p.z();
      }
      c.dense.emplace_back(x, y, z);
      heaviest.push_back(faces[f][std::size_t(std::max_element(w, w + 3) - w)]);
    }
    if (c.dense.size() != c.source.number_of_vertices())
      throw crossparam::Input_error(corr.string() + ": not one row per source vertex");
    for (std::size_t v : farthest_point_sample(c.source, k)) c.features.push_back({v, heaviest[v]});
    crossparam::validate_feature_pairs(c.features, c.source.number_of_vertices(), c.target.number_of_vertices(), name);
    return c;
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------------------------
// Scoring
// ---------------------------------------------------------------------------------------------------------

/// One scored point.
struct Scored {
  std::size_t source_vertex = 0;
  std::size_t target_vertex = 0; ///< the true partner (landmark cases; the same index for dense ones)
  Point_3 image, truth;
  double error = 0;    ///< of the map, over sqrt(target area)
  double baseline = 0; ///< of the nearest target point to the source vertex
};

/// The outcome of one case.
struct Outcome {
  bool ok = false;
  bool dense = false;  ///< dense truth (else held-out landmarks)
  std::string message; ///< the exception's, when the map failed
  std::size_t source_vertices = 0, target_vertices = 0, features = 0, protrusion_features = 0;
  double mean = 0, median = 0, max = 0;
  double baseline_mean = 0, baseline_max = 0; ///< nearest target point to each source point, as given
  double aligned_mean = 0;                    ///< the same after a similarity fitted to the features
  double seconds = 0;
  double descriptor_mismatch = 0; ///< of the map, over the case's features (no truth needed)
  crossparam::Cross_parameterization_statistics stats;
  Feature_correspondence map_features; ///< the map's features: the case's, then the protrusion features added
  std::vector<Scored> points;
};

/// The similarity (scale, rotation, translation) taking the source features onto the target's in the least
/// squares sense (Umeyama 1991), applied to p.
struct Similarity {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double s = 1;
  Point_3 operator()(const Point_3& p) const {
    const Eigen::Vector3d q = s * (R * Eigen::Vector3d(p.x(), p.y(), p.z())) + t;
    return Point_3(q.x(), q.y(), q.z());
  }
};

inline Similarity fit_similarity(const Case& c) {
  Similarity out;
  const std::size_t n = c.features.size();
  if (n < 3) return out;
  Eigen::Matrix3Xd A(3, n), B(3, n);
  for (std::size_t i = 0; i < n; ++i) {
    const Point_3 p = point(c.source, c.features[i].source), q = point(c.target, c.features[i].target);
    A.col(Eigen::Index(i)) << p.x(), p.y(), p.z();
    B.col(Eigen::Index(i)) << q.x(), q.y(), q.z();
  }
  const Eigen::Vector3d ma = A.rowwise().mean(), mb = B.rowwise().mean();
  A.colwise() -= ma;
  B.colwise() -= mb;
  const Eigen::Matrix3d S = B * A.transpose() / double(n);
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) D(2, 2) = -1;
  out.R = svd.matrixU() * D * svd.matrixV().transpose();
  const double var = A.squaredNorm() / double(n);
  out.s = var > 0 ? (svd.singularValues().asDiagonal() * D).trace() / var : 1;
  out.t = mb - out.s * out.R * ma;
  return out;
}

/// Runs the map on a copy of case c with the given named parameters and scores it.
template <class NP = CGAL::parameters::Default_named_parameters>
Outcome evaluate(const Case& c, const NP& np = CGAL::parameters::default_values()) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  Outcome o;
  Surface_mesh s = c.source, t = c.target;
  const Surface_mesh& t0 = c.target;
  o.source_vertices = s.number_of_vertices();
  o.target_vertices = t.number_of_vertices();
  o.features = c.features.size();
  o.dense = c.is_dense();
  const double norm = std::sqrt(PMP::area(t0));

  // The baselines: nearest target point to each scored source point, as given and after the features'
  // similarity.
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<Surface_mesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<crossparam::Kernel, Primitive>>;
  Tree tree(faces(t0).first, faces(t0).second, t0);
  tree.accelerate_distance_queries();
  const Similarity align = fit_similarity(c);
  std::vector<std::pair<std::size_t, Point_3>> scored; // source vertex, truth
  std::vector<std::size_t> partner;
  if (c.is_dense()) {
    for (std::size_t v = 0; v < c.dense.size(); ++v) {
      scored.emplace_back(v, c.dense[v]);
      partner.push_back(v);
    }
  } else {
    for (const auto& [a, b] : c.landmarks) {
      scored.emplace_back(a, point(t0, b));
      partner.push_back(b);
    }
  }

  const auto start = std::chrono::steady_clock::now();
  try {
    crossparam::Cross_parameterization<Surface_mesh, Surface_mesh> cp(s, t, c.features, np);
    o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    o.stats = cp.statistics();
    o.protrusion_features = o.stats.protrusion_features;
    o.map_features = cp.features();
    o.descriptor_mismatch = cp.descriptor_mismatch(c.features.size());
    std::vector<std::array<Surface_mesh::Vertex_index, 3>> tri;
    for (auto f : t0.faces()) {
      std::array<Surface_mesh::Vertex_index, 3> a;
      int i = 0;
      for (auto v : CGAL::vertices_around_face(t0.halfedge(f), t0)) a[i++] = v;
      tri.push_back(a);
    }
    std::vector<double> errors, base;
    for (std::size_t i = 0; i < scored.size(); ++i) {
      const auto& [v, truth] = scored[i];
      const crossparam::Input_location l = cp.source_vertex_to_target_input(v);
      double x = 0, y = 0, z = 0;
      for (int j = 0; j < 3; ++j) {
        const Point_3& p = t0.point(tri[l.face][j]);
        x += l.b[j] * p.x(), y += l.b[j] * p.y(), z += l.b[j] * p.z();
      }
      Scored r;
      r.source_vertex = v;
      r.target_vertex = partner[i];
      r.image = Point_3(x, y, z);
      r.truth = truth;
      r.error = std::sqrt(CGAL::squared_distance(r.image, truth)) / norm;
      const Point_3 sp = point(c.source, v);
      r.baseline = std::sqrt(CGAL::squared_distance(tree.closest_point(sp), truth)) / norm;
      o.aligned_mean += std::sqrt(CGAL::squared_distance(tree.closest_point(align(sp)), truth)) / norm;
      errors.push_back(r.error);
      base.push_back(r.baseline);
      o.points.push_back(r);
    }
    const double n = double(std::max<std::size_t>(1, errors.size()));
    for (std::size_t i = 0; i < errors.size(); ++i) {
      o.mean += errors[i] / n;
      o.baseline_mean += base[i] / n;
      o.max = std::max(o.max, errors[i]);
      o.baseline_max = std::max(o.baseline_max, base[i]);
    }
    o.aligned_mean /= n;
    if (!errors.empty()) {
      std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
      o.median = errors[errors.size() / 2];
    }
    o.ok = true;
  } catch (const std::exception& e) {
    o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    o.message = e.what();
  }
  return o;
}

/// Mean and worst of the per-case mean errors over a set of outcomes; a failed case counts as worst.
struct Aggregate {
  std::size_t cases = 0, failed = 0;
  double mean = 0, worst = 0, mean_of_max = 0, baseline_mean = 0;
  std::string worst_case;
};

inline Aggregate aggregate(const std::vector<std::pair<std::string, Outcome>>& r) {
  Aggregate a;
  for (const auto& [name, o] : r) {
    ++a.cases;
    if (!o.ok) {
      ++a.failed;
      a.worst = std::numeric_limits<double>::infinity();
      a.worst_case = name;
      continue;
    }
    a.mean += o.mean;
    a.mean_of_max += o.max;
    a.baseline_mean += o.baseline_mean;
    if (o.mean > a.worst) {
      a.worst = o.mean;
      a.worst_case = name;
    }
  }
  const std::size_t ok = a.cases - a.failed;
  if (ok > 0) {
    a.mean /= double(ok);
    a.mean_of_max /= double(ok);
    a.baseline_mean /= double(ok);
  }
  return a;
}

} // namespace wide_bench

#endif // CROSSPARAM_TEST_WIDE_CASES_H

// SPDX-License-Identifier: GPL-3.0-or-later
// Shared by the benchmark programs: the remeshing cases, loaded into memory. The cases of a bench directory
// (source.off, target.off, features.txt per case) and cases built here from the meshes of the shared data
// directory: pose pairs with an identity ground truth (features by farthest-point sampling of the source,
// mapped through the truth), the cat and lion reference meshes with their landmarks, a pair whose target is a
// hundred times smaller than its source, and the generated creature pair of the examples.
#ifndef CROSSPARAM_BENCH_CASES_H
#define CROSSPARAM_BENCH_CASES_H

#include <crossparam/io.h>

#include <support/shapes.h>

#include "bench_common.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace bench {

/// One remeshing case: the two meshes and the feature correspondence.
struct Remesh_case {
  std::string name;
  crossparam::Surface_mesh source, target;
  crossparam::Feature_correspondence features;
};

/// A case, built on demand (loading every case first would hold them all in memory).
struct Case_builder {
  std::string name;
  std::function<Remesh_case()> build;
};

/// Features by farthest-point sampling: `k` source vertices, each the farthest (Euclidean) from those chosen
/// before, starting at vertex 0; each mapped to the target vertex of the same index (an identity ground truth:
/// the two meshes share their vertex list).
inline crossparam::Feature_correspondence farthest_point_features(const crossparam::Surface_mesh& m, std::size_t k) {
  const std::size_t n = m.number_of_vertices();
  std::vector<double> d(n, std::numeric_limits<double>::infinity());
  crossparam::Feature_correspondence out;
  std::size_t next = 0;
  for (std::size_t i = 0; i < k && i < n; ++i) {
    out.push_back({next, next});
    const crossparam::Point_3& p = m.point(crossparam::Surface_mesh::Vertex_index(next));
    std::size_t best = 0;
    for (std::size_t j = 0; j < n; ++j) {
      d[j] = std::min(d[j], CGAL::squared_distance(p, m.point(crossparam::Surface_mesh::Vertex_index(j))));
      if (d[j] > d[best]) best = j;
    }
    next = best;
  }
  return out;
}

/// Feature pairs from a file of lines "a b" (0-based vertex indices), `swap`ped to "b a" if asked.
inline crossparam::Feature_correspondence read_index_pairs(const std::filesystem::path& path, bool swap) {
  std::ifstream in(path);
  if (!in) throw crossparam::Input_error("cannot read " + path.string());
  crossparam::Feature_correspondence out;
  for (std::size_t a, b; in >> a >> b;) out.push_back(swap ? crossparam::Feature_pair{b, a} : crossparam::Feature_pair{a, b});
  return out;
}

/// The number of features sampled on the pose pairs: about as many as the bench cases' landmark features.
constexpr std::size_t pose_pair_features = 12;
/// The scale of the target of the size-ratio case, against its source.
constexpr double size_ratio = 0.01;

/// The cases of `bench_dir` (see cases()), then those built from `data_dir` (when it exists) and the
/// generated creature pair.
inline std::vector<Case_builder> remesh_cases(const std::filesystem::path& bench_dir, const std::filesystem::path& data_dir,
                                              const char* program) {
  namespace fs = std::filesystem;
  using crossparam::Surface_mesh;
  std::vector<Case_builder> out;
  for (const fs::path& c : cases(bench_dir, program))
    out.push_back({c.filename().string(), [c] {
                     Remesh_case r{c.filename().string(), {}, {}, {}};
                     crossparam::read_triangle_mesh((c / "source.off").string(), r.source);
                     crossparam::read_triangle_mesh((c / "target.off").string(), r.target);
                     r.features = crossparam::read_feature_pairs((c / "features.txt").string(),
                                                                 r.source.number_of_vertices(), r.target.number_of_vertices());
                     return r;
                   }});
  const fs::path tosca = data_dir / "correspondence" / "tosca", sumner = data_dir / "correspondence" / "sumner_cat_lion";
  auto pose_pair = [&](const std::string& a, const std::string& b) {
    out.push_back({a + "_" + b, [=] {
                     Remesh_case r{a + "_" + b, {}, {}, {}};
                     crossparam::read_triangle_mesh((tosca / (a + ".off")).string(), r.source);
                     crossparam::read_triangle_mesh((tosca / (b + ".off")).string(), r.target);
                     r.features = farthest_point_features(r.source, pose_pair_features);
                     return r;
                   }});
  };
  if (fs::exists(tosca / "wolf1.off")) pose_pair("wolf1", "wolf2");
  if (fs::exists(tosca / "horse5.off")) pose_pair("horse0", "horse5");
  if (fs::exists(sumner / "landmarks.txt")) {
    // landmarks.txt: "cat_vertex lion_vertex" per line.
    out.push_back({"cat_lion", [=] {
                     Remesh_case r{"cat_lion", {}, {}, {}};
                     crossparam::read_triangle_mesh((sumner / "cat-reference.obj").string(), r.source);
                     crossparam::read_triangle_mesh((sumner / "lion-reference.obj").string(), r.target);
                     r.features = read_index_pairs(sumner / "landmarks.txt", false);
                     return r;
                   }});
    out.push_back({"lion_cat_small", [=] {
                     Remesh_case r{"lion_cat_small", {}, {}, {}};
                     crossparam::read_triangle_mesh((sumner / "lion-reference.obj").string(), r.source);
                     crossparam::read_triangle_mesh((sumner / "cat-reference.obj").string(), r.target);
                     for (auto v : r.target.vertices()) {
                       const crossparam::Point_3 p = r.target.point(v);
                       r.target.point(v) = crossparam::Point_3(size_ratio * p.x(), size_ratio * p.y(), size_ratio * p.z());
                     }
                     r.features = read_index_pairs(sumner / "landmarks.txt", true);
                     return r;
                   }});
  }
  out.push_back({"creature_a_b", [] {
                   Remesh_case r{"creature_a_b", crossparam::shapes::creature_a(), crossparam::shapes::creature_b(), {}};
                   r.features = crossparam::shapes::creature_features(r.source, r.target);
                   return r;
                 }});
  return out;
}

} // namespace bench

#endif // CROSSPARAM_BENCH_CASES_H

// SPDX-License-Identifier: GPL-3.0-or-later
// Benchmark of the N-way common connectivity (paper §2.3) on the five four-legged animals of
// bench_multi/fourleg5, with all five meshes and with the first three. Per run, checked by code that does not
// trust the remesher: the N outputs are written as OFF files and read back, and their face lists compared; each
// output against its own input by CGAL's bounded-error Hausdorff distance and the flip rule of the
// verification (remeshing_verification.h). The held-out landmarks (truth/landmarks_eval.txt) are sent through
// the maps: the distance of each landmark's image from its true position, in units of the square root of the
// mesh's area. Prints a Markdown table.
//
// With --wide, the N-way cases built in code from ../shared/data by the wider bench's loader (test/wide_cases.h)
// instead: one source and the targets of that bench's cases with this source, each target as that bench makes
// it (the TOSCA poses remeshed isotropically), one feature row per feature of the source (geodesic farthest-point
// sampling, the same on every case of the source). Scored by the dense truth of each case: the distance of the
// image of every source vertex from its true position on that target, in units of √(target area).
//   - tosca/wolf0_wolf1_wolf2, tosca/horse0_horse5_horse7: the three poses of each class, 12 features;
//   - cross/dog0_wolf0_horse0_cat0: four animals of different classes and resolutions, 12 features.
//
//   bench_multi [CASE_DIR] [TOLERANCE_PERCENT] [MESH_COUNTS] [--construction=refinement|overlay]
//   bench_multi --wide [TOLERANCE_PERCENT] [CASE_FILTER] [--construction=refinement|overlay]
//   (MESH_COUNTS default "3,5"; the construction of each two-mesh remeshing, automatic by default)
#include <crossparam/io.h>
#include <crossparam/multi_remeshing.h>
#include <crossparam/remeshing_verification.h>

#include "../test/wide_cases.h"
#include "bench_common.h"

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <tuple>

using namespace crossparam;
namespace fs = std::filesystem;

namespace {

std::string fmt(double x, int digits = 3) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << x;
  return s.str();
}

/// One N-way case: the meshes (the first is the source), the features, and the truth: held-out landmark rows
/// (one column per mesh), or per other mesh the true position of every source vertex on it (dense).
struct Multi_case {
  std::string name;
  std::vector<Surface_mesh> meshes;
  Multi_feature_correspondence features, landmarks;
  std::vector<std::vector<Point_3>> dense; ///< per mesh, empty for the source
};

void run(const Multi_case& c, double tolerance, Remeshing_construction construction) {
  const std::vector<Surface_mesh>& meshes = c.meshes;
  const std::size_t n = meshes.size();
  std::size_t largest = 0;
  for (const auto& m : meshes) largest = std::max<std::size_t>(largest, m.number_of_vertices());
  const Multi_feature_correspondence& features = c.features;
  const Multi_feature_correspondence& landmarks = c.landmarks;
  const Multi_remesher<Surface_mesh> r(meshes, features,
                                       crossparam::parameters::tolerance(tolerance, crossparam::parameters::remeshing_construction(construction)));
  const Multi_remeshing_statistics& S = r.statistics();
  // One face list: the outputs as files, read back.
  const fs::path tmp = fs::temp_directory_path() / ("crossparam_bench_multi_" + std::to_string(n));
  fs::create_directories(tmp);
  std::vector<Polygon_soup> back;
  for (std::size_t m = 0; m < n; ++m) {
    const std::string p = (tmp / ("compatible_" + std::to_string(m) + ".off")).string();
    write_off(p, r.points(m), r.faces());
    back.push_back(read_polygon_soup(p));
  }
  bool one_face_list = true;
  for (std::size_t m = 1; m < n; ++m)
    one_face_list = one_face_list && back[m].polygons == back[0].polygons && back[m].points.size() == back[0].points.size();
  fs::remove_all(tmp);
  std::vector<Surface_mesh> outs(n);
  for (std::size_t m = 0; m < n; ++m) r.copy_to(m, outs[m]);
  const std::size_t tiling = source_tiling_defects(r.source_face_locations());
  std::cout << "\n### " << c.name << ": " << n << " meshes (source: mesh " << S.source << "), tolerance " << tolerance << "%\n\n";
  std::cout << "one face list (outputs read back from OFF): " << (one_face_list ? "yes" : "NO") << "; "
            << S.output_faces << " faces, " << S.output_vertices << " vertices = "
            << fmt(double(S.output_vertices) / double(largest), 2) << " x the largest input (" << largest
            << "); faces not tiling their source face: " << tiling
            << "; source faces triangulated anew: " << S.retriangulated_faces << " (" << fmt(S.seconds_common, 2)
            << " s); output repair " << fmt(S.seconds_repair, 2) << " s; total " << fmt(S.seconds_total, 1) << " s\n\n";
  std::cout << "| mesh | input vertices | Hausdorff % | flipped (at target folds) | new self-intersecting pairs | bad faces before / after the repair | its remeshing's vertices | "
            << (c.dense.empty() ? "landmark" : "dense") << " error mean | max | map s | fit s | verified |\n";
  std::cout << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t m = 0; m < n; ++m) {
    if (m == S.source) {
      const Remeshing_verification v = verify_compatible_remeshing(meshes[m], meshes[m], outs[m], outs[m], tolerance);
      std::cout << "| " << m << " (source) | " << meshes[m].number_of_vertices() << " | " << fmt(v.hausdorff_source, 6)
                << " | " << v.flipped_faces << " | " << v.new_self_intersections << " | " << S.bad_faces_before_repair[m] << " / "
                << S.bad_faces_after_repair[m] << " | - | - | - | - | - | " << (v.valid && tiling == 0 ? "yes" : "no") << " |\n";
      continue;
    }
    const Remeshing_verification v = verify_compatible_remeshing(meshes[S.source], meshes[m], outs[S.source], outs[m], tolerance);
    const double unit = std::sqrt(CGAL::Polygon_mesh_processing::area(meshes[m]));
    const auto& cp = r.map(m);
    double sum = 0, mx = 0;
    std::size_t count = 0;
    auto score = [&](std::size_t v, const Point_3& t) {
      const std::array<double, 3> q = cp.input_point(Mesh_side::target, cp.source_vertex_to_target_input(v));
      const double d = std::sqrt(CGAL::square(q[0] - t.x()) + CGAL::square(q[1] - t.y()) + CGAL::square(q[2] - t.z())) / unit;
      sum += d, mx = std::max(mx, d), ++count;
    };
    for (const auto& row : landmarks)
      score(row[S.source], meshes[m].point(Surface_mesh::Vertex_index(Surface_mesh::size_type(row[m]))));
    if (!c.dense.empty())
      for (std::size_t v = 0; v < c.dense[m].size(); ++v) score(v, c.dense[m][v]);
    std::cout << "| " << m << " | " << meshes[m].number_of_vertices() << " | " << fmt(v.hausdorff_target) << " | "
              << v.flipped_faces << " (" << v.flipped_at_target_folds << ") | " << v.new_self_intersections << " | "
              << S.bad_faces_before_repair[m] << " / " << S.bad_faces_after_repair[m] << " | " << S.fitted_vertices[m] << " | " << fmt(sum / double(std::max<std::size_t>(count, 1)), 4) << " | "
              << fmt(mx, 4) << " | " << fmt(S.seconds_map[m], 1) << " | " << fmt(S.seconds_fit[m], 1) << " | "
              << (v.valid ? "yes" : "no: " + v.message) << " |\n";
  }
  std::cout << std::flush;
}

Multi_case fourleg(const fs::path& dir, std::size_t n) {
  Multi_case c;
  c.name = dir.filename().string() + " (first " + std::to_string(n) + ")";
  c.meshes.resize(n);
  std::vector<std::size_t> counts, columns;
  for (std::size_t m = 0; m < n; ++m) {
    read_triangle_mesh((dir / ("mesh_" + std::to_string(m) + ".off")).string(), c.meshes[m]);
    counts.push_back(c.meshes[m].number_of_vertices()), columns.push_back(m);
  }
  c.features = read_multi_features((dir / "features.txt").string(), counts, columns);
  c.landmarks = read_multi_features((dir / "truth" / "landmarks_eval.txt").string(), counts, columns);
  return c;
}

/// The name of an N-way case of the wider bench: FAMILY/ and its meshes, source first.
std::string case_name(const std::string& family, const std::vector<std::string>& names) {
  std::string out = family + "/";
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? "_" : "") + names[i];
  return out;
}

/// An N-way case of the wider bench, named by case_name(); the two-mesh cases
/// "FAMILY/SOURCE_TARGET[_k12]" give the meshes, the features and the truth. Nothing when the data is absent.
std::optional<Multi_case> wide_case(const std::string& family, const std::vector<std::string>& names, const std::string& suffix) {
  Multi_case c;
  c.name = case_name(family, names);
  c.dense.resize(1);
  for (std::size_t i = 1; i < names.size(); ++i) {
    std::optional<wide_bench::Case> w = wide_bench::load(family + "/" + names[0] + "_" + names[i] + suffix);
    if (!w) return std::nullopt;
    if (i == 1) {
      c.meshes.push_back(std::move(w->source));
      for (const Feature_pair& f : w->features) c.features.push_back({f.source});
    }
    if (w->features.size() != c.features.size()) throw Input_error(c.name + ": the cases' features differ");
    for (std::size_t k = 0; k < c.features.size(); ++k) {
      if (w->features[k].source != c.features[k][0]) throw Input_error(c.name + ": the cases' features differ");
      c.features[k].push_back(w->features[k].target);
    }
    c.meshes.push_back(std::move(w->target));
    c.dense.push_back(std::move(w->dense));
  }
  return c;
}

} // namespace

int main(int argc_given, char** argv_given) try {
  Remeshing_construction construction = Remeshing_construction::automatic;
  std::vector<char*> args;
  for (int i = 0; i < argc_given; ++i)
    if (!bench::construction_flag(argv_given[i], construction)) args.push_back(argv_given[i]);
  const int argc = int(args.size());
  char** argv = args.data();
  if (argc > 1 && std::string(argv[1]) == "--wide") {
    const double tolerance = argc > 2 ? std::stod(argv[2]) : 0.5;
    const std::string filter = argc > 3 ? argv[3] : "";
    const std::vector<std::tuple<std::string, std::vector<std::string>, std::string>> cases{
        {"tosca", {"wolf0", "wolf1", "wolf2"}, "_k12"},
        {"tosca", {"horse0", "horse5", "horse7"}, "_k12"},
        {"cross", {"dog0", "wolf0", "horse0", "cat0"}, "_k12"}};
    std::cout << "## N-way common connectivity: the wider bench\n";
    for (const auto& [family, names, suffix] : cases) {
      const std::string name = case_name(family, names);
      if (name.find(filter) == std::string::npos) continue;
      const std::optional<Multi_case> c = wide_case(family, names, suffix);
      if (!c) {
        std::cout << name << ": no data, skipped\n";
        continue;
      }
      run(*c, tolerance, construction);
    }
    return 0;
  }
  const fs::path dir = argc > 1 ? fs::path(argv[1]) : fs::path(CROSSPARAM_SHARED_DIR) / "bench_multi" / "fourleg5";
  const double tolerance = argc > 2 ? std::stod(argv[2]) : 0.5;
  if (!fs::exists(dir / "features.txt")) {
    std::cout << "bench_multi: no case at " << dir << ", skipped\n";
    return 0;
  }
  std::cout << "## N-way common connectivity: " << dir.filename().string() << "\n";
  std::stringstream counts(argc > 3 ? argv[3] : "3,5");
  for (std::string n; std::getline(counts, n, ',');) run(fourleg(dir, std::stoul(n)), tolerance, construction);
  return 0;
} catch (const std::exception& e) {
  std::cerr << "bench_multi: " << e.what() << "\n";
  return 1;
}

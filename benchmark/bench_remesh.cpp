// SPDX-License-Identifier: GPL-3.0-or-later
// Compatible remeshing (paper §5) on the ../shared/bench cases: a table in the style of the paper's Table 2
// (input sizes, output size, L2 error and PSNR from e(v), time), plus the independent two-sided Hausdorff
// distance of the target-shaped output.
// Usage: bench_remesh [BENCH_DIR] [TOLERANCES] [CASE_FILTER] (BENCH_DIR ../shared/bench_genus: genus > 0)
//        bench_remesh --wide [TOLERANCES] [CASE_FILTER]: the cases of the wider bench (test/wide_cases.h) that
//        are not ../shared/bench's (shrec, hand and tosca pairs), e.g. CASE_FILTER "tosca/" or "_k12".
// TOLERANCES: one or several percentages separated by commas, e.g. 1,0.5,0.2,0.1 (default 0.5).
// --straighten-paths (anywhere): the maps' layouts with their paths straightened (parameters::straighten_paths).
// --map-smoothing (anywhere): the maps smoothed as maps after the paper's smoothing (parameters::map_smoothing).
// --no-retry (anywhere): no second attempt with the map smoothing where a remeshing fails the strict checks.
// --construction=refinement|overlay (anywhere): the remesher's construction (parameters::remeshing_construction;
// default automatic). The column "built" says which one made each row's output.
#include <crossparam/compatible_remeshing.h>
#include <crossparam/io.h>
#include <crossparam/remeshing_verification.h>

#include "bench_common.h"
#include "../test/wide_cases.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <vector>
#include <string>

using namespace crossparam;
namespace fs = std::filesystem;

namespace {
/// One case to remesh: its name, the meshes as given and the features.
struct Remesh_case {
  std::string name;
  Surface_mesh source, target;
  Feature_correspondence features;
};

/// Whether the maps' layouts have their paths straightened (--straighten-paths).
bool straighten = false;
/// Whether the maps are smoothed as maps (--map-smoothing).
bool smooth_map = false;
/// Whether a remeshing that fails the strict checks is done again with the map smoothing (not --no-retry).
bool retry_with_map_smoothing = true;
/// The remesher's construction (--construction=...).
Remeshing_construction construction = Remeshing_construction::automatic;

/// One attempt at a case: the map, the remeshing, the independent verification.
struct Attempt {
  std::unique_ptr<Surface_mesh> s, t; // the map refines its inputs and refers to them
  std::unique_ptr<Cross_parameterization<Surface_mesh, Surface_mesh>> map;
  std::unique_ptr<Compatible_remesher<Surface_mesh, Surface_mesh>> remesher;
  Remeshing_verification v;
  double seconds = 0; ///< map and remeshing
};

/// `global_steps`: those of the map smoothing (the second attempt makes the local steps alone, as the CLI does).
Attempt attempt(const Remesh_case& c, double tol, bool with_map_smoothing, bool global_steps = true) {
  Attempt a;
  const auto t_start = std::chrono::steady_clock::now();
  a.s = std::make_unique<Surface_mesh>(c.source);
  a.t = std::make_unique<Surface_mesh>(c.target);
  a.map = std::make_unique<Cross_parameterization<Surface_mesh, Surface_mesh>>(
      *a.s, *a.t, c.features,
      crossparam::parameters::straighten_paths(straighten, crossparam::parameters::map_smoothing(with_map_smoothing,
                                                   crossparam::parameters::map_smoothing_global_steps(global_steps))));
  std::function<void(const std::string&)> say;
  if (std::getenv("CROSSPARAM_VERBOSE")) say = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  namespace p = crossparam::parameters;
  a.remesher = std::make_unique<Compatible_remesher<Surface_mesh, Surface_mesh>>(
      *a.map, p::tolerance(tol, p::progress(say, p::remeshing_construction(construction))));
  a.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  Surface_mesh os, ot;
  a.remesher->copy_to(Mesh_side::source, os);
  a.remesher->copy_to(Mesh_side::target, ot);
  a.v = verify_compatible_remeshing(c.source, c.target, os, ot, tol);
  // The source side, from the faces' places on the source (not in the verifier, which sees the meshes only).
  if (const std::size_t folds = source_tiling_defects(a.remesher->source_face_locations()); folds > 0) {
    a.v.valid = false;
    a.v.message += "; " + std::to_string(folds) + " faces do not tile their input face of the source";
  }
  if (!a.v.valid && std::getenv("CROSSPARAM_VERBOSE")) {
    std::fprintf(stderr, "%s: %s\n", c.name.c_str(), a.v.message.c_str());
    // Where the overlay refused inserts and splits (the places an invalid output's defects usually lie beside).
    const auto& q = a.remesher->statistics().overlay_refused_points;
    for (std::size_t i = 0; i < q.size() && i < 40; ++i)
      std::fprintf(stderr, "%s: overlay refused at (%.6g, %.6g, %.6g)\n", c.name.c_str(), q[i][0], q[i][1], q[i][2]);
  }
  return a;
}

/// One row per tolerance for case `c`: as the CLI's `remesh` does, where the remeshing fails the strict checks
/// and the map was not smoothed as a map, the map and the remeshing again with the map smoothing, kept if that
/// passes (the column "built" then says "map smoothed"; total (s) counts both attempts).
void run(const Remesh_case& c, double tol) {
  const std::size_t ns = c.source.number_of_vertices(), nt = c.target.number_of_vertices();
  Attempt a;
  try {
    a = attempt(c, tol, smooth_map);
  } catch (const Insufficient_features_error& e) { // genus > 0 with too few features: reported, not fatal
    std::printf("| %s | %.3g | %zu/%zu | too few features: %s |\n", c.name.c_str(), tol, ns, nt, e.what());
    return;
  }
  double total = a.seconds;
  bool retried = false;
  if (!a.v.valid && !smooth_map && retry_with_map_smoothing) {
    std::fprintf(stderr, "%s at %.3g %%: invalid (%s); again with the map smoothing\n", c.name.c_str(), tol, a.v.message.c_str());
    Attempt b = attempt(c, tol, true, false);
    total += b.seconds;
    if (b.v.valid) a = std::move(b), retried = true;
  }
  const auto& S = a.remesher->statistics();
  const Remeshing_verification& v = a.v;
  const std::string built = std::string(!S.overlay_used ? "refinement" : S.overlay_refusing_slivers ? "overlay, second" : "overlay") +
                            (retried ? ", map smoothed" : "");
  std::printf("| %s | %.3g | %zu/%zu | %zu | %+.1f%% | %.3f | %.3f | %zu (%zu) | %zu / %.2f | %zu / %zu | %zu / %zu (%zu) | %s | %s | %.2f | %.2f | %.2f |\n",
              c.name.c_str(), tol, ns, nt, S.output_vertices, 100.0 * (double(S.output_vertices) - double(ns)) / double(ns),
              S.l2_error, v.hausdorff_target, v.flipped_faces, v.flipped_at_target_folds, v.faces_above_30, v.normal_deviation_above_30,
              v.creases_output, v.creases_target, v.self_intersections_output, v.self_intersections_target,
              v.new_self_intersections, v.valid ? "yes" : "**no**", built.c_str(),
              a.map->statistics().seconds_total, S.seconds_total, total);
  std::fflush(stdout);
}

std::vector<double> parse_tolerances(const std::string& list) {
  std::vector<double> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) out.push_back(std::atof(item.c_str()));
  return out;
}
} // namespace

int main(int argc_given, char** argv_given) {
  std::vector<char*> args;
  for (int i = 0; i < argc_given; ++i)
    if (std::string(argv_given[i]) == "--straighten-paths")
      straighten = true;
    else if (std::string(argv_given[i]) == "--map-smoothing")
      smooth_map = true;
    else if (std::string(argv_given[i]) == "--no-retry")
      retry_with_map_smoothing = false;
    else if (!bench::construction_flag(argv_given[i], construction))
      args.push_back(argv_given[i]);
  const int argc = int(args.size());
  char** argv = args.data();
  const bool wide = argc > 1 && std::string(argv[1]) == "--wide";
  fs::path dir = argc > 1 && !wide ? fs::path(argv[1]) : fs::path(CROSSPARAM_SHARED_DIR) / "bench";
  const std::vector<double> tolerances = parse_tolerances(argc > 2 ? argv[2] : "0.5");
  const std::string filter = argc > 3 ? argv[3] : "";
  std::printf("compatible remeshing, tolerance in %% of the target's bbox diagonal, one run per case, assertions %s%s%s%s\n\n",
              bench::assertions(), straighten ? "; layout paths straightened" : "", smooth_map ? "; maps smoothed as maps" : "",
              construction == Remeshing_construction::refinement ? "; refinement only"
              : construction == Remeshing_construction::overlay ? "; decimated overlay only" : "");
  std::printf("| case | tol. %% | input sizes (#v) | output size | added | L2 error (%%) | Hausdorff (%%) | flipped (at target folds) | >30°: faces / area %% | creases out / in | self-int. out / in (new) | valid | built | map (s) | remesh (s) | total (s) |\n");
  std::printf("|---|---:|---|---:|---:|---:|---:|---:|---|---|---|---|---|---:|---:|---:|\n");
  if (wide) {
    for (const std::string& name : wide_bench::names()) {
      if (wide_bench::family(name) == "bench" || name.find(filter) == std::string::npos) continue;
      std::optional<wide_bench::Case> w = wide_bench::load(name);
      if (!w) {
        std::printf("| %s | data absent |\n", name.c_str());
        continue;
      }
      const Remesh_case c{name, w->source, w->target, w->features};
      for (const double tol : tolerances) run(c, tol);
    }
    return 0;
  }
  for (const fs::path& d : bench::cases(dir, "bench_remesh")) {
    if (!filter.empty() && d.filename().string().find(filter) == std::string::npos) continue;
    Remesh_case c;
    c.name = d.filename().string();
    read_triangle_mesh((d / "source.off").string(), c.source);
    read_triangle_mesh((d / "target.off").string(), c.target);
    c.features = read_feature_pairs((d / "features.txt").string(), c.source.number_of_vertices(), c.target.number_of_vertices());
    for (const double tol : tolerances) run(c, tol);
  }
  return 0;
}

// SPDX-License-Identifier: GPL-3.0-or-later
// Compatible remeshing (paper §5) on the ../shared/bench cases: a table in the style of the paper's Table 2
// (input sizes, output size, L2 error and PSNR from e(v), time), plus the independent two-sided Hausdorff
// distance of the target-shaped output.
// Usage: bench_remesh [BENCH_DIR] [TOLERANCE_PERCENT] [CASE_FILTER] (BENCH_DIR ../shared/bench_genus: genus > 0)
#include <crossparam/compatible_remeshing.h>
#include <crossparam/io.h>
#include <crossparam/remeshing_verification.h>

#include "bench_common.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

using namespace crossparam;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  fs::path dir = argc > 1 ? fs::path(argv[1]) : fs::path(CROSSPARAM_SHARED_DIR) / "bench";
  const double tol = argc > 2 ? std::atof(argv[2]) : 0.5;
  const std::string filter = argc > 3 ? argv[3] : "";
  const std::vector<fs::path> cases = bench::cases(dir, "bench_remesh");
  std::printf("compatible remeshing, tolerance %.3g%% of the target's bbox diagonal, one run per case, assertions %s\n\n",
              tol, bench::assertions());
  std::printf("| case | input sizes (#v) | output size | added | L2 error (%%) | PSNR | max e(v) (%%) | Hausdorff (%%) | layout splits kept / undone | splits + pseudo flips + fold repair | flipped | normal dev. mean ° / >30° area %% | map (s) | remesh (s) | total (s) | map squeeze s/t |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---|---|---:|---|---:|---:|---:|---|\n");
  for (const fs::path& c : cases) {
    if (!filter.empty() && c.filename().string().find(filter) == std::string::npos) continue;
    Surface_mesh s, t;
    read_triangle_mesh((c / "source.off").string(), s);
    read_triangle_mesh((c / "target.off").string(), t);
    const Surface_mesh s0 = s, t0 = t;
    const std::size_t ns = s.number_of_vertices(), nt = t.number_of_vertices();
    Feature_correspondence f = read_feature_pairs((c / "features.txt").string(), ns, nt);
    const auto t_start = std::chrono::steady_clock::now();
    std::unique_ptr<Cross_parameterization<Surface_mesh, Surface_mesh>> map;
    try {
      map = std::make_unique<Cross_parameterization<Surface_mesh, Surface_mesh>>(s, t, f);
    } catch (const Insufficient_features_error& e) { // genus > 0 with too few features: reported, not fatal
      std::printf("| %s | %zu/%zu | too few features: %s |\n", c.filename().string().c_str(), ns, nt, e.what());
      continue;
    }
    Cross_parameterization<Surface_mesh, Surface_mesh>& cp = *map;
    std::function<void(const std::string&)> say;
    if (std::getenv("CROSSPARAM_VERBOSE")) say = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    Compatible_remesher<Surface_mesh, Surface_mesh> r(cp, crossparam::parameters::tolerance(tol, crossparam::parameters::progress(say)));
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    const auto& S = r.statistics();
    Surface_mesh os, ot;
    r.copy_to(Mesh_side::source, os);
    r.copy_to(Mesh_side::target, ot);
    Remeshing_verification v = verify_compatible_remeshing(s0, t0, os, ot, tol);
    std::printf("| %s | %zu/%zu | %zu | %+.1f%% | %.3f | %.1f | %.3f | %.3f | %zu / %zu | %zu + %zu + %zu | %zu | %.2f / %.2f | %.2f | %.2f | %.2f | %.1e / %.1e |%s\n",
                c.filename().string().c_str(), ns, nt, S.output_vertices,
                100.0 * (double(S.output_vertices) - double(ns)) / double(ns), S.l2_error, S.psnr, S.max_error,
                v.hausdorff_target, S.layout_vertices - ns, S.layout_splits_undone, S.refinement_splits, S.pseudo_flips, S.fold_repair_splits, v.flipped_faces, v.normal_deviation_mean, v.normal_deviation_above_30, S.seconds_cross_parameterization,
                S.seconds_total, total, cp.statistics().squeeze_source, cp.statistics().squeeze_target, v.valid ? "" : (" FAILED: " + v.message).c_str());
    std::fflush(stdout);
  }
  return 0;
}

// SPDX-License-Identifier: GPL-3.0-or-later
// Cross-parameterization (paper §4) on the ../shared/bench cases: time per step and distortion per case.
// Usage: bench_map [BENCH_DIR] (../shared/bench_genus for genus > 0; too few features is a row naming it)
#include <crossparam/cross_parameterization.h>
#include <crossparam/io.h>

#include "bench_common.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

using namespace crossparam;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  fs::path dir = argc > 1 ? fs::path(argv[1]) : fs::path(CROSSPARAM_SHARED_DIR) / "bench";
  const std::vector<fs::path> cases = bench::cases(dir, "bench_map");
  const char* asserts = bench::assertions();
  std::printf("cross-parameterization, one run per case, assertions %s, times in ms\n\n", asserts);
  std::printf("| case | V source | V target | features (+ protrusion + extremity kept / found) | probe | extremity selection | layout | param | smoothing (passes) | certificate | total | E_ang before -> after | L2 stretch before -> after |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|\n");
  for (const fs::path& c : cases) {
    Surface_mesh s, t;
    read_triangle_mesh((c / "source.off").string(), s);
    read_triangle_mesh((c / "target.off").string(), t);
    const std::size_t ns = s.number_of_vertices(), nt = t.number_of_vertices();
    Feature_correspondence f = read_feature_pairs((c / "features.txt").string(), ns, nt);
    std::unique_ptr<Cross_parameterization<Surface_mesh, Surface_mesh>> map;
    try {
      map = std::make_unique<Cross_parameterization<Surface_mesh, Surface_mesh>>(s, t, f);
    } catch (const Insufficient_features_error& e) { // genus > 0 with too few features: reported, not fatal
      std::printf("| %s | %zu | %zu | %zu | too few features: %s |\n", c.filename().string().c_str(), ns, nt, f.size(),
                  e.what());
      continue;
    }
    const Cross_parameterization<Surface_mesh, Surface_mesh>& cp = *map;
    const auto& S = cp.statistics();
    // An adopted map (the probe's or the selection's winner) was parameterized and smoothed during the probe or
    // the selection: its own two columns say so, with the passes of the map adopted.
    char param[32], smoothing[48];
    if (S.map_adopted) {
      std::snprintf(param, sizeof param, "adopted");
      std::snprintf(smoothing, sizeof smoothing, "adopted (%u)", S.smoothing_source.iterations);
    } else {
      std::snprintf(param, sizeof param, "%.0f", 1e3 * S.seconds_parameterization);
      std::snprintf(smoothing, sizeof smoothing, "%.0f (%u)", 1e3 * S.seconds_smoothing, S.smoothing_source.iterations);
    }
    std::printf("| %s | %zu | %zu | %zu + %zu + %zu / %zu | %.0f | %.0f | %.0f | %s | %s | %.0f | %.0f | %.3f -> %.3f | %.3f -> %.3f |\n",
                c.filename().string().c_str(), ns, nt, f.size(), S.protrusion_features, S.extremity_features,
                S.extremity_candidates, 1e3 * S.seconds_probe, 1e3 * S.seconds_selection, 1e3 * S.layout.seconds_total,
                param, smoothing, 1e3 * S.seconds_certificate, 1e3 * S.seconds_total, S.distortion_initial.angular,
                S.distortion.angular, S.distortion_initial.l2_stretch, S.distortion.l2_stretch);
  }
  return 0;
}

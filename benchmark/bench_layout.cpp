// SPDX-License-Identifier: GPL-3.0-or-later
// Layout stage (paper §3) on the ../shared/bench cases: prints a table of sizes, features, paths, splits,
// flips and the time of each step. Usage: bench_layout [BENCH_DIR] [REPEATS]; BENCH_DIR ../shared/bench_genus
// for the meshes of genus > 0 (a case with too few features is a row naming the problem).
#include <crossparam/io.h>

#include "bench_common.h"
#include <crossparam/patch_layout.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <vector>

using namespace crossparam;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  fs::path dir = argc > 1 ? fs::path(argv[1]) : fs::path(CROSSPARAM_SHARED_DIR) / "bench";
  int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
  const std::vector<fs::path> cases = bench::cases(dir, "bench_layout");
  const char* asserts = bench::assertions();
  std::printf("layout stage, best of %d runs, assertions %s, times in ms\n\n", repeats, asserts);
  std::printf("| case | V source | V target | features | edge paths | face paths | splits s/t | flips | edge paths ms | face paths ms | flips ms | layout ms | verify ms |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const fs::path& c : cases) {
    Surface_mesh s0, t0;
    read_triangle_mesh((c / "source.off").string(), s0);
    read_triangle_mesh((c / "target.off").string(), t0);
    Feature_correspondence f =
        read_feature_pairs((c / "features.txt").string(), s0.number_of_vertices(), t0.number_of_vertices());
    Layout_statistics best;
    best.seconds_total = HUGE_VAL;
    double verify_best = HUGE_VAL;
    bool too_few = false;
    for (int r = 0; r < repeats && !too_few; ++r) {
      Surface_mesh s = s0, t = t0;
      Patch_layout L;
      try {
        L = compute_patch_layouts(s, t, f);
      } catch (const Insufficient_features_error& e) { // genus > 0 with too few features: reported, not fatal
        std::printf("| %s | %zu | %zu | %zu | too few features: %s |\n", c.filename().string().c_str(),
                    std::size_t(s0.number_of_vertices()), std::size_t(t0.number_of_vertices()), f.size(), e.what());
        too_few = true;
        break;
      }
      auto t1 = std::chrono::steady_clock::now();
      bool ok = verify_patch_layouts(s, t, L).valid;
      double vs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
      if (!ok) {
        std::cerr << c.filename() << ": verification failed\n";
        return 1;
      }
      if (L.statistics.seconds_total < best.seconds_total) best = L.statistics;
      verify_best = std::min(verify_best, vs);
    }
    if (too_few) continue;
    std::printf("| %s | %zu | %zu | %zu | %zu | %zu | %zu/%zu | %zu | %.1f | %.1f | %.1f | %.1f | %.1f |\n",
                c.filename().string().c_str(), std::size_t(s0.number_of_vertices()),
                std::size_t(t0.number_of_vertices()), f.size(), best.edge_paths, best.face_paths, best.splits_source,
                best.splits_target, best.flips, 1e3 * best.seconds_edge_paths, 1e3 * best.seconds_face_paths,
                1e3 * best.seconds_flips, 1e3 * best.seconds_total, 1e3 * verify_best);
  }
  return 0;
}

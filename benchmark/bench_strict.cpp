// SPDX-License-Identifier: GPL-3.0-or-later
// Compatible remeshing under the strict checks of verify_compatible_remeshing, over the cases of a bench
// directory and the added cases of bench_cases.h, at several tolerances: one table, one row per case and
// tolerance. Each case is cross-parameterized once; every tolerance remeshes that map.
// Usage: bench_strict [BENCH_DIR] [TOLERANCES] [CASE_FILTER] [DATA_DIR]
//   TOLERANCES: percent, comma-separated (default 1,0.5,0.2,0.1); CASE_FILTER: a substring of the case name.
#include <crossparam/compatible_remeshing.h>
#include <crossparam/io.h>
#include <crossparam/remeshing_verification.h>

#include "bench_cases.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>

using namespace crossparam;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  const fs::path dir = argc > 1 ? fs::path(argv[1]) : fs::path(CROSSPARAM_SHARED_DIR) / "bench";
  std::vector<double> tolerances;
  {
    std::stringstream in(argc > 2 ? argv[2] : "1,0.5,0.2,0.1");
    for (std::string t; std::getline(in, t, ',');) tolerances.push_back(std::atof(t.c_str()));
  }
  const std::string filter = argc > 3 ? argv[3] : "";
  const fs::path data = argc > 4 ? fs::path(argv[4]) : fs::path(CROSSPARAM_SHARED_DIR) / "data";
  std::printf("compatible remeshing under the strict checks (verify_compatible_remeshing), one run per case and "
              "tolerance, assertions %s\n\n", bench::assertions());
  std::printf("| case | tolerance (%%) | input #v s/t | added | Hausdorff (%%) | flipped | faces >30° (area %%) | "
              "excess creases | self-int. out/in | map (s) | remesh (s) | verify (s) | valid |\n");
  std::printf("|---|---:|---|---:|---:|---:|---|---:|---|---:|---:|---:|---|\n");
  std::fflush(stdout);
  using clock = std::chrono::steady_clock;
  auto sec = [](clock::time_point a) { return std::chrono::duration<double>(clock::now() - a).count(); };
  for (const bench::Case_builder& b : bench::remesh_cases(dir, data, "bench_strict")) {
    if (!filter.empty() && b.name.find(filter) == std::string::npos) continue;
    bench::Remesh_case c = b.build();
    const Surface_mesh s0 = c.source, t0 = c.target;
    const std::size_t ns = s0.number_of_vertices(), nt = t0.number_of_vertices();
    std::function<void(const std::string&)> say;
    if (std::getenv("CROSSPARAM_VERBOSE")) say = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    const auto tm = clock::now();
    Cross_parameterization<Surface_mesh, Surface_mesh> cp(c.source, c.target, c.features);
    const double map_seconds = sec(tm);
    for (double tol : tolerances) {
      const auto tr = clock::now();
      Compatible_remesher<Surface_mesh, Surface_mesh> r(cp, crossparam::parameters::tolerance(tol, crossparam::parameters::progress(say)));
      const double remesh_seconds = sec(tr);
      const auto& S = r.statistics();
      Surface_mesh os, ot;
      r.copy_to(0, os);
      r.copy_to(1, ot);
      const auto tv = clock::now();
      const Remeshing_verification v = verify_compatible_remeshing(s0, t0, os, ot, tol);
      std::printf("| %s | %.3g | %zu/%zu | %+.1f%% | %.3f | %zu | %zu (%.2f) | %zu | %zu/%zu | %.1f | %.1f | %.1f | %s |\n",
                  c.name.c_str(), tol, ns, nt, 100.0 * (double(S.output_vertices) - double(ns)) / double(ns),
                  v.hausdorff_target, v.flipped_faces, v.faces_above_30, v.normal_deviation_above_30, v.excess_creases,
                  v.self_intersections_output, v.self_intersections_target, map_seconds, remesh_seconds, sec(tv),
                  v.valid ? "yes" : "NO");
      std::fflush(stdout);
      if (!v.valid) std::fprintf(stderr, "%s at %g%%: %s\n", c.name.c_str(), tol, v.message.c_str());
    }
  }
  return 0;
}

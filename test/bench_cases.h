// SPDX-License-Identifier: GPL-3.0-or-later
// Shared by the tests on the real bench cases of ../shared/bench: the case names and their loading.
// A test whose case is absent skips with `absent(name)` as its message.
#ifndef CROSSPARAM_TEST_BENCH_CASES_H
#define CROSSPARAM_TEST_BENCH_CASES_H

#include <crossparam/io.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace test_bench {

/// The cases shipped in shared/bench; listed (not discovered) so that missing data shows up as skips.
inline std::vector<std::string> names() {
  return {"horse0_horse7", "lion_cat", "shrec_381_382", "shrec_383_385", "wolf0_wolf2", "yang_cat_horse"};
}

inline std::filesystem::path dir(const std::string& name) {
  return std::filesystem::path(CROSSPARAM_SHARED_DIR) / "bench" / name;
}

inline std::string absent(const std::string& name) {
  return "shared data not found at " + dir(name).string() + ": skipping";
}

/// One case as read from its files.
struct Case {
  std::filesystem::path dir;
  crossparam::Surface_mesh source, target;
  crossparam::Feature_correspondence features;
};

/// Case `name`, or nothing when ../shared is absent.
inline std::optional<Case> load(const std::string& name) {
  Case c;
  c.dir = dir(name);
  if (!std::filesystem::exists(c.dir / "source.off")) return std::nullopt;
  crossparam::read_triangle_mesh((c.dir / "source.off").string(), c.source);
  crossparam::read_triangle_mesh((c.dir / "target.off").string(), c.target);
  c.features = crossparam::read_feature_pairs((c.dir / "features.txt").string(), c.source.number_of_vertices(),
                                              c.target.number_of_vertices());
  return c;
}

} // namespace test_bench

#endif // CROSSPARAM_TEST_BENCH_CASES_H

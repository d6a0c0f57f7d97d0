// SPDX-License-Identifier: GPL-3.0-or-later
// Shared by the benchmark programs: finding the bench cases, saying how the build was made, reading the
// construction flag.
#ifndef CROSSPARAM_BENCH_COMMON_H
#define CROSSPARAM_BENCH_COMMON_H

#include <crossparam/parameters.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace bench {

/// The case directories (those holding a source.off) under `dir`, sorted; exits with a message if none.
inline std::vector<std::filesystem::path> cases(const std::filesystem::path& dir, const char* program) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir)) {
    std::cerr << program << ": no bench directory at " << dir << "\n";
    std::exit(1);
  }
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (fs::exists(e.path() / "source.off")) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

inline const char* assertions() {
#ifdef NDEBUG
  return "off";
#else
  return "on";
#endif
}

/// Whether `arg` is --construction=refinement or --construction=overlay; if so, sets `c`.
inline bool construction_flag(const std::string& arg, crossparam::Remeshing_construction& c) {
  if (arg == "--construction=refinement") return c = crossparam::Remeshing_construction::refinement, true;
  if (arg == "--construction=overlay") return c = crossparam::Remeshing_construction::overlay, true;
  return false;
}

} // namespace bench

#endif // CROSSPARAM_BENCH_COMMON_H

// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness of one reader: the bytes are handed to the reader (and what it accepts
// to the mesh checks of soup_to_triangle_mesh()) chosen at compile time by
// CROSSPARAM_FUZZ_FORMAT (0 OFF, 1 OBJ, 2 PLY, 3 STL, 4 the feature file). A reader may refuse the bytes
// with an Input_error (its documented behaviour); anything else (a crash, a sanitizer report, another
// exception, a leak) is a finding. Built by the CMake option CROSSPARAM_BUILD_FUZZERS, run by
// scripts/fuzz.sh.
#include <crossparam/errors.h>
#include <crossparam/io.h>
#include <crossparam/types.h>
#include <crossparam/validation.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include <unistd.h>

#ifndef CROSSPARAM_FUZZ_FORMAT
#error "define CROSSPARAM_FUZZ_FORMAT (0 OFF, 1 OBJ, 2 PLY, 3 STL, 4 features)"
#endif

namespace {

/// Vertex counts the feature file is checked against: enough for any index a short input can hold to be
/// either valid or out of range.
[[maybe_unused]] constexpr std::size_t fuzz_source_vertices = 1000, fuzz_target_vertices = 700;

/// A file name for the messages (the readers name the file in every error).
const std::string fuzz_path = "fuzz-input";

/// The feature file is read from disk (read_feature_pairs takes a path): one file per process, rewritten for
/// every input.
[[maybe_unused]] std::string feature_file() {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("crossparam-fuzz-features-" + std::to_string(::getpid()) + ".txt")).string();
  return path;
}

/// A soup the reader accepted goes through the mesh checks too, as read_triangle_mesh() does.
void build_mesh(const crossparam::Polygon_soup& soup) {
  crossparam::Surface_mesh mesh;
  (void)crossparam::soup_to_triangle_mesh(soup, mesh, fuzz_path);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace sio = crossparam::internal::soup_io;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
#if CROSSPARAM_FUZZ_FORMAT == 0
    std::string_view d = bytes;
    if (sio::starts_with(d, "\xEF\xBB\xBF")) d.remove_prefix(3);
    build_mesh(sio::read_off(fuzz_path, d));
#elif CROSSPARAM_FUZZ_FORMAT == 1
    std::string_view d = bytes;
    if (sio::starts_with(d, "\xEF\xBB\xBF")) d.remove_prefix(3);
    build_mesh(sio::read_obj(fuzz_path, d));
#elif CROSSPARAM_FUZZ_FORMAT == 2
    build_mesh(sio::read_ply(fuzz_path, bytes));
#elif CROSSPARAM_FUZZ_FORMAT == 3
    build_mesh(sio::read_stl(fuzz_path, bytes));
#else
    std::FILE* f = std::fopen(feature_file().c_str(), "wb");
    if (!f) return 0;
    std::fwrite(data, 1, size, f);
    std::fclose(f);
    (void)crossparam::read_feature_pairs(feature_file(), fuzz_source_vertices, fuzz_target_vertices);
#endif
  } catch (const crossparam::Input_error&) {
    // a refused input: the documented outcome
  }
  return 0;
}

// SPDX-License-Identifier: GPL-3.0-or-later
// Our own polygon-soup readers for OFF, OBJ, PLY (ascii and binary) and STL (ascii and binary).
//
// CGAL's readers crash, overflow buffers or allocate gigabytes on malformed files (see NOTES-CGAL.md), so
// crossparam never hands a file to them. These readers:
//  - never trust a count: every header count is checked against the number of bytes that follow it before
//    anything is reserved, and list lengths are checked against the bytes that remain;
//  - throw crossparam::Input_error("<path>: [line N: ]<problem>") for every defect: truncation, unparsable
//    numbers, face indices out of range, faces with fewer than 3 vertices, NaN/inf coordinates (also from
//    binary PLY/STL), coordinates with |x| > 1e100, unknown formats, empty or missing files;
//  - return points and polygons in file order (STL: exactly identical corner positions are merged into one
//    vertex, numbered in first-seen order, since STL stores a triangle soup).
// One header per format beside this one (off.h, obj.h, ply.h, stl.h; text.h: the shared primitives); the
// coordinate checks are those of <crossparam/validation.h>. Use crossparam::read_polygon_soup() from
// <crossparam/io.h>; everything here is an implementation detail.
#ifndef CROSSPARAM_INTERNAL_IO_SOUP_READERS_H
#define CROSSPARAM_INTERNAL_IO_SOUP_READERS_H

#include <crossparam/errors.h>
#include <crossparam/types.h>
#include <crossparam/internal/io/obj.h>
#include <crossparam/internal/io/off.h>
#include <crossparam/internal/io/ply.h>
#include <crossparam/internal/io/stl.h>
#include <crossparam/internal/io/text.h>

#include <filesystem>
#include <string>
#include <string_view>

namespace crossparam {
namespace internal {
namespace soup_io {

inline Polygon_soup read_polygon_soup(const std::string& path) {
  const std::string ext = to_lower(std::filesystem::path(path).extension().string());
  if (ext != ".off" && ext != ".obj" && ext != ".ply" && ext != ".stl")
    throw Input_error(path + ": unknown mesh file format " +
                      (ext.empty() ? std::string("(no file extension)") : quote(ext)) +
                      " (supported: .off, .obj, .ply, .stl)");
  const std::string bytes = read_whole_file<Input_error>(path);
  std::string_view data(bytes);
  Polygon_soup soup;
  if (ext == ".off" || ext == ".obj") {
    if (starts_with(data, "\xEF\xBB\xBF")) data.remove_prefix(3);  // UTF-8 byte order mark
    soup = (ext == ".off") ? read_off(path, data) : read_obj(path, data);
  } else if (ext == ".ply") {
    soup = read_ply(path, data);
  } else {
    soup = read_stl(path, data);
  }
  if (soup.points.empty()) throw Input_error(path + ": the file contains no vertices");
  if (soup.polygons.empty()) throw Input_error(path + ": the file contains no faces");
  return soup;
}

} // namespace soup_io
} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_IO_SOUP_READERS_H

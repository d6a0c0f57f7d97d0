// SPDX-License-Identifier: GPL-3.0-or-later
// Input and output: robust mesh reading, feature correspondence files, atomic file writing.
//
// Reading never hands a file to CGAL's readers (they crash on malformed input, see NOTES-CGAL.md): our own
// readers (internal/io/) produce a polygon soup, soup_to_triangle_mesh() of <crossparam/validation.h>
// validates it completely and only then builds the mesh, with vertex k = point k and face k = polygon k.
#ifndef CROSSPARAM_IO_H
#define CROSSPARAM_IO_H

#include <crossparam/errors.h>
#include <crossparam/types.h>
#include <crossparam/validation.h>
#include <crossparam/internal/io/soup_readers.h>
#include <crossparam/internal/io/text.h>

#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/boost/graph/properties.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <ostream>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace crossparam {

/// Reads an OFF (also COFF/NOFF/CNOFF/STOFF), OBJ, PLY (ascii/binary) or STL (ascii/binary) file as a polygon
/// soup, chosen by the (case-insensitive) extension; never crashes and never allocates more than the file size
/// justifies. The soup is not checked as a mesh (soup_to_triangle_mesh() does that); its coordinates are
/// finite with |x| <= 1e100 and its face indices in range.
/// \throws Input_error("<path>: [line N: ]<problem>") for any defect of the file.
inline Polygon_soup read_polygon_soup(const std::string& path) {
  return internal::soup_io::read_polygon_soup(path);
}

/// read_polygon_soup(path) followed by soup_to_triangle_mesh(soup, tm, path).
/// \throws Input_error("<path>: [line N: ]<problem>") for a defect of the file or of the mesh it holds.
template <class TriangleMesh>
Mesh_check_report read_triangle_mesh(const std::string& path, TriangleMesh& tm) {
  return soup_to_triangle_mesh(read_polygon_soup(path), tm, path);
}

// ---------------------------------------------------------------------------------------------- features

/// Reads feature pairs: one "source_vertex target_vertex" pair (0-based) per line, '#' starts a comment, blank
/// lines are ignored, a UTF-8 byte order mark is skipped; the k-th pair is feature k. Validated as by
/// validate_feature_pairs() against the vertex counts of the two meshes.
/// \throws Feature_error("<path>: [line N: ]<problem>") for a missing or unreadable file, a malformed line or an
///         invalid correspondence.
inline Feature_correspondence read_feature_pairs(const std::string& path, std::size_t n_source_vertices,
                                                 std::size_t n_target_vertices) {
  namespace sio = internal::soup_io;
  const std::string bytes = sio::read_whole_file<Feature_error>(path);
  const sio::Reporter<Feature_error> rep{path};
  std::string_view text(bytes);
  if (sio::starts_with(text, "\xEF\xBB\xBF")) text.remove_prefix(3); // UTF-8 byte order mark, as OFF and OBJ
  sio::Line_cursor lc{text};
  std::string_view line;
  std::vector<std::string_view> toks;
  Feature_correspondence fc;
  std::vector<std::size_t> lines;
  while (lc.next(line)) {
    sio::split(line, toks, true);
    if (toks.empty()) continue;
    std::array<std::uint64_t, 2> v{};
    bool ok = toks.size() == 2;
    for (std::size_t i = 0; ok && i < 2; ++i) {
      const std::string_view t = toks[i];
      ok = !t.empty() && std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; }) &&
           sio::parse_count(t, v[i]);
    }
    if (!ok) {
      std::string shown(line.substr(0, line.find('#')));
      while (!shown.empty() && sio::is_space(shown.back())) shown.pop_back();
      rep.fail_line(lc.line, "malformed line " + sio::quote(shown) +
                                 ": expected exactly two non-negative integers 'source_vertex target_vertex'");
    }
    fc.push_back(Feature_pair{static_cast<std::size_t>(v[0]), static_cast<std::size_t>(v[1])});
    lines.push_back(lc.line);
  }
  internal::validate_feature_pairs_impl(fc, n_source_vertices, n_target_vertices, path, &lines);
  return fc;
}

/// Reads the features of N meshes: one row per feature, whitespace-separated 0-based vertex indices, one column
/// per mesh; '#' starts a comment, blank lines are ignored, a UTF-8 byte order mark is skipped. With `columns`
/// empty, every row has exactly `vertex_counts.size()` entries; otherwise `columns[m]` is the column read for
/// mesh m (so that a file written for N meshes serves any of them in any order) and every row has an entry there.
/// Each index must be below its mesh's vertex count, no vertex of a mesh may be two features, and there must be
/// at least three rows. Used by `crossparam remesh` with three or more meshes.
/// \throws Feature_error("<path>: [line N: ]<problem>") for a missing or unreadable file, a malformed line or an
///         invalid correspondence.
inline Multi_feature_correspondence read_multi_features(const std::string& path, const std::vector<std::size_t>& vertex_counts,
                                                        const std::vector<std::size_t>& columns = {}) {
  namespace sio = internal::soup_io;
  const sio::Reporter<Feature_error> rep{path};
  if (!columns.empty() && columns.size() != vertex_counts.size())
    rep.fail(std::to_string(columns.size()) + " columns chosen for " + std::to_string(vertex_counts.size()) + " meshes");
  const std::string bytes = sio::read_whole_file<Feature_error>(path);
  std::string_view text(bytes);
  if (sio::starts_with(text, "\xEF\xBB\xBF")) text.remove_prefix(3);
  sio::Line_cursor lc{text};
  std::string_view line;
  std::vector<std::string_view> toks;
  std::vector<std::vector<std::size_t>> used; // per mesh and vertex: the line of the feature that has it, 0 if none
  for (std::size_t c : vertex_counts) used.emplace_back(c, 0);
  Multi_feature_correspondence out;
  while (lc.next(line)) {
    sio::split(line, toks, true);
    if (toks.empty()) continue;
    std::vector<std::uint64_t> row(toks.size());
    for (std::size_t i = 0; i < toks.size(); ++i) {
      const std::string_view t = toks[i];
      if (t.empty() || !std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
          !sio::parse_count(t, row[i]))
        rep.fail_line(lc.line, sio::quote(t) + " is not a vertex index (a non-negative integer)");
    }
    const std::size_t needed = columns.empty() ? vertex_counts.size() : *std::max_element(columns.begin(), columns.end()) + 1;
    if (columns.empty() ? row.size() != needed : row.size() < needed)
      rep.fail_line(lc.line, std::to_string(row.size()) + " vertices where " + (columns.empty() ? "" : "at least ") +
                                 std::to_string(needed) + " are needed (one column per mesh)");
    std::vector<std::size_t> feature(vertex_counts.size());
    for (std::size_t m = 0; m < vertex_counts.size(); ++m) {
      const std::uint64_t v = row[columns.empty() ? m : columns[m]];
      if (v >= vertex_counts[m])
        rep.fail_line(lc.line, "vertex " + std::to_string(v) + " of mesh " + std::to_string(m) + ", which has " +
                                   std::to_string(vertex_counts[m]) + " vertices");
      if (used[m][v] != 0)
        rep.fail_line(lc.line, "vertex " + std::to_string(v) + " of mesh " + std::to_string(m) +
                                   " is a duplicate: it is already the feature of line " + std::to_string(used[m][v]));
      used[m][v] = lc.line;
      feature[m] = static_cast<std::size_t>(v);
    }
    out.push_back(std::move(feature));
  }
  if (out.size() < 3) rep.fail("at least three features are needed, found " + std::to_string(out.size()));
  return out;
}

// ---------------------------------------------------------------------------------------------- writing

/// Writes a file via `write` into "<path>.tmp-XXXXXXXX" in the same directory, then renames it over `path`, so
/// readers never see a partial file. If `write` throws, the temporary file is removed and the exception
/// propagates. The stream has precision 17 (doubles round-trip). Throws Input_error if the file cannot be written.
inline void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  namespace fs = std::filesystem;
  if (path.empty()) throw Input_error("(empty file name): no output file name given");
  const fs::path target(path);
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Input_error(path + ": cannot write: directory '" + dir.string() + "' does not exist");
  if (fs::is_directory(target, ec)) throw Input_error(path + ": cannot write: it is a directory");

  thread_local std::mt19937_64 rng(
      static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
      static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(&ec)));
  static const char* hex = "0123456789abcdef";
  std::string tmp;
  std::ofstream os;
  for (int attempt = 0; attempt < 100 && !os.is_open(); ++attempt) {
    std::uint64_t r = rng();
    tmp = path + ".tmp-";
    for (int i = 0; i < 8; ++i, r >>= 4) tmp += hex[r & 15];
    if (fs::exists(tmp, ec)) continue;
    os.open(tmp, std::ios::binary | std::ios::trunc);
    if (!os.is_open())
      throw Input_error(path + ": cannot write: cannot create a file in directory '" + dir.string() + "' (" +
                        std::strerror(errno) + ")");
  }
  if (!os.is_open()) throw Input_error(path + ": cannot write: no free temporary file name");
  os.precision(17);
  try {
    write(os);
    os.flush();
    if (!os) throw Input_error(path + ": write error (disk full?)");
    os.close();
    if (os.fail()) throw Input_error(path + ": write error while closing the file (disk full?)");
    fs::rename(tmp, target, ec);
    if (ec) throw Input_error(path + ": cannot replace the file: " + ec.message());
  } catch (...) {
    if (os.is_open()) os.close();
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

namespace internal {

inline void check_points_and_triangles(const std::string& path, const std::vector<std::array<double, 3>>& points,
                                       const std::vector<std::array<std::size_t, 3>>& triangles) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string problem = coordinates_problem(points[i]);
    if (!problem.empty()) throw Error(path + ": cannot write vertex " + std::to_string(i) + ": " + problem);
  }
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (std::size_t v : triangles[f])
      if (v >= points.size())
        throw Error(path + ": cannot write triangle " + std::to_string(f) + ": vertex " + std::to_string(v) +
                    " is out of range (" + std::to_string(points.size()) + " points)");
}

template <class Color>
void write_ply_impl(const std::string& path, const std::vector<std::array<double, 3>>& points,
                    const std::vector<std::array<std::size_t, 3>>& triangles, const std::vector<Color>* face_colors,
                    const std::vector<Color>* vertex_colors) {
  check_points_and_triangles(path, points, triangles);
  if (face_colors && face_colors->size() != triangles.size())
    throw Error(path + ": " + std::to_string(face_colors->size()) + " face colours for " +
                std::to_string(triangles.size()) + " triangles");
  if (vertex_colors && vertex_colors->size() != points.size())
    throw Error(path + ": " + std::to_string(vertex_colors->size()) + " vertex colours for " +
                std::to_string(points.size()) + " vertices");
  write_file_atomically(path, [&](std::ostream& os) {
    os << "ply\nformat ascii 1.0\ncomment written by crossparam\n"
       << "element vertex " << points.size() << "\nproperty double x\nproperty double y\nproperty double z\n";
    if (vertex_colors) os << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    os << "element face " << triangles.size() << "\nproperty list uchar uint vertex_indices\n";
    if (face_colors) os << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    os << "end_header\n";
    for (std::size_t i = 0; i < points.size(); ++i) {
      os << points[i][0] << ' ' << points[i][1] << ' ' << points[i][2];
      if (vertex_colors)
        for (unsigned char c : (*vertex_colors)[i]) os << ' ' << static_cast<unsigned>(c);
      os << '\n';
    }
    for (std::size_t f = 0; f < triangles.size(); ++f) {
      os << "3 " << triangles[f][0] << ' ' << triangles[f][1] << ' ' << triangles[f][2];
      if (face_colors)
        for (unsigned char c : (*face_colors)[f]) os << ' ' << static_cast<unsigned>(c);
      os << '\n';
    }
  });
}

} // namespace internal

/// Writes an OFF file (atomically, 17 significant digits).
inline void write_off(const std::string& path, const std::vector<std::array<double, 3>>& points,
                      const std::vector<std::array<std::size_t, 3>>& triangles) {
  internal::check_points_and_triangles(path, points, triangles);
  write_file_atomically(path, [&](std::ostream& os) {
    os << "OFF\n" << points.size() << ' ' << triangles.size() << " 0\n";
    for (const auto& p : points) os << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const auto& t : triangles) os << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  });
}

/// Writes a face graph as OFF: vertices in vertices(tm) order, faces in faces(tm) order (any face degree).
template <class TriangleMesh>
void write_off(const std::string& path, const TriangleMesh& tm) {
  const auto vindex = internal::number_in_order(vertices(tm));
  auto vim = [&](auto v) { return vindex.at(v); };
  const auto vpm = get(CGAL::vertex_point, tm);
  std::vector<std::array<double, 3>> points(static_cast<std::size_t>(num_vertices(tm)));
  for (auto v : vertices(tm)) {
    const auto& p = get(vpm, v);
    points[vim(v)] = {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string problem = internal::coordinates_problem(points[i]);
    if (!problem.empty()) throw Error(path + ": cannot write vertex " + std::to_string(i) + ": " + problem);
  }
  std::vector<std::vector<std::size_t>> polys;
  polys.reserve(static_cast<std::size_t>(num_faces(tm)));
  for (auto f : faces(tm)) {
    polys.emplace_back();
    for (auto v : CGAL::vertices_around_face(halfedge(f, tm), tm)) polys.back().push_back(vim(v));
  }
  write_file_atomically(path, [&](std::ostream& os) {
    os << "OFF\n" << points.size() << ' ' << polys.size() << " 0\n";
    for (const auto& p : points) os << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const auto& poly : polys) {
      os << poly.size();
      for (std::size_t v : poly) os << ' ' << v;
      os << '\n';
    }
  });
}

/// Writes an ascii PLY with one red/green/blue (uchar) colour per face (atomically, 17 significant digits).
inline void write_ply_colored(const std::string& path, const std::vector<std::array<double, 3>>& points,
                              const std::vector<std::array<std::size_t, 3>>& triangles,
                              const std::vector<std::array<unsigned char, 3>>& face_colors) {
  internal::write_ply_impl(path, points, triangles, &face_colors, static_cast<decltype(&face_colors)>(nullptr));
}

/// Writes an ascii PLY with one red/green/blue (uchar) colour per vertex (atomically, 17 significant digits).
inline void write_ply_vertex_colored(const std::string& path, const std::vector<std::array<double, 3>>& points,
                                     const std::vector<std::array<std::size_t, 3>>& triangles,
                                     const std::vector<std::array<unsigned char, 3>>& vertex_colors) {
  internal::write_ply_impl(path, points, triangles, static_cast<decltype(&vertex_colors)>(nullptr), &vertex_colors);
}

} // namespace crossparam

#endif // CROSSPARAM_IO_H

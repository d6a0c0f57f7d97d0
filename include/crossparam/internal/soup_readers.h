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
// Use crossparam::read_polygon_soup() from <crossparam/io.h>; everything here is an implementation detail.
#ifndef CROSSPARAM_INTERNAL_SOUP_READERS_H
#define CROSSPARAM_INTERNAL_SOUP_READERS_H

#include <crossparam/errors.h>
#include <crossparam/types.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <vector>

namespace crossparam {
namespace internal {
namespace soup_io {

/// Coordinates beyond this magnitude are rejected: exact predicates overflow to inf/NaN inside GMP there.
constexpr double max_abs_coordinate = 1e100;

inline std::string format_double(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

/// A token of a file, quoted for an error message: at most 40 characters, non-printable bytes as \xNN.
inline std::string quote(std::string_view s) {
  static const char* hex = "0123456789abcdef";
  std::string out = "'";
  const std::size_t n = std::min<std::size_t>(s.size(), 40);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  if (s.size() > n) out += "...";
  out += "'";
  return out;
}

/// Empty when `v` is a usable coordinate, otherwise the problem.
inline std::string coordinate_problem(double v) {
  if (!std::isfinite(v)) return "non-finite coordinate: " + format_double(v);
  if (std::abs(v) > max_abs_coordinate)
    return "coordinate out of supported range: " + format_double(v) + " (|x| must be <= 1e100)";
  return std::string();
}

inline std::string coordinates_problem(const std::array<double, 3>& p) {
  for (double c : p) {
    std::string problem = coordinate_problem(c);
    if (!problem.empty()) return problem;
  }
  return std::string();
}

/// Throws E("<path>: <msg>") or E("<path>: line N: <msg>").
template <class E = Input_error>
struct Reporter {
  std::string path;
  [[noreturn]] void fail(const std::string& msg) const { throw E(path + ": " + msg); }
  [[noreturn]] void fail_line(std::size_t line, const std::string& msg) const {
    throw E(path + ": line " + std::to_string(line) + ": " + msg);
  }
};

/// Reads a whole file; throws E naming the path if it is missing, a directory, unreadable or empty.
template <class E = Input_error>
std::string read_whole_file(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) throw E("(empty file name): no file name given");
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::not_found) throw E(path + ": file does not exist");
  if (ec) throw E(path + ": cannot access file (" + ec.message() + ")");
  if (st.type() == fs::file_type::directory) throw E(path + ": is a directory, not a file");
  if (st.type() != fs::file_type::regular) throw E(path + ": is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw E(path + ": cannot open file for reading (" + std::strerror(errno) + ")");
  std::string data;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size < (std::uintmax_t(1) << 40)) data.reserve(static_cast<std::size_t>(size));
  char buf[1 << 16];
  while (in) {
    in.read(buf, sizeof buf);
    data.append(buf, static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw E(path + ": read error (" + std::strerror(errno) + ")");
  if (data.empty()) throw E(path + ": file is empty");
  return data;
}

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

inline bool starts_with(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

inline std::string to_lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

/// Splits `line` at whitespace; with `hash_comments`, everything from the first '#' on is dropped.
inline void split(std::string_view line, std::vector<std::string_view>& toks, bool hash_comments) {
  toks.clear();
  if (hash_comments) {
    const std::size_t h = line.find('#');
    if (h != std::string_view::npos) line = line.substr(0, h);
  }
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && is_space(line[i])) ++i;
    if (i >= n) break;
    std::size_t j = i;
    while (j < n && !is_space(line[j])) ++j;
    toks.push_back(line.substr(i, j - i));
    i = j;
  }
}

/// Iterates over lines ending in "\n", "\r\n" or "\r"; `line` is the 1-based number of the last line returned.
struct Line_cursor {
  std::string_view data;
  std::size_t pos = 0;
  std::size_t line = 0;
  int cr_breaks = -1; // a lone '\r' ends a line only in files without any '\n' (classic Mac); else it is a space

  bool next(std::string_view& out) {
    if (pos >= data.size()) return false;
    if (cr_breaks < 0) cr_breaks = data.find('\n') == std::string_view::npos ? 1 : 0;
    std::size_t e = cr_breaks ? data.find('\r', pos) : data.find('\n', pos);
    if (e == std::string_view::npos) e = data.size();
    out = data.substr(pos, e - pos);
    pos = e < data.size() ? e + 1 : e;
    ++line;
    return true;
  }
  std::size_t remaining() const { return pos >= data.size() ? 0 : data.size() - pos; }
};

/// Parses a whole token as a double (decimal or scientific, "nan"/"inf" allowed and reported later).
/// Values too large for a double become +-max (rejected as out of range); too small ones become 0.
inline bool parse_double(std::string_view t, double& v) {
  if (t.empty()) return false;
  const char* b = t.data();
  const char* e = b + t.size();
  if (*b == '+') {
    ++b;
    if (b == e || *b == '+' || *b == '-') return false;
  }
  const auto r = std::from_chars(b, e, v, std::chars_format::general);
  if (r.ptr != e) return false;
  if (r.ec == std::errc::result_out_of_range) {
    const bool negative = (*b == '-');
    const std::size_t epos = t.find_first_of("eE");
    const bool tiny = epos != std::string_view::npos && epos + 1 < t.size() && t[epos + 1] == '-';
    if (tiny) {
      v = negative ? -0.0 : 0.0;
    } else {
      v = negative ? -std::numeric_limits<double>::max() : std::numeric_limits<double>::max();
    }
    return true;
  }
  return r.ec == std::errc();
}

/// Parses a whole token as a signed 64-bit integer ('+' allowed).
inline bool parse_int(std::string_view t, long long& v) {
  if (t.empty()) return false;
  const char* b = t.data();
  const char* e = b + t.size();
  if (*b == '+') {
    ++b;
    if (b == e || *b == '+' || *b == '-') return false;
  }
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

/// Parses a whole token as an unsigned 64-bit integer (digits only, '+' allowed).
inline bool parse_count(std::string_view t, std::uint64_t& v) {
  if (t.empty()) return false;
  const char* b = t.data();
  const char* e = b + t.size();
  if (*b == '+') ++b;
  if (b == e || *b < '0' || *b > '9') return false;
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

// ------------------------------------------------------------------------------------------------ OFF

inline Polygon_soup read_off(const std::string& path, std::string_view data) {
  const Reporter<> rep{path};
  Line_cursor lc{data};
  std::vector<std::string_view> toks;
  std::string_view line;
  auto next_significant = [&]() -> bool {
    while (lc.next(line)) {
      split(line, toks, true);
      if (!toks.empty()) return true;
    }
    return false;
  };

  if (!next_significant()) rep.fail("file contains no data (only blank lines or comments)");
  std::size_t first = 0;
  const std::string_view kw = toks[0];
  if (kw.size() >= 3 && kw.substr(kw.size() - 3) == "OFF") {
    std::string_view prefix = kw.substr(0, kw.size() - 3);
    if (starts_with(prefix, "ST")) prefix.remove_prefix(2);
    if (starts_with(prefix, "C")) prefix.remove_prefix(1);
    if (starts_with(prefix, "N")) prefix.remove_prefix(1);
    if (starts_with(prefix, "4") || starts_with(prefix, "n"))
      rep.fail_line(lc.line, "OFF variant " + quote(kw) + " (not 3-dimensional) is not supported");
    if (!prefix.empty()) rep.fail_line(lc.line, "unknown OFF header keyword " + quote(kw));
    if (toks.size() > 1 && toks[1] == "BINARY") rep.fail_line(lc.line, "binary OFF is not supported");
    first = 1;
  } else {
    long long dummy;
    if (!parse_int(kw, dummy))
      rep.fail_line(lc.line, "not an OFF file: expected the header keyword 'OFF', found " + quote(kw));
  }

  std::vector<std::string_view> counts(toks.begin() + static_cast<std::ptrdiff_t>(first), toks.end());
  std::size_t counts_line = lc.line;
  if (counts.empty()) {
    if (!next_significant()) rep.fail_line(lc.line, "file ends before the vertex and face counts");
    counts = toks;
    counts_line = lc.line;
  }
  if (counts.size() < 2 || counts.size() > 3)
    rep.fail_line(counts_line, "expected 'vertex_count face_count [edge_count]', found " +
                                   std::to_string(counts.size()) + " values");
  std::uint64_t nv = 0, nf = 0, ne = 0;
  if (!parse_count(counts[0], nv)) rep.fail_line(counts_line, "cannot parse the vertex count " + quote(counts[0]));
  if (!parse_count(counts[1], nf)) rep.fail_line(counts_line, "cannot parse the face count " + quote(counts[1]));
  if (counts.size() == 3 && !parse_count(counts[2], ne))
    rep.fail_line(counts_line, "cannot parse the edge count " + quote(counts[2]));
  if (nv == 0) rep.fail_line(counts_line, "the header declares 0 vertices");
  if (nf == 0) rep.fail_line(counts_line, "the header declares 0 faces");

  // Each vertex and face needs a line of its own, i.e. at least 2 bytes (the last line may lack its newline).
  // Check before reserving anything; malformed short lines get their own, more precise, errors below.
  const std::uint64_t rem = lc.remaining();
  if (nv > rem / 2 + 1 || nf > rem / 2 + 1 || 2 * (nv + nf) > rem + 1)
    rep.fail_line(counts_line, "the header declares " + std::to_string(nv) + " vertices and " +
                                   std::to_string(nf) + " faces, which need at least " +
                                   (nv < (std::uint64_t(1) << 61) && nf < (std::uint64_t(1) << 61) ? std::to_string(2 * (nv + nf) - 1)
                                                                                    : "more than " + std::to_string(rem)) +
                                   " bytes, but only " + std::to_string(rem) +
                                   " bytes follow the header (truncated file or corrupt header)");

  Polygon_soup soup;
  soup.points.reserve(static_cast<std::size_t>(nv));
  soup.polygons.reserve(static_cast<std::size_t>(nf));
  for (std::uint64_t i = 0; i < nv; ++i) {
    if (!next_significant())
      rep.fail_line(lc.line, "file ends after " + std::to_string(i) + " of " + std::to_string(nv) +
                                 " vertices (truncated file?)");
    if (toks.size() < 3)
      rep.fail_line(lc.line, "vertex " + std::to_string(i) + ": expected 3 coordinates, found " +
                                 std::to_string(toks.size()));
    std::array<double, 3> p{};
    for (int k = 0; k < 3; ++k) {
      if (!parse_double(toks[k], p[k]))
        rep.fail_line(lc.line, "vertex " + std::to_string(i) + ": cannot parse coordinate " + quote(toks[k]));
      const std::string problem = coordinate_problem(p[k]);
      if (!problem.empty()) rep.fail_line(lc.line, "vertex " + std::to_string(i) + ": " + problem);
    }
    soup.points.push_back(p);
  }
  for (std::uint64_t j = 0; j < nf; ++j) {
    if (!next_significant())
      rep.fail_line(lc.line, "file ends after " + std::to_string(j) + " of " + std::to_string(nf) +
                                 " faces (truncated file?)");
    const std::string face = "face " + std::to_string(j);
    std::uint64_t n = 0;
    if (!parse_count(toks[0], n)) rep.fail_line(lc.line, face + ": cannot parse the vertex count " + quote(toks[0]));
    if (n < 3) rep.fail_line(lc.line, face + " has " + std::to_string(n) + " vertices (at least 3 are needed)");
    if (n > toks.size() - 1)
      rep.fail_line(lc.line, face + " declares " + std::to_string(n) + " vertices but the line lists only " +
                                 std::to_string(toks.size() - 1) + " (truncated line?)");
    std::vector<std::size_t> poly(static_cast<std::size_t>(n));
    for (std::size_t k = 0; k < n; ++k) {
      long long idx = 0;
      if (!parse_int(toks[k + 1], idx))
        rep.fail_line(lc.line, face + ": cannot parse vertex index " + quote(toks[k + 1]));
      if (idx < 0 || static_cast<std::uint64_t>(idx) >= nv)
        rep.fail_line(lc.line, face + " refers to vertex " + std::to_string(idx) + " but the file has " +
                                   std::to_string(nv) + " vertices (index out of range)");
      poly[k] = static_cast<std::size_t>(idx);
    }
    soup.polygons.push_back(std::move(poly));
  }
  return soup;
}

// ------------------------------------------------------------------------------------------------ OBJ

inline Polygon_soup read_obj(const std::string& path, std::string_view data) {
  const Reporter<> rep{path};
  Line_cursor lc{data};
  std::vector<std::string_view> toks;
  std::string_view line;
  std::string joined;
  Polygon_soup soup;
  std::vector<std::size_t> face_lines;
  while (lc.next(line)) {
    const std::size_t line_no = lc.line;
    if (!line.empty() && line.back() == '\\') {  // continuation lines
      joined.assign(line.substr(0, line.size() - 1));
      std::string_view more;
      while (lc.next(more)) {
        joined += ' ';
        if (!more.empty() && more.back() == '\\') {
          joined.append(more.substr(0, more.size() - 1));
        } else {
          joined.append(more);
          break;
        }
      }
      line = joined;
    }
    split(line, toks, true);
    if (toks.empty()) continue;
    const std::string_view kw = toks[0];
    if (kw == "v") {
      const std::string vertex = "vertex " + std::to_string(soup.points.size());
      if (toks.size() < 4)
        rep.fail_line(line_no, vertex + ": expected 3 coordinates after 'v', found " + std::to_string(toks.size() - 1));
      std::array<double, 3> p{};
      for (int k = 0; k < 3; ++k) {
        if (!parse_double(toks[k + 1], p[k]))
          rep.fail_line(line_no, vertex + ": cannot parse coordinate " + quote(toks[k + 1]));
        const std::string problem = coordinate_problem(p[k]);
        if (!problem.empty()) rep.fail_line(line_no, vertex + ": " + problem);
      }
      soup.points.push_back(p);
    } else if (kw == "f" || kw == "fo") {
      const std::string face = "face " + std::to_string(soup.polygons.size());
      if (toks.size() < 4)
        rep.fail_line(line_no, face + " has " + std::to_string(toks.size() - 1) + " vertices (at least 3 are needed)");
      std::vector<std::size_t> poly;
      poly.reserve(toks.size() - 1);
      for (std::size_t k = 1; k < toks.size(); ++k) {
        const std::string_view t = toks[k];
        const std::string_view idx_tok = t.substr(0, t.find('/'));
        long long idx = 0;
        if (idx_tok.empty() || !parse_int(idx_tok, idx))
          rep.fail_line(line_no, face + ": cannot parse vertex index " + quote(t));
        if (idx == 0) rep.fail_line(line_no, face + ": vertex index 0 is invalid (OBJ indices start at 1)");
        if (idx < 0) {
          const long long n = static_cast<long long>(soup.points.size());
          if (idx < -n)
            rep.fail_line(line_no, face + ": relative vertex index " + std::to_string(idx) +
                                       " refers before the first vertex (only " + std::to_string(n) +
                                       " vertices defined so far; index out of range)");
          poly.push_back(static_cast<std::size_t>(n + idx));
        } else {
          poly.push_back(static_cast<std::size_t>(idx - 1));
        }
      }
      soup.polygons.push_back(std::move(poly));
      face_lines.push_back(line_no);
    }
    // Everything else (vt, vn, vp, g, o, s, l, p, usemtl, mtllib, curves, ...) is irrelevant here.
  }
  // Faces may legally refer to vertices defined later in the file: check the range at the end.
  const std::size_t nv = soup.points.size();
  for (std::size_t f = 0; f < soup.polygons.size(); ++f)
    for (std::size_t idx : soup.polygons[f])
      if (idx >= nv)
        rep.fail_line(face_lines[f], "face " + std::to_string(f) + " refers to vertex " + std::to_string(idx + 1) +
                                         " (1-based) but the file has " + std::to_string(nv) +
                                         " vertices (index out of range)");
  return soup;
}

// ------------------------------------------------------------------------------------------------ PLY

enum class Ply_type : unsigned char { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

inline bool ply_type_from_name(std::string_view s, Ply_type& t) {
  if (s == "char" || s == "int8") t = Ply_type::int8;
  else if (s == "uchar" || s == "uint8") t = Ply_type::uint8;
  else if (s == "short" || s == "int16") t = Ply_type::int16;
  else if (s == "ushort" || s == "uint16") t = Ply_type::uint16;
  else if (s == "int" || s == "int32") t = Ply_type::int32;
  else if (s == "uint" || s == "uint32") t = Ply_type::uint32;
  else if (s == "float" || s == "float32") t = Ply_type::float32;
  else if (s == "double" || s == "float64") t = Ply_type::float64;
  else return false;
  return true;
}

inline std::size_t ply_size(Ply_type t) {
  switch (t) {
    case Ply_type::int8: case Ply_type::uint8: return 1;
    case Ply_type::int16: case Ply_type::uint16: return 2;
    case Ply_type::int32: case Ply_type::uint32: case Ply_type::float32: return 4;
    case Ply_type::float64: return 8;
  }
  return 8;
}

inline bool ply_is_integral(Ply_type t) { return t != Ply_type::float32 && t != Ply_type::float64; }

struct Ply_property {
  std::string name;
  bool is_list = false;
  Ply_type count_type = Ply_type::uint8;
  Ply_type value_type = Ply_type::float32;
};

struct Ply_element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Ply_property> properties;
  std::size_t line = 0;
};

inline bool host_is_big_endian() {
  const std::uint16_t x = 1;
  unsigned char b;
  std::memcpy(&b, &x, 1);
  return b == 0;
}

/// Decodes one binary scalar of type t from b (already in host byte order).
inline double ply_decode(Ply_type t, const unsigned char* b) {
  switch (t) {
    case Ply_type::int8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
    case Ply_type::uint8: { std::uint8_t v; std::memcpy(&v, b, 1); return v; }
    case Ply_type::int16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
    case Ply_type::uint16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
    case Ply_type::int32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
    case Ply_type::uint32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
    case Ply_type::float32: { float v; std::memcpy(&v, b, 4); return v; }
    case Ply_type::float64: { double v; std::memcpy(&v, b, 8); return v; }
  }
  return 0;
}

inline Polygon_soup read_ply(const std::string& path, std::string_view data) {
  const Reporter<> rep{path};
  Line_cursor lc{data};
  std::vector<std::string_view> toks;
  std::string_view line;

  if (!lc.next(line)) rep.fail_line(1, "not a PLY file (the first line must be 'ply')");
  split(line, toks, false);
  if (toks.size() != 1 || toks[0] != "ply") rep.fail_line(1, "not a PLY file (the first line must be 'ply')");

  enum class Format { none, ascii, little, big } format = Format::none;
  std::vector<Ply_element> elements;
  bool end_found = false;
  while (lc.next(line)) {
    split(line, toks, false);
    if (toks.empty()) continue;
    const std::string_view kw = toks[0];
    if (kw == "comment" || kw == "obj_info") continue;
    if (kw == "format") {
      if (format != Format::none) rep.fail_line(lc.line, "second 'format' line");
      if (toks.size() != 3) rep.fail_line(lc.line, "malformed 'format' line (expected 'format <type> 1.0')");
      if (toks[1] == "ascii") format = Format::ascii;
      else if (toks[1] == "binary_little_endian") format = Format::little;
      else if (toks[1] == "binary_big_endian") format = Format::big;
      else rep.fail_line(lc.line, "unsupported PLY format " + quote(toks[1]));
      double version = 0;
      if (!parse_double(toks[2], version) || version != 1.0)
        rep.fail_line(lc.line, "unsupported PLY version " + quote(toks[2]));
    } else if (kw == "element") {
      if (format == Format::none) rep.fail_line(lc.line, "'element' before the 'format' line");
      if (toks.size() != 3) rep.fail_line(lc.line, "malformed 'element' line (expected 'element <name> <count>')");
      Ply_element e;
      e.name = std::string(toks[1]);
      e.line = lc.line;
      if (!parse_count(toks[2], e.count))
        rep.fail_line(lc.line, "cannot parse the count " + quote(toks[2]) + " of element " + quote(toks[1]));
      elements.push_back(std::move(e));
    } else if (kw == "property") {
      if (elements.empty()) rep.fail_line(lc.line, "'property' before any 'element'");
      Ply_property p;
      if (toks.size() >= 2 && toks[1] == "list") {
        if (toks.size() != 5)
          rep.fail_line(lc.line, "malformed list property (expected 'property list <count type> <type> <name>')");
        if (!ply_type_from_name(toks[2], p.count_type)) rep.fail_line(lc.line, "unknown PLY type " + quote(toks[2]));
        if (!ply_is_integral(p.count_type))
          rep.fail_line(lc.line, "the length type of a list property must be an integer type, not " + quote(toks[2]));
        if (!ply_type_from_name(toks[3], p.value_type)) rep.fail_line(lc.line, "unknown PLY type " + quote(toks[3]));
        p.is_list = true;
        p.name = std::string(toks[4]);
      } else {
        if (toks.size() != 3) rep.fail_line(lc.line, "malformed property (expected 'property <type> <name>')");
        if (!ply_type_from_name(toks[1], p.value_type)) rep.fail_line(lc.line, "unknown PLY type " + quote(toks[1]));
        p.name = std::string(toks[2]);
      }
      elements.back().properties.push_back(std::move(p));
    } else if (kw == "end_header") {
      end_found = true;
      break;
    } else {
      rep.fail_line(lc.line, "unknown PLY header keyword " + quote(kw));
    }
  }
  if (!end_found) rep.fail("the header has no 'end_header' line (truncated file or not a PLY file)");
  if (format == Format::none) rep.fail("the header has no 'format' line");
  const std::size_t header_lines = lc.line;

  // The vertex and face elements.
  std::size_t vertex_elem = elements.size(), face_elem = elements.size();
  std::size_t ix = 0, iy = 0, iz = 0, ilist = 0;
  for (std::size_t ei = 0; ei < elements.size(); ++ei) {
    const Ply_element& e = elements[ei];
    if (e.name == "vertex" && vertex_elem == elements.size()) {
      vertex_elem = ei;
      const char* names[3] = {"x", "y", "z"};
      std::size_t* slots[3] = {&ix, &iy, &iz};
      for (int c = 0; c < 3; ++c) {
        std::size_t found = e.properties.size();
        for (std::size_t pi = 0; pi < e.properties.size(); ++pi)
          if (e.properties[pi].name == names[c]) { found = pi; break; }
        if (found == e.properties.size())
          rep.fail_line(e.line, std::string("element 'vertex' has no property '") + names[c] + "'");
        if (e.properties[found].is_list)
          rep.fail_line(e.line, std::string("vertex property '") + names[c] + "' is a list, expected a scalar");
        *slots[c] = found;
      }
    } else if (e.name == "face" && face_elem == elements.size()) {
      face_elem = ei;
      std::size_t found = e.properties.size();
      for (std::size_t pi = 0; pi < e.properties.size(); ++pi)
        if (e.properties[pi].is_list &&
            (e.properties[pi].name == "vertex_indices" || e.properties[pi].name == "vertex_index")) {
          found = pi;
          break;
        }
      if (found == e.properties.size())
        rep.fail_line(e.line, "element 'face' has no list property 'vertex_indices' (or 'vertex_index')");
      if (!ply_is_integral(e.properties[found].value_type))
        rep.fail_line(e.line, "face vertex indices must have an integer type");
      ilist = found;
    }
  }
  if (vertex_elem == elements.size()) rep.fail("the header declares no 'vertex' element");
  if (face_elem == elements.size()) rep.fail("the header declares no 'face' element");
  const std::uint64_t nv = elements[vertex_elem].count;

  // Check every count against the bytes that follow the header, before reserving anything.
  const bool ascii = (format == Format::ascii);
  const std::size_t data_start = lc.pos;
  const std::uint64_t rem = data.size() - std::min(data_start, data.size());
  const std::uint64_t budget = ascii ? rem + 1 : rem;  // the last ascii token needs no separator
  std::uint64_t needed = 0;
  for (std::size_t ei = 0; ei < elements.size(); ++ei) {
    const Ply_element& e = elements[ei];
    std::uint64_t min_bytes = 0;  // per entry
    for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
      const Ply_property& p = e.properties[pi];
      if (ascii) min_bytes += 2;  // a token and a separator (a list: at least its length)
      else min_bytes += ply_size(p.is_list ? p.count_type : p.value_type);
    }
    if (e.count == 0 || min_bytes == 0) continue;
    if (e.count > budget / min_bytes || needed + e.count * min_bytes > budget)
      rep.fail_line(e.line, "element '" + e.name + "' declares " + std::to_string(e.count) + " entries of at least " +
                                std::to_string(min_bytes) + " bytes each, but only " + std::to_string(rem) +
                                " bytes follow the header (truncated file or corrupt header)");
    needed += e.count * min_bytes;
  }

  Polygon_soup soup;
  soup.points.reserve(static_cast<std::size_t>(nv));
  soup.polygons.reserve(static_cast<std::size_t>(elements[face_elem].count));

  // Cursors over the data.
  const unsigned char* bytes = reinterpret_cast<const unsigned char*>(data.data());
  std::size_t pos = std::min(data_start, data.size());
  std::size_t ascii_line = header_lines + 1;
  const bool swap = !ascii && ((format == Format::big) != host_is_big_endian());

  std::string where;  // "line N: " (ascii) or "" (binary), set before each entry
  auto truncated = [&](const Ply_element& e, std::uint64_t k) {
    rep.fail(where + "file ends inside entry " + std::to_string(k) + " of " + std::to_string(e.count) +
             " of element '" + e.name + "' (truncated file?)");
  };
  // Reads the next value; false at end of data.
  auto read_value = [&](Ply_type t, double& v, std::string_view& tok) -> bool {
    if (ascii) {
      while (pos < data.size() && is_space(data[pos])) {
        if (data[pos] == '\n') ++ascii_line;
        ++pos;
      }
      if (pos >= data.size()) return false;
      const std::size_t s = pos;
      while (pos < data.size() && !is_space(data[pos])) ++pos;
      tok = data.substr(s, pos - s);
      if (!parse_double(tok, v)) rep.fail_line(ascii_line, "cannot parse value " + quote(tok));
      return true;
    }
    const std::size_t n = ply_size(t);
    if (data.size() - pos < n) return false;
    unsigned char b[8];
    std::memcpy(b, bytes + pos, n);
    if (swap) std::reverse(b, b + n);
    pos += n;
    v = ply_decode(t, b);
    return true;
  };
  auto current_where = [&]() -> std::string {
    if (ascii) {
      // Line of the next token.
      std::size_t p = pos, l = ascii_line;
      while (p < data.size() && is_space(data[p])) {
        if (data[p] == '\n') ++l;
        ++p;
      }
      return "line " + std::to_string(l) + ": ";
    }
    return "byte offset " + std::to_string(pos) + ": ";
  };

  std::vector<std::size_t> face_lines;
  for (std::size_t ei = 0; ei < elements.size(); ++ei) {
    const Ply_element& e = elements[ei];
    if (e.properties.empty()) continue;  // nothing stored per entry
    const bool is_v = (ei == vertex_elem), is_f = (ei == face_elem);
    for (std::uint64_t k = 0; k < e.count; ++k) {
      where = current_where();
      std::array<double, 3> p{};
      std::vector<std::size_t> poly;
      for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
        const Ply_property& prop = e.properties[pi];
        double v = 0;
        std::string_view tok;
        if (!prop.is_list) {
          if (!read_value(prop.value_type, v, tok)) truncated(e, k);
          if (is_v) {
            if (pi == ix) p[0] = v;
            if (pi == iy) p[1] = v;
            if (pi == iz) p[2] = v;
          }
          continue;
        }
        if (!read_value(prop.count_type, v, tok)) truncated(e, k);
        if (!(v >= 0) || v != std::floor(v))
          rep.fail(where + "element '" + e.name + "' entry " + std::to_string(k) + ": invalid list length " +
                   format_double(v));
        // The remaining data bounds the list length (also keeps huge values away from the cast).
        const std::uint64_t left = data.size() - pos;
        const double max_len = ascii ? static_cast<double>(left / 2 + 1) : static_cast<double>(left / ply_size(prop.value_type));
        if (v > max_len) truncated(e, k);
        const std::size_t n = static_cast<std::size_t>(v);
        const bool face_list = is_f && pi == ilist;
        if (face_list && n < 3)
          rep.fail(where + "face " + std::to_string(k) + " has " + std::to_string(n) + " vertices (at least 3 are needed)");
        if (face_list) poly.resize(n);
        if (!ascii && !face_list) {
          pos += n * ply_size(prop.value_type);  // skip
          continue;
        }
        for (std::size_t i = 0; i < n; ++i) {
          if (!read_value(prop.value_type, v, tok)) truncated(e, k);
          if (!face_list) continue;
          if (!(v >= 0) || v != std::floor(v) || v >= static_cast<double>(nv))
            rep.fail(where + "face " + std::to_string(k) + " refers to vertex " + format_double(v) +
                     " but the file has " + std::to_string(nv) + " vertices (index out of range)");
          poly[i] = static_cast<std::size_t>(v);
        }
      }
      if (is_v) {
        const std::string problem = coordinates_problem(p);
        if (!problem.empty()) rep.fail(where + "vertex " + std::to_string(k) + ": " + problem);
        soup.points.push_back(p);
      }
      if (is_f) soup.polygons.push_back(std::move(poly));
    }
  }
  return soup;
}

// ------------------------------------------------------------------------------------------------ STL

struct Point_key_hash {
  std::size_t operator()(const std::array<double, 3>& p) const {
    std::uint64_t h = 1469598103934665603ull;
    for (double c : p) {
      const double d = c + 0.0;  // -0.0 and 0.0 compare equal: give them the same hash
      std::uint64_t bits;
      std::memcpy(&bits, &d, sizeof bits);
      h ^= bits + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    }
    return static_cast<std::size_t>(h);
  }
};

/// Merges exactly identical positions into one vertex, numbered in first-seen order.
struct Vertex_merger {
  Polygon_soup& soup;
  std::unordered_map<std::array<double, 3>, std::size_t, Point_key_hash> index;
  std::size_t operator()(const std::array<double, 3>& p) {
    const auto it = index.emplace(p, soup.points.size());
    if (it.second) soup.points.push_back(p);
    return it.first->second;
  }
};

inline bool looks_like_text(std::string_view data) {
  for (char ch : data) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (!((c >= 0x20 && c < 0x7f) || (c >= 0x09 && c <= 0x0d))) return false;
  }
  return true;
}

inline Polygon_soup read_stl_binary(const std::string& path, std::string_view data) {
  const Reporter<> rep{path};
  const unsigned char* b = reinterpret_cast<const unsigned char*>(data.data());
  const std::uint32_t n = static_cast<std::uint32_t>(b[80]) | (static_cast<std::uint32_t>(b[81]) << 8) |
                          (static_cast<std::uint32_t>(b[82]) << 16) | (static_cast<std::uint32_t>(b[83]) << 24);
  Polygon_soup soup;
  Vertex_merger merge{soup, {}};
  soup.polygons.reserve(n);
  merge.index.reserve(std::min<std::size_t>(3 * static_cast<std::size_t>(n), 1u << 24));
  const bool big = host_is_big_endian();
  for (std::uint32_t t = 0; t < n; ++t) {
    const unsigned char* tri = b + 84 + 50 * static_cast<std::size_t>(t);
    std::vector<std::size_t> poly(3);
    for (int c = 0; c < 3; ++c) {
      std::array<double, 3> p{};
      for (int k = 0; k < 3; ++k) {
        unsigned char f[4];
        std::memcpy(f, tri + 12 + 12 * c + 4 * k, 4);
        if (big) std::reverse(f, f + 4);
        float v;
        std::memcpy(&v, f, 4);
        p[k] = v;
      }
      const std::string problem = coordinates_problem(p);
      if (!problem.empty())
        rep.fail("triangle " + std::to_string(t) + ", corner " + std::to_string(c) + ": " + problem);
      poly[c] = merge(p);
    }
    soup.polygons.push_back(std::move(poly));
  }
  return soup;
}

inline Polygon_soup read_stl_ascii(const std::string& path, std::string_view data) {
  const Reporter<> rep{path};
  Line_cursor lc{data};
  std::vector<std::string_view> toks;
  std::string_view line;
  Polygon_soup soup;
  Vertex_merger merge{soup, {}};
  enum class State { outside, solid, facet, loop } state = State::outside;
  bool seen_solid = false;
  std::vector<std::size_t> poly;
  std::size_t facet_line = 0;
  while (lc.next(line)) {
    split(line, toks, false);
    if (toks.empty()) continue;
    const std::string kw = to_lower(toks[0]);
    const std::string facet = "facet " + std::to_string(soup.polygons.size());
    if (kw == "solid") {
      if (state != State::outside) rep.fail_line(lc.line, "'solid' inside another solid (missing 'endsolid')");
      state = State::solid;
      seen_solid = true;
    } else if (kw == "facet") {
      if (state != State::solid)
        rep.fail_line(lc.line, state == State::outside ? "'facet' outside a solid" : "'facet' inside a facet (missing 'endfacet')");
      state = State::facet;
      poly.clear();
      facet_line = lc.line;
    } else if (kw == "outer") {
      if (state != State::facet || toks.size() < 2 || to_lower(toks[1]) != "loop")
        rep.fail_line(lc.line, "unexpected " + quote(line));
      state = State::loop;
    } else if (kw == "vertex") {
      if (state != State::loop) rep.fail_line(lc.line, "'vertex' outside 'outer loop'");
      if (toks.size() < 4) rep.fail_line(lc.line, facet + ": expected 3 coordinates after 'vertex'");
      std::array<double, 3> p{};
      for (int k = 0; k < 3; ++k) {
        if (!parse_double(toks[k + 1], p[k]))
          rep.fail_line(lc.line, facet + ": cannot parse coordinate " + quote(toks[k + 1]));
        const std::string problem = coordinate_problem(p[k]);
        if (!problem.empty()) rep.fail_line(lc.line, facet + ": " + problem);
      }
      poly.push_back(merge(p));
    } else if (kw == "endloop") {
      if (state != State::loop) rep.fail_line(lc.line, "'endloop' without 'outer loop'");
      state = State::facet;
    } else if (kw == "endfacet") {
      if (state != State::facet) rep.fail_line(lc.line, "'endfacet' without 'facet' (or missing 'endloop')");
      if (poly.size() < 3)
        rep.fail_line(facet_line, facet + " has " + std::to_string(poly.size()) + " vertices (at least 3 are needed)");
      soup.polygons.push_back(poly);
      state = State::solid;
    } else if (kw == "endsolid") {
      if (state != State::solid) rep.fail_line(lc.line, "'endsolid' inside a facet (missing 'endfacet')");
      state = State::outside;
    } else {
      rep.fail_line(lc.line, "unexpected " + quote(toks[0]) + " in ASCII STL");
    }
  }
  if (!seen_solid) rep.fail("not an ASCII STL file (no 'solid')");
  if (state != State::outside)
    rep.fail_line(lc.line, "file ends inside a " + std::string(state == State::solid ? "solid" : "facet") +
                               " (truncated file?)");
  return soup;
}

inline Polygon_soup read_stl(const std::string& path, std::string_view data) {
  std::size_t first = 0;
  while (first < data.size() && is_space(data[first])) ++first;
  const bool solid = to_lower(data.substr(first, 5)) == "solid";
  bool binary_size = false;
  std::uint64_t n = 0;
  if (data.size() >= 84) {
    const unsigned char* b = reinterpret_cast<const unsigned char*>(data.data());
    n = static_cast<std::uint64_t>(b[80]) | (static_cast<std::uint64_t>(b[81]) << 8) |
        (static_cast<std::uint64_t>(b[82]) << 16) | (static_cast<std::uint64_t>(b[83]) << 24);
    binary_size = (84 + 50 * n == data.size());
  }
  const bool text = solid && looks_like_text(data);
  if (binary_size && !text) return read_stl_binary(path, data);
  if (text) return read_stl_ascii(path, data);
  if (solid)
    throw Input_error(path + ": not a valid STL file: it starts with 'solid' but contains binary data, and its size " +
                      std::to_string(data.size()) + " bytes does not match a binary STL with the declared " +
                      std::to_string(n) + " triangles (" + std::to_string(84 + 50 * n) + " bytes; truncated file?)");
  if (data.size() < 84)
    throw Input_error(path + ": not a valid STL file: not ASCII (no 'solid') and too short for binary STL (" +
                      std::to_string(data.size()) + " bytes, at least 84 needed)");
  throw Input_error(path + ": not a valid STL file: not ASCII (no 'solid') and the size " + std::to_string(data.size()) +
                    " bytes does not match a binary STL with the declared " + std::to_string(n) + " triangles (" +
                    std::to_string(84 + 50 * n) + " bytes; truncated file?)");
}

// ------------------------------------------------------------------------------------------------ dispatch

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

#endif // CROSSPARAM_INTERNAL_SOUP_READERS_H

// SPDX-License-Identifier: GPL-3.0-or-later
// The PLY reader (ascii, binary little and big endian): the vertex and face elements as a polygon soup.
#ifndef CROSSPARAM_INTERNAL_IO_PLY_H
#define CROSSPARAM_INTERNAL_IO_PLY_H

#include <crossparam/types.h>
#include <crossparam/validation.h>
#include <crossparam/internal/io/text.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace crossparam {
namespace internal {
namespace soup_io {

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

} // namespace soup_io
} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_IO_PLY_H

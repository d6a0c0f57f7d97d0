// SPDX-License-Identifier: GPL-3.0-or-later
// The STL readers (ascii and binary): a triangle soup whose exactly identical corner positions are merged
// into one vertex, numbered in first-seen order.
#ifndef CROSSPARAM_INTERNAL_IO_STL_H
#define CROSSPARAM_INTERNAL_IO_STL_H

#include <crossparam/types.h>
#include <crossparam/validation.h>
#include <crossparam/internal/io/text.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace crossparam {
namespace internal {
namespace soup_io {

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

} // namespace soup_io
} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_IO_STL_H

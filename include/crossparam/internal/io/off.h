// SPDX-License-Identifier: GPL-3.0-or-later
// The OFF reader (also COFF, NOFF, CNOFF, STOFF headers): a polygon soup in file order.
#ifndef CROSSPARAM_INTERNAL_IO_OFF_H
#define CROSSPARAM_INTERNAL_IO_OFF_H

#include <crossparam/types.h>
#include <crossparam/validation.h>
#include <crossparam/internal/io/text.h>

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace crossparam {
namespace internal {
namespace soup_io {

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

} // namespace soup_io
} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_IO_OFF_H

// SPDX-License-Identifier: GPL-3.0-or-later
// The OBJ reader: vertices (v) and faces (f, fo) as a polygon soup in file order; every other statement is skipped.
#ifndef CROSSPARAM_INTERNAL_IO_OBJ_H
#define CROSSPARAM_INTERNAL_IO_OBJ_H

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

} // namespace soup_io
} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_IO_OBJ_H

// SPDX-License-Identifier: GPL-3.0-or-later
// Textured Wavefront OBJ: positions, texture coordinates per corner (`f v/vt`, seams allowed) and the texture
// image named by the material library; read, and written as OBJ + MTL. The plain mesh readers of io.h drop
// texture coordinates; this reader keeps them.
#ifndef CROSSPARAM_TEXTURED_OBJ_H
#define CROSSPARAM_TEXTURED_OBJ_H

#include <crossparam/attribute_transfer.h>
#include <crossparam/errors.h>
#include <crossparam/io.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace crossparam {

/// A triangle mesh with texture coordinates, as a textured OBJ holds it.
struct Textured_mesh {
  std::vector<std::array<double, 3>> points;
  Mesh_uvs uv; ///< `uv.face_vertices` is the face list (indices into `points`)
  std::string texture; ///< the texture image named by the material (`map_Kd`), a path; empty if none
};

namespace internal {

/// Parses one OBJ index ("7", "-1"): 1-based, negative counts from the end; returns the 0-based index.
inline std::size_t parse_obj_index(const std::string& token, std::size_t count, const std::string& where) {
  long i = 0;
  std::size_t used = 0;
  try {
    i = std::stol(token, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != token.size() || i == 0) throw Input_error(where + ": bad index '" + token + "'");
  const long k = i > 0 ? i - 1 : long(count) + i;
  if (k < 0 || std::size_t(k) >= count) throw Input_error(where + ": index " + token + " out of range");
  return std::size_t(k);
}

/// The `map_Kd` image of the first material of an MTL file (a path relative to the MTL's folder), or empty.
inline std::string read_mtl_texture(const std::filesystem::path& mtl) {
  std::ifstream in(mtl);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string key, value;
    s >> key;
    if (key != "map_Kd") continue;
    std::getline(s >> std::ws, value);
    while (!value.empty() && std::isspace(static_cast<unsigned char>(value.back()))) value.pop_back();
    if (!value.empty()) return (mtl.parent_path() / value).string();
  }
  return {};
}

} // namespace internal

/// \brief Reads an OBJ with texture coordinates: `v`, `vt`, `f` with `v/vt` or `v/vt/vn` corners (polygons
/// are split into fans), `mtllib` (the first material's `map_Kd` becomes `texture`). Other lines are ignored.
/// \throws Input_error for an unreadable file, a malformed line, an index out of range, or a face corner
///         without texture coordinates
inline Textured_mesh read_textured_obj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Input_error(path + ": cannot open the file");
  Textured_mesh out;
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    const std::string where = path + ": line " + std::to_string(n);
    std::istringstream s(line);
    std::string key;
    if (!(s >> key) || key[0] == '#') continue;
    if (key == "v") {
      std::array<double, 3> p{};
      if (!(s >> p[0] >> p[1] >> p[2]) || !std::isfinite(p[0] + p[1] + p[2])) throw Input_error(where + ": bad vertex");
      out.points.push_back(p);
    } else if (key == "vt") {
      std::array<double, 2> t{};
      if (!(s >> t[0] >> t[1]) || !std::isfinite(t[0] + t[1])) throw Input_error(where + ": bad texture coordinate");
      out.uv.uvs.push_back(t);
    } else if (key == "f") {
      std::vector<std::size_t> vs, ts;
      std::string corner;
      while (s >> corner) {
        const std::size_t slash = corner.find('/');
        if (slash == std::string::npos) throw Input_error(where + ": a face corner without texture coordinates");
        const std::size_t slash2 = corner.find('/', slash + 1);
        const std::string vt = corner.substr(slash + 1, slash2 == std::string::npos ? std::string::npos : slash2 - slash - 1);
        if (vt.empty()) throw Input_error(where + ": a face corner without texture coordinates");
        vs.push_back(internal::parse_obj_index(corner.substr(0, slash), out.points.size(), where));
        ts.push_back(internal::parse_obj_index(vt, out.uv.uvs.size(), where));
      }
      if (vs.size() < 3) throw Input_error(where + ": a face with fewer than three corners");
      for (std::size_t i = 1; i + 1 < vs.size(); ++i) {
        out.uv.face_vertices.push_back({vs[0], vs[i], vs[i + 1]});
        out.uv.face_uvs.push_back({ts[0], ts[i], ts[i + 1]});
      }
    } else if (key == "mtllib" && out.texture.empty()) {
      std::string name;
      std::getline(s >> std::ws, name);
      while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
      out.texture = internal::read_mtl_texture(std::filesystem::path(path).parent_path() / name);
    }
  }
  if (out.uv.face_vertices.empty()) throw Input_error(path + ": no faces");
  return out;
}

/// \brief Writes a textured mesh as `obj_path` (OBJ with `v`, `vt` per corner and `f v/vt`) and an MTL file
/// next to it (same name, extension `.mtl`) whose material shows `texture_file` (a file name in the OBJ's
/// folder). Each file is written atomically.
/// \param points the mesh's points
/// \param faces its faces (indices into `points`)
/// \param uvs per face, its corners' texture coordinates
inline void write_textured_obj(const std::string& obj_path, const std::vector<std::array<double, 3>>& points,
                               const std::vector<std::array<std::size_t, 3>>& faces, const std::vector<Corner_uvs>& uvs,
                               const std::string& texture_file) {
  if (uvs.size() != faces.size()) throw Input_error("textured OBJ: one corner triple of texture coordinates per face is needed");
  const std::filesystem::path obj(obj_path);
  std::filesystem::path mtl = obj;
  mtl.replace_extension(".mtl");
  write_file_atomically(mtl.string(), [&](std::ostream& o) {
    o << "newmtl textured\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nmap_Kd " << texture_file << "\n";
  });
  write_file_atomically(obj_path, [&](std::ostream& o) {
    o << "mtllib " << mtl.filename().string() << "\n";
    for (const auto& p : points) o << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << "\n";
    for (const Corner_uvs& c : uvs)
      for (const auto& t : c) o << "vt " << t[0] << ' ' << t[1] << "\n";
    o << "usemtl textured\n";
    for (std::size_t f = 0; f < faces.size(); ++f) {
      o << "f";
      for (int k = 0; k < 3; ++k) o << ' ' << faces[f][std::size_t(k)] + 1 << '/' << 3 * f + std::size_t(k) + 1;
      o << "\n";
    }
  });
}

} // namespace crossparam

#endif // CROSSPARAM_TEXTURED_OBJ_H

// SPDX-License-Identifier: GPL-3.0-or-later
// Transfer through a cross-parameterization (paper §6): per-vertex data of one mesh carried to every vertex of
// the other mesh as the user gave it, and texture coordinates of the source carried corner by corner onto the
// target-shaped mesh of a compatible remeshing.
//
// A vertex v of the receiving mesh takes the data at its image under the map (F^-1(v) on the source for data
// of the source): the image lies in an input face of the giving mesh, and the data there is the barycentric
// interpolation of its corners' values (real-valued data: a field linear on the giving mesh arrives exactly,
// up to rounding), or the value of the corner nearest the image, i.e. with the largest barycentric coordinate
// (integer labels: a label constant over a region stays constant over its image).
//
// Texture coordinates are per corner (an OBJ's `f v/vt`): a seam gives one vertex several (u, v). The
// target-shaped mesh of a compatible remeshing has the face list of the source refined by splits, so every one
// of its faces lies inside one input source face; its three corners take that face's corner coordinates,
// interpolated at their barycentric coordinates in it. One face never mixes the coordinates of two source
// faces, so a face next to a seam takes the chart of its own source face.
#ifndef CROSSPARAM_ATTRIBUTE_TRANSFER_H
#define CROSSPARAM_ATTRIBUTE_TRANSFER_H

#include <crossparam/errors.h>
#include <crossparam/types.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace crossparam {

/// Per-vertex data: one row per vertex (input order), the same number of columns in every row.
using Vertex_data = std::vector<std::vector<double>>;

/// Texture coordinates (u, v) of the three corners of a face.
using Corner_uvs = std::array<std::array<double, 2>, 3>;

namespace internal {

/// Where vertex v of mesh `to` lands on the other mesh of `cp`, as the user gave it.
template <class CP>
Input_location image_of_input_vertex(const CP& cp, Mesh_side to, std::size_t v) {
  return to == Mesh_side::target ? cp.target_vertex_to_source_input(v) : cp.source_vertex_to_target_input(v);
}

/// The checks shared by the transfers: one row per vertex of the giving mesh, all rows of one width.
inline std::size_t check_vertex_data_shape(std::size_t rows, std::size_t expected, const std::string& what) {
  if (rows != expected)
    throw Input_error(what + ": " + std::to_string(rows) + " rows for a mesh of " + std::to_string(expected) +
                      " vertices (one row per vertex is needed)");
  return rows;
}

} // namespace internal

/// \brief Carries per-vertex data of mesh `from` of the map `cp` to every vertex of the other mesh, as given
/// by the user (its input vertices, in input order), by barycentric interpolation at the vertex's image.
///
/// \tparam CP a `Cross_parameterization`
/// \param cp the map
/// \param from the mesh whose vertices carry `data` (`Mesh_side::source`: the data goes to the target's
///        vertices through F^-1; `Mesh_side::target`: to the source's through F)
/// \param data one row per input vertex of mesh `from`, any number of columns (the same in every row)
/// \returns one row per input vertex of the other mesh, as many columns as `data`
/// \throws Input_error if `data` has not one row per vertex, or rows of different widths
template <class CP>
Vertex_data transfer_vertex_data(const CP& cp, Mesh_side from, const Vertex_data& data) {
  const Mesh_side to = other_side(from);
  internal::check_vertex_data_shape(data.size(), cp.input_vertices(from), "vertex data");
  const std::size_t width = data.empty() ? 0 : data[0].size();
  for (std::size_t i = 0; i < data.size(); ++i)
    if (data[i].size() != width)
      throw Input_error("vertex data: row " + std::to_string(i) + " has " + std::to_string(data[i].size()) +
                        " columns, row 0 has " + std::to_string(width));
  Vertex_data out(cp.input_vertices(to), std::vector<double>(width, 0.0));
  for (std::size_t v = 0; v < out.size(); ++v) {
    const Input_location l = internal::image_of_input_vertex(cp, to, v);
    const std::array<std::size_t, 3>& corners = cp.input_face_vertices(from, l.face);
    for (int i = 0; i < 3; ++i)
      for (std::size_t k = 0; k < width; ++k) out[v][k] += l.b[i] * data[corners[i]][k];
  }
  return out;
}

/// \brief Carries integer labels of the vertices of mesh `from` of the map `cp` to every input vertex of the
/// other mesh: each takes the label of the corner nearest its image (the largest barycentric coordinate; ties
/// go to the first corner of the face in input order).
/// \throws Input_error if `labels` has not one entry per input vertex of mesh `from`
template <class CP>
std::vector<long> transfer_vertex_labels(const CP& cp, Mesh_side from, const std::vector<long>& labels) {
  const Mesh_side to = other_side(from);
  internal::check_vertex_data_shape(labels.size(), cp.input_vertices(from), "vertex labels");
  std::vector<long> out(cp.input_vertices(to), 0);
  for (std::size_t v = 0; v < out.size(); ++v) {
    const Input_location l = internal::image_of_input_vertex(cp, to, v);
    int best = 0;
    for (int i = 1; i < 3; ++i)
      if (l.b[i] > l.b[best]) best = i;
    out[v] = labels[cp.input_face_vertices(from, l.face)[std::size_t(best)]];
  }
  return out;
}

/// Texture coordinates of a mesh, as an OBJ file stores them: a pool of (u, v) pairs and, per face (input
/// order), the pool indices of its three corners in the face's own corner order. `face_vertices[f]` are the
/// vertex indices of face f in the same order, so that a corner is found by its vertex.
struct Mesh_uvs {
  std::vector<std::array<double, 2>> uvs;
  std::vector<std::array<std::size_t, 3>> face_uvs;
  std::vector<std::array<std::size_t, 3>> face_vertices;
};

/// \brief Texture coordinates for every corner of a refinement of a textured mesh: per refined face, its
/// corners' (u, v) interpolated in the input face holding it (`Compatible_remesher::source_face_locations()`).
/// Use them with the target-shaped mesh of the remeshing (same face list) to show the source's texture on the
/// target's shape, or with any morph or blend of the compatible meshes.
///
/// \param locations per refined face, the input face holding it and its corners' barycentric coordinates
/// \param source the texture coordinates of the input mesh
/// \returns per refined face, the (u, v) of its corners in its own corner order
/// \throws Input_error if a location names a face `source` has not, or a face whose vertices differ from those
///         of `source.face_vertices` (the texture belongs to another mesh), or a pool index out of range
inline std::vector<Corner_uvs> transfer_corner_uvs(const std::vector<Input_face_location>& locations,
                                                   const Mesh_uvs& source) {
  if (source.face_uvs.size() != source.face_vertices.size())
    throw Input_error("texture coordinates: one corner triple of texture coordinates per face is needed");
  std::vector<Corner_uvs> out;
  out.reserve(locations.size());
  for (const Input_face_location& l : locations) {
    if (l.face >= source.face_uvs.size())
      throw Input_error("texture coordinates: face " + std::to_string(l.face) + " has none");
    // The pool index of each of the location's corners, matched by vertex.
    std::array<std::size_t, 3> uv_of{};
    for (int i = 0; i < 3; ++i) {
      int found = -1;
      for (int j = 0; j < 3; ++j)
        if (source.face_vertices[l.face][std::size_t(j)] == l.vertices[std::size_t(i)]) found = j;
      if (found < 0)
        throw Input_error("texture coordinates: face " + std::to_string(l.face) +
                          " has other vertices than the mesh that was remeshed");
      uv_of[std::size_t(i)] = source.face_uvs[l.face][std::size_t(found)];
      if (uv_of[std::size_t(i)] >= source.uvs.size())
        throw Input_error("texture coordinates: index out of range in face " + std::to_string(l.face));
    }
    Corner_uvs c{};
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i)
        for (int d = 0; d < 2; ++d) c[std::size_t(k)][std::size_t(d)] += l.corners[std::size_t(k)][std::size_t(i)] * source.uvs[uv_of[std::size_t(i)]][std::size_t(d)];
    out.push_back(c);
  }
  return out;
}

} // namespace crossparam

#endif // CROSSPARAM_ATTRIBUTE_TRANSFER_H

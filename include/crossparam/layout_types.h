// SPDX-License-Identifier: GPL-3.0-or-later
// Result types of the patch layout (Kraevoy & Sheffer 2004, §3): the layouts of both meshes over their common
// base mesh, the edge splits that made them, the layout's statistics and the result of its independent
// verification. Both patch_layout.h (which computes a layout) and layout_verification.h (which checks one)
// include this header; neither includes the other's algorithms through it.
#ifndef CROSSPARAM_LAYOUT_TYPES_H
#define CROSSPARAM_LAYOUT_TYPES_H

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace crossparam {

/// One edge split performed while building a layout: edge (u, v) was split at u + t (v - u), creating
/// vertex w. Indices are vertex indices in the order "original vertices, then appended ones".
struct Edge_split {
  std::size_t u = 0;
  std::size_t v = 0;
  std::size_t w = 0;
  double t = 0.5;
};

/// Counts and timings of one layout computation (paper §3).
struct Layout_statistics {
  std::size_t features = 0;
  std::size_t edge_paths = 0;             ///< path pairs traced on the edge graphs by PathMatch (§3.1)
  std::size_t face_paths = 0;             ///< path pairs added by make-simple and triangulation (§3.2)
  std::size_t face_traced_source = 0;     ///< of those, paths that needed the face graph on the source
  std::size_t face_traced_target = 0;     ///< ... and on the target
  std::size_t splits_source = 0;          ///< edge splits on the source
  std::size_t splits_target = 0;          ///< edge splits on the target
  std::size_t flips = 0;                  ///< path flips (§3.3)
  std::size_t guided_paths = 0;           ///< pairs replaced by a more consistent descriptor-guided variant
  std::size_t straightened = 0;           ///< path pairs replaced by shorter ones once the layout was complete
  std::size_t adjacency_splits_source = 0; ///< splits of §4.2 (edges joining two boundary vertices of a patch)
  std::size_t adjacency_splits_target = 0;
  std::size_t rejected_blocking = 0;      ///< candidate pairs dropped by the blocking test
  std::size_t sector_recomputations = 0;  ///< paths recomputed inside the matching sector (Update, rule 3)
  std::size_t path_recomputations = 0;    ///< paths recomputed after their vertices were taken (Update, 1-2)
  double seconds_edge_paths = 0;
  double seconds_face_paths = 0;
  double seconds_flips = 0;
  double seconds_straightening = 0;
  double seconds_total = 0;
};

/// The layout of one mesh. Vertex and face indices are positions in `vertices(tm)` / `faces(tm)` order of
/// the refined mesh: the original vertices first, in their original order, then one vertex per split.
struct Mesh_layout {
  std::size_t original_vertices = 0;
  std::size_t original_faces = 0;
  std::vector<Edge_split> splits;              ///< the edge splits, in the order performed
  std::vector<int> face_triangle;              ///< per face of the refined mesh: its base-triangle id
  std::vector<std::vector<std::size_t>> paths; ///< per path id: its vertices, from base_edges[p][0] to [1]
  std::vector<std::size_t> feature_vertices;   ///< per feature: its vertex
};

/// Topologically identical triangular layouts of a source and a target mesh over one base mesh.
struct Patch_layout {
  /// Base triangles as feature indices, counter-clockwise seen from outside. Triangle ids name
  /// corresponding patches on both meshes.
  std::vector<std::array<std::size_t, 3>> base_triangles;
  /// Per path id: its two features. Path p on the source matches path p on the target.
  std::vector<std::array<std::size_t, 2>> base_edges;
  Mesh_layout source;
  Mesh_layout target;
  Layout_statistics statistics;
};

/// Result of `verify_patch_layouts` (layout_verification.h): `valid`, or the first problem found in `message`.
struct Layout_verification {
  bool valid = true;
  std::string message;
};

} // namespace crossparam

#endif // CROSSPARAM_LAYOUT_TYPES_H

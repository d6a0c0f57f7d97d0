// SPDX-License-Identifier: GPL-3.0-or-later
// Self-intersections of the target-shaped mesh M_st (an addition to the paper): pairs of its faces that
// intersect (CGAL's self_intersections) away from where the target intersects itself, and their removal by
// refinement: the longest edge of each such face is split on the source, its image F of the split point, as the
// refinement of §5.3 does. A finer M_st follows the target more closely, and the target does not intersect
// itself there.
#ifndef CROSSPARAM_INTERNAL_REMESHING_SELF_INTERSECTIONS_H
#define CROSSPARAM_INTERNAL_REMESHING_SELF_INTERSECTIONS_H

#include <crossparam/internal/remeshing/fold_repair.h>
#include <crossparam/internal/remeshing/remesh_state.h>

#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <iterator>
#include <utility>
#include <vector>

namespace crossparam {
namespace internal {

/// The points of M_st as a vertex point map of the remeshed mesh.
struct Image_point_map {
  using key_type = WV;
  using value_type = Point_3;
  using reference = const Point_3&;
  using category = boost::readable_property_map_tag;
  const std::vector<Point_3>* pos;
  friend reference get(const Image_point_map& m, WV v) { return (*m.pos)[v]; }
};

/// Finds the intersecting face pairs of M_st that the target does not explain, and refines them away.
class Self_intersection_repair {
public:
  /// Finds the target's own intersecting faces (their neighbourhood is where M_st may intersect too).
  explicit Self_intersection_repair(Remesh_state& state) : s(state) {
    std::vector<std::pair<WF, WF>> pairs;
    CGAL::Polygon_mesh_processing::self_intersections<CGAL::Sequential_tag>(s.target.m, std::back_inserter(pairs));
    std::vector<WF> own;
    for (const auto& p : pairs) own.push_back(p.first), own.push_back(p.second);
    std::sort(own.begin(), own.end());
    own.erase(std::unique(own.begin(), own.end()), own.end());
    if (!own.empty()) {
      own_tree.insert(own.begin(), own.end(), s.target.m);
      own_tree.build();
      own_tree.accelerate_distance_queries();
    }
  }

  /// The intersecting face pairs of M_st (its current points) except those with both faces near a face of
  /// the target that intersects the target: within the face's longest edge plus ε of it.
  std::vector<std::pair<WF, WF>> new_pairs() const {
    const auto& m = s.mesh.m;
    std::vector<std::pair<WF, WF>> pairs, out;
    CGAL::Polygon_mesh_processing::self_intersections<CGAL::Sequential_tag>(
        m, std::back_inserter(pairs), CGAL::parameters::vertex_point_map(Image_point_map{&s.pos}));
    for (const auto& p : pairs)
      if (!(near_own(p.first) && near_own(p.second))) out.push_back(p);
    return out;
  }

  /// Splits the longest edge (in M_st) of every face of `pairs` near its middle (split_near_middle(), with
  /// its validity test; where it would fold M_st, with a local fold repair). Returns the number of vertices
  /// added.
  std::size_t refine(const std::vector<std::pair<WF, WF>>& pairs) {
    const auto& m = s.mesh.m;
    std::vector<std::pair<WV, WV>> edges;
    for (const auto& p : pairs)
      for (WF f : {p.first, p.second}) {
        const WH h = s.longest_edge(f);
        WV u = m.source(h), v = m.target(h);
        if (v < u) std::swap(u, v);
        edges.push_back({u, v});
      }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    std::size_t splits = 0;
    for (const auto& e : edges)
      if (m.halfedge(e.first, e.second) != WH()) {
        const std::size_t v0 = m.number_of_vertices();
        // A split refused because it would fold M_st is made with a local fold repair (with_repair()).
        if (s.split_near_middle(e.first, e.second, split_points) ||
            with_repair(s, [&] { return s.split_near_middle(e.first, e.second, split_points); }))
          splits += m.number_of_vertices() - v0;
      }
    return splits;
  }

private:
  /// Points of an edge tried by refine(): the midpoint and the six others of split_near_middle().
  static constexpr int split_points = 7;

  bool near_own(WF f) const {
    if (own_tree.empty()) return false;
    const auto& m = s.mesh.m;
    const WH h = s.longest_edge(f);
    const Point_3 &a = s.pos[m.source(h)], &b = s.pos[m.target(h)], &c = s.pos[m.target(m.next(h))];
    const double reach = std::sqrt(CGAL::squared_distance(a, b)) + s.eps;
    return own_tree.squared_distance(CGAL::centroid(a, b, c)) <= reach * reach;
  }

  Remesh_state& s;
  Target_tree own_tree; ///< the target's faces that intersect another face of the target
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_SELF_INTERSECTIONS_H

// SPDX-License-Identifier: GPL-3.0-or-later
// A chart of a piece of a triangulated surface: faces grown around a point into a topological disk, flattened
// onto the unit disk by mean-value coordinates (Floater 2003) with the disk's boundary laid on the circle by
// arc length. The weights are positive and the boundary convex, so the flattening is one-to-one (Floater's
// theorem on convex-combination maps); it is checked all the same, face by face, with the exact orientation
// predicate. Points move between the surface and the chart through barycentric coordinates, so a point of
// the chart maps back to a point on the surface exactly, wherever the surface bends.
#ifndef CROSSPARAM_INTERNAL_REMESHING_DISK_CHART_H
#define CROSSPARAM_INTERNAL_REMESHING_DISK_CHART_H

#include <crossparam/internal/base_locator.h>
#include <crossparam/internal/base_parameterization.h>

#include <Eigen/Dense>

#include <cmath>
#include <optional>
#include <queue>
#include <vector>

namespace crossparam {
namespace internal {

class Disk_chart {
public:
  /// The chart of the faces of m grown from `seeds[0]` towards the nearest faces (centroid distance to
  /// `center`) while they stay within `radius` of it, face `direction` (unit) with a cosine of at least
  /// `min_cosine` (so that the disk does not wrap around a limb), and keep the set a topological disk (a face
  /// is added across one edge of the boundary with its third corner new, or across two consecutive ones).
  /// Empty if some seed is left out, if the disk exceeds `max_faces`, or if the flattening fails its check.
  static std::optional<Disk_chart> grow(const Work_mesh& m, const std::vector<WF>& seeds, const Point_3& center,
                                        double radius, const Kernel::Vector_3& direction, double min_cosine,
                                        std::size_t max_faces = 20000) {
    Disk_chart c;
    c.face_slot_.assign(m.number_of_faces(), -1);
    c.vertex_slot_.assign(m.number_of_vertices(), -1);
    std::vector<int> vertex_faces(m.number_of_vertices(), 0);
    auto distance = [&](WF f) {
      const WH h = m.halfedge(f);
      return std::sqrt(CGAL::squared_distance(center, CGAL::centroid(m.point(m.source(h)), m.point(m.target(h)),
                                                                       m.point(m.target(m.next(h))))));
    };
    auto facing = [&](WF f) {
      const WH h = m.halfedge(f);
      const Kernel::Vector_3 n = triangle_normal(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))));
      return n * direction >= min_cosine * std::sqrt(n * n);
    };
    auto in_disk = [&](WF f) { return f != Work_mesh::null_face() && c.face_slot_[f] >= 0; };
    auto add = [&](WF f) {
      c.face_slot_[f] = int(c.faces_.size());
      c.faces_.push_back(f);
      for (WV v : CGAL::vertices_around_face(m.halfedge(f), m)) ++vertex_faces[v];
    };
    // Whether adding f keeps the set a disk.
    auto keeps_disk = [&](WF f) {
      int shared = 0;
      WH lone = WH();
      for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m))
        if (in_disk(m.face(m.opposite(h)))) ++shared, lone = h;
      if (shared == 1) return vertex_faces[m.target(m.next(lone))] == 0;
      return shared == 2;
    };
    using Entry = std::pair<double, WF>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    auto push_neighbours = [&](WF f) {
      for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        const WF g = m.face(m.opposite(h));
        if (g != Work_mesh::null_face() && !in_disk(g)) queue.push({distance(g), g});
      }
    };
    if (seeds.empty() || !facing(seeds.front())) return std::nullopt;
    add(seeds.front());
    push_neighbours(seeds.front());
    while (!queue.empty() && queue.top().first <= radius) {
      const WF f = queue.top().second;
      queue.pop();
      if (in_disk(f) || !keeps_disk(f) || !facing(f)) continue;
      if (c.faces_.size() >= max_faces) return std::nullopt;
      add(f);
      push_neighbours(f);
    }
    for (WF s : seeds)
      if (!in_disk(s)) return std::nullopt;
    if (!c.flatten(m)) return std::nullopt;
    return c;
  }

  bool contains(WF f) const { return std::size_t(f) < face_slot_.size() && face_slot_[f] >= 0; }
  const std::vector<WF>& faces() const { return faces_; }

  /// The chart point of a location on a face of the chart.
  Eigen::Vector2d at(const Work_mesh& m, const Work_location& l) const {
    const std::array<Eigen::Vector2d, 3> q = corners(m, l.face);
    return l.b[0] * q[0] + l.b[1] * q[1] + l.b[2] * q[2];
  }

  /// The location on the surface of chart point p; false if p is outside the chart.
  bool locate(const Work_mesh& m, const Eigen::Vector2d& p, Work_location& out) const {
    for (WF f : faces_) {
      const std::array<Eigen::Vector2d, 3> q = corners(m, f);
      const double area = cross(q[1] - q[0], q[2] - q[0]);
      std::array<double, 3> b{cross(q[2] - q[1], p - q[1]) / area, cross(q[0] - q[2], p - q[2]) / area,
                              cross(q[1] - q[0], p - q[0]) / area};
      constexpr double slack = -1e-12;
      if (!(b[0] >= slack && b[1] >= slack && b[2] >= slack)) continue;
      double sum = 0;
      for (double& x : b) sum += (x = std::max(0.0, x));
      for (double& x : b) x /= sum;
      out = {f, b};
      return true;
    }
    return false;
  }

private:
  /// The chart points of f's corners in the order of Work_location: source(h), target(h), target(next(h)).
  std::array<Eigen::Vector2d, 3> corners(const Work_mesh& m, WF f) const {
    const WH h = m.halfedge(f);
    return {uv_[vertex_slot_[m.source(h)]], uv_[vertex_slot_[m.target(h)]], uv_[vertex_slot_[m.target(m.next(h))]]};
  }
  static double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

  /// Boundary on the unit circle by arc length, interior by mean-value coordinates; then the exact check.
  bool flatten(const Work_mesh& m) {
    for (WF f : faces_)
      for (WV v : CGAL::vertices_around_face(m.halfedge(f), m))
        if (vertex_slot_[v] < 0) vertex_slot_[v] = int(vertices_.size()), vertices_.push_back(v);
    const std::size_t n = vertices_.size();
    // The boundary: halfedges with a chart face on their left and none on their right, one per boundary vertex.
    std::vector<WH> out(n, WH());
    std::size_t boundary_edges = 0;
    for (WF f : faces_)
      for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        const WF g = m.face(m.opposite(h));
        if (g != Work_mesh::null_face() && contains(g)) continue;
        if (out[vertex_slot_[m.source(h)]] != WH()) return false; // a vertex twice on the boundary
        out[vertex_slot_[m.source(h)]] = h;
        ++boundary_edges;
      }
    if (boundary_edges < 3) return false;
    std::vector<WH> cycle;
    double length = 0;
    WH start = WH();
    for (WH h : out)
      if (h != WH()) start = h;
    for (WH h = start;;) {
      cycle.push_back(h);
      length += std::sqrt(CGAL::squared_distance(m.point(m.source(h)), m.point(m.target(h))));
      h = out[vertex_slot_[m.target(h)]];
      if (h == WH() || cycle.size() > boundary_edges) return false;
      if (h == cycle.front()) break;
    }
    if (cycle.size() != boundary_edges || !(length > 0)) return false; // more than one boundary loop
    uv_.assign(n, Eigen::Vector2d(0, 0));
    std::vector<char> fixed(n, 0);
    double run = 0;
    for (WH h : cycle) {
      const double angle = 2 * CGAL_PI * run / length;
      const int i = vertex_slot_[m.source(h)];
      uv_[i] = Eigen::Vector2d(std::cos(angle), std::sin(angle));
      fixed[i] = 1;
      run += std::sqrt(CGAL::squared_distance(m.point(m.source(h)), m.point(m.target(h))));
    }
    if (!mean_value_layout(m, vertices_, [this](WV v) { return vertex_slot_[v]; }, fixed, uv_)) return false;
    for (WF f : faces_) {
      std::array<Kernel::Point_2, 3> q;
      int i = 0;
      for (WV v : CGAL::vertices_around_face(m.halfedge(f), m)) {
        const Eigen::Vector2d& p = uv_[vertex_slot_[v]];
        if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return false;
        q[i++] = Kernel::Point_2(p.x(), p.y());
      }
      if (CGAL::orientation(q[0], q[1], q[2]) != CGAL::POSITIVE) return false;
    }
    return true;
  }

  std::vector<WF> faces_;
  std::vector<int> face_slot_, vertex_slot_;
  std::vector<WV> vertices_;
  std::vector<Eigen::Vector2d> uv_;
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_DISK_CHART_H

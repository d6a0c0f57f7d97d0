// SPDX-License-Identifier: GPL-3.0-or-later
// The strict repair (an addition to the paper): the last step of the remeshing, which works to the definitions
// of the independent verifier (remeshing_verification.h). A face of M_st is bad when it is flipped by the
// standard rule (its normal more than 90° from the target's at the point of the target nearest its centroid)
// or when it belongs to a pair of faces that intersect away from where the target folds itself (its faces on
// creases or in self-intersecting pairs, remeshing_verification.h). Bad
// faces get edge flips that keep the source's surface, then refinement in the target's metric, new vertices at
// F of source points (the map is one-to-one and orientation preserving, so a fine enough M_st follows the
// target), and what the refinement leaves flipped is untangled along the target; last, the disk of faces
// around a bad face is laid out anew along the target (disk_embedding.h). Flips at the target's own
// folds are repaired too, although the verifier lets them pass: the fewer the better.
#ifndef CROSSPARAM_INTERNAL_REMESHING_STRICT_REPAIR_H
#define CROSSPARAM_INTERNAL_REMESHING_STRICT_REPAIR_H

#include <crossparam/internal/remeshing/disk_embedding.h>
#include <crossparam/internal/remeshing/fold_repair.h>
#include <crossparam/internal/remeshing/gap_refinement.h>
#include <crossparam/internal/remeshing/remesh_state.h>
#include <crossparam/internal/remeshing/target_untangling.h>
#include <crossparam/remeshing_verification.h>

#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <array>
#include <optional>
#include <set>
#include <utility>
#include <vector>

namespace crossparam {
namespace internal {

/// What strict_repair() did.
struct Strict_repair_result {
  std::size_t flipped_before = 0;           ///< faces flipped by the standard rule when it started
  std::size_t intersecting_before = 0;      ///< faces in new self-intersecting pairs when it started
  std::size_t flipped_after = 0;            ///< and when it ended
  std::size_t intersecting_after = 0;
  std::size_t splits = 0;                   ///< vertices it added
  std::size_t rounds = 0;                   ///< passes over the bad faces
  std::size_t flips = 0;                    ///< edge flips kept (Remesh_state::flip())
  std::size_t disks = 0;                    ///< disks re-embedded (embed_disk())
  bool work_bound_reached = false;          ///< whether it stopped at strict_repair_work
};

/// The strict repair's work bound, in the work of Strict_checker::local_bad() (faces scanned plus faces tested
/// for intersections; about 0.6 µs each on one core, with the repairs it judges): on the bench at most 1e8
/// (shrec_383_385, 65 s; horse0_horse7 7e7, lion_cat 6e6), so three times that stops only repairs that would
/// run for minutes more (feline_g2's ran for over 15 minutes).
constexpr std::size_t strict_repair_work = 300000000;

/// The faces of M_st that the verifier would reject, found with the same definitions.
class Strict_checker {
public:
  /// Weight of a face beyond the tolerance in local_bad(): more than any region holds faces, so that no repair
  /// trades flips or intersections for it.
  static constexpr std::size_t far_weight = 1000000;
  /// M_st's points as a property map of the source's vertices.
  auto positions() const { return CGAL::make_property_map(s.pos); }
  /// Finds the target's own folds once (its faces on creases or in self-intersecting pairs): a pair of M_st's
  /// faces that intersect within ε of one of them is the target's own, as the verifier counts it.
  Strict_checker(Remesh_state& state, Target_untangler& standard, double keep_within = 0)
      : s(state), flips(standard), keep_within(keep_within) {
    std::vector<std::pair<WF, WF>> pairs;
    CGAL::Polygon_mesh_processing::self_intersections(faces(s.target.m), s.target.m, std::back_inserter(pairs));
    target_folds = fold_face_boxes(s.target.m, pairs);
  }

  /// Per face of M_st: whether it is flipped by the standard rule or in a new self-intersecting pair; counts
  /// of both in `flipped` and `intersecting`.
  std::vector<char> bad_faces(std::size_t& flipped, std::size_t& intersecting) const {
    const auto& m = s.mesh.m;
    std::vector<char> bad(m.number_of_faces(), 0);
    flipped = 0, intersecting = 0;
    for (WF f : m.faces())
      if (flips.flipped(f)) bad[f] = 1, ++flipped;
    std::vector<std::pair<WF, WF>> pairs; // M_st: the source's connectivity at the points s.pos
    CGAL::Polygon_mesh_processing::self_intersections(faces(m), m, std::back_inserter(pairs),
                                                      CGAL::parameters::vertex_point_map(positions()));
    for (const auto& p : pairs) {
      if (near_target_pair(face_box(p.first) + face_box(p.second))) continue;
      for (WF f : {p.first, p.second}) intersecting += !(bad[f] & 2), bad[f] |= 2;
    }
    return bad;
  }

  /// The bad figure of a region: faces of `region` flipped by the standard rule or needles (needle_triangle():
  /// their normal is rounding, and the verifier, which reads the output in the input's coordinates, may find
  /// them flipped or intersecting where these tests do not), plus the face pairs with a face in `region` that
  /// intersect away from the target's own folds; with `keep_within` > 0, plus far_weight
  /// for each face of `region` not certified within that distance of the target (Target_untangler::far()): a
  /// repair is then never bought with such a face.
  std::size_t local_bad(const std::vector<WF>& region) const {
    const auto& m = s.mesh.m;
    std::size_t n = 0;
    CGAL::Bbox_3 box;
    for (WF f : region) {
      n += flips.flipped(f) + needle(f) + (keep_within > 0 && flips.far(f, keep_within) ? far_weight : 0);
      box += face_box(f);
    }
    std::vector<char> in(m.number_of_faces(), 0);
    for (WF f : region) in[f] = 1;
    std::vector<WF> candidates;
    for (WF f : m.faces())
      if (CGAL::do_overlap(box, face_box(f))) candidates.push_back(f);
    work_ += m.number_of_faces() + candidates.size();
    std::vector<std::pair<WF, WF>> pairs;
    CGAL::Polygon_mesh_processing::self_intersections(candidates, m, std::back_inserter(pairs),
                                                      CGAL::parameters::vertex_point_map(positions()));
    for (const auto& p : pairs)
      if ((in[p.first] || in[p.second]) && !near_target_pair(face_box(p.first) + face_box(p.second))) ++n;
    return n;
  }

  /// The work of local_bad() so far: faces scanned, plus faces tested for intersections.
  std::size_t work() const { return work_; }

private:
  bool needle(WF f) const {
    const auto& m = s.mesh.m;
    const WH h = m.halfedge(f);
    return needle_triangle(s.pos[m.source(h)], s.pos[m.target(h)], s.pos[m.target(m.next(h))], s.eps);
  }
  CGAL::Bbox_3 face_box(WF f) const {
    const auto& m = s.mesh.m;
    CGAL::Bbox_3 b;
    for (WV v : CGAL::vertices_around_face(m.halfedge(f), m)) b += s.pos[v].bbox();
    return b;
  }
  bool near_target_pair(const CGAL::Bbox_3& b) const { return meets_grown(b, s.eps, target_folds); }

  Remesh_state& s;
  Target_untangler& flips;
  double keep_within; ///< the distance beyond which local_bad() counts a face (0: it does not)
  std::vector<CGAL::Bbox_3> target_folds; ///< the target's faces on creases or in self-intersecting pairs
  mutable std::size_t work_ = 0;
};

/// The faces around the corners of f and their neighbours (f's two-ring of faces).
inline std::vector<WF> two_ring(const Remesh_state& s, WF f) {
  const auto& m = s.mesh.m;
  std::vector<WV> ring;
  for (WV v : CGAL::vertices_around_face(m.halfedge(f), m))
    for (WV w : CGAL::vertices_around_target(m.halfedge(v), m)) ring.push_back(w);
  std::vector<WF> out;
  for (WV v : ring)
    for (WF g : CGAL::faces_around_target(m.halfedge(v), m))
      if (g != WF()) out.push_back(g);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// One repair of bad face f: with `to_f`, f's corners that an earlier step moved off F are put back at F;
/// then f is refined: its longest edge on M_st split near the middle (Remesh_state::split_near_middle(): the
/// parameterization stays one-to-one, exact test; up to two more folds by the all-corners rule are let
/// through, the transaction judging the result), and the faces of that split still flipped split again, up
/// to `depth` levels. Returns the vertices the repair made.
inline std::vector<WV> repair_face(Remesh_state& s, Target_untangler& flips, WF f, int to_f,
                                   int depth, const std::vector<WF>& region) {
  auto& m = s.mesh.m;
  auto back_to_f = [&](WV v) {
    if (s.mesh.vfeature[v] != no_feature) return;
    const Corner c = s.corner_at(s.param[v]);
    s.img[v] = c.img, s.pos[v] = c.pos;
  };
  if (to_f == 1)
    for (WV v : CGAL::vertices_around_face(m.halfedge(f), m)) back_to_f(v);
  if (to_f == 2)
    for (WF g : region)
      for (WV v : CGAL::vertices_around_face(m.halfedge(g), m)) back_to_f(v);
  std::vector<WV> made;
  std::vector<WF> todo{f};
  s.fold_slack = 2;

  for (int level = 0; level < depth && !todo.empty(); ++level) {
    std::vector<WF> next;
    for (WF g : todo) {
      std::vector<std::pair<double, WH>> es;
      for (WH h : CGAL::halfedges_around_face(m.halfedge(g), m))
        es.push_back({-CGAL::squared_distance(s.pos[m.source(h)], s.pos[m.target(h)]), h});
      std::sort(es.begin(), es.end());
      for (const auto& e : es)
        if (s.split_near_middle(m.source(e.second), m.target(e.second), 7)) {
          const WV w = WV(m.number_of_vertices() - 1);
          made.push_back(w);
          for (WF k : CGAL::faces_around_target(m.halfedge(w), m))
            if (k != WF() && flips.flipped(k)) next.push_back(k);
          break;
        }
    }
    todo = std::move(next);
  }
  s.fold_slack = 0;
  return made;
}

/// The rings of the disk repair of the two-mesh remeshing (embed_disk()): as many as the N-way output repair's
/// (output_repair_disk_rings). Ten rings hold a few hundred faces on a regular mesh: one sparse solve and one
/// local_bad() each, so the growth costs little beside the repairs before it; a bad face that a disk of that
/// size does not mend is a fold of the map at a larger scale, which moving M_st along the target does not undo.
constexpr unsigned strict_repair_disk_rings = 10;

/// The disk repair of bad face f of M_st (disk_embedding.h): the faces within r rings of f (r = 1 ...
/// strict_repair_disk_rings, whenever they form a disk) keep their boundary and their feature vertices; every
/// other corner goes to Tutte's embedding in space and then to its nearest point of the target (its source vertex
/// stays: this is M_st leaving F, as the untangling does). A disk is a candidate only if every face of it is
/// certified within `within` of the target (Target_untangler::far()); of the candidates whose bad figure
/// (Strict_checker::local_bad() over `region` and the disk) is below `before`, the lowest is kept (the first at 0
/// ends the growth). Returns whether one was kept; M_st is as before otherwise. The distance from the target to
/// the disk is not tested (the decimation's coverage test, overlay_decimation.h, is not applied here): a disk
/// that cuts across a protrusion of the target would open a gap that only the verifier's two-sided distance sees.
inline bool embed_disk(Remesh_state& s, Target_untangler& flips, const Strict_checker& check, WF f,
                       const std::vector<WF>& region, std::size_t before, double within) {
  const auto& m = s.mesh.m;
  const Remesh_state::Images images = s.images();
  std::vector<WF> disk{f};
  std::size_t best = before;
  std::optional<std::pair<std::vector<std::size_t>, std::vector<Work_location>>> chosen; // free corners, their places
  for (unsigned ring = 1; ring <= strict_repair_disk_rings && best > 0; ++ring) {
    std::vector<WF> grown;
    for (WF g : disk)
      for (WV v : CGAL::vertices_around_face(m.halfedge(g), m))
        for (WF k : CGAL::faces_around_target(m.halfedge(v), m))
          if (k != WF()) grown.push_back(k);
    std::sort(grown.begin(), grown.end());
    grown.erase(std::unique(grown.begin(), grown.end()), grown.end());
    disk = std::move(grown);
    std::vector<std::array<std::size_t, 3>> triples;
    for (WF g : disk) {
      const WH h = m.halfedge(g);
      triples.push_back({std::size_t(m.source(h)), std::size_t(m.target(h)), std::size_t(m.target(m.next(h)))});
    }
    const std::optional<Disk_faces> d = disk_of(triples);
    if (!d) continue; // not a disk (yet: a hole fills at the next ring)
    std::vector<std::size_t> free;
    for (std::size_t i : d->corners) {
      const WV v(static_cast<WV::size_type>(i));
      bool inside = s.mesh.vfeature[v] == no_feature;
      for (WF k : CGAL::faces_around_target(m.halfedge(v), m))
        inside = inside && k != WF() && std::binary_search(disk.begin(), disk.end(), k);
      if (inside) free.push_back(i);
    }
    if (free.empty()) continue;
    const std::optional<std::vector<Point_3>> x =
        tutte_in_space(free, d->edges, [&s](std::size_t i) -> const Point_3& { return s.pos[i]; });
    if (!x) continue;
    std::vector<Work_location> at;
    for (std::size_t i = 0; i < free.size(); ++i) {
      at.push_back(flips.nearest_location((*x)[i]));
      s.img[free[i]] = at.back(), s.pos[free[i]] = s.target_point(at.back());
    }
    const bool near = std::none_of(disk.begin(), disk.end(), [&](WF g) { return flips.far(g, within); });
    std::vector<WF> judged = region;
    judged.insert(judged.end(), disk.begin(), disk.end());
    std::sort(judged.begin(), judged.end());
    judged.erase(std::unique(judged.begin(), judged.end()), judged.end());
    const std::size_t now = near ? check.local_bad(judged) : before;
    if (now < best) best = now, chosen.emplace(free, std::move(at));
    s.restore(images);
  }
  if (!chosen) return false;
  for (std::size_t i = 0; i < chosen->first.size(); ++i)
    s.img[chosen->first[i]] = chosen->second[i], s.pos[chosen->first[i]] = s.target_point(chosen->second[i]);
  return true;
}

/// The strict repair: each bad face of M_st (Strict_checker) repaired as a transaction, kept only if the bad
/// figure of the region around it (Strict_checker::local_bad() over its two-ring and the faces around every
/// vertex the repair moved or made) goes below that of the two-ring before. The repairs, in order, the first
/// kept: the untangling around it (Target_untangler::untangle_around()); repair_face() as M_st is, with its
/// corners back at F, and with its two-ring back at F; one split of its longest edge, then the untangling
/// around each face of the split still flipped (the new vertex gives the untangling a degree of freedom); the disk
/// repair around it (embed_disk()). Passes over the bad faces until a pass keeps nothing,
/// at most `max_passes`, and not past `max_vertices` vertices; a face whose every repair failed is not tried
/// again. No repair that is kept adds a bad face in its region; faces outside the region are not counted, so
/// the total can rise where repairs change them (it falls on the bench; on feline_g2 the flipped faces rose).
/// With `keep_within` > 0 (on the decimated overlay, certified within decimation_margin ε), no repair is kept
/// that leaves a face of its region not certified within that distance of the target (Strict_checker::local_bad()).
inline Strict_repair_result strict_repair(Remesh_state& s, std::size_t max_vertices, unsigned max_passes = 8,
                                          double keep_within = 0) {
  auto& m = s.mesh.m;
  Target_untangler standard(s, Target_untangler::Rule::standard);
  Strict_checker check(s, standard, keep_within);
  // How near the target the disk repair keeps its faces: the decimation's margin on the overlay, else the share
  // of ε that the surface-distance step samples to (gap_refinement.h).
  const double within = keep_within > 0 ? keep_within : gap_sample_share * s.eps;
  Strict_repair_result r;
  const std::size_t v0 = m.number_of_vertices();
  std::size_t flipped = 0, intersecting = 0;
  std::vector<char> bad = check.bad_faces(flipped, intersecting);
  r.flipped_before = flipped, r.intersecting_before = intersecting;
  // Levels of splits of one repair: six take a face down to about an eighth of its size (two levels halve
  // it), enough where F is smooth at that scale; where it is not, deeper splits at F make new folds.
  constexpr int depth = 6;
  // Faces whose every repair failed, by their corners: not tried again (their region is judged the same way).
  std::set<std::array<WV, 3>> failed;
  auto corners = [&m](WF f) {
    const WH h = m.halfedge(f);
    return std::array<WV, 3>{m.source(h), m.target(h), m.target(m.next(h))};
  };
  for (unsigned pass = 0; pass < max_passes && flipped + intersecting > 0; ++pass) {
    std::vector<WF> todo;
    for (WF f : m.faces())
      if (bad[f] && !failed.count(corners(f))) todo.push_back(f);
    std::size_t kept = 0;
    for (WF f : todo) {
      if (m.number_of_vertices() >= max_vertices) break;
      if (check.work() >= strict_repair_work) {
        r.work_bound_reached = true;
        break;
      }
      if (s.budget.stop("the remeshing's strict repair", [&] {
            return "pass " + std::to_string(pass + 1) + " of at most " + std::to_string(max_passes);
          }))
        break;
      const std::vector<WF> region = two_ring(s, f);
      const std::size_t before = check.local_bad(region);
      if (before == 0) continue; // repaired with an earlier face
      bool done = false;
      // First the flips of f's edges that keep the source's surface (Remesh_state::flip()): F stays at every
      // vertex and nothing is added.
      std::vector<WE> edges;
      for (WH h : CGAL::halfedges_around_face(m.halfedge(f), m)) edges.push_back(m.edge(h));
      for (WE e : edges) {
        if (!s.flip(m.halfedge(e))) continue;
        if (check.local_bad(region) < before) {
          done = true;
          break;
        }
        CGAL::Euler::flip_edge(m.halfedge(e), m); // undone: the same two faces again
      }
      if (done) {
        ++kept, ++r.flips;
        continue;
      }
      // to_f: -1 the untangling around f; 0, 1, 2 repair_face() with nothing, f's corners, or its two-ring put
      // back at F; 3 one split, then the untangling around what it leaves flipped; 4 the disk repair (embed_disk()).
      for (int to_f : {-1, 0, 1, 2, 3, 4}) {
        // The split is for flipped faces only: on faces that only intersect others it costs time
        // (shrec_383_385's remeshing took twice as long) and removed nothing more.
        if (to_f == 3 && !standard.flipped(f)) continue;
        // The untangling and the disk repair only move vertices: their undo needs M_st's points alone.
        std::optional<Remesh_state::Checkpoint> cp;
        if (to_f >= 0 && to_f != 4) cp = s.checkpoint();
        const Remesh_state::Images images = s.images();
        if (to_f < 0) {
          if (!standard.untangle_around(f)) continue;
        } else if (to_f == 4) {
          if (!embed_disk(s, standard, check, f, region, before, within)) continue;
        } else if (to_f == 3) {
          const std::vector<WV> made = repair_face(s, standard, f, 0, 1, region);
          if (made.empty()) {
            s.rollback(*cp);
            continue;
          }
          std::vector<WF> flipped_now;
          for (WV w : made)
            for (WF g : CGAL::faces_around_target(m.halfedge(w), m))
              if (g != WF() && standard.flipped(g)) flipped_now.push_back(g);
          for (WF g : flipped_now)
            if (standard.flipped(g)) standard.untangle_around(g, true);
        } else if (repair_face(s, standard, f, to_f, depth, region).empty() && to_f == 0) {
          s.rollback(*cp);
          continue;
        }
        // Judged over the region and every face around a vertex the repair moved or made.
        std::vector<WF> after = region;
        for (std::size_t i = 0; i < m.number_of_vertices(); ++i)
          if (i >= images.pos.size() || s.pos[i] != images.pos[i])
            for (WF g : CGAL::faces_around_target(m.halfedge(WV(i)), m))
              if (g != WF()) after.push_back(g);
        std::sort(after.begin(), after.end());
        after.erase(std::unique(after.begin(), after.end()), after.end());
        if (check.local_bad(after) < before) {
          done = true;
          r.disks += to_f == 4;
          break;
        }
        if (cp) s.rollback(*cp);
        s.restore(images);
      }
      if (done) ++kept;
      else failed.insert(corners(f));
    }
    s.folded.resize(m.number_of_faces(), 0);
    bad = check.bad_faces(flipped, intersecting);
    ++r.rounds;
    if (kept == 0) break;
  }
  s.folded.resize(m.number_of_faces(), 0);
  standard.mark_flipped();
  r.flipped_after = flipped, r.intersecting_after = intersecting;
  r.splits = m.number_of_vertices() - v0;
  return r;
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_STRICT_REPAIR_H

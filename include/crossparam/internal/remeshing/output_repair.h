// SPDX-License-Identifier: GPL-3.0-or-later
// Repair of one output of the N-way remeshing (an addition to the paper). The N outputs share one face list and
// nothing else: each has its own points. Output k is its two-mesh remeshing's surface subdivided by the common
// refinement (common_refinement.h), and a part of a good face can be bad by the verifier's definitions
// (remeshing_verification.h) although the whole face is not: the flip rule tests a face at its own centroid,
// whose nearest point on mesh k can lie across a thin part or a crease from the whole face's; a sliver's normal,
// and whether it meets its neighbours, can be rounding.
//
// The repair moves points of output k only: it changes neither the face list nor any other output. A face is bad
// when it is flipped by the verifier's rule, degenerate, or meets another face beyond their shared corners
// (faces_intersect(), exact predicates), each away from mesh k's own folds as the verifier counts them. Rounds
// over the bad faces try, for each of their corners that may move, a few new positions:
//  - on an output other than the source's, the point of mesh k nearest the corner, the point of mesh k nearest
//    the centroid of the corner's neighbours, that centroid itself, the midpoint of the corner and its nearest
//    point, and the points nearest the corner and the centroid among mesh k's faces within ε that face the way
//    the corner's faces do (across a thin part the nearest point can be on the other side); feature vertices
//    do not move;
//  - on the source's output, only a vertex that the source does not have and that lies inside one source face
//    moves, to the centroid of its neighbours in that face's barycentric coordinates, if every face around it
//    is then oriented there as the faces that tile it (exact): the output stays the source's surface.
// A position is kept when it makes the faces around the corner less bad than before (bad faces, intersecting
// pairs, and any sample of a face farther than output_repair_margin ε from mesh k outweighing both), so no round
// makes the output worse, and the rounds end when one keeps nothing.
//
// A bad face that no move of one corner mends, on an output other than the source's, is then mended with its
// surroundings: where one map squeezes a part of mesh k to a point, the common refinement puts there a cluster of
// points of every other output too small for their coordinates to carry a face's normal, and no corner of the
// cluster can move out of it alone. The repair takes the disk of faces within r rings of the bad face (r = 1, 2,
// ... up to output_repair_disk_rings, whenever they form a disk: Euler characteristic 1, the faces being connected;
// a ring that leaves a hole is skipped, and the hole closes at the next), keeps its
// boundary and its corners that may not move, puts every other corner at the average of its neighbours (Tutte's
// embedding with uniform weights, solved in space with the boundary held) and then at its nearest point of mesh
// k. Of the disks that are less bad than before by the same measure, summed over their faces, it keeps the one
// that gains most (the first with no bad face left ends the growth); passes over the bad faces left repeat while
// one keeps a disk.
#ifndef CROSSPARAM_INTERNAL_REMESHING_OUTPUT_REPAIR_H
#define CROSSPARAM_INTERNAL_REMESHING_OUTPUT_REPAIR_H

#include <crossparam/internal/barycentric.h>
#include <crossparam/internal/layout_mesh.h>
#include <crossparam/internal/remeshing/disk_embedding.h>
#include <crossparam/internal/remeshing/triangle_intersection.h>
#include <crossparam/remeshing_verification.h>
#include <crossparam/types.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

namespace crossparam {
namespace internal {

/// Rounds of the output repair at most; each tries every bad face's corners once, and the rounds end when one
/// keeps nothing (on bench_multi/fourleg5 and the three wolves the second or third does).
constexpr unsigned output_repair_rounds = 12;

/// Fraction of ε within which a moved corner's faces must stay of mesh k at their samples (corners, edge
/// midpoints, centroid): the margin of the overlay decimation (overlay_decimation.h), for the same reasons (the
/// verifier measures to 1 % of ε, and positions are rounded).
constexpr double output_repair_margin = 0.9;

/// Barycentric coordinate (in the nearest face of the mesh) below which the nearest point of a face's centroid
/// counts as on that face's edge, or at its vertex, in the flip test of the repair (Output_repairer::face_bad()):
/// there the verifier's search may meet any of the faces around it first. The point is computed to about 10⁻¹⁶;
/// 10⁻⁹ is far above that and below any position that matters.
constexpr double output_repair_tie = 1e-9;

/// Rings around a bad face that the disk repair grows to at most (see above). On bench_multi/fourleg5 the one
/// cluster measured needs 5 (the rings within 4 of its bad face are all below 2·10⁻⁹ of the diagonal); each ring
/// that forms a disk costs a sparse solve of the disk's size and a count of its faces' pairs; 10 rings hold a few
/// hundred faces on a regular mesh.
constexpr unsigned output_repair_disk_rings = 10;

/// What the repair of one output did.
struct Output_repair_result {
  std::size_t bad_before = 0; ///< faces flipped, degenerate or in an intersecting pair (away from the mesh's folds) when it started
  std::size_t bad_after = 0;  ///< and when it ended
  std::size_t moves = 0;      ///< positions kept
  std::size_t disks = 0;      ///< disks around a bad face embedded anew (see above)
  std::size_t rounds = 0;
};

/// The repair of one output (see above). `points` are output k's, changed in place; `mesh` is mesh k (the
/// source itself for the source's output); `eps` the tolerance in the mesh's units; `movable` per vertex;
/// `on_source`, for the source's output only, the source face of every face of the face list.
class Output_repairer {
public:
  using Faces = std::vector<std::array<std::size_t, 3>>;
  using Points = std::vector<std::array<double, 3>>;

  Output_repairer(const Faces& faces, Points& points, const Surface_mesh& mesh, double eps, std::vector<char> movable,
                  const std::vector<Input_face_location>* on_source = nullptr)
      : faces_(faces), out_(points), mesh_(mesh), eps_(eps), movable_(std::move(movable)), on_source_(on_source),
        tree_(CGAL::faces(mesh).first, CGAL::faces(mesh).second, mesh) {
    tree_.accelerate_distance_queries();
    P_.reserve(points.size());
    for (const auto& p : points) P_.emplace_back(p[0], p[1], p[2]);
    star_.resize(points.size());
    for (std::size_t f = 0; f < faces.size(); ++f)
      for (std::size_t v : faces[f]) star_[v].push_back(std::uint32_t(f));
    folds_ = fold_face_boxes(mesh, self_intersecting_pairs(mesh));
    box_.resize(faces.size());
    std::vector<Face_box_entry> entries;
    entries.reserve(faces.size());
    for (std::size_t f = 0; f < faces.size(); ++f) {
      box_[f] = to_face_box(face_box(f));
      entries.emplace_back(box_[f], std::uint32_t(f));
    }
    index_ = Face_box_index(entries.begin(), entries.end()); // bulk loading (packing): much faster than one insert each
  }

  Output_repair_result run() {
    Output_repair_result r;
    std::vector<char> bad(faces_.size(), 0);
    std::vector<std::uint32_t> list;
    const auto P = [this](std::size_t v) -> const Point_3& { return P_[v]; };
    for (std::size_t f = 0; f < faces_.size(); ++f) {
      bad[f] = bad[f] || face_bad(f);
      if (normal(f) == CGAL::NULL_VECTOR) continue;
      for_each_near(f, [&](std::uint32_t g) { // each pair once
        if (g > f && normal(g) != CGAL::NULL_VECTOR && faces_intersect(faces_[f], faces_[g], P) &&
            !near_fold(face_box(f) + face_box(g)))
          bad[f] = bad[g] = 1;
      });
    }
    for (std::size_t f = 0; f < faces_.size(); ++f)
      if (bad[f]) list.push_back(std::uint32_t(f));
    r.bad_before = list.size();
    for (; r.rounds < output_repair_rounds && !list.empty(); ++r.rounds) {
      std::vector<std::uint32_t> touched = list;
      std::size_t kept = 0;
      for (std::uint32_t f : list)
        for (std::size_t v : faces_[f]) {
          if (!movable_[v]) continue;
          // The faces whose status a move of v can change: those around v and those their boxes meet, before
          // the move and after it.
          std::vector<std::uint32_t> near;
          auto collect = [&] {
            for (std::uint32_t g : star_[v]) {
              near.push_back(g);
              for_each_near(g, [&](std::uint32_t h) { near.push_back(h); });
            }
          };
          collect();
          if (!try_move(v)) continue;
          ++kept;
          collect();
          touched.insert(touched.end(), near.begin(), near.end());
        }
      r.moves += kept;
      std::sort(touched.begin(), touched.end());
      touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
      for (std::uint32_t f : touched) bad[f] = face_bad(f) || intersections(f, {}) > 0;
      list.clear();
      for (std::uint32_t f : touched)
        if (bad[f]) list.push_back(f);
      if (kept == 0) break;
    }
    // The disks around the bad faces that are left (not on the source's output: its points stay on the source),
    // in passes while one keeps a disk.
    for (unsigned pass = 0; !on_source_ && pass < output_repair_rounds; ++pass) {
      std::vector<std::uint32_t> left;
      for (std::size_t f = 0; f < faces_.size(); ++f)
        if (bad[f]) left.push_back(std::uint32_t(f));
      std::size_t kept = 0;
      std::vector<std::uint32_t> touched;
      for (std::uint32_t f : left)
        if (bad[f] && embed_disk(f, touched)) {
          ++kept;
          for (std::uint32_t g : touched) bad[g] = face_bad(g) || intersections(g, {}) > 0;
        }
      r.disks += kept;
      if (kept == 0) break;
    }
    r.bad_after = std::size_t(std::count(bad.begin(), bad.end(), char(1)));
    for (std::size_t v = 0; v < P_.size(); ++v) out_[v] = {P_[v].x(), P_[v].y(), P_[v].z()};
    return r;
  }

private:
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_face_graph_triangle_primitive<Surface_mesh>>>;
  /// Weight of a face beyond the margin in badness(): more than a star holds bad faces and pairs.
  static constexpr std::size_t far_weight = 1000000;

  CGAL::Bbox_3 face_box(std::size_t f) const {
    const auto& c = faces_[f];
    return P_[c[0]].bbox() + P_[c[1]].bbox() + P_[c[2]].bbox();
  }
  Kernel::Vector_3 normal(std::size_t f) const {
    const auto& c = faces_[f];
    return triangle_normal(P_[c[0]], P_[c[1]], P_[c[2]]);
  }
  bool near_fold(const CGAL::Bbox_3& b) const { return meets_grown(b, eps_, folds_); }

  Kernel::Vector_3 mesh_normal(Surface_mesh::Face_index t) const {
    const auto g = halfedge(t, mesh_);
    return triangle_normal(mesh_.point(source(g, mesh_)), mesh_.point(target(g, mesh_)), mesh_.point(target(next(g, mesh_), mesh_)));
  }
  /// Flipped by the verifier's rule or degenerate, away from the mesh's folds, whichever corner its normal is
  /// computed from. Where the nearest point of the
  /// mesh is on one of its edges or vertices (within output_repair_tie of its face's size), the verifier's
  /// answer depends on which face there its search meets first: the face is bad if it opposes any of them.
  bool face_bad(std::size_t f) const {
    const auto& c = faces_[f];
    const auto nearest = tree_.closest_point_and_primitive(CGAL::centroid(P_[c[0]], P_[c[1]], P_[c[2]]));
    if (near_fold(nearest.first.bbox())) return false;
    // The normal from each corner: they differ by rounding, which decides the sign for a needle near 90°; the
    // verifier takes the corners in the order of the face's halfedge, which a mesh made from the face list may
    // start anywhere.
    const std::array<Kernel::Vector_3, 3> ns{triangle_normal(P_[c[0]], P_[c[1]], P_[c[2]]),
                                             triangle_normal(P_[c[1]], P_[c[2]], P_[c[0]]),
                                             triangle_normal(P_[c[2]], P_[c[0]], P_[c[1]])};
    for (const auto& n : ns)
      if (n == CGAL::NULL_VECTOR) return true;
    auto opposes = [&](const Kernel::Vector_3& nt) { return ns[0] * nt < 0 || ns[1] * nt < 0 || ns[2] * nt < 0; };
    if (opposes(mesh_normal(nearest.second))) return true;
    // The faces that share the nearest point: across an edge it is on, around a vertex it is at.
    const auto h = halfedge(nearest.second, mesh_);
    const std::array<Surface_mesh::Halfedge_index, 3> hs{h, next(h, mesh_), prev(h, mesh_)};
    const Point_3 &a = mesh_.point(source(h, mesh_)), &b = mesh_.point(target(h, mesh_)), &d = mesh_.point(target(next(h, mesh_), mesh_));
    // Barycentric coordinate opposite each edge of hs (a-b, b-d, d-a): those of d, a and b.
    const std::array<double, 3> abd = barycentric_in_triangle(a, b, d, nearest.first);
    const std::array<double, 3> w{abd[2], abd[0], abd[1]};
    for (int i = 0; i < 3; ++i) {
      if (!(w[i] < output_repair_tie)) continue;
      const auto o = opposite(hs[i], mesh_);
      if (!is_border(o, mesh_) && opposes(mesh_normal(face(o, mesh_)))) return true;
      // At a vertex: the end this edge shares with the next edge (hs[i + 1]) if q is on that one too.
      if (w[(i + 1) % 3] < output_repair_tie)
        for (const auto t : CGAL::faces_around_target(hs[i], mesh_))
          if (t != Surface_mesh::null_face() && opposes(mesh_normal(t))) return true;
    }
    return false;
  }
  /// Whether a sample of face f is farther than the margin from the mesh.
  bool far(std::size_t f) const {
    const auto& c = faces_[f];
    const double limit = output_repair_margin * eps_ * output_repair_margin * eps_;
    const Point_3 &a = P_[c[0]], &b = P_[c[1]], &d = P_[c[2]];
    for (const Point_3& x : {a, b, d, CGAL::midpoint(a, b), CGAL::midpoint(b, d), CGAL::midpoint(d, a), CGAL::centroid(a, b, d)})
      if (tree_.squared_distance(x) > limit) return true;
    return false;
  }
  /// Calls `visit(g)` for every face g whose box, as entered, meets face f's present box.
  template <class Visit>
  void for_each_near(std::size_t f, Visit visit) const {
    const Face_box q = to_face_box(face_box(f));
    for (auto it = index_.qbegin(boost::geometry::index::intersects(q)); it != index_.qend(); ++it)
      if (it->second != f) visit(it->second);
  }
  /// Faces that face f intersects away from the folds, those of `skip` (a star, tested on its own) left out.
  std::size_t intersections(std::size_t f, const std::vector<std::uint32_t>& skip) const {
    if (normal(f) == CGAL::NULL_VECTOR) return 0; // counted by face_bad()
    const auto P = [this](std::size_t v) -> const Point_3& { return P_[v]; };
    std::size_t n = 0;
    const CGAL::Bbox_3 bf = face_box(f);
    for_each_near(f, [&](std::uint32_t g) {
      if (std::find(skip.begin(), skip.end(), g) != skip.end() || normal(g) == CGAL::NULL_VECTOR) return;
      if (faces_intersect(faces_[f], faces_[g], P) && !near_fold(bf + face_box(g))) ++n;
    });
    return n;
  }
  /// How bad a set of faces is (the star of a corner, a disk): bad faces, intersecting pairs (among them and
  /// with the others), and, on an output other than the source's, far faces weighted far_weight.
  std::size_t badness_of(const std::vector<std::uint32_t>& fs) const {
    const auto P = [this](std::size_t x) -> const Point_3& { return P_[x]; };
    std::size_t b = 0;
    for (std::size_t i = 0; i < fs.size(); ++i) {
      const std::uint32_t f = fs[i];
      b += face_bad(f) + intersections(f, fs) + (on_source_ ? 0 : far_weight * far(f));
      if (normal(f) == CGAL::NULL_VECTOR) continue;
      const CGAL::Bbox_3 bf = face_box(f);
      for (std::size_t j = i + 1; j < fs.size(); ++j)
        if (CGAL::do_overlap(bf, face_box(fs[j])) && normal(fs[j]) != CGAL::NULL_VECTOR &&
            faces_intersect(faces_[f], faces_[fs[j]], P) && !near_fold(bf + face_box(fs[j])))
          ++b;
    }
    return b;
  }
  /// How bad the faces around v are.
  std::size_t badness(std::size_t v) const { return badness_of(star_[v]); }

  /// Tries the new positions of v; keeps the least bad if it is less bad than v's present one.
  bool try_move(std::size_t v) {
    const std::vector<Point_3> candidates = on_source_ ? source_candidates(v) : mesh_candidates(v);
    if (candidates.empty()) return false;
    const Point_3 old = P_[v];
    const std::size_t before = badness(v);
    if (before == 0) return false;
    std::size_t best = before;
    Point_3 chosen = old;
    for (const Point_3& x : candidates) {
      P_[v] = x;
      const std::size_t b = badness(v);
      if (b < best) best = b, chosen = x;
    }
    P_[v] = old;
    if (!(best < before)) return false;
    set_points({v}, {chosen});
    return true;
  }

  /// Moves the points of `moved` to `to`, keeping the box index current.
  void set_points(const std::vector<std::size_t>& moved, const std::vector<Point_3>& to) {
    std::vector<std::uint32_t> fs;
    for (std::size_t v : moved) fs.insert(fs.end(), star_[v].begin(), star_[v].end());
    std::sort(fs.begin(), fs.end());
    fs.erase(std::unique(fs.begin(), fs.end()), fs.end());
    for (std::uint32_t f : fs) index_.remove(Face_box_entry(box_[f], f));
    for (std::size_t i = 0; i < moved.size(); ++i) P_[moved[i]] = to[i];
    for (std::uint32_t f : fs) {
      box_[f] = to_face_box(face_box(f));
      index_.insert(Face_box_entry(box_[f], f));
    }
  }

  /// The disk repair of bad face f (see above). On success `touched` holds the faces whose status may have
  /// changed: the disk's and those their boxes meet.
  bool embed_disk(std::uint32_t f, std::vector<std::uint32_t>& touched) {
    std::vector<std::uint32_t> disk{f};
    // The best disk so far: its faces, its free corners and their new positions, and how much less bad it is.
    std::vector<std::uint32_t> best_disk;
    std::vector<std::size_t> best_free;
    std::vector<Point_3> best_to;
    long best_gain = 0;
    for (unsigned ring = 1; ring <= output_repair_disk_rings; ++ring) {
      std::vector<std::size_t> vs;
      for (std::uint32_t g : disk) vs.insert(vs.end(), faces_[g].begin(), faces_[g].end());
      std::sort(vs.begin(), vs.end());
      vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
      for (std::size_t v : vs) disk.insert(disk.end(), star_[v].begin(), star_[v].end());
      std::sort(disk.begin(), disk.end());
      disk.erase(std::unique(disk.begin(), disk.end()), disk.end());
      std::vector<std::array<std::size_t, 3>> triples;
      for (std::uint32_t g : disk) triples.push_back(faces_[g]);
      const std::optional<Disk_faces> d = disk_of(triples);
      if (!d) continue; // not a disk (yet: a hole fills at the next ring)
      std::vector<std::size_t> free;
      for (std::size_t v : d->corners) {
        const bool inside = std::all_of(star_[v].begin(), star_[v].end(),
                                        [&](std::uint32_t g) { return std::binary_search(disk.begin(), disk.end(), g); });
        if (inside && movable_[v]) free.push_back(v);
      }
      if (free.empty()) continue;
      const std::optional<std::vector<Point_3>> x = tutte_in_space(free, d->edges, [this](std::size_t v) -> const Point_3& { return P_[v]; });
      if (!x) continue;
      std::vector<Point_3> to;
      for (const Point_3& p : *x) to.push_back(tree_.closest_point(p));
      std::vector<Point_3> old;
      for (std::size_t v : free) old.push_back(P_[v]);
      const std::size_t before = badness_of(disk);
      set_points(free, to);
      const std::size_t after = badness_of(disk);
      set_points(free, old);
      if (long(before) - long(after) > best_gain) {
        best_gain = long(before) - long(after);
        best_disk = disk, best_free = std::move(free), best_to = std::move(to);
        if (after == 0) break;
      }
    }
    if (best_gain == 0) return false;
    const auto collect = [&] {
      for (std::uint32_t g : best_disk) {
        touched.push_back(g);
        for_each_near(g, [&](std::uint32_t h) { touched.push_back(h); });
      }
    };
    touched.clear();
    collect();
    set_points(best_free, best_to);
    collect();
    return true;
  }

  std::vector<Point_3> mesh_candidates(std::size_t v) const {
    Kernel::Vector_3 sum = CGAL::NULL_VECTOR;
    std::size_t n = 0;
    for (std::uint32_t f : star_[v])
      for (std::size_t w : faces_[f])
        if (w != v) sum = sum + (P_[w] - CGAL::ORIGIN), ++n; // each neighbour twice: the centroid is the same
    const Point_3 centre = CGAL::ORIGIN + sum / double(n);
    const Point_3 near = tree_.closest_point(P_[v]);
    std::vector<Point_3> out{near, tree_.closest_point(centre), centre, CGAL::midpoint(P_[v], near)};
    // Where a thin part or a crease of the mesh is nearer than the side v's faces stand for: the nearest points
    // on the faces of the mesh within ε that face the way v's faces do (the sum of their normals).
    Kernel::Vector_3 facing = CGAL::NULL_VECTOR;
    for (std::uint32_t f : star_[v]) facing = facing + normal(f);
    for (const Point_3& x : {P_[v], centre})
      if (const auto q = nearest_facing(x, facing)) out.push_back(*q);
    return out;
  }

  /// The point nearest x on the faces of the mesh within ε of x whose normal makes an acute angle with `facing`.
  std::optional<Point_3> nearest_facing(const Point_3& x, const Kernel::Vector_3& facing) const {
    if (facing == CGAL::NULL_VECTOR) return std::nullopt;
    std::vector<Surface_mesh::Face_index> near;
    const CGAL::Bbox_3 box(x.x() - eps_, x.y() - eps_, x.z() - eps_, x.x() + eps_, x.y() + eps_, x.z() + eps_);
    tree_.all_intersected_primitives(box, std::back_inserter(near));
    std::optional<Point_3> best;
    double best_d = HUGE_VAL;
    for (const auto t : near) {
      if (!(mesh_normal(t) * facing > 0)) continue;
      const auto h = halfedge(t, mesh_);
      const Kernel::Triangle_3 T(mesh_.point(source(h, mesh_)), mesh_.point(target(h, mesh_)), mesh_.point(target(next(h, mesh_), mesh_)));
      const Point_3 q = Kernel().construct_projected_point_3_object()(T, x);
      const double d = CGAL::squared_distance(q, x);
      if (d < best_d) best_d = d, best = q;
    }
    return best;
  }

  /// The centroid of v's neighbours in barycentric coordinates of the one source face around v, if there is one
  /// and every face around v then has the orientation of the faces that tile it there (exact,
  /// barycentric_orientation()); the faces around v keep tiling the same part of that source face.
  std::vector<Point_3> source_candidates(std::size_t v) const {
    const auto& L = *on_source_;
    if (star_[v].empty()) return {};
    const Input_face_location& home = L[star_[v].front()];
    std::array<double, 3> sum{0, 0, 0};
    std::size_t n = 0;
    double area = 0; // of the star, in normalized coordinates: its sign is the tiling's orientation
    for (std::uint32_t f : star_[v]) {
      const Input_face_location& l = L[f];
      if (l.face != home.face || l.vertices != home.vertices) return {}; // on a source edge or vertex
      std::array<std::array<double, 3>, 3> q;
      for (std::size_t c = 0; c < 3; ++c) {
        const double t = l.corners[c][0] + l.corners[c][1] + l.corners[c][2];
        for (std::size_t k = 0; k < 3; ++k) q[c][k] = l.corners[c][k] / t;
        if (faces_[f][c] != v) {
          for (std::size_t k = 0; k < 3; ++k) sum[k] += q[c][k];
          ++n;
        }
      }
      area += (q[1][1] - q[0][1]) * (q[2][2] - q[0][2]) - (q[2][1] - q[0][1]) * (q[1][2] - q[0][2]);
    }
    const CGAL::Orientation want = area > 0 ? CGAL::POSITIVE : area < 0 ? CGAL::NEGATIVE : CGAL::COLLINEAR;
    if (want == CGAL::COLLINEAR || n == 0) return {};
    const std::array<double, 3> b{sum[0] / double(n), sum[1] / double(n), sum[2] / double(n)};
    for (std::uint32_t f : star_[v]) {
      std::array<std::array<double, 3>, 3> q;
      for (std::size_t c = 0; c < 3; ++c) q[c] = faces_[f][c] == v ? b : L[f].corners[c];
      if (barycentric_orientation(q[0], q[1], q[2]) != want) return {};
    }
    const auto corner = [this](std::size_t i) { return mesh_.point(Surface_mesh::Vertex_index(Surface_mesh::size_type(i))); };
    const Point_3 &a = corner(home.vertices[0]), &p = corner(home.vertices[1]), &c = corner(home.vertices[2]);
    return {Point_3(b[0] * a.x() + b[1] * p.x() + b[2] * c.x(), b[0] * a.y() + b[1] * p.y() + b[2] * c.y(),
                    b[0] * a.z() + b[1] * p.z() + b[2] * c.z())};
  }

  const Faces& faces_;
  Points& out_;
  const Surface_mesh& mesh_;
  double eps_;
  std::vector<char> movable_;
  const std::vector<Input_face_location>* on_source_;
  Tree tree_;
  std::vector<Point_3> P_;
  std::vector<std::vector<std::uint32_t>> star_;
  std::vector<CGAL::Bbox_3> folds_;
  std::vector<Face_box> box_;
  Face_box_index index_;
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_REMESHING_OUTPUT_REPAIR_H

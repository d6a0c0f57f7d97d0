// SPDX-License-Identifier: GPL-3.0-or-later
// Topologically identical triangular patch layouts of two closed genus-0 meshes (Kraevoy & Sheffer 2004, §3).
//
// Invariant kept after every path pair added: the two partial layouts are topologically identical, i.e. the
// rotation of path ids around every feature is the same on both meshes, and every patch contains the same
// paths and isolated features on both. A candidate pair (s, t) keeps the invariant iff it leaves each
// endpoint in corresponding sectors (sector = wedge between consecutive paths, named by the path on its
// clockwise side) and, when it splits its patch, leaves the same paths and isolated features on its left on
// both meshes (the blocking test: fronts from the same side of both paths, §3 condition 3).
//
// Stages: §3.1 PathMatch on the edge graphs (shortest pairs first, lazy Update: stale paths are recomputed
// when popped, paths in the wrong sector are recomputed inside the right one); §3.2 make-simple then
// triangulation of the patches by chords traced on the face graph and turned into edge paths with splits;
// §3.3 path flips. Genus 0 guarantees completion: once the layout graph is connected every patch is a disk
// and any chord between two of its corners splits it identically on both meshes.
#ifndef CROSSPARAM_INTERNAL_LAYOUT_BUILDER_H
#define CROSSPARAM_INTERNAL_LAYOUT_BUILDER_H

#include <crossparam/internal/layout_mesh.h>

#include <array>
#include <chrono>
#include <map>
#include <set>
#include <sstream>

namespace crossparam {

namespace internal {

class Layout_builder {
public:
  Layout_mesh side[2];                       ///< 0: source, 1: target
  std::vector<std::array<int, 2>> path_ends; ///< endpoints (features) of each path id; {-1,-1} once removed
  std::vector<int> degree;                   ///< number of paths at each feature (same on both meshes)
  std::vector<int> connection;               ///< nf x nf: path id joining two features, or no_path
  Layout_statistics stats;
  bool do_flips = true;
  /// Consistent matching paths (an addition to the paper): every matching pair is also traced with
  /// descriptor guidance on either mesh, each path following the other's geodesic-distance descriptors, and
  /// the most consistent of the three pairs is kept. Where two routes around a featureless protrusion have
  /// nearly equal lengths, shortest paths alone pick sides independently on the two meshes.
  bool consistent_paths = true;
  bool do_straighten = false;
  double consistency_threshold = 0.02; ///< pairs agreeing better than this (RMS per feature) are kept as traced
  double guide_weight = 20;        ///< edge cost = length * (1 + guide_weight * descriptor distance)
  std::size_t guide_samples = 16;  ///< descriptors of at most this many vertices of the guiding path
  std::size_t max_flip_splits = 2; ///< a flip may split at most this many edges on each mesh
  /// Genus of both meshes (checked equal by the input checks). Genus > 0 switches on the handle tests of §3.1
  /// rule 4 and the handle cuts of complete_with_handles(); genus 0 never runs them.
  int genus = 0;
  /// Handle cuts: at most this many pairs of corners are tried per patch, and at most this many handle cycles
  /// per corner pair and mesh; the closest pairs and the first cycles almost always succeed, the bounds keep the
  /// time of a hopeless search (too few features) small.
  std::size_t max_handle_corner_pairs = 12;
  std::size_t max_handle_cycles = 6;
  /// Passes of straighten_paths() at most. Each kept change shortens the total length, so the passes stop by
  /// themselves once no path can be shortened; the bound only makes the time certain.
  unsigned max_straightening_passes = 8;

  std::size_t nf() const { return degree.size(); }
  int& connected(int a, int b) { return connection[std::size_t(a) * nf() + std::size_t(b)]; }

  void run() {
    using clock = std::chrono::steady_clock;
    auto t0 = clock::now();
    degree.assign(side[0].feature_vertex.size(), 0);
    connection.assign(nf() * nf(), no_path);
    stats.features = nf();
    if (consistent_paths) {
      side[0].compute_descriptors();
      side[1].compute_descriptors();
    }
    path_match();
    auto t1 = clock::now();
    if (genus > 0)
      complete_with_handles();
    else
      complete_with_face_paths();
    auto t2 = clock::now();
    if (do_flips) flip_paths();
    auto t3 = clock::now();
    if (do_straighten) straighten_paths();
    auto t4 = clock::now();
    stats.splits_source = side[0].splits.size();
    stats.splits_target = side[1].splits.size();
    auto sec = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
    stats.seconds_edge_paths = sec(t0, t1);
    stats.seconds_face_paths = sec(t1, t2);
    stats.seconds_flips = sec(t2, t3);
    stats.seconds_straightening = sec(t3, t4);
    stats.seconds_total = sec(t0, t4);
  }

  // ---------------------------------------------------------------------------------------------------
  // Adding and removing path pairs
  // ---------------------------------------------------------------------------------------------------
  int add_path(int a, int b, const Halfedge_path& hs, const Halfedge_path& ht, int reuse_id = -1) {
    int id = reuse_id;
    if (id < 0) {
      id = int(path_ends.size());
      path_ends.push_back({a, b});
    } else {
      path_ends[id] = {a, b};
    }
    side[0].mark_path(id, hs);
    side[1].mark_path(id, ht);
    ++degree[a];
    ++degree[b];
    connected(a, b) = connected(b, a) = id;
    check_rotation(a);
    check_rotation(b);
    return id;
  }

  void remove_path(int id) {
    auto [a, b] = path_ends[id];
    side[0].unmark_path(id);
    side[1].unmark_path(id);
    --degree[a];
    --degree[b];
    connected(a, b) = connected(b, a) = no_path;
    path_ends[id] = {-1, -1};
  }

  /// Self-check: the cyclic order of paths around feature a is the same on both meshes.
  void check_rotation(int a) const {
    auto r0 = side[0].rotation(side[0].feature_vertex[a]);
    auto r1 = side[1].rotation(side[1].feature_vertex[a]);
    bool same = r0.size() == r1.size();
    if (same && !r0.empty()) {
      auto it = std::find(r1.begin(), r1.end(), r0[0]);
      same = it != r1.end();
      if (same) {
        std::rotate(r1.begin(), it, r1.end());
        same = r0 == r1;
      }
    }
    if (!same)
      throw Algorithm_error("internal error: cyclic order of paths at feature " + std::to_string(a) +
                            " differs between the meshes");
  }

  /// Corners (sectors) of a halfedge path at both ends.
  std::pair<int, int> corners(int s, const Halfedge_path& hp) const {
    const Layout_mesh& L = side[s];
    return {L.corner_of_outgoing(hp.front()), L.corner_of_outgoing(L.m.opposite(hp.back()))};
  }

  /// Descriptor disagreement of two matching paths: symmetric mean distance from each path vertex's
  /// descriptor to the nearest descriptor on the other path, RMS per feature (unit-area scale).
  double consistency(const Halfedge_path& hs, const Halfedge_path& ht) const {
    auto ds = side[0].path_descriptors(hs), dt = side[1].path_descriptors(ht);
    auto one = [&](const Layout_mesh& L, const Halfedge_path& hp, const std::vector<std::vector<float>>& ref) {
      double t = L.descriptor_distance(L.m.source(hp.front()), ref);
      for (WH h : hp) t += L.descriptor_distance(L.m.target(h), ref);
      return t / double(hp.size() + 1);
    };
    return 0.5 * (one(side[0], hs, dt) + one(side[1], ht, ds)) / std::sqrt(double(std::max<std::size_t>(1, nf())));
  }

  /// Tries each path of (hs, ht) retraced under the other's guidance (same sectors) and keeps the most
  /// consistent of the three pairs.
  void make_consistent(int a, int b, Halfedge_path& hs, Halfedge_path& ht) {
    if (!consistent_paths) return;
    double best = consistency(hs, ht);
    if (best <= consistency_threshold) return;
    auto cs = corners(0, hs);
    auto ds = side[0].path_descriptors(hs, guide_samples), dt = side[1].path_descriptors(ht, guide_samples);
    Halfedge_path t2 = side[1].shortest_path(a, b, cs.first, cs.second, &ds, guide_weight);
    Halfedge_path s2 = side[0].shortest_path(a, b, cs.first, cs.second, &dt, guide_weight);
    bool changed = false;
    if (!t2.empty()) {
      double c = consistency(hs, t2);
      if (c < best) best = c, ht = t2, changed = true;
    }
    if (!s2.empty()) {
      double c = consistency(s2, ht);
      if (c < best) best = c, hs = s2, changed = true;
    }
    stats.guided_paths += changed;
  }

  /// The blocking test: whether adding (hs, ht) keeps the two layouts topologically identical, given that
  /// their corners already correspond.
  bool non_blocking(const Halfedge_path& hs, const Halfedge_path& ht) const {
    if (genus > 0) return non_blocking_with_handles(hs, ht);
    const int tmp = int(path_ends.size());
    auto a = side[0].left_side_signature(hs, tmp, degree);
    auto b = side[1].left_side_signature(ht, tmp, degree);
    if (a.splits != b.splits) return false;
    if (!a.splits) return true;
    return a.paths == b.paths && a.isolated == b.isolated;
  }

  /// The blocking test on meshes of genus > 0 (§3.1 rules 3 and 4): the pair must split its patches on both
  /// meshes or on neither (4.1: a path that splits on one mesh but only cuts a handle on the other); when it
  /// splits, each part must show the same path sides and isolated features on both meshes (3) and the same
  /// Euler characteristic, hence the same genus (4.2). A pair that splits neither patch joins two boundary
  /// loops or cuts a handle on both, the same on both since its corners correspond.
  bool non_blocking_with_handles(const Halfedge_path& hs, const Halfedge_path& ht) const {
    const int tmp = int(path_ends.size());
    const auto a = side[0].split_signature(hs, tmp, degree);
    const auto b = side[1].split_signature(ht, tmp, degree);
    if (a.splits != b.splits) return false;
    return !a.splits || (a.left == b.left && a.right == b.right);
  }

  // ---------------------------------------------------------------------------------------------------
  // §3.1 PathMatch
  // ---------------------------------------------------------------------------------------------------
  struct Pair_state {
    int a = 0, b = 0;
    Halfedge_path s, t;
    unsigned version = 0;
    unsigned recomputations = 0;
    bool dead = false;
  };


  void path_match() {
    const int n = int(nf());
    std::vector<std::vector<Halfedge_path>> ps(n), pt(n);
    for (int a = 0; a < n; ++a) {
      ps[a] = side[0].shortest_paths_from(a);
      pt[a] = side[1].shortest_paths_from(a);
    }
    std::vector<Pair_state> pairs;
    using QE = std::tuple<double, std::size_t, unsigned>;
    std::priority_queue<QE, std::vector<QE>, std::greater<QE>> q;
    auto push = [&](std::size_t i) {
      Pair_state& p = pairs[i];
      q.push({side[0].path_length(p.s) + side[1].path_length(p.t), i, p.version}); // paper: |s| + |t|
    };
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b) {
        if (ps[a][b].empty() || pt[a][b].empty()) continue;
        Pair_state p;
        p.a = a;
        p.b = b;
        p.s = std::move(ps[a][b]);
        p.t = std::move(pt[a][b]);
        pairs.push_back(std::move(p));
        push(pairs.size() - 1);
      }
    // Each pair is recomputed at most this often; every recomputation follows a path added since the last
    // one or fixes sectors once, so the bound is never reached in practice. It only guarantees termination.
    const unsigned max_recomputations = 4 * unsigned(3 * n) + 8;
    while (!q.empty()) {
      auto [key, i, version] = q.top();
      q.pop();
      Pair_state& p = pairs[i];
      if (p.dead || version != p.version || connected(p.a, p.b) != no_path) continue;
      auto recompute = [&](Halfedge_path& hp, int s, int ca, int cb) {
        hp = side[s].shortest_path(p.a, p.b, ca, cb);
        return !hp.empty();
      };
      auto requeue = [&]() {
        if (++p.recomputations > max_recomputations) {
          p.dead = true;
          return;
        }
        ++p.version;
        push(i);
      };
      // Update, rules 1-2: paths through vertices now taken by other paths are recomputed.
      bool fs = side[0].path_still_free(p.s), ft = side[1].path_still_free(p.t);
      if (!fs || !ft) {
        ++stats.path_recomputations;
        if ((!fs && !recompute(p.s, 0, Layout_mesh::any_corner, Layout_mesh::any_corner)) ||
            (!ft && !recompute(p.t, 1, Layout_mesh::any_corner, Layout_mesh::any_corner))) {
          p.dead = true;
          continue;
        }
        requeue();
        continue;
      }
      // Update, rule 3: both paths must leave and enter their features in corresponding sectors.
      auto cs = corners(0, p.s), ct = corners(1, p.t);
      if (cs != ct) {
        ++stats.sector_recomputations;
        Halfedge_path t2 = side[1].shortest_path(p.a, p.b, cs.first, cs.second);
        Halfedge_path s2 = side[0].shortest_path(p.a, p.b, ct.first, ct.second);
        double la = t2.empty() ? HUGE_VAL : side[0].path_length(p.s) + side[1].path_length(t2);
        double lb = s2.empty() ? HUGE_VAL : side[0].path_length(s2) + side[1].path_length(p.t);
        if (t2.empty() && s2.empty()) {
          p.dead = true;
          continue;
        }
        if (la <= lb)
          p.t = std::move(t2);
        else
          p.s = std::move(s2);
        requeue();
        continue;
      }
      make_consistent(p.a, p.b, p.s, p.t);
      if (!non_blocking(p.s, p.t)) {
        ++stats.rejected_blocking;
        p.dead = true;
        continue;
      }
      add_path(p.a, p.b, p.s, p.t);
      ++stats.edge_paths;
    }
  }

  // ---------------------------------------------------------------------------------------------------
  // The combinatorial layout: darts, loops (boundary walks of patches), patches
  // ---------------------------------------------------------------------------------------------------
  struct Dart {
    int path;
    int from; // feature the dart leaves; the corner on its left at `from` is (from, path)
  };

  struct Combinatorics {
    std::vector<std::vector<int>> rotation; // per feature, path ids counter-clockwise
    std::vector<std::vector<Dart>> loops;   // boundary walks, darts in order, patch on the left
    std::vector<int> loop_patch;            // patch label (on the source) of each loop
    std::vector<int> isolated_patch;        // per feature: patch label if isolated, else -1
    std::vector<int> face_label;            // source patch labels
    int patches = 0;
  };

  int other_end(int path, int from) const {
    return path_ends[path][0] == from ? path_ends[path][1] : path_ends[path][0];
  }

  /// The first halfedge of a dart on mesh s (leaving the dart's feature).
  WH dart_halfedge(int s, const Dart& d) const {
    const Layout_mesh& L = side[s];
    const Halfedge_path& hp = L.paths[d.path];
    return path_ends[d.path][0] == d.from ? hp.front() : L.m.opposite(hp.back());
  }

  Dart next_dart(const Combinatorics& c, const Dart& d) const {
    int y = other_end(d.path, d.from);
    const auto& r = c.rotation[y];
    auto it = std::find(r.begin(), r.end(), d.path);
    std::size_t k = std::size_t(it - r.begin());
    int q = r[(k + r.size() - 1) % r.size()]; // clockwise neighbour of the reverse dart
    return {q, y};
  }

  Combinatorics combinatorics() const {
    Combinatorics c;
    const Layout_mesh& L = side[0];
    c.rotation.resize(nf());
    for (std::size_t a = 0; a < nf(); ++a) c.rotation[a] = L.rotation(L.feature_vertex[a]);
    c.patches = L.label_patches(c.face_label);
    std::map<std::pair<int, int>, char> seen; // (path, from)
    for (int p = 0; p < int(path_ends.size()); ++p) {
      if (path_ends[p][0] < 0) continue;
      for (int e = 0; e < 2; ++e) {
        Dart d0{p, path_ends[p][e]};
        if (seen.count({d0.path, d0.from})) continue;
        std::vector<Dart> loop;
        Dart d = d0;
        do {
          seen[{d.path, d.from}] = 1;
          loop.push_back(d);
          d = next_dart(c, d);
        } while (!(d.path == d0.path && d.from == d0.from));
        c.loop_patch.push_back(c.face_label[L.m.face(dart_halfedge(0, d0))]);
        c.loops.push_back(std::move(loop));
      }
    }
    c.isolated_patch.assign(nf(), -1);
    for (std::size_t a = 0; a < nf(); ++a)
      if (degree[a] == 0) c.isolated_patch[a] = c.face_label[L.m.face(L.out_halfedge(L.feature_vertex[a]))];
    return c;
  }

  double feature_distance(int a, int b) const {
    double d = 0;
    for (int s = 0; s < 2; ++s) {
      const Layout_mesh& L = side[s];
      d += std::sqrt(CGAL::squared_distance(L.m.point(L.feature_vertex[a]), L.m.point(L.feature_vertex[b])));
    }
    return d;
  }

  /// Traces a path between two corners on mesh s: an edge path when one exists through free vertices,
  /// otherwise a face path turned into an edge path with splits.
  Halfedge_path trace(int s, int a, int b, int ca, int cb, bool& used_faces) {
    Layout_mesh& L = side[s];
    Halfedge_path hp = L.shortest_path(a, b, ca, cb);
    used_faces = hp.empty();
    if (used_faces) hp = L.halfedges_of(L.trace_face_path(a, b, ca, cb));
    auto c = corners(s, hp);
    if (c.first != ca || c.second != cb)
      throw Algorithm_error("internal error: traced path left its sectors");
    return hp;
  }

  void add_traced_pair(int a, int b, int ca, int cb) {
    bool fs = false, ft = false;
    Halfedge_path hs = trace(0, a, b, ca, cb, fs);
    Halfedge_path ht = trace(1, a, b, ca, cb, ft);
    if (!fs && !ft) make_consistent(a, b, hs, ht);
    if (!non_blocking(hs, ht))
      throw Algorithm_error("internal error: a path pair traced inside matching patches splits them differently");
    stats.face_traced_source += fs;
    stats.face_traced_target += ft;
    add_path(a, b, hs, ht);
  }

  // ---------------------------------------------------------------------------------------------------
  // §3.2 make-simple and triangulation
  // ---------------------------------------------------------------------------------------------------
  void complete_with_face_paths() {
    // Each step adds one path; a triangulation of nf >= 3 features has 3 nf - 6 of them.
    const std::size_t max_steps = 3 * nf() + 8;
    for (std::size_t step = 0; step < max_steps; ++step) {
      Combinatorics c = combinatorics();
      // Components of each patch: loops and isolated features, as lists of corners (feature, sector).
      struct Component {
        std::vector<std::pair<int, int>> corners;
      };
      std::vector<std::vector<Component>> in_patch(c.patches);
      for (std::size_t l = 0; l < c.loops.size(); ++l) {
        Component comp;
        for (const Dart& d : c.loops[l]) comp.corners.push_back({d.from, d.path});
        in_patch[c.loop_patch[l]].push_back(std::move(comp));
      }
      for (std::size_t a = 0; a < nf(); ++a)
        if (c.isolated_patch[a] >= 0) in_patch[c.isolated_patch[a]].push_back({{{int(a), isolated_corner}}});

      // Make simple: join two components of one patch by the closest pair of corners.
      double best = HUGE_VAL;
      std::array<int, 4> pick{};
      for (const auto& comps : in_patch) {
        for (std::size_t i = 0; i < comps.size(); ++i)
          for (std::size_t j = i + 1; j < comps.size(); ++j)
            for (auto [x, cx] : comps[i].corners)
              for (auto [y, cy] : comps[j].corners) {
                double d = feature_distance(x, y);
                if (d < best) {
                  best = d;
                  pick = {x, y, cx, cy};
                }
              }
      }
      if (best < HUGE_VAL) {
        add_traced_pair(pick[0], pick[1], pick[2], pick[3]);
        ++stats.face_paths;
        continue;
      }
      // Triangulate: a chord between two non-adjacent corners of a loop longer than three, joining
      // distinct features not yet joined (keeps the base mesh a simple triangulation).
      for (const auto& loop : c.loops) {
        const std::size_t k = loop.size();
        if (k <= 3) continue;
        for (std::size_t i = 0; i < k; ++i)
          for (std::size_t j = i + 2; j < k; ++j) {
            if (i == 0 && j == k - 1) continue;
            int x = loop[i].from, y = loop[j].from;
            if (x == y || connected(x, y) != no_path) continue;
            double d = feature_distance(x, y);
            if (d < best) {
              best = d;
              pick = {x, y, loop[i].path, loop[j].path};
            }
          }
      }
      if (best < HUGE_VAL) {
        add_traced_pair(pick[0], pick[1], pick[2], pick[3]);
        ++stats.face_paths;
        continue;
      }
      // Nothing left to add: every loop must be a triangle now.
      for (const auto& loop : c.loops)
        if (loop.size() != 3)
          throw Algorithm_error("internal error: a patch with " + std::to_string(loop.size()) +
                                " sides has no valid chord");
      return;
    }
    throw Algorithm_error("internal error: patch triangulation did not terminate");
  }

  // ---------------------------------------------------------------------------------------------------
  // §3.2 on meshes of genus > 0: make-simple, handle cuts, triangulation
  // ---------------------------------------------------------------------------------------------------

  /// Per patch (source labels of `c`): its boundary loops, corner features and genus from
  /// chi = 2 - 2 genus - loops.
  struct Patch_topology {
    std::vector<std::vector<std::size_t>> loops; ///< loop indices of each patch
    std::vector<int> genus;
  };
  Patch_topology patch_topology(const Combinatorics& c) const {
    Patch_topology t;
    t.loops.resize(std::size_t(c.patches));
    for (std::size_t l = 0; l < c.loops.size(); ++l) t.loops[c.loop_patch[l]].push_back(l);
    const std::vector<long> chi = side[0].euler_characteristics(c.face_label, c.patches);
    for (int p = 0; p < c.patches; ++p) t.genus.push_back(int((2 - chi[p] - long(t.loops[p].size())) / 2));
    return t;
  }

  /// The completion of §3.2 on meshes of genus > 0. Each step adds one pair of paths, in this order: make-simple
  /// (join two boundary loops or isolated features of one patch), a handle cut (a path between two corners of
  /// the single loop of a patch with handles that does not split it), a chord of a disk patch. Each patch
  /// keeps the same genus and loops on both meshes (the blocking test), so the same step applies to both.
  /// When no step applies and a patch is not a triangle, the features are too few
  /// (Insufficient_features_error naming that patch).
  void complete_with_handles() {
    // A triangulation of genus g with nf vertices has 3 (nf - 2 + 2 g) edges: each step adds one, or flips one
    // to free a chord (unblock_chord, move_path_into, then triangulates again); four times that many steps
    // bound the loop.
    const std::size_t max_steps = 4 * (3 * nf() + 6 * std::size_t(genus)) + 8;
    for (std::size_t step = 0; step < max_steps; ++step) {
      Combinatorics c = combinatorics();
      const Patch_topology topo = patch_topology(c);
      std::vector<std::vector<std::vector<std::pair<int, int>>>> in_patch(c.patches); // components' corners
      for (std::size_t l = 0; l < c.loops.size(); ++l) {
        std::vector<std::pair<int, int>> comp;
        for (const Dart& d : c.loops[l]) comp.push_back({d.from, d.path});
        in_patch[c.loop_patch[l]].push_back(std::move(comp));
      }
      for (std::size_t a = 0; a < nf(); ++a)
        if (c.isolated_patch[a] >= 0) in_patch[c.isolated_patch[a]].push_back({{int(a), isolated_corner}});

      // Make simple: the closest corners of two components of one patch, distinct features not joined yet.
      double best = HUGE_VAL;
      std::array<int, 4> pick{};
      for (const auto& comps : in_patch)
        for (std::size_t i = 0; i < comps.size(); ++i)
          for (std::size_t j = i + 1; j < comps.size(); ++j)
            for (auto [x, cx] : comps[i])
              for (auto [y, cy] : comps[j]) {
                if (x == y || connected(x, y) != no_path) continue;
                const double d = feature_distance(x, y);
                if (d < best) {
                  best = d;
                  pick = {x, y, cx, cy};
                }
              }
      if (best < HUGE_VAL) {
        add_traced_pair(pick[0], pick[1], pick[2], pick[3]);
        ++stats.face_paths;
        continue;
      }
      // Handle cuts on simple patches of genus > 0.
      bool cut = false;
      for (int p = 0; p < c.patches && !cut; ++p)
        if (topo.genus[p] > 0 && topo.loops[p].size() == 1) cut = cut_handle(c.loops[topo.loops[p][0]]);
      if (cut) {
        ++stats.face_paths;
        continue;
      }
      for (int p = 0; p < c.patches; ++p)
        if (topo.genus[p] > 0 || in_patch[p].size() != 1) throw_insufficient(c, topo, p);
      // Triangulate: every patch is a disk now; a chord between two non-adjacent corners of a loop, joining
      // distinct features not yet joined.
      for (const auto& loop : c.loops) {
        const std::size_t k = loop.size();
        if (k <= 3) continue;
        for (std::size_t i = 0; i < k; ++i)
          for (std::size_t j = i + 2; j < k; ++j) {
            if (i == 0 && j == k - 1) continue;
            int x = loop[i].from, y = loop[j].from;
            if (x == y || connected(x, y) != no_path) continue;
            double d = feature_distance(x, y);
            if (d < best) {
              best = d;
              pick = {x, y, loop[i].path, loop[j].path};
            }
          }
      }
      if (best < HUGE_VAL) {
        add_traced_pair(pick[0], pick[1], pick[2], pick[3]);
        ++stats.face_paths;
        continue;
      }
      // Every chord left joins two features already joined elsewhere (on a surface with handles the layout
      // graph need not be planar): free one by flipping the path that joins them.
      bool unblocked = false;
      for (std::size_t l = 0; l < c.loops.size() && !unblocked; ++l) {
        const auto& loop = c.loops[l];
        const std::size_t k = loop.size();
        for (std::size_t i = 0; i < k && !unblocked; ++i)
          for (std::size_t j = i + 2; j < k && !unblocked; ++j)
            if (!(i == 0 && j == k - 1) && loop[i].from != loop[j].from)
              unblocked = unblock_chord(loop[i].from, loop[j].from);
      }
      // No flip frees a chord: move a path that blocks one into the patch (each feature pair once).
      for (std::size_t l = 0; l < c.loops.size() && !unblocked; ++l) {
        const auto& loop = c.loops[l];
        const std::size_t k = loop.size();
        for (std::size_t i = 0; i < k && !unblocked; ++i)
          for (std::size_t j = i + 2; j < k && !unblocked; ++j)
            if (!(i == 0 && j == k - 1) && loop[i].from != loop[j].from)
              unblocked = move_path_into(loop[i].from, loop[j].from, loop[i].path, loop[j].path);
      }
      // Nor a move: turn a side of the patch into a chord of the patch grown by the triangle beyond that side.
      for (std::size_t l = 0; l < c.loops.size() && !unblocked; ++l)
        if (c.loops[l].size() > 3) unblocked = rotate_side(c, c.loops[l]);
      if (unblocked) continue;
      for (std::size_t l = 0; l < c.loops.size(); ++l)
        if (c.loops[l].size() != 3) throw_insufficient(c, topo, c.loop_patch[l]);
      // A simple base mesh: no two triangles on the same three features.
      std::map<std::array<int, 3>, std::size_t> corners_seen;
      for (std::size_t l = 0; l < c.loops.size(); ++l) {
        std::array<int, 3> t{c.loops[l][0].from, c.loops[l][1].from, c.loops[l][2].from};
        std::sort(t.begin(), t.end());
        auto [it, fresh] = corners_seen.insert({t, l});
        if (!fresh) throw_insufficient(c, topo, c.loop_patch[l]);
      }
      return;
    }
    throw Algorithm_error("internal error: the layout of a mesh of genus " + std::to_string(genus) +
                          " did not terminate");
  }

  /// Frees chord (x, y) of a disk patch when x and y are already joined by a path p elsewhere: if both sides of
  /// p are triangular patches (x, y, c) and (y, x, d) (disks, as every patch is when this is called), p is flipped
  /// to (c, d) inside their union, as in §3.3. Returns whether p was flipped.
  bool unblock_chord(int x, int y) {
    const int p = connected(x, y);
    if (p == no_path) return false;
    const Combinatorics c = combinatorics_rotations_only();
    const Dart dab{p, path_ends[p][0]}, dba{p, path_ends[p][1]};
    auto same = [](const Dart& u, const Dart& v) { return u.path == v.path && u.from == v.from; };
    const Dart d1 = next_dart(c, dab), d2 = next_dart(c, d1), e1 = next_dart(c, dba), e2 = next_dart(c, e1);
    if (!same(next_dart(c, d2), dab) || !same(next_dart(c, e2), dba)) return false; // not two triangles
    if (same(d1, dba) || same(d2, dba) || same(e1, dab) || same(e2, dab)) return false; // one patch on both sides
    const int cc = d2.from, dd = e2.from;
    if (cc == dd || connected(cc, dd) != no_path) return false;
    remove_path(p);
    add_traced_pair(cc, dd, d2.path, e2.path);
    ++stats.flips;
    return true;
  }

  /// Pairs of features whose path move_path_into() has moved: each moves at most once, which bounds the moves.
  std::set<std::pair<int, int>> moved_pairs;

  /// Replaces the path joining x and y elsewhere by a chord (x, y) of a disk patch, from sector cx of x to sector
  /// cy of y. The two patches on the sides of the old path merge and are triangulated again later.
  bool move_path_into(int x, int y, int cx, int cy) {
    const int p = connected(x, y);
    if (p == no_path || p == cx || p == cy || !moved_pairs.insert({std::min(x, y), std::max(x, y)}).second) return false;
    remove_path(p);
    add_traced_pair(x, y, cx, cy);
    return true;
  }

  /// Sides (feature pairs) that rotate_side() has turned: each at most once, which bounds the turns.
  std::set<std::pair<int, int>> rotated_pairs;

  /// For a disk patch with no admissible chord: a side (x, y) of its loop whose other side is a triangular
  /// patch (y, x, v) is removed, and v is joined to a corner u of the loop (u not x, y, v and not joined to v)
  /// across the union of the two patches, a disk, which the chord splits alike on both meshes.
  bool rotate_side(const Combinatorics& c, const std::vector<Dart>& loop) {
    auto same = [](const Dart& u, const Dart& v) { return u.path == v.path && u.from == v.from; };
    const std::size_t k = loop.size();
    double best = HUGE_VAL;
    int pick_path = no_path, pick_v = -1, pick_u = -1, corner_v = 0, corner_u = 0;
    for (std::size_t i = 0; i < k; ++i) {
      const int q = loop[i].path, x = loop[i].from, y = loop[(i + 1) % k].from;
      if (rotated_pairs.count({std::min(x, y), std::max(x, y)})) continue;
      const Dart r{q, y}, e1 = next_dart(c, r), e2 = next_dart(c, e1);
      if (!same(next_dart(c, e2), r)) continue; // the other side is not a triangle
      bool inside = false;                      // the other side is this patch itself
      for (const Dart& d : loop) inside |= same(d, r) || same(d, e1) || same(d, e2);
      if (inside) continue;
      const int v = e2.from;
      for (std::size_t j = 0; j < k; ++j) {
        const int u = loop[j].from;
        if (u == x || u == y || u == v || connected(u, v) != no_path) continue;
        if (loop[j].path == q) continue;
        const double d = feature_distance(u, v);
        if (d < best) {
          best = d;
          pick_path = q, pick_v = v, pick_u = u, corner_v = e2.path, corner_u = loop[j].path;
        }
      }
    }
    if (pick_path == no_path) return false;
    const auto [x, y] = path_ends[pick_path];
    rotated_pairs.insert({std::min(x, y), std::max(x, y)});
    remove_path(pick_path);
    add_traced_pair(pick_v, pick_u, corner_v, corner_u);
    ++stats.flips;
    return true;
  }

  /// Source patch label -> label of the same patch on mesh s (the face left of one of its darts).
  int patch_on(int s, const Dart& d, const std::vector<int>& label) const {
    return label[side[s].m.face(dart_halfedge(s, d))];
  }

  /// Cuts one handle of the patch bounded by `loop` (its only loop): a pair of paths between two corners of the
  /// loop, distinct features not yet joined, that splits the patch on neither mesh (each crosses a handle cycle
  /// of its mesh an odd number of times). Closest corners first; among the candidates of both meshes the most
  /// consistent pair. If the free vertices of the patch are too few for such paths, the edges inside the patch
  /// joining two of its boundary vertices are split once and the search repeated. Returns false if no pair
  /// was found.
  bool cut_handle(const std::vector<Dart>& loop) {
    std::vector<std::tuple<double, int, int, int, int>> pairs;
    for (std::size_t i = 0; i < loop.size(); ++i)
      for (std::size_t j = i + 1; j < loop.size(); ++j) {
        const int x = loop[i].from, y = loop[j].from;
        if (x == y || connected(x, y) != no_path) continue;
        pairs.push_back({feature_distance(x, y), x, y, loop[i].path, loop[j].path});
      }
    std::sort(pairs.begin(), pairs.end());
    if (pairs.size() > max_handle_corner_pairs) pairs.resize(max_handle_corner_pairs);
    const int tmp = int(path_ends.size());
    for (int attempt = 0; attempt < 2; ++attempt) {
      std::array<std::vector<int>, 2> label;
      std::array<Layout_mesh::Handle_cycles, 2> hc;
      for (int s = 0; s < 2; ++s) {
        side[s].label_patches(label[s]);
        hc[s] = side[s].handle_cycles(label[s], patch_on(s, loop[0], label[s]));
      }
      for (const auto& [d, x, y, cx, cy] : pairs) {
        std::array<std::vector<Halfedge_path>, 2> found;
        for (int s = 0; s < 2; ++s)
          for (std::size_t k = 0; k < hc[s].leftover.size() && k < max_handle_cycles; ++k) {
            Halfedge_path hp = side[s].handle_cutting_path(x, y, cx, cy, hc[s], hc[s].leftover[k]);
            if (!hp.empty() && !side[s].split_signature(hp, tmp, degree).splits) found[s].push_back(std::move(hp));
          }
        if (found[0].empty() || found[1].empty()) continue;
        std::size_t bi = 0, bj = 0;
        double bc = HUGE_VAL;
        for (std::size_t i = 0; i < found[0].size(); ++i)
          for (std::size_t j = 0; j < found[1].size(); ++j) {
            const double q = consistent_paths ? consistency(found[0][i], found[1][j])
                                              : side[0].path_length(found[0][i]) + side[1].path_length(found[1][j]);
            if (q < bc) bc = q, bi = i, bj = j;
          }
        if (!non_blocking(found[0][bi], found[1][bj]))
          throw Algorithm_error("internal error: two handle cuts of matching patches differ");
        add_path(x, y, found[0][bi], found[1][bj]);
        return true;
      }
      if (attempt == 0)
        for (int s = 0; s < 2; ++s) refine_patch(s, label[s], patch_on(s, loop[0], label[s]));
    }
    return false;
  }

  /// Splits every non-path edge of a patch whose two ends are on its boundary: the patch gains free vertices
  /// along its boundary.
  void refine_patch(int s, const std::vector<int>& label, int patch) {
    Layout_mesh& L = side[s];
    std::vector<std::pair<WV, WV>> todo;
    for (WE e : L.m.edges()) {
      const WH h = L.m.halfedge(e);
      if (L.epath[e] != no_path || label[L.m.face(h)] != patch) continue;
      if (!L.is_free(L.m.source(h)) && !L.is_free(L.m.target(h))) todo.push_back({L.m.source(h), L.m.target(h)});
    }
    for (auto [u, v] : todo) L.split_edge(u, v);
  }

  /// Throws Insufficient_features_error for source patch `p` of `c`: its corner features, what it still carries,
  /// and per mesh an input vertex near a handle of it (on a handle cycle) or deep inside it.
  [[noreturn]] void throw_insufficient(const Combinatorics& c, const Patch_topology& topo, int p) const {
    std::vector<int> corners;
    for (std::size_t l : topo.loops[p])
      for (const Dart& d : c.loops[l]) corners.push_back(d.from);
    for (std::size_t a = 0; a < nf(); ++a)
      if (c.isolated_patch[a] == p) corners.push_back(int(a));
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    std::ostringstream msg;
    msg << "too few features for meshes of genus " << genus << ": the patch with corner feature"
        << (corners.size() == 1 ? " " : "s ");
    for (std::size_t i = 0; i < corners.size(); ++i) msg << (i ? ", " : "") << corners[i];
    const std::size_t loops = topo.loops[p].size();
    if (topo.genus[p] > 0)
      msg << " still has " << topo.genus[p] << (topo.genus[p] == 1 ? " handle" : " handles");
    else if (loops != 1)
      msg << " still has " << loops << " boundary loops";
    else
      msg << " cannot be cut into triangles without joining two features twice";
    msg << " on both meshes; one more corresponding feature near";
    const char* names[2] = {"source", "target"};
    for (int s = 0; s < 2; ++s) {
      std::vector<int> label;
      side[s].label_patches(label);
      int ps = -1;
      if (!topo.loops[p].empty())
        ps = patch_on(s, c.loops[topo.loops[p].front()].front(), label);
      else if (!corners.empty())
        ps = label[side[s].m.face(side[s].out_halfedge(side[s].feature_vertex[corners.front()]))];
      msg << (s ? " and" : "") << " " << names[s] << " vertex " << hint_vertex(s, label, ps);
    }
    msg << " would help (give about four features around each handle)";
    throw Insufficient_features_error(msg.str());
  }

  /// An input vertex of mesh s in patch `patch`: an end of its first handle cycle's leftover edge if it has
  /// handles, otherwise the free vertex farthest (in edges) from its boundary.
  std::size_t hint_vertex(int s, const std::vector<int>& label, int patch) const {
    const Layout_mesh& L = side[s];
    const auto hc = L.handle_cycles(label, patch);
    WV v = L.feature_vertex.empty() ? WV(0) : L.feature_vertex[0];
    if (!hc.leftover.empty()) {
      const WH h = L.m.halfedge(hc.leftover.front());
      v = L.is_free(L.m.source(h)) ? L.m.source(h) : L.m.target(h);
    } else {
      int deepest = -1;
      for (WV w : L.m.vertices())
        if (hc.depth[w] > deepest) deepest = hc.depth[w], v = w;
    }
    return L.input_vertex_near(v);
  }

  // ---------------------------------------------------------------------------------------------------
  // §3.3 path flips: replace path (a,b) by (c,d) when deg(a)+deg(b) > deg(c)+deg(d)+2.
  // Each flip lowers the sum of squared degrees, so the loop terminates.
  // ---------------------------------------------------------------------------------------------------
  /// The darts of path p's two triangles that leave the corners opposite p: c -> a in the triangle on p's left
  /// (a -> b -> c) and d -> b in the one on its right (b -> a -> d), a and b p's ends.
  std::pair<Dart, Dart> opposite_darts(const Combinatorics& c, int p) const {
    return {next_dart(c, next_dart(c, Dart{p, path_ends[p][0]})), next_dart(c, next_dart(c, Dart{p, path_ends[p][1]}))};
  }

  void flip_paths() {
    bool changed = true;
    std::size_t guard = 0;
    while (changed && guard++ < 64 * nf() + 64) {
      changed = false;
      for (int p = 0; p < int(path_ends.size()); ++p) {
        if (path_ends[p][0] < 0) continue;
        Combinatorics c = combinatorics_rotations_only();
        int a = path_ends[p][0], b = path_ends[p][1];
        const auto [d2, e2] = opposite_darts(c, p);
        int cc = d2.from, dd = e2.from;
        if (cc == dd || connected(cc, dd) != no_path) continue;
        if (degree[a] + degree[b] <= degree[cc] + degree[dd] + 2) continue;
        // A flip is taken only when the new path needs at most max_flip_splits edge splits on each mesh:
        // flips exist to improve valences, and every split adds a vertex to every output mesh.
        Halfedge_path old_s = side[0].paths[p], old_t = side[1].paths[p];
        remove_path(p);
        bool affordable = true;
        for (int s = 0; s < 2 && affordable; ++s)
          if (side[s].shortest_path(cc, dd, d2.path, e2.path).empty())
            affordable = side[s].face_path_split_count(cc, dd, d2.path, e2.path) <= max_flip_splits;
        if (!affordable) {
          add_path(a, b, old_s, old_t, p); // restore, same id
          continue;
        }
        add_traced_pair(cc, dd, d2.path, e2.path);
        ++stats.flips;
        changed = true;
      }
    }
  }

  /// Straightening (an addition to the paper): each path of the finished layout, on each mesh, is replaced by
  /// the shortest edge path between its two features through the free vertices of the two patches beside it,
  /// leaving and entering the same sectors, when that is shorter on the two meshes together. A path is the
  /// shortest in its sectors when PathMatch adds it, but the paths added after it are not there yet: the
  /// finished layout often leaves a shorter way inside the quadrilateral of its two triangles (on a pair of
  /// meshes of one surface, 3 % of the total length and patches that differ between the two meshes). The two
  /// triangles must have four distinct corners, so that together they are a disk, and every path inside it
  /// from one feature to the other splits it the same way: the combinatorics and the homotopy class of the
  /// layout stay as they are (the blocking test still checks it). No vertex is added. Passes over all paths
  /// until one changes none, at most `max_straightening_passes`; each path can only get shorter, so the
  /// passes converge.
  void straighten_paths() {
    for (unsigned pass = 0; pass < max_straightening_passes; ++pass) {
      std::size_t changed = 0;
      for (int p = 0; p < int(path_ends.size()); ++p) {
        if (path_ends[p][0] < 0) continue;
        const Combinatorics c = combinatorics_rotations_only();
        const int a = path_ends[p][0], b = path_ends[p][1];
        const auto [dx, dy] = opposite_darts(c, p);
        const int x = dx.from, y = dy.from;
        if (x == y || x == a || x == b || y == a || y == b) continue;
        const Halfedge_path old_s = side[0].paths[p], old_t = side[1].paths[p];
        const double before = side[0].path_length(old_s) + side[1].path_length(old_t);
        remove_path(p);
        // The sectors the path occupied, named by the next path clockwise, as on both meshes.
        const auto cs = corners(0, old_s), ct = corners(1, old_t);
        Halfedge_path hs, ht;
        if (cs == ct) {
          hs = side[0].shortest_path(a, b, cs.first, cs.second);
          ht = side[1].shortest_path(a, b, cs.first, cs.second);
        }
        if (!hs.empty() && !ht.empty() && side[0].path_length(hs) + side[1].path_length(ht) < before * (1 - 1e-9) &&
            non_blocking(hs, ht)) {
          add_path(a, b, hs, ht, p);
          ++changed;
        } else {
          add_path(a, b, old_s, old_t, p);
        }
      }
      stats.straightened += changed;
      if (changed == 0) break;
    }
  }

  /// Paper §4.2, adjacency constraint: splits every edge inside a patch whose two ends lie on the patch
  /// boundary (on paths or at features). Afterwards no triangle has all its corners on one base edge, and every
  /// edge joins vertices of one patch or of two adjacent ones. Returns the number of splits.
  std::size_t split_for_adjacency(int s) {
    Layout_mesh& L = side[s];
    auto on_boundary = [&](WV v) { return L.vfeature[v] != no_feature || L.vpath[v] != no_path; };
    std::vector<std::pair<WV, WV>> todo;
    for (WE e : L.m.edges()) {
      if (L.epath[e] != no_path) continue;
      WH h = L.m.halfedge(e);
      if (on_boundary(L.m.source(h)) && on_boundary(L.m.target(h))) todo.push_back({L.m.source(h), L.m.target(h)});
    }
    for (auto [u, v] : todo) L.split_edge(u, v);
    return todo.size();
  }

  Combinatorics combinatorics_rotations_only() const {
    Combinatorics c;
    c.rotation.resize(nf());
    for (std::size_t a = 0; a < nf(); ++a) c.rotation[a] = side[0].rotation(side[0].feature_vertex[a]);
    return c;
  }
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_LAYOUT_BUILDER_H

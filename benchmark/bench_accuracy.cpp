// SPDX-License-Identifier: GPL-3.0-or-later
// Accuracy of the map on the wider bench (test/wide_cases.h): per case the mean and maximum error against the
// truth (dense or held-out landmarks) in units of sqrt(target area), the nearest-point baselines, the time;
// then the mean and the worst over all cases and per family.
//
// Usage: bench_accuracy [options] [FILTER...]
//   FILTER       only the cases whose name contains one of these strings (default: all)
//   --detail     after each case, where its scored points land: per landmark (the target landmark nearest to
//                the image, to show swaps) or, for dense truth, per region of the source (the geodesic Voronoi
//                cell of each feature)
//   --ply DIR    write DIR/<case>_source.ply, the source coloured by the error of each vertex (dense cases, blue
//                0 to red at 0.1), or DIR/<case>_image.ply, the target with the true partners of the scored
//                landmarks green and the vertices nearest to their images red (landmark cases)
//   --png        with --ply, render the same meshes to PNG with POV-Ray (tools/cli/render.h)
//   --view X,Y,Z --up X,Y,Z   the camera of --png (direction from the object to the camera, the up vector)
//   --threads N  threads of the map (default 1: the figures do not depend on it, the times do)
//   --extremity-features MODE    select (the default: the pairs kept when they lower the map's worst
//                                descriptor mismatch), all (every pair found kept) or off
//   --extremity-persistence X    their persistence threshold (default 0.05, in sqrt(area) units)
//   --straighten-paths           the layout's paths shortened once it is complete (parameters::straighten_paths)
//   --map-smoothing on|off       the smoothing of F itself after the paper's (parameters::map_smoothing, default off)
// The table's "descriptor mismatch" is the map's mean disagreement with the geodesic distances to the case's
// features (Cross_parameterization::descriptor_mismatch), a figure that needs no truth.
#include "../test/wide_cases.h"

#include "../tools/cli/render.h"
#include "bench_common.h"

#include <cstdio>
#include <map>
#include <set>

using namespace crossparam;
namespace fs = std::filesystem;

namespace {

/// Error at which the colour scale of --ply saturates (red), in units of sqrt(target area).
constexpr double ply_error_scale = 0.1;
/// Radius of the landmark marks of --ply, in units of sqrt(target area): large enough to see on a picture.
constexpr double ply_mark_radius = 0.02;

cli::Render_options render_options;

std::array<unsigned char, 3> heat(double e) {
  const double x = std::clamp(e / ply_error_scale, 0.0, 1.0);
  return {static_cast<unsigned char>(255 * x), static_cast<unsigned char>(255 * (1 - std::abs(2 * x - 1))),
          static_cast<unsigned char>(255 * (1 - x))};
}

std::string file_name(const std::string& name) {
  std::string s = name;
  std::replace(s.begin(), s.end(), '/', '_');
  return s;
}

void soup(const Surface_mesh& m, std::vector<std::array<double, 3>>& pts, std::vector<std::array<std::size_t, 3>>& tris) {
  for (auto v : m.vertices()) pts.push_back({m.point(v).x(), m.point(v).y(), m.point(v).z()});
  for (auto f : m.faces()) {
    std::array<std::size_t, 3> t;
    int i = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) t[i++] = std::size_t(v);
    tris.push_back(t);
  }
}

/// Geodesic (edge-graph) Voronoi cells of the features on the source: the feature index of each vertex.
std::vector<int> feature_cells(const Surface_mesh& m, const Feature_correspondence& f) {
  std::vector<double> dist(m.number_of_vertices(), std::numeric_limits<double>::infinity());
  std::vector<int> cell(m.number_of_vertices(), -1);
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
  for (std::size_t k = 0; k < f.size(); ++k) {
    dist[f[k].source] = 0;
    cell[f[k].source] = int(k);
    q.push({0, f[k].source});
  }
  while (!q.empty()) {
    auto [d, v] = q.top();
    q.pop();
    if (d > dist[v]) continue;
    const auto vi = Surface_mesh::Vertex_index(Surface_mesh::size_type(v));
    for (auto w : CGAL::vertices_around_target(m.halfedge(vi), m)) {
      const double dw = d + std::sqrt(CGAL::squared_distance(m.point(vi), m.point(w)));
      if (dw < dist[std::size_t(w)]) {
        dist[std::size_t(w)] = dw;
        cell[std::size_t(w)] = cell[v];
        q.push({dw, std::size_t(w)});
      }
    }
  }
  return cell;
}

void detail(const wide_bench::Case& c, const wide_bench::Outcome& o) {
  const double norm = std::sqrt(CGAL::Polygon_mesh_processing::area(c.target));
  if (!c.is_dense()) {
    // Every landmark of the target (features and scored), to name the one the image lands nearest to.
    std::vector<std::pair<std::string, std::size_t>> marks;
    for (std::size_t k = 0; k < c.features.size(); ++k) marks.push_back({"f" + std::to_string(k), c.features[k].target});
    for (std::size_t k = 0; k < c.landmarks.size(); ++k) marks.push_back({"s" + std::to_string(k), c.landmarks[k].second});
    // The protrusion features the map added: the landmarks nearest to their two ends (a pair whose ends are
    // near different landmarks joins different parts of the animals).
    std::vector<std::pair<std::string, std::size_t>> source_marks;
    for (std::size_t k = 0; k < c.features.size(); ++k) source_marks.push_back({"f" + std::to_string(k), c.features[k].source});
    for (std::size_t k = 0; k < c.landmarks.size(); ++k) source_marks.push_back({"s" + std::to_string(k), c.landmarks[k].first});
    const double norm_s = std::sqrt(CGAL::Polygon_mesh_processing::area(c.source));
    auto nearest = [](const Surface_mesh& m, const std::vector<std::pair<std::string, std::size_t>>& ms, const Point_3& p,
                      double scale) {
      double best = HUGE_VAL;
      std::string who;
      for (const auto& [n, v] : ms) {
        const double d = std::sqrt(CGAL::squared_distance(p, wide_bench::point(m, v))) / scale;
        if (d < best) best = d, who = n;
      }
      return std::make_pair(who, best);
    };
    std::printf("  squeeze source %.3g, target %.3g\n", o.stats.squeeze_source, o.stats.squeeze_target);
    for (std::size_t k = c.features.size(); k < o.map_features.size(); ++k) {
      const auto a = nearest(c.source, source_marks, wide_bench::point(c.source, o.map_features[k].source), norm_s);
      const auto b = nearest(c.target, marks, wide_bench::point(c.target, o.map_features[k].target), norm);
      std::printf("  protrusion feature %zu: source %zu near %s (%.3f), target %zu near %s (%.3f)%s\n", k,
                  o.map_features[k].source, a.first.c_str(), a.second, o.map_features[k].target, b.first.c_str(),
                  b.second, a.first == b.first ? "" : "  <- different landmarks");
    }
    std::printf("  | scored | source v | target v | error | baseline | lands nearest to | its distance |\n");
    std::printf("  |---|---:|---:|---:|---:|---|---:|\n");
    for (std::size_t k = 0; k < o.points.size(); ++k) {
      const wide_bench::Scored& p = o.points[k];
      double best = HUGE_VAL;
      std::string who;
      for (const auto& [n, v] : marks) {
        const double d = std::sqrt(CGAL::squared_distance(p.image, wide_bench::point(c.target, v))) / norm;
        if (d < best) best = d, who = n;
      }
      std::printf("  | s%zu | %zu | %zu | %.4f | %.4f | %s%s | %.4f |\n", k, p.source_vertex, p.target_vertex, p.error,
                  p.baseline, who.c_str(), who == "s" + std::to_string(k) ? " (itself)" : "", best);
    }
    return;
  }
  // Dense: the features the map added, each with the distance of its target end from the truth of its source
  // end (a wrong pair joins points that do not correspond).
  for (std::size_t k = c.features.size(); k < o.map_features.size(); ++k) {
    const Point_3 t = wide_bench::point(c.target, o.map_features[k].target);
    std::printf("  added feature %zu: source %zu, target %zu, %.4f from the truth\n", k, o.map_features[k].source,
                o.map_features[k].target, std::sqrt(CGAL::squared_distance(t, c.dense.at(o.map_features[k].source))) / norm);
  }
  // Per feature cell of the source, the mean and max error and the share of the total error.
  const std::vector<int> cell = feature_cells(c.source, c.features);
  struct Acc {
    double sum = 0, max = 0;
    std::size_t n = 0;
  };
  std::vector<Acc> acc(c.features.size());
  double total = 0;
  for (const wide_bench::Scored& p : o.points) {
    Acc& a = acc[std::size_t(std::max(0, cell[p.source_vertex]))];
    a.sum += p.error;
    a.max = std::max(a.max, p.error);
    ++a.n;
    total += p.error;
  }
  std::printf("  | cell of feature | source v | vertices | mean | max | share of total error |\n");
  std::printf("  |---:|---:|---:|---:|---:|---:|\n");
  for (std::size_t k = 0; k < acc.size(); ++k)
    std::printf("  | %zu | %zu | %zu | %.4f | %.4f | %.1f%% |\n", k, c.features[k].source, acc[k].n,
                acc[k].n ? acc[k].sum / double(acc[k].n) : 0.0, acc[k].max, 100 * acc[k].sum / std::max(total, 1e-300));
}

void output(const fs::path& path, const std::vector<std::array<double, 3>>& pts,
            const std::vector<std::array<std::size_t, 3>>& tris, const std::vector<std::array<unsigned char, 3>>& col,
            bool png) {
  write_ply_vertex_colored(path.string(), pts, tris, col);
  if (!png) return;
  cli::Render_mesh m{pts, tris, {}, col};
  fs::path p = path;
  cli::render_png(m, p.replace_extension(".png").string(), render_options);
}

void write_ply(const fs::path& dir, const wide_bench::Case& c, const wide_bench::Outcome& o, bool png) {
  fs::create_directories(dir);
  std::vector<std::array<double, 3>> pts;
  std::vector<std::array<std::size_t, 3>> tris;
  if (c.is_dense()) {
    soup(c.source, pts, tris);
    std::vector<std::array<unsigned char, 3>> col(pts.size(), {128, 128, 128});
    for (const wide_bench::Scored& p : o.points) col[p.source_vertex] = heat(p.error);
    output(dir / (file_name(c.name) + "_source.ply"), pts, tris, col, png);
    return;
  }
  // Landmarks: the target grey, the true partners' one-rings green, the images' nearest vertices' one-rings red.
  soup(c.target, pts, tris);
  std::vector<std::array<unsigned char, 3>> col(pts.size(), {160, 160, 160});
  const double radius = ply_mark_radius * std::sqrt(CGAL::Polygon_mesh_processing::area(c.target));
  auto mark = [&](std::size_t v, std::array<unsigned char, 3> rgb) {
    const Point_3 centre = wide_bench::point(c.target, v);
    for (auto w : c.target.vertices())
      if (CGAL::squared_distance(c.target.point(w), centre) <= radius * radius) col[std::size_t(w)] = rgb;
  };
  for (const wide_bench::Scored& p : o.points) {
    mark(p.target_vertex, {0, 200, 0});
    std::size_t near = 0;
    double best = HUGE_VAL;
    for (auto v : c.target.vertices()) {
      const double d = CGAL::squared_distance(c.target.point(v), p.image);
      if (d < best) best = d, near = std::size_t(v);
    }
    mark(near, {220, 0, 0});
  }
  output(dir / (file_name(c.name) + "_image.ply"), pts, tris, col, png);
}

} // namespace

int main(int argc, char** argv) {
  std::vector<std::string> filters;
  bool show_detail = false, png = false;
  fs::path ply_dir;
  unsigned threads = 1;
  bool extremities = true, select = true, straighten = false, smooth_map = false;
  double persistence = Cross_parameterization<Surface_mesh, Surface_mesh>::default_extremity_persistence;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--detail")
      show_detail = true;
    else if (a == "--png")
      png = true;
    else if ((a == "--view" || a == "--up") && i + 1 < argc) {
      std::array<double, 3> x{};
      if (std::sscanf(argv[++i], "%lf,%lf,%lf", &x[0], &x[1], &x[2]) != 3) {
        std::fprintf(stderr, "bench_accuracy: %s takes X,Y,Z\n", a.c_str());
        return 2;
      }
      (a == "--view" ? render_options.view_direction : render_options.up) = x;
    } else if (a == "--ply" && i + 1 < argc)
      ply_dir = argv[++i];
    else if (a == "--threads" && i + 1 < argc)
      threads = unsigned(std::stoul(argv[++i]));
    else if (a == "--extremity-features" && i + 1 < argc) {
      const std::string m = argv[++i];
      if (m != "off" && m != "all" && m != "select") {
        std::fprintf(stderr, "bench_accuracy: --extremity-features takes off, all or select\n");
        return 2;
      }
      extremities = m != "off";
      select = m == "select";
    }
    else if (a == "--straighten-paths")
      straighten = true;
    else if (a == "--map-smoothing" && i + 1 < argc) {
      const std::string m = argv[++i];
      if (m != "off" && m != "on") {
        std::fprintf(stderr, "bench_accuracy: --map-smoothing takes on or off\n");
        return 2;
      }
      smooth_map = m == "on";
    }
    else if (a == "--extremity-persistence" && i + 1 < argc)
      persistence = std::stod(argv[++i]);
    else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "bench_accuracy: unknown option %s\n", a.c_str());
      return 2;
    } else
      filters.push_back(a);
  }
  std::vector<std::string> names;
  for (const std::string& n : wide_bench::names()) {
    bool keep = filters.empty();
    for (const std::string& f : filters) keep = keep || n.find(f) != std::string::npos;
    if (keep) names.push_back(n);
  }

  char ext[96] = "off";
  if (extremities)
    std::snprintf(ext, sizeof ext, "%s (persistence %g)", select ? "selected by the worst descriptor mismatch" : "all kept",
                  persistence);
  std::printf("map accuracy on the wider bench, one run per case, %u thread(s), assertions %s; extremity features "
              "%s;%s%s errors in units of sqrt(target area)\n\n",
              threads, bench::assertions(), ext, straighten ? " paths straightened;" : "", smooth_map ? " map smoothing;" : "");
  std::printf("| case | truth | V source | V target | features (+ protrusion + extremity) | points | mean | median | max | "
              "nearest point | nearest after similarity | descriptor mismatch | time (s) |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  std::vector<std::pair<std::string, wide_bench::Outcome>> all;
  std::map<std::string, std::vector<std::pair<std::string, wide_bench::Outcome>>> by_family;
  std::size_t absent = 0;
  for (const std::string& n : names) {
    const std::optional<wide_bench::Case> c = wide_bench::load(n);
    if (!c) {
      ++absent;
      std::printf("| %s | absent | | | | | | | | | | | |\n", n.c_str());
      continue;
    }
    const wide_bench::Outcome o = wide_bench::evaluate(
        *c, parameters::number_of_threads(threads, parameters::extremity_features(
                                                       extremities, parameters::select_extremity_features(select,
                                                           parameters::extremity_persistence(persistence, parameters::straighten_paths(straighten, parameters::map_smoothing(smooth_map)))))));
    if (!o.ok)
      std::printf("| %s | %s | %zu | %zu | %zu | | FAILED: %s | | | | | | %.1f |\n", n.c_str(), c->is_dense() ? "dense" : "landmarks",
                  o.source_vertices, o.target_vertices, o.features, o.message.c_str(), o.seconds);
    else
      std::printf("| %s | %s | %zu | %zu | %zu + %zu + %zu | %zu | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.1f |\n", n.c_str(),
                  c->is_dense() ? "dense" : "landmarks", o.source_vertices, o.target_vertices, o.features,
                  o.protrusion_features, o.stats.extremity_features, o.points.size(), o.mean, o.median, o.max, o.baseline_mean, o.aligned_mean,
                  o.descriptor_mismatch, o.seconds);
    std::fflush(stdout);
    if (show_detail && o.ok) detail(*c, o);
    if (!ply_dir.empty() && o.ok) write_ply(ply_dir, *c, o, png);
    all.emplace_back(n, o);
    by_family[wide_bench::family(n) + (c->is_dense() ? " (dense)" : " (landmarks)")].emplace_back(n, o);
    by_family[c->is_dense() ? "all dense" : "all landmark"].emplace_back(n, o);
  }
  std::printf("\n| set | cases | failed | mean of means | worst mean (case) | mean of maxima | nearest point |\n");
  std::printf("|---|---:|---:|---:|---|---:|---:|\n");
  auto row = [](const std::string& set, const std::vector<std::pair<std::string, wide_bench::Outcome>>& r) {
    const wide_bench::Aggregate a = wide_bench::aggregate(r);
    std::printf("| %s | %zu | %zu | %.4f | %.4f (%s) | %.4f | %.4f |\n", set.c_str(), a.cases, a.failed, a.mean,
                a.worst, a.worst_case.c_str(), a.mean_of_max, a.baseline_mean);
  };
  for (const auto& [set, r] : by_family) row(set, r);
  row("all", all);
  if (absent) std::printf("\n%zu case(s) absent (no ../shared/data)\n", absent);
  return 0;
}

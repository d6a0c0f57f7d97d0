// SPDX-License-Identifier: GPL-3.0-or-later
// What each command writes: the output files (meshes, patch ids, vertex maps, the checkerboard texture, the
// morph frames), report.json, the pictures of --png and the summary lines on stdout. The files of one result
// are written into a staging folder (Output_folder) and moved into the output folder together at the end.
#ifndef CROSSPARAM_CLI_OUTPUTS_H
#define CROSSPARAM_CLI_OUTPUTS_H

#include "options.h"
#include "png.h"
#include "render.h"
#include "report.h"

#include <crossparam/compatible_remeshing.h>
#include <crossparam/cross_parameterization.h>
#include <crossparam/io.h>
#include <crossparam/morph.h>
#include <crossparam/patch_layout.h>
#include <crossparam/remeshing_verification.h>
#include <crossparam/scaling.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace crossparam {
namespace cli {

namespace fs = std::filesystem;

using Map = Cross_parameterization<Surface_mesh, Surface_mesh>;
using Remesher = Compatible_remesher<Surface_mesh, Surface_mesh>;

/// Wall-clock seconds since construction.
struct Timer {
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
};

/// The folder the files of `o` are written into: the staging folder while a result is being written (see
/// Output_folder), else the output folder.
inline const std::string& write_folder(const Options& o) { return o.staging.empty() ? o.output : o.staging; }

/// The path of file `name` in the folder the files are written into.
inline std::string output_path(const Options& o, const std::string& name) { return (fs::path(write_folder(o)) / name).string(); }

/// A distinct, stable colour per id (golden-ratio hue steps).
inline std::array<unsigned char, 3> color_of(std::size_t id) {
  double h = std::fmod(0.1 + 0.61803398875 * double(id), 1.0) * 6.0, s = 0.65, v = 0.95;
  int i = int(h);
  double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r, g, b;
  switch (i % 6) {
  case 0: r = v, g = t, b = p; break;
  case 1: r = q, g = v, b = p; break;
  case 2: r = p, g = v, b = t; break;
  case 3: r = p, g = q, b = v; break;
  case 4: r = t, g = p, b = v; break;
  default: r = v, g = p, b = q; break;
  }
  return {static_cast<unsigned char>(r * 255), static_cast<unsigned char>(g * 255), static_cast<unsigned char>(b * 255)};
}

/// Blue (no error) through white to red (at or above the tolerance).
inline std::array<unsigned char, 3> error_color(double e, double tolerance) {
  const double x = std::min(1.0, std::max(0.0, e / tolerance));
  auto c = [](double a, double b, double t) { return static_cast<unsigned char>(std::lround(a + (b - a) * t)); };
  if (x < 0.5) return {c(40, 255, 2 * x), c(80, 255, 2 * x), c(220, 255, 2 * x)};
  return {c(255, 220, 2 * x - 1), c(255, 40, 2 * x - 1), c(255, 30, 2 * x - 1)};
}

/// `points` in the user's units (see Options::units_exponent): exact, a power-of-two factor.
inline std::vector<std::array<double, 3>> in_user_units(const Options& o, std::vector<std::array<double, 3>> points) {
  return scaled_by_power_of_two(std::move(points), -o.units_exponent);
}
inline Point_3 in_user_units(const Options& o, const Point_3& p) {
  const int k = -o.units_exponent;
  return Point_3(std::ldexp(p.x(), k), std::ldexp(p.y(), k), std::ldexp(p.z(), k));
}

/// Inputs whose larger bounding-box diagonal lies in [2^-units_band, 2^(units_band + 1)) are computed in their
/// own units; others are first scaled by a power of two to a diagonal in [1, 2). A pair at any scale the
/// readers accept (up to 1e100, down to where the mesh checks still see distinct points) is computed
/// at a moderate scale, far from overflow and underflow, and pairs that differ by a scale outside the band give
/// the same results up to the rounding of their mantissas.
constexpr int units_band = 20;

/// Scales `s` and `t` as units_band says and records the exponent in `o.units_exponent` (see there).
inline void normalize_units(Options& o, Surface_mesh& s, Surface_mesh& t) {
  const int k = unit_scale_exponent<Surface_mesh>({&s, &t});
  o.units_exponent = std::abs(k) <= units_band ? 0 : k;
  scale_by_power_of_two(s, o.units_exponent);
  scale_by_power_of_two(t, o.units_exponent);
}

/// The points and triangles of a triangle mesh, in vertex index order.
inline void soup_of(const Surface_mesh& m, std::vector<std::array<double, 3>>& pts, std::vector<std::array<std::size_t, 3>>& tris) {
  pts.clear();
  tris.clear();
  for (auto v : m.vertices()) pts.push_back({m.point(v).x(), m.point(v).y(), m.point(v).z()});
  for (auto f : m.faces()) {
    std::array<std::size_t, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) t[k++] = std::size_t(v);
    tris.push_back(t);
  }
}

/// Writes report.json into the output directory; `members` adds the members of its top-level object.
template <class Members>
void write_report(const Options& o, const Members& members) {
  write_file_atomically(output_path(o, "report.json"), [&](std::ostream& os) {
    Json_writer json(os);
    json.begin_object();
    members(json);
    json.end_object();
  });
}

// ---- layout ----

/// Writes the outputs of `layout` (and the demo's layouts): the refined meshes, patch ids and coloured patches
/// of both meshes, the base mesh and report.json. `extra_times` are timings (seconds) to report before the
/// layout's own.
inline void write_layout(const Options& o, const Surface_mesh& s, const Surface_mesh& t, const Patch_layout& L,
                         const std::map<std::string, double>& extra_times) {
  fs::create_directories(write_folder(o));
  std::vector<std::array<double, 3>> pts;
  std::vector<std::array<std::size_t, 3>> tris;
  const Surface_mesh* meshes[2] = {&s, &t};
  const Mesh_layout* layouts[2] = {&L.source, &L.target};
  const char* names[2] = {"source", "target"};
  for (int k = 0; k < 2; ++k) {
    const std::string name = names[k];
    soup_of(*meshes[k], pts, tris);
    pts = in_user_units(o, std::move(pts));
    write_off(output_path(o, name + "_refined.off"), pts, tris);
    write_file_atomically(output_path(o, name + "_patches.txt"), [&](std::ostream& os) {
      for (int id : layouts[k]->face_triangle) os << id << "\n";
    });
    std::vector<std::array<unsigned char, 3>> colors;
    for (int id : layouts[k]->face_triangle) colors.push_back(color_of(std::size_t(id)));
    write_ply_colored(output_path(o, name + "_patches.ply"), pts, tris, colors);
    if (o.png) render_png(Render_mesh{pts, tris, colors, {}}, output_path(o, name + "_patches.png"), o.render);
  }
  write_file_atomically(output_path(o, "base_mesh.txt"), [&](std::ostream& os) {
    os << "# base triangles: three feature indices each, counter-clockwise seen from outside\n";
    for (const auto& tri : L.base_triangles) os << tri[0] << " " << tri[1] << " " << tri[2] << "\n";
  });
  const Layout_statistics& S = L.statistics;
  write_report(o, [&](Json_writer& j) {
    j.member("stage", "layout");
    for (int k = 0; k < 2; ++k) {
      j.key(names[k]).begin_object();
      j.member("vertices", layouts[k]->original_vertices).member("faces", layouts[k]->original_faces);
      j.member("refined_vertices", meshes[k]->number_of_vertices()).member("refined_faces", meshes[k]->number_of_faces());
      j.end_object();
    }
    j.member("features", S.features);
    j.member("base_triangles", L.base_triangles.size());
    j.member("paths", L.base_edges.size());
    j.member("edge_paths", S.edge_paths);
    j.member("face_paths", S.face_paths);
    j.key("face_traced").begin_object().member("source", S.face_traced_source).member("target", S.face_traced_target).end_object();
    j.key("splits").begin_object().member("source", S.splits_source).member("target", S.splits_target).end_object();
    j.member("flips", S.flips);
    j.member("straightened", S.straightened);
    j.member("rejected_blocking", S.rejected_blocking);
    j.member("verified", true);
    j.key("seconds").begin_object();
    for (const auto& [k, v] : extra_times) j.member(k, v);
    j.member("edge_paths", S.seconds_edge_paths).member("face_paths", S.seconds_face_paths);
    j.member("flips", S.seconds_flips).member("straightening", S.seconds_straightening);
    j.member("layout_total", S.seconds_total);
    j.end_object();
  });
}

/// The one-line summary of `layout`.
inline void print_layout_summary(const Options& o, const Patch_layout& L) {
  if (o.quiet) return;
  const Layout_statistics& S = L.statistics;
  std::cout << "layout: " << S.features << " features, " << L.base_triangles.size() << " base triangles, "
            << S.edge_paths << " edge paths, " << S.face_paths << " face paths, " << S.splits_source << "+"
            << S.splits_target << " splits, " << S.flips << " flips, " << format_number(S.seconds_total * 1000)
            << " ms; verified\n";
  std::cout << "wrote " << o.output << "/\n";
}

// ---- map ----

/// Side length in pixels of the checkerboard texture, and its squares per side.
constexpr int checker_pixels = 512, checker_squares = 32;
/// The checkerboard's two colours: dark blue and off-white.
constexpr std::array<unsigned char, 3> checker_dark{40, 60, 140}, checker_light{240, 235, 220};

/// The map at a glance: both input meshes as textured OBJ files sharing one checkerboard texture. Texture
/// coordinates come from the base domain: each base triangle owns a tile of the texture, and a vertex's UV is
/// its base location placed in that tile. A target vertex's UV is that of its preimage on the source (F^-1),
/// which is the same base location; corresponding squares on the two meshes are corresponding regions. With
/// --png, each mesh is also rendered with every face coloured by the texture at its centroid.
inline void write_checkerboard(const Options& o, const Map& cp) {
  const int tex = checker_pixels;
  std::vector<std::array<unsigned char, 3>> img(std::size_t(tex) * tex);
  for (int y = 0; y < tex; ++y)
    for (int x = 0; x < tex; ++x) {
      bool dark = ((x * checker_squares / tex) + (y * checker_squares / tex)) % 2;
      img[std::size_t(y) * tex + x] = dark ? checker_dark : checker_light;
    }
  write_file_atomically(output_path(o, "checker.png"), [&](std::ostream& os) { write_png(os, tex, tex, img); });
  write_file_atomically(output_path(o, "checker.mtl"), [&](std::ostream& os) {
    os << "newmtl checker\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nmap_Kd checker.png\n";
  });
  for (Mesh_side side : {Mesh_side::source, Mesh_side::target}) {
    const std::string name = side == Mesh_side::source ? "source" : "target";
    const Indexed_triangle_mesh mesh = cp.refined_mesh(side);
    const auto atlas = cp.base_atlas_coordinates(side);
    write_file_atomically(output_path(o, name + "_checker.obj"), [&](std::ostream& os) {
      os.precision(17);
      os << "# crossparam: " << name << " textured from the base domain\n";
      os << "mtllib checker.mtl\nusemtl checker\n";
      for (const Point_3& q : mesh.points) {
        const Point_3 p = in_user_units(o, q);
        os << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
      }
      for (std::size_t f = 0, k = 0; f < mesh.faces.size(); ++f, k += 3) {
        for (const auto& t : atlas[f]) os << "vt " << t[0] << " " << t[1] << "\n";
        const auto& vs = mesh.faces[f];
        os << "f " << vs[0] + 1 << "/" << k + 1 << " " << vs[1] + 1 << "/" << k + 2 << " " << vs[2] + 1 << "/" << k + 3 << "\n";
      }
    });
    if (o.png) {
      Render_mesh picture;
      for (const Point_3& q : mesh.points) {
        const Point_3 p = in_user_units(o, q);
        picture.points.push_back({p.x(), p.y(), p.z()});
      }
      picture.triangles = mesh.faces;
      for (const auto& corners : atlas) {
        double cu = 0, cv = 0;
        for (const auto& t : corners) cu += t[0] / 3, cv += t[1] / 3;
        int x = std::min(tex - 1, std::max(0, int(cu * tex))), y = std::min(tex - 1, std::max(0, int((1 - cv) * tex)));
        picture.face_colors.push_back(img[std::size_t(y) * tex + x]);
      }
      render_png(picture, output_path(o, name + "_checker.png"), o.render);
    }
  }
}

/// The feature pairs the map added at protrusion tips and at extremities, as two arrays of [source, target]
/// pairs (the map's features are the user's, then the protrusion pairs, then the extremity pairs).
inline void write_protrusion_pairs(Json_writer& j, const Map& cp) {
  const std::size_t n = cp.features().size(), tips = cp.statistics().protrusion_features,
                    ends = cp.statistics().extremity_features;
  auto pairs = [&](const char* key, std::size_t begin, std::size_t end) {
    j.key(key).begin_array();
    for (std::size_t k = begin; k < end; ++k)
      j.begin_array().value(cp.features()[k].source).value(cp.features()[k].target).end_array();
    j.end_array();
  };
  pairs("protrusion_features", n - ends - tips, n - ends);
  pairs("extremity_features", n - ends, n);
  // The extremity selection: how many pairs the probe found, and the worst descriptor mismatch of the maps
  // made without and with them (both 0 when no selection was made).
  const auto& S = cp.statistics();
  j.key("extremity_selection").begin_object().member("candidates", S.extremity_candidates);
  j.member("kept", S.extremity_features).member("worst_mismatch_without", S.mismatch_without_extremities);
  j.member("worst_mismatch_with", S.mismatch_with_extremities).member("seconds", S.seconds_selection).end_object();
  // Whether the final map is the probe's or the selected candidate's (its smoothing was not run again).
  j.member("map_adopted", S.map_adopted);
}

/// The places a verification names (Remeshing_verification::Spot), as the object "where" with those found:
/// index, point (in the user's units) and distance in percent of the target's diagonal.
inline void write_verification_spots(Json_writer& j, const Remeshing_verification& c) {
  j.key("where").begin_object();
  auto spot = [&j](const char* key, const Remeshing_verification::Spot& s) {
    if (!s.found) return;
    j.key(key).begin_object().member("index", s.index);
    j.key("point").begin_array().value(s.point[0]).value(s.point[1]).value(s.point[2]).end_array();
    j.member("distance_percent", s.distance).end_object();
  };
  spot("farthest_target_vertex", c.farthest_target_vertex);
  spot("farthest_output_vertex", c.farthest_output_vertex);
  spot("new_flipped_face", c.new_flipped_face);
  spot("new_self_intersection", c.new_self_intersection);
  j.end_object();
}

/// Writes the outputs of `map` (and the demo's map): the vertex maps both ways, the checkerboard and
/// report.json. `read_s` is the time to read (or generate) the inputs.
inline void write_map(const Options& o, const Map& cp, double read_s) {
  fs::create_directories(write_folder(o));
  auto write_vertex_map = [&](const std::string& name, Mesh_side side) {
    write_file_atomically(output_path(o, name), [&](std::ostream& os) {
      os.precision(17);
      const std::size_t n = cp.input_vertices(side);
      for (std::size_t v = 0; v < n; ++v) {
        Input_location l = side == Mesh_side::source ? cp.source_vertex_to_target_input(v) : cp.target_vertex_to_source_input(v);
        os << l.face << " " << l.b[0] << " " << l.b[1] << " " << l.b[2] << "\n";
      }
    });
  };
  write_vertex_map("source_to_target.txt", Mesh_side::source);
  write_vertex_map("target_to_source.txt", Mesh_side::target);
  write_checkerboard(o, cp);
  const Cross_parameterization_statistics& S = cp.statistics();
  const Layout_statistics& L = S.layout;
  auto distortion = [](Json_writer& j, const std::string& key, const Distortion& d) {
    j.key(key).begin_object().member("angular", d.angular).member("l2_stretch", d.l2_stretch).end_object();
  };
  auto certificate = [](Json_writer& j, const std::string& key, const Bijectivity_certificate& c) {
    j.key(key).begin_object().member("valid", c.valid).member("faces", c.faces);
    j.member("flipped_or_degenerate", c.not_positive).member("outside_chart", c.not_in_a_chart).member("coverage", c.coverage);
    j.end_object();
  };
  write_report(o, [&](Json_writer& j) {
    j.member("stage", "map");
    j.member("source_vertices", cp.input_vertices(Mesh_side::source)).member("target_vertices", cp.input_vertices(Mesh_side::target));
    j.member("features", L.features).member("base_triangles", cp.layout().base_triangles.size());
    j.key("layout").begin_object().member("edge_paths", L.edge_paths).member("face_paths", L.face_paths);
    j.key("splits").begin_object().member("source", L.splits_source).member("target", L.splits_target).end_object();
    j.key("adjacency_splits").begin_object().member("source", L.adjacency_splits_source).member("target", L.adjacency_splits_target).end_object();
    j.member("flips", L.flips).member("straightened", L.straightened).end_object();
    write_protrusion_pairs(j, cp);
    j.key("stretch_reweighted").begin_object().member("source", S.stretch_reweighted_source).member("target", S.stretch_reweighted_target).end_object();
    j.key("squeeze").begin_object().member("source", S.squeeze_source).member("target", S.squeeze_target).end_object();
    j.key("smoothing").begin_object().member("passes", S.smoothing_source.iterations).member("kept_after", S.smoothing_best_iteration);
    j.member("moves", S.smoothing_source.moves + S.smoothing_target.moves);
    j.member("rejected", S.smoothing_source.rejected + S.smoothing_target.rejected);
    j.member("migrations", S.smoothing_source.migrations + S.smoothing_target.migrations).end_object();
    j.key("map_smoothing").begin_object().member("passes", S.smoothing_map.iterations).member("kept_after", S.smoothing_map_best_iteration);
    j.member("moves", S.smoothing_map.moves).member("rejected", S.smoothing_map.rejected);
    j.member("migrations", S.smoothing_map.migrations);
    j.member("energy_initial", S.map_energy_initial).member("energy", S.map_energy).end_object();
    distortion(j, "distortion_before_smoothing", S.distortion_initial);
    distortion(j, "distortion", S.distortion);
    j.key("certificate").begin_object();
    certificate(j, "source", cp.certificate(Mesh_side::source));
    certificate(j, "target", cp.certificate(Mesh_side::target));
    j.end_object();
    j.key("seconds").begin_object().member("read", read_s).member("protrusion_probe", S.seconds_probe);
    j.member("layout", L.seconds_total).member("parameterization", S.seconds_parameterization);
    j.member("smoothing", S.seconds_smoothing).member("certificate", S.seconds_certificate).member("total", S.seconds_total);
    j.end_object();
  });
  if (!o.quiet) {
    std::cout << "map: " << L.features << " features, " << cp.layout().base_triangles.size() << " base triangles; "
              << "distortion E_ang " << format_number(S.distortion_initial.angular) << " -> " << format_number(S.distortion.angular)
              << ", L2 stretch " << format_number(S.distortion_initial.l2_stretch) << " -> " << format_number(S.distortion.l2_stretch)
              << "; certified one-to-one; " << format_number(S.seconds_total) << " s\n";
    std::cout << "wrote " << o.output << "/\n";
  }
}

// ---- remesh ----

/// The summary of `remesh` (and the demo's remeshing), the verified figure first: the independent
/// verification's two-sided Hausdorff distance between the target-shaped output and the target, against the
/// tolerance. Then the rest of the verification, and last the remesher's own measure: e(v) = |F'(F^-1(v)) - v|,
/// the distance from a target vertex to the point of the output that the map makes correspond to it, and the
/// chord error of output edges and faces, which the remesher refines until both are within the tolerance. e(v)
/// is never less than the distance from v to the output surface, so it is a stricter bound than the Hausdorff
/// distance at the vertices: the remesher may stop refining (no more progress, or its vertex cap) before
/// meeting it while the surfaces are within the tolerance.
inline void print_remesh_summary(const Options& o, const Remeshing_statistics& S, const Remeshing_verification& check,
                                 double added, double seconds, double verify_s) {
  if (o.quiet) return;
  const bool within = check.hausdorff_target <= o.tolerance;
  std::cout << "remesh: " << S.source_vertices << " -> " << S.output_vertices << " vertices (" << format_number(added)
            << "% added); verified: Hausdorff distance to the target " << format_number(check.hausdorff_target) << "%, "
            << (within ? "within" : "NOT within") << " the tolerance " << format_number(o.tolerance) << "%; "
            << format_number(seconds) << " s\n";
  std::cout << "remesh: verification: the source-shaped output within " << format_number(check.hausdorff_source)
            << "% of the source, " << check.flipped_faces << " flipped faces (" << check.flipped_at_target_folds
            << " at the target's own folds), "
            << check.new_self_intersections << " new self-intersecting face pairs (" << check.self_intersections_output
            << " in all, " << check.self_intersections_target << " in the target), normals "
            << format_number(check.normal_deviation_mean) << " degrees off on average, "
            << format_number(check.normal_deviation_above_30) << "% of the area beyond 30 degrees, "
            << check.excess_creases() << " creases beyond the target's ("
            << format_number(verify_s) << " s)" << (check.valid ? "" : "; NOT valid: " + check.message) << "\n";
  std::cout << "remesh: the remesher's own measure, e(v) = |F'(F^-1(v)) - v| (the distance between corresponding "
               "points, never less than the distance between the surfaces): max "
            << format_number(S.max_error) << "%, L2 " << format_number(S.l2_error) << "%, PSNR " << format_number(S.psnr)
            << "; chord error max " << format_number(S.max_chord_error) << "%; "
            << (S.converged ? "both within the tolerance"
                            : "this stricter bound was not met everywhere when refinement stopped")
            << "\n";
}

/// A remeshing's independent verification (verify_remesh()).
struct Checked_remeshing {
  Remeshing_verification check;
  std::size_t tiling = 0; ///< faces that do not tile their face of the source (source_tiling_defects())
  double seconds = 0;
};

/// A remeshing that failed the strict checks and was done again with the map smoothed as a map (`remesh`
/// without --map-smoothing): what the first attempt found and its time.
struct Map_smoothing_retry {
  bool tried = false, kept = false;
  std::string first_message; ///< the first attempt's verification message
  double first_seconds = 0;  ///< the first attempt's map, remeshing and verification
};

/// The independent verification of a remeshing's outputs against the inputs as they were before the map
/// refined them (`source0`, `target0`), with the source side's tiling defects, and its time.
inline Checked_remeshing verify_remesh(const Options& o, const Remesher& r, const Surface_mesh& source0,
                                       const Surface_mesh& target0) {
  Timer tv;
  Surface_mesh out_source, out_target;
  r.copy_to(Mesh_side::source, out_source);
  r.copy_to(Mesh_side::target, out_target);
  Remeshing_verification check = verify_compatible_remeshing(source0, target0, out_source, out_target, o.tolerance);
  check.scale_places_by_power_of_two(-o.units_exponent); // the places it names, in the user's units
  // The source side from the faces' places on the source (the verifier sees the meshes only).
  const std::size_t tiling = source_tiling_defects(r.source_face_locations());
  if (tiling > 0) {
    check.valid = false;
    check.message += "; " + std::to_string(tiling) + " faces do not tile their face of the source";
  }
  const Remeshing_statistics& S = r.statistics();
  // What the remesher could not make, and where: target points the overlay could not insert.
  if (!check.valid && S.overlay_used && !S.overlay_refused_points.empty()) {
    const auto& q = S.overlay_refused_points.front();
    const Point_3 p = in_user_units(o, Point_3(q[0], q[1], q[2]));
    check.message += "; the overlay could not insert " + std::to_string(S.overlay_refused_points.size()) +
                     " target points (the map compresses that part of the target into a piece of the source too "
                     "small for its exact tests in double precision), the first at (" + format_number(p.x()) + ", " +
                     format_number(p.y()) + ", " + format_number(p.z()) + ") on the target";
  }
  return {check, tiling, tv.seconds()};
}

/// Writes the outputs of `remesh` (and the demo's remeshing) and report.json, with the verification `checked`
/// of verify_remesh(). `read_s` is the time to read (or generate) the inputs; `retry`, what a first attempt
/// that failed the strict checks found (`remesh` only).
inline Remeshing_verification write_remesh(const Options& o, const Map& cp, const Remesher& r, const Checked_remeshing& checked,
                                           double read_s, const Map_smoothing_retry& retry = {}) {
  const Remeshing_verification& check = checked.check;
  const std::size_t tiling = checked.tiling;
  const double verify_s = checked.seconds;
  const Remeshing_statistics& S = r.statistics();
  fs::create_directories(write_folder(o));
  const std::vector<std::array<double, 3>> source_points = in_user_units(o, r.source_points());
  const std::vector<std::array<double, 3>> target_points = in_user_units(o, r.target_points());
  write_off(output_path(o, "source_compatible.off"), source_points, r.faces());
  write_off(output_path(o, "target_compatible.off"), target_points, r.faces());
  std::vector<std::array<unsigned char, 3>> colors;
  for (double e : r.vertex_error()) colors.push_back(error_color(e, o.tolerance));
  write_ply_vertex_colored(output_path(o, "target_error.ply"), target_points, r.faces(), colors);
  if (o.png) render_png(Render_mesh{target_points, r.faces(), {}, colors}, output_path(o, "target_error.png"), o.render);
  const Cross_parameterization_statistics& C = cp.statistics();
  const double added = 100.0 * (double(S.output_vertices) - double(S.source_vertices)) / double(S.source_vertices);
  write_report(o, [&](Json_writer& j) {
    j.member("stage", "remesh");
    j.member("source_vertices", S.source_vertices).member("target_vertices", S.target_vertices);
    j.member("features", C.layout.features);
    write_protrusion_pairs(j, cp);
    j.member("layout_vertices", S.layout_vertices).member("layout_splits_undone", S.layout_splits_undone);
    j.member("output_vertices", S.output_vertices).member("output_faces", S.output_faces);
    j.member("added_vertices_percent", added);
    j.member("refinement_splits", S.refinement_splits).member("pseudo_flips", S.pseudo_flips).member("unfold_moves", S.unfold_moves);
    j.key("refinement_repairs").begin_object().member("kept", S.refinement_repairs_kept).member("undone", S.refinement_repairs_undone).end_object();
    j.key("fold_repair").begin_object().member("splits", S.fold_repair_splits).member("kept", S.fold_repairs_kept);
    j.member("undone", S.fold_repairs_undone).end_object();
    j.key("untangling").begin_object().member("folds_removed", S.untangled_folds).member("vertices_moved", S.untangle_moves);
    j.member("standard_rule_removed", S.standard_flips_untangled).member("standard_rule_left", S.standard_flips_left);
    j.member("standard_rule_vertices_moved", S.standard_untangle_moves).member("standard_rule_max_move_percent", S.standard_untangle_max_move);
    j.member("max_move_percent", S.untangle_max_move).member("folds_not_tried", S.untangle_folds_not_tried).end_object();
    j.key("strict_repair").begin_object().member("flipped_before", S.strict_flipped_before);
    j.member("intersecting_before", S.strict_intersecting_before).member("flipped_after", S.strict_flipped_after);
    j.member("intersecting_after", S.strict_intersecting_after).member("edge_flips", S.strict_flips);
    j.member("vertices_added", S.strict_splits).member("disks", S.strict_disks);
    j.member("passes", S.strict_rounds).member("work_bound_reached", S.strict_work_bound_reached).end_object();
    j.key("overlay").begin_object().member("used", S.overlay_used).member("attempts", S.overlay_attempts);
    j.member("refusing_source_slivers", S.overlay_refusing_slivers).member("vertices", S.overlay_vertices);
    j.member("refused", S.overlay_refused).member("exact", S.overlay_exact).member("along_crossed", S.overlay_along_crossed);
    j.key("refused_points").begin_array();
    for (const auto& q : in_user_units(o, S.overlay_refused_points))
      j.begin_array().value(q[0]).value(q[1]).value(q[2]).end_array();
    j.end_array();
    j.member("flips", S.overlay_flips).member("complete", S.overlay_complete).member("collapses", S.overlay_collapses);
    j.member("work_bound_reached", S.overlay_work_bound_reached);
    j.member("needles_removed", S.overlay_needles_removed).member("needles_left", S.overlay_needles_left)
        .member("zippers_flipped", S.overlay_zippers_flipped).member("zippers_folding", S.overlay_zippers_folding);
    j.member("flipped", S.overlay_flipped).member("intersecting", S.overlay_intersecting).member("disks", S.overlay_disks);
    j.member("gap_vertices", S.overlay_gap_vertices).member("gap_samples_left", S.overlay_gap_samples_left).end_object();
    j.key("surface_gaps").begin_object().member("sampled_max_before_percent", S.gap_before).member("vertices_added", S.gap_vertices);
    j.member("rounds", S.gap_rounds).member("samples_left", S.gap_samples_left).end_object();
    j.member("tolerance_percent", S.tolerance);
    j.key("error_initial").begin_object().member("max_percent", S.max_error_initial).member("l2_percent", S.l2_error_initial).end_object();
    j.key("error").begin_object().member("max_percent", S.max_error).member("l2_percent", S.l2_error);
    j.member("psnr", S.psnr).member("max_chord_percent", S.max_chord_error).end_object();
    j.member("converged", S.converged);
    j.member("flipped_faces", S.flipped_faces);
    j.member("certificate", r.certificate().valid);
    j.key("map_smoothing_retry").begin_object().member("tried", retry.tried).member("kept", retry.kept);
    j.member("first_message", retry.first_message).member("first_seconds", retry.first_seconds).end_object();
    j.key("verification").begin_object().member("valid", check.valid).member("compatible", check.compatible);
    j.member("hausdorff_percent", check.hausdorff_target).member("hausdorff_source_percent", check.hausdorff_source);
    j.member("source_tiling_defects", tiling);
    j.member("flipped_faces", check.flipped_faces).member("flipped_at_target_folds", check.flipped_at_target_folds);
    j.member("normal_deviation_mean_degrees", check.normal_deviation_mean);
    j.member("faces_above_30", check.faces_above_30);
    j.member("normal_deviation_above_30_percent", check.normal_deviation_above_30);
    j.member("creases_output", check.creases_output).member("creases_target", check.creases_target);
    j.member("self_intersections_output", check.self_intersections_output);
    j.member("self_intersections_target", check.self_intersections_target);
    j.member("new_self_intersections", check.new_self_intersections);
    write_verification_spots(j, check);
    j.member("seconds", verify_s).end_object();
    j.key("iterations").begin_object().member("smoothing_rounds", S.smoothing_rounds).member("refinement_rounds", S.refinement_rounds).end_object();
    j.key("seconds").begin_object().member("read", read_s).member("protrusion_probe", C.seconds_probe);
    j.member("layout", C.layout.seconds_total).member("parameterization", C.seconds_parameterization);
    j.member("smoothing", C.seconds_smoothing).member("map_total", C.seconds_total);
    j.member("adaptive_smoothing", S.seconds_smoothing).member("refinement", S.seconds_refinement);
    j.member("pseudo_flips", S.seconds_flips).member("fold_repair", S.seconds_fold_repair).member("untangle", S.seconds_untangle);
    j.member("surface_gaps", S.seconds_gaps).member("strict_repair", S.seconds_strict_repair).member("overlay", S.seconds_overlay).member("certificate", S.seconds_certificate).member("remesh_total", S.seconds_total);
    j.end_object();
  });
  print_remesh_summary(o, S, check, added, C.seconds_total + S.seconds_total, verify_s);
  if (!o.quiet) std::cout << "wrote " << o.output << "/\n";
  return check;
}

// ---- morph ----

/// Frames side by side in the morph strip at most, and the strip picture's size per frame.
constexpr unsigned strip_frames_max = 5;
constexpr int strip_frame_width = 300, strip_height = 320;
/// Distance between neighbouring frames of the strip, in frame widths (a small gap between them).
constexpr double strip_pitch = 1.1;

/// Writes frame_000.off ... between two compatible soups; with --png a picture per frame and morph_strip.png.
inline void write_morph(const Options& o, const Polygon_soup& a, const Polygon_soup& b) {
  fs::create_directories(write_folder(o));
  std::vector<std::array<std::size_t, 3>> tris;
  for (const auto& p : a.polygons) tris.push_back({p[0], p[1], p[2]});
  // One frame for every picture: the union of both ends' boxes keeps the sequence steady.
  Render_options ro = o.render;
  ro.fixed_frame = true;
  ro.frame_min = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
  ro.frame_max = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const auto* soup : {&a, &b})
    for (const auto& p : soup->points)
      for (int i = 0; i < 3; ++i) ro.frame_min[i] = std::min(ro.frame_min[i], p[i]), ro.frame_max[i] = std::max(ro.frame_max[i], p[i]);
  // The strip: up to strip_frames_max frames side by side, from left to right along the picture's horizontal
  // (seen from view_direction with `up` up, the picture's right is up x view_direction).
  Render_mesh strip;
  const std::array<double, 3> right = unit3(cross3(o.render.up, o.render.view_direction));
  double width = 0;
  for (int i = 0; i < 3; ++i) width += (ro.frame_max[i] - ro.frame_min[i]) * std::abs(right[i]);
  const unsigned strip_frames = std::min(o.frames, strip_frames_max);
  std::vector<unsigned> strip_of(o.frames, ~0u);
  for (unsigned slot = 0; slot < strip_frames; ++slot)
    strip_of[std::size_t(std::lround(double(slot) * (o.frames - 1) / double(strip_frames - 1)))] = slot;
  for (unsigned k = 0; k < o.frames; ++k) {
    const double t = double(k) / double(o.frames - 1);
    std::vector<std::array<double, 3>> pts = morph(a.points, b.points, t);
    std::ostringstream name;
    name << "frame_" << std::setw(3) << std::setfill('0') << k;
    write_off(output_path(o, name.str() + ".off"), pts, tris);
    if (o.png) {
      render_png(Render_mesh{pts, tris, {}, {}}, output_path(o, name.str() + ".png"), ro);
      if (strip_of[k] != ~0u) {
        const std::size_t base = strip.points.size();
        const double shift = strip_pitch * width * strip_of[k];
        for (const auto& p : pts) strip.points.push_back({p[0] + shift * right[0], p[1] + shift * right[1], p[2] + shift * right[2]});
        for (const auto& f : tris) strip.triangles.push_back({f[0] + base, f[1] + base, f[2] + base});
      }
    }
    if (!o.quiet) std::cerr << "morph: frame " << k + 1 << "/" << o.frames << "\n";
  }
  if (o.png) {
    Render_options so = o.render;
    so.height = strip_height;
    so.width = strip_frame_width * int(strip_frames);
    so.zoom = 1.0;
    render_png(strip, output_path(o, "morph_strip.png"), so);
  }
  if (!o.quiet) std::cout << "morph: " << o.frames << " frames of " << a.points.size() << " vertices; wrote " << o.output << "/\n";
}

} // namespace cli
} // namespace crossparam

#endif // CROSSPARAM_CLI_OUTPUTS_H

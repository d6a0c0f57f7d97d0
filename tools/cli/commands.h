// SPDX-License-Identifier: GPL-3.0-or-later
// The CLI's commands: read (or generate) the inputs, call the library's public API the way a user would, hand
// the results to the writers of outputs.h. The demo runs the same steps as `map`, `remesh` and `morph` (the
// same library calls with the same options) on two generated creatures.
#ifndef CROSSPARAM_CLI_COMMANDS_H
#define CROSSPARAM_CLI_COMMANDS_H

#include "options.h"
#include "output_folder.h"
#include "outputs.h"

#include <crossparam/compatible_remeshing.h>
#include <crossparam/cross_parameterization.h>
#include <crossparam/io.h>
#include <crossparam/morph.h>
#include <crossparam/patch_layout.h>
#include <support/shapes.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>

namespace crossparam {
namespace cli {

/// A mesh as read, with the reader's report.
struct Loaded {
  Surface_mesh mesh;
  Mesh_check_report report;
};

/// Reads a mesh file; the reader's warnings go to stderr unless --quiet. A mesh whose vertices are all at one
/// point is refused here, naming the file.
inline Loaded load(const std::string& path, const Options& o) {
  Loaded l;
  l.report = read_triangle_mesh(path, l.mesh);
  bool spread = false;
  const Point_3 first = l.mesh.point(*l.mesh.vertices().begin());
  for (auto v : l.mesh.vertices()) spread = spread || l.mesh.point(v) != first;
  if (!spread)
    throw Input_error(path + ": the mesh has a degenerate bounding box (all its vertices are at one point)");
  if (!o.quiet)
    for (const auto& w : l.report.warnings) std::cerr << "crossparam: warning: " << w << "\n";
  return l;
}

/// The two meshes and the features of a `layout`, `map` or `remesh` command, validated.
struct Inputs {
  Loaded source, target;
  Feature_correspondence features;
  double seconds = 0; ///< to read them
};

/// The usage checks of `layout`, `map` and `remesh`.
inline void check_pair_usage(const Options& o) {
  const std::string& c = o.command;
  if (o.positional.size() != 2) throw Usage_error(c + " needs SOURCE and TARGET");
  if (o.features.empty()) throw Usage_error(c + " needs --features FILE");
  if (o.output.empty()) throw Usage_error(c + " needs -o DIR");
}

inline Inputs read_inputs(const Options& o) {
  check_pair_usage(o);
  Timer tr;
  Inputs in;
  in.source = load(o.positional[0], o);
  in.target = load(o.positional[1], o);
  in.features = read_feature_pairs(o.features, in.source.mesh.number_of_vertices(), in.target.mesh.number_of_vertices());
  in.seconds = tr.seconds();
  return in;
}

/// Progress lines on stderr unless --quiet.
inline std::function<void(const std::string&)> progress_printer(const Options& o) {
  if (o.quiet) return {};
  return [](const std::string& line) { std::cerr << line << "\n"; };
}

/// Seconds left of --time-limit (infinite without one; 0 once run out).
inline double remaining_seconds(const Options& o) {
  if (!std::isfinite(o.time_limit)) return HUGE_VAL;
  const double used = std::chrono::duration<double>(std::chrono::steady_clock::now() - o.start).count();
  return std::max(0.0, o.time_limit - used);
}

/// The options `o` with the staging folder of `out` to write into.
inline Options writing_into(const Options& o, const Output_folder& out) {
  Options w = o;
  w.staging = out.staging();
  return w;
}

/// The exit code of a result whose independent verification failed: 4, or 0 with --best-effort; the message
/// says which.
inline int failed_verification(const Options& o, const std::string& message) {
  if (o.best_effort) {
    std::cerr << "crossparam: warning: the result failed its independent verification (" << message
              << "); written to " << o.output << "/ as --best-effort asks\n";
    return 0;
  }
  std::cerr << "crossparam: error: the result failed its independent verification (" << message << "); written to "
            << o.output << "/ for inspection (exit code 4)\n";
  return exit_failed_verification;
}

// ---- the library calls, one per stage, shared by the commands and the demo ----

/// The cross-parameterization (§3-4) of `s` and `t` with the options' flips, smoothing, protrusion and extremity features,
/// threads and iterations. Refines `s` and `t` in place, as the layout does.
inline Map cross_parameterize(const Options& o, Surface_mesh& s, Surface_mesh& t, const Feature_correspondence& f) {
  namespace cp = crossparam::parameters;
  return Map(s, t, f,
             cp::apply_path_flips(
                 o.flips, cp::straighten_paths(o.straighten, cp::apply_smoothing(
                              o.smoothing, cp::map_smoothing(o.map_smoothing, cp::map_smoothing_global_steps(o.map_smoothing_global, cp::protrusion_features(
                                               o.protrusion_features, cp::extremity_features(o.extremity_features,
                                               cp::select_extremity_features(o.select_extremities, cp::number_of_threads(
                                                   o.threads, cp::time_limit(remaining_seconds(o), cp::best_effort(o.best_effort,
                                                       cp::progress(progress_printer(o),
                                                           CGAL::parameters::number_of_iterations(o.iterations))))))))))))),
             CGAL::parameters::default_values());
}

/// The compatible remeshing (§5) of `cp` with the options' tolerance, progress lines and threads.
inline Remesher remesh(const Options& o, const Map& cp) {
  namespace p = crossparam::parameters;
  return Remesher(cp, p::tolerance(o.tolerance, p::progress(progress_printer(o), p::number_of_threads(o.threads,
                      p::time_limit(remaining_seconds(o), p::best_effort(o.best_effort, p::remeshing_construction(o.construction)))))));
}

// ---- the commands; each returns the exit code ----

inline int run_layout(const Options& user) {
  check_pair_usage(user);
  Output_folder out(user.output);
  Options o = writing_into(user, out);
  Inputs in = read_inputs(o);
  normalize_units(o, in.source.mesh, in.target.mesh);
  Surface_mesh &s = in.source.mesh, &t = in.target.mesh;
  Patch_layout L = compute_patch_layouts(
      s, t, in.features, crossparam::parameters::apply_path_flips(o.flips, crossparam::parameters::straighten_paths(o.straighten)),
      CGAL::parameters::default_values());
  write_layout(o, s, t, L, {{"read", in.seconds}});
  out.commit();
  print_layout_summary(o, L);
  return 0;
}

inline int run_map(const Options& user) {
  check_pair_usage(user);
  Output_folder out(user.output);
  Options o = writing_into(user, out);
  Inputs in = read_inputs(o);
  normalize_units(o, in.source.mesh, in.target.mesh);
  Map cp = cross_parameterize(o, in.source.mesh, in.target.mesh, in.features);
  write_map(o, cp, in.seconds);
  out.commit();
  return 0;
}

inline int run_remesh(const Options& user) {
  check_pair_usage(user);
  Output_folder out(user.output);
  Options o = writing_into(user, out);
  Inputs in = read_inputs(o);
  normalize_units(o, in.source.mesh, in.target.mesh);
  const Surface_mesh source0 = in.source.mesh, target0 = in.target.mesh; // the map refines its inputs
  Timer first;
  Map cp = cross_parameterize(o, in.source.mesh, in.target.mesh, in.features);
  const Remesher r = remesh(o, cp);
  const Checked_remeshing checked = verify_remesh(o, r, source0, target0);
  Map_smoothing_retry retry;
  if (!checked.check.valid && o.smoothing && !o.map_smoothing && o.map_smoothing_retry) {
    // A map that squeezes a part of the target into a sliver of the source leaves the overlay faces it cannot
    // make exact; the map smoothed as a map, by its local steps alone, spreads that part (doc/algorithms.md, "A
    // map smoothed where the remeshing fails"). The second result is kept if it passes the checks.
    retry.tried = true;
    retry.first_message = checked.check.message;
    retry.first_seconds = first.seconds();
    if (!o.quiet)
      std::cerr << "crossparam: the remeshing fails the strict checks (" << checked.check.message
                << "); again with the map smoothed as a map (--map-smoothing; --no-map-smoothing-retry skips this)\n";
    Options o2 = o;
    o2.map_smoothing = true;
    o2.map_smoothing_global = false;
    try {
      Surface_mesh s2 = source0, t2 = target0;
      const Map cp2 = cross_parameterize(o2, s2, t2, in.features);
      const Remesher r2 = remesh(o2, cp2);
      const Checked_remeshing checked2 = verify_remesh(o2, r2, source0, target0);
      if (checked2.check.valid) {
        retry.kept = true;
        write_remesh(o2, cp2, r2, checked2, in.seconds, retry);
        out.commit();
        return 0;
      }
    } catch (const crossparam::Error& e) { // out of time, or the smoothed map failed: the first result stands
      if (!o.quiet) std::cerr << "crossparam: the second attempt stopped (" << e.what() << ")\n";
    }
  }
  const Remeshing_verification check = write_remesh(o, cp, r, checked, in.seconds, retry);
  out.commit();
  return check.valid ? 0 : failed_verification(o, check.message);
}

inline int run_morph(const Options& user) {
  if (user.positional.size() != 2) throw Usage_error("morph needs two compatible meshes A and B");
  if (user.output.empty()) throw Usage_error("morph needs -o DIR");
  Output_folder out(user.output);
  const Options o = writing_into(user, out);
  Polygon_soup a = read_polygon_soup(o.positional[0]), b = read_polygon_soup(o.positional[1]);
  // Each end must be a closed manifold mesh (the checks of the other commands, genus aside), then both
  // must share one face list.
  for (int k = 0; k < 2; ++k) {
    Surface_mesh checked;
    soup_to_triangle_mesh(k == 0 ? a : b, checked, o.positional[std::size_t(k)]);
  }
  check_compatible(a, b, o.positional[0], o.positional[1]);
  write_morph(o, a, b);
  out.commit();
  return 0;
}

/// Where the demo's pictures are, for its last line (with --png).
inline void print_demo_pictures(const Options& o) {
  if (o.quiet || !o.png) return;
  const std::string d = o.output + "/";
  std::cout << "demo: pictures:\n"
            << "  patch layouts      " << d << "source_patches.png " << d << "target_patches.png\n"
            << "  map (checkerboard) " << d << "source_checker.png " << d << "target_checker.png\n"
            << "  remeshing error    " << d << "target_error.png\n"
            << "  morph              " << d << "morph/morph_strip.png (frames " << d << "morph/frame_*.png)\n";
}

/// The built-in example: two creatures generated in code and their corresponding features, written as
/// source.off, target.off and features.txt, then what `map` (with the layouts of `layout`), `remesh` and
/// `morph` write, all into one directory (the morph in morph/).
inline int run_demo(const Options& user) {
  if (user.output.empty()) throw Usage_error("demo needs -o DIR");
  Output_folder out(user.output);
  Options o = writing_into(user, out);
  Timer tg;
  Surface_mesh a = shapes::creature_a(), b = shapes::creature_b();
  Feature_correspondence f = shapes::creature_features(a, b);
  const double gen_s = tg.seconds();
  std::filesystem::create_directories(write_folder(o));
  std::vector<std::array<double, 3>> pts;
  std::vector<std::array<std::size_t, 3>> tris;
  soup_of(a, pts, tris);
  write_off(output_path(o, "source.off"), pts, tris);
  soup_of(b, pts, tris);
  write_off(output_path(o, "target.off"), pts, tris);
  write_file_atomically(output_path(o, "features.txt"), [&](std::ostream& os) {
    os << "# source_vertex target_vertex (0-based, file order)\n";
    for (const auto& p : f) os << p.source << " " << p.target << "\n";
  });
  if (!o.quiet)
    std::cout << "demo: creature A " << a.number_of_vertices() << " vertices, creature B " << b.number_of_vertices()
              << " vertices, " << f.size() << " features (" << format_number(gen_s) << " s to generate)\n";
  // As `remesh`: the map (whose patch layouts are written as `layout` writes them), then the remeshing.
  normalize_units(o, a, b);
  const Surface_mesh a0 = a, b0 = b; // the map refines its inputs
  Map cp = cross_parameterize(o, a, b, f);
  write_layout(o, a, b, cp.layout(), {{"generate", gen_s}});
  write_map(o, cp, gen_s);
  const Remesher r = remesh(o, cp);
  const Remeshing_verification check = write_remesh(o, cp, r, verify_remesh(o, r, a0, b0), gen_s);
  // As `morph`, on the two compatible meshes.
  Polygon_soup sa, sb;
  sa.points = in_user_units(o, r.source_points());
  sb.points = in_user_units(o, r.target_points());
  for (const auto& t : r.faces()) sa.polygons.push_back({t[0], t[1], t[2]});
  sb.polygons = sa.polygons;
  check_compatible(sa, sb, "source_compatible", "target_compatible");
  Options mo = o;
  mo.output = (fs::path(o.output) / "morph").string();
  mo.staging = output_path(o, "morph");
  write_morph(mo, sa, sb);
  out.commit();
  print_demo_pictures(o);
  return check.valid ? 0 : failed_verification(o, check.message);
}

} // namespace cli
} // namespace crossparam

#endif // CROSSPARAM_CLI_COMMANDS_H

// SPDX-License-Identifier: GPL-3.0-or-later
// The CLI's commands: read (or generate) the inputs, call the library's public API the way a user would, hand
// the results to the writers of outputs.h. The demo runs the same steps as `map`, `remesh` and `morph` (the
// same library calls with the same options) on two generated creatures.
#ifndef CROSSPARAM_CLI_COMMANDS_H
#define CROSSPARAM_CLI_COMMANDS_H

#include "options.h"
#include "outputs.h"

#include <crossparam/compatible_remeshing.h>
#include <crossparam/cross_parameterization.h>
#include <crossparam/io.h>
#include <crossparam/morph.h>
#include <crossparam/patch_layout.h>
#include <support/shapes.h>

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

/// Reads a mesh file; the reader's warnings go to stderr unless --quiet.
inline Loaded load(const std::string& path, const Options& o) {
  Loaded l;
  l.report = read_triangle_mesh(path, l.mesh);
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

inline Inputs read_inputs(const Options& o) {
  const std::string& c = o.command;
  if (o.positional.size() != 2) throw Usage_error(c + " needs SOURCE and TARGET");
  if (o.features.empty()) throw Usage_error(c + " needs --features FILE");
  if (o.output.empty()) throw Usage_error(c + " needs -o DIR");
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

// ---- the library calls, one per stage, shared by the commands and the demo ----

/// The cross-parameterization (§3-4) of `s` and `t` with the options' flips, smoothing, protrusion features,
/// threads and iterations. Refines `s` and `t` in place, as the layout does.
inline Map cross_parameterize(const Options& o, Surface_mesh& s, Surface_mesh& t, const Feature_correspondence& f) {
  return Map(s, t, f,
             crossparam::parameters::apply_path_flips(
                 o.flips, crossparam::parameters::apply_smoothing(
                              o.smoothing, crossparam::parameters::protrusion_features(
                                               o.protrusion_features,
                                               crossparam::parameters::number_of_threads(
                                                   o.threads, CGAL::parameters::number_of_iterations(o.iterations))))),
             CGAL::parameters::default_values());
}

/// The compatible remeshing (§5) of `cp` with the options' tolerance, progress lines and threads.
inline Remesher remesh(const Options& o, const Map& cp) {
  return Remesher(cp, crossparam::parameters::tolerance(o.tolerance, crossparam::parameters::progress(progress_printer(o),
                      crossparam::parameters::number_of_threads(o.threads))));
}

// ---- the commands; each returns the exit code ----

inline int run_layout(const Options& o) {
  Inputs in = read_inputs(o);
  Surface_mesh &s = in.source.mesh, &t = in.target.mesh;
  Patch_layout L = compute_patch_layouts(s, t, in.features, crossparam::parameters::apply_path_flips(o.flips),
                                         CGAL::parameters::default_values());
  write_layout(o, s, t, L, {{"read", in.seconds}});
  print_layout_summary(o, L);
  return 0;
}

inline int run_map(const Options& o) {
  Inputs in = read_inputs(o);
  Map cp = cross_parameterize(o, in.source.mesh, in.target.mesh, in.features);
  write_map(o, cp, in.seconds);
  return 0;
}

inline int run_remesh(const Options& o) {
  Inputs in = read_inputs(o);
  const Surface_mesh source0 = in.source.mesh, target0 = in.target.mesh; // the map refines its inputs
  Map cp = cross_parameterize(o, in.source.mesh, in.target.mesh, in.features);
  const Remesher r = remesh(o, cp);
  write_remesh(o, cp, r, source0, target0, in.seconds);
  return 0;
}

inline int run_morph(const Options& o) {
  if (o.positional.size() != 2) throw Usage_error("morph needs two compatible meshes A and B");
  if (o.output.empty()) throw Usage_error("morph needs -o DIR");
  Polygon_soup a = read_polygon_soup(o.positional[0]), b = read_polygon_soup(o.positional[1]);
  check_compatible(a, b, o.positional[0], o.positional[1]);
  write_morph(o, a, b);
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
inline int run_demo(const Options& o) {
  if (o.output.empty()) throw Usage_error("demo needs -o DIR");
  Timer tg;
  Surface_mesh a = shapes::creature_a(), b = shapes::creature_b();
  Feature_correspondence f = shapes::creature_features(a, b);
  const double gen_s = tg.seconds();
  std::filesystem::create_directories(o.output);
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
  const Surface_mesh a0 = a, b0 = b; // the map refines its inputs
  Map cp = cross_parameterize(o, a, b, f);
  write_layout(o, a, b, cp.layout(), {{"generate", gen_s}});
  write_map(o, cp, gen_s);
  const Remesher r = remesh(o, cp);
  write_remesh(o, cp, r, a0, b0, gen_s);
  // As `morph`, on the two compatible meshes.
  Polygon_soup sa, sb;
  sa.points = r.source_points();
  sb.points = r.target_points();
  for (const auto& t : r.faces()) sa.polygons.push_back({t[0], t[1], t[2]});
  sb.polygons = sa.polygons;
  check_compatible(sa, sb, "source_compatible", "target_compatible");
  Options mo = o;
  mo.output = output_path(o, "morph");
  write_morph(mo, sa, sb);
  print_demo_pictures(o);
  return 0;
}

} // namespace cli
} // namespace crossparam

#endif // CROSSPARAM_CLI_COMMANDS_H

// SPDX-License-Identifier: GPL-3.0-or-later
// The crossparam command-line tool: thin; parses arguments, calls the library, writes files.
//
//   crossparam layout SOURCE TARGET --features FILE -o DIR   patch layouts (paper §3)
//   crossparam demo -o DIR                                   the built-in example, end to end
//
// Errors: one line on stderr, exit code 1 for bad input, 2 for bad usage, 3 for an internal failure.
// Outputs are computed completely before anything is written, and each file is written atomically.
#include <crossparam/io.h>
#include <crossparam/patch_layout.h>
#include <crossparam/render.h>
#include <crossparam/shapes.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace crossparam;

namespace {

const char* const usage_text =
    "usage: crossparam <command> [options]\n"
    "\n"
    "commands:\n"
    "  layout SOURCE TARGET --features FILE -o DIR\n"
    "      topologically identical triangular patch layouts of two closed genus-0 meshes (paper section 3)\n"
    "  demo -o DIR\n"
    "      generate two creatures in code, pick corresponding features, run the pipeline on them\n"
    "\n"
    "options:\n"
    "  --features FILE   feature correspondence: one 'source_vertex target_vertex' pair per line,\n"
    "                    0-based indices in file order, '#' starts a comment\n"
    "  -o, --output DIR  output directory (created if missing)\n"
    "  --no-flips        skip the path flips of section 3.3\n"
    "  --png             also render pictures of the results (needs POV-Ray: apt-get install povray)\n"
    "  --quiet           print nothing but errors\n"
    "  -h, --help        this text\n"
    "\n"
    "meshes: OFF, OBJ, PLY or STL; closed, manifold, one component, genus 0.\n";

struct Usage_error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Options {
  std::string command;
  std::vector<std::string> positional;
  std::string features;
  std::string output;
  bool flips = true;
  bool quiet = false;
  bool png = false;
};

Options parse(int argc, char** argv) {
  Options o;
  if (argc < 2) throw Usage_error("missing command");
  o.command = argv[1];
  for (int i = 2; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw Usage_error("option " + a + " needs a value");
      return argv[++i];
    };
    if (a == "--features") o.features = value();
    else if (a == "-o" || a == "--output") o.output = value();
    else if (a == "--no-flips") o.flips = false;
    else if (a == "--png") o.png = true;
    else if (a == "--quiet" || a == "-q") o.quiet = true;
    else if (a == "-h" || a == "--help") throw Usage_error("");
    else if (!a.empty() && a[0] == '-') throw Usage_error("unknown option " + a);
    else o.positional.push_back(a);
  }
  return o;
}

/// A distinct, stable colour per id (golden-ratio hue steps).
std::array<unsigned char, 3> color_of(std::size_t id) {
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

void soup_of(const Surface_mesh& m, std::vector<std::array<double, 3>>& pts, std::vector<std::array<std::size_t, 3>>& tris) {
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

std::string json_number(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

struct Timer {
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
};

struct Loaded {
  Surface_mesh mesh;
  Mesh_check_report report;
};

Loaded load(const std::string& path, const Options& o) {
  Loaded l;
  l.report = read_triangle_mesh(path, l.mesh);
  if (!o.quiet)
    for (const auto& w : l.report.warnings) std::cerr << "crossparam: warning: " << w << "\n";
  return l;
}

/// Writes the layout outputs of `crossparam layout` into o.output.
void write_layout(const Options& o, const Surface_mesh& s, const Surface_mesh& t, const Patch_layout& L,
                  const std::map<std::string, double>& extra_times) {
  fs::create_directories(o.output);
  auto out = [&](const std::string& name) { return (fs::path(o.output) / name).string(); };
  std::vector<std::array<double, 3>> pts;
  std::vector<std::array<std::size_t, 3>> tris;
  const Surface_mesh* meshes[2] = {&s, &t};
  const Mesh_layout* layouts[2] = {&L.source, &L.target};
  const char* names[2] = {"source", "target"};
  for (int k = 0; k < 2; ++k) {
    soup_of(*meshes[k], pts, tris);
    write_off(out(std::string(names[k]) + "_refined.off"), pts, tris);
    write_file_atomically(out(std::string(names[k]) + "_patches.txt"), [&](std::ostream& os) {
      for (int id : layouts[k]->face_triangle) os << id << "\n";
    });
    std::vector<std::array<unsigned char, 3>> colors;
    for (int id : layouts[k]->face_triangle) colors.push_back(color_of(std::size_t(id)));
    write_ply_colored(out(std::string(names[k]) + "_patches.ply"), pts, tris, colors);
    if (o.png) {
      Render_mesh rm{pts, tris, colors, {}};
      render_png(rm, out(std::string(names[k]) + "_patches.png"));
    }
  }
  write_file_atomically(out("base_mesh.txt"), [&](std::ostream& os) {
    os << "# base triangles: three feature indices each, counter-clockwise seen from outside\n";
    for (const auto& tri : L.base_triangles) os << tri[0] << " " << tri[1] << " " << tri[2] << "\n";
  });
  const Layout_statistics& S = L.statistics;
  write_file_atomically(out("report.json"), [&](std::ostream& os) {
    os << "{\n";
    os << "  \"stage\": \"layout\",\n";
    os << "  \"source\": {\"vertices\": " << L.source.original_vertices << ", \"faces\": " << L.source.original_faces
       << ", \"refined_vertices\": " << s.number_of_vertices() << ", \"refined_faces\": " << s.number_of_faces() << "},\n";
    os << "  \"target\": {\"vertices\": " << L.target.original_vertices << ", \"faces\": " << L.target.original_faces
       << ", \"refined_vertices\": " << t.number_of_vertices() << ", \"refined_faces\": " << t.number_of_faces() << "},\n";
    os << "  \"features\": " << S.features << ",\n";
    os << "  \"base_triangles\": " << L.base_triangles.size() << ",\n";
    os << "  \"paths\": " << L.base_edges.size() << ",\n";
    os << "  \"edge_paths\": " << S.edge_paths << ",\n";
    os << "  \"face_paths\": " << S.face_paths << ",\n";
    os << "  \"face_traced\": {\"source\": " << S.face_traced_source << ", \"target\": " << S.face_traced_target << "},\n";
    os << "  \"splits\": {\"source\": " << S.splits_source << ", \"target\": " << S.splits_target << "},\n";
    os << "  \"flips\": " << S.flips << ",\n";
    os << "  \"rejected_blocking\": " << S.rejected_blocking << ",\n";
    os << "  \"verified\": true,\n";
    os << "  \"seconds\": {";
    bool first = true;
    for (const auto& [k, v] : extra_times) {
      os << (first ? "" : ", ") << "\"" << k << "\": " << json_number(v);
      first = false;
    }
    os << (first ? "" : ", ") << "\"edge_paths\": " << json_number(S.seconds_edge_paths)
       << ", \"face_paths\": " << json_number(S.seconds_face_paths) << ", \"flips\": " << json_number(S.seconds_flips)
       << ", \"layout_total\": " << json_number(S.seconds_total) << "}\n";
    os << "}\n";
  });
}

void print_summary(const Options& o, const Patch_layout& L) {
  if (o.quiet) return;
  const Layout_statistics& S = L.statistics;
  std::cout << "layout: " << S.features << " features, " << L.base_triangles.size() << " base triangles, "
            << S.edge_paths << " edge paths, " << S.face_paths << " face paths, " << S.splits_source << "+"
            << S.splits_target << " splits, " << S.flips << " flips, " << json_number(S.seconds_total * 1000)
            << " ms; verified\n";
  std::cout << "wrote " << o.output << "/\n";
}

int run_layout(const Options& o) {
  if (o.positional.size() != 2) throw Usage_error("layout needs SOURCE and TARGET");
  if (o.features.empty()) throw Usage_error("layout needs --features FILE");
  if (o.output.empty()) throw Usage_error("layout needs -o DIR");
  Timer tr;
  Loaded s = load(o.positional[0], o), t = load(o.positional[1], o);
  Feature_correspondence f =
      read_feature_pairs(o.features, s.mesh.number_of_vertices(), t.mesh.number_of_vertices());
  double read_s = tr.seconds();
  Patch_layout L = compute_patch_layouts(s.mesh, t.mesh, f, crossparam::parameters::apply_path_flips(o.flips),
                                         CGAL::parameters::default_values());
  write_layout(o, s.mesh, t.mesh, L, {{"read", read_s}});
  print_summary(o, L);
  return 0;
}

int run_demo(const Options& o) {
  if (o.output.empty()) throw Usage_error("demo needs -o DIR");
  Timer tg;
  Surface_mesh a = shapes::creature_a(), b = shapes::creature_b();
  Feature_correspondence f = shapes::creature_features(a, b);
  double gen_s = tg.seconds();
  fs::create_directories(o.output);
  std::vector<std::array<double, 3>> pts;
  std::vector<std::array<std::size_t, 3>> tris;
  soup_of(a, pts, tris);
  write_off((fs::path(o.output) / "source.off").string(), pts, tris);
  soup_of(b, pts, tris);
  write_off((fs::path(o.output) / "target.off").string(), pts, tris);
  write_file_atomically((fs::path(o.output) / "features.txt").string(), [&](std::ostream& os) {
    os << "# source_vertex target_vertex (0-based, file order)\n";
    for (const auto& p : f) os << p.source << " " << p.target << "\n";
  });
  if (!o.quiet)
    std::cout << "demo: creature A " << a.number_of_vertices() << " vertices, creature B " << b.number_of_vertices()
              << " vertices, " << f.size() << " features (" << json_number(gen_s) << " s to generate)\n";
  Patch_layout L = compute_patch_layouts(a, b, f, crossparam::parameters::apply_path_flips(o.flips),
                                         CGAL::parameters::default_values());
  write_layout(o, a, b, L, {{"generate", gen_s}});
  print_summary(o, L);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  try {
    Options o = parse(argc, argv);
    if (o.command == "layout") return run_layout(o);
    if (o.command == "demo") return run_demo(o);
    if (o.command == "-h" || o.command == "--help" || o.command == "help") {
      std::cout << usage_text;
      return 0;
    }
    throw Usage_error("unknown command '" + o.command + "'");
  } catch (const Usage_error& e) {
    if (std::string(e.what()).empty()) {
      std::cout << usage_text;
      return 0;
    }
    std::cerr << "crossparam: " << e.what() << " (see crossparam --help)\n";
    return 2;
  } catch (const Algorithm_error& e) {
    std::cerr << "crossparam: internal error: " << e.what() << "\n";
    return 3;
  } catch (const Error& e) {
    std::cerr << "crossparam: error: " << e.what() << "\n";
    return 1;
  } catch (const fs::filesystem_error& e) {
    std::cerr << "crossparam: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "crossparam: internal error: " << e.what() << "\n";
    return 3;
  }
}

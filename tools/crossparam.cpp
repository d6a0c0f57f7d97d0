// SPDX-License-Identifier: GPL-3.0-or-later
// The crossparam command-line tool: thin; parses arguments, calls the library, writes files.
//
//   crossparam layout SOURCE TARGET --features FILE -o DIR   patch layouts (paper §3)
//   crossparam map SOURCE TARGET --features FILE -o DIR      cross-parameterization (§4)
//   crossparam remesh SOURCE TARGET --features FILE -o DIR   compatible remeshing (§5)
//   crossparam morph A B --frames N -o DIR                   morph between two compatible meshes
//   crossparam demo -o DIR                                   the built-in example, end to end
//
// Errors: one line on stderr, exit code 1 for bad input, 2 for bad usage, 3 for an internal failure.
// Outputs are computed completely before anything is written, and each file is written atomically.
#include <crossparam/compatible_remeshing.h>
#include <crossparam/cross_parameterization.h>
#include <crossparam/morph.h>
#include <crossparam/io.h>
#include <crossparam/patch_layout.h>
#include <crossparam/remeshing_verification.h>
#include <crossparam/render.h>
#include <crossparam/shapes.h>
#include <crossparam/internal/png.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iomanip>
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
    "  map SOURCE TARGET --features FILE -o DIR\n"
    "      cross-parameterization (paper section 4): the bijective map between the meshes, certified\n"
    "  remesh SOURCE TARGET --features FILE -o DIR [--tolerance PCT]\n"
    "      compatible remeshing (paper section 5): two meshes with one connectivity, one reproducing SOURCE,\n"
    "      the other approximating TARGET\n"
    "  morph A B --frames N -o DIR\n"
    "      N meshes interpolating between two compatible meshes (e.g. the outputs of remesh)\n"
    "  demo -o DIR\n"
    "      generate two creatures in code, pick corresponding features, run the whole pipeline on them\n"
    "      (layout, map, remesh, and a morph sequence)\n"
    "\n"
    "options:\n"
    "  --features FILE   feature correspondence: one 'source_vertex target_vertex' pair per line,\n"
    "                    0-based indices in file order, '#' starts a comment\n"
    "  -o, --output DIR  output directory (created if missing)\n"
    "  --no-flips        skip the path flips of section 3.3\n"
    "  --iterations N    smoothing passes at most (map; default 200)\n"
    "  --no-smoothing    skip the smoothing of section 4.2 (map)\n"
    "  --no-protrusion-features\n"
    "                    use only the given features (map, remesh, demo): no pairs added at the tips of\n"
    "                    squeezed protrusions\n"
    "  --tolerance PCT   remesh: approximation tolerance in percent of the target's bounding-box diagonal\n"
    "                    (default 0.5)\n"
    "  --threads N       map, remesh, demo: threads for the smoothing of the two meshes and the error\n"
    "                    measurements (default 0: one per hardware thread); the results are the same for any N\n"
    "  --frames N        morph: number of meshes written, both ends included (default 9)\n"
    "  --png             also render pictures of the results (needs POV-Ray: apt-get install povray)\n"
    "  --up X,Y,Z        the models' up direction in the pictures (default 0,0,1)\n"
    "  --view X,Y,Z      direction from the model towards the camera (default 1,-1.6,0.6)\n"
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
  bool smoothing = true;
  bool protrusion_features = true;
  unsigned iterations = 200;
  double tolerance = 0.5;
  unsigned threads = 0;
  unsigned frames = 9;
  Render_options render;
};

std::array<double, 3> parse_vector(const std::string& name, const std::string& v) {
  std::array<double, 3> out{};
  std::istringstream is(v);
  char c1 = 0, c2 = 0;
  if (!(is >> out[0] >> c1 >> out[1] >> c2 >> out[2]) || c1 != ',' || c2 != ',' || !is.eof() ||
      !(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] > 0))
    throw Usage_error(name + " needs three numbers X,Y,Z, not all zero");
  return out;
}

/// A whole number in [lo, hi] written in decimal digits alone, or a usage error with `message`.
unsigned whole_number(const std::string& v, unsigned long lo, unsigned long hi, const char* message) {
  char* end = nullptr;
  const unsigned long n = std::strtoul(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0' || n < lo || n > hi) throw Usage_error(message);
  return unsigned(n);
}

Options parse(int argc, char** argv) {
  Options o;
  o.render.up = {0, 0, 1};
  o.render.view_direction = {1, -1.6, 0.6};
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
    else if (a == "--no-smoothing") o.smoothing = false;
    else if (a == "--no-protrusion-features") o.protrusion_features = false;
    else if (a == "--up") o.render.up = parse_vector(a, value());
    else if (a == "--view") o.render.view_direction = parse_vector(a, value());
    else if (a == "--iterations") o.iterations = whole_number(value(), 0, 100000, "--iterations needs a whole number up to 100000");
    else if (a == "--threads") o.threads = whole_number(value(), 0, 1024, "--threads needs a whole number up to 1024");
    else if (a == "--tolerance") {
      std::string v = value();
      char* end = nullptr;
      double t = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0' || !(t > 0) || !(t <= 100)) throw Usage_error("--tolerance needs a percentage in (0, 100]");
      o.tolerance = t;
    }
    else if (a == "--frames") o.frames = whole_number(value(), 2, 10000, "--frames needs a whole number from 2 to 10000");
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
      render_png(rm, out(std::string(names[k]) + "_patches.png"), o.render);
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

/// The two meshes and the features of a `layout` or `map` command, validated.
struct Inputs {
  Loaded source, target;
  Feature_correspondence features;
  double seconds = 0;
};

Inputs read_inputs(const Options& o) {
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

int run_layout(const Options& o) {
  Inputs in = read_inputs(o);
  Surface_mesh &s = in.source.mesh, &t = in.target.mesh;
  Patch_layout L = compute_patch_layouts(s, t, in.features, crossparam::parameters::apply_path_flips(o.flips),
                                         CGAL::parameters::default_values());
  write_layout(o, s, t, L, {{"read", in.seconds}});
  print_summary(o, L);
  return 0;
}

using Map = Cross_parameterization<Surface_mesh, Surface_mesh>;

/// The map at a glance: both input meshes as textured OBJ files sharing one checkerboard texture. Texture
/// coordinates come from the base domain: each base triangle owns a tile of the texture, and a vertex's UV is
/// its base location placed in that tile. A target vertex's UV is that of its preimage on the source (F^-1),
/// which is the same base location; corresponding squares on the two meshes are corresponding regions.
void write_checkerboard(const Options& o, const Map& cp) {
  auto out = [&](const std::string& name) { return (fs::path(o.output) / name).string(); };
  const int tex = 512, squares = 32;
  std::vector<std::array<unsigned char, 3>> img(std::size_t(tex) * tex);
  for (int y = 0; y < tex; ++y)
    for (int x = 0; x < tex; ++x) {
      bool dark = ((x * squares / tex) + (y * squares / tex)) % 2;
      img[std::size_t(y) * tex + x] = dark ? std::array<unsigned char, 3>{40, 60, 140} : std::array<unsigned char, 3>{240, 235, 220};
    }
  write_file_atomically(out("checker.png"), [&](std::ostream& os) { internal::write_png(os, tex, tex, img); });
  write_file_atomically(out("checker.mtl"), [&](std::ostream& os) {
    os << "newmtl checker\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nmap_Kd checker.png\n";
  });
  const auto& base = cp.base_mesh();
  const std::size_t nt = base.tri.size();
  const int cols = int(std::ceil(std::sqrt(double(nt))));
  // Tile of base triangle t: a square of side 1/cols; the frame is scaled to fit with a margin.
  auto uv = [&](int t, const internal::Point_2& p) {
    double lo_x = HUGE_VAL, hi_x = -HUGE_VAL, lo_y = HUGE_VAL, hi_y = -HUGE_VAL;
    for (const auto& q : base.q[t]) lo_x = std::min(lo_x, q.x()), hi_x = std::max(hi_x, q.x()), lo_y = std::min(lo_y, q.y()), hi_y = std::max(hi_y, q.y());
    double size = std::max(hi_x - lo_x, hi_y - lo_y);
    double cell = 1.0 / cols;
    double u = (t % cols + 0.1 + 0.8 * (p.x() - lo_x) / size) * cell;
    double v = (t / cols + 0.1 + 0.8 * (p.y() - lo_y) / size) * cell;
    return std::array<double, 2>{u, v};
  };
  for (int side = 0; side < 2; ++side) {
    const auto& L = cp.work().side[side];
    const auto& P = cp.parameterization(side);
    Render_mesh picture;
    write_file_atomically(out(side == 0 ? "source_checker.obj" : "target_checker.obj"), [&](std::ostream& os) {
      os.precision(17);
      os << "# crossparam: " << (side == 0 ? "source" : "target") << " textured from the base domain\n";
      os << "mtllib checker.mtl\nusemtl checker\n";
      for (auto v : L.m.vertices()) {
        const auto p = L.input_point(L.m.point(v));
        os << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
      }
      std::size_t k = 0;
      for (auto f : L.m.faces()) {
        auto h = L.m.halfedge(f);
        std::array<internal::WV, 3> vs{L.m.source(h), L.m.target(h), L.m.target(L.m.next(h))};
        std::array<const Base_location*, 3> ls{&P[vs[0]], &P[vs[1]], &P[vs[2]]};
        std::array<internal::Point_2, 3> q;
        int c, n;
        base.canonical_frame(ls, c, n, q);
        double cu = 0, cv = 0;
        for (int i = 0; i < 3; ++i) {
          auto t = uv(c, q[i]);
          os << "vt " << t[0] << " " << t[1] << "\n";
          cu += t[0] / 3;
          cv += t[1] / 3;
        }
        if (o.png) {
          int x = std::min(tex - 1, std::max(0, int(cu * tex))), y = std::min(tex - 1, std::max(0, int((1 - cv) * tex)));
          picture.face_colors.push_back(img[std::size_t(y) * tex + x]);
          picture.triangles.push_back({std::size_t(vs[0]), std::size_t(vs[1]), std::size_t(vs[2])});
        }
        os << "f " << std::size_t(vs[0]) + 1 << "/" << k + 1 << " " << std::size_t(vs[1]) + 1 << "/" << k + 2 << " "
           << std::size_t(vs[2]) + 1 << "/" << k + 3 << "\n";
        k += 3;
      }
    });
    if (o.png) {
      for (auto v : L.m.vertices()) picture.points.push_back(L.input_point(L.m.point(v)));
      render_png(picture, out(side == 0 ? "source_checker.png" : "target_checker.png"), o.render);
    }
  }
}

Map compute_map(const Options& o, Surface_mesh& s, Surface_mesh& t, const Feature_correspondence& f) {
  return Map(s, t, f,
             crossparam::parameters::apply_path_flips(
                 o.flips, crossparam::parameters::apply_smoothing(
                              o.smoothing, crossparam::parameters::protrusion_features(
                                               o.protrusion_features,
                                               crossparam::parameters::number_of_threads(
                                                   o.threads, CGAL::parameters::number_of_iterations(o.iterations))))),
             CGAL::parameters::default_values());
}

/// The feature pairs the map added at protrusion tips, as a JSON array of [source, target] pairs.
std::string protrusion_pairs_json(const Map& cp) {
  const std::size_t n = cp.features().size(), added = cp.statistics().protrusion_features;
  std::string out = "[";
  for (std::size_t k = n - added; k < n; ++k)
    out += (k == n - added ? "[" : ", [") + std::to_string(cp.features()[k].source) + ", " +
           std::to_string(cp.features()[k].target) + "]";
  return out + "]";
}

/// Writes the outputs of `crossparam map` into o.output.
void write_map(const Options& o, const Map& cp, double read_s) {
  fs::create_directories(o.output);
  auto out = [&](const std::string& name) { return (fs::path(o.output) / name).string(); };
  auto write_vertex_map = [&](const std::string& name, int side) {
    write_file_atomically(out(name), [&](std::ostream& os) {
      os.precision(17);
      const std::size_t n = cp.input_vertices(side);
      for (std::size_t v = 0; v < n; ++v) {
        Input_location l = side == 0 ? cp.source_vertex_to_target_input(v) : cp.target_vertex_to_source_input(v);
        os << l.face << " " << l.b[0] << " " << l.b[1] << " " << l.b[2] << "\n";
      }
    });
  };
  write_vertex_map("source_to_target.txt", 0);
  write_vertex_map("target_to_source.txt", 1);
  write_checkerboard(o, cp);
  const Cross_parameterization_statistics& S = cp.statistics();
  const Layout_statistics& L = S.layout;
  auto dist = [&](const Distortion& d) {
    return "{\"angular\": " + json_number(d.angular) + ", \"l2_stretch\": " + json_number(d.l2_stretch) + "}";
  };
  auto cert = [&](const Bijectivity_certificate& c) {
    return std::string("{\"valid\": ") + (c.valid ? "true" : "false") + ", \"faces\": " + std::to_string(c.faces) +
           ", \"flipped_or_degenerate\": " + std::to_string(c.not_positive) +
           ", \"outside_chart\": " + std::to_string(c.not_in_a_chart) + ", \"coverage\": " + std::to_string(c.coverage) + "}";
  };
  write_file_atomically(out("report.json"), [&](std::ostream& os) {
    os << "{\n  \"stage\": \"map\",\n";
    os << "  \"source_vertices\": " << cp.input_vertices(0) << ",\n  \"target_vertices\": " << cp.input_vertices(1) << ",\n";
    os << "  \"features\": " << L.features << ",\n  \"base_triangles\": " << cp.layout().base_triangles.size() << ",\n";
    os << "  \"layout\": {\"edge_paths\": " << L.edge_paths << ", \"face_paths\": " << L.face_paths
       << ", \"splits\": {\"source\": " << L.splits_source << ", \"target\": " << L.splits_target
       << "}, \"adjacency_splits\": {\"source\": " << L.adjacency_splits_source << ", \"target\": " << L.adjacency_splits_target
       << "}, \"flips\": " << L.flips << "},\n";
    os << "  \"protrusion_features\": " << protrusion_pairs_json(cp) << ",\n";
    os << "  \"stretch_reweighted\": {\"source\": " << (S.stretch_reweighted_source ? "true" : "false")
       << ", \"target\": " << (S.stretch_reweighted_target ? "true" : "false") << "},\n";
    os << "  \"squeeze\": {\"source\": " << json_number(S.squeeze_source) << ", \"target\": " << json_number(S.squeeze_target) << "},\n";
    os << "  \"smoothing\": {\"passes\": " << S.smoothing_source.iterations << ", \"kept_after\": " << S.smoothing_best_iteration
       << ", \"moves\": " << S.smoothing_source.moves + S.smoothing_target.moves
       << ", \"rejected\": " << S.smoothing_source.rejected + S.smoothing_target.rejected
       << ", \"migrations\": " << S.smoothing_source.migrations + S.smoothing_target.migrations << "},\n";
    os << "  \"distortion_before_smoothing\": " << dist(S.distortion_initial) << ",\n";
    os << "  \"distortion\": " << dist(S.distortion) << ",\n";
    os << "  \"certificate\": {\"source\": " << cert(cp.certificate(0)) << ", \"target\": " << cert(cp.certificate(1)) << "},\n";
    os << "  \"seconds\": {\"read\": " << json_number(read_s) << ", \"protrusion_probe\": " << json_number(S.seconds_probe)
       << ", \"layout\": " << json_number(L.seconds_total)
       << ", \"parameterization\": " << json_number(S.seconds_parameterization)
       << ", \"smoothing\": " << json_number(S.seconds_smoothing) << ", \"certificate\": " << json_number(S.seconds_certificate)
       << ", \"total\": " << json_number(S.seconds_total) << "}\n}\n";
  });
  if (!o.quiet) {
    std::cout << "map: " << L.features << " features, " << cp.layout().base_triangles.size() << " base triangles; "
              << "distortion E_ang " << json_number(S.distortion_initial.angular) << " -> " << json_number(S.distortion.angular)
              << ", L2 stretch " << json_number(S.distortion_initial.l2_stretch) << " -> " << json_number(S.distortion.l2_stretch)
              << "; certified one-to-one; " << json_number(S.seconds_total) << " s\n";
    std::cout << "wrote " << o.output << "/\n";
  }
}

int run_map(const Options& o) {
  Inputs in = read_inputs(o);
  Map cp = compute_map(o, in.source.mesh, in.target.mesh, in.features);
  write_map(o, cp, in.seconds);
  return 0;
}

using Remesher = Compatible_remesher<Surface_mesh, Surface_mesh>;

/// Blue (no error) through white to red (at or above the tolerance).
std::array<unsigned char, 3> error_color(double e, double tolerance) {
  const double x = std::min(1.0, std::max(0.0, e / tolerance));
  auto c = [](double a, double b, double t) { return static_cast<unsigned char>(std::lround(a + (b - a) * t)); };
  if (x < 0.5) return {c(40, 255, 2 * x), c(80, 255, 2 * x), c(220, 255, 2 * x)};
  return {c(255, 220, 2 * x - 1), c(255, 40, 2 * x - 1), c(255, 30, 2 * x - 1)};
}

/// Writes the outputs of `crossparam remesh` into o.output.
/// Writes the outputs of `remesh` and report.json, with the independent verification of the outputs against
/// the inputs as they were before the map refined them (`source0`, `target0`).
void write_remesh(const Options& o, const Map& cp, const Remesher& r, const Surface_mesh& source0,
                  const Surface_mesh& target0, double read_s) {
  Timer tv;
  Surface_mesh out_source, out_target;
  r.copy_to(0, out_source);
  r.copy_to(1, out_target);
  const Remeshing_verification check = verify_compatible_remeshing(source0, target0, out_source, out_target, o.tolerance);
  const double verify_s = tv.seconds();
  if (!o.quiet)
    std::cout << "remesh: verified: Hausdorff " << json_number(check.hausdorff_target) << "% (tolerance "
              << json_number(o.tolerance) << "%), source " << json_number(check.hausdorff_source) << "%, "
              << check.flipped_faces << " flipped faces, normals " << json_number(check.normal_deviation_mean)
              << " degrees off on average, " << json_number(check.normal_deviation_above_30)
              << "% of the area beyond 30 degrees (" << json_number(verify_s) << " s)\n";
  if (!check.valid) std::cerr << "crossparam: warning: the remeshing misses its tolerance: " << check.message << "\n";
  fs::create_directories(o.output);
  auto out = [&](const std::string& name) { return (fs::path(o.output) / name).string(); };
  write_off(out("source_compatible.off"), r.source_points(), r.faces());
  write_off(out("target_compatible.off"), r.target_points(), r.faces());
  std::vector<std::array<unsigned char, 3>> colors;
  for (double e : r.vertex_error()) colors.push_back(error_color(e, o.tolerance));
  write_ply_vertex_colored(out("target_error.ply"), r.target_points(), r.faces(), colors);
  if (o.png) render_png(Render_mesh{r.target_points(), r.faces(), {}, colors}, out("target_error.png"), o.render);
  const Remeshing_statistics& S = r.statistics();
  const Cross_parameterization_statistics& C = cp.statistics();
  const double added = 100.0 * (double(S.output_vertices) - double(S.source_vertices)) / double(S.source_vertices);
  write_file_atomically(out("report.json"), [&](std::ostream& os) {
    os << "{\n  \"stage\": \"remesh\",\n";
    os << "  \"source_vertices\": " << S.source_vertices << ",\n  \"target_vertices\": " << S.target_vertices << ",\n";
    os << "  \"features\": " << C.layout.features << ",\n";
    os << "  \"protrusion_features\": " << protrusion_pairs_json(cp) << ",\n";
    os << "  \"layout_vertices\": " << S.layout_vertices << ",\n  \"layout_splits_undone\": " << S.layout_splits_undone << ",\n";
    os << "  \"output_vertices\": " << S.output_vertices << ",\n  \"output_faces\": " << S.output_faces << ",\n";
    os << "  \"added_vertices_percent\": " << json_number(added) << ",\n";
    os << "  \"refinement_splits\": " << S.refinement_splits << ",\n  \"pseudo_flips\": " << S.pseudo_flips << ",\n  \"unfold_moves\": " << S.unfold_moves << ",\n";
    os << "  \"refinement_repairs\": {\"kept\": " << S.refinement_repairs_kept << ", \"undone\": " << S.refinement_repairs_undone
       << "},\n";
    os << "  \"fold_repair\": {\"splits\": " << S.fold_repair_splits << ", \"kept\": " << S.fold_repairs_kept
       << ", \"undone\": " << S.fold_repairs_undone << "},\n";
    os << "  \"untangling\": {\"folds_removed\": " << S.untangled_folds << ", \"vertices_moved\": " << S.untangle_moves
       << ", \"max_move_percent\": " << json_number(S.untangle_max_move) << "},\n";
    os << "  \"tolerance_percent\": " << json_number(S.tolerance) << ",\n";
    os << "  \"error_initial\": {\"max_percent\": " << json_number(S.max_error_initial)
       << ", \"l2_percent\": " << json_number(S.l2_error_initial) << "},\n";
    os << "  \"error\": {\"max_percent\": " << json_number(S.max_error) << ", \"l2_percent\": " << json_number(S.l2_error)
       << ", \"psnr\": " << json_number(S.psnr) << ", \"max_chord_percent\": " << json_number(S.max_chord_error) << "},\n";
    os << "  \"converged\": " << (S.converged ? "true" : "false") << ",\n";
    os << "  \"flipped_faces\": " << S.flipped_faces << ",\n";
    os << "  \"certificate\": " << (r.certificate().valid ? "true" : "false") << ",\n";
    os << "  \"verification\": {\"valid\": " << (check.valid ? "true" : "false") << ", \"compatible\": "
       << (check.compatible ? "true" : "false") << ", \"hausdorff_percent\": " << json_number(check.hausdorff_target)
       << ", \"hausdorff_source_percent\": " << json_number(check.hausdorff_source)
       << ", \"flipped_faces\": " << check.flipped_faces
       << ", \"normal_deviation_mean_degrees\": " << json_number(check.normal_deviation_mean)
       << ", \"normal_deviation_above_30_percent\": " << json_number(check.normal_deviation_above_30)
       << ", \"seconds\": " << json_number(verify_s) << "},\n";
    os << "  \"iterations\": {\"smoothing_rounds\": " << S.smoothing_rounds << ", \"refinement_rounds\": " << S.refinement_rounds << "},\n";
    os << "  \"seconds\": {\"read\": " << json_number(read_s) << ", \"protrusion_probe\": " << json_number(C.seconds_probe)
       << ", \"layout\": " << json_number(C.layout.seconds_total)
       << ", \"parameterization\": " << json_number(C.seconds_parameterization)
       << ", \"smoothing\": " << json_number(C.seconds_smoothing) << ", \"map_total\": " << json_number(C.seconds_total)
       << ", \"adaptive_smoothing\": " << json_number(S.seconds_smoothing)
       << ", \"refinement\": " << json_number(S.seconds_refinement) << ", \"pseudo_flips\": " << json_number(S.seconds_flips)
       << ", \"fold_repair\": " << json_number(S.seconds_fold_repair)
       << ", \"untangle\": " << json_number(S.seconds_untangle)
       << ", \"certificate\": " << json_number(S.seconds_certificate) << ", \"remesh_total\": " << json_number(S.seconds_total)
       << "}\n}\n";
  });
  if (!o.quiet) {
    std::cout << "remesh: " << S.source_vertices << " -> " << S.output_vertices << " vertices (" << json_number(added)
              << "% added), error max " << json_number(S.max_error) << "%, L2 " << json_number(S.l2_error) << "%, PSNR "
              << json_number(S.psnr) << (S.converged ? "" : " (tolerance not reached everywhere)") << "; "
              << json_number(C.seconds_total + S.seconds_total) << " s\n";
    std::cout << "wrote " << o.output << "/\n";
  }
}

/// Progress lines on stderr unless --quiet.
std::function<void(const std::string&)> progress_printer(const Options& o) {
  if (o.quiet) return {};
  return [](const std::string& line) { std::cerr << line << "\n"; };
}

// The compatible remeshing of `cp` with the options' tolerance, progress lines and threads.
Remesher remesh(const Options& o, const Map& cp) {
  return Remesher(cp, crossparam::parameters::tolerance(o.tolerance, crossparam::parameters::progress(progress_printer(o),
                      crossparam::parameters::number_of_threads(o.threads))));
}

int run_remesh(const Options& o) {
  Inputs in = read_inputs(o);
  const Surface_mesh source0 = in.source.mesh, target0 = in.target.mesh; // the map refines its inputs
  Map cp = compute_map(o, in.source.mesh, in.target.mesh, in.features);
  const Remesher r = remesh(o, cp);
  write_remesh(o, cp, r, source0, target0, in.seconds);
  return 0;
}

/// Writes frame_000.off ... between two compatible soups; with --png a picture per frame and morph_strip.png.
void write_morph(const Options& o, const Polygon_soup& a, const Polygon_soup& b) {
  fs::create_directories(o.output);
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
  // The strip: up to five frames side by side, spread along the picture's horizontal.
  Render_mesh strip;
  const std::array<double, 3> right = internal::unit3(internal::cross3(o.render.view_direction, o.render.up));
  double width = 0;
  for (int i = 0; i < 3; ++i) width += (ro.frame_max[i] - ro.frame_min[i]) * std::abs(right[i]);
  const unsigned strip_frames = std::min(o.frames, 5u);
  std::vector<unsigned> strip_of(o.frames, ~0u);
  for (unsigned slot = 0; slot < strip_frames; ++slot)
    strip_of[std::size_t(std::lround(double(slot) * (o.frames - 1) / double(strip_frames - 1)))] = slot;
  for (unsigned k = 0; k < o.frames; ++k) {
    const double t = double(k) / double(o.frames - 1);
    std::vector<std::array<double, 3>> pts = morph(a.points, b.points, t);
    std::ostringstream name;
    name << "frame_" << std::setw(3) << std::setfill('0') << k;
    write_off((fs::path(o.output) / (name.str() + ".off")).string(), pts, tris);
    if (o.png) {
      render_png(Render_mesh{pts, tris, {}, {}}, (fs::path(o.output) / (name.str() + ".png")).string(), ro);
      if (strip_of[k] != ~0u) {
        const std::size_t base = strip.points.size();
        const double shift = 1.1 * width * strip_of[k];
        for (const auto& p : pts) strip.points.push_back({p[0] + shift * right[0], p[1] + shift * right[1], p[2] + shift * right[2]});
        for (const auto& f : tris) strip.triangles.push_back({f[0] + base, f[1] + base, f[2] + base});
      }
    }
    if (!o.quiet) std::cerr << "morph: frame " << k + 1 << "/" << o.frames << "\n";
  }
  if (o.png) {
    Render_options so = o.render;
    so.height = 320;
    so.width = 300 * int(strip_frames);
    so.zoom = 1.0;
    render_png(strip, (fs::path(o.output) / "morph_strip.png").string(), so);
  }
  if (!o.quiet) std::cout << "morph: " << o.frames << " frames of " << a.points.size() << " vertices; wrote " << o.output << "/\n";
}

int run_morph(const Options& o) {
  if (o.positional.size() != 2) throw Usage_error("morph needs two compatible meshes A and B");
  if (o.output.empty()) throw Usage_error("morph needs -o DIR");
  Polygon_soup a = read_polygon_soup(o.positional[0]), b = read_polygon_soup(o.positional[1]);
  check_compatible(a, b, o.positional[0], o.positional[1]);
  write_morph(o, a, b);
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
  const Surface_mesh a0 = a, b0 = b; // the map refines its inputs
  Map cp = compute_map(o, a, b, f);
  write_layout(o, a, b, cp.layout(), {{"generate", gen_s}});
  write_map(o, cp, gen_s);
  const Remesher r = remesh(o, cp);
  write_remesh(o, cp, r, a0, b0, gen_s);
  // The morph sequence between the two compatible meshes.
  Polygon_soup sa, sb;
  sa.points = r.source_points();
  sb.points = r.target_points();
  for (const auto& t : r.faces()) sa.polygons.push_back({t[0], t[1], t[2]});
  sb.polygons = sa.polygons;
  Options mo = o;
  mo.output = (fs::path(o.output) / "morph").string();
  write_morph(mo, sa, sb);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  try {
    Options o = parse(argc, argv);
    if (o.png && !povray_available())
      throw Error("--png needs POV-Ray, which is not installed (apt-get install povray)");
    if (o.command == "layout") return run_layout(o);
    if (o.command == "map") return run_map(o);
    if (o.command == "remesh") return run_remesh(o);
    if (o.command == "morph") return run_morph(o);
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
    // Many library messages already begin with "internal error: "; say it once.
    const std::string what = e.what(), prefix = "internal error: ";
    std::cerr << "crossparam: " << (what.rfind(prefix, 0) == 0 ? "" : prefix) << what << "\n";
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

// SPDX-License-Identifier: GPL-3.0-or-later
// The CLI's arguments: the usage text, the options of every command and their parsing. Bad usage throws
// Usage_error (exit code 2); `-h`/`--help` throws it with an empty message (print the usage, exit 0).
#ifndef CROSSPARAM_CLI_OPTIONS_H
#define CROSSPARAM_CLI_OPTIONS_H

#include "render.h"

#include <crossparam/parameters.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace crossparam {
namespace cli {

inline const char* const usage_text =
    "usage: crossparam <command> [options]\n"
    "\n"
    "commands:\n"
    "  layout SOURCE TARGET --features FILE -o DIR\n"
    "      topologically identical triangular patch layouts of two closed meshes of one genus (paper section 3)\n"
    "  map SOURCE TARGET --features FILE -o DIR\n"
    "      cross-parameterization (paper section 4): the bijective map between the meshes, certified\n"
    "  remesh SOURCE TARGET --features FILE -o DIR [--tolerance PCT]\n"
    "      compatible remeshing (paper section 5): two meshes with one connectivity, one reproducing SOURCE,\n"
    "      the other approximating TARGET\n"
    "  remesh M0 M1 M2 ... --features FILE -o DIR [--tolerance PCT] [--source-mesh K|finest]\n"
    "      one connectivity for three or more meshes (paper section 2.3): compatible_0.off ... one per mesh,\n"
    "      in command-line order; FILE has one column per mesh\n"
    "  blend M0 M1 ... -o DIR (--weights W0,W1,... | --weight-file FILE | --region K,R[,F] --features FILE)\n"
    "      blend of compatible meshes: affine weights, one row of weights per vertex, or (two meshes) M1\n"
    "      within geodesic distance R of feature K and M0 elsewhere, with a falloff F (R, F in units of the\n"
    "      square root of M0's area; F defaults to R/2)\n"
    "  transfer SOURCE.obj TARGET --features FILE -o DIR [--texture IMG] [--attributes FILE]\n"
    "      the source's texture coordinates onto the target's shape (target_textured.obj, .mtl, the image),\n"
    "      and per-vertex data of the source (one row per vertex) onto the target's vertices\n"
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
    "  --straighten-paths\n"
    "                    layout, map, remesh, demo: once the layout is complete, shorten each path inside its\n"
    "                    two patches (on the wider bench a more accurate map on average; on some pairs a\n"
    "                    remeshing with more flipped faces)\n"
    "  --iterations N    smoothing passes at most (map; default 200)\n"
    "  --no-smoothing    skip the smoothing of section 4.2 (map)\n"
    "  --map-smoothing   map, remesh, demo: after the smoothing of section 4.2, smooth the map itself\n"
    "                    (the source's vertices move so that the map is as rigid as possible onto the\n"
    "                    target; on the wider bench a more accurate map on average, at about 5 times the\n"
    "                    map's time)\n"
    "  --no-map-smoothing-retry\n"
    "                    remesh: where the remeshing fails the strict checks, do not map and remesh again\n"
    "                    with the map smoothing (by default that is tried, and its result kept if it passes)\n"
    "  --no-protrusion-features\n"
    "                    use only the given features (map, remesh, demo): no pairs added at the tips of\n"
    "                    squeezed protrusions\n"
    "  --extremity-features\n"
    "                    map, remesh, demo: keep every pair found at the extremities (fingertips, limbs, tails\n"
    "                    away from every feature) that a first map sends to the wrong place; by default they\n"
    "                    are kept only if they lower the map's worst disagreement with the distances to the\n"
    "                    features\n"
    "  --no-extremity-features\n"
    "                    map, remesh, demo: do not look for such pairs\n"
    "  --tolerance PCT   remesh: approximation tolerance in percent of the target's bounding-box diagonal\n"
    "                    (default 0.5)\n"
    "  --construction C  remesh, demo: how the target-shaped mesh is built: refinement (the paper's), overlay\n"
    "                    (the map's overlay with the target, decimated within the tolerance) or automatic (the\n"
    "                    refinement, and the overlay where the refinement's result fails the strict checks;\n"
    "                    the default)\n"
    "  --threads N       map, remesh, demo: threads for the smoothing of the two meshes and the error\n"
    "                    measurements (default 0: one per hardware thread); the results are the same for any N\n"
    "  --frames N        morph: number of meshes written, both ends included (default 9)\n"
    "  --png             also render pictures of the results (needs POV-Ray: apt-get install povray)\n"
    "  --up X,Y,Z        the models' up direction in the pictures (default 0,0,1)\n"
    "  --view X,Y,Z      direction from the model towards the camera (default 1,-1.6,0.6)\n"
    "  --time-limit S    stop after S seconds (map, remesh, demo: the computation's budget) with exit code 3\n"
    "  --best-effort     at the time limit, keep and write the best valid result reached instead; write a\n"
    "                    result that fails its independent verification with exit code 0 instead of 4\n"
    "  --quiet           print nothing but errors\n"
    "  -h, --help        this text\n"
    "\n"
    "meshes: OFF, OBJ, PLY or STL; closed, manifold, one component, both of one genus (genus > 0: about four\n"
    "features around each handle, or the layout stops naming the patch that needs more).\n"
    "\n"
    "exit codes: 0 a valid result, 1 bad input (or an output that cannot be written), 2 bad usage,\n"
    "3 internal error or time limit, 4 a result written that failed its independent verification.\n";

/// The exit codes: a valid result, bad input (or an output that cannot be written), bad usage, an internal
/// error or the time limit, a result written that failed its independent verification.
constexpr int exit_valid = 0, exit_bad_input = 1, exit_bad_usage = 2, exit_internal_error = 3,
              exit_failed_verification = 4;

/// Bad usage: exit code 2. An empty message asks for the usage text (exit code 0).
struct Usage_error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Every command's options, with their defaults.
struct Options {
  std::string command;
  std::vector<std::string> positional;
  std::string features;
  std::string output;
  std::string staging; ///< the folder the files are written into while a result is being written (Output_folder)
  bool flips = true;
  bool straighten = false;
  bool quiet = false;
  bool png = false;
  bool smoothing = true;
  bool map_smoothing = false;
  bool map_smoothing_global = true; ///< its global steps (off only in remesh's second attempt)
  bool map_smoothing_retry = true; ///< remesh: again with the map smoothing where the remeshing fails the checks
  bool protrusion_features = true;
  bool extremity_features = true;  ///< look for pairs at extremities
  bool select_extremities = true;  ///< keep them only if they lower the worst descriptor mismatch
  unsigned iterations = 200;
  double tolerance = 0.5;
  unsigned threads = 0;
  unsigned frames = 9;
  /// The computation runs on the inputs multiplied by 2^units_exponent (exact; see normalize_units() in
  /// outputs.h); every coordinate written is divided back.
  int units_exponent = 0;
  double time_limit = HUGE_VAL; ///< seconds; none by default
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now(); ///< when the run started
  bool best_effort = false;
  Remeshing_construction construction = Remeshing_construction::automatic;
  Render_options render;
  // N-way remeshing, blends and transfers (cli/multi.h)
  std::size_t source_mesh = 0; ///< --source-mesh; crossparam::finest_mesh for "finest"
  std::string weights, weight_file, region, texture, attributes;
};

/// Largest accepted `--iterations`, `--threads` and `--frames`: far above any useful value, low enough that a
/// typing error does not start a run of days or a million threads.
constexpr unsigned long max_iterations = 100000, max_threads = 1024, max_frames = 10000;

/// `X,Y,Z`: three numbers, not all zero, or a usage error naming the option `name`.
inline std::array<double, 3> parse_vector(const std::string& name, const std::string& v) {
  std::array<double, 3> out{};
  std::istringstream is(v);
  char c1 = 0, c2 = 0;
  if (!(is >> out[0] >> c1 >> out[1] >> c2 >> out[2]) || c1 != ',' || c2 != ',' || !is.eof() ||
      !(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] > 0))
    throw Usage_error(name + " needs three numbers X,Y,Z, not all zero");
  return out;
}

/// A whole number in [lo, hi] written in decimal digits alone, or a usage error with `message`.
inline unsigned whole_number(const std::string& v, unsigned long lo, unsigned long hi, const char* message) {
  char* end = nullptr;
  const unsigned long n = std::strtoul(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0' || n < lo || n > hi) throw Usage_error(message);
  return unsigned(n);
}

/// A percentage in (0, 100], or a usage error naming `--tolerance`.
inline double tolerance_percent(const std::string& v) {
  char* end = nullptr;
  const double t = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !(t > 0) || !(t <= 100)) throw Usage_error("--tolerance needs a percentage in (0, 100]");
  return t;
}

/// Largest accepted `--time-limit`: a year, far above any run, low enough to stay a finite number of seconds.
constexpr double max_time_limit_seconds = 366.0 * 24 * 3600;

/// A number of seconds in (0, max_time_limit_seconds], or a usage error naming `--time-limit`.
inline double time_limit_seconds(const std::string& v) {
  char* end = nullptr;
  const double t = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !(t > 0) || !(t <= max_time_limit_seconds))
    throw Usage_error("--time-limit needs a positive number of seconds (at most a year)");
  return t;
}

/// The command line: argv[1] is the command, then options and positional arguments in any order.
inline Options parse(int argc, char** argv) {
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
    else if (a == "--straighten-paths") o.straighten = true;
    else if (a == "--png") o.png = true;
    else if (a == "--no-smoothing") o.smoothing = false;
    else if (a == "--map-smoothing") o.map_smoothing = true;
    else if (a == "--no-map-smoothing-retry") o.map_smoothing_retry = false;
    else if (a == "--no-protrusion-features") o.protrusion_features = false;
    else if (a == "--extremity-features") o.extremity_features = true, o.select_extremities = false;
    else if (a == "--no-extremity-features") o.extremity_features = false;
    else if (a == "--up") o.render.up = parse_vector(a, value());
    else if (a == "--view") o.render.view_direction = parse_vector(a, value());
    else if (a == "--iterations") o.iterations = whole_number(value(), 0, max_iterations, "--iterations needs a whole number up to 100000");
    else if (a == "--threads") o.threads = whole_number(value(), 0, max_threads, "--threads needs a whole number up to 1024");
    else if (a == "--tolerance") o.tolerance = tolerance_percent(value());
    else if (a == "--frames") o.frames = whole_number(value(), 2, max_frames, "--frames needs a whole number from 2 to 10000");
    else if (a == "--time-limit") o.time_limit = time_limit_seconds(value());
    else if (a == "--best-effort") o.best_effort = true;
    else if (a == "--construction") {
      const std::string v = value();
      if (v == "automatic") o.construction = Remeshing_construction::automatic;
      else if (v == "refinement") o.construction = Remeshing_construction::refinement;
      else if (v == "overlay") o.construction = Remeshing_construction::overlay;
      else throw Usage_error("--construction needs automatic, refinement or overlay");
    }
    else if (a == "--weights") o.weights = value();
    else if (a == "--weight-file") o.weight_file = value();
    else if (a == "--region") o.region = value();
    else if (a == "--texture") o.texture = value();
    else if (a == "--attributes") o.attributes = value();
    else if (a == "--source-mesh") {
      const std::string v = value();
      o.source_mesh = v == "finest" ? std::size_t(-1) : whole_number(v, 0, max_frames, "--source-mesh needs a mesh index or 'finest'");
    }
    else if (a == "--quiet" || a == "-q") o.quiet = true;
    else if (a == "-h" || a == "--help") throw Usage_error("");
    else if (!a.empty() && a[0] == '-') throw Usage_error("unknown option " + a);
    else o.positional.push_back(a);
  }
  return o;
}

} // namespace cli
} // namespace crossparam

#endif // CROSSPARAM_CLI_OPTIONS_H

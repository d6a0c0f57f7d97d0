// SPDX-License-Identifier: GPL-3.0-or-later
// The crossparam command-line tool: thin; parses arguments, calls the library, writes files.
//
//   crossparam layout SOURCE TARGET --features FILE -o DIR   patch layouts (paper §3)
//   crossparam map SOURCE TARGET --features FILE -o DIR      cross-parameterization (§4)
//   crossparam remesh SOURCE TARGET --features FILE -o DIR   compatible remeshing (§5)
//   crossparam remesh M0 M1 M2 ... --features FILE -o DIR   one connectivity for N meshes (§2.3)
//   crossparam blend M0 M1 ... -o DIR                       affine and local blends of compatible meshes
//   crossparam transfer SOURCE.obj TARGET --features FILE -o DIR   texture and attribute transfer (§6)
//   crossparam morph A B --frames N -o DIR                   morph between two compatible meshes
//   crossparam demo -o DIR                                   the built-in example, end to end
//
// Errors: one line on stderr, exit code 1 for bad input, 2 for bad usage, 3 for an internal failure.
// Outputs are computed completely before anything is written, and each file is written atomically.
//
// One translation unit (CGAL compiles slowly); its parts are headers in cli/:
//   options.h   the usage text and the argument parsing
//   commands.h  the commands: inputs, the library calls, the demo
//   outputs.h   the files, pictures and summary lines each command writes
//   multi.h     the commands on N meshes and the transfers
//   report.h    the JSON writer of report.json
//   render.h    pictures with POV-Ray (--png)
//   png.h       the PNG writer of the checkerboard texture
#include "cli/commands.h"
#include "cli/multi.h"
#include "cli/options.h"
#include "cli/render.h"

#include <crossparam/errors.h>

#include <filesystem>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  using namespace crossparam;
  using namespace crossparam::cli;
  try {
    Options o = parse(argc, argv);
    if (o.png && !povray_available())
      throw Error("--png needs POV-Ray, which is not installed (apt-get install povray)");
    if (o.command == "layout") return run_layout(o);
    if (o.command == "map") return run_map(o);
    if (o.command == "remesh") return o.positional.size() >= 3 ? run_multi_remesh(o) : run_remesh(o);
    if (o.command == "blend") return run_blend(o);
    if (o.command == "transfer") return run_transfer(o);
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
  } catch (const std::filesystem::filesystem_error& e) {
    std::cerr << "crossparam: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "crossparam: internal error: " << e.what() << "\n";
    return 3;
  }
}

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
// Errors: one line on stderr. Exit codes: 0 a valid result, 1 bad input (or an output that cannot be written),
// 2 bad usage, 3 an internal error or the time limit (--time-limit), 4 a result that was written but failed its
// independent verification (0 with --best-effort). The output folder is checked before any work; the files of
// a result are written into a staging folder and moved into place together (cli/output_folder.h).
//
// One translation unit (CGAL compiles slowly); its parts are headers in cli/:
//   options.h   the usage text and the argument parsing
//   commands.h  the commands: inputs, the library calls, the demo
//   output_folder.h  the output folder: checked first, whole results moved into place at the end
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

#include <CGAL/exceptions.h>

#include <filesystem>
#include <cmath>
#include <iostream>
#include <new>
#include <string>

int main(int argc, char** argv) {
  using namespace crossparam;
  using namespace crossparam::cli;
  double time_limit = HUGE_VAL; // the user's --time-limit, for its message
  try {
    Options o = parse(argc, argv);
    time_limit = o.time_limit;
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
    return exit_bad_usage;
  } catch (const Time_limit_error& e) {
    std::cerr << "crossparam: time limit of " << format_number(time_limit) << " s reached during " << e.stage()
              << (e.reached().empty() ? "" : " (" + e.reached() + ")")
              << "; nothing written (--best-effort keeps the best result reached)\n";
    return exit_internal_error;
  } catch (const Algorithm_error& e) {
    // Many library messages already begin with "internal error: "; say it once.
    const std::string what = e.what(), prefix = "internal error: ";
    std::cerr << "crossparam: " << (what.rfind(prefix, 0) == 0 ? "" : prefix) << what << "\n";
    return exit_internal_error;
  } catch (const Error& e) {
    std::cerr << "crossparam: error: " << e.what() << "\n";
    return exit_bad_input;
  } catch (const std::filesystem::filesystem_error& e) {
    std::cerr << "crossparam: error: " << e.what() << "\n";
    return exit_bad_input;
  } catch (const CGAL::Failure_exception& e) {
    // One line, not CGAL's multi-line report: a failed check inside CGAL is a bug of crossparam's.
    std::cerr << "crossparam: internal error: a CGAL " << e.library() << " check failed (" << e.expression() << ")\n";
    return exit_internal_error;
  } catch (const std::bad_alloc&) {
    std::cerr << "crossparam: internal error: out of memory\n";
    return exit_internal_error;
  } catch (const std::exception& e) {
    std::string what = e.what();
    for (char& c : what)
      if (c == '\n') c = ' ';
    std::cerr << "crossparam: internal error: " << what << "\n";
    return exit_internal_error;
  }
}

// SPDX-License-Identifier: GPL-3.0-or-later
// Exception types thrown by crossparam. The library never prints: every failure a user can cause is an
// exception whose what() names the input (file or mesh) and the problem, with a line or index where there is one.
#ifndef CROSSPARAM_ERRORS_H
#define CROSSPARAM_ERRORS_H

#include <stdexcept>
#include <string>

namespace crossparam {

/// Base class of every exception crossparam throws.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// A file could not be read, or a mesh is not a valid input (open, non-manifold, non-finite, ...). Thrown by the
/// readers of <crossparam/io.h> and the mesh checks of <crossparam/validation.h>, also for invalid options.
class Input_error : public Error {
public:
  using Error::Error;
};

/// The feature correspondence is invalid (malformed line, index out of range, duplicates, too few). Thrown by
/// read_feature_pairs() and validate_feature_pairs().
class Feature_error : public Input_error {
public:
  using Input_error::Input_error;
};

/// The two inputs are individually valid but cannot be used together (different genus, meshes that are not
/// compatible, ...). Thrown by the input checks of the entry points and check_compatible().
class Incompatible_inputs_error : public Input_error {
public:
  using Input_error::Input_error;
};

/// The features are too few for a layout of meshes of genus > 0: once every path the features allow is in
/// place, a patch still carries a handle or several boundary loops (or the base mesh cannot be a simple
/// triangulation). what() names that patch by its corner features, says what it still carries, and gives a
/// vertex of each mesh near it where one more corresponding feature would help. Thrown by
/// compute_patch_layouts() and everything built on it; about four features around each handle avoid it.
class Insufficient_features_error : public Feature_error {
public:
  using Feature_error::Feature_error;
};

/// An algorithm could not complete, or a result failed its independent verification.
/// Seeing this is a bug in crossparam or an unsupported case that the message names.
class Algorithm_error : public Error {
public:
  using Error::Error;
};

/// The time budget of a computation (named parameter `time_limit`) ran out. Not a defect of the inputs nor a
/// bug: the computation was stopped between two of its steps, or inside a long loop, at a point where it holds
/// no partial result. what() is "time limit of S s reached during <stage> (<what was reached>)".
class Time_limit_error : public Error {
public:
  Time_limit_error(const std::string& stage, const std::string& reached, double seconds)
      : Error("time limit of " + format_seconds(seconds) + " s reached during " + stage +
              (reached.empty() ? std::string() : " (" + reached + ")")),
        stage_(stage), reached_(reached) {}

  /// The step that was running, e.g. "the remeshing's untangling".
  const std::string& stage() const { return stage_; }
  /// What that step had done when it stopped, e.g. "round 3 of at most 30"; may be empty.
  const std::string& reached() const { return reached_; }

private:
  static std::string format_seconds(double s) {
    std::string t = std::to_string(s);
    while (t.size() > 1 && t.back() == '0') t.pop_back();
    if (!t.empty() && t.back() == '.') t.pop_back();
    return t;
  }
  std::string stage_, reached_;
};

} // namespace crossparam

#endif // CROSSPARAM_ERRORS_H

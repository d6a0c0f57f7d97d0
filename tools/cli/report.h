// SPDX-License-Identifier: GPL-3.0-or-later
// report.json: a small JSON writer. The top-level object has one member per line; nested objects and arrays
// stay on one line:
//
//   {
//     "stage": "remesh",
//     "error": {"max_percent": 0.66991, "l2_percent": 0.0638325},
//     "protrusion_features": [[12, 40], [13, 52]]
//   }
//
// Strings are escaped as JSON requires; numbers are written with `number_digits` significant digits in the
// C locale; a number that is not finite (JSON has no inf or NaN) is written as null.
#ifndef CROSSPARAM_CLI_REPORT_H
#define CROSSPARAM_CLI_REPORT_H

#include <cmath>
#include <cstdio>
#include <locale>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace crossparam {
namespace cli {

/// Significant digits of the numbers the CLI prints and writes to report.json.
constexpr int number_digits = 6;

/// `x` with `number_digits` significant digits, shortest form (as printf's %g), in the C locale.
inline std::string format_number(double x) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s.precision(number_digits);
  s << x;
  return s.str();
}

/// Writes one JSON document to a stream as it is built: `begin_object()`, then `key(...)` and a value (or a
/// nested object or array) per member, `end_object()`. `member(k, v)` is `key(k).value(v)`. The document is
/// complete (with a final newline) when the outermost container is closed.
class Json_writer {
public:
  explicit Json_writer(std::ostream& os) : os_(os) {}

  Json_writer& begin_object() { return open('{', true); }
  Json_writer& end_object() { return close('}', true); }
  Json_writer& begin_array() { return open('[', false); }
  Json_writer& end_array() { return close(']', false); }

  /// The name of the next member of the current object.
  Json_writer& key(const std::string& k) {
    if (stack_.empty() || !stack_.back().object || pending_key_) throw std::logic_error("Json_writer: key outside an object");
    separate();
    write_string(k);
    os_ << ": ";
    pending_key_ = true;
    return *this;
  }

  Json_writer& value(const std::string& s) {
    start_value();
    write_string(s);
    return *this;
  }
  Json_writer& value(const char* s) { return value(std::string(s)); }
  Json_writer& value(bool b) {
    start_value();
    os_ << (b ? "true" : "false");
    return *this;
  }
  Json_writer& value(double x) {
    start_value();
    os_ << (std::isfinite(x) ? format_number(x) : std::string("null"));
    return *this;
  }
  template <class Integer, std::enable_if_t<std::is_integral<Integer>::value && !std::is_same<Integer, bool>::value, int> = 0>
  Json_writer& value(Integer n) {
    start_value();
    os_ << std::to_string(n);
    return *this;
  }

  template <class T>
  Json_writer& member(const std::string& k, const T& v) {
    return key(k).value(v);
  }

private:
  struct Level {
    bool object;    // an object (else an array)
    bool multiline; // one member per line (the top-level object)
    bool empty;     // nothing written in it yet
  };

  Json_writer& open(char bracket, bool object) {
    start_value();
    os_ << bracket;
    stack_.push_back({object, object && stack_.empty(), true});
    return *this;
  }

  Json_writer& close(char bracket, bool object) {
    if (stack_.empty() || stack_.back().object != object || pending_key_)
      throw std::logic_error("Json_writer: unbalanced container");
    if (stack_.back().multiline && !stack_.back().empty) os_ << "\n";
    os_ << bracket;
    stack_.pop_back();
    if (stack_.empty()) os_ << "\n";
    return *this;
  }

  // Before a member's key or an array element: the separator from the previous one.
  void separate() {
    Level& l = stack_.back();
    if (l.multiline) os_ << (l.empty ? "\n  " : ",\n  ");
    else if (!l.empty) os_ << ", ";
    l.empty = false;
  }

  // Before any value: after its key in an object, after a separator in an array; only one top-level value.
  void start_value() {
    if (pending_key_) {
      pending_key_ = false;
      return;
    }
    if (stack_.empty()) {
      if (started_) throw std::logic_error("Json_writer: a second top-level value");
      started_ = true;
      return;
    }
    if (stack_.back().object) throw std::logic_error("Json_writer: value without a key");
    separate();
  }

  void write_string(const std::string& s) {
    os_ << '"';
    for (unsigned char c : s) {
      switch (c) {
      case '"': os_ << "\\\""; break;
      case '\\': os_ << "\\\\"; break;
      case '\b': os_ << "\\b"; break;
      case '\f': os_ << "\\f"; break;
      case '\n': os_ << "\\n"; break;
      case '\r': os_ << "\\r"; break;
      case '\t': os_ << "\\t"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(c));
          os_ << buf;
        } else {
          os_ << char(c); // UTF-8 bytes pass through unchanged
        }
      }
    }
    os_ << '"';
  }

  std::ostream& os_;
  std::vector<Level> stack_;
  bool pending_key_ = false;
  bool started_ = false;
};

} // namespace cli
} // namespace crossparam

#endif // CROSSPARAM_CLI_REPORT_H

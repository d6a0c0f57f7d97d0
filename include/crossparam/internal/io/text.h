// SPDX-License-Identifier: GPL-3.0-or-later
// The text and file primitives shared by the soup readers: reading a whole file, lines, tokens, numbers, and
// error messages that name the file and line. Everything here is an implementation detail of <crossparam/io.h>.
#ifndef CROSSPARAM_INTERNAL_IO_TEXT_H
#define CROSSPARAM_INTERNAL_IO_TEXT_H

#include <crossparam/errors.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace crossparam {
namespace internal {
namespace soup_io {

/// A token of a file, quoted for an error message: at most 40 characters, non-printable bytes as \xNN.
inline std::string quote(std::string_view s) {
  static const char* hex = "0123456789abcdef";
  std::string out = "'";
  const std::size_t n = std::min<std::size_t>(s.size(), 40);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  if (s.size() > n) out += "...";
  out += "'";
  return out;
}

/// Throws E("<path>: <msg>") or E("<path>: line N: <msg>").
template <class E = Input_error>
struct Reporter {
  std::string path;
  [[noreturn]] void fail(const std::string& msg) const { throw E(path + ": " + msg); }
  [[noreturn]] void fail_line(std::size_t line, const std::string& msg) const {
    throw E(path + ": line " + std::to_string(line) + ": " + msg);
  }
};

/// Reads a whole file; throws E naming the path if it is missing, a directory, unreadable or empty.
template <class E = Input_error>
std::string read_whole_file(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) throw E("(empty file name): no file name given");
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::not_found) throw E(path + ": file does not exist");
  if (ec) throw E(path + ": cannot access file (" + ec.message() + ")");
  if (st.type() == fs::file_type::directory) throw E(path + ": is a directory, not a file");
  if (st.type() != fs::file_type::regular) throw E(path + ": is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw E(path + ": cannot open file for reading (" + std::strerror(errno) + ")");
  std::string data;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size < (std::uintmax_t(1) << 40)) data.reserve(static_cast<std::size_t>(size));
  char buf[1 << 16];
  while (in) {
    in.read(buf, sizeof buf);
    data.append(buf, static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw E(path + ": read error (" + std::strerror(errno) + ")");
  if (data.empty()) throw E(path + ": file is empty");
  return data;
}

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

inline bool starts_with(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

inline std::string to_lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

/// Splits `line` at whitespace; with `hash_comments`, everything from the first '#' on is dropped.
inline void split(std::string_view line, std::vector<std::string_view>& toks, bool hash_comments) {
  toks.clear();
  if (hash_comments) {
    const std::size_t h = line.find('#');
    if (h != std::string_view::npos) line = line.substr(0, h);
  }
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && is_space(line[i])) ++i;
    if (i >= n) break;
    std::size_t j = i;
    while (j < n && !is_space(line[j])) ++j;
    toks.push_back(line.substr(i, j - i));
    i = j;
  }
}

/// Iterates over lines ending in "\n", "\r\n" or "\r"; `line` is the 1-based number of the last line returned.
struct Line_cursor {
  std::string_view data;
  std::size_t pos = 0;
  std::size_t line = 0;
  int cr_breaks = -1; // a lone '\r' ends a line only in files without any '\n' (classic Mac); else it is a space

  bool next(std::string_view& out) {
    if (pos >= data.size()) return false;
    if (cr_breaks < 0) cr_breaks = data.find('\n') == std::string_view::npos ? 1 : 0;
    std::size_t e = cr_breaks ? data.find('\r', pos) : data.find('\n', pos);
    if (e == std::string_view::npos) e = data.size();
    out = data.substr(pos, e - pos);
    pos = e < data.size() ? e + 1 : e;
    ++line;
    return true;
  }
  std::size_t remaining() const { return pos >= data.size() ? 0 : data.size() - pos; }
};

/// Whether binary numbers in memory are big-endian (binary PLY and STL files say which order they use).
inline bool host_is_big_endian() {
  const std::uint16_t x = 1;
  unsigned char b;
  std::memcpy(&b, &x, 1);
  return b == 0;
}

/// Parses a whole token as a double (decimal or scientific, "nan"/"inf" allowed and reported later).
/// Values too large for a double become +-max (rejected as out of range); too small ones become 0.
inline bool parse_double(std::string_view t, double& v) {
  if (t.empty()) return false;
  const char* b = t.data();
  const char* e = b + t.size();
  if (*b == '+') {
    ++b;
    if (b == e || *b == '+' || *b == '-') return false;
  }
  const auto r = std::from_chars(b, e, v, std::chars_format::general);
  if (r.ptr != e) return false;
  if (r.ec == std::errc::result_out_of_range) {
    const bool negative = (*b == '-');
    const std::size_t epos = t.find_first_of("eE");
    const bool tiny = epos != std::string_view::npos && epos + 1 < t.size() && t[epos + 1] == '-';
    if (tiny) {
      v = negative ? -0.0 : 0.0;
    } else {
      v = negative ? -std::numeric_limits<double>::max() : std::numeric_limits<double>::max();
    }
    return true;
  }
  return r.ec == std::errc();
}

/// Parses a whole token as a signed 64-bit integer ('+' allowed).
inline bool parse_int(std::string_view t, long long& v) {
  if (t.empty()) return false;
  const char* b = t.data();
  const char* e = b + t.size();
  if (*b == '+') {
    ++b;
    if (b == e || *b == '+' || *b == '-') return false;
  }
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

/// Parses a whole token as an unsigned 64-bit integer (digits only, '+' allowed).
inline bool parse_count(std::string_view t, std::uint64_t& v) {
  if (t.empty()) return false;
  const char* b = t.data();
  const char* e = b + t.size();
  if (*b == '+') ++b;
  if (b == e || *b < '0' || *b > '9') return false;
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

} // namespace soup_io
} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_IO_TEXT_H

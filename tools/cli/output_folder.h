// SPDX-License-Identifier: GPL-3.0-or-later
// The output folder of one command, and whole results. The folder given with -o is checked (or created) before
// any work; the files of the result are written into a staging folder beside it (".DIR.crossparam-PID", or
// inside DIR when DIR's parent cannot be written) and moved into DIR when all of them are complete: by one
// rename when DIR is new or empty, else file by file (renames only, no data written). A failure, a full disk or
// an interrupting signal (SIGINT, SIGTERM, SIGHUP) removes the staging folder and leaves DIR as it was; the
// staging folder of a killed run (SIGKILL) is removed by the next run into the same DIR.
#ifndef CROSSPARAM_CLI_OUTPUT_FOLDER_H
#define CROSSPARAM_CLI_OUTPUT_FOLDER_H

#include <crossparam/errors.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>

#include <sys/syscall.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace crossparam {
namespace cli {

namespace output_folder_detail {

/// The staging folder's path for the signal handler (which may not allocate): a fixed buffer, empty when none.
constexpr std::size_t max_path_bytes = 4096;
inline char staging_path[max_path_bytes] = {0};
/// Folder levels the handler removes: the staging folder and the folders in it (the demo's morph/).
constexpr int max_staging_depth = 2;

/// A directory entry as the getdents64 system call returns it (Linux).
struct Directory_entry64 {
  std::uint64_t inode;
  std::int64_t offset;
  unsigned short length;
  unsigned char type;
  char name[1];
};

/// Removes the files and folders inside the folder open as `dirfd` (and closes it), `depth` levels deep at most,
/// with async-signal-safe calls only: the getdents64 system call into a buffer on the stack, unlinkat, openat,
/// lseek, close. (opendir and readdir allocate: a signal that interrupts a malloc of the main computation would
/// deadlock in them.) Entries are read again from the start until a pass removes nothing, as removing entries
/// while reading may skip some.
inline void remove_contents(int dirfd, int depth) {
  alignas(8) char buffer[4096];
  for (int pass = 0; pass < 8; ++pass) {
    if (lseek(dirfd, 0, SEEK_SET) != 0) break;
    bool removed = false;
    for (;;) {
      const long n = syscall(SYS_getdents64, dirfd, buffer, sizeof buffer);
      if (n <= 0) break;
      for (long at = 0; at < n;) {
        const auto* e = reinterpret_cast<const Directory_entry64*>(buffer + at);
        at += e->length;
        const char* name = e->name;
        if (std::strcmp(name, ".") == 0 || std::strcmp(name, "..") == 0) continue;
        if (unlinkat(dirfd, name, 0) == 0) {
          removed = true;
          continue;
        }
        if (depth > 1) {
          const int sub = openat(dirfd, name, O_RDONLY | O_DIRECTORY);
          if (sub >= 0) remove_contents(sub, depth - 1);
          if (unlinkat(dirfd, name, AT_REMOVEDIR) == 0) removed = true;
        }
      }
    }
    if (!removed) break;
  }
  close(dirfd);
}

/// On SIGINT, SIGTERM or SIGHUP: removes the staging folder, then dies of the same signal.
extern "C" inline void remove_staging_and_die(int sig) {
  if (staging_path[0]) {
    const int fd = open(staging_path, O_RDONLY | O_DIRECTORY);
    if (fd >= 0) remove_contents(fd, max_staging_depth);
    rmdir(staging_path);
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

} // namespace output_folder_detail

/// The output folder of one result (see the file comment). Not copyable; one at a time per process.
class Output_folder {
public:
  /// Checks `dir` (a folder that can be written, or that can be created: then it is) and makes the staging
  /// folder. \throws Error (exit code 1) naming `dir` and the problem.
  explicit Output_folder(const std::string& dir) : dir_(normalized(dir)) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const std::string shown = dir;
    if (fs::exists(dir_, ec) && !fs::is_directory(dir_, ec))
      throw Error(shown + ": cannot write the results there: it exists and is not a folder");
    if (!fs::exists(dir_, ec)) {
      fs::create_directories(dir_, ec);
      if (ec) throw Error(shown + ": cannot create the output folder: " + ec.message());
    }
    if (access(dir_.c_str(), W_OK | X_OK) != 0)
      throw Error(shown + ": cannot write into the output folder: " + std::strerror(errno));
    // Beside DIR where its parent can be written (then a new or empty DIR is replaced in one rename).
    const fs::path parent = dir_.parent_path();
    beside_ = access(parent.c_str(), W_OK | X_OK) == 0;
    const fs::path where = beside_ ? parent : dir_;
    const std::string prefix = (beside_ ? "." + dir_.filename().string() : std::string()) + ".crossparam-";
    remove_stale(where, prefix);
    staging_ = where / (prefix + std::to_string(getpid()));
    fs::remove_all(staging_, ec);
    if (!fs::create_directory(staging_, ec) || ec)
      throw Error(shown + ": cannot create a staging folder for the results: " + ec.message());
    const std::string s = staging_.string();
    if (s.size() < output_folder_detail::max_path_bytes) {
      std::memcpy(output_folder_detail::staging_path, s.c_str(), s.size() + 1);
      for (int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, output_folder_detail::remove_staging_and_die);
    }
    // A file-size limit (ulimit -f) makes a write fail (EFBIG), reported as a write error, instead of killing
    // the process before it can clean up.
    std::signal(SIGXFSZ, SIG_IGN);
  }

  Output_folder(const Output_folder&) = delete;
  Output_folder& operator=(const Output_folder&) = delete;

  /// Removes the staging folder unless the result was committed.
  ~Output_folder() {
    output_folder_detail::staging_path[0] = 0;
    std::error_code ec;
    if (!committed_) std::filesystem::remove_all(staging_, ec);
  }

  /// The folder to write the files into.
  std::string staging() const { return staging_.string(); }

  /// Moves the complete result into the output folder. \throws Error if a rename fails.
  void commit() {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (beside_ && fs::is_empty(dir_, ec) && !ec) {
      fs::rename(staging_, dir_, ec); // replaces the empty folder: all files appear at once
      if (!ec) {
        committed_ = true;
        output_folder_detail::staging_path[0] = 0;
        return;
      }
    }
    move_into(staging_, dir_);
    fs::remove_all(staging_, ec);
    committed_ = true;
    output_folder_detail::staging_path[0] = 0;
  }

private:
  static std::filesystem::path normalized(const std::string& dir) {
    namespace fs = std::filesystem;
    fs::path p = fs::absolute(fs::path(dir)).lexically_normal();
    if (p.filename().empty() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();
    return p;
  }

  /// Removes the staging folders "<prefix><pid>" in `where` whose process no longer runs.
  static void remove_stale(const std::filesystem::path& where, const std::string& prefix) {
    namespace fs = std::filesystem;
    std::error_code ec;
    for (fs::directory_iterator it(where, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (name.compare(0, prefix.size(), prefix) != 0 || name.size() == prefix.size()) continue;
      const std::string digits = name.substr(prefix.size());
      if (digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 9) continue;
      const pid_t pid = pid_t(std::stol(digits));
      std::error_code ignored;
      if (pid != getpid() && kill(pid, 0) != 0 && errno == ESRCH) fs::remove_all(it->path(), ignored);
    }
  }

  /// Renames every entry of `from` into `to`; a folder that exists in both is merged.
  static void move_into(const std::filesystem::path& from, const std::filesystem::path& to) {
    namespace fs = std::filesystem;
    for (const fs::directory_entry& e : fs::directory_iterator(from)) {
      const fs::path dest = to / e.path().filename();
      std::error_code ec;
      if (e.is_directory() && fs::is_directory(dest, ec)) {
        move_into(e.path(), dest);
        continue;
      }
      fs::rename(e.path(), dest, ec);
      if (ec) throw Error(dest.string() + ": cannot move the result into place: " + ec.message());
    }
  }

  std::filesystem::path dir_, staging_;
  bool beside_ = false, committed_ = false;
};

} // namespace cli
} // namespace crossparam

#endif // CROSSPARAM_CLI_OUTPUT_FOLDER_H

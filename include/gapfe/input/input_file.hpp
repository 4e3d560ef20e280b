#pragma once
// Reading an input (a deck, a scene file, a mesh) whole: standard input, read once ("-", /dev/stdin), or a
// regular file. Anything else is refused before it is read: a directory, a device (/dev/zero would be read
// until memory runs out), a FIFO (opened without waiting for a writer, so it cannot block the run).
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

#include "gapfe/core/error.hpp"

namespace gapfe {

/// Whether `path` names this process's standard input.
inline bool is_standard_input(const std::string& path) {
  return path == "-" || path == "/dev/stdin" || path == "/dev/fd/0" || path == "/proc/self/fd/0";
}

/// The whole text of input `path`; `what` names it in errors ("deck", "scene file", "mesh").
inline std::string read_input(const std::string& path, const std::string& what) {
  const bool standard = is_standard_input(path);
  const int fd        = standard ? STDIN_FILENO : ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw FileError("cannot open the " + what + " '" + path + "': " + std::strerror(errno));
  struct Closer {  // the descriptor is closed on every path, a bad_alloc of a huge file's text included
    int fd;
    bool own;
    ~Closer() {
      if (own) ::close(fd);
    }
  } closer{fd, !standard};
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    throw FileError("cannot read the " + what + " '" + path + "': " + std::strerror(errno));
  }
  if (!standard && !S_ISREG(st.st_mode)) {
    const char* kind = S_ISDIR(st.st_mode)                          ? "a folder"
                       : S_ISFIFO(st.st_mode)                       ? "a FIFO"
                       : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device"
                                                                    : "not a regular file";
    throw FileError("the " + what + " '" + path + "' is " + kind +
                    ": gapfe reads regular files (and standard input, as '-')");
  }
  if (!standard) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string text;
  if (S_ISREG(st.st_mode)) text.reserve(static_cast<std::size_t>(st.st_size));
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      throw FileError("cannot read the " + what + " '" + path + "': " + std::strerror(errno));
    }
    text.append(buffer, static_cast<std::size_t>(n));
  }
  return text;
}

}  // namespace gapfe

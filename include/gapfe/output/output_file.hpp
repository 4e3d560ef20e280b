#pragma once
// Writing result files so that they cannot corrupt or mislead (POSIX: open, write, rename):
//
//   OutputFile             a table written in appended rows (a CSV file's, one increment at a time):
//                          created new (truncated), never through a symbolic link (O_NOFOLLOW: a planted
//                          `nodes.csv -> elsewhere` is refused, not followed), every write() checked and
//                          repeated until complete, close() checked.
//   write_file_atomically  a file written whole (a VTU file, a picture): into a temporary created
//                          exclusively beside it (mkstemp: O_EXCL, a name no one can predict), completed
//                          and closed, then renamed over the path (which replaces a link, not its
//                          target); on any failure the temporary is removed and nothing else changes.
//   PvdFile                ParaView's collection, one DataSet per increment, whole XML at every moment.
//
// A run killed at any moment (SIGKILL included) leaves whole rows and a whole collection. Linux stops a
// write() to a regular file between pages when the process is killed (generic_perform_write checks for a
// fatal signal before each page it copies), so a write is all or nothing within one page and can be cut
// only at a multiple of the page size. Hence (kPage = 4096, which every page size is a multiple of):
//   - OutputFile never lets a data row straddle a multiple of kPage: the row before is padded with
//     spaces (after its last field: numbers read the same) so that the next row starts there, and each
//     append holds back its last newline (written before the next row, or by close()), so the padding
//     can always go before it. About 1 % more bytes; a killed run's table ends in a whole row.
//   - PvdFile keeps room (spaces) between its last DataSet and the closing tags, and writes each new
//     DataSet into the room within one page (pwrite, all or nothing); when the room runs out the file
//     is rewritten whole (write_file_atomically) with room as large as its entries, so the rewrites cost
//     a constant per increment on average; close() rewrites it compact.
//
// Every failure is a FileError naming the path and the system's reason (the command's exit code 3).
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <string_view>
#include <sys/stat.h>
#include <unistd.h>

#include "gapfe/core/error.hpp"

namespace gapfe {

namespace detail {

/// A number as the text outputs write it: the shortest text that reads back to the same double (to_chars).
inline void append_number(std::string& s, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}
inline void append_number(std::string& s, long long v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

inline std::string system_reason() {
  return std::strerror(errno);
}

/// Write all of `text` to `fd` at its position (or at `offset`, when >= 0), repeating short writes.
inline bool write_all(int fd, std::string_view text, off_t offset = -1) {
  while (!text.empty()) {
    const ssize_t n =
        offset >= 0 ? ::pwrite(fd, text.data(), text.size(), offset) : ::write(fd, text.data(), text.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    text.remove_prefix(static_cast<std::size_t>(n));
    if (offset >= 0) offset += n;
  }
  return true;
}

}  // namespace detail

/// A result file written in appended pieces (see the top).
class OutputFile {
 public:
  OutputFile() = default;
  explicit OutputFile(std::string path) : path_(std::move(path)) {
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd_ < 0)
      throw FileError("cannot write " + path_ + ": " + detail::system_reason() +
                      (errno == ELOOP ? " (it is a symbolic link; gapfe does not write through links)" : ""));
  }
  OutputFile(const OutputFile&)            = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  OutputFile(OutputFile&& o) noexcept { *this = std::move(o); }
  OutputFile& operator=(OutputFile&& o) noexcept {
    if (this != &o) {
      if (fd_ >= 0) ::close(fd_);
      fd_ = o.fd_, path_ = std::move(o.path_), size_ = o.size_, rows_ = o.rows_, held_ = o.held_;
      o.fd_ = -1;
    }
    return *this;
  }
  ~OutputFile() {
    if (fd_ >= 0) ::close(fd_);
  }

  bool is_open() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }

  /// Append whole rows: `text` is rows, each ending with a newline (see the top: row starts kept off page
  /// boundaries, the last newline held back).
  void append(std::string_view text) {
    if (fd_ < 0 || text.empty())
      return;  // a file this process does not write (a partitioned run's other ranks)
    piece_.clear();
    for (std::size_t at = 0; at < text.size();) {
      const std::size_t end = std::min(text.find('\n', at), text.size());
      const std::size_t row = end - at, start = size_ + piece_.size() + (held_ ? 1 : 0);
      const std::size_t boundary = (start / kPage + 1) * kPage;
      // A data row that would straddle a boundary starts on it instead (never the header, whose names
      // would take the padding, nor a row longer than a page).
      if (held_ && rows_ > 1 && start % kPage != 0 && start + row > boundary && row <= kPage)
        piece_.append(boundary - start, ' ');
      if (held_) piece_ += '\n';
      piece_.append(text.substr(at, row));
      held_ = true, ++rows_, at = end + 1;
    }
    write_piece();
  }
  /// Close, checking what the system reports then (a delayed write error).
  void close() {
    if (fd_ < 0) return;
    if (held_) piece_.assign(1, '\n'), held_ = false, write_piece();
    const int fd = fd_;
    fd_          = -1;
    if (::close(fd) != 0) throw FileError("error while closing " + path_ + ": " + detail::system_reason());
  }

  static constexpr std::size_t kPage = 4096;

 private:
  void write_piece() {
    if (!detail::write_all(fd_, piece_))
      throw FileError("error while writing " + path_ + ": " + detail::system_reason());
    size_ += piece_.size();
  }

  int fd_ = -1;
  std::string path_;
  std::size_t size_ = 0;      ///< bytes in the file
  long long rows_   = 0;      ///< rows written (the first is the header)
  bool held_        = false;  ///< the last row's newline is still to be written
  std::string piece_;         ///< the bytes of one append, as written
};

namespace detail {

/// Write a file to `path` whole from pieces: produce(put) calls put(std::string_view) with the file's
/// bytes in order (a VTU file's arrays one by one, never all in memory at once). Into a temporary created
/// exclusively beside it, completed and closed, then renamed over the path; the temporary is removed on any
/// failure, the producer's exceptions included (see the top).
template <class Produce>
void write_file_atomically_from(const std::string& path, Produce&& produce) {
  const std::size_t slash = path.rfind('/');
  std::string temporary   = (slash == std::string::npos ? std::string() : path.substr(0, slash + 1)) + "." +
                          path.substr(slash == std::string::npos ? 0 : slash + 1) + ".gapfe-XXXXXX";
  const int fd = ::mkstemp(temporary.data());
  if (fd < 0) throw FileError("cannot write " + path + ": " + system_reason());
  const mode_t mask = ::umask(0);  // mkstemp makes 0600; the file gets what open(0666) would give
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  bool ok = true;
  std::string fault;
  try {
    produce([&](std::string_view piece) {
      if (ok && !write_all(fd, piece)) ok = false, fault = system_reason();
    });
  } catch (...) {
    ::close(fd);
    ::unlink(temporary.c_str());
    throw;
  }
  if (::close(fd) != 0 && ok) ok = false, fault = system_reason();
  if (ok && ::rename(temporary.c_str(), path.c_str()) != 0) ok = false, fault = system_reason();
  if (!ok) {
    ::unlink(temporary.c_str());
    throw FileError("cannot write " + path + ": " + fault);
  }
}

/// Write `text` to `path` whole (write_file_atomically_from, in one piece).
inline void write_file_atomically(const std::string& path, std::string_view text) {
  write_file_atomically_from(path, [&](const auto& put) { put(text); });
}

}  // namespace detail

/// ParaView's collection of a run's VTU files, whole XML at every moment (see the top).
class PvdFile {
 public:
  PvdFile() = default;
  explicit PvdFile(std::string path) : path_(std::move(path)) { rewrite(); }
  PvdFile(const PvdFile&)            = delete;
  PvdFile& operator=(const PvdFile&) = delete;
  PvdFile(PvdFile&& o) noexcept
      : path_(std::move(o.path_)),
        entries_(std::move(o.entries_)),
        fd_(o.fd_),
        end_(o.end_),
        tail_at_(o.tail_at_) {
    o.fd_ = -1;
  }
  ~PvdFile() {
    if (fd_ >= 0) ::close(fd_);
  }

  /// One more DataSet: `time` (the command's t), `file` relative to the collection's folder.
  void add(double time, const std::string& file) {
    std::string entry = "<DataSet timestep=\"";
    detail::append_number(entry, time);
    entry += "\" file=\"" + file + "\"/>\n";
    entries_ += entry;
    std::size_t at = end_;  // within one page: from the next page's start if it would cross one
    if (at / OutputFile::kPage != (at + entry.size() - 1) / OutputFile::kPage)
      at = (at / OutputFile::kPage + 1) * OutputFile::kPage;
    if (at + entry.size() > tail_at_ || entry.size() > OutputFile::kPage) return rewrite();
    if (!detail::write_all(fd_, entry, static_cast<off_t>(at)))
      throw FileError("error while writing " + path_ + ": " + detail::system_reason());
    end_ = at + entry.size();
  }
  /// The collection compact (no room), closed.
  void close() {
    if (fd_ < 0) return;
    ::close(fd_);
    fd_ = -1;
    detail::write_file_atomically(path_, std::string(kHead) + entries_ + std::string(kTail));
  }

 private:
  /// The whole file: its entries, then room for as many bytes again (at least 16 KiB), then the tail.
  void rewrite() {
    const std::size_t room = std::max<std::size_t>(16384, entries_.size());
    detail::write_file_atomically(
        path_, std::string(kHead) + entries_ + std::string(room, ' ') + "\n" + std::string(kTail));
    if (fd_ >= 0) ::close(fd_);
    fd_ = ::open(path_.c_str(), O_WRONLY | O_NOFOLLOW | O_CLOEXEC);
    if (fd_ < 0) throw FileError("cannot write " + path_ + ": " + detail::system_reason());
    end_     = kHead.size() + entries_.size();
    tail_at_ = end_ + room;
  }

  static constexpr std::string_view kHead =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  static constexpr std::string_view kTail = "</Collection>\n</VTKFile>\n";
  std::string path_, entries_;  ///< entries_: every DataSet so far, compact
  int fd_              = -1;
  std::size_t end_     = 0;  ///< where the entries written in place end
  std::size_t tail_at_ = 0;  ///< where the room ends (the closing tags begin)
};

}  // namespace gapfe

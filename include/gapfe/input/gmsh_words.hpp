#pragma once
// The words of a Gmsh MSH file (input/gmsh_reader.hpp reads them): the element types gapfe keeps, and a
// tokenizer that knows the line it is on, so that every error names the line and the section.
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <string>
#include <string_view>

#include "gapfe/core/error.hpp"

namespace gapfe {

namespace detail {

/// Gmsh's element types that gapfe reads, with their node counts (0: skipped, -1: not supported).
inline int gmsh_node_count(int type) {
  switch (type) {
    case 1:
      return 2;  // 2-node line
    case 8:
      return 3;  // 3-node line
    case 2:
      return 3;  // 3-node triangle
    case 9:
      return 6;  // 6-node triangle
    case 3:
      return 4;  // 4-node quadrangle
    case 16:
      return 8;  // 8-node quadrangle
    case 10:
      return 9;  // 9-node quadrangle: read, its centre then dropped (GmshReader::add_element)
    case 15:
      return 0;  // point: skipped
    default:
      return -1;
  }
}
/// The corners of a Gmsh cell type: 3 for triangles (2, 9), else 4 (quadrangles 3, 16, 10).
inline int gmsh_corners(int type) {
  return type == 2 || type == 9 ? 3 : 4;
}
inline int gmsh_dimension(int type) {
  return type == 1 || type == 8 ? 1 : type == 15 ? 0 : 2;
}

/// The file as whitespace-separated words with their line numbers, read in order.
class GmshWords {
 public:
  explicit GmshWords(std::string_view text) : text_(text) {}

  /// The next word (never empty, never quoted: numbers and section names); InputError naming `what` and the
  /// section when the file ends.
  std::string_view word(const char* what) {
    skip_space();
    if (at_ >= text_.size())
      throw InputError("the file ends in " + section_ + " (line " + std::to_string(line_) + ") where " +
                       what + " was expected: truncated?");
    if (text_[at_] == '"') fail(std::string("a quoted word where ") + what + " was expected");
    const std::size_t start = at_;
    while (at_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
    return text_.substr(start, at_ - start);
  }
  /// A physical group's name: a quoted word, spaces included, not empty.
  std::string_view name(const char* what) {
    skip_space();
    if (at_ >= text_.size() || text_[at_] != '"') return word(what);
    const std::size_t start = at_, end = text_.find('"', at_ + 1);
    if (end == std::string_view::npos || text_.substr(at_, end - at_).find('\n') != std::string_view::npos)
      fail(std::string("an unterminated quoted name where ") + what + " was expected");
    if (end == start + 1) fail(std::string("an empty name (\"\") where ") + what + " was expected");
    at_ = end + 1;
    return text_.substr(start + 1, end - start - 1);
  }
  long integer(const char* what) {
    const std::string_view w = word(what);
    long v                   = 0;
    std::size_t k            = w[0] == '-' || w[0] == '+' ? 1 : 0;
    if (k == w.size()) fail(std::string(what) + ": expected an integer, found '" + std::string(w) + "'");
    for (; k < w.size(); ++k) {
      if (w[k] < '0' || w[k] > '9' || v > 100'000'000'000L)
        fail(std::string(what) + ": expected an integer, found '" + std::string(w) + "'");
      v = v * 10 + (w[k] - '0');
    }
    return w[0] == '-' ? -v : v;
  }
  /// An integer in [lo, hi].
  int count(const char* what, long lo, long hi) {
    const long v = integer(what);
    if (v < lo || v > hi)
      fail(std::string(what) + " = " + std::to_string(v) + ": expected " + std::to_string(lo) + " to " +
           std::to_string(hi));
    return static_cast<int>(v);
  }
  double real(const char* what) {
    const std::string w(word(what));
    char* end      = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (end != w.c_str() + w.size() || !std::isfinite(v))
      fail(std::string(what) + ": expected a finite number, found '" + w + "'");
    return v;
  }
  /// Skip to the line after `$End<name>`. A skipped section may hold quoted strings, spaces included
  /// ($NodeData's field name "temperature", as meshio and Gmsh write it).
  void skip_section(const std::string& name) {
    const std::string end = "$End" + name;
    for (;;) {
      skip_space();
      if (at_ < text_.size() && text_[at_] == '"') {
        const std::size_t close = text_.find('"', at_ + 1);
        if (close == std::string_view::npos) fail("an unterminated quoted string before " + end);
        for (; at_ <= close; ++at_) line_ += text_[at_] == '\n';
        continue;
      }
      if (word(end.c_str()) == end) return;
    }
  }
  void expect(const std::string& token) {
    const std::string_view w = word(token.c_str());
    if (w != token) fail("expected " + token + ", found '" + std::string(w) + "'");
  }
  bool done() {
    skip_space();
    return at_ >= text_.size();
  }
  int line() const { return line_; }
  void enter(const std::string& section) { section_ = section; }
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError("line " + std::to_string(line_) + " (" + section_ + "): " + why);
  }

 private:
  void skip_space() {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) {
      if (text_[at_] == '\n') ++line_;
      ++at_;
    }
  }
  std::string_view text_;
  std::size_t at_      = 0;
  int line_            = 1;
  std::string section_ = "the file's start";
};

}  // namespace detail

}  // namespace gapfe

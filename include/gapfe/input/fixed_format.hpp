#pragma once
// Column-exact reading of one card image with Fortran formatted-input semantics (the seed's decks,
// Appendix A):
//  * a field is the columns [first, last] (1-based, inclusive); columns past the end of the line read
//    as blanks (Fortran's PAD = 'YES'); an all-blank field reads as zero;
//  * blanks inside a field are ignored (BLANK = 'NULL', the Fortran 77 default; "1 0" reads as 10);
//  * Iw: an optional sign and digits;
//  * Fw.d and Ew.d: an optional sign, digits with an optional decimal point, and an optional exponent
//    (E or D with a signed integer, or a bare sign: "1.5-3" is 1.5e-3). Without a written decimal
//    point the last d digits of the mantissa are the fraction: "    1000" in F8.3 reads as 1.000.
// Anything else (letters, two decimal points, a tab, a value beyond int range, non-finite) is an
// InputError naming the card, the deck line, the columns, the field and what was expected.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>
#include <string_view>

#include "gapfe/core/error.hpp"

namespace gapfe {

/// One card image: its text, its 1-based line in the deck, and what the deck expected there, as the
/// seed names it ("DATA NO. 5 (boundary condition card 2)").
class CardImage {
 public:
  CardImage(std::string_view text, int line, std::string card)
      : text_(text), line_(line), card_(std::move(card)) {
    while (!text_.empty() && (text_.back() == '\r' || text_.back() == '\n')) text_.remove_suffix(1);
    if (const auto tab = text_.find('\t'); tab != std::string_view::npos)
      throw InputError(where() + ", column " + std::to_string(tab + 1) +
                       ": tab character; cards are column-exact, expand tabs to spaces");
  }

  int line() const { return line_; }
  const std::string& card() const { return card_; }
  std::string_view text() const { return text_; }
  std::string where() const { return card_ + ", line " + std::to_string(line_); }

  /// Raw text of columns [first, last] (padded with blanks).
  std::string field(int first, int last) const {
    std::string s;
    for (int c = first; c <= last; ++c) s += c <= static_cast<int>(text_.size()) ? text_[c - 1] : ' ';
    return s;
  }
  bool blank(int first, int last) const {
    return field(first, last).find_first_not_of(' ') == std::string::npos;
  }

  /// Iw in columns [first, last].
  int integer(int first, int last, const char* name) const {
    const std::string s = squeeze(first, last);
    if (s.empty()) return 0;
    std::size_t k = (s[0] == '+' || s[0] == '-') ? 1 : 0;
    if (k == s.size()) fail(first, last, name, "an integer");
    long long v = 0;
    for (; k < s.size(); ++k) {
      if (s[k] < '0' || s[k] > '9') fail(first, last, name, "an integer");
      v = v * 10 + (s[k] - '0');
      if (v > 2147483647LL) fail(first, last, name, "an integer within +-2147483647");
    }
    return static_cast<int>(s[0] == '-' ? -v : v);
  }

  /// Fw.d (or Ew.d: the same rules on input) in columns [first, last]; `decimals` is d.
  double real(int first, int last, int decimals, const char* name) const {
    const std::string s = squeeze(first, last);
    if (s.empty()) return 0.0;
    std::size_t k    = 0;
    std::string mant = (s[0] == '-') ? "-" : "";
    if (s[0] == '+' || s[0] == '-') ++k;
    bool point = false, digits = false;
    for (; k < s.size(); ++k) {
      const char c = s[k];
      if (c >= '0' && c <= '9') {
        mant += c, digits = true;
      } else if (c == '.' && !point) {
        mant += c, point = true;
      } else {
        break;
      }
    }
    if (!digits) fail(first, last, name, "a number");
    long exponent = 0;
    if (k < s.size()) {  // exponent: E/D then optional sign, or a bare sign
      if (s[k] == 'E' || s[k] == 'e' || s[k] == 'D' || s[k] == 'd') ++k;
      std::size_t e = k;
      if (e < s.size() && (s[e] == '+' || s[e] == '-')) ++e;
      if (e == s.size()) fail(first, last, name, "a number (exponent without digits)");
      for (std::size_t q = e; q < s.size(); ++q)
        if (s[q] < '0' || s[q] > '9') fail(first, last, name, "a number");
      if (s.size() - e > 4) fail(first, last, name, "a number with an exponent below 10000");
      exponent = std::strtol(s.c_str() + k, nullptr, 10);
    }
    if (!point) exponent -= decimals;  // implied decimal point
    errno          = 0;
    const double v = std::strtod((mant + "e" + std::to_string(exponent)).c_str(), nullptr);
    if (!std::isfinite(v) || errno == ERANGE) {
      if (std::isfinite(v) && std::abs(v) < 1.0) return 0.0;  // underflow: a harmless zero
      fail(first, last, name, "a finite number");
    }
    return v;
  }

  [[noreturn]] void fail(int first, int last, const std::string& name, const std::string& expected) const {
    throw InputError(where() + ", columns " + std::to_string(first) + "-" + std::to_string(last) + " (" +
                     name + "): expected " + expected + ", found '" + field(first, last) + "'");
  }
  /// An error about a value that reads but is not acceptable.
  [[noreturn]] void reject(int first, int last, const std::string& name, const std::string& why) const {
    throw InputError(where() + ", columns " + std::to_string(first) + "-" + std::to_string(last) + " (" +
                     name + "): " + why);
  }

 private:
  std::string squeeze(int first, int last) const {
    std::string s;
    for (const char c : field(first, last))
      if (c != ' ') s += c;
    return s;
  }

  std::string_view text_;
  int line_;
  std::string card_;
};

}  // namespace gapfe

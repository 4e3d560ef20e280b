#pragma once
// Text from an input (a deck's title, a group's name, a file's path) shown to a person: on the terminal, in
// a log, in an SVG picture. Such text may hold anything: an escape sequence that would drive the terminal,
// a control character or a byte that is not UTF-8, either of which makes an SVG file invalid XML (XML 1.0
// allows no control character but tab, newline and carriage return, not even as a reference). Every such
// byte is shown as the four characters \xNN, so the reader sees what the input holds and no output breaks.
#include <cstddef>
#include <string>
#include <string_view>

namespace gapfe::detail {

/// The length of the UTF-8 character at s[k] that may be shown as it is (a valid sequence, not a C0 or C1
/// control, DEL, U+FFFE or U+FFFF), or 0 when s[k] is to be escaped. Tab and newline pass when `lines`.
inline std::size_t showable_length(std::string_view s, std::size_t k, bool lines) {
  const auto byte  = [&](std::size_t i) { return i < s.size() ? static_cast<unsigned char>(s[i]) : 0u; };
  const unsigned c = byte(k);
  if (c == '\t' || c == '\n') return lines ? 1 : 0;
  if (c < 0x20 || c == 0x7f) return 0;
  if (c < 0x80) return 1;
  const auto in     = [](unsigned b, unsigned lo, unsigned hi) { return b >= lo && b <= hi; };
  const unsigned b1 = byte(k + 1), b2 = byte(k + 2), b3 = byte(k + 3);
  if (in(c, 0xc2, 0xdf)) return in(b1, 0x80, 0xbf) && !(c == 0xc2 && b1 < 0xa0) ? 2 : 0;  // C1 controls
  if (in(c, 0xe0, 0xef)) {
    const bool second  = c == 0xe0 ? in(b1, 0xa0, 0xbf) : c == 0xed ? in(b1, 0x80, 0x9f) : in(b1, 0x80, 0xbf);
    const bool nonchar = c == 0xef && b1 == 0xbf && (b2 == 0xbe || b2 == 0xbf);  // U+FFFE, U+FFFF
    return second && in(b2, 0x80, 0xbf) && !nonchar ? 3 : 0;
  }
  if (in(c, 0xf0, 0xf4)) {
    const bool second = c == 0xf0 ? in(b1, 0x90, 0xbf) : c == 0xf4 ? in(b1, 0x80, 0x8f) : in(b1, 0x80, 0xbf);
    return second && in(b2, 0x80, 0xbf) && in(b3, 0x80, 0xbf) ? 4 : 0;
  }
  return 0;
}

/// `s` with every byte that showable_length refuses written as \xNN (tab and newline kept when `lines`).
inline std::string visible_text(std::string_view s, bool lines = false) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t k = 0; k < s.size();) {
    if (const std::size_t n = showable_length(s, k, lines)) {
      out.append(s.substr(k, n));
      k += n;
      continue;
    }
    static constexpr char kHex[] = "0123456789abcdef";
    const auto c                 = static_cast<unsigned char>(s[k++]);
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 15];
  }
  return out;
}

}  // namespace gapfe::detail

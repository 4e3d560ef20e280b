#pragma once
// Building card images column by column in tests (the seed's decks are column-exact).
#include <cstdio>
#include <string>
#include <vector>

namespace gapfe::test {

/// One card image; each field is right-justified in its columns [first, last] (1-based).
class Card {
 public:
  Card& f(int first, int last, const std::string& text) {
    const int width = last - first + 1;
    if (static_cast<int>(line_.size()) < last) line_.resize(static_cast<std::size_t>(last), ' ');
    const std::string t = text.size() >= static_cast<std::size_t>(width)
                              ? text.substr(0, width)
                              : std::string(width - text.size(), ' ') + text;
    line_.replace(static_cast<std::size_t>(first - 1), static_cast<std::size_t>(width), t);
    return *this;
  }
  Card& i(int first, int last, int v) { return f(first, last, std::to_string(v)); }
  std::string str() const { return line_; }

 private:
  std::string line_;
};

/// Data 4: two points and a type (3(2I3, 2F8.3), I5).
inline std::string segment(int i1, int j1, const char* r1, const char* z1, int i2, int j2, const char* r2,
                           const char* z2, int type = 1) {
  return Card()
      .i(1, 3, i1)
      .i(4, 6, j1)
      .f(7, 14, r1)
      .f(15, 22, z1)
      .i(23, 25, i2)
      .i(26, 28, j2)
      .f(29, 36, r2)
      .f(37, 44, z2)
      .i(67, 71, type)
      .str();
}

/// Data 10b, the first property card of an isotropic steel row: T, E_N, E_S, E_T (200000) and the three
/// Poisson's ratios (0.3), in F10.0 fields.
inline std::string steel_first_property_card(const char* temperature = "0.") {
  return Card()
      .f(1, 10, temperature)
      .f(11, 20, "200000.")
      .f(21, 30, "200000.")
      .f(31, 40, "200000.")
      .f(41, 50, ".3")
      .f(51, 60, ".3")
      .f(61, 70, ".3")
      .str();
}

/// The Lame tube of the example deck (thick_tube.deck) on any grid: a = 100 < r < b = 200, plane strain
/// (u_z = 0 on both ends), pressure p on the bore as NUMPC = nj - 1 pressure cards, E = 200000, nu = 0.3;
/// node(I, J) = (J - 1) ni + I. `wide`: `$ fields = wide` with the widened line segment cards
/// 3(2I5, 2F12.3), I5 and pressure cards 2I10, F10.0 (input/deck_lines.hpp, CardLayout); otherwise the
/// seed's 3(2I3, 2F8.3), I5 and 2I5, F10.0, whose fields cut an index above 999 or a node above 99,999
/// short, as a card punch would.
inline std::string lame_tube_deck(int ni, int nj, bool wide, double p = 100) {
  const int iw = wide ? 5 : 3, cw = wide ? 12 : 8, nw = wide ? 10 : 5, pw = 2 * iw + 2 * cw;
  const double a = 100, b = 200, h = (b - a) * (nj - 1) / (ni - 1);
  const auto number = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3f", v);
    return std::string(text);
  };
  const auto segment_card = [&](int i1, int j1, double r1, double z1, int i2, int j2, double r2, double z2) {
    Card c;
    const int q[2][2]    = {{i1, j1}, {i2, j2}};
    const double x[2][2] = {{r1, z1}, {r2, z2}};
    for (int k = 0; k < 2; ++k) {
      const int o = pw * k;
      c.i(o + 1, o + iw, q[k][0]).i(o + iw + 1, o + 2 * iw, q[k][1]);
      c.f(o + 2 * iw + 1, o + 2 * iw + cw, number(x[k][0])).f(o + 2 * iw + cw + 1, o + pw, number(x[k][1]));
    }
    return c.i(3 * pw + 1, 3 * pw + 5, 1).str();
  };
  const auto node = [&](int i, int j) { return (j - 1) * ni + i; };
  std::string s   = "$ format = elastic\n";
  if (wide) s += "$ fields = wide\n";
  s += "LAME TUBE " + std::to_string(ni) + " X " + std::to_string(nj) + "\n";
  s += Card().i(1, 5, 1).i(11, 15, 1).i(16, 20, nj - 1).i(41, 45, 1).str() + "\n";
  s += Card().i(1, 5, ni).i(6, 10, nj).i(11, 15, 4).i(16, 20, 2).i(21, 25, 1).str() + "\n";
  s += segment_card(1, 1, a, 0, ni, 1, b, 0) + "\n" + segment_card(ni, 1, b, 0, ni, nj, b, h) + "\n";
  s += segment_card(ni, nj, b, h, 1, nj, a, h) + "\n" + segment_card(1, nj, a, h, 1, 1, a, 0) + "\n";
  s += Card().i(1, 5, 1).i(6, 10, ni).i(11, 15, 1).i(16, 20, 1).i(21, 30, 2).str() + "\n";
  s += Card().i(1, 5, 1).i(6, 10, ni).i(11, 15, nj).i(16, 20, nj).i(21, 30, 2).str() + "\n";
  s += Card().i(1, 5, 1).i(6, 10, 1).i(11, 15, ni).i(16, 20, 1).i(21, 25, nj).str() + "\n";
  s += Card().i(1, 5, 1).i(6, 10, 1).str() + "\n";
  s += steel_first_property_card() + "\n";
  s += Card().f(1, 10, "76923.0769").f(11, 20, "76923.0769").f(21, 30, "76923.0769").str() + "\n";
  for (int j = 1; j < nj; ++j)  // from M = (1, J + 1) to N = (1, J): the element on the left (seed Data 13)
    s += Card()
             .i(1, nw, node(1, j + 1))
             .i(nw + 1, 2 * nw, node(1, j))
             .f(2 * nw + 1, 2 * nw + 10, number(p))
             .str() +
         "\n";
  return s;
}

/// A small valid elastic deck: a tube 1 < r < 2, 0 < z < 0.25 on a 5 x 3 grid (4 x 2 cells), u_z = 0 on
/// both ends, pressure 100 on the bore. Line indices: 0 `$`, 1 title, 2 control, 3 mesh control,
/// 4-7 segments, 8-9 BC, 10 block, 11 material id, 12-13 properties, 14-15 pressure cards.
/// Written with implied decimals where the test reads them ("    1000" in F8.3, "   70" in F5.0).
inline std::string tube_deck() {
  std::vector<std::string> l = {
      "$ format = elastic",
      "TUBE",
      Card().i(1, 5, 1).i(11, 15, 1).i(16, 20, 2).f(31, 35, "70").i(41, 45, 1).str(),
      Card().i(1, 5, 5).i(6, 10, 3).i(11, 15, 4).i(16, 20, 2).i(21, 25, 1).str(),
      segment(1, 1, "1000", "0", 5, 1, "2.0", "0."),
      segment(5, 1, "2.0", "0.", 5, 3, "2.0", "0.250"),
      segment(5, 3, "2.0", "0.250", 1, 3, "1.0", "0.250"),
      segment(1, 3, "1.0", "0.250", 1, 1, "1.0", "0."),
      Card().i(1, 5, 1).i(6, 10, 5).i(11, 15, 1).i(16, 20, 1).i(21, 30, 2).str(),
      Card().i(1, 5, 1).i(6, 10, 5).i(11, 15, 3).i(16, 20, 3).i(21, 30, 2).str(),
      Card()
          .i(1, 5, 1)
          .i(6, 10, 1)
          .i(11, 15, 5)
          .i(16, 20, 1)
          .i(21, 25, 3)
          .f(26, 35, "90.")
          .i(46, 50, 1)
          .i(51, 55, 2)
          .i(56, 60, 1)
          .str(),
      Card().i(1, 5, 1).i(6, 10, 1).f(11, 20, "7.85e-9").str(),
      steel_first_property_card(),
      Card()
          .f(1, 10, "80000.")
          .f(11, 20, "80000.")
          .f(21, 30, "80000.")
          .f(31, 40, "1.2e-5")
          .f(41, 50, "1.2e-5")
          .f(51, 60, "1.2e-5")
          .str(),
      Card().i(1, 5, 6).i(6, 10, 1).f(11, 20, "100.").str(),
      Card().i(1, 5, 11).i(6, 10, 6).f(11, 20, "100.").str(),
  };
  std::string s;
  for (const auto& x : l) s += x + "\n";
  return s;
}

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    out.push_back(text.substr(start, end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

inline std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& x : lines) s += x + "\n";
  return s;
}

}  // namespace gapfe::test

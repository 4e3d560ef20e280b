#pragma once
// An SVG picture of a meridian section (r to the right, z up), the canvas of every picture the command
// draws (mesh.svg, deformed.svg, the field and curve plots): 1000 px wide, the section fitted between the
// margins, the title wrapped onto as many lines as it needs at the top (a title never runs off the page:
// kTitleChar is a generous mean glyph width for sans-serif, so a wrapped line fits in any common font).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "gapfe/core/text.hpp"
#include "gapfe/core/types.hpp"
#include "gapfe/output/vtu_writer.hpp"

namespace gapfe::detail {

/// Text escaped for SVG/XML character data and attribute values; what XML cannot hold at all (a control
/// character, a byte that is not UTF-8) shown as \xNN (core/text.hpp), so the picture always parses.
inline std::string xml_text(const std::string& text) {
  const std::string s = visible_text(text);
  std::string out;
  out.reserve(s.size());
  for (const char c : s)
    out += c == '<'   ? std::string("&lt;")
           : c == '>' ? std::string("&gt;")
           : c == '&' ? std::string("&amp;")
           : c == '"' ? std::string("&quot;")
                      : std::string(1, c);
  return out;
}

/// The cell sides a picture keeps as the section's outline: those of one cell only (the boundary) and those
/// between cells of different materials (`material` per cell; empty: one material), as node pairs (smaller
/// node first). `sides_of(e, side)` calls side(a, b) for each side of cell e. deformed_svg.hpp's outline of a
/// large mesh and the field pictures' undeformed boundary (field_plot.hpp).
template <class SidesOf>
std::vector<std::array<int, 2>> outline_sides(std::size_t cells, const SidesOf& sides_of,
                                              const std::vector<int>& material) {
  struct Side {
    std::array<int, 2> nodes;
    int material;
    bool operator<(const Side& o) const { return nodes < o.nodes; }
  };
  std::vector<Side> sides;
  sides.reserve(4 * cells);
  for (std::size_t e = 0; e < cells; ++e)
    sides_of(e, [&](int a, int b) {
      sides.push_back({{std::min(a, b), std::max(a, b)}, material.empty() ? 0 : material[e]});
    });
  // In the order of their node pairs: bucketed by the smaller node (linear in the sides, where one sort of
  // them all took a tenth of a second at 1e6 cells), each bucket's few sorted.
  int top = -1;
  for (const Side& s : sides) top = std::max(top, s.nodes[1]);
  std::vector<std::size_t> start(static_cast<std::size_t>(top) + 2, 0);
  for (const Side& s : sides) ++start[static_cast<std::size_t>(s.nodes[0]) + 1];
  for (std::size_t n = 1; n < start.size(); ++n) start[n] += start[n - 1];
  {
    std::vector<Side> bucketed(sides.size());
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (const Side& s : sides) bucketed[next[static_cast<std::size_t>(s.nodes[0])]++] = s;
    sides.swap(bucketed);
  }
  for (std::size_t n = 0; n + 1 < start.size(); ++n)
    std::sort(sides.begin() + static_cast<std::ptrdiff_t>(start[n]),
              sides.begin() + static_cast<std::ptrdiff_t>(start[n + 1]));
  std::vector<std::array<int, 2>> out;
  for (std::size_t k = 0; k < sides.size();) {
    std::size_t end = k + 1;
    bool interface  = false;
    for (; end < sides.size() && sides[end].nodes == sides[k].nodes; ++end)
      interface = interface || sides[end].material != sides[k].material;
    if (end - k == 1 || interface) out.push_back(sides[k].nodes);
    k = end;
  }
  return out;
}

struct SvgCanvas {
  static constexpr double kTitleSize = 14, kTitleLine = 18;
  static constexpr double kTitleChar = 0.6;  ///< mean glyph width / font size, generous for sans-serif
  /// Space around the section [px]; `top` is below the title's lines.
  struct Margins {
    double left = 40, right = 40, top = 40, bottom = 40;
  };

  Vec2 lo, hi;
  double width = 1000.0, scale = 1.0, height = 0.0;
  Margins margin;
  std::vector<std::string> title_lines;
  std::string t;

  /// The section of `nodes` below `title`, with `extra_height` more room at the top (legends).
  SvgCanvas(const std::vector<Vec2>& nodes, const std::string& title, double extra_height = 30)
      : SvgCanvas(nodes, title, Margins{40, 40, 40 + extra_height, 40}) {}
  /// `min_height`: a flat section is centred in at least this height [px] (room for a colour bar).
  SvgCanvas(const std::vector<Vec2>& nodes, const std::string& title, Margins m, double min_height = 0)
      : margin(m) {
    title_lines = wrap(title, static_cast<std::size_t>((width - 20) / (kTitleChar * kTitleSize)));
    margin.top += kTitleLine * static_cast<double>(title_lines.size() - 1);
    lo = hi = nodes.front();
    for (const auto& x : nodes) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    scale  = (width - margin.left - margin.right) / std::max((hi - lo).maxCoeff(), 1e-300);
    height = (hi(1) - lo(1)) * scale + margin.top + margin.bottom;
    if (height < min_height)
      margin.top += 0.5 * (min_height - height), margin.bottom += 0.5 * (min_height - height),
          height = min_height;
    t += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"";
    num(width), t += "\" height=\"", num(height), t += "\" font-family=\"sans-serif\">\n";
    t += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    for (std::size_t k = 0; k < title_lines.size(); ++k)
      text(10, 20 + kTitleLine * static_cast<double>(k), kTitleSize, title_lines[k], "black", "start",
           "title");
  }

  /// `title` in lines of at most `columns` characters, broken at spaces (a longer word on its own line).
  static std::vector<std::string> wrap(const std::string& title, std::size_t columns) {
    std::vector<std::string> lines{""};
    std::size_t at = 0;
    while (at < title.size()) {
      const std::size_t end  = std::min(title.find(' ', at), title.size());
      const std::string word = title.substr(at, end - at);
      if (!lines.back().empty() && lines.back().size() + 1 + word.size() > columns) lines.emplace_back();
      lines.back() += (lines.back().empty() ? "" : " ") + word;
      at = end + 1;
    }
    return lines;
  }

  double extent() const { return (hi - lo).maxCoeff(); }
  void num(double v) { append_number(t, std::round(v * 100) / 100); }
  std::array<double, 2> px(const Vec2& x) const {
    return {margin.left + (x(0) - lo(0)) * scale, height - margin.bottom - (x(1) - lo(1)) * scale};
  }
  /// A closed polygon through `corners` points of `x`; `attributes` are added as they are (` class="cell"`).
  template <class Points>
  void polygon(const Points& x, int corners, const char* fill, const char* stroke, double stroke_width,
               const std::string& attributes = {}) {
    t += "<polygon points=\"";
    for (int k = 0; k < corners; ++k) {
      const auto p = px(x[k]);
      num(p[0]), t += ',', num(p[1]), t += ' ';
    }
    t += "\" fill=\"" + std::string(fill) + "\" stroke=\"" + stroke + "\" stroke-width=\"";
    num(stroke_width), t += "\"" + attributes + "/>\n";
  }
  void line(double x0, double y0, double x1, double y1, const char* stroke = "black",
            double stroke_width = 1) {
    t += "<line x1=\"", num(x0), t += "\" y1=\"", num(y0), t += "\" x2=\"", num(x1), t += "\" y2=\"", num(y1);
    t += "\" stroke=\"" + std::string(stroke) + "\" stroke-width=\"", num(stroke_width), t += "\"/>\n";
  }
  void text(double x, double y, double size, const std::string& what, const char* fill = "black",
            const char* anchor = "start", const char* css_class = nullptr, double rotate = 0) {
    t += "<text x=\"", num(x), t += "\" y=\"", num(y), t += "\" font-size=\"", num(size),
        t += "\" fill=\"" + std::string(fill) + "\" text-anchor=\"" + anchor + "\"";
    if (css_class) t += " class=\"" + std::string(css_class) + "\"";
    if (rotate != 0) t += " transform=\"rotate(", num(rotate), t += " ", num(x), t += " ", num(y), t += ")\"";
    t += ">" + xml_text(what) + "</text>\n";
  }
  /// The finished picture's text.
  std::string close() {
    t += "</svg>\n";
    return std::move(t);
  }
  void save(const std::string& path) { write_file_atomically(path, close()); }
};

}  // namespace gapfe::detail

#pragma once
// Pictures an analyst reads at a glance: the deformed section coloured by a field, with a colour
// bar, r and z axes in the run's units and the magnification stated (write_field_svg), and a curve of one
// history.csv column against another (write_curve_svg). Both are SVG through output/svg_canvas.hpp; the
// command also rasterizes them to PNG when rsvg-convert is installed.
//
// Fields (plot_field), from the arrays of a VTU file (output/vtu_writer.hpp, input/vtu_reader.hpp):
//   nodal   u (|u|, all components), u_r, u_z, u_t                                         [length]
//   cells   s_rr, s_zz, s_tt, s_rz, s_rt, s_zt, mises (von Mises, core/types.hpp)           [stress]
//           eqps (equivalent plastic strain) [-], gap_state (0 structural, -1 soft throughout, 1-4 the seed's
//           contact states), contact_force (the normal forces of a gap element's pairs) [force], material,
//           error_estimate (a cell's share of the relative energy-norm error, post/error_estimate.hpp) [-]
// A nodal field colours each cell with the mean of its corners; a cell field with the cell's centroid value.
// The colour map is viridis (perceptually uniform, readable in grey and by colour-blind readers): 17 of its
// 256 entries, linear between them (the table is matplotlib's, CC0).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/types.hpp"
#include "gapfe/input/vtu_reader.hpp"
#include "gapfe/output/svg_canvas.hpp"

namespace gapfe {

/// Unit names for labels: the deck option `units = LENGTH,FORCE,STRESS` (e.g. mm,N,MPa); generic words when
/// the deck does not say (gapfe never converts units: docs/theory.md 0).
struct PlotUnits {
  std::string length = "length", force = "force", stress = "stress";
};

/// A field's values on the nodes or the cells of a VTU file's mesh, and its label with its unit.
struct PlotField {
  std::string name, label;
  bool nodal = false;
  std::vector<double> values;
};

/// The names plot_field knows, in the order the help lists them.
inline const std::vector<std::string>& plot_field_names() {
  static const std::vector<std::string> names{
      "u",    "u_r",  "u_z",   "u_t",  "s_rr",      "s_zz",          "s_tt",     "s_rz",
      "s_rt", "s_zt", "mises", "eqps", "gap_state", "contact_force", "material", "error_estimate"};
  return names;
}

namespace detail {

inline std::string names_text() {
  std::string s;
  for (const auto& n : plot_field_names()) s += (s.empty() ? "" : ", ") + n;
  return s;
}

/// viridis(t), t in [0, 1], as "#rrggbb".
inline std::string viridis(double t) {
  static constexpr std::array<std::array<int, 3>, 17> kTable{{{0x44, 0x01, 0x54},
                                                              {0x48, 0x18, 0x6a},
                                                              {0x47, 0x2d, 0x7b},
                                                              {0x42, 0x40, 0x86},
                                                              {0x3b, 0x52, 0x8b},
                                                              {0x33, 0x63, 0x8d},
                                                              {0x2c, 0x72, 0x8e},
                                                              {0x26, 0x82, 0x8e},
                                                              {0x21, 0x91, 0x8c},
                                                              {0x1f, 0xa0, 0x88},
                                                              {0x28, 0xae, 0x80},
                                                              {0x3f, 0xbc, 0x73},
                                                              {0x5e, 0xc9, 0x62},
                                                              {0x84, 0xd4, 0x4b},
                                                              {0xad, 0xdc, 0x30},
                                                              {0xd8, 0xe2, 0x19},
                                                              {0xfd, 0xe7, 0x25}}};
  const double x = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * 16;
  const int k    = std::min(static_cast<int>(x), 15);
  const double f = x - k;
  char text[8];
  const auto channel = [&](int c) {
    return static_cast<int>(std::lround(kTable[k][c] + f * (kTable[k + 1][c] - kTable[k][c])));
  };
  std::snprintf(text, sizeof text, "#%02x%02x%02x", channel(0), channel(1), channel(2));
  return text;
}

/// viridis(t) from a table of 256 colours made once (the pictures colour every cell).
inline const char* viridis_hex(double t) {
  static const std::array<std::array<char, 8>, 256> kPalette = [] {
    std::array<std::array<char, 8>, 256> p{};
    for (int k = 0; k < 256; ++k) {
      const std::string c = viridis(k / 255.0);
      std::copy(c.begin(), c.end(), p[static_cast<std::size_t>(k)].begin());
    }
    return p;
  }();
  const double x = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
  return kPalette[static_cast<std::size_t>(std::lround(x * 255))].data();
}

/// A number for labels: 4 significant digits, no trailing noise.
inline std::string label_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", std::abs(v) < 1e-300 ? 0.0 : v);
  return text;
}

/// Round tick values covering [lo, hi] at a 1-2-5 spacing, at most about `count` of them.
inline std::vector<double> nice_ticks(double lo, double hi, int count) {
  if (!(hi > lo)) return {lo};
  const double raw = (hi - lo) / count, decade = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw <= decade       ? decade
                      : raw <= 2 * decade ? 2 * decade
                      : raw <= 5 * decade ? 5 * decade
                                          : 10 * decade;
  if (!(lo + step > lo) || !(hi + step > hi)) return {lo, hi};  // a range of a few round-off steps
  std::vector<double> ticks;
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step && ticks.size() <= 2u * count + 2;
       v += step)
    ticks.push_back(std::abs(v) < 1e-9 * step ? 0.0 : v);
  return ticks;
}

}  // namespace detail

/// The displacement magnification of a picture: the largest in-plane displacement shown as 5% of the
/// section's extent, rounded down to a 1-2-5 factor (1 when nothing moved). deformed.svg and the field plots.
inline double picture_magnification(const std::vector<Vec2>& nodes, double largest_displacement) {
  if (!(largest_displacement > 0) || nodes.empty()) return 1;
  Vec2 lo = nodes.front(), hi = nodes.front();
  for (const auto& x : nodes) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double want   = 0.05 * (hi - lo).maxCoeff() / largest_displacement,
               decade = std::pow(10.0, std::floor(std::log10(want)));
  return want >= 5 * decade ? 5 * decade : want >= 2 * decade ? 2 * decade : decade;
}

/// Field `name` of a VTU file's arrays; InputError listing the names there are.
inline PlotField plot_field(const VtuData& d, const std::string& name, const PlotUnits& units = {}) {
  PlotField f;
  f.name                = name;
  const auto need_point = [&](const char* array, int components) -> const VtuField& {
    const VtuField* a = d.point(array);
    if (!a || a->components != components)
      throw InputError("field " + name + ": the file has no point array '" + array + "'");
    return *a;
  };
  const auto need_cell = [&](const char* array, int components) -> const VtuField& {
    const VtuField* a = d.cell(array);
    if (!a || a->components != components)
      throw InputError("field " + name + ": the file has no cell array '" + array +
                       "' (gap_state and contact_force come from runs with gap elements, error_estimate "
                       "from runs with error_estimate = energy)");
    return *a;
  };
  static constexpr std::array<const char*, 6> kStress{"s_rr", "s_zz", "s_tt", "s_rz", "s_rt", "s_zt"};
  static constexpr std::array<int, 6> kSlot{voigt::rr, voigt::zz,      voigt::hoop,
                                            voigt::rz, voigt::theta_r, voigt::z_theta};
  const std::string length = " [" + units.length + "]", stress = " [" + units.stress + "]";
  if (name == "u" || name == "u_r" || name == "u_z" || name == "u_t") {
    const VtuField& u = need_point("displacement", 3);
    f.nodal = true, f.label = (name == "u" ? std::string("|u|") : name) + length;
    const int c = name == "u_r" ? 0 : name == "u_z" ? 1 : name == "u_t" ? 2 : -1;
    for (std::size_t n = 0; n < d.points.size(); ++n)
      f.values.push_back(c >= 0 ? u.values[3 * n + static_cast<std::size_t>(c)]
                                : std::sqrt(u.values[3 * n] * u.values[3 * n] +
                                            u.values[3 * n + 1] * u.values[3 * n + 1] +
                                            u.values[3 * n + 2] * u.values[3 * n + 2]));
    return f;
  }
  for (std::size_t k = 0; k < kStress.size(); ++k)
    if (name == kStress[k] || name == "mises") {
      const VtuField& s = need_cell("stress", 6);
      f.label           = (name == "mises" ? std::string("von Mises stress") : name) + stress;
      for (std::size_t e = 0; e < d.cells.size(); ++e) {
        const Vec<6> v = Eigen::Map<const Vec<6>>(s.values.data() + 6 * e);
        f.values.push_back(name == "mises" ? voigt::von_mises(v) : v(kSlot[k]));
      }
      return f;
    }
  if (name == "eqps" || name == "gap_state" || name == "contact_force" || name == "material" ||
      name == "error_estimate") {
    f.values = need_cell(name.c_str(), 1).values;
    f.label  = name == "eqps"             ? "equivalent plastic strain eqps [-]"
               : name == "gap_state"      ? "gap state (0 structural, -1 soft, 1 open, 2-4 closed)"
               : name == "contact_force"  ? "contact force f_n [" + units.force + "]"
               : name == "error_estimate" ? std::string("relative energy-norm error per cell [-]")
                                          : std::string("material");
    return f;
  }
  throw InputError("unknown field '" + name + "' (known: " + detail::names_text() + ")");
}

/// The deformed section of `d` coloured by `f` (plot_field of the same file) as SVG text: every cell once
/// (`class="cell"`, its value in `data-value`), a colour bar from the field's least to its greatest value
/// (`class="colorbar"` with `data-min`, `data-max`), r and z axes, the magnification in the title.
inline std::string field_svg(const VtuData& d, const PlotField& f, const std::string& title,
                             const PlotUnits& units = {}) {
  if (d.points.empty() || d.cells.empty()) throw InputError("nothing to draw: the mesh has no cells");
  const VtuField* u = d.point("displacement");
  if (u && u->components != 3) u = nullptr;  // not ours: draw undeformed
  double largest = 0;
  for (std::size_t n = 0; u && n < d.points.size(); ++n)
    largest = std::max(largest, std::hypot(u->values[3 * n], u->values[3 * n + 1]));
  const double factor        = picture_magnification(d.points, largest);
  std::vector<Vec2> deformed = d.points, both = d.points;
  for (std::size_t n = 0; u && n < d.points.size(); ++n) {
    deformed[n] += factor * Vec2(u->values[3 * n], u->values[3 * n + 1]);
    both.push_back(deformed[n]);
  }
  const double lo = *std::min_element(f.values.begin(), f.values.end()),
               hi = *std::max_element(f.values.begin(), f.values.end());
  detail::SvgCanvas svg(both,
                        title + ": " + f.label + " on the deformed section (displacements x " +
                            detail::label_number(factor) + "; grey: undeformed)",
                        detail::SvgCanvas::Margins{90, 200, 40, 70}, 320);
  // ---- the undeformed boundary, thin and grey: cell sides that belong to one cell only
  const auto corners_of = [](const std::vector<int>& cell) {  // quadratic cells: corners first
    return cell.size() == 8 ? 4 : cell.size() == 6 ? 3 : cell.size();
  };
  {
    const auto sides = detail::outline_sides(d.cells.size(),
                                             [&](std::size_t e, auto&& side) {
                                               const auto& cell = d.cells[e];
                                               for (std::size_t k = 0, n = corners_of(cell); k < n; ++k)
                                                 side(cell[k], cell[(k + 1) % n]);
                                             },
                                             {});
    for (const auto& [a, b] : sides)
      svg.polygon(
          std::array<Vec2, 2>{d.points[static_cast<std::size_t>(a)], d.points[static_cast<std::size_t>(b)]},
          2, "none", "#a0a0a0", 0.8, " class=\"undeformed\"");
  }
  // ---- cells, each once, in the file's order; slivers (gap elements: a tenth of a percent of the median
  // cell's area or less) after the others with a heavy outline in their colour, which is what stays visible
  // of them. Written straight into the picture: a run draws this for its last increment, and 1e4 cells
  // through temporary strings cost 12 ms of a 0.1 s contact run.
  std::vector<double> area(d.cells.size());
  for (std::size_t e = 0; e < d.cells.size(); ++e) {  // shoelace, undeformed
    const auto& cell = d.cells[e];
    for (std::size_t k = 0, n = corners_of(cell); k < n; ++k) {
      const Vec2 &a = d.points[static_cast<std::size_t>(cell[k])],
                 &b = d.points[static_cast<std::size_t>(cell[(k + 1) % n])];
      area[e] += 0.5 * (a(0) * b(1) - b(0) * a(1));
    }
  }
  std::vector<double> sorted = area;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                   sorted.end());
  const double sliver = 1e-3 * std::abs(sorted[sorted.size() / 2]);
  const bool thin     = d.cells.size() > 5000;  // outlines would hide small cells
  svg.t.reserve(svg.t.size() + 160 * d.cells.size());
  for (const bool sliver_pass : {false, true})
    for (std::size_t e = 0; e < d.cells.size(); ++e) {
      if ((std::abs(area[e]) <= sliver) != sliver_pass) continue;
      const auto& cell = d.cells[e];
      double value     = 0;
      if (f.nodal) {
        for (const int n : cell) value += f.values[static_cast<std::size_t>(n)];
        value /= static_cast<double>(cell.size());
      } else {
        value = f.values[e];
      }
      const char* colour = detail::viridis_hex(hi > lo ? (value - lo) / (hi - lo) : 0.5);
      svg.t += "<polygon class=\"cell\" data-cell=\"";
      detail::append_number(svg.t, static_cast<long long>(e + 1));
      svg.t += "\" data-value=\"";
      detail::append_number(svg.t, value);
      svg.t += "\" points=\"";
      for (std::size_t k = 0, n = corners_of(cell); k < n; ++k) {
        const auto p = svg.px(deformed[static_cast<std::size_t>(cell[k])]);
        svg.num(p[0]), svg.t += ',', svg.num(p[1]), svg.t += ' ';
      }
      svg.t += "\" fill=\"", svg.t += colour, svg.t += "\" stroke=\"";
      svg.t += sliver_pass || thin ? colour : "#404040";
      svg.t += sliver_pass ? "\" stroke-width=\"3\"/>\n"
               : thin      ? "\" stroke-width=\"0.2\"/>\n"
                           : "\" stroke-width=\"0.3\"/>\n";
    }
  // ---- axes: r along the bottom, z along the left, ticks in model coordinates
  const double x0 = svg.margin.left - 12, y0 = svg.height - svg.margin.bottom + 12;
  const double x1 = svg.px(svg.hi)[0], y1 = svg.px(svg.hi)[1];
  svg.line(svg.margin.left, y0, x1, y0), svg.line(x0, y1, x0, svg.height - svg.margin.bottom);
  for (const double r : detail::nice_ticks(svg.lo(0), svg.hi(0), 6)) {
    const double x = svg.px(Vec2(r, svg.lo(1)))[0];
    svg.line(x, y0, x, y0 + 5), svg.text(x, y0 + 18, 11, detail::label_number(r), "black", "middle");
  }
  // at most a tick per 40 px of a flat section's height
  const int z_ticks = std::clamp(static_cast<int>((svg.hi(1) - svg.lo(1)) * svg.scale / 40), 1, 6);
  for (const double z : detail::nice_ticks(svg.lo(1), svg.hi(1), z_ticks)) {
    const double y = svg.px(Vec2(svg.lo(0), z))[1];
    svg.line(x0 - 5, y, x0, y), svg.text(x0 - 8, y + 4, 11, detail::label_number(z), "black", "end");
  }
  svg.text(0.5 * (svg.margin.left + x1), y0 + 38, 13, "r [" + units.length + "]", "black", "middle", "axis");
  svg.text(24, 0.5 * (y1 + svg.height - svg.margin.bottom), 13, "z [" + units.length + "]", "black", "middle",
           "axis", -90);
  // ---- the colour bar: 64 bands from lo (bottom) to hi (top), five labels
  const std::vector<std::string> label = detail::SvgCanvas::wrap(f.label, 26);
  const double bar_x                   = svg.width - 170,
               bar_top                 = svg.margin.top + 14.0 * static_cast<double>(label.size()) + 6,
               bar_height              = std::clamp(svg.height - bar_top - svg.margin.bottom, 120.0, 400.0);
  for (std::size_t k = 0; k < label.size(); ++k)
    svg.text(bar_x - 6, svg.margin.top + 14.0 * static_cast<double>(k), 12, label[k], "black", "start",
             "bar-label");
  svg.t += "<g class=\"colorbar\" data-min=\"";
  detail::append_number(svg.t, lo), svg.t += "\" data-max=\"", detail::append_number(svg.t, hi),
      svg.t += "\">\n";
  constexpr int kBands = 64;
  for (int b = 0; b < kBands; ++b) {
    const double y = bar_top + bar_height * (kBands - 1 - b) / kBands;
    svg.t += "<rect x=\"", svg.num(bar_x), svg.t += "\" y=\"", svg.num(y),
        svg.t += "\" width=\"24\" height=\"";
    svg.num(bar_height / kBands + 0.5), svg.t += "\" fill=\"",
        svg.t += detail::viridis_hex((b + 0.5) / kBands), svg.t += "\"/>\n";
  }
  for (int k = 0; k <= 4; ++k) {
    const double v = lo + (hi - lo) * k / 4, y = bar_top + bar_height * (1 - k / 4.0);
    svg.line(bar_x + 24, y, bar_x + 29, y);
    svg.text(bar_x + 32, y + 4, 11, detail::label_number(v), "black", "start", "tick");
  }
  svg.t += "</g>\n";
  return svg.close();
}

/// field_svg written to `path` (through a temporary file and a rename).
inline void write_field_svg(const std::string& path, const VtuData& d, const PlotField& f,
                            const std::string& title, const PlotUnits& units = {}) {
  detail::write_file_atomically(path, field_svg(d, f, title, units));
}

/// A curve of column `y` against column `x` (history.csv's), one marker per row, with axes and labels.
/// Rows with a value that is not finite (cone_ratio is inf for a pair carrying friction in tension) are
/// left out, and the title says how many.
inline void write_curve_svg(const std::string& path, const std::vector<double>& x_all,
                            const std::vector<double>& y_all, const std::string& x_label,
                            const std::string& y_label, const std::string& title) {
  if (x_all.size() != y_all.size() || x_all.empty()) throw InputError("nothing to draw: no rows");
  std::vector<double> x, y;
  for (std::size_t k = 0; k < x_all.size(); ++k)
    if (std::isfinite(x_all[k]) && std::isfinite(y_all[k])) x.push_back(x_all[k]), y.push_back(y_all[k]);
  if (x.empty())
    throw InputError("nothing to draw: no row has finite values of " + x_label + " and " + y_label);
  const std::string left_out =
      x.size() < x_all.size() ? " (" + std::to_string(x_all.size() - x.size()) + " rows not finite, left out)"
                              : "";
  const double left = 100, right = 40, top = 40, bottom = 70;
  const auto range = [](const std::vector<double>& v) {  // with 0 when every value has one sign
    double lo = std::min(0.0, *std::min_element(v.begin(), v.end())),
           hi = std::max(0.0, *std::max_element(v.begin(), v.end()));
    if (!(hi > lo)) lo -= 0.5 * std::max(1.0, std::abs(lo)), hi += 0.5 * std::max(1.0, std::abs(hi));
    return std::pair{lo, hi};
  };
  const std::pair<double, double> xr = range(x), yr = range(y);  // clang 14 captures no structured binding
  const double xl = xr.first, xh = xr.second, yl = yr.first, yh = yr.second;
  // The canvas of a rectangle: a picture of (x, y) in place of (r, z), fitted by its own scales.
  std::vector<Vec2> frame{Vec2(0, 0), Vec2(1, 0.6)};
  detail::SvgCanvas svg(frame, title + ": " + y_label + " against " + x_label + left_out,
                        detail::SvgCanvas::Margins{left, right, top, bottom});
  const auto px = [&](double vx, double vy) {
    return svg.px(Vec2((vx - xl) / (xh - xl), 0.6 * (vy - yl) / (yh - yl)));
  };
  const auto origin = px(xl, yl), corner = px(xh, yh);
  svg.line(origin[0], origin[1], corner[0], origin[1]), svg.line(origin[0], origin[1], origin[0], corner[1]);
  for (const double v : detail::nice_ticks(xl, xh, 8)) {
    const double p = px(v, yl)[0];
    svg.line(p, origin[1], p, origin[1] + 5),
        svg.text(p, origin[1] + 18, 11, detail::label_number(v), "black", "middle");
  }
  for (const double v : detail::nice_ticks(yl, yh, 8)) {
    const double p = px(xl, v)[1];
    svg.line(origin[0] - 5, p, origin[0], p),
        svg.text(origin[0] - 8, p + 4, 11, detail::label_number(v), "black", "end");
  }
  svg.text(0.5 * (origin[0] + corner[0]), origin[1] + 40, 13, x_label, "black", "middle", "axis");
  svg.text(24, 0.5 * (origin[1] + corner[1]), 13, y_label, "black", "middle", "axis", -90);
  svg.t += "<polyline class=\"curve\" fill=\"none\" stroke=\"#3b528b\" stroke-width=\"1.5\" points=\"";
  for (std::size_t k = 0; k < x.size(); ++k) {
    const auto p = px(x[k], y[k]);
    svg.num(p[0]), svg.t += ',', svg.num(p[1]), svg.t += ' ';
  }
  svg.t += "\"/>\n";
  for (std::size_t k = 0; k < x.size(); ++k) {
    const auto p = px(x[k], y[k]);
    svg.t += "<circle class=\"point\" cx=\"", svg.num(p[0]), svg.t += "\" cy=\"", svg.num(p[1]);
    svg.t += "\" r=\"2.5\" fill=\"#21918c\"/>\n";
  }
  svg.save(path);
}

}  // namespace gapfe

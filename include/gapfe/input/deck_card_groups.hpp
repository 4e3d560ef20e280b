#pragma once
// The card-deck reader's card groups, in the deck's order (BRL-CR-670 Appendix A): each reads its cards
// from DeckLines (input/deck_lines.hpp) into the Deck, checking columns, counts and ranges.
#include <string>
#include <utility>
#include <vector>

#include "gapfe/input/deck_cards.hpp"
#include "gapfe/input/deck_lines.hpp"
#include "gapfe/input/fixed_format.hpp"

namespace gapfe::detail {

/// The extension lines `$ key = value` before the first card, then the command line's `overrides`.
inline void read_extensions(DeckLines& in, Deck& d,
                            const std::vector<std::pair<std::string, std::string>>& overrides) {
  // ---- extensions: `$ key = value` lines before the first card
  while (!in.done() && !in.peek().empty() && in.peek().front() == '$') {
    std::string line(in.peek().substr(1));
    const int number = in.line_number();
    in.skip();
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;  // a comment
    const auto trim = [](std::string s) {
      const auto a = s.find_first_not_of(' '), b = s.find_last_not_of(' ');
      return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
    };
    try {
      d.options.set(trim(line.substr(0, eq)), trim(line.substr(eq + 1)));
    } catch (const InputError& e) {
      throw InputError("extension line " + std::to_string(number) + ": " + e.what());
    }
  }
  for (const auto& [key, value] : overrides) d.options.set(key, value);
}

/// Data 0-3: the rate property card (SAAC3 only), the title, the control card, the mesh generation control.
inline void read_head_cards(DeckLines& in, Deck& d, const InputLimits& limits) {
  // ---- Data 0: rate property card (5E12.6), SAAC3 / SAAC3X only
  if (d.options.format == DeckFormat::saac3) {
    const CardImage c = in.take("DATA NO. 0 (rate property card)");
    RateCard r;
    r.time_step           = c.real(1, 12, 6, "time increment");
    r.rate_b              = c.real(13, 24, 6, "rate parameter b");
    r.rate_plastic_strain = c.real(25, 36, 6, "rate parameter eps_p dot");
    r.strain_rate         = c.real(37, 48, 6, "STRRATE");
    r.shear_stress_step   = c.real(49, 60, 6, "STRSTEP");
    if (!(r.time_step > 0)) c.reject(1, 12, "time increment", "must be > 0");
    d.rate = r;
  }
  // ---- Data 1: title (20A4)
  {
    const CardImage c = in.take("DATA NO. 1 (title card)");
    d.title           = c.field(1, 80);
    while (!d.title.empty() && d.title.back() == ' ') d.title.pop_back();
  }
  // ---- Data 2: control card (6I5, F5.0, 6I5)
  {
    const CardImage c = in.take("DATA NO. 2 (control card)");
    ControlCard& k    = d.control;
    k.nnla            = c.integer(1, 5, "NNLA");
    k.numtc           = c.integer(6, 10, "NUMTC");
    k.nummat          = c.integer(11, 15, "NUMMAT");
    k.numpc           = c.integer(16, 20, "NUMPC");
    k.numsc           = c.integer(21, 25, "NUMSC");
    k.numst           = c.integer(26, 30, "NUMST");
    k.tref            = c.real(31, 35, 0, "TREF");
    k.inert           = c.integer(36, 40, "INERT");
    k.nlinc           = c.integer(41, 45, "NLINC");
    k.inci            = c.integer(46, 50, "INCI");
    k.incf            = c.integer(51, 55, "INCF");
    k.iplot           = c.integer(56, 60, "IPLLOT");
    if (k.numtc < 0 && k.numtc != -2)
      c.reject(6, 10, "NUMTC", "must be >= 0, or -2 for a constant temperature");
    if (k.nummat < 1) c.reject(11, 15, "NUMMAT", "must be >= 1");
    if (k.numpc < 0) c.reject(16, 20, "NUMPC", "must be >= 0");
    if (k.numsc < 0) c.reject(21, 25, "NUMSC", "must be >= 0");
    if (k.numst < 0) c.reject(26, 30, "NUMST", "must be >= 0");
    if (k.nlinc < 1) c.reject(41, 45, "NLINC", "must be >= 1");
    if (k.nlinc > limits.max_load_steps) c.reject(41, 45, "NLINC", "exceeds the limit of load steps");
    if (k.inert < 0) c.reject(36, 40, "INERT", "must be 0 (no inertia card) or positive");
  }
  LoadProgram& program = d.program;  // the control card's part of it
  program.steps = d.control.nlinc, program.inertia = d.control.inert != 0;
  program.inertia_repeats = d.control.inci == 0, program.surface_repeats = d.control.incf == 0;
  program.reference_temperature = d.control.tref;
  // ---- Data 3: mesh generation control (5I5)
  {
    const CardImage c  = in.take("DATA NO. 3 (mesh generation control card)");
    MeshControlCard& k = d.mesh;
    k.max_i            = c.integer(1, 5, "MAXI");
    k.max_j            = c.integer(6, 10, "MAXJ");
    k.nseg             = c.integer(11, 15, "NSEG");
    k.nbc              = c.integer(16, 20, "NBC");
    k.nmtl             = c.integer(21, 25, "NMTL");
    if (k.max_i < 1) c.reject(1, 5, "MAXI", "must be >= 1");
    if (k.max_j < 1) c.reject(6, 10, "MAXJ", "must be >= 1");
    if (static_cast<long long>(k.max_i) * k.max_j > limits.max_grid_points)
      c.reject(1, 10, "MAXI x MAXJ",
               "the grid exceeds " + std::to_string(limits.max_grid_points) + " points");
    if (k.nseg < 1) c.reject(11, 15, "NSEG", "must be >= 1");
    if (k.nbc < 0) c.reject(16, 20, "NBC", "must be >= 0");
    if (k.nmtl < 1) c.reject(21, 25, "NMTL", "must be >= 1");
  }
}

/// Data 4-6: line segments, boundary conditions, material blocks.
inline void read_mesh_cards(DeckLines& in, Deck& d) {
  const CardLayout& cols = d.options.wide_fields ? kWideCards : kLegacyCards;
  // ---- Data 4: line segment cards (3(2I3, 2F8.3), I5; wide: 3(2I5, 2F12.3), I5)
  const int iw = cols.index_width, cw = cols.coordinate_width, type_at = 3 * cols.point_width() + 1;
  for (int s = 1; s <= d.mesh.nseg; ++s) {
    const CardImage c = in.take(numbered("DATA NO. 4", "line segment card", s));
    Segment seg;
    for (int k = 0; k < 3; ++k) {
      const int o = cols.point_width() * k;
      seg.p[k].i  = c.integer(o + 1, o + iw, "I");
      seg.p[k].j  = c.integer(o + iw + 1, o + 2 * iw, "J");
      seg.p[k].x  = {c.real(o + 2 * iw + 1, o + 2 * iw + cw, 3, "R"),
                     c.real(o + 2 * iw + cw + 1, o + 2 * iw + 2 * cw, 3, "Z")};
    }
    const int type = c.integer(type_at, type_at + 4, "line segment type");
    if (type < 0 || type > 6)
      c.reject(type_at, type_at + 4, "line segment type", "must be 0-6, got " + std::to_string(type));
    seg.type       = static_cast<SegmentType>(type);
    const int used = type == 0 ? 1 : type == 3 ? 3 : 2;
    for (int k = 0; k < used; ++k) {
      const int o        = cols.point_width() * k;
      const GridPoint& p = seg.p[k];
      if (p.i < 1 || p.i > d.mesh.max_i)
        c.reject(o + 1, o + iw, "I",
                 "must be within 1..MAXI = " + std::to_string(d.mesh.max_i) + ", got " + std::to_string(p.i));
      if (p.j < 1 || p.j > d.mesh.max_j)
        c.reject(o + iw + 1, o + 2 * iw, "J",
                 "must be within 1..MAXJ = " + std::to_string(d.mesh.max_j) + ", got " + std::to_string(p.j));
    }
    d.segments.push_back(seg);
    d.segment_refs.push_back({c.card(), c.line()});
  }
  // ---- Data 5: boundary condition cards (4I5, I10, 3F10.0)
  for (int b = 1; b <= d.mesh.nbc; ++b) {
    const CardImage c = in.take(numbered("DATA NO. 5", "boundary condition card", b));
    BoundaryCard k;
    read_index_rectangle(c, 1, d.mesh, false, k.i1, k.i2, k.j1, k.j2);
    k.code  = c.integer(21, 30, "boundary condition code");
    k.value = {c.real(31, 40, 0, "XR"), c.real(41, 50, 0, "XZ"), c.real(51, 60, 0, "XT")};
    if (k.code < 0 || k.code > 7)
      c.reject(21, 30, "boundary condition code", "must be 0-7 (bit mask 1 = u_r, 2 = u_z, 4 = u_t)");
    if (d.options.loads_per_radian)
      for (int comp = 0; comp < 3; ++comp)
        if (!((k.code >> comp) & 1)) k.value[comp] *= kTwoPi;  // per radian -> total ring force
    k.ref = {c.card(), c.line()};
    d.boundary.push_back(k);
  }
  // ---- Data 6: material block cards (5I5, 2F10.0, 3I5)
  for (int b = 1; b <= d.mesh.nmtl; ++b) {
    const CardImage c = in.take(numbered("DATA NO. 6", "material block card", b));
    MaterialBlockCard k;
    k.material = c.integer(1, 5, "material number");
    read_index_rectangle(c, 6, d.mesh, true, k.i1, k.i2, k.j1, k.j2);
    k.beta_deg  = c.real(26, 35, 0, "BETA");
    k.alpha_deg = c.real(36, 45, 0, "ALPHA");
    k.iang      = c.integer(46, 50, "IANG");
    k.nang      = c.integer(51, 55, "NANG");
    k.ijdir     = c.integer(56, 60, "IJDIR");
    if (k.material < 1) c.reject(1, 5, "material number", "must be >= 1");
    if (k.iang != 0 && k.iang != 1) c.reject(46, 50, "IANG", "must be 0 or 1");
    if (k.iang == 1 && k.nang < 1) c.reject(51, 55, "NANG", "must be >= 1 when IANG = 1");
    if (k.ijdir < 0 || k.ijdir > 2) c.reject(56, 60, "IJDIR", "must be 0, 1 or 2");
    k.ref = {c.card(), c.line()};
    d.blocks.push_back(k);
  }
}

/// Data 7-9: the plot cards (IPLLOT = 1) and the temperature field.
inline void read_temperature_cards(DeckLines& in, Deck& d) {
  // ---- Data 7, 8: plot title and plot limits, only with IPLLOT = 1
  if (d.control.iplot == 1) {
    const CardImage t = in.take("DATA NO. 7 (plot title card)");
    d.plot_title      = t.field(1, 80);
    while (!d.plot_title.empty() && d.plot_title.back() == ' ') d.plot_title.pop_back();
    const CardImage c = in.take("DATA NO. 8 (plot generation information card)");
    d.plot_rmax       = c.real(1, 10, 0, "RMAX");
    d.plot_zmax       = c.real(11, 20, 0, "ZMAX");
  }
  // ---- Data 9: temperature field
  if (d.control.numtc > 0) {
    for (int t = 1; t <= d.control.numtc; ++t) {
      const CardImage c = in.take(numbered("DATA NO. 9", "temperature card", t));
      d.temperature_points.push_back({c.real(1, 10, 0, "R coordinate"), c.real(11, 20, 0, "Z coordinate"),
                                      c.real(21, 30, 0, "temperature")});
    }
  } else if (d.control.numtc == -2) {
    const CardImage c      = in.take("DATA NO. 9 (constant temperature card)");
    d.constant_temperature = c.real(1, 10, 0, "temperature");
  }
}

/// Data 10 and 11: each material's property table, and its yield card in the plastic formats.
inline void read_material_cards(DeckLines& in, Deck& d) {
  const bool plastic_format = d.options.format != DeckFormat::elastic;
  // ---- Data 10 (+ 11): materials
  for (int m = 1; m <= d.control.nummat; ++m) {
    const CardImage c = in.take(numbered("DATA NO. 10a", "material identification card of material", m));
    MaterialInput mat;
    mat.id            = c.integer(1, 5, "material identification number");
    const int ntemp   = c.integer(6, 10, "number of temperatures");
    mat.table.density = c.real(11, 20, 0, "mass density");
    const double tep  = c.real(21, 30, 0, "thermal expansion parameter");
    mat.table.thermal = tep == 1.0 ? ThermalInput::free_strain : ThermalInput::coefficients;
    mat.ref           = {c.card(), c.line()};
    if (mat.id < 1) c.reject(1, 5, "material identification number", "must be >= 1");
    if (d.material(mat.id))
      c.reject(1, 5, "material identification number",
               "material " + std::to_string(mat.id) + " is defined twice");
    if (ntemp < 1) c.reject(6, 10, "number of temperatures", "must be >= 1");
    if (mat.table.density < 0) c.reject(11, 20, "mass density", "must be >= 0");
    for (int t = 1; t <= ntemp; ++t) {
      const std::string what =
          "property cards of material " + std::to_string(mat.id) + ", temperature " + std::to_string(t);
      const CardImage a = in.take("DATA NO. 10b (first " + what + ")");
      const CardImage b = in.take("DATA NO. 10b (second " + what + ")");
      ElasticConstants row;
      row.temperature = a.real(1, 10, 0, "temperature");
      row.E_N         = a.real(11, 20, 0, "E_N");
      row.E_S         = a.real(21, 30, 0, "E_S");
      row.E_T         = a.real(31, 40, 0, "E_T");
      row.nu_NS       = a.real(41, 50, 0, "nu_NS");
      row.nu_NT       = a.real(51, 60, 0, "nu_NT");
      row.nu_ST       = a.real(61, 70, 0, "nu_ST");
      row.G_NS        = b.real(1, 10, 0, "G_NS");
      row.G_ST        = b.real(11, 20, 0, "G_ST");
      row.G_TN        = b.real(21, 30, 0, "G_TN");
      row.alpha_N     = b.real(31, 40, 0, "alpha_N");
      row.alpha_S     = b.real(41, 50, 0, "alpha_S");
      row.alpha_T     = b.real(51, 60, 0, "alpha_T");
      try {
        row.validate("");
      } catch (const InputError& e) {
        throw InputError(a.where() + " and line " + std::to_string(b.line()) + e.what());
      }
      if (!mat.table.rows.empty() && !(row.temperature > mat.table.rows.back().temperature))
        a.reject(1, 10, "temperature", "the temperatures of a material must increase strictly");
      mat.table.rows.push_back(row);
    }
    if (plastic_format) {
      const CardImage y =
          in.take("DATA NO. 11 (yield stress card of material " + std::to_string(mat.id) + ")");
      YieldCard card;
      const char* names[] = {"yield stress N",  "yield stress S",  "yield stress T",
                             "yield stress NS", "yield stress NT", "yield stress TS"};
      for (int k = 0; k < 6; ++k) {
        card.yield[k] = y.real(10 * k + 1, 10 * k + 10, 0, names[k]);
        if (card.yield[k] < 0) y.reject(10 * k + 1, 10 * k + 10, names[k], "must be >= 0");
      }
      card.hardening = y.real(61, 70, 0, "hardening parameter C");
      card.blank     = y.blank(1, 70);
      if (!card.blank)
        for (int k = 0; k < 6; ++k)
          if (!(card.yield[k] > 0))
            y.reject(10 * k + 1, 10 * k + 10, names[k],
                     "a yield card that is not blank needs all six yield stresses > 0");
      mat.yield = card;
    }
    d.materials.push_back(std::move(mat));
  }
}

/// Data 12-15: the load blocks, one per load step or the first only (INCI, INCF = 0).
inline void read_load_cards(DeckLines& in, Deck& d) {
  const CardLayout& cols = d.options.wide_fields ? kWideCards : kLegacyCards;
  // ---- Data 12-15: load blocks
  const ControlCard& k = d.control;
  for (int s = 1; s <= k.nlinc; ++s) {
    const bool inertia_card = k.inert != 0 && (s == 1 || k.inci != 0);
    const bool surface      = s == 1 || k.incf != 0;
    if (!inertia_card && !surface) {
      if (s > 1 && k.inci == 0 && k.incf == 0) break;  // nothing more to read: every step repeats block 1
      continue;
    }
    LoadBlock block;
    const std::string step = " of load step " + std::to_string(s);
    if (inertia_card) {
      const CardImage c = in.take("DATA NO. 12 (inertia load card" + step + ")");
      block.inertia =
          InertiaLoad{c.real(1, 10, 0, "ACELZ"), c.real(11, 20, 0, "ANGVEL"), c.real(21, 30, 0, "ANGACC")};
    }
    if (surface) {
      const auto edges = [&](int count, const char* data, const char* what, std::vector<EdgeCard>& out) {
        for (int e = 1; e <= count; ++e) {
          const CardImage c = in.take(std::string(data) + " (" + what + " " + std::to_string(e) + step + ")");
          const int nw      = cols.node_width;  // 2I5, F10.0; wide: 2I10, F10.0
          EdgeCard card{c.integer(1, nw, "nodal point M"),
                        c.integer(nw + 1, 2 * nw, "nodal point N"),
                        c.real(2 * nw + 1, 2 * nw + 10, 0, "value"),
                        {c.card(), c.line()}};
          if (card.node_m < 1) c.reject(1, nw, "nodal point M", "node numbers start at 1");
          if (card.node_n < 1) c.reject(nw + 1, 2 * nw, "nodal point N", "node numbers start at 1");
          if (card.node_m == card.node_n) c.reject(1, 2 * nw, "nodal points M, N", "M and N must differ");
          out.push_back(card);
        }
      };
      edges(k.numpc, "DATA NO. 13", "boundary pressure card", block.pressure);
      edges(k.numsc, "DATA NO. 14", "boundary shear card", block.shear);
      edges(k.numst, "DATA NO. 15", "boundary transverse shear card", block.transverse_shear);
    }
    d.program.blocks.push_back(std::move(block));
  }
}

}  // namespace gapfe::detail

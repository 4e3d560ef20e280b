#pragma once
// From a read Deck to what an analysis needs: the I-J grid and its mesh with material tags, the
// boundary conditions on nodes, the temperature field, the edge loads checked against the mesh, and which
// model features the deck requires (so the runner picks the smallest variant). Everything that refers to
// the mesh is checked here and reported with its card and line; run/step_loads.hpp turns the scene's cards
// into the loads in force after each step.
//
// Readings (README deck section): a BC card applies to the grid points in [I1, I2] x [J1, J2]; a
// material block to the cells whose corners all lie in [I1, I2] x [J1, J2] (later blocks win); a BC
// load is a total ring force.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/input/deck.hpp"
#include "gapfe/input/grid_gaps.hpp"
#include "gapfe/mesh/ij_grid.hpp"
#include "gapfe/mesh/temperature.hpp"

namespace gapfe {

/// What a deck needs beyond SAAS (2 DOF, no gaps, elastic), each with the card that asks for it.
struct DeckNeeds {
  std::vector<std::string> theta;       ///< reasons for the 3-DOF kinematics
  std::vector<std::string> gaps;        ///< material-2 blocks (saac formats)
  std::vector<std::string> plasticity;  ///< non-blank yield cards
  bool needs_theta() const { return !theta.empty(); }
};

/// Loads in force after a load step (totals of the increments so far).
struct StepTotals {
  std::vector<NodalCondition> conditions;
  InertiaLoad inertia;
  std::vector<EdgeLoad> edge_loads;
  double thermal_fraction = 0;  ///< Problem::thermal_fraction: the part of the temperature change in force
};

/// SAAC3X's constant-strain-rate test (card 0's STRRATE and STRSTEP; seed section 4.2, THEORY.md 8.7),
/// driven through the faces of the mesh at its least and greatest z (README "SAAC3X"): load step 1 ramps
/// the theta traction STRSTEP onto the top face and then holds it; from step 2 on the top face moves
/// along z at u_z = STRRATE L (t - delta t), L the length between the faces, so every later step adds
/// STRRATE L delta t; the bottom face is held at u_z = u_theta = 0 throughout.
struct StrainRateTest {
  double strain_rate = 0;  ///< STRRATE [1/time]
  double shear_step  = 0;  ///< STRSTEP, tau_z-theta on the top face, + along +theta [stress]
  double length      = 0;  ///< top z - bottom z [length]
  double step_time   = 0;  ///< how long a load step lasts, Deck::step_time() [time]
  double bottom_z = 0, top_z = 0;
  std::vector<int> bottom, top;                ///< nodes on the faces (0-based)
  std::vector<std::pair<int, int>> top_edges;  ///< cell edges on the top face, the element on the left
  bool active() const { return strain_rate != 0 || shear_step != 0; }
  /// u_z of the top face after load step `step`: 0 through the shear step, then STRRATE L delta t a step.
  double top_displacement(int step) const { return strain_rate * length * step_time * std::max(0, step - 1); }
};

struct DeckScene {
  IJGrid grid;
  Mesh<4> mesh;                            ///< quads as cells, 3-corner cells as triangles, tags set
  std::vector<int> material_id;            ///< per grid cell (numbering order): deck material number
  std::vector<int> ijdir;                  ///< per grid cell: IJDIR of its block (gap direction)
  std::vector<Orthotropic> materials;      ///< in deck order; CellTag::material indexes this
  std::vector<NodalCondition> conditions;  ///< one step's BC values (0-based nodes), later cards last
  /// Per condition (parallel to `conditions`, or empty): an index into LoadProgram::amplitudes, whose factor
  /// then multiplies the condition's values in place of the step count (a scene file's load history); -1:
  /// none.
  std::vector<int> condition_amplitude;
  /// Per condition (parallel to `conditions`): the card that gave it (a deck's BC card, a scene's
  /// [[boundary]]), an index into condition_cards, their names (bc1, bc2, ...; a scene's groups):
  /// history.csv's reactions.
  std::vector<int> condition_card;
  std::vector<std::string> condition_cards;
  VecX temperature;  ///< nodal [deg]; empty: TREF everywhere
  double reference_temperature = 0;
  DeckNeeds needs;
  GapLayout gaps;         ///< pairs of the material-2 elements (saac formats), soft corners
  int gap_material = -1;  ///< index of deck material 2 in `materials` (gap elements), -1 without gaps
  StrainRateTest strain_rate_test;  ///< SAAC3X (card 0's STRRATE, STRSTEP); inactive otherwise

  /// Element number (0-based, grid numbering) of a mesh cell or triangle.
  std::vector<int> element_of_cell, element_of_triangle;
};

/// A model as read: a card deck with its scene (build_scene), or the deck and scene a scene file stands for
/// (input/scene_file.hpp), which everything after reading takes alike.
struct SceneModel {
  Deck deck;
  DeckScene scene;
  std::string mesh_file;  ///< a scene file's Gmsh mesh ([mesh] file, resolved by read_scene_file)
};

namespace detail {

inline std::string ij_text(int i, int j) {
  return "(I = " + std::to_string(i) + ", J = " + std::to_string(j) + ")";
}

/// The deck's materials as the scene's (in deck order) and the plasticity they ask for.
inline void scene_materials(const Deck& d, DeckScene& s) {
  for (const auto& m : d.materials) {
    s.materials.push_back(Orthotropic{{}, m.table});
    if (m.yield && !m.yield->blank)
      s.needs.plasticity.push_back("material " + std::to_string(m.id) + " has a yield card (" +
                                   m.ref.where() + ")");
  }
}

/// What every scene gets once its mesh, cells (s.grid.cells), tags and conditions are in place, whether a
/// deck's I-J grid or a scene file's Gmsh mesh made them: the temperature field, the edge loads checked
/// against the cells, and SAAC3X's faces.
inline void finish_scene(const Deck& d, DeckScene& s) {
  const IJGrid& g      = s.grid;
  const int nn         = g.node_count();
  const std::size_t ne = g.cells.size();
  // ---- temperature: the field; the load program applies it (StepTotals::thermal_fraction)
  s.reference_temperature = d.program.reference_temperature;
  if (!d.temperature_points.empty())
    s.temperature = nodal_temperatures(s.mesh, d.temperature_points, d.temperature_where);
  else if (d.constant_temperature)
    s.temperature = VecX::Constant(nn, *d.constant_temperature);

  // ---- surface loads: node numbers and edges checked per card (element on the left going M -> N)
  std::vector<int> first(static_cast<std::size_t>(nn) + 1, 0), cells_of;  // node -> cells, CSR
  for (const auto& c : g.cells)
    for (int k = 0; k < c.corners; ++k) ++first[c.node[k] + 1];
  for (int n = 0; n < nn; ++n) first[n + 1] += first[n];
  cells_of.resize(static_cast<std::size_t>(first[nn]));
  {
    std::vector<int> fill(first.begin(), first.end() - 1);
    for (std::size_t e = 0; e < ne; ++e)
      for (int k = 0; k < g.cells[e].corners; ++k) cells_of[fill[g.cells[e].node[k]]++] = static_cast<int>(e);
  }
  const auto has_edge = [&](int m, int n) {  // 0-based; true when some cell runs m -> n counterclockwise
    for (int q = first[m]; q < first[m + 1]; ++q) {
      const GridCell& c = g.cells[cells_of[q]];
      for (int k = 0; k < c.corners; ++k)
        if (c.node[k] == m && c.node[(k + 1) % c.corners] == n) return true;
    }
    return false;
  };
  for (const auto& block : d.program.blocks) {
    for (const auto* cards : {&block.pressure, &block.shear, &block.transverse_shear})
      for (const auto& c : *cards) {
        for (const int n : {c.node_m, c.node_n})
          if (n > nn)
            throw InputError(c.ref.where() + ", columns " + (n == c.node_m ? "1-5" : "6-10") + ": node " +
                             std::to_string(n) + " does not exist (the mesh has " + std::to_string(nn) +
                             " nodes)");
        if (!has_edge(c.node_m - 1, c.node_n - 1)) {
          if (has_edge(c.node_n - 1, c.node_m - 1))
            throw InputError(c.ref.where() + ": the element is on the right going from node " +
                             std::to_string(c.node_m) + " to node " + std::to_string(c.node_n) +
                             "; it must be on the left (swap M and N)");
          throw InputError(c.ref.where() + ": nodes " + std::to_string(c.node_m) + " and " +
                           std::to_string(c.node_n) + " are not the ends of an element edge");
        }
        if (cards == &block.transverse_shear && c.value != 0)
          s.needs.theta.push_back("transverse shear in " + c.ref.where());
      }
    if (block.inertia && block.inertia->angular_acceleration != 0)
      s.needs.theta.push_back("angular acceleration ANGACC in the inertia card of a load block");
  }

  // ---- SAAC3X: the faces at the least and greatest z
  if (d.rate && (d.rate->strain_rate != 0 || d.rate->shear_stress_step != 0)) {
    StrainRateTest& x = s.strain_rate_test;
    x.strain_rate = d.rate->strain_rate, x.shear_step = d.rate->shear_stress_step;
    x.step_time            = d.step_time();  // delta t when b != 0; else time is the load factor
    const std::string card = "DATA NO. 0 (rate property card), columns 37-60 (STRRATE, STRSTEP)";
    if (!std::isfinite(x.strain_rate) || !std::isfinite(x.shear_step))
      throw InputError(card + ": not a finite number");
    x.bottom_z = x.top_z = s.mesh.nodes[0](1);
    for (const Vec2& p : s.mesh.nodes)
      x.bottom_z = std::min(x.bottom_z, p(1)), x.top_z = std::max(x.top_z, p(1));
    x.length         = x.top_z - x.bottom_z;
    const double tol = 1e-9 * s.mesh.size();
    if (!(x.length > tol))
      throw InputError(card +
                       ": the constant-strain-rate test needs a mesh with length along z (all nodes at z = " +
                       detail::number_text(x.top_z) + ")");
    std::vector<char> on_top(static_cast<std::size_t>(nn), 0);
    for (int n = 0; n < nn; ++n) {
      if (std::abs(s.mesh.nodes[n](1) - x.bottom_z) <= tol) x.bottom.push_back(n);
      if (std::abs(s.mesh.nodes[n](1) - x.top_z) <= tol) x.top.push_back(n), on_top[n] = 1;
    }
    for (const auto& c : g.cells)
      for (int k = 0; k < c.corners; ++k) {
        const int m = c.node[k], n = c.node[(k + 1) % c.corners];
        if (on_top[m] && on_top[n]) x.top_edges.emplace_back(m, n);
      }
    if (x.shear_step != 0) {
      if (x.top_edges.empty())
        throw InputError(card + ": the shear stress step needs element edges on the top face z = " +
                         detail::number_text(x.top_z) + " (it has only corners there)");
      s.needs.theta.push_back("the shear stress step STRSTEP = " + detail::number_text(x.shear_step) +
                              " in DATA NO. 0 (SAAC3X)");
    }
  }
}

}  // namespace detail

namespace detail {

/// A generated I-J grid as the scene's grid and mesh, every node checked to belong to an element.
inline void grid_scene_mesh(IJGrid&& grid, DeckScene& s) {
  s.grid          = std::move(grid);
  const IJGrid& g = s.grid;
  s.mesh          = g.to_mesh();
  std::vector<char> used(static_cast<std::size_t>(g.node_count()), 0);
  for (const auto& c : g.cells)
    for (int k = 0; k < c.corners; ++k) used[c.node[k]] = 1;
  for (int n = 0; n < g.node_count(); ++n)
    if (!used[n])
      throw InputError("mesh: node " + std::to_string(n + 1) + " " +
                       ij_text(g.node_ij[n][0], g.node_ij[n][1]) +
                       " belongs to no element; check the line segment cards of its row");
}

}  // namespace detail

/// Build the scene (mesh, tags, conditions, temperatures, checked loads) of a read deck.
inline DeckScene build_scene(const Deck& d) {
  DeckScene s;
  IJGrid grid;
  try {
    grid = generate_ij_grid(d.mesh.max_i, d.mesh.max_j, d.segments);
  } catch (const InputError& e) {
    // The generator numbers segment cards from 1 in deck order: add their lines.
    std::string msg       = e.what();
    const std::string tag = "line segment card ";
    if (const auto at = msg.find(tag); at != std::string::npos) {
      const int k = std::atoi(msg.c_str() + at + tag.size());
      if (k >= 1 && k <= static_cast<int>(d.segment_refs.size()))
        throw InputError("DATA NO. 4 (" + msg.substr(at) + "), line " +
                         std::to_string(d.segment_refs[k - 1].line));
    }
    throw InputError("DATA NO. 3-4 (mesh generation): " + msg);
  }
  detail::grid_scene_mesh(std::move(grid), s);
  const IJGrid& g = s.grid;

  // ---- materials
  const bool saac = d.options.format != DeckFormat::elastic;
  detail::scene_materials(d, s);

  // ---- material blocks: cells whose corners all lie in the block's nodal rectangle
  std::vector<int> cell_at(g.box_points(), -1);  // by lower-left corner, in the grid's index box
  for (std::size_t e = 0; e < g.cells.size(); ++e)
    cell_at[g.box_index(g.cells[e].i, g.cells[e].j)] = static_cast<int>(e);
  const std::size_t ne = g.cells.size();
  s.material_id.assign(ne, 0);
  s.ijdir.assign(ne, 0);
  std::vector<CellTag> tags(ne);
  for (const auto& b : d.blocks) {
    const DeckMaterial* mat = d.material(b.material);
    if (!mat) {
      std::string ids;
      for (const auto& m : d.materials) ids += (ids.empty() ? "" : ", ") + std::to_string(m.id);
      throw InputError(b.ref.where() + ", columns 1-5 (material number): material " +
                       std::to_string(b.material) + " is not defined by a material card (defined: " + ids +
                       ")");
    }
    const int index             = static_cast<int>(mat - d.materials.data());
    int selected                = 0;
    const auto [i1, i2, j1, j2] = g.box_cut(b.i1, b.i2 - 1, b.j1, b.j2 - 1);
    for (int j = j1; j <= j2; ++j)
      for (int i = i1; i <= i2; ++i) {
        const int e = cell_at[g.box_index(i, j)];
        if (e < 0) continue;
        ++selected;
        const double deg = kTwoPi / 360.0;
        tags[e] = {index, helical_frame(b.beta_deg * deg, b.alpha_deg * deg, b.iang, b.nang, i - b.i1)};
        s.material_id[e] = b.material;
        s.ijdir[e]       = b.ijdir;
      }
    if (selected == 0)
      throw InputError(b.ref.where() + ": the block I " + std::to_string(b.i1) + "-" + std::to_string(b.i2) +
                       ", J " + std::to_string(b.j1) + "-" + std::to_string(b.j2) +
                       " contains no element of the mesh");
    if (saac && b.material == 2) s.needs.gaps.push_back("material 2 (gap elements) in " + b.ref.where());
    if (b.alpha_deg != 0)
      s.needs.theta.push_back("ALPHA = " + detail::number_text(b.alpha_deg) + " in " + b.ref.where());
  }
  if (!s.needs.gaps.empty()) {  // gap elements: node pairs from the grid (contact/gap_pairs.hpp)
    std::vector<char> is_gap(ne, 0);
    for (std::size_t e = 0; e < ne; ++e) is_gap[e] = s.material_id[e] == 2;
    s.gap_material = static_cast<int>(d.material(2) - d.materials.data());
    s.gaps         = grid_gap_pairs(g, is_gap, s.ijdir, d.options.gap_direction);
  }
  s.element_of_cell.resize(s.mesh.cells.size());
  s.element_of_triangle.resize(s.mesh.triangles.size());
  s.mesh.cell_tags.resize(s.mesh.cells.size());
  s.mesh.triangle_tags.resize(s.mesh.triangles.size());
  for (std::size_t e = 0; e < ne; ++e) {
    const GridCell& c = g.cells[e];
    if (s.material_id[e] == 0)
      throw InputError("element " + std::to_string(e + 1) + " " + detail::ij_text(c.i, c.j) +
                       " is in no material block (DATA NO. 6)");
    if (c.corners == 4) {
      s.mesh.cell_tags[c.group_index] = tags[e], s.element_of_cell[c.group_index] = static_cast<int>(e);
    } else {
      s.mesh.triangle_tags[c.group_index]  = tags[e],
      s.element_of_triangle[c.group_index] = static_cast<int>(e);
    }
  }

  // ---- boundary conditions on the grid points of each card's rectangle
  for (const auto& b : d.boundary) {
    int found      = 0;
    const int card = static_cast<int>(s.condition_cards.size());
    s.condition_cards.push_back("bc" + std::to_string(card + 1));
    const auto [i1, i2, j1, j2] = g.box_cut(b.i1, b.i2, b.j1, b.j2);
    for (int j = j1; j <= j2; ++j)
      for (int i = i1; i <= i2; ++i)
        if (const int n = g.node(i, j); n >= 0)
          s.conditions.push_back({n, b.code, b.value}), s.condition_card.push_back(card), ++found;
    if (found == 0)
      throw InputError(b.ref.where() + ": no grid point lies in I " + std::to_string(b.i1) + "-" +
                       std::to_string(b.i2) + ", J " + std::to_string(b.j1) + "-" + std::to_string(b.j2));
    if (b.value[2] != 0)
      s.needs.theta.push_back(std::string("a theta ") + ((b.code & 4) ? "displacement" : "load") + " in " +
                              b.ref.where());
  }

  detail::finish_scene(d, s);
  return s;
}

}  // namespace gapfe

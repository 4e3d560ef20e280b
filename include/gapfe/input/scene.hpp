#pragma once
// The scene: what an analysis needs of a model, built from a deck's I-J grid (input/deck_scene.hpp) or a
// scene file's mesh (input/scene_file.hpp): the mesh with material tags, the boundary conditions on nodes,
// the temperature field, the edge loads checked against the mesh, the gap pairs and which model features
// are needed (so the runner picks the smallest variant). Everything that refers to the mesh is checked here
// and reported with its card or key; run/step_loads.hpp turns the scene's loads into those in force after
// each step.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/text.hpp"
#include "gapfe/input/grid_gaps.hpp"
#include "gapfe/input/model_description.hpp"
#include "gapfe/material/elastic.hpp"
#include "gapfe/mesh/ij_grid.hpp"
#include "gapfe/mesh/mesh.hpp"
#include "gapfe/mesh/temperature.hpp"

namespace gapfe {

/// What a model needs beyond SAAS (2 DOF, no gaps, elastic), each with the card or key that asks for it.
struct ModelNeeds {
  std::vector<std::string> theta;       ///< reasons for the 3-DOF kinematics
  std::vector<std::string> gaps;        ///< material-2 blocks (saac formats)
  std::vector<std::string> plasticity;  ///< non-blank yield cards
  bool needs_theta() const { return !theta.empty(); }
};

/// SAAC3X's constant-strain-rate test (card 0's STRRATE and STRSTEP; seed section 4.2, docs/theory.md 8.7),
/// driven through the faces of the mesh at its least and greatest z (docs/decks.md "SAAC3X"): load step 1
/// ramps the theta traction STRSTEP onto the top face and then holds it; from step 2 on the top face moves
/// along z at u_z = STRRATE L (t - delta t), L the length between the faces, so every later step adds
/// STRRATE L delta t; the bottom face is held at u_z = u_theta = 0 throughout.
struct StrainRateTest {
  double strain_rate = 0;  ///< STRRATE [1/time]
  double shear_step  = 0;  ///< STRSTEP, tau_z-theta on the top face, + along +theta [stress]
  double length      = 0;  ///< top z - bottom z [length]
  double step_time   = 0;  ///< how long a load step lasts, ModelDescription::step_time() [time]
  double bottom_z = 0, top_z = 0;
  std::vector<int> bottom, top;                ///< nodes on the faces (0-based)
  std::vector<std::pair<int, int>> top_edges;  ///< cell edges on the top face, the element on the left
  bool active() const { return strain_rate != 0 || shear_step != 0; }
  /// u_z of the top face after load step `step`: 0 through the shear step, then STRRATE L delta t a step.
  double top_displacement(int step) const { return strain_rate * length * step_time * std::max(0, step - 1); }
};

struct Scene {
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
  ModelNeeds needs;
  GapLayout gaps;         ///< pairs of the material-2 elements (saac formats), soft corners
  int gap_material = -1;  ///< index of deck material 2 in `materials` (gap elements), -1 without gaps
  StrainRateTest strain_rate_test;  ///< SAAC3X (card 0's STRRATE, STRSTEP); inactive otherwise

  /// Element number (0-based, grid numbering) of a mesh cell or triangle.
  std::vector<int> element_of_cell, element_of_triangle;

  /// Quadratic cells (element = quad8; input/scene_quadratic.hpp): `mesh` and `grid` then hold a middle
  /// node on every side after the corner nodes (GridCell::mid), and this the same cells with them (8-node
  /// quadrilaterals, 6-node triangles) for the run; empty otherwise.
  Mesh<8> quadratic;
  /// Where an order-2 mesh file puts the middle node of a side (its two corners, the lesser first); empty
  /// for an order-1 mesh, whose middle nodes go half-way along each side.
  std::map<std::array<int, 2>, Vec2> given_mid_sides;
  bool is_quadratic() const { return !quadratic.cells.empty() || !quadratic.triangles.empty(); }
};

/// A model as read: the description a card deck or a scene file becomes, and its scene (for a deck,
/// build_scene's). Everything after reading takes it alike.
struct SceneModel {
  ModelDescription description;
  Scene scene;
  std::string mesh_file;  ///< a scene file's Gmsh mesh ([mesh] file, resolved by read_scene_file)
  std::string refined;    ///< how the scene's mesh was refined (`gapfe run --estimate`); empty: it was not
};

namespace detail {

inline std::string ij_text(int i, int j) {
  return "(I = " + std::to_string(i) + ", J = " + std::to_string(j) + ")";
}

/// The model's materials as the scene's (in their order) and the plasticity they ask for.
inline void scene_materials(const ModelDescription& d, Scene& s) {
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
inline void finish_scene(const ModelDescription& d, Scene& s) {
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

/// A generated I-J grid as the scene's grid and mesh, every node checked to belong to an element.
inline void grid_scene_mesh(IJGrid&& grid, Scene& s) {
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

}  // namespace gapfe

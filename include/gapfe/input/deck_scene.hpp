#pragma once
// From a read Deck to its scene (input/scene.hpp): the I-J grid from the segment cards (Data 3-4), material
// tags from the blocks (Data 6), gap pairs from the material-2 blocks, and the boundary conditions (Data 5),
// each checked against the grid and reported with its card and line.
//
// Readings (docs deck section): a BC card applies to the grid points in [I1, I2] x [J1, J2]; a
// material block to the cells whose corners all lie in [I1, I2] x [J1, J2] (later blocks win); a BC
// load is a total ring force.
#include <algorithm>
#include <array>
#include <cstdlib>
#include <string>
#include <vector>

#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/input/deck.hpp"
#include "gapfe/input/scene.hpp"
#include "gapfe/input/scene_quadratic.hpp"
#include "gapfe/mesh/ij_generator.hpp"

namespace gapfe {

/// The I-J grid of a read deck's segment cards (Data 3-4); an error names the card and its line.
inline IJGrid deck_grid(const Deck& d) {
  try {
    return generate_ij_grid(d.mesh.max_i, d.mesh.max_j, d.segments);
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
}

namespace detail {

/// Whether grid line `k` is one of a refined deck's own (Deck::own_i, own_j; every line when `own` is empty).
inline bool own_line(const std::vector<int>& own, int k) {
  return own.empty() || std::binary_search(own.begin(), own.end(), k);
}

/// The deck's own cells from line `from` to the cell at `k` (a refined deck counts its own lines).
inline int own_cells(const std::vector<int>& own, int from, int k) {
  if (own.empty()) return k - from;
  const auto upto = [&](int line) {  // own lines at or below `line`
    return static_cast<int>(std::upper_bound(own.begin(), own.end(), line) - own.begin());
  };
  return upto(k) - upto(from);
}

}  // namespace detail

/// Build the scene (mesh, tags, conditions, temperatures, checked loads) of a read deck on its grid
/// (deck_grid(d), or a refined deck's, input/deck_refine.hpp).
inline Scene build_scene(const Deck& d, IJGrid grid) {
  Scene s;
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
    const MaterialInput* mat = d.material(b.material);
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
        tags[e]          = {index, helical_frame(b.beta_deg * deg, b.alpha_deg * deg, b.iang, b.nang,
                                                 detail::own_cells(d.own_i, b.i1, i))};
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
    std::array<double, 3> held  = b.value;  // between a refined deck's own points: its forces zero
    for (int c = 0; c < 3; ++c)
      if (!((b.code >> c) & 1)) held[static_cast<std::size_t>(c)] = 0;
    for (int j = j1; j <= j2; ++j)
      for (int i = i1; i <= i2; ++i)
        if (const int n = g.node(i, j); n >= 0) {
          const bool own = detail::own_line(d.own_i, i) && detail::own_line(d.own_j, j);
          s.conditions.push_back({n, b.code, own ? b.value : held}), s.condition_card.push_back(card),
              ++found;
        }
    if (found == 0)
      throw InputError(b.ref.where() + ": no grid point lies in I " + std::to_string(b.i1) + "-" +
                       std::to_string(b.i2) + ", J " + std::to_string(b.j1) + "-" + std::to_string(b.j2));
    if (b.value[2] != 0)
      s.needs.theta.push_back(std::string("a theta ") + ((b.code & 4) ? "displacement" : "load") + " in " +
                              b.ref.where());
  }

  detail::finish_scene(d, s);
  quadratic_cells(d, s);
  return s;
}

/// Build the scene of a read deck on the grid of its segment cards.
inline Scene build_scene(const Deck& d) {
  return build_scene(d, deck_grid(d));
}

}  // namespace gapfe

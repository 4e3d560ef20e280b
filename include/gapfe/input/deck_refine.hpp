#pragma once
// A deck's model on a finer mesh: its I-J grid at 1 / 2^times the spacing, generated from the same line
// segment cards (grid point I of the deck is point (I - 1) 2^times + 1 of the finer grid, and likewise J),
// for the levels of `gapfe run --estimate` (docs/accuracy.md "Error bars"). Every card keeps its meaning:
//   * a segment card places the same points (its index steps are 2^times apart: lines and arcs get the points
//     between, evenly in index as the generator spaces them; the Laplace fill covers the rest);
//   * a material block covers the cells of its old cells (IANG's sign flips every NANG old cells still);
//   * a BC card prescribes its displacements at every grid point of its rectangle, the new ones between too
//   (an
//     edge held stays held all along), and its forces at the deck's own points only (BoundaryCard::
//     load_spacing): a ring load stays one ring load;
//   * an edge load card (Data 13-15) loads the 2^times edges its edge became, with the same traction;
//   * temperature cards give (r, z) points and stay as they are.
// Gap elements (material 2 blocks) are not refined: a gap layer one cell thick would become 2^times gap
// elements in series, a different model; such decks are refused, naming their first gap block.
#include <string>
#include <utility>
#include <vector>

#include "gapfe/input/deck_cards.hpp"
#include "gapfe/input/deck_scene.hpp"
#include "gapfe/mesh/ij_generator.hpp"

namespace gapfe {

/// Deck grid index `i` on the grid refined `times` times.
constexpr int refined_index(int i, int times) {
  return (i - 1) * (1 << times) + 1;
}

/// The refined deck and its scene, built on the refined grid.
struct RefinedDeck {
  Deck deck;
  Scene scene;
};

namespace detail {

/// The edge cards of `cards` on the refined grid: each edge of the deck's grid (nodes numbered 1-based on
/// `coarse`) becomes the 2^times edges of `fine` along it.
inline std::vector<EdgeCard> refined_edges(const std::vector<EdgeCard>& cards, const IJGrid& coarse,
                                           const IJGrid& fine, int times) {
  std::vector<EdgeCard> out;
  const int steps = 1 << times;
  for (const EdgeCard& c : cards) {
    const auto node_ij = [&](int n) -> std::array<int, 2> {
      if (n < 1 || n > coarse.node_count())  // build_scene names it with its columns on the deck's grid
        throw InputError(c.ref.where() + ": node " + std::to_string(n) + " is not a node of the mesh (1 to " +
                         std::to_string(coarse.node_count()) + ")");
      const auto ij = coarse.node_ij[static_cast<std::size_t>(n - 1)];
      return {refined_index(ij[0], times), refined_index(ij[1], times)};
    };
    const auto m = node_ij(c.node_m), n = node_ij(c.node_n);
    const int di = (n[0] - m[0]) / steps, dj = (n[1] - m[1]) / steps;
    for (int k = 0; k < steps; ++k) {
      EdgeCard piece = c;
      piece.node_m   = fine.node(m[0] + k * di, m[1] + k * dj) + 1;
      piece.node_n   = fine.node(m[0] + (k + 1) * di, m[1] + (k + 1) * dj) + 1;
      if (piece.node_m < 1 || piece.node_n < 1)
        throw InputError(c.ref.where() + ": nodes " + std::to_string(c.node_m) + " and " +
                         std::to_string(c.node_n) + " are not the ends of an element edge");
      out.push_back(piece);
    }
  }
  return out;
}

}  // namespace detail

/// Throws InputError when `d`'s grid cannot be refined: its gap elements (see the top).
inline void refinable(const Deck& d) {
  if (d.options.format != DeckFormat::elastic)
    for (const MaterialBlockCard& b : d.blocks)
      if (b.material == 2)
        throw InputError(
            "--estimate: the gap elements of this deck (material 2, " + b.ref.where() +
            ") are not refined yet (a gap layer one cell thick would become several gap elements "
            "in series)");
}

/// `d`'s model on its grid refined `times` (>= 1) times, and that model's scene; `coarse` is the grid of `d`
/// itself (its scene's). Throws InputError for a deck with gap elements, and for a refined grid past
/// `limits`.
inline RefinedDeck refine_deck(const Deck& d, const IJGrid& coarse, int times,
                               const InputLimits& limits = {}) {
  refinable(d);
  RefinedDeck out{d, {}};
  Deck& f          = out.deck;
  const auto index = [&](int i) { return refined_index(i, times); };
  f.mesh.max_i = index(d.mesh.max_i), f.mesh.max_j = index(d.mesh.max_j);
  if (static_cast<double>(f.mesh.max_i) * f.mesh.max_j > static_cast<double>(limits.max_grid_points))
    throw InputError("a finer mesh of this deck: its grid, " + std::to_string(f.mesh.max_i) + " x " +
                     std::to_string(f.mesh.max_j) + " points, is past the limit of " +
                     std::to_string(limits.max_grid_points));
  for (Segment& s : f.segments)
    for (GridPoint& p : s.p)
      if (p.i > 0 && p.j > 0) p.i = index(p.i), p.j = index(p.j);
  for (BoundaryCard& b : f.boundary)
    b.i1 = index(b.i1), b.i2 = index(b.i2), b.j1 = index(b.j1), b.j2 = index(b.j2), b.load_spacing <<= times;
  for (MaterialBlockCard& b : f.blocks)
    b.i1 = index(b.i1), b.i2 = index(b.i2), b.j1 = index(b.j1), b.j2 = index(b.j2), b.nang <<= times;
  IJGrid fine = generate_ij_grid(f.mesh.max_i, f.mesh.max_j, f.segments);
  for (LoadBlock& block : f.program.blocks)
    for (auto* cards : {&block.pressure, &block.shear, &block.transverse_shear})
      *cards = detail::refined_edges(*cards, coarse, fine, times);
  out.scene = build_scene(f, std::move(fine));
  return out;
}

}  // namespace gapfe

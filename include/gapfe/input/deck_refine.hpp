#pragma once
// A deck's model on a finer mesh, for the meshes of `gapfe run --estimate` (docs/accuracy.md "Error bars"):
// its I-J grid with every cell split into 2^times x 2^times, generated from the same cards. Grid line I of
// the deck becomes line RefinedIndices::i[I] of the finer grid, 2^times lines on from the last, and likewise
// J; except across a gap layer: the interval a gap element closes across (its IJDIR, or the deck's one LGAP)
// stays one cell, because a gap layer split into several gap elements in series would be another model. Every
// card keeps its meaning:
//   * a segment card places the same points (the finer grid's points between them evenly in index along
//     lines, in angle along arcs; a line across a gap layer is split there); the Laplace fill covers the
//     rest;
//   * a material block covers the cells of its old cells (IANG flips the sign every NANG of the old ones);
//   * a BC card prescribes its displacements at every grid point of its rectangle, the new ones between too
//   (an
//     edge held stays held all along), and its forces at the deck's own points only (Deck::own_i, own_j): a
//     ring load stays one ring load;
//   * an edge load card (Data 13-15) loads the edges its edge became, with the same traction;
//   * temperature cards give (r, z) points and stay as they are.
#include <algorithm>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "gapfe/input/deck_cards.hpp"
#include "gapfe/input/deck_scene.hpp"
#include "gapfe/mesh/ij_generator.hpp"

namespace gapfe {

/// A deck's grid lines on the finer grid: i[I] is the finer index of line I (i[0] unused), likewise j.
struct RefinedIndices {
  std::vector<int> i, j;
};

/// The refined deck and its scene, built on the refined grid.
struct RefinedDeck {
  Deck deck;
  Scene scene;
  RefinedIndices index;
};

namespace detail {

/// Line k of 1..count on the finer grid: 2^times intervals from line k to k + 1, one where `kept[k]`.
inline std::vector<int> refined_lines(int count, const std::vector<char>& kept, int times) {
  std::vector<int> line(static_cast<std::size_t>(count) + 1, 0);
  line[1] = 1;
  for (int k = 1; k < count; ++k)
    line[static_cast<std::size_t>(k) + 1] = line[static_cast<std::size_t>(k)] + (kept[k] ? 1 : 1 << times);
  return line;
}

/// Whether a segment's index path crosses a kept interval along I or J (its lines do not step evenly there).
inline bool crosses_kept(const GridPoint& a, const GridPoint& b, const std::vector<char>& kept_i,
                         const std::vector<char>& kept_j) {
  for (int k = std::min(a.i, b.i); k < std::max(a.i, b.i); ++k)
    if (kept_i[k]) return true;
  for (int k = std::min(a.j, b.j); k < std::max(a.j, b.j); ++k)
    if (kept_j[k]) return true;
  return false;
}

/// The segment cards on the finer grid, into `out` (each with its card's reference, into `out_refs`): each
/// point moved to its line; a line (type 1) across a kept interval split into lines between the intervals'
/// ends, its points there where the deck's grid put them (evenly in index). Other types across one are
/// refused (their steps could not stay even).
inline void refined_segments(const std::vector<Segment>& segments, const std::vector<CardRef>& refs,
                             const RefinedIndices& f, const std::vector<char>& kept_i,
                             const std::vector<char>& kept_j, std::vector<Segment>& out,
                             std::vector<CardRef>& out_refs) {
  out.clear(), out_refs.clear();
  const auto moved = [&](GridPoint p) {
    if (p.i >= 1 && p.i < static_cast<int>(f.i.size()) && p.j >= 1 && p.j < static_cast<int>(f.j.size()))
      p.i = f.i[static_cast<std::size_t>(p.i)], p.j = f.j[static_cast<std::size_t>(p.j)];
    return p;  // an unused point (an arc's centre) keeps its indices
  };
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const Segment& c  = segments[s];
    const GridPoint a = c.p[0], b = c.type == SegmentType::arc_three_points ? c.p[2] : c.p[1];
    if (c.type == SegmentType::point || !crosses_kept(a, b, kept_i, kept_j)) {
      Segment m = c;
      for (GridPoint& p : m.p) p = moved(p);
      out.push_back(m), out_refs.push_back(refs[s]);
      continue;
    }
    if (c.type != SegmentType::line || (a.i != b.i && a.j != b.j))  // a diagonal's steps stay equal
      throw InputError(refs[s].where() +
                       ": this segment card crosses a gap layer, which stays one cell thick on the "
                       "finer meshes; only a line along I or J (type 1) can be split there");
    const int steps = std::max(std::abs(b.i - a.i), std::abs(b.j - a.j));
    const int di = (b.i - a.i) / steps, dj = (b.j - a.j) / steps;
    int from             = 0;
    const auto kept_step = [&](int n) {  // whether the step from point n to n + 1 crosses a kept interval
      const int i = a.i + n * di, j = a.j + n * dj;
      return (di != 0 && kept_i[std::min(i, i + di)]) || (dj != 0 && kept_j[std::min(j, j + dj)]);
    };
    for (int k = 1; k <= steps; ++k) {  // a piece ends before and after every kept interval, and at b
      if (k < steps && !kept_step(k - 1) && !kept_step(k)) continue;
      const auto at = [&](int n) {
        return GridPoint{a.i + n * di, a.j + n * dj,
                         n == steps ? b.x : Vec2(a.x + (b.x - a.x) * (static_cast<double>(n) / steps))};
      };
      Segment piece;
      piece.type = SegmentType::line;
      piece.p[0] = moved(at(from)), piece.p[1] = moved(at(k));
      out.push_back(piece), out_refs.push_back(refs[s]);
      from = k;
    }
  }
}

/// The edge cards of `cards` on the finer grid: each edge of the deck's grid (nodes numbered 1-based on
/// `coarse`) becomes the edges of `fine` along it.
inline std::vector<EdgeCard> refined_edges(const std::vector<EdgeCard>& cards, const IJGrid& coarse,
                                           const IJGrid& fine, const RefinedIndices& f) {
  std::vector<EdgeCard> out;
  for (const EdgeCard& c : cards) {
    const auto node_ij = [&](int n) -> std::array<int, 2> {
      if (n < 1 || n > coarse.node_count())  // build_scene names it with its columns on the deck's grid
        throw InputError(c.ref.where() + ": node " + std::to_string(n) + " is not a node of the mesh (1 to " +
                         std::to_string(coarse.node_count()) + ")");
      const auto ij = coarse.node_ij[static_cast<std::size_t>(n - 1)];
      return {f.i[static_cast<std::size_t>(ij[0])], f.j[static_cast<std::size_t>(ij[1])]};
    };
    const auto m = node_ij(c.node_m), n = node_ij(c.node_n);
    const int si = n[0] - m[0], sj = n[1] - m[1], steps = std::max(std::abs(si), std::abs(sj));
    if (steps == 0 || (si != 0 && sj != 0 && std::abs(si) != std::abs(sj)))
      throw InputError(c.ref.where() + ": nodes " + std::to_string(c.node_m) + " and " +
                       std::to_string(c.node_n) +
                       " are not the ends of an element edge the finer meshes keep");
    const int di = si / steps, dj = sj / steps;
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

/// The intervals the gap elements of a deck's scene close across, along I and J (kept[k]: from line k to
/// k + 1), which the finer meshes keep one cell (see the top).
inline std::pair<std::vector<char>, std::vector<char>> gap_layers(const Deck& d, const Scene& coarse) {
  std::vector<char> kept_i(static_cast<std::size_t>(d.mesh.max_i) + 1, 0),
      kept_j(static_cast<std::size_t>(d.mesh.max_j) + 1, 0);
  const IJGrid& g = coarse.grid;
  for (std::size_t e = 0; e < g.cells.size() && e < coarse.gaps.direction.size(); ++e) {
    const int dir = coarse.gaps.direction[e];
    if (dir == 1) kept_i[static_cast<std::size_t>(g.cells[e].i)] = 1;
    if (dir == 2) kept_j[static_cast<std::size_t>(g.cells[e].j)] = 1;
  }
  return {std::move(kept_i), std::move(kept_j)};
}

namespace detail {

/// The deck's grid line at or below finer line `k` (lines: RefinedIndices::i or j).
inline int line_below(const std::vector<int>& lines, int k) {
  return static_cast<int>(std::upper_bound(lines.begin() + 1, lines.end(), k) - lines.begin()) - 1;
}

/// Refuses a finer grid that does not fill every quadrilateral of the deck's (rows placed only at the deck's
/// own lines leave the finer rows between them empty), and one whose gap elements have corners no segment
/// card places (the Laplace fill spreads those anew on each grid, and a gap of 0.02 between two placed faces
/// would come out another size).
inline void check_fine_points(const IJGrid& coarse, const IJGrid& fine, const RefinedIndices& index,
                              const std::vector<int>& gap_direction) {
  for (std::size_t e = 0; e < coarse.cells.size(); ++e) {
    const GridCell& c = coarse.cells[e];
    if (c.corners != 4) continue;  // a triangle's finer points follow its diagonal
    const bool gap = e < gap_direction.size() && gap_direction[e] != 0;
    const int i0 = index.i[static_cast<std::size_t>(c.i)], i1 = index.i[static_cast<std::size_t>(c.i) + 1];
    const int j0 = index.j[static_cast<std::size_t>(c.j)], j1 = index.j[static_cast<std::size_t>(c.j) + 1];
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const int n = fine.node(i, j);
        if (n < 0)
          throw InputError("element " + std::to_string(e + 1) + " " + ij_text(c.i, c.j) +
                           ": no segment card places the ends of the finer grid's rows inside it (give the "
                           "sides as segment cards along J as well as along I)");
        const bool on_face = gap && (gap_direction[e] == 1 ? (i == i0 || i == i1) : (j == j0 || j == j1));
        if (on_face && !fine.placed[static_cast<std::size_t>(n)])
          throw InputError("gap element " + std::to_string(e + 1) + " " + ij_text(c.i, c.j) +
                           ": a corner of its pieces on the finer grid is placed by no segment card; the "
                           "Laplace fill would put it elsewhere and the gap would change (place the gap's "
                           "faces with line segment cards)");
      }
  }
}

/// Refuses a finer grid whose gap elements close another way than the deck's they split: `fine` against
/// `coarse` through `index`.
inline void check_gap_layout(const Scene& coarse, const Scene& fine, const RefinedIndices& index) {
  std::map<std::pair<int, int>, int> coarse_cell;  // (I, J) of a deck's gap element -> its direction
  for (std::size_t e = 0; e < coarse.grid.cells.size() && e < coarse.gaps.direction.size(); ++e)
    if (coarse.material_id[e] == 2)
      coarse_cell[{coarse.grid.cells[e].i, coarse.grid.cells[e].j}] = coarse.gaps.direction[e];
  for (std::size_t e = 0; e < fine.grid.cells.size() && e < fine.gaps.direction.size(); ++e) {
    if (fine.material_id[e] != 2) continue;
    const GridCell& c = fine.grid.cells[e];
    const auto it     = coarse_cell.find({line_below(index.i, c.i), line_below(index.j, c.j)});
    if (it == coarse_cell.end() || it->second == fine.gaps.direction[e]) continue;
    throw InputError(
        "the deck's gap element at " + ij_text(it->first.first, it->first.second) +
        (it->second == 0 ? " is soft (a corner, a 3-corner cell or IJDIR 0), but its pieces on a finer "
                           "grid would close"
         : fine.gaps.direction[e] == 0
             ? " closes, but its pieces on a finer grid would be soft (corners of a thicker gap layer)"
             : " would close another way on a finer grid"));
  }
}

}  // namespace detail

/// An I-J grid's lines and segment cards on the grid refined `times` (>= 1) times, the intervals `kept_i`
/// and `kept_j` one cell (see the top); its size checked against `limits`.
struct RefinedCards {
  RefinedIndices index;
  int max_i = 0, max_j = 0;
  std::vector<Segment> segments;
  std::vector<CardRef> refs;
};
inline RefinedCards refine_cards(int max_i, int max_j, const std::vector<Segment>& segments,
                                 const std::vector<CardRef>& refs, const std::vector<char>& kept_i,
                                 const std::vector<char>& kept_j, int times, const InputLimits& limits) {
  RefinedCards out;
  out.index = {detail::refined_lines(max_i, kept_i, times), detail::refined_lines(max_j, kept_j, times)};
  out.max_i = out.index.i.back(), out.max_j = out.index.j.back();
  if (static_cast<double>(out.max_i) * out.max_j > static_cast<double>(limits.max_grid_points))
    throw InputError("the finer grid, " + std::to_string(out.max_i) + " x " + std::to_string(out.max_j) +
                     " points, is past the limit of " + std::to_string(limits.max_grid_points));
  detail::refined_segments(segments, refs, out.index, kept_i, kept_j, out.segments, out.refs);
  return out;
}

/// `d`'s model on its grid refined `times` (>= 1) times, and that model's scene; `coarse` is `d`'s own scene.
/// Throws InputError when a card cannot keep its meaning (a segment card other than a line along I or J
/// across a gap layer, a gap whose faces no card places, a gap element that would close another way) and for
/// a refined grid past `limits`.
inline RefinedDeck refine_deck(const Deck& d, const Scene& coarse, int times,
                               const InputLimits& limits = {}) {
  const IJGrid& g             = coarse.grid;
  const auto [kept_i, kept_j] = gap_layers(d, coarse);
  RefinedCards grid =
      refine_cards(d.mesh.max_i, d.mesh.max_j, d.segments, d.segment_refs, kept_i, kept_j, times, limits);
  RefinedDeck out{d, {}, std::move(grid.index)};
  Deck& f           = out.deck;
  const auto& index = out.index;
  f.mesh.max_i = grid.max_i, f.mesh.max_j = grid.max_j;
  f.segments = std::move(grid.segments), f.segment_refs = std::move(grid.refs);
  const auto box = [&](int& i1, int& i2, int& j1, int& j2) {
    const auto line = [](const std::vector<int>& lines, int k) {  // a card's index past the grid: its end
      const int last = static_cast<int>(lines.size()) - 1;
      return lines[static_cast<std::size_t>(std::clamp(k, 1, last))] + std::max(k - last, 0);
    };
    i1 = line(index.i, i1), i2 = line(index.i, i2), j1 = line(index.j, j1), j2 = line(index.j, j2);
  };
  for (BoundaryCard& b : f.boundary) box(b.i1, b.i2, b.j1, b.j2);
  for (MaterialBlockCard& b : f.blocks) box(b.i1, b.i2, b.j1, b.j2);
  f.own_i = std::vector<int>(index.i.begin() + 1, index.i.end());
  f.own_j = std::vector<int>(index.j.begin() + 1, index.j.end());
  IJGrid fine;
  try {
    fine = deck_grid(f);
  } catch (const InputError& e) {
    throw InputError(
        std::string(e.what()) +
        " (on the finer grid, do the deck's cards place the ends of every row and column, along J as "
        "well as along I?)");
  }
  detail::check_fine_points(g, fine, index, coarse.gaps.direction);
  for (LoadBlock& block : f.program.blocks)
    for (auto* cards : {&block.pressure, &block.shear, &block.transverse_shear})
      *cards = detail::refined_edges(*cards, g, fine, index);
  out.scene = build_scene(f, std::move(fine));
  detail::check_gap_layout(coarse, out.scene, index);
  return out;
}

}  // namespace gapfe

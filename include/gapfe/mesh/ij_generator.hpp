#pragma once
// The I-J mesh generator (seed section 2.4, docs/theory.md 9): the segment cards' points placed, the nodes
// numbered row by row, the interior filled by the discrete Laplace equation, the cells built and checked.
// Included at the end of mesh/ij_grid.hpp, whose types it fills.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "gapfe/mesh/grid_laplace.hpp"
#include "gapfe/mesh/ij_grid.hpp"

namespace gapfe {

namespace detail {

/// The grid's row limits (MNIMX) entry of row j.
inline int& row_entry(std::vector<int>& v, const IJGrid& g, int j) {
  return v[static_cast<std::size_t>(j - g.j0)];
}

/// Place the points of every segment card (POINTS, CIRCLE) into `x` (the index box's points), marking them
/// in `fixed`.
inline void place_segment_points(const IJGrid& g, const std::vector<Segment>& segments,
                                 const std::vector<IndexPath>& paths, std::vector<Vec2>& x,
                                 std::vector<char>& fixed) {
  const auto at = [&](int i, int j) { return g.box_index(i, j); };
  // ---- place the points of every segment card (POINTS, CIRCLE)
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const int card   = static_cast<int>(s) + 1;
    const Segment& c = segments[s];
    const auto put   = [&](int i, int j, const Vec2& v) { x[at(i, j)] = v, fixed[at(i, j)] = 1; };
    if (c.type == SegmentType::point) {
      put(c.p[0].i, c.p[0].j, c.p[0].x);
      continue;
    }
    const GridPoint& a = c.p[0];
    const GridPoint& b = c.type == SegmentType::arc_three_points ? c.p[2] : c.p[1];
    const int di = paths[s].di, dj = paths[s].dj, n = paths[s].steps;
    if (c.type == SegmentType::arc_three_points || c.type == SegmentType::arc_centre) {
      Vec2 centre;
      double sweep      = 0;
      const double from = angle_of(a.x - (centre = c.type == SegmentType::arc_centre
                                                       ? c.p[2].x
                                                       : circumcentre(a.x, c.p[1].x, b.x, card)));
      const double to   = angle_of(b.x - centre);
      const double ra = (a.x - centre).norm(), rb = (b.x - centre).norm();
      if (!(ra > 0 && rb > 0)) throw InputError(grid_where(card) + ": an arc end lies on its centre");
      if (c.type == SegmentType::arc_centre) {
        // Ends read from F8.3 fields: allow the radii to differ by card rounding, not more.
        if (std::abs(ra - rb) > 2e-3 * std::max(ra, rb) + 1e-3)
          throw InputError(grid_where(card) +
                           ": the arc's ends are at different distances from its "
                           "centre (" +
                           std::to_string(ra) + " and " + std::to_string(rb) + ")");
        sweep = ccw_sweep(from, to);  // the seed: counterclockwise from the 1st to the 2nd point
      } else {
        // The arc from the 1st to the 3rd point that passes through the 2nd, in whichever sense.
        const double s13 = ccw_sweep(from, to), s12 = ccw_sweep(from, angle_of(c.p[1].x - centre));
        sweep = s12 < s13 ? s13 : s13 - kTwoPi;
      }
      if (!(std::abs(sweep) > 1e-12)) throw InputError(grid_where(card) + ": the arc has zero sweep");
      for (int k = 0; k <= n; ++k) {
        const double f = static_cast<double>(k) / n, phi = from + f * sweep, rad = ra + f * (rb - ra);
        put(a.i + k * di, a.j + k * dj,
            k == 0   ? a.x
            : k == n ? b.x
                     : Vec2(centre + rad * Vec2(std::cos(phi), std::sin(phi))));
      }
    } else {
      for (int k = 0; k <= n; ++k) {
        const double f = static_cast<double>(k) / n;
        put(a.i + k * di, a.j + k * dj, k == n ? b.x : Vec2(a.x + f * (b.x - a.x)));
      }
    }
  }
}

/// Row limits (MNIMX) and node numbering: J ascending, I ascending within a row, over the points placed.
inline void number_nodes(IJGrid& g, const std::vector<Vec2>& x, const std::vector<char>& fixed) {
  const auto at            = [&](int i, int j) { return g.box_index(i, j); };
  const std::size_t points = g.box_points();
  // ---- row limits (MNIMX) and node numbering: J ascending, I ascending within a row
  const int i_end = g.i0 + g.box_i, j_end = g.j0 + g.box_j;  // one past the box
  g.row_min.assign(static_cast<std::size_t>(g.box_j), 0),
      g.row_max.assign(static_cast<std::size_t>(g.box_j), -1);
  const auto row = [&](std::vector<int>& v, int j) -> int& { return v[static_cast<std::size_t>(j - g.j0)]; };
  for (int j = g.j0; j < j_end; ++j)
    for (int i = g.i0; i < i_end; ++i)
      if (fixed[at(i, j)]) {
        if (row(g.row_max, j) < 0) row(g.row_min, j) = i;
        row(g.row_max, j) = i;
      }
  g.node_at.assign(points, -1);
  // Reserved to the exact count: at 1e6 points a growing vector's copies are fresh memory to touch.
  std::size_t node_count = 0;
  for (int j = g.j0; j < j_end; ++j)
    node_count += static_cast<std::size_t>(row(g.row_max, j) - row(g.row_min, j) + 1);
  g.nodes.reserve(node_count), g.node_ij.reserve(node_count), g.placed.reserve(node_count);
  for (int j = g.j0; j < j_end; ++j)
    for (int i = row(g.row_min, j); i <= row(g.row_max, j); ++i) {
      g.node_at[at(i, j)] = static_cast<int>(g.nodes.size());
      g.nodes.push_back(x[at(i, j)]);
      g.node_ij.push_back({i, j});
      g.placed.push_back(fixed[at(i, j)]);
    }
}

/// The interior points: the discrete Laplace equation on the index lattice (grid_laplace.hpp), from `x`.
inline void fill_interior(IJGrid& g, std::vector<Vec2>& x) {
  const auto at            = [&](int i, int j) { return g.box_index(i, j); };
  const std::size_t points = g.box_points();
  const int j_end          = g.j0 + g.box_j;
  const auto row           = [&](std::vector<int>& v, int j) -> int& { return row_entry(v, g, j); };
  // ---- interior points: the discrete Laplace equation on the index lattice (grid_laplace.hpp)
  if (std::find(g.placed.begin(), g.placed.end(), 0) != g.placed.end()) {
    std::vector<char> state(points, GridLaplace::absent);
    std::vector<Vec2> rhs(points, Vec2::Zero());
    for (std::size_t n = 0; n < g.nodes.size(); ++n) {
      const auto [i, j] = g.node_ij[n];
      state[at(i, j)]   = g.placed[n] ? GridLaplace::fixed : GridLaplace::unknown;
    }
    for (std::size_t n = 0; n < g.nodes.size(); ++n) {
      if (g.placed[n]) continue;
      const auto [i, j] = g.node_ij[n];
      for (const auto& [oi, oj] : {std::array{-1, 0}, std::array{1, 0}, std::array{0, -1}, std::array{0, 1}})
        if (const int q = g.node(i + oi, j + oj); q >= 0 && g.placed[q]) rhs[at(i, j)] += g.nodes[q];
    }
    // Initial guess, written into x (zero at the unknowns so far): linear in I between the nearest
    // placed points of the row (exact for straight top and bottom boundaries, and close for gentle
    // curves), which saves most CG iterations.
    for (int j = g.j0; j < j_end; ++j) {
      int left = 0;
      for (int i = row(g.row_min, j); i <= row(g.row_max, j); ++i) {
        if (g.placed[g.node(i, j)]) {
          if (left > 0 && i > left + 1)
            for (int k = left + 1; k < i; ++k)
              x[at(k, j)] = x[at(left, j)] + (x[at(i, j)] - x[at(left, j)]) * (k - left) / (i - left);
          left = i;
        }
      }
    }
    GridLaplace laplace(g.box_i, g.box_j, state);
    laplace.solve(rhs, x);
    for (std::size_t n = 0; n < g.nodes.size(); ++n)
      if (!g.placed[n]) g.nodes[n] = x[at(g.node_ij[n][0], g.node_ij[n][1])];
  }
  for (std::size_t n = 0; n < g.nodes.size(); ++n)
    if (!g.nodes[n].allFinite())
      throw InputError("mesh: grid point " + std::to_string(g.node_ij[n][0]) + ", " +
                       std::to_string(g.node_ij[n][1]) +
                       " has a non-finite position (coordinates too large?)");
}

/// The cells in numbering order (a cell needs three or four existing corners), oriented counterclockwise
/// and each checked for a positive area at every corner.
inline void build_cells(IJGrid& g, int max_i) {
  const int j_end = g.j0 + g.box_j;
  const auto row  = [&](std::vector<int>& v, int j) -> int& { return row_entry(v, g, j); };
  // ---- cells in numbering order; a cell needs three or four existing corners
  double total_area     = 0;
  const auto twice_area = [&](const std::array<int, 4>& v, int count) {
    double a = 0;
    for (int k = 0; k < count; ++k) {
      const Vec2& p = g.nodes[v[k]];
      const Vec2& q = g.nodes[v[(k + 1) % count]];
      a += p(0) * q(1) - q(0) * p(1);
    }
    return a;
  };
  int quads = 0, triangles = 0;
  g.cells.reserve(g.nodes.size());  // at most (a cell per node but the last row's and column's)
  for (int j = g.j0; j + 1 < j_end; ++j) {
    const int lo = std::min(row(g.row_min, j) > 0 ? row(g.row_min, j) : max_i,
                            row(g.row_min, j + 1) > 0 ? row(g.row_min, j + 1) : max_i);
    const int hi = std::max(row(g.row_max, j), row(g.row_max, j + 1));
    for (int i = lo; i < hi; ++i) {
      GridCell cell;
      cell.i = i, cell.j = j, cell.corners = 0;
      for (const int q : {g.node(i, j), g.node(i + 1, j), g.node(i + 1, j + 1), g.node(i, j + 1)})
        if (q >= 0) cell.node[cell.corners++] = q;
      if (cell.corners < 3) continue;
      cell.group_index = cell.corners == 4 ? quads++ : triangles++;
      total_area += twice_area(cell.node, cell.corners);
      g.cells.push_back(cell);
    }
  }
  if (g.cells.empty()) throw InputError("mesh: the grid has no cells (every cell lacks corners)");
  g.reversed = total_area < 0;
  for (std::size_t e = 0; e < g.cells.size(); ++e) {
    GridCell& c = g.cells[e];
    if (g.reversed) std::reverse(c.node.begin(), c.node.begin() + c.corners);
    // Every corner's triangle must be positive: this catches folded and bow-tie quadrilaterals.
    double smallest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < c.corners; ++k) {
      const Vec2 a = g.nodes[c.node[(k + c.corners - 1) % c.corners]], b = g.nodes[c.node[k]],
                 d = g.nodes[c.node[(k + 1) % c.corners]];
      const Vec2 u = d - b, v = a - b;
      smallest = std::min(smallest, u(0) * v(1) - u(1) * v(0));
    }
    if (!(smallest > 0))
      throw InputError("mesh: element " + std::to_string(e + 1) + " (I = " + std::to_string(c.i) +
                       ", J = " + std::to_string(c.j) +
                       ") has zero or negative area: the line segment "
                       "cards cross, a boundary is concave beyond what the Laplace fill can follow, or "
                       "points coincide");
  }
}

}  // namespace detail

/// Build the grid. `max_i`, `max_j`: MAXI, MAXJ (Data 3). Throws InputError naming the card (1-based
/// in `segments`) or the element for indices out of range, malformed segments, grid points without
/// neighbours and cells of zero or negative area.
inline IJGrid generate_ij_grid(int max_i, int max_j, const std::vector<Segment>& segments) {
  if (max_i < 1 || max_j < 1)
    throw InputError("mesh: MAXI and MAXJ must be >= 1, got " + std::to_string(max_i) + " and " +
                     std::to_string(max_j));
  IJGrid g;
  g.max_i = max_i, g.max_j = max_j;
  std::vector<detail::IndexPath> paths;
  for (std::size_t s = 0; s < segments.size(); ++s)
    paths.push_back(detail::index_path(segments[s], static_cast<int>(s) + 1, max_i, max_j));
  detail::grid_box(g, paths);
  const std::size_t points = g.box_points();
  std::vector<Vec2> x(points, Vec2::Zero());
  std::vector<char> fixed(points, 0);
  detail::place_segment_points(g, segments, paths, x, fixed);
  detail::number_nodes(g, x, fixed);
  detail::fill_interior(g, x);
  detail::build_cells(g, max_i);
  return g;
}

}  // namespace gapfe

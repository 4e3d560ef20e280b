#pragma once
// The seed's structured I-J mesh generator (MESH, POINTS, MNIMX, ANGLE, CIRCLE; Appendix A Data 3-4;
// THEORY.md 9), usable without a deck.
//
// Line-segment cards place grid points (I, J) at (r, z): a point (type 0), straight lines (1; 2 an
// internal diagonal; 5 and 6 boundary diagonals on the row-minimum and row-maximum side) with points
// evenly spaced in index, and circular arcs (3: through three points; 4: by its ends and centre)
// with points evenly spaced in angle. Row J then spans IMIN(J) <= I <= IMAX(J), the smallest and
// largest I placed in that row. Points no card placed solve the discrete Laplace equation on the
// index grid (each the mean of its existing neighbours among the four), solved by multigrid-
// preconditioned conjugate gradients (grid_laplace.hpp) instead of the seed's relaxation sweeps.
//
// Numbering (users' load cards refer to it): nodes J ascending, then I ascending within a row, so a
// full NI x NJ grid has node (I, J) = (J - 1) NI + I (1-based). Element (I, J) is the cell with
// corners (I, J), (I+1, J), (I+1, J+1), (I, J+1) (IX(N, 1..4), counterclockwise when I runs with r
// and J with z), numbered the same way. A cell with exactly three existing corners (beside a
// type 5/6 boundary diagonal, where IMIN or IMAX shifts between rows) is a triangle of those three.
// When I runs with z the whole grid is clockwise and every cell's corner order is reversed.
// Indices are 1-based here, as on the cards; node and element numbers are 0-based in memory.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/mesh/grid_laplace.hpp"
#include "gapfe/mesh/mesh.hpp"

namespace gapfe {

/// A grid index with its position [length].
struct GridPoint {
  int i = 0, j = 0;
  Vec2 x = Vec2::Zero();
};

/// Line-segment card types (seed Data 4, column 71).
enum class SegmentType : int {
  point             = 0,
  line              = 1,
  internal_diagonal = 2,
  arc_three_points  = 3,  ///< p[0] and p[2] the ends, p[1] on the arc (the seed: its midpoint)
  arc_centre        = 4,  ///< p[0] to p[1] counterclockwise about the centre p[2].x (p[2].i, .j unused)
  min_diagonal      = 5,  ///< boundary diagonal on the row-minimum (IMIN) side
  max_diagonal      = 6,  ///< boundary diagonal on the row-maximum (IMAX) side
};

struct Segment {
  std::array<GridPoint, 3> p{};
  SegmentType type = SegmentType::point;
};

/// One element of the grid, in numbering order.
struct GridCell {
  int i = 0, j = 0;           ///< index of its lower-left corner (I, J)
  int corners = 4;            ///< 4: quadrilateral; 3: triangle
  std::array<int, 4> node{};  ///< node numbers, counterclockwise; node[3] unused for triangles
  int group_index = 0;        ///< index into Mesh::cells (quad) or Mesh::triangles (triangle)
};

struct IJGrid {
  int max_i = 0, max_j = 0;
  /// The index box the line segment cards reach, I in [i0, i0 + box_i), J in [j0, j0 + box_j): every node
  /// lies in it, and the per-point arrays below span it, not MAXI x MAXJ (memory follows what the cards
  /// place).
  int i0 = 1, j0 = 1, box_i = 0, box_j = 0;
  std::vector<int> row_min, row_max;        ///< IMIN(J), IMAX(J) at [J - j0]; 0, -1 for an empty row
  std::vector<int> node_at;                 ///< node at box_index(I, J), -1 when absent
  std::vector<Vec2> nodes;                  ///< (r, z) [length]
  std::vector<std::array<int, 2>> node_ij;  ///< (I, J) of every node
  std::vector<char> placed;                 ///< 1 when a segment card placed the node
  std::vector<GridCell> cells;              ///< elements in numbering order
  bool reversed = false;                    ///< I runs with z: corner order reversed to keep cells CCW

  int node_count() const { return static_cast<int>(nodes.size()); }
  bool inside(int i, int j) const { return i >= 1 && i <= max_i && j >= 1 && j <= max_j; }
  bool in_box(int i, int j) const { return i >= i0 && i < i0 + box_i && j >= j0 && j < j0 + box_j; }
  /// Points of the box, and the index of (I, J) in it (for per-point arrays); (I, J) must lie in the box.
  std::size_t box_points() const { return static_cast<std::size_t>(box_i) * static_cast<std::size_t>(box_j); }
  std::size_t box_index(int i, int j) const { return static_cast<std::size_t>(j - j0) * box_i + (i - i0); }
  /// Node number (0-based) at (I, J), -1 when that grid point does not exist.
  int node(int i, int j) const { return in_box(i, j) ? node_at[box_index(i, j)] : -1; }
  /// [I1, I2] x [J1, J2] (a card's index rectangle) cut to the box, where every grid point lies: its
  /// loops then follow the grid, not MAXI x MAXJ. An empty cut has lo > hi.
  std::array<int, 4> box_cut(int i1, int i2, int j1, int j2) const {
    return {std::max(i1, i0), std::min(i2, i0 + box_i - 1), std::max(j1, j0), std::min(j2, j0 + box_j - 1)};
  }

  /// The grid as a finite-element mesh: quadrilaterals as cells, 3-corner cells as triangles.
  Mesh<4> to_mesh() const {
    Mesh<4> m;
    m.nodes = nodes;
    for (const auto& c : cells) {
      if (c.corners == 4)
        m.cells.push_back(c.node);
      else
        m.triangles.push_back({c.node[0], c.node[1], c.node[2]});
    }
    return m;
  }
};

namespace detail {

inline std::string grid_where(int card) {
  return "line segment card " + std::to_string(card);
}

/// Index path of a straight or arc segment from a to b: a row, a column or a 45-degree diagonal.
inline int index_steps(const GridPoint& a, const GridPoint& b, int card, int& di, int& dj) {
  const int Di = b.i - a.i, Dj = b.j - a.j;
  const int n = std::max(std::abs(Di), std::abs(Dj));
  if (n == 0)
    throw InputError(grid_where(card) + ": both ends have the same index (" + std::to_string(a.i) + ", " +
                     std::to_string(a.j) + "); use type 0 for a single point");
  if (Di != 0 && Dj != 0 && std::abs(Di) != std::abs(Dj))
    throw InputError(grid_where(card) + ": from (" + std::to_string(a.i) + ", " + std::to_string(a.j) +
                     ") to (" + std::to_string(b.i) + ", " + std::to_string(b.j) +
                     ") is neither a row, a column nor a 45-degree diagonal in index space");
  di = Di / n, dj = Dj / n;
  return n;
}

/// Centre of the circle through three points; throws when they are (nearly) collinear.
inline Vec2 circumcentre(const Vec2& a, const Vec2& b, const Vec2& c, int card) {
  const Vec2 ab = b - a, ac = c - a;
  const double d     = 2.0 * (ab(0) * ac(1) - ab(1) * ac(0));
  const double scale = std::max(ab.squaredNorm(), ac.squaredNorm());
  if (!(std::abs(d) > 1e-12 * scale) || !(scale > 0))
    throw InputError(grid_where(card) + ": the three points of the type 3 arc are collinear or coincide");
  const double b2 = ab.squaredNorm(), c2 = ac.squaredNorm();
  return a + Vec2(ac(1) * b2 - ab(1) * c2, ab(0) * c2 - ac(0) * b2) / d;
}

inline double angle_of(const Vec2& v) {
  return std::atan2(v(1), v(0));
}
inline double ccw_sweep(double from, double to) {  // in [0, 2 pi)
  double s = std::fmod(to - from, kTwoPi);
  return s < 0 ? s + kTwoPi : s;
}

}  // namespace detail

namespace detail {

/// Where a line segment card's points go in index space: its first point, the step (di, dj) and the number
/// of steps (0 for a single point). Checks the card's type, indices and coordinates first.
struct IndexPath {
  GridPoint from;
  int di = 0, dj = 0, steps = 0;
};
inline IndexPath index_path(const Segment& c, int card, int max_i, int max_j) {
  const int t = static_cast<int>(c.type);
  if (t < 0 || t > 6)
    throw InputError(grid_where(card) + ": segment type must be 0-6, got " + std::to_string(t));
  const int used = c.type == SegmentType::point ? 1 : c.type == SegmentType::arc_three_points ? 3 : 2;
  for (int k = 0; k < used; ++k) {
    const GridPoint& p = c.p[k];
    if (p.i < 1 || p.i > max_i || p.j < 1 || p.j > max_j)
      throw InputError(grid_where(card) + ": point " + std::to_string(k + 1) + " index (" +
                       std::to_string(p.i) + ", " + std::to_string(p.j) + ") is outside 1..MAXI = " +
                       std::to_string(max_i) + ", 1..MAXJ = " + std::to_string(max_j));
    if (!p.x.allFinite()) throw InputError(grid_where(card) + ": non-finite coordinate");
  }
  IndexPath path{c.p[0]};
  if (c.type != SegmentType::point)
    path.steps = index_steps(c.p[0], c.type == SegmentType::arc_three_points ? c.p[2] : c.p[1], card, path.di,
                             path.dj);
  return path;
}

/// The index box of the points the cards place, and the nodes their rows will hold (IMIN..IMAX of each
/// row): found from the cards alone, before anything per grid point is allocated, so that a deck's memory
/// follows what it places and not MAXI x MAXJ. A box far larger than its nodes (cards placing a few points
/// far apart in index) is refused: the generator fills the box.
inline void grid_box(IJGrid& g, const std::vector<IndexPath>& paths) {
  std::map<int, std::pair<int, int>> rows;  // J -> smallest and largest I placed
  int i0 = g.max_i, i1 = 1, j0 = g.max_j, j1 = 1;
  for (const IndexPath& p : paths)
    for (int k = 0; k <= p.steps; ++k) {
      const int i = p.from.i + k * p.di, j = p.from.j + k * p.dj;
      auto [row, fresh] = rows.try_emplace(j, i, i);
      if (!fresh)
        row->second.first  = std::min(row->second.first, i),
        row->second.second = std::max(row->second.second, i);
      i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
    }
  if (rows.empty()) throw InputError("mesh: the line segment cards place no points");
  double nodes = 0;
  for (const auto& [j, extent] : rows) nodes += extent.second - extent.first + 1;
  const double box = static_cast<double>(i1 - i0 + 1) * static_cast<double>(j1 - j0 + 1);
  // The generator's arrays span the box (about 20 bytes a point): up to 1e7 points beyond 4 per node
  // (200 MB) are allowed, so parts numbered far apart still mesh; a box far past its nodes is refused
  // before anything is allocated.
  if (box > 4 * nodes + 1e7)
    throw InputError(
        "mesh: the line segment cards place points across I " + std::to_string(i0) + "-" +
        std::to_string(i1) + ", J " + std::to_string(j0) + "-" + std::to_string(j1) + " (" +
        std::to_string(static_cast<long long>(box)) + " grid points) for " +
        std::to_string(static_cast<long long>(nodes)) +
        " nodes: the generator works on that index box; number the grid's parts closer together");
  g.i0 = i0, g.j0 = j0, g.box_i = i1 - i0 + 1, g.box_j = j1 - j0 + 1;
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
      double sweep = 0;
      const double from =
          detail::angle_of(a.x - (centre = c.type == SegmentType::arc_centre
                                               ? c.p[2].x
                                               : detail::circumcentre(a.x, c.p[1].x, b.x, card)));
      const double to = detail::angle_of(b.x - centre);
      const double ra = (a.x - centre).norm(), rb = (b.x - centre).norm();
      if (!(ra > 0 && rb > 0)) throw InputError(detail::grid_where(card) + ": an arc end lies on its centre");
      if (c.type == SegmentType::arc_centre) {
        // Ends read from F8.3 fields: allow the radii to differ by card rounding, not more.
        if (std::abs(ra - rb) > 2e-3 * std::max(ra, rb) + 1e-3)
          throw InputError(detail::grid_where(card) +
                           ": the arc's ends are at different distances from its "
                           "centre (" +
                           std::to_string(ra) + " and " + std::to_string(rb) + ")");
        sweep = detail::ccw_sweep(from, to);  // the seed: counterclockwise from the 1st to the 2nd point
      } else {
        // The arc from the 1st to the 3rd point that passes through the 2nd, in whichever sense.
        const double s13 = detail::ccw_sweep(from, to),
                     s12 = detail::ccw_sweep(from, detail::angle_of(c.p[1].x - centre));
        sweep            = s12 < s13 ? s13 : s13 - kTwoPi;
      }
      if (!(std::abs(sweep) > 1e-12)) throw InputError(detail::grid_where(card) + ": the arc has zero sweep");
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

  // ---- interior points: the discrete Laplace equation on the index lattice (grid_laplace.hpp)
  if (std::find(g.placed.begin(), g.placed.end(), 0) != g.placed.end()) {
    std::vector<char> state(points, detail::GridLaplace::absent);
    std::vector<Vec2> rhs(points, Vec2::Zero());
    for (std::size_t n = 0; n < g.nodes.size(); ++n) {
      const auto [i, j] = g.node_ij[n];
      state[at(i, j)]   = g.placed[n] ? detail::GridLaplace::fixed : detail::GridLaplace::unknown;
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
    detail::GridLaplace laplace(g.box_i, g.box_j, state);
    laplace.solve(rhs, x);
    for (std::size_t n = 0; n < g.nodes.size(); ++n)
      if (!g.placed[n]) g.nodes[n] = x[at(g.node_ij[n][0], g.node_ij[n][1])];
  }
  for (std::size_t n = 0; n < g.nodes.size(); ++n)
    if (!g.nodes[n].allFinite())
      throw InputError("mesh: grid point " + std::to_string(g.node_ij[n][0]) + ", " +
                       std::to_string(g.node_ij[n][1]) +
                       " has a non-finite position (coordinates too large?)");

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
  g.cells.reserve(node_count);  // at most (a cell per node but the last row's and column's)
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
  return g;
}

}  // namespace gapfe

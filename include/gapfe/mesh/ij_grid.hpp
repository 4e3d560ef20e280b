#pragma once
// The seed's structured I-J mesh generator (MESH, POINTS, MNIMX, ANGLE, CIRCLE; Appendix A Data 3-4;
// docs/theory.md 9), usable without a deck.
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
  /// The middle node of side k (corner k to k + 1) when the model runs quadratic cells
  /// (input/scene_quadratic.hpp); -1 otherwise.
  std::array<int, 4> mid{-1, -1, -1, -1};
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

}  // namespace gapfe

// The generator itself.
#include "gapfe/mesh/ij_generator.hpp"  // IWYU pragma: export

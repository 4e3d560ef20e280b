#pragma once
// Structured meshes of a rectangle [r0, r1] x [z0, z1] in the meridian plane, for tests, benchmarks
// and examples (the seed's I-J generator with line-segment cards lives in ij_grid.hpp).
// Numbering follows the seed: nodes row by row, J (z) ascending, I (r) fastest; cell (I, J) has
// corners (I,J), (I+1,J), (I+1,J+1), (I,J+1) counterclockwise.
#include <stdexcept>

#include "gapfe/core/error.hpp"
#include "gapfe/mesh/mesh.hpp"

namespace gapfe {

/// nr x nz cells with 4 corners (Quad4, LegacyQuad), 8 nodes (Quad8: mid-side nodes added, the
/// grid of (2 nr + 1) x (2 nz + 1) points without cell centres) or 3 (Tri3: the 4-corner mesh's nodes,
/// every cell split along its diagonal from corner 0 to corner 2 into {0, 1, 2} and {0, 2, 3}, so cell
/// 2 k + 1 has the quad's edge 3 -> 0). `ratio_r` > 0 grades radial sizes geometrically (each cell
/// ratio_r times the previous); 1 is uniform.
template <int NodesPerCell>
Mesh<NodesPerCell> rectangle_mesh(double r0, double r1, double z0, double z1, int nr, int nz,
                                  double ratio_r = 1.0) {
  static_assert(NodesPerCell == 3 || NodesPerCell == 4 || NodesPerCell == 8,
                "rectangle_mesh makes 3-, 4- or 8-node cells");
  if constexpr (NodesPerCell == 3) {
    const auto quads = rectangle_mesh<4>(r0, r1, z0, z1, nr, nz, ratio_r);
    Mesh<3> m;
    m.nodes = quads.nodes;
    m.cells.reserve(2 * quads.cells.size());
    for (const auto& c : quads.cells)
      m.cells.push_back({c[0], c[1], c[2]}), m.cells.push_back({c[0], c[2], c[3]});
    return m;
  } else {
    if (nr < 1 || nz < 1 || !(r1 > r0) || !(z1 > z0) || r0 < 0 || !(ratio_r > 0))
      throw InputError("rectangle_mesh: need nr, nz >= 1, 0 <= r0 < r1, z0 < z1 and ratio_r > 0");
    // Radial stations of cell corners (graded), then refined by 2 for Quad8.
    std::vector<double> rc(static_cast<std::size_t>(nr) + 1);
    double total = 0, h = 1;
    for (int i = 0; i < nr; ++i) total += h, h *= ratio_r;
    rc[0] = r0, h = (r1 - r0) / total;
    for (int i = 0; i < nr; ++i) rc[i + 1] = rc[i] + h, h *= ratio_r;
    rc[nr]             = r1;
    constexpr int kSub = NodesPerCell == 8 ? 2 : 1;
    const int ni = kSub * nr + 1, nj = kSub * nz + 1;
    auto r_at = [&](int i) { return i % kSub == 0 ? rc[i / kSub] : 0.5 * (rc[i / kSub] + rc[i / kSub + 1]); };

    Mesh<NodesPerCell> m;
    std::vector<int> id(static_cast<std::size_t>(ni) * nj, -1);
    for (int j = 0; j < nj; ++j)
      for (int i = 0; i < ni; ++i) {
        if (kSub == 2 && i % 2 == 1 && j % 2 == 1) continue;  // serendipity: no centre node
        id[static_cast<std::size_t>(j) * ni + i] = m.node_count();
        m.nodes.push_back({r_at(i), z0 + (z1 - z0) * j / (nj - 1)});
      }
    auto at = [&](int i, int j) { return id[static_cast<std::size_t>(j) * ni + i]; };
    for (int j = 0; j < nz; ++j)
      for (int i = 0; i < nr; ++i) {
        const int I = kSub * i, J = kSub * j;
        if constexpr (NodesPerCell == 4) {
          m.cells.push_back({at(I, J), at(I + 1, J), at(I + 1, J + 1), at(I, J + 1)});
        } else {
          m.cells.push_back({at(I, J), at(I + 2, J), at(I + 2, J + 2), at(I, J + 2), at(I + 1, J),
                             at(I + 2, J + 1), at(I + 1, J + 2), at(I, J + 1)});
        }
      }
    return m;
  }
}

/// Index of the node nearest to (r, z) (for tests and examples).
template <int NodesPerCell>
int nearest_node(const Mesh<NodesPerCell>& m, double r, double z) {
  int best     = 0;
  double dbest = 1e300;
  for (int n = 0; n < m.node_count(); ++n) {
    const double d = (m.nodes[n] - Vec2(r, z)).squaredNorm();
    if (d < dbest) dbest = d, best = n;
  }
  return best;
}

}  // namespace gapfe

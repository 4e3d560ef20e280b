#pragma once
// The largest von Mises stress of a solution, as `--estimate` and `--accuracy` read it (app/
// read_quantities.hpp; docs/accuracy.md "Error bars"). A stress peaks on a boundary (a bore, a notch's
// root), where no stiffness point lies: a cell's centroid stress is half a cell from it, off by O(h), and a
// patch fitted around the boundary node itself extrapolates its cells' point values outwards, where the
// points' O(h) in-cell error (the bilinear cell's stresses are superconvergent at its centre only) becomes an
// O(h) error at the node. Zienkiewicz and Zhu's remedy (1992): recover the nodal stress from the centroid
// stresses of the cells around each node (a least-squares plane, post/patch_recovery.hpp), and at a boundary
// node read the planes of its interior neighbours there, unless its own cells surround it enough to
// interpolate (a re-entrant corner's three: its own plane's leverage, 1.5 there, at most 2). Second order on
// smooth fields for either cell order (quadratic cells' centroids too are O(h^2)); a stress that is singular
// (a re-entrant corner) keeps growing as the mesh is refined, and the error bars say it does not converge.
#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "gapfe/core/pair_key.hpp"
#include "gapfe/mesh/mesh.hpp"
#include "gapfe/post/patch_recovery.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

/// The largest recovered nodal von Mises stress and its node.
struct PeakStress {
  double mises = 0;   ///< [stress]
  int node     = -1;  ///< -1: no cell recovered
};

/// The peak on `mesh` from `centroids`, the cells' centroid stresses (cells, then triangles: a driver's
/// centroid_values(Recovered::stress)); the cells of material `skip` (gap elements, -1: none) are left out.
/// Each material is recovered on its own (its stresses jump at a bond); a node is on a material's boundary
/// when one of its sides has one cell of that material.
template <int N>
PeakStress recovered_peak(const Mesh<N>& mesh, const std::vector<PointValues>& centroids, int skip) {
  detail::RecoverySlots slots(mesh.node_count());
  std::vector<std::array<int, 5>> cells;  // corners (a triangle's 4th = -1), then material
  const auto visit = [&](const auto& cell, int corners, const CellTag& tag) {
    std::array<int, 5> c{-1, -1, -1, -1, tag.material};
    std::size_t placed = 0;  // a degenerate quadrilateral's repeated corner once: a triangle
    for (int k = 0; k < corners; ++k)
      if (const int n = cell[static_cast<std::size_t>(k)]; placed == 0 || (n != c[placed - 1] && n != c[0]))
        c[placed++] = n;
    cells.push_back(c);
  };
  for (std::size_t e = 0; e < mesh.cells.size(); ++e)
    visit(mesh.cells[e], N == 3 || N == 6 ? 3 : 4, mesh.cell_tag(e));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) visit(mesh.triangles[t], 3, mesh.triangle_tag(t));
  for (const auto& c : cells)
    if (c[4] != skip)
      for (int k = 0; k < 4 && c[k] >= 0; ++k) slots.add(c[k], c[4]);
  slots.finish();
  if (centroids.size() != cells.size())
    throw std::invalid_argument("recovered_peak: " + std::to_string(centroids.size()) + " centroids for " +
                                std::to_string(cells.size()) + " cells");

  // The patches' planes through the centroids, and the sides (pairs of slots) with how many cells hold them.
  std::vector<detail::PatchSums<6, 3>> sums(slots.size());
  std::vector<std::uint64_t> sides;
  for (std::size_t e = 0; e < cells.size(); ++e) {
    const auto& c = cells[e];
    if (c[4] == skip) continue;
    const int corners = c[3] < 0 ? 3 : 4;
    const Vec2 centre(centroids[e].r, centroids[e].z);
    for (int k = 0; k < corners; ++k) {
      const std::size_t a = slots(c[k], c[4]), b = slots(c[(k + 1) % corners], c[4]);
      sums[a].add(centre - mesh.nodes[static_cast<std::size_t>(c[k])], centroids[e].stress);
      if (a != b) sides.push_back(side_key(a, b));  // a degenerate quadrilateral's collapsed side is none
    }
  }
  std::sort(sides.begin(), sides.end());
  std::vector<char> boundary(slots.size(), 0);
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j] == sides[i]) ++j;
    if (j - i == 1) boundary[sides[i] >> 32] = boundary[sides[i] & 0xffffffffu] = 1;
    i = j;
  }
  // A boundary slot's interior neighbours: the slots of the cells around it that are not on a boundary.
  std::vector<std::uint64_t> reads;  // (boundary slot, interior slot)
  for (std::size_t e = 0; e < cells.size(); ++e) {
    const auto& c = cells[e];
    if (c[4] == skip) continue;
    for (int k = 0; k < 4 && c[k] >= 0; ++k)
      for (int l = 0; l < 4 && c[l] >= 0; ++l) {
        const std::size_t a = slots(c[k], c[4]), b = slots(c[l], c[4]);
        if (boundary[a] && !boundary[b]) reads.push_back(pair_key(a, b));
      }
  }
  std::sort(reads.begin(), reads.end());
  reads.erase(std::unique(reads.begin(), reads.end()), reads.end());

  PeakStress out;
  const auto consider = [&](std::size_t k, const Vec6& stress) {
    if (const double s = voigt::von_mises(stress); s > out.mises) out.mises = s, out.node = slots.node(k);
  };
  std::size_t next = 0;  // the reads of slot k start at reads[next]
  for (std::size_t k = 0; k < slots.size(); ++k) {
    if (slots.node(k) < 0) continue;
    Vec6 sum        = Vec6::Zero(), value;
    int read        = 0;
    double leverage = 0;
    if (boundary[k] && sums[k].plane_at(Vec2::Zero(), value, &leverage) && leverage <= 2) {
      for (; next < reads.size() && (reads[next] >> 32) == k;) ++next;
      consider(k, value);
      continue;
    }
    for (; next < reads.size() && (reads[next] >> 32) == k; ++next) {
      const std::size_t from = reads[next] & 0xffffffffu;
      const Vec2 offset      = mesh.nodes[static_cast<std::size_t>(slots.node(k))] -
                          mesh.nodes[static_cast<std::size_t>(slots.node(from))];
      if (sums[from].plane_at(offset, value)) sum += value, ++read;
    }
    consider(k, read > 0 ? Vec6(sum / read) : sums[k].at_node());
  }
  return out;
}

}  // namespace gapfe

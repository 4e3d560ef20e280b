#pragma once
// The results of a partitioned run (core/subdomain.hpp) as the whole mesh's, on part 0, for output: each
// part gives the rows it owns (its owned nodes' displacements and reactions, its cells' centroid values) in
// the whole mesh's numbering; part 0 gets the whole tables and writes the files a whole run writes, the
// others get nothing. Collective. Only output gathers: the solve keeps each part's vectors on its part.
#include <vector>

#include "gapfe/core/subdomain.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

/// The first `count` nodes' displacements and reactions as rows of six, (u, R) per node: what
/// gather_solution sends to part 0 and a part's ghost nodes take from their owners.
inline std::vector<double> node_rows(const Solution& s, int count) {
  std::vector<double> rows(static_cast<std::size_t>(count) * 6);
  for (int n = 0; n < count; ++n)
    for (int c = 0; c < 3; ++c) {
      rows[6 * static_cast<std::size_t>(n) + static_cast<std::size_t>(c)]     = s.displacement(n, c);
      rows[6 * static_cast<std::size_t>(n) + 3 + static_cast<std::size_t>(c)] = s.reaction(n, c);
    }
  return rows;
}

/// Nodes [first, last) of `s` from node_rows()-shaped `rows` (row n at rows + 6 n).
inline void set_node_rows(Solution& s, const double* rows, int first, int last) {
  for (int n = first; n < last; ++n)
    for (int c = 0; c < 3; ++c) {
      s.displacement(n, c) = rows[6 * static_cast<std::size_t>(n) + static_cast<std::size_t>(c)];
      s.reaction(n, c)     = rows[6 * static_cast<std::size_t>(n) + 3 + static_cast<std::size_t>(c)];
    }
}

/// Displacements and reactions of every node of the whole mesh on part 0 (rows: whole nodes); the residual
/// and the global balance are totals already. Other parts get an empty Solution.
inline Solution gather_solution(const Subdomain& domain, const Solution& local) {
  const PartLayout& l            = domain.layout();
  const std::vector<double> rows = node_rows(local, l.owned_nodes);
  const int whole                = static_cast<int>(l.local_node.size());
  const std::vector<double> table =
      domain.gather_rows(rows.data(), l.owned_nodes, 6, l.global_node.data(), whole);
  Solution out;
  out.residual = local.residual;
  out.balance  = local.balance;
  if (table.empty()) return out;
  out.displacement.resize(whole, 3), out.reaction.resize(whole, 3);
  set_node_rows(out, table.data(), 0, whole);
  return out;
}

/// The whole mesh's index of a part's cell `cell` (a triangle's among the triangles), in the order of
/// centroid_values(): cells, then triangles.
inline int whole_cell_index(const PartLayout& l, bool triangle, int cell) {
  return triangle ? l.whole_cells + l.global_triangle[static_cast<std::size_t>(cell)]
                  : l.global_cell[static_cast<std::size_t>(cell)];
}

/// One value per cell (cells then triangles, as centroid_values() orders them) of the whole mesh on part 0;
/// empty elsewhere.
inline std::vector<double> gather_cell_values(const Subdomain& domain, const std::vector<double>& local) {
  const PartLayout& l = domain.layout();
  const int cells     = static_cast<int>(l.global_cell.size());
  std::vector<int> index(local.size());
  for (int e = 0; e < static_cast<int>(local.size()); ++e)
    index[static_cast<std::size_t>(e)] = whole_cell_index(l, e >= cells, e >= cells ? e - cells : e);
  return domain.gather_rows(local.data(), static_cast<int>(local.size()), 1, index.data(),
                            l.whole_cells + l.whole_triangles);
}

/// Centroid values (one per cell, cells then triangles, as centroid_values() gives them) of the whole mesh
/// on part 0; empty elsewhere. `what` as the recovery's: Recovered::stress gathers only the position, the
/// global stress and eqps (what the deck output writes), a third of the traffic.
inline std::vector<PointValues> gather_cells(const Subdomain& domain, const std::vector<PointValues>& local,
                                             Recovered what = Recovered::all) {
  const PartLayout& l = domain.layout();
  const bool all      = what == Recovered::all;
  const int width     = all ? 28 : 10;  // point, r, z, stress, eqps [, strain, strain and stress in axes]
  std::vector<double> rows;
  std::vector<int> index;
  rows.reserve(local.size() * static_cast<std::size_t>(width)), index.reserve(local.size());
  for (const PointValues& v : local) {
    index.push_back(whole_cell_index(l, v.triangle, v.cell));
    rows.insert(rows.end(), {static_cast<double>(v.point), v.r, v.z, v.eqps});
    rows.insert(rows.end(), v.stress.data(), v.stress.data() + 6);
    if (!all) continue;
    rows.insert(rows.end(), v.strain.data(), v.strain.data() + 6);
    rows.insert(rows.end(), v.strain_material.data(), v.strain_material.data() + 6);
    rows.insert(rows.end(), v.stress_material.data(), v.stress_material.data() + 6);
  }
  const int whole = l.whole_cells + l.whole_triangles;
  const std::vector<double> table =
      domain.gather_rows(rows.data(), static_cast<int>(index.size()), width, index.data(), whole);
  std::vector<PointValues> out;
  if (table.empty()) return out;
  out.resize(static_cast<std::size_t>(whole));
  for (int e = 0; e < whole; ++e) {
    const double* x = table.data() + static_cast<std::size_t>(e) * static_cast<std::size_t>(width);
    PointValues& v  = out[static_cast<std::size_t>(e)];
    v.triangle      = e >= l.whole_cells;
    v.cell          = v.triangle ? e - l.whole_cells : e;
    v.point = static_cast<int>(x[0]), v.r = x[1], v.z = x[2], v.eqps = x[3];
    v.stress = Eigen::Map<const Vec6>(x + 4);
    if (all) {
      v.strain          = Eigen::Map<const Vec6>(x + 10);
      v.strain_material = Eigen::Map<const Vec6>(x + 16);
      v.stress_material = Eigen::Map<const Vec6>(x + 22);
    } else {
      v.strain.setZero(), v.strain_material.setZero(), v.stress_material.setZero();
    }
  }
  return out;
}

}  // namespace gapfe

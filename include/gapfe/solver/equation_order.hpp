#pragma once
// equation_order: a fill-reducing elimination order of a system's free equations, from its mesh: the
// nested dissection of the nodes by their coordinates (coordinate_dissection.hpp), each node's free
// equations together. Direct solvers that take an order (OrderedSolver, core/concepts.hpp) get it from the
// driver that builds their System (driver/system_setup.hpp).
#include <algorithm>
#include <vector>

#include "gapfe/core/types.hpp"
#include "gapfe/solver/coordinate_dissection.hpp"

namespace gapfe {

/// order[k] = the equation eliminated k-th. `nodes`: the nodes' (r, z); `equation(n, c)`: the equation of
/// component c (of `components`) of node n, or -1 where it is prescribed; `free_count` equations in all.
/// `node_lists...`: containers of node lists (cells, triangles, node links) whose nodes are neighbours.
/// Empty when there is no free equation.
template <class Equation, class... NodeLists>
std::vector<int> equation_order(const std::vector<Vec2>& nodes, int components, int free_count,
                                Equation&& equation, const NodeLists&... node_lists) {
  if (free_count == 0) return {};
  const int nn = static_cast<int>(nodes.size());
  std::vector<std::vector<int>> near(static_cast<std::size_t>(nn));
  const auto connect = [&](const auto& lists) {
    for (const auto& list : lists)
      for (const int a : list)
        for (const int b : list)
          if (a != b) near[static_cast<std::size_t>(a)].push_back(b);
  };
  (connect(node_lists), ...);
  std::vector<int> ptr(static_cast<std::size_t>(nn) + 1, 0), adj;
  for (int n = 0; n < nn; ++n) {
    auto& list = near[static_cast<std::size_t>(n)];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    adj.insert(adj.end(), list.begin(), list.end());
    ptr[static_cast<std::size_t>(n) + 1] = static_cast<int>(adj.size());
    std::vector<int>().swap(list);
  }
  std::vector<int> order;
  order.reserve(static_cast<std::size_t>(free_count));
  for (const int n : coordinate_dissection(nodes, ptr, adj))
    for (int c = 0; c < components; ++c)
      if (const int eq = equation(n, c); eq >= 0) order.push_back(eq);
  return order;
}

}  // namespace gapfe

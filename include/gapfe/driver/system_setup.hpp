#pragma once
// The System of an analysis, built by its driver from the assembler's pattern: with a fill-reducing order
// (solver/equation_order.hpp) for a solver that takes one and, for a part of a partitioned problem, the
// equation layout (collective). A distributed solver that takes no order gets the layout on a whole problem
// too (for its near-null space); a RuntimeSolver offering both kinds gets it only for a part.
#include <memory>
#include <vector>

#include "gapfe/assembly/assembler.hpp"
#include "gapfe/assembly/equation_layout.hpp"
#include "gapfe/core/concepts.hpp"
#include "gapfe/problem/problem.hpp"
#include "gapfe/solver/equation_order.hpp"
#include "gapfe/solver/system.hpp"

namespace gapfe {

/// The fill-reducing order of the assembler's free equations (equation_order): the mesh's cells and
/// triangles and the assembler's node links are the neighbours.
template <class M>
std::vector<int> fill_reducing_order(const Assembler<M>& a, const Problem<M>& p) {
  const auto& dofs = a.dofs();
  return equation_order(
      p.mesh.nodes, M::kDofsPerNode, dofs.free_count,
      [&](int n, int c) { return dofs.equation[static_cast<std::size_t>(dofs.dof(n, c))]; }, p.mesh.cells,
      p.mesh.triangles, a.links());
}

/// The System of the analysis: takes the assembler's pattern (once). `solver`: the solver object (empty: a
/// default-constructed one).
template <class Solver, class M>
System<Solver> make_system(Assembler<M>& a, const Problem<M>& p, std::unique_ptr<Solver> solver = nullptr) {
  if (p.subdomain || (DistributedSolver<Solver> && !OrderedSolver<Solver>)) {
    const EquationLayout layout = equation_layout(a.dofs(), p.mesh, p.subdomain.get());
    return System<Solver>(a.take_pattern(), {}, &layout, std::move(solver));
  }
  if constexpr (OrderedSolver<Solver>) {
    std::vector<int> order = fill_reducing_order(a, p);
    return System<Solver>(a.take_pattern(), order, nullptr, std::move(solver));
  }
  return System<Solver>(a.take_pattern(), {}, nullptr, std::move(solver));
}

}  // namespace gapfe

#pragma once
// A part's free equations in the global system of a partitioned problem (EquationLayout, core/concepts.hpp),
// and the near-null space of the axisymmetric kinematics that an algebraic multigrid preconditioner needs.
//
// Numbering: part k's rows are its owned nodes' free DOFs, in its local order (DofMap numbers free DOFs
// node by node and a part's owned nodes come first, so they are its local equations [0, owned)), after the
// rows of parts 0 .. k-1. A ghost's numbers are its owner's, copied over (Subdomain::copy_to_ghosts).
//
// Near-null space: the displacement fields of (almost) no strain energy, which smoothed aggregation must
// reproduce on every coarse level. In axisymmetry the rigid motions of the (r, z) plane are not all free:
//   u_z = 1                     axial translation: no strain at all (an exact null mode);
//   u_theta = r     (3 DOF)     rigid rotation about the axis: no strain at all (exact);
//   u_r = 1                     radial translation: only the hoop strain u_r / r = 1 / r, small where r is
//                               large against the section (a tube's wall, far from the axis);
//   u_r = z, u_z = -r           in-plane rotation: hoop strain z / r only, small in the same way.
// For the thin-walled and thick tubes gapfe meets, the last two are the low-energy modes a coarse space
// built from the exact ones alone would miss (BENCHMARKS.md "Past one machine" measures CG + GAMG with and
// without them). The vectors are not orthonormal; the solver orthonormalizes them.
#include <cstdint>
#include <vector>

#include "gapfe/assembly/dof_map.hpp"
#include "gapfe/core/concepts.hpp"
#include "gapfe/core/subdomain.hpp"
#include "gapfe/mesh/mesh.hpp"

namespace gapfe {

/// The layout of the free equations of `dofs` on `mesh` (a part's, when `subdomain` is set; the identity
/// otherwise). Collective over the parts.
template <int DofsPerNode, class MeshT>
EquationLayout equation_layout(const DofMap<DofsPerNode>& dofs, const MeshT& mesh,
                               const Subdomain* subdomain) {
  constexpr int nd  = DofsPerNode;
  const int nodes   = mesh.node_count();
  const int owned_n = subdomain ? subdomain->owned_nodes() : nodes;
  EquationLayout l;
  l.partitioned = subdomain != nullptr;
  for (int d = 0; d < owned_n * nd; ++d) l.owned += dofs.equation[static_cast<std::size_t>(d)] >= 0;
  l.first = 0, l.total = l.owned;
  if (subdomain) {  // the parts' row counts, summed: rows before this part's, and in all
    std::vector<double> rows(static_cast<std::size_t>(subdomain->parts()), 0.0);
    rows[static_cast<std::size_t>(subdomain->part())] = l.owned;
    subdomain->sum(rows.data(), static_cast<int>(rows.size()));
    l.total = 0;
    for (int k = 0; k < subdomain->parts(); ++k) {
      if (k == subdomain->part()) l.first = l.total;
      l.total += static_cast<std::int64_t>(rows[static_cast<std::size_t>(k)]);
    }
  }
  // Global numbers at owned nodes (as doubles: exact below 2^53), then the owners' to the ghosts.
  std::vector<double> global(static_cast<std::size_t>(nodes) * nd, -1.0);
  for (int d = 0; d < owned_n * nd; ++d)
    if (const int eq = dofs.equation[static_cast<std::size_t>(d)]; eq >= 0)
      global[static_cast<std::size_t>(d)] = static_cast<double>(l.first + eq);
  if (subdomain) subdomain->copy_to_ghosts(global.data(), nd);
  l.global.assign(static_cast<std::size_t>(dofs.free_count), -1);
  on_every_part(subdomain, [&] {
    for (std::size_t d = 0; d < global.size(); ++d)
      if (const int eq = dofs.equation[d]; eq >= 0) {
        if (global[d] < 0)  // the owner prescribes it: the parts' conditions disagree (a partitioning bug)
          throw SolveError("equation_layout: a ghost DOF is free here and prescribed by its owner");
        l.global[static_cast<std::size_t>(eq)] = static_cast<std::int64_t>(global[d]);
      }
  });

  // Near-null modes over the owned rows, column-major: u_z = 1, u_r = 1, (u_r, u_z) = (z, -r), u_theta = r.
  l.modes = nd == 3 ? 4 : 3;
  l.near_null.assign(static_cast<std::size_t>(l.owned) * static_cast<std::size_t>(l.modes), 0.0);
  const auto at = [&](int eq, int mode) -> double& {
    return l.near_null[static_cast<std::size_t>(mode) * static_cast<std::size_t>(l.owned) +
                       static_cast<std::size_t>(eq)];
  };
  for (int n = 0; n < owned_n; ++n) {
    const double r = mesh.nodes[static_cast<std::size_t>(n)](0),
                 z = mesh.nodes[static_cast<std::size_t>(n)](1);
    for (int c = 0; c < nd; ++c) {
      const int eq = dofs.equation[static_cast<std::size_t>(dofs.dof(n, c))];
      if (eq < 0) continue;
      if (c == dof::z) at(eq, 0) = 1, at(eq, 2) = -r;
      if (c == dof::r) at(eq, 1) = 1, at(eq, 2) = z;
      if (c == dof::theta) at(eq, 3) = r;
    }
  }
  return l;
}

}  // namespace gapfe

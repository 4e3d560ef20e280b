#pragma once
// Node -> equation numbering for a kinematics with DofsPerNode components. Free DOFs are numbered
// node by node, component fastest, so equation numbers increase with (node, component); prescribed
// DOFs get -1 and keep their value in `prescribed`.
//
// Nodes on the axis (r = 0 within 1e-9 of the mesh size) get u_r = u_theta = 0: a smooth field needs
// it, and the exact stiffness of u_r there is infinite (docs/theory.md 1.3). A card that prescribes a
// non-zero u_r or u_theta there, or loads those components, is an input error.
#include <cmath>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/problem/loads.hpp"

namespace gapfe {

template <int DofsPerNode>
struct DofMap {
  std::vector<int> equation;  ///< [node * DofsPerNode + component] -> free equation or -1
  VecX prescribed;            ///< prescribed values per DOF (0 for free DOFs) [length]
  VecX nodal_force;           ///< card forces per DOF (0 for prescribed DOFs) [force]
  std::vector<bool> on_axis;  ///< per node
  int free_count = 0;

  int dof(int node, int component) const { return node * DofsPerNode + component; }
  /// "node N u_r" for free equation `eq`, for messages (a factorization that broke down there).
  std::string describe(int eq) const {
    for (std::size_t d = 0; d < equation.size(); ++d)
      if (equation[d] == eq)
        return "node " + std::to_string(d / DofsPerNode + 1) + " " + dof::kName[d % DofsPerNode];
    return "equation " + std::to_string(eq);
  }

  /// The errors build() gives for a card (seed Data 5) on a mesh of `nodes` nodes; `on_axis(node)` says
  /// whether a node lies on the axis (asked only for a node in range). A partitioned problem checks the
  /// whole problem's cards with it before each part keeps its own (assembly/problem_part.hpp).
  template <class OnAxis>
  static void check(const NodalCondition& c, int nodes, OnAxis&& on_axis) {
    const std::string where = "boundary condition at node " + std::to_string(c.node + 1);
    if (c.node < 0 || c.node >= nodes) throw InputError(where + ": no such node");
    if (c.code < 0 || c.code > 7)
      throw InputError(where + ": code must be 0-7, got " + std::to_string(c.code));
    if (!std::isfinite(c.value[0]) || !std::isfinite(c.value[1]) || !std::isfinite(c.value[2]))
      throw InputError(where + ": non-finite value");
    const bool axis = on_axis(c.node);
    for (int k = 0; k < 3; ++k) {
      if (c.value[k] == 0) continue;
      if (k == dof::theta && DofsPerNode == 2)
        throw InputError(where + ": a theta " + (c.prescribed(k) ? "displacement" : "load") +
                         " needs the 3-DOF (SAGA) kinematics");
      if (axis && k != dof::z)
        throw InputError(where + ": the node is on the axis, where " + dof::kName[k] +
                         " = 0 is imposed; a non-zero " + dof::kName[k] +
                         (c.prescribed(k) ? " displacement" : " load") + " is not allowed");
    }
  }

  template <class MeshT>
  static DofMap build(const MeshT& mesh, const std::vector<NodalCondition>& conditions) {
    const int nn = mesh.node_count();
    DofMap m;
    m.prescribed  = VecX::Zero(nn * DofsPerNode);
    m.nodal_force = VecX::Zero(nn * DofsPerNode);
    m.on_axis.assign(static_cast<std::size_t>(nn), false);
    std::vector<bool> fixed(static_cast<std::size_t>(nn) * DofsPerNode, false);
    const double axis_tol = 1e-9 * mesh.size();
    for (int n = 0; n < nn; ++n) {
      if (mesh.nodes[n](0) < -axis_tol)
        throw InputError("node " + std::to_string(n + 1) +
                         " has negative radius r = " + std::to_string(mesh.nodes[n](0)));
      if (mesh.nodes[n](0) <= axis_tol) {
        m.on_axis[n]            = true;
        fixed[m.dof(n, dof::r)] = true;
        if constexpr (DofsPerNode == 3) fixed[m.dof(n, dof::theta)] = true;
      }
    }
    for (const auto& c : conditions) {  // later cards win, as in the seed (in the components they set)
      check(c, nn, [&](int node) { return static_cast<bool>(m.on_axis[node]); });
      for (int k = 0; k < DofsPerNode; ++k) {
        const int d = m.dof(c.node, k);
        if ((m.on_axis[c.node] && k != dof::z) || !((c.sets >> k) & 1)) continue;
        fixed[d]         = c.prescribed(k);
        m.prescribed(d)  = c.prescribed(k) ? c.value[k] : 0.0;
        m.nodal_force(d) = c.prescribed(k) ? 0.0 : c.value[k];
      }
    }
    m.equation.assign(fixed.size(), -1);
    for (std::size_t d = 0; d < fixed.size(); ++d)
      if (!fixed[d]) m.equation[d] = m.free_count++;
    return m;
  }
};

}  // namespace gapfe

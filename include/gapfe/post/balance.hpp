#pragma once
// What the global balance (Solution::balance, post/recovery.hpp's nodal_results) needs beyond the nodal
// vectors of a solve.
//
// The body forces' totals: a linear law's body forces are element loads of the right-hand side and no vector
// of the driver holds them at every node, so their totals come from the elements' own load integration (the
// same ElementKernel::shape_load the right-hand side is built from: one source of truth). Over a cell's shape
// nodes, an inner node of the legacy quad included: its static condensation moves a load to the corners
// without changing the force along the axis or the torque about it (rigid axial translation and rotation
// strain nothing).
//
// The node links' torque: a link's two forces are equal and opposite, so they sum to nothing along the axis,
// but a gap pair across a radial gap carries its theta force at two radii, r_a and r_b, and so exerts the
// torque f_theta (r_b - r_a) on the structure (the seed's gap element, Eq. 1-3, is a spring between the two
// nodes; 4e-7 of the load on the press fit pushed and twisted, whose gap is 4e-5 of its radius).
#include "gapfe/assembly/assembler.hpp"

namespace gapfe {

/// The axial force and (3 DOF per node) the torque about the axis of every body force of the problem's
/// cells, or of a part's own cells for a part of a partitioned problem (the caller sums over the parts)
/// [force, force x length]. Zero, without a pass over the cells, when the problem has no inertia load.
template <class M>
Vec2 body_force_totals(const Assembler<M>& a, const Problem<M>& p) {
  using Kin  = typename M::Kinematics;
  Vec2 total = Vec2::Zero();
  if (!body_force(p.inertia, 1.0).any()) return total;
  a.reset_cache();
  for_each_cell<typename M::Element>(
      p.mesh, [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                            const std::array<int, NPC>& cell, const CellTag& tag) {
        using Kernel      = ElementKernel<Kin, E>;
        constexpr int kNd = Kin::kDofsPerNode;
        const auto& lp    = a.local(p, tag, cell);
        const BodyForce b = body_force(p.inertia, lp.density);
        if (!b.any()) return;
        const auto x                    = cell_coords<E>(p.mesh, cell);
        const Mat<E::kShapeNodes, 2> xs = E::shape_coords(x);
        const auto f = Kernel::shape_load(x, Kernel::restrict(lp.stiffness), Kernel::StrainVector::Zero(), b);
        for (int n = 0; n < E::kShapeNodes; ++n) {
          total(0) += f(kNd * n + 1);
          if constexpr (kNd == 3) total(1) += xs(n, 0) * f(kNd * n + 2);
        }
      });
  return total;
}

/// The torque about the axis of the node links' internal forces at `u` (all DOFs) over the links this part
/// assembles (a partitioned caller sums over the parts); 0 with 2 DOF per node [force x length].
template <class M>
double link_torque(const Assembler<M>& a, const Problem<M>& p, const VecX& u) {
  constexpr int kNd = M::Kinematics::kDofsPerNode;
  double torque     = 0;
  if constexpr (kNd == 3) {
    for (std::size_t l = 0; l < a.links().size(); ++l) {
      if (!a.assembles_link(l)) continue;
      const NodeLink& link = a.link_values()[l];
      const auto& nodes    = a.links()[l];
      const Vec<2 * kNd> f =
          link.template element_stiffness<kNd>() * a.gather(nodes, u) - link.template element_load<kNd>();
      for (int end = 0; end < 2; ++end)
        torque += p.mesh.nodes[static_cast<std::size_t>(nodes[static_cast<std::size_t>(end)])](0) *
                  f(end * kNd + 2);
    }
  }
  return torque;
}

}  // namespace gapfe

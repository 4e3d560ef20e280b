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
// The node links' torque: a link's two internal forces are equal and opposite, so they sum to nothing along
// the axis, but a gap pair across a radial gap carries its theta force at two radii, r_a and r_b, so they
// sum to the torque f_theta,b (r_b - r_a) about it (the seed's gap element, Eq. 1-3, is a spring between the
// two nodes); the balance counts it (Balance::gap_torque). On the press fit pushed and twisted it is 4e-7 of
// the load, the gap being 4e-5 of the radius.
#include "gapfe/assembly/assembler.hpp"

namespace gapfe {

/// The axial force and (3 DOF per node) the torque about the axis of every body force of the problem's
/// cells, or of a part's own cells for a part of a partitioned problem (the caller sums over the parts)
/// [force, force x length]. Zero, without a pass over the cells, when the problem's inertia loads have no
/// axial or theta part (none, or a spin alone: its body force is radial).
template <class M>
Vec2 body_force_totals(const Assembler<M>& a, const Problem<M>& p) {
  constexpr int kNd        = M::Kinematics::kDofsPerNode;
  Vec2 total               = Vec2::Zero();
  const BodyForce per_mass = body_force(p.inertia, 1.0);
  if (per_mass.axial == 0 && (kNd == 2 || per_mass.hoop_per_r == 0)) return total;
  a.for_each_body_load(p, [&]<class E, std::size_t NPC>(std::type_identity<E>, const std::array<int, NPC>&,
                                                        const auto& f, const auto& xs) {
    for (int n = 0; n < E::kShapeNodes; ++n) {
      total(0) += f(kNd * n + 1);
      if constexpr (kNd == 3) total(1) += xs(n, 0) * f(kNd * n + 2);
    }
  });
  return total;
}

/// The torque about the axis, sum r f_theta, of the node links' internal forces at `u` (all DOFs) over the
/// links this part assembles (a partitioned caller sums over the parts); 0 with 2 DOF per node
/// [force x length]. A link's two forces are equal and opposite, so this is sum f_theta,b (r_b - r_a).
template <class M>
double link_torque(const Assembler<M>& a, const Problem<M>& p, const VecX& u) {
  constexpr int kNd = M::Kinematics::kDofsPerNode;
  double torque     = 0;
  if constexpr (kNd == 3) {
    for (std::size_t l = 0; l < a.links().size(); ++l) {
      if (!a.assembles_link(l)) continue;
      const Vec<2 * kNd> f = a.link_force(l, u);
      for (int end = 0; end < 2; ++end)
        torque += p.mesh.nodes[static_cast<std::size_t>(a.links()[l][static_cast<std::size_t>(end)])](0) *
                  f(end * kNd + 2);
    }
  }
  return torque;
}

}  // namespace gapfe

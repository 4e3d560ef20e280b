#pragma once
// The pass of a law with history over the cells, Assembler's members defined out of its class (included at
// the end of assembly/assembler.hpp, never on its own): F_int, the trial history and, for tangent(), K_t
// and Newton's iteration-0 predictor.

#include "gapfe/assembly/assembler.hpp"

namespace gapfe {

template <class M>
template <class State>
void Assembler<M>::history_pass(const Problem<M>& p, const VecX& u, History<State>& points,
                                std::vector<Vec6>& stress, const StepContext& ctx, double* values,
                                VecX& internal, const VecX* prescribed_step, VecX* predictor) const {
  static_assert(ElementKernel<Kin, Elem>::kInner == 0,
                "laws with history need elements without condensed interior nodes (not LegacyQuad)");
  if (values) Eigen::Map<VecX>(values, nonzeros_).setZero();
  internal.setZero(u.size());
  if (predictor) predictor->setZero(dofs_.free_count);
  StepContext point_ctx = ctx;  // a residual pass: the laws may skip their tangents
  point_ctx.tangent     = values != nullptr;
  // Each cell's points on any thread, its forces and stiffness added in the cells' order
  // (assembly/cell_blocks.hpp); a cell writes only its own points' trial states and stresses.
  const auto compute = [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                     const std::array<int, NPC>& cell, const CellTag& tag,
                                                     CellSystem<E>& s, const LawCache& cache) {
    using Kernel                           = ElementKernel<Kin, E>;
    const auto x                           = cell_coords<E>(p.mesh, cell);
    const typename Kernel::Points geometry = Kernel::stiffness_points(x);
    const auto& lp                         = local(p, tag, cell, cache);
    const auto dilation                    = Kernel::dilatation(geometry, x);
    const auto ue                          = gather(cell, u);
    const std::size_t first                = first_point<E>(e);
    s.k.setZero(), s.f.setZero();
    for (int q = 0; q < E::kStiffnessPoints; ++q) {
      const auto& g   = geometry[q];
      const auto b    = Kernel::point_B(g, dilation);
      const auto resp = Law::update(lp, Kernel::extend(b * ue), points.committed(first + q), point_ctx);
      s.f.noalias() += g.weight * (b.transpose() * Kernel::restrict(resp.stress));
      if (values) {  // lazyProduct: see ElementKernel::shape_stiffness
        const typename Kernel::StrainDisplacement d_b = Kernel::restrict(resp.tangent) * b;
        s.k.noalias() += g.weight * b.transpose().lazyProduct(d_b);
      }
      points.trial(first + q) = resp.state;
      stress[first + q]       = resp.stress;
    }
  };
  const auto commit = [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                    const std::array<int, NPC>& cell, const CellTag&,
                                                    const CellSystem<E>& s) {
    add_to(cell, s.f, internal);
    if (!values) return;
    scatter<kStorage>(values, offsets<E>(e), s.k);
    if (prescribed_step) add_predictor(cell, s.k, *prescribed_step, *predictor);
  };
  for_each_cell_ordered<Elem, CellSystem, LawCache>(p.mesh, CellGroups::all, compute, commit);
  add_link_forces(u, internal);
  if (!values) return;
  constexpr int n = 2 * kNd;
  for (std::size_t l = 0; l < links_.size(); ++l) {
    if (!assembles_link(l)) continue;
    const Mat<n, n> k = link_values_[l].template element_stiffness<kNd>();
    scatter<kStorage>(values, link_offsets_.data() + l * offset_count(n, kStorage), k);
    if (prescribed_step) add_predictor(links_[l], k, *prescribed_step, *predictor);
  }
}

template <class M>
template <std::size_t NPC, class Matrix>
void Assembler<M>::add_predictor(const std::array<int, NPC>& nodes, const Matrix& k, const VecX& du_p,
                                 VecX& predictor) const {
  const auto step = gather(nodes, du_p);
  if (step.isZero(0.0)) return;
  for (int i = 0; i < k.rows(); ++i) {
    const int eq = dofs_.equation[dofs_.dof(nodes[i / kNd], i % kNd)];
    if (eq >= 0) predictor(eq) -= k.row(i).dot(step);
  }
}

}  // namespace gapfe

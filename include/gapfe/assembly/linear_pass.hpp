#pragma once
// The passes of a linear law over the cells, Assembler's members defined out of its class (included at the
// end of assembly/assembler.hpp, never on its own): the stiffness and right-hand side (linear_system, with
// the Quad4 batch kernel for 2 DOF), the right-hand side alone (linear_rhs), K u - f (linear_internal), the
// node links into a linear system (add_links), and one cell's condensed system (element_system).

#include "gapfe/assembly/assembler.hpp"

namespace gapfe {

template <class M>
void Assembler<M>::linear_system(const Problem<M>& p, const VecX& external, double* values, VecX& rhs) const {
  Eigen::Map<VecX>(values, nonzeros_).setZero();
  rhs = VecX::Zero(dofs_.free_count);
  for (std::size_t d = 0; d < dofs_.equation.size(); ++d)
    if (dofs_.equation[d] >= 0) rhs(dofs_.equation[d]) += external(static_cast<Eigen::Index>(d));
  // Each cell's system on any thread, added in the cells' order (assembly/cell_blocks.hpp); the batches
  // below do the model's cells.
  for_each_cell_ordered<Elem, CellSystem, LawCache>(
      p.mesh, kBatchedQuad4 ? CellGroups::triangles : CellGroups::all,
      [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t, const std::array<int, NPC>& cell,
                                    const CellTag& tag, CellSystem<E>& s, const LawCache& cache) {
        element_system<E>(p, cell, tag, s.k, s.f, cache);
      },
      [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e, const std::array<int, NPC>& cell,
                                    const CellTag&, const CellSystem<E>& s) {
        scatter<kStorage>(values, offsets<E>(e), s.k);
        add_element_rhs(
            cell, s.f, [&](int i, int j) { return s.k(i, j); }, rhs);
      });
  if constexpr (kBatchedQuad4) quad4_batched(p, values, rhs);
}

template <class M>
void Assembler<M>::linear_rhs(const Problem<M>& p, const VecX& external, VecX& rhs) const {
  rhs = VecX::Zero(dofs_.free_count);
  cache_.reset();
  for (std::size_t d = 0; d < dofs_.equation.size(); ++d)
    if (dofs_.equation[d] >= 0) rhs(dofs_.equation[d]) += external(static_cast<Eigen::Index>(d));
  for_each_cell<Elem>(p.mesh,
                      [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                    const std::array<int, NPC>& cell, const CellTag& tag) {
                        using Kernel = ElementKernel<Kin, E>;
                        if (!has_element_load<E>(p, local(p, tag, cell)) && !moves_prescribed(cell)) return;
                        typename Kernel::Matrix k;
                        typename Kernel::Vector f;
                        element_system<E>(p, cell, tag, k, f);
                        add_element_rhs(
                            cell, f, [&](int i, int j) { return k(i, j); }, rhs);
                      });
}

template <class M>
VecX Assembler<M>::linear_internal(const Problem<M>& p, const VecX& u, bool prescribed_only) const {
  VecX internal = VecX::Zero(u.size());
  cache_.reset();
  const bool reuse        = prescribed_only && kept_.valid;
  const std::size_t bytes = prescribed_only && !reuse ? kept_bytes(p) : 0;
  const bool keep         = prescribed_only && !reuse && bytes <= kKeptBytes;
  if (keep) kept_.values.clear(), kept_.values.reserve(bytes / sizeof(double));
  std::size_t at = 0;  // the cell's first entry in kept_.values
  for_each_cell<Elem>(p.mesh,
                      [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                    const std::array<int, NPC>& cell, const CellTag& tag) {
                        if (prescribed_only && !has_prescribed(cell)) return;
                        using Kernel         = ElementKernel<Kin, E>;
                        constexpr auto count = static_cast<std::size_t>(Kernel::kDofs * Kernel::kDofs);
                        typename Kernel::Matrix k;
                        typename Kernel::Vector f;
                        if (reuse && !has_element_load<E>(p, local(p, tag, cell))) {
                          k = Eigen::Map<const typename Kernel::Matrix>(kept_.values.data() + at);
                          f.setZero();
                        } else {
                          element_system<E>(p, cell, tag, k, f);
                          if (keep) kept_.values.insert(kept_.values.end(), k.data(), k.data() + count);
                        }
                        at += count;
                        const typename Kernel::Vector fe = k * gather(cell, u) - f;
                        add_to(cell, fe, internal);
                      });
  if (keep) kept_.valid = true;
  add_link_forces(u, internal);
  return internal;
}

template <class M>
void Assembler<M>::add_links(double* values, VecX& rhs) const {
  constexpr int n = 2 * kNd;
  for (std::size_t l = 0; l < links_.size(); ++l) {
    const NodeLink& link = link_values_[l];
    if (!assembles_link(l)) continue;
    const Mat<n, n> k = link.template element_stiffness<kNd>();
    scatter<kStorage>(values, link_offsets_.data() + l * offset_count(n, kStorage), k);
    add_element_rhs(
        links_[l], link.template element_load<kNd>(), [&](int i, int j) { return k(i, j); }, rhs);
  }
}

template <class M>
template <class E, std::size_t NPC>
void Assembler<M>::element_system(const Problem<M>& p, const std::array<int, NPC>& cell, const CellTag& tag,
                                  typename ElementKernel<Kin, E>::Matrix& k,
                                  typename ElementKernel<Kin, E>::Vector& f, const LawCache& cache) const {
  using Kernel                          = ElementKernel<Kin, E>;
  const auto x                          = cell_coords<E>(p.mesh, cell);
  const auto& lp                        = local(p, tag, cell, cache);
  const typename Kernel::StrainMatrix d = Kernel::restrict(lp.stiffness);
  if (!has_element_load<E>(p, lp)) {
    k = Kernel::stiffness(x, d);
    f.setZero();
  } else {
    const typename Kernel::ShapeVector fs =
        Kernel::shape_load(x, d, Kernel::restrict(lp.thermal_strain), body_force(p.inertia, lp.density));
    Kernel::condense(Kernel::shape_stiffness(x, d), fs, k, f);
  }
}

template <class M>
template <std::size_t NPC, class Vector, class Stiffness>
void Assembler<M>::add_element_rhs(const std::array<int, NPC>& cell, const Vector& f, Stiffness&& k,
                                   VecX& rhs) const {
  constexpr int n = kNd * static_cast<int>(NPC);
  std::array<int, n> dof;
  for (int a = 0; a < static_cast<int>(NPC); ++a)
    for (int c = 0; c < kNd; ++c) dof[a * kNd + c] = dofs_.dof(cell[a], c);
  const bool moved = moves_prescribed(cell);
  for (int i = 0; i < n; ++i) {
    const int eq = dofs_.equation[dof[i]];
    if (eq < 0) continue;
    double r = f(i);
    if (moved)
      for (int j = 0; j < n; ++j)
        if (dofs_.equation[dof[j]] < 0) r -= k(i, j) * dofs_.prescribed(dof[j]);
    rhs(eq) += r;
  }
}

template <class M>
void Assembler<M>::quad4_batched(const Problem<M>& p, double* values, VecX& rhs) const {
  using Kernel                 = ElementKernel<Kin, Elem>;
  using Batch                  = Quad4Axisym2Batch<8>;
  const auto& m                = p.mesh;
  static constexpr auto kUpper = [] {  // (i, j) -> index in the upper-triangle row-major list
    std::array<std::array<int, 8>, 8> t{};
    for (int i = 0, c = 0; i < 8; ++i)
      for (int j = i; j < 8; ++j, ++c) t[i][j] = t[j][i] = c;
    return t;
  }();
  struct Slot {  // one cell's upper triangle (the batch's order) and load
    std::array<double, 36> k;
    typename Kernel::Vector f;
  };
  static_assert(kCellsPerTask % Batch::kLanes == 0, "a task's cells fill whole batches");
  // Batches on any thread, added in the cells' order (assembly/cell_blocks.hpp).
  auto task = [&](std::size_t begin, std::size_t end, Slot* slots) {
    Batch batch;
    LawCache cache;
    for (std::size_t e0 = begin; e0 < end; e0 += Batch::kLanes) {
      const int lanes = static_cast<int>(std::min<std::size_t>(Batch::kLanes, end - e0));
      for (int l = 0; l < Batch::kLanes; ++l) {
        const std::size_t e =
            e0 + static_cast<std::size_t>(std::min(l, lanes - 1));  // pad with the last cell
        for (int a = 0; a < 4; ++a)
          batch.r[a][l] = m.nodes[m.cells[e][a]](0), batch.z[a][l] = m.nodes[m.cells[e][a]](1);
        batch.set_material(
            l, local(p, m.cell_tag(e), m.cells[e], cache).stiffness.template topLeftCorner<4, 4>());
      }
      batch.compute();
      for (int l = 0; l < lanes; ++l) {
        const std::size_t e = e0 + static_cast<std::size_t>(l);
        Slot& s             = slots[e - begin];
        for (int c = 0; c < 36; ++c) s.k[c] = batch.k[c][l];
        const auto& lp = local(p, m.cell_tag(e), m.cells[e], cache);
        s.f.setZero();
        if (has_element_load<Elem>(p, lp))
          s.f = Kernel::shape_load(cell_coords<Elem>(m, m.cells[e]), Kernel::restrict(lp.stiffness),
                                   Kernel::restrict(lp.thermal_strain), body_force(p.inertia, lp.density));
      }
    }
  };
  auto commit = [&](std::size_t e, const Slot& s) {
    const int* off = cell_offsets_.data() + e * offset_count(8, kStorage);
    if constexpr (kStorage == MatrixStorage::lower) {  // the batch's upper-triangle order is the offsets'
      for (int c = 0; c < 36; ++c)
        if (off[c] >= 0) values[off[c]] += s.k[c];
    } else {
      for (int i = 0, c = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j, ++c)
          if (off[c] >= 0) values[off[c]] += s.k[kUpper[i][j]];
    }
    add_element_rhs(
        m.cells[e], s.f, [&](int i, int j) { return s.k[kUpper[i][j]]; }, rhs);
  };
  ordered_tasks<Slot>(m.cells.size(), task, commit);
}

}  // namespace gapfe

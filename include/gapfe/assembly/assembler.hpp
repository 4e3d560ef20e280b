#pragma once
// Assembler<M>: the discrete operator of a Problem, nothing else. Built once per analysis: the DOF map,
// the stiffness pattern (element and node-link couplings over the free DOFs, in the storage the model's
// solver reads), the scatter
// offsets of every element and link into its value array, and the history layout of the points. Then,
// for a given state, it returns what a driver asks for:
//   * linear_system       K and the right-hand side of a linear law (element loads, prescribed columns);
//   * linear_internal     K u - f of the elements and links (reactions, equilibrium check);
//   * evaluate            F_int(u), trial history and, on request, the tangent K_t of a law with history;
//   * external_forces     card forces and edge tractions (add_body_forces: for laws with history);
//   * add_links           node-link springs into values and right-hand side (contact, next friction);
//   * nodal_stiffness     each node's diagonal block, what a contact penalty is scaled by.
// It owns no matrix values and no solver (solver/system.hpp) and keeps no displacement or history: the
// driver passes them in, so one assembler serves the linear, Newton and contact drivers alike.
//
// Conventions: full ring (core/types.hpp); element DOFs node-major; stiffness values are scattered from
// each element matrix's upper triangle, or all of it when the solver reads full storage
// (assembly/sparsity.hpp).
#include <algorithm>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "gapfe/assembly/cells.hpp"
#include "gapfe/assembly/dof_map.hpp"
#include "gapfe/assembly/edge_index.hpp"
#include "gapfe/assembly/element_kernel.hpp"
#include "gapfe/assembly/equation_layout.hpp"
#include "gapfe/assembly/node_links.hpp"
#include "gapfe/assembly/problem_check.hpp"
#include "gapfe/assembly/quad4_batch.hpp"
#include "gapfe/assembly/sparsity.hpp"
#include "gapfe/core/history.hpp"
#include "gapfe/problem/problem.hpp"
#include "gapfe/solver/coordinate_dissection.hpp"
#include "gapfe/solver/system.hpp"

namespace gapfe {

template <class M>
class Assembler {
 public:
  using Kin                = typename M::Kinematics;
  using Elem               = typename M::Element;
  using Law                = typename M::Material;
  static constexpr int kNd = Kin::kDofsPerNode;
  /// Quad4 with 2 DOF assembles linear stiffness through the vectorized batch kernel (same result,
  /// BENCHMARKS.md).
  static constexpr bool kBatchedQuad4 = std::is_same_v<Elem, Quad4> && kNd == 2;
  /// What the model's solver reads: the lower triangle, or every entry (assembly/sparsity.hpp).
  static constexpr MatrixStorage kStorage = storage_of<typename M::LinearSolver>();

  /// Checks the model (assembly/problem_check.hpp) and builds the pattern. `links`: node pairs that may
  /// carry node links; their values start at zero.
  Assembler(const Problem<M>& p, Connectivity<2> links)
      : links_(std::move(links)),
        link_values_(links_.size()),
        cells_(p.mesh.cells.size()),
        subdomain_(p.subdomain) {
    // A part's checks fail on every part together (core/subdomain.hpp, on_every_part).
    on_every_part(subdomain_.get(), [&] {
      check_model(p, links_);
      dofs_ = DofMap<kNd>::build(p.mesh, p.conditions);
    });
    // A partitioned problem: every part holds every link (the ends of gap pairs are on every part), and the
    // part that owns a link's first node assembles it, so that the parts' sum counts it once.
    link_owned_.assign(links_.size(), 1);
    if (subdomain_)
      for (std::size_t l = 0; l < links_.size(); ++l)
        link_owned_[l] = subdomain_->layout().owns(links_[l][0]);
    SparsityBuilder<kNd> sb(p.mesh.node_count(), dofs_.equation, dofs_.free_count);
    sb.add(p.mesh.cells);
    if constexpr (kHasTriangles<Elem>) sb.add(p.mesh.triangles);
    sb.add(links_);
    pattern_      = sb.build(kStorage);
    nonzeros_     = pattern_.nonZeros();
    cell_offsets_ = scatter_offsets<kNd>(pattern_, dofs_.equation, p.mesh.cells, kStorage);
    if constexpr (kHasTriangles<Elem>)
      tri_offsets_ = scatter_offsets<kNd>(pattern_, dofs_.equation, p.mesh.triangles, kStorage);
    link_offsets_ = scatter_offsets<kNd>(pattern_, dofs_.equation, links_, kStorage);
    points_       = cells_ * Elem::kStiffnessPoints;
    if constexpr (kHasTriangles<Elem>)
      points_ += p.mesh.triangles.size() * Elem::Degenerate::kStiffnessPoints;
  }

  const DofMap<kNd>& dofs() const { return dofs_; }
  /// The free DOFs' pattern in kStorage, values zero, handed over once to the System that will hold the
  /// values (a second copy of the matrix was 113 MB at 1e6 equations); the assembler keeps its size.
  SpMat take_pattern() { return std::move(pattern_); }
  /// A fill-reducing elimination order of the free equations (order[k] = the equation eliminated k-th):
  /// nested dissection of the nodes by their coordinates (solver/coordinate_dissection.hpp), each node's
  /// free components together. Node links count as edges. Empty when there is no free equation.
  std::vector<int> fill_reducing_order(const Problem<M>& p) const {
    const int nn = p.mesh.node_count();
    if (dofs_.free_count == 0) return {};
    std::vector<std::vector<int>> near(static_cast<std::size_t>(nn));
    const auto connect = [&](const auto& cells) {
      for (const auto& c : cells)
        for (const int a : c)
          for (const int b : c)
            if (a != b) near[static_cast<std::size_t>(a)].push_back(b);
    };
    connect(p.mesh.cells);
    connect(p.mesh.triangles);
    connect(links_);
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
    order.reserve(static_cast<std::size_t>(dofs_.free_count));
    for (const int n : coordinate_dissection(p.mesh.nodes, ptr, adj))
      for (int c = 0; c < kNd; ++c)
        if (const int eq = dofs_.equation[static_cast<std::size_t>(dofs_.dof(n, c))]; eq >= 0)
          order.push_back(eq);
    return order;
  }
  /// The System of the analysis, given the pattern (take_pattern()): with the fill-reducing order for a
  /// solver that takes one and, for a part of a partitioned problem, the equation layout (collective). A
  /// distributed solver that takes no order gets the layout on a whole problem too (for its near-null
  /// space); a RuntimeSolver offering both kinds gets it only for a part.
  /// `solver`: the solver object (empty: a default-constructed one).
  template <class Solver>
  System<Solver> make_system(const Problem<M>& p, std::unique_ptr<Solver> solver = nullptr) {
    if (p.subdomain || (DistributedSolver<Solver> && !OrderedSolver<Solver>)) {
      const EquationLayout layout = equation_layout(dofs_, p.mesh, p.subdomain.get());
      return System<Solver>(take_pattern(), {}, &layout, std::move(solver));
    }
    if constexpr (OrderedSolver<Solver>)
      return System<Solver>(take_pattern(), fill_reducing_order(p), nullptr, std::move(solver));
    return System<Solver>(take_pattern(), {}, nullptr, std::move(solver));
  }
  const Connectivity<2>& links() const { return links_; }
  /// Whether link l adds anything here: it is not zero and this part assembles it.
  bool assembles_link(std::size_t l) const { return link_owned_[l] && !link_values_[l].zero(); }
  std::vector<NodeLink>& link_values() { return link_values_; }
  const std::vector<NodeLink>& link_values() const { return link_values_; }
  /// Stiffness points of the mesh: the size of a History of material points.
  std::size_t point_count() const { return points_; }
  /// History slot of stiffness point 0 of cell e of element type E: cells first, then triangles.
  template <class E>
  std::size_t first_point(std::size_t e) const {
    if constexpr (std::is_same_v<E, Elem>) return e * Elem::kStiffnessPoints;
    return cells_ * Elem::kStiffnessPoints + e * E::kStiffnessPoints;
  }

  /// Before a solve: the loads are checked and the prescribed values and card forces re-read (which DOFs
  /// are prescribed may not change after construction: the pattern depends on it).
  void refresh(const Problem<M>& p) {
    on_every_part(subdomain_.get(), [&] {
      check_loads(p);
      DofMap<kNd> now = DofMap<kNd>::build(p.mesh, p.conditions);
      if (now.equation != dofs_.equation)
        throw InputError("boundary conditions: the set of prescribed DOFs changed after construction");
      dofs_ = std::move(now);
    });
  }

  /// F_ext over all DOFs: card forces and edge tractions (a linear law's body and thermal loads are
  /// element loads in linear_system; a law with history adds body forces with add_body_forces).
  VecX external_forces(const Problem<M>& p) {
    VecX f = dofs_.nodal_force;
    edges_.template add_loads<kNd>(p.mesh, p.edge_loads, f);
    return f;
  }
  /// Body forces (seed Data 12) into `f` (all DOFs), for laws with history; their thermal strain is in
  /// the law.
  void add_body_forces(const Problem<M>& p, VecX& f) const {
    for_each_body_load(p, [&]<class E, std::size_t NPC>(std::type_identity<E>,
                                                        const std::array<int, NPC>& cell, const auto& fe,
                                                        const auto&) {
      static_assert(ElementKernel<Kin, E>::kInner == 0, "a condensed centre's load is the linear system's");
      add_to(cell, fe, f);
    });
  }
  /// Every cell's body-force load (seed Data 12; ElementKernel::shape_load) to
  /// `visit(std::type_identity<E>, cell, load over the shape nodes, the shape nodes' (r, z))`, cells
  /// without one skipped (an inner node of the legacy quad included: the load before condensation).
  template <class Visit>
  void for_each_body_load(const Problem<M>& p, Visit&& visit) const {
    cache_.reset();
    for_each_cell<Elem>(p.mesh, [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                              const std::array<int, NPC>& cell,
                                                              const CellTag& tag) {
      using Kernel      = ElementKernel<Kin, E>;
      const auto& lp    = local(p, tag, cell);
      const BodyForce b = body_force(p.inertia, lp.density);
      if (!b.any()) return;
      const auto x  = cell_coords<E>(p.mesh, cell);
      const auto fe = Kernel::shape_load(x, Kernel::restrict(lp.stiffness), Kernel::StrainVector::Zero(), b);
      visit(std::type_identity<E>{}, cell, fe, E::shape_coords(x));
    });
  }
  /// Node link l's internal force K (u_b - u_a) - f on its nodes a, b at `u` (all DOFs), node-major.
  Vec<2 * kNd> link_force(std::size_t l, const VecX& u) const {
    const NodeLink& link = link_values_[l];
    return link.template element_stiffness<kNd>() * gather(links_[l], u) - link.template element_load<kNd>();
  }

  /// A linear law's system: element stiffness into `values` (zeroed first, no links), and
  /// rhs = F_ext (free rows) + element loads (body, thermal) - K_fp u_p.
  void linear_system(const Problem<M>& p, const VecX& external, double* values, VecX& rhs) const {
    Eigen::Map<VecX>(values, nonzeros_).setZero();
    rhs = VecX::Zero(dofs_.free_count);
    cache_.reset();
    for (std::size_t d = 0; d < dofs_.equation.size(); ++d)
      if (dofs_.equation[d] >= 0) rhs(dofs_.equation[d]) += external(static_cast<Eigen::Index>(d));
    for_each_cell<Elem>(p.mesh,
                        [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                      const std::array<int, NPC>& cell, const CellTag& tag) {
                          if constexpr (kBatchedQuad4 && std::is_same_v<E, Elem>)
                            return;  // done in batches below
                          typename ElementKernel<Kin, E>::Matrix k;
                          typename ElementKernel<Kin, E>::Vector f;
                          element_system<E>(p, cell, tag, k, f);
                          scatter<kStorage>(values, offsets<E>(e), k);
                          add_element_rhs(
                              cell, f, [&](int i, int j) { return k(i, j); }, rhs);
                        });
    if constexpr (kBatchedQuad4) quad4_batched(p, values, rhs);
  }

  /// linear_system's right-hand side alone, for a stiffness assembled from the same mesh, materials and
  /// temperatures (the element loads may differ: body forces, and the part of the thermal strain in
  /// force, Problem::thermal_fraction): F_ext (free rows) + element loads -
  /// K_fp u_p. Only cells with a body or thermal load or a non-zero prescribed value compute their element
  /// system; for pressures and card forces alone this is a scan of the cells (issue 14: a contact run's
  /// increments and a linear deck's later steps re-assembled the whole stiffness for their loads).
  void linear_rhs(const Problem<M>& p, const VecX& external, VecX& rhs) const {
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

  /// K u - f of a linear law's elements and of the node links at `u` (all DOFs). `prescribed_only`: only
  /// the cells with a prescribed DOF, so the entries at prescribed DOFs are complete (reactions) and those
  /// at free DOFs are not: a pass over the boundary instead of the mesh. Those cells' element stiffnesses
  /// are kept from the first such pass (when they fit in kKeptBytes) and reused until
  /// forget_kept_stiffness(): a contact run reads reactions every increment, and with u_z prescribed at
  /// every node its "boundary" is the whole mesh (issue 14: 11 element passes of the two-tube run).
  VecX linear_internal(const Problem<M>& p, const VecX& u, bool prescribed_only = false) const {
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
  /// The element stiffness changed (a new assembly): linear_internal's kept matrices no longer hold.
  void forget_kept_stiffness() { kept_.valid = false, kept_.values = {}; }
  /// At most this much memory for linear_internal's kept element stiffnesses [bytes].
  static constexpr std::size_t kKeptBytes = std::size_t(64) << 20;

  /// Node links into the stiffness values and the right-hand side (after the elements).
  void add_links(double* values, VecX& rhs) const {
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

  /// A law with history at displacements `u` (all DOFs), from the committed states of `points`:
  /// F_int = sum_e int B^T sigma dV + node links into `internal` (all DOFs), sigma into `stress`, the new
  /// states into points' trial records. With `values`, K_t = sum_e int B^T D B dV + links (zeroed first);
  /// with `prescribed_step` too, predictor = -K_fp du_p on the free rows (Newton's iteration 0).
  template <class State>
  void evaluate(const Problem<M>& p, const VecX& u, History<State>& points, std::vector<Vec6>& stress,
                const StepContext& ctx, double* values, VecX& internal, const VecX* prescribed_step,
                VecX& predictor) const {
    static_assert(ElementKernel<Kin, Elem>::kInner == 0,
                  "laws with history need elements without condensed interior nodes (not LegacyQuad)");
    if (values) Eigen::Map<VecX>(values, nonzeros_).setZero();
    internal.setZero(u.size());
    predictor.setZero(dofs_.free_count);
    cache_.reset();
    StepContext point_ctx = ctx;  // a residual pass: the laws may skip their tangents
    point_ctx.tangent     = values != nullptr;
    for_each_cell<Elem>(
        p.mesh, [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                              const std::array<int, NPC>& cell, const CellTag& tag) {
          using Kernel                           = ElementKernel<Kin, E>;
          const typename Kernel::Points geometry = Kernel::stiffness_points(cell_coords<E>(p.mesh, cell));
          const auto& lp                         = local(p, tag, cell);
          const auto mean                        = Kernel::mean_volumetric(geometry);
          const auto ue                          = gather(cell, u);
          const std::size_t first                = first_point<E>(e);
          typename Kernel::Matrix k              = Kernel::Matrix::Zero();
          typename Kernel::Vector f              = Kernel::Vector::Zero();
          for (int q = 0; q < E::kStiffnessPoints; ++q) {
            const auto& g   = geometry[q];
            const auto b    = Kernel::point_B(g, mean);
            const auto resp = Law::update(lp, Kernel::extend(b * ue), points.committed(first + q), point_ctx);
            f.noalias() += g.weight * (b.transpose() * Kernel::restrict(resp.stress));
            if (values) {  // lazyProduct: see ElementKernel::shape_stiffness
              const typename Kernel::StrainDisplacement d_b = Kernel::restrict(resp.tangent) * b;
              k.noalias() += g.weight * b.transpose().lazyProduct(d_b);
            }
            points.trial(first + q) = resp.state;
            stress[first + q]       = resp.stress;
          }
          add_to(cell, f, internal);
          if (!values) return;
          scatter<kStorage>(values, offsets<E>(e), k);
          if (prescribed_step) add_predictor(cell, k, *prescribed_step, predictor);
        });
    add_link_forces(u, internal);
    if (!values) return;
    constexpr int n = 2 * kNd;
    for (std::size_t l = 0; l < links_.size(); ++l) {
      if (!assembles_link(l)) continue;
      const Mat<n, n> k = link_values_[l].template element_stiffness<kNd>();
      scatter<kStorage>(values, link_offsets_.data() + l * offset_count(n, kStorage), k);
      if (prescribed_step) add_predictor(links_[l], k, *prescribed_step, predictor);
    }
  }

  /// The kNd x kNd diagonal block of every node (zero-padded to 3 x 3), summed over the cells whose tag
  /// passes `keep`, prescribed DOFs included: the "adjacent structure's stiffness" a penalty is scaled by.
  /// A part of a partitioned problem gets the sum over every part's cells (collective).
  template <class Keep>
  std::vector<Mat33> nodal_stiffness(const Problem<M>& p, Keep&& keep) const {
    std::vector<Mat33> out(static_cast<std::size_t>(p.mesh.node_count()), Mat33::Zero());
    cache_.reset();
    for_each_cell<Elem>(
        p.mesh, [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                              const std::array<int, NPC>& cell, const CellTag& tag) {
          if (!keep(tag)) return;
          typename ElementKernel<Kin, E>::Matrix k;
          typename ElementKernel<Kin, E>::Vector f;
          element_system<E>(p, cell, tag, k, f);
          for (int a = 0; a < static_cast<int>(NPC); ++a)
            out[cell[a]].template topLeftCorner<kNd, kNd>() += k.template block<kNd, kNd>(a * kNd, a * kNd);
        });
    if (subdomain_ && !out.empty()) subdomain_->sum_shared(out.front().data(), 9);  // Mat33: 9 contiguous
    return out;
  }

  /// The law resolved for a cell (cached across consecutive cells; reset_cache() at the start of a pass).
  template <std::size_t NPC>
  const typename Law::Local& local(const Problem<M>& p, const CellTag& tag,
                                   const std::array<int, NPC>& cell) const {
    return cache_.get(p.materials, tag, cell_temperature(p.temperature, p.reference_temperature, cell),
                      p.reference_temperature, p.thermal_fraction);
  }
  void reset_cache() const { cache_.reset(); }

  /// The element (or link) DOF values of `u` (all DOFs), node-major.
  template <std::size_t NPC>
  Vec<kNd* static_cast<int>(NPC)> gather(const std::array<int, NPC>& nodes, const VecX& u) const {
    Vec<kNd* static_cast<int>(NPC)> ue;
    for (int a = 0; a < static_cast<int>(NPC); ++a)
      for (int c = 0; c < kNd; ++c) ue(a * kNd + c) = u(dofs_.dof(nodes[a], c));
    return ue;
  }

  /// Internal force K u_e - f_e of every non-zero node link into `internal`.
  void add_link_forces(const VecX& u, VecX& internal) const {
    for (std::size_t l = 0; l < links_.size(); ++l)
      if (assembles_link(l)) add_to(links_[l], link_force(l, u), internal);
  }

 private:
  /// out(dof) += v over the element's (or link's) DOFs.
  template <std::size_t NPC, class Vector>
  void add_to(const std::array<int, NPC>& nodes, const Vector& v, VecX& out) const {
    for (int a = 0; a < static_cast<int>(NPC); ++a)
      for (int c = 0; c < kNd; ++c) out(dofs_.dof(nodes[a], c)) += v(a * kNd + c);
  }
  template <class E>
  const int* offsets(std::size_t e) const {
    constexpr int n = ElementKernel<Kin, E>::kDofs;
    return (std::is_same_v<E, Elem> ? cell_offsets_ : tri_offsets_).data() + e * offset_count(n, kStorage);
  }
  /// Condensed element stiffness and load (body + thermal) of one cell of a linear law.
  template <class E, std::size_t NPC>
  void element_system(const Problem<M>& p, const std::array<int, NPC>& cell, const CellTag& tag,
                      typename ElementKernel<Kin, E>::Matrix& k,
                      typename ElementKernel<Kin, E>::Vector& f) const {
    using Kernel                          = ElementKernel<Kin, E>;
    const auto x                          = cell_coords<E>(p.mesh, cell);
    const auto& lp                        = local(p, tag, cell);
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

  /// Element load into the right-hand side, and the prescribed-displacement columns moved there:
  /// rhs_i += f_i - sum_j K_ij u_j over prescribed j. `k(i, j)` gives the element stiffness.
  template <std::size_t NPC, class Vector, class Stiffness>
  void add_element_rhs(const std::array<int, NPC>& cell, const Vector& f, Stiffness&& k, VecX& rhs) const {
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
  /// Whether a cell has a prescribed DOF.
  template <std::size_t NPC>
  bool has_prescribed(const std::array<int, NPC>& cell) const {
    for (const int node : cell)
      for (int c = 0; c < kNd; ++c)
        if (dofs_.equation[static_cast<std::size_t>(dofs_.dof(node, c))] < 0) return true;
    return false;
  }
  /// The memory the stiffnesses of the cells with a prescribed DOF take [bytes].
  std::size_t kept_bytes(const Problem<M>& p) const {
    std::size_t bytes = 0;
    for_each_cell<Elem>(p.mesh,
                        [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                      const std::array<int, NPC>& cell, const CellTag&) {
                          constexpr int n = ElementKernel<Kin, E>::kDofs;
                          if (has_prescribed(cell)) bytes += sizeof(double) * n * n;
                        });
    return bytes;
  }
  /// Whether a cell of law values `lp` carries an element load (body force or thermal strain).
  template <class E>
  bool has_element_load(const Problem<M>& p, const typename Law::Local& lp) const {
    return body_force(p.inertia, lp.density).any() ||
           !ElementKernel<Kin, E>::restrict(lp.thermal_strain).isZero(0.0);
  }
  /// Whether a cell has a prescribed DOF with a non-zero value (a K_fp u_p term for the right-hand side).
  template <std::size_t NPC>
  bool moves_prescribed(const std::array<int, NPC>& cell) const {
    for (const int node : cell)
      for (int c = 0; c < kNd; ++c)
        if (const int d = dofs_.dof(node, c); dofs_.equation[d] < 0 && dofs_.prescribed(d) != 0) return true;
    return false;
  }
  /// predictor -= K_fp du_p over one element's free rows and prescribed columns.
  template <std::size_t NPC, class Matrix>
  void add_predictor(const std::array<int, NPC>& nodes, const Matrix& k, const VecX& du_p,
                     VecX& predictor) const {
    const auto step = gather(nodes, du_p);
    if (step.isZero(0.0)) return;
    for (int i = 0; i < k.rows(); ++i) {
      const int eq = dofs_.equation[dofs_.dof(nodes[i / kNd], i % kNd)];
      if (eq >= 0) predictor(eq) -= k.row(i).dot(step);
    }
  }

  /// Quad4 cells with 2 DOF: stiffness from the vectorized batch kernel (assembly/quad4_batch.hpp), W
  /// cells at a time; loads, when there are any, from the generic kernel.
  void quad4_batched(const Problem<M>& p, double* values, VecX& rhs) const {
    using Kernel                 = ElementKernel<Kin, Elem>;
    using Batch                  = Quad4Axisym2Batch<8>;
    const auto& m                = p.mesh;
    const std::size_t count      = m.cells.size();
    static constexpr auto kUpper = [] {  // (i, j) -> index in the upper-triangle row-major list
      std::array<std::array<int, 8>, 8> t{};
      for (int i = 0, c = 0; i < 8; ++i)
        for (int j = i; j < 8; ++j, ++c) t[i][j] = t[j][i] = c;
      return t;
    }();
    Batch batch;
    for (std::size_t e0 = 0; e0 < count; e0 += Batch::kLanes) {
      const int lanes = static_cast<int>(std::min<std::size_t>(Batch::kLanes, count - e0));
      for (int l = 0; l < Batch::kLanes; ++l) {
        const std::size_t e =
            e0 + static_cast<std::size_t>(std::min(l, lanes - 1));  // pad with the last cell
        for (int a = 0; a < 4; ++a)
          batch.r[a][l] = m.nodes[m.cells[e][a]](0), batch.z[a][l] = m.nodes[m.cells[e][a]](1);
        batch.set_material(l, local(p, m.cell_tag(e), m.cells[e]).stiffness.template topLeftCorner<4, 4>());
      }
      batch.compute();
      for (int l = 0; l < lanes; ++l) {
        const std::size_t e = e0 + static_cast<std::size_t>(l);
        const int* off      = cell_offsets_.data() + e * offset_count(8, kStorage);
        if constexpr (kStorage == MatrixStorage::lower) {  // the batch's upper-triangle order is the offsets'
          for (int c = 0; c < 36; ++c)
            if (off[c] >= 0) values[off[c]] += batch.k[c][l];
        } else {
          for (int i = 0, c = 0; i < 8; ++i)
            for (int j = 0; j < 8; ++j, ++c)
              if (off[c] >= 0) values[off[c]] += batch.k[kUpper[i][j]][l];
        }
        const auto& lp            = local(p, m.cell_tag(e), m.cells[e]);
        typename Kernel::Vector f = Kernel::Vector::Zero();
        if (has_element_load<Elem>(p, lp))
          f = Kernel::shape_load(cell_coords<Elem>(m, m.cells[e]), Kernel::restrict(lp.stiffness),
                                 Kernel::restrict(lp.thermal_strain), body_force(p.inertia, lp.density));
        add_element_rhs(
            m.cells[e], f, [&](int i, int j) { return batch.k[kUpper[i][j]][l]; }, rhs);
      }
    }
  }

  DofMap<kNd> dofs_;
  SpMat pattern_;              ///< until take_pattern()
  Eigen::Index nonzeros_ = 0;  ///< stored entries of the pattern
  std::vector<int> cell_offsets_, tri_offsets_, link_offsets_;
  Connectivity<2> links_;
  std::vector<NodeLink> link_values_;
  std::vector<char> link_owned_;  ///< per link: whether this part assembles it (all, when whole)
  std::size_t cells_ = 0, points_ = 0;
  EdgeIndex<Elem> edges_;
  LocalLawCache<Law> cache_;
  std::shared_ptr<const Subdomain> subdomain_;  ///< the problem's, when it is a part
  mutable struct {  // linear_internal's element stiffnesses of the cells with a prescribed DOF
    std::vector<double> values;
    bool valid = false;
  } kept_;
};

}  // namespace gapfe

#pragma once
// Assembler<M>: the discrete operator of a Problem, nothing else. Built once per analysis: the DOF map, the
// stiffness pattern (element and node-link couplings over the free DOFs, in the storage the model's solver
// reads), the scatter offsets of every element and link into its value array, and the history layout of
// the points. Then, for a given state, it returns what a driver asks for:
//   * linear_system       K and the right-hand side of a linear law (element loads, prescribed columns);
//   * linear_internal     K u - f of the elements and links (reactions, equilibrium check);
//   * residual, tangent   F_int(u) and the trial history of a law with history, and with tangent() K_t;
//   * external_forces     card forces and edge tractions (add_body_forces: for laws with history);
//   * add_links           node-link springs into values and right-hand side (contact, friction);
//   * nodal_stiffness     each node's diagonal block, what a contact penalty is scaled by.
// The passes over the cells are defined in assembly/linear_pass.hpp and assembly/history_pass.hpp. It owns
// no matrix values and no solver: the driver builds the System from its pattern (driver/system_setup.hpp,
// with the fill-reducing order of solver/equation_order.hpp), and keeps the displacement and history, so
// one assembler serves the linear, Newton and contact drivers alike.
//
// Conventions: full ring (core/types.hpp); element DOFs node-major; stiffness values are scattered from
// each element matrix's upper triangle, or all of it when the solver reads full storage
// (assembly/sparsity.hpp).
#include <algorithm>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "gapfe/assembly/cell_blocks.hpp"
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
  using LawCache                          = LocalLawCache<Law>;
  /// One cell's element matrix and vector, computed on any thread before they are added in the cells'
  /// order (assembly/cell_blocks.hpp).
  template <class E>
  struct CellSystem {
    typename ElementKernel<Kin, E>::Matrix k;
    typename ElementKernel<Kin, E>::Vector f;
  };

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
      if (!subdomain_)
        check_held<kNd, Elem>(p.mesh, dofs_.equation, links_);  // a part's body may be held by another
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
    {
      SpMat built = sb.build(kStorage);
      pattern_.swap(built);  // Eigen 3.4's SparseMatrix has no move: assigning would copy
    }
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
  /// Swapped out, not moved: Eigen 3.4's SparseMatrix has no move constructor, so std::move copies (the
  /// return is a named local: no copy where the compiler elides it, as GCC and Clang do even at -O0).
  SpMat take_pattern() {
    SpMat out;
    out.swap(pattern_);
    return out;
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
  void linear_system(const Problem<M>& p, const VecX& external, double* values, VecX& rhs) const;

  /// linear_system's right-hand side alone, for a stiffness assembled from the same mesh, materials and
  /// temperatures (the element loads may differ: body forces, and the part of the thermal strain in
  /// force, Problem::thermal_fraction): F_ext (free rows) + element loads -
  /// K_fp u_p. Only cells with a body or thermal load or a non-zero prescribed value compute their element
  /// system; for pressures and card forces alone this is a scan of the cells (BENCHMARKS.md, levers: a
  /// contact run's increments and a linear deck's later steps re-assembled the whole stiffness for their
  /// loads).
  void linear_rhs(const Problem<M>& p, const VecX& external, VecX& rhs) const;

  /// K u - f of a linear law's elements and of the node links at `u` (all DOFs). `prescribed_only`: only
  /// the cells with a prescribed DOF, so the entries at prescribed DOFs are complete (reactions) and those
  /// at free DOFs are not: a pass over the boundary instead of the mesh. Those cells' element stiffnesses
  /// are kept from the first such pass (when they fit in kKeptBytes) and reused until
  /// forget_kept_stiffness(): a contact run reads reactions every increment, and with u_z prescribed at
  /// every node its "boundary" is the whole mesh (BENCHMARKS.md, levers: 11 element passes of the two-tube
  /// run).
  VecX linear_internal(const Problem<M>& p, const VecX& u, bool prescribed_only = false) const;
  /// The element stiffness changed (a new assembly): linear_internal's kept matrices no longer hold.
  void forget_kept_stiffness() { kept_.valid = false, kept_.values = {}; }
  /// At most this much memory for linear_internal's kept element stiffnesses [bytes].
  static constexpr std::size_t kKeptBytes = std::size_t(64) << 20;

  /// Node links into the stiffness values and the right-hand side (after the elements).
  void add_links(double* values, VecX& rhs) const;

  /// A law with history at displacements `u` (all DOFs), from the committed states of `points`:
  /// F_int = sum_e int B^T sigma dV + node links into `internal` (all DOFs), sigma into `stress`, the new
  /// states into points' trial records. The laws may skip their tangents (StepContext::tangent).
  template <class State>
  void residual(const Problem<M>& p, const VecX& u, History<State>& points, std::vector<Vec6>& stress,
                const StepContext& ctx, VecX& internal) const {
    history_pass(p, u, points, stress, ctx, nullptr, internal, nullptr, nullptr);
  }
  /// The residual's F_int with K_t = sum_e int B^T D B dV + links into the pattern's `values` (zeroed
  /// first).
  template <class State>
  void tangent(const Problem<M>& p, const VecX& u, History<State>& points, std::vector<Vec6>& stress,
               const StepContext& ctx, double* values, VecX& internal) const {
    history_pass(p, u, points, stress, ctx, values, internal, nullptr, nullptr);
  }
  /// The same, and Newton's iteration-0 predictor = -K_fp du_p on the free rows for the step
  /// `prescribed_step` of the prescribed DOFs (all DOFs).
  template <class State>
  void tangent(const Problem<M>& p, const VecX& u, History<State>& points, std::vector<Vec6>& stress,
               const StepContext& ctx, double* values, VecX& internal, const VecX& prescribed_step,
               VecX& predictor) const {
    history_pass(p, u, points, stress, ctx, values, internal, &prescribed_step, &predictor);
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

  /// The law resolved for a cell (cached across consecutive cells; reset_cache() at the start of a pass),
  /// in the assembler's cache or in `cache` (a task's, assembly/cell_blocks.hpp).
  template <std::size_t NPC>
  const typename Law::Local& local(const Problem<M>& p, const CellTag& tag, const std::array<int, NPC>& cell,
                                   const LawCache& cache) const {
    return cache.get(p.materials, tag, cell_temperature(p.temperature, p.reference_temperature, cell),
                     p.reference_temperature, p.thermal_fraction);
  }
  template <std::size_t NPC>
  const typename Law::Local& local(const Problem<M>& p, const CellTag& tag,
                                   const std::array<int, NPC>& cell) const {
    return local(p, tag, cell, cache_);
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
  /// One pass over the cells of a law with history: residual(), and tangent() when `values` is given.
  template <class State>
  void history_pass(const Problem<M>& p, const VecX& u, History<State>& points, std::vector<Vec6>& stress,
                    const StepContext& ctx, double* values, VecX& internal, const VecX* prescribed_step,
                    VecX* predictor) const;
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
                      typename ElementKernel<Kin, E>::Matrix& k, typename ElementKernel<Kin, E>::Vector& f,
                      const LawCache& cache) const;
  template <class E, std::size_t NPC>
  void element_system(const Problem<M>& p, const std::array<int, NPC>& cell, const CellTag& tag,
                      typename ElementKernel<Kin, E>::Matrix& k,
                      typename ElementKernel<Kin, E>::Vector& f) const {
    element_system<E>(p, cell, tag, k, f, cache_);
  }

  /// Element load into the right-hand side, and the prescribed-displacement columns moved there:
  /// rhs_i += f_i - sum_j K_ij u_j over prescribed j. `k(i, j)` gives the element stiffness.
  template <std::size_t NPC, class Vector, class Stiffness>
  void add_element_rhs(const std::array<int, NPC>& cell, const Vector& f, Stiffness&& k, VecX& rhs) const;
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
                     VecX& predictor) const;

  /// Quad4 cells with 2 DOF: stiffness from the vectorized batch kernel (assembly/quad4_batch.hpp), W
  /// cells at a time; loads, when there are any, from the generic kernel.
  void quad4_batched(const Problem<M>& p, double* values, VecX& rhs) const;

  DofMap<kNd> dofs_;
  SpMat pattern_;              ///< until take_pattern()
  Eigen::Index nonzeros_ = 0;  ///< stored entries of the pattern
  std::vector<int> cell_offsets_, tri_offsets_, link_offsets_;
  Connectivity<2> links_;
  std::vector<NodeLink> link_values_;
  std::vector<char> link_owned_;  ///< per link: whether this part assembles it (all, when whole)
  std::size_t cells_ = 0, points_ = 0;
  EdgeIndex<Elem> edges_;
  LawCache cache_;
  std::shared_ptr<const Subdomain> subdomain_;  ///< the problem's, when it is a part
  mutable struct {  // linear_internal's element stiffnesses of the cells with a prescribed DOF
    std::vector<double> values;
    bool valid = false;
  } kept_;
};

}  // namespace gapfe

// Out-of-class members, one file per job.
#include "gapfe/assembly/history_pass.hpp"  // IWYU pragma: export
#include "gapfe/assembly/linear_pass.hpp"   // IWYU pragma: export

#pragma once
// LinearStatic: one linear-elastic analysis of a Problem with a compile-time Model. The DOF map, the
// sparsity pattern, the per-element scatter offsets and the solver's symbolic analysis are built
// once in the constructor; solve() re-assembles values and right-hand side (loads, temperatures and
// material constants may change between calls; which DOFs are prescribed and the mesh may not).
// Node links (assembly/node_links.hpp), declared at construction so that the pattern holds their
// couplings, add two-node springs whose values may change between solves: what contact policies use.
//
// Conventions: full ring (types.hpp). Reactions are total ring forces at prescribed DOFs.
#include <algorithm>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "gapfe/assembly/dof_map.hpp"
#include "gapfe/assembly/edge_loads.hpp"
#include "gapfe/assembly/element_kernel.hpp"
#include "gapfe/assembly/node_links.hpp"
#include "gapfe/assembly/quad4_batch.hpp"
#include "gapfe/assembly/sparsity.hpp"
#include "gapfe/mesh/mesh.hpp"
#include "gapfe/post/point_values.hpp"

namespace gapfe {

/// Everything a linear analysis needs. Node and material indices are 0-based.
template <class M>
struct Problem {
  Mesh<M::Element::kNodes> mesh;
  std::vector<typename M::Material> materials;  ///< indexed by CellTag::material
  std::vector<NodalCondition> conditions;       ///< seed Data 5, later entries win
  std::vector<EdgeLoad> edge_loads;             ///< seed Data 13-15
  InertiaLoad inertia;                          ///< seed Data 12
  VecX temperature;                             ///< nodal temperatures [deg]; empty: T_ref everywhere
  double reference_temperature = 0.0;           ///< TREF [deg]
};

/// Nodal results. Rows are nodes; columns (r, z, theta); u_theta and its reaction are 0 in 2-DOF.
struct Solution {
  Eigen::Matrix<double, Eigen::Dynamic, 3> displacement;  ///< [length]
  Eigen::Matrix<double, Eigen::Dynamic, 3> reaction;      ///< total ring force at prescribed DOFs [force]
  double residual = 0.0;  ///< |K u - f| / |f| over free DOFs after the solve (equilibrium check)
};

/// Wall-clock seconds of the last solve's phases.
struct SolveTimings {
  double assemble = 0, factorize = 0, solve = 0, reactions = 0;
};

template <class M>
class LinearStatic {
 public:
  using Kin                  = typename M::Kinematics;
  using Elem                 = typename M::Element;
  using Tri                  = typename Elem::Degenerate;
  using Law                  = typename M::Material;
  using Solver               = typename M::LinearSolver;
  static constexpr int kNd   = Kin::kDofsPerNode;
  static constexpr bool kTri = !std::is_void_v<Tri>;
  /// Quad4 with 2 DOF assembles through the vectorized batch kernel (same result, BENCHMARKS.md).
  static constexpr bool kBatchedQuad4 = std::is_same_v<Elem, Quad4> && kNd == 2;

  /// `links`: node pairs (a, b) that may carry node links; their values start at zero (link_values()).
  explicit LinearStatic(Problem<M> problem, Connectivity<2> links = {})
      : p_(std::move(problem)), links_(std::move(links)), link_values_(links_.size()) {
    validate();
    for (const auto& l : links_)
      if (l[0] < 0 || l[1] < 0 || l[0] >= p_.mesh.node_count() || l[1] >= p_.mesh.node_count() ||
          l[0] == l[1])
        throw InputError("node link (" + std::to_string(l[0] + 1) + ", " + std::to_string(l[1] + 1) +
                         "): needs two different nodes of the mesh");
    dofs_ = DofMap<kNd>::build(p_.mesh, p_.conditions);
    SparsityBuilder<kNd> sb(p_.mesh.node_count(), dofs_.equation, dofs_.free_count);
    sb.add(p_.mesh.cells);
    if constexpr (kTri) sb.add(p_.mesh.triangles);
    sb.add(links_);
    k_            = sb.build();
    cell_offsets_ = scatter_offsets<kNd>(k_, dofs_.equation, p_.mesh.cells);
    if constexpr (kTri) tri_offsets_ = scatter_offsets<kNd>(k_, dofs_.equation, p_.mesh.triangles);
    link_offsets_ = scatter_offsets<kNd>(k_, dofs_.equation, links_);
    if (dofs_.free_count > 0) solver_->analyze(k_);  // all prescribed: a pure recovery, nothing to factorize
  }

  /// Loads, temperatures and materials may be changed here between solves.
  Problem<M>& problem() { return p_; }
  const Problem<M>& problem() const { return p_; }
  const DofMap<kNd>& dofs() const { return dofs_; }
  const SpMat& stiffness() const { return k_; }  ///< lower triangle, free DOFs
  /// Displacements, reactions and the equilibrium residual of the last solve. With defer_reactions(),
  /// the reactions and residual are computed here, on the first call after a solve.
  const Solution& solution() const {
    if (reactions_stale_) {
      const auto t0 = std::chrono::steady_clock::now();
      reactions();
      time_.reactions  = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      reactions_stale_ = false;
    }
    return sol_;
  }
  /// Nodal displacements of the last solve (rows nodes, columns r, z, theta), never computing reactions.
  const Eigen::Matrix<double, Eigen::Dynamic, 3>& displacement() const { return sol_.displacement; }
  /// Compute reactions and the residual (an element pass) only when solution() is read, not in every
  /// solve: for drivers that solve several trial systems per accepted increment (contact). solve() and
  /// resolve_links() then return a Solution whose reactions and residual are stale: read solution().
  void defer_reactions(bool defer) { defer_reactions_ = defer; }
  const SolveTimings& timings() const { return time_; }
  const Connectivity<2>& links() const { return links_; }
  /// Values of the node links, parallel to links(); change them, then solve() or resolve_links().
  std::vector<NodeLink>& link_values() { return link_values_; }
  const std::vector<NodeLink>& link_values() const { return link_values_; }
  /// Number of numeric factorizations so far (contact policies report it; the pattern's symbolic
  /// analysis is done once, in the constructor).
  int factorizations() const { return factorization_count_; }

  /// Assemble, factorize, solve, recover reactions. Throws SolveError when the stiffness is singular
  /// (say, a missing constraint) and InputError for loads that do not fit the mesh or the kinematics.
  /// `same_stiffness`: the caller changed only loads and prescribed values since the last solve (not
  /// materials or temperatures) and kept the link stiffnesses, so the last factorization is reused.
  const Solution& solve(bool same_stiffness = false) {
    using clock = std::chrono::steady_clock;
    validate_loads();
    refresh_condition_values();
    auto t0 = clock::now();
    assemble();
    if (!links_.empty()) {  // keep the element-only system for resolve_links()
      k_elements_.assign(k_.valuePtr(), k_.valuePtr() + k_.nonZeros());
      rhs_elements_ = rhs_;
      add_links();
    }
    return finish(!(same_stiffness && factorized_), clock::now() - t0);
  }

  /// Solve again after changing only link_values() since the last solve(): loads, materials and
  /// conditions are as they were, so the element system is reused and, when `same_link_stiffness`,
  /// the factorization too (one back-substitution: an augmented-Lagrangian update, a split step).
  const Solution& resolve_links(bool same_link_stiffness) {
    if (k_elements_.size() != static_cast<std::size_t>(k_.nonZeros()))
      throw std::logic_error("resolve_links() needs node links and a solve() before it");
    const auto t0 = std::chrono::steady_clock::now();
    std::copy(k_elements_.begin(), k_elements_.end(), k_.valuePtr());
    rhs_ = rhs_elements_;
    add_links();
    return finish(!(same_link_stiffness && factorized_), std::chrono::steady_clock::now() - t0);
  }

  /// The kNd x kNd diagonal block of every node (zero-padded to 3 x 3), summed over the cells whose tag
  /// passes `keep`, prescribed DOFs included: the "adjacent structure's stiffness" a penalty is scaled by.
  template <class Keep>
  std::vector<Mat33> nodal_stiffness(Keep&& keep) const {
    std::vector<Mat33> out(static_cast<std::size_t>(p_.mesh.node_count()), Mat33::Zero());
    cache_valid_ = false;
    for_each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                const std::array<int, NPC>& cell, const CellTag& tag) {
      if (!keep(tag)) return;
      typename ElementKernel<Kin, E>::Matrix k;
      typename ElementKernel<Kin, E>::Vector f;
      element_system<E>(cell, tag, k, f);
      for (int a = 0; a < static_cast<int>(NPC); ++a)
        out[cell[a]].template topLeftCorner<kNd, kNd>() += k.template block<kNd, kNd>(a * kNd, a * kNd);
    });
    return out;
  }

  /// Assemble stiffness values and right-hand side only (what solve() does first); for benchmarks and
  /// for callers that want the system without solving it.
  void assemble_system() {
    validate_loads();
    refresh_condition_values();
    assemble();
  }
  const VecX& rhs() const { return rhs_; }

  /// Strain and stress at every stiffness point of every cell (after solve()).
  std::vector<PointValues> point_values() const { return recover(false); }
  /// Strain and stress at every cell's centroid (LegacyQuad: the r-bar A weighted mean of its four
  /// sub-triangles, THEORY.md 2 item 4).
  std::vector<PointValues> centroid_values() const { return recover(true); }

 protected:  // shared with NonlinearStatic (driver/nonlinear_static.hpp), which derives privately
  /// Numeric factorization of k_; a SolveError naming the equation where it broke down.
  void factorize() {
    ++factorization_count_;
    if (!(factorized_ = solver_->factorize(k_))) {
      std::string where;
      if (const int eq = solver_->failed_equation(); eq >= 0) where = " near " + describe_equation(eq);
      throw SolveError(solver_->failure() + where +
                       ": check that the constraints remove every rigid-body motion (axial translation; in "
                       "3-DOF also rotation about the axis) and that no element is degenerate");
    }
  }

  /// Factorize (when asked), solve, recover reactions; `assembly` is the time already spent assembling.
  template <class Duration>
  const Solution& finish(bool refactor, Duration assembly) {
    using clock        = std::chrono::steady_clock;
    const auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
    auto t1            = clock::now();
    if (dofs_.free_count > 0 && refactor) factorize();
    auto t2        = clock::now();
    const VecX u_f = dofs_.free_count > 0 ? solver_->solve(rhs_) : VecX();
    auto t3        = clock::now();
    if (!u_f.allFinite()) throw SolveError("the solution has non-finite values (singular stiffness?)");
    u_ = dofs_.prescribed;
    for (std::size_t d = 0; d < dofs_.equation.size(); ++d)
      if (dofs_.equation[d] >= 0) u_(static_cast<Eigen::Index>(d)) = u_f(dofs_.equation[d]);
    const int nn = p_.mesh.node_count();
    sol_.displacement.setZero(nn, 3);
    for (int n = 0; n < nn; ++n)
      for (int c = 0; c < kNd; ++c) sol_.displacement(n, c) = u_(dofs_.dof(n, c));
    reactions_stale_ = defer_reactions_;
    if (!defer_reactions_) reactions();
    auto t4 = clock::now();
    time_   = {std::chrono::duration<double>(assembly).count(), seconds(t1, t2), seconds(t2, t3),
               seconds(t3, t4)};
    return sol_;
  }

  /// An element matrix's upper triangle into the stiffness values, through its scatter offsets (-1: a
  /// prescribed row or column).
  template <class Matrix>
  static void scatter(double* values, const int* off, const Matrix& k) {
    for (int i = 0, c = 0; i < k.rows(); ++i)
      for (int j = i; j < k.cols(); ++j, ++c)
        if (off[c] >= 0) values[off[c]] += k(i, j);
  }

  /// The element (or link) DOF values of `u` (all DOFs), node-major.
  template <std::size_t NPC>
  Vec<kNd* static_cast<int>(NPC)> gather(const std::array<int, NPC>& nodes, const VecX& u) const {
    Vec<kNd* static_cast<int>(NPC)> ue;
    for (int a = 0; a < static_cast<int>(NPC); ++a)
      for (int c = 0; c < kNd; ++c) ue(a * kNd + c) = u(dofs_.dof(nodes[a], c));
    return ue;
  }
  /// out(dof) += v over the element's (or link's) DOFs.
  template <std::size_t NPC, class Vector>
  void add_to(const std::array<int, NPC>& nodes, const Vector& v, VecX& out) const {
    for (int a = 0; a < static_cast<int>(NPC); ++a)
      for (int c = 0; c < kNd; ++c) out(dofs_.dof(nodes[a], c)) += v(a * kNd + c);
  }

  /// Internal force K u_e - f_e of node link `l` at displacements `u` (all DOFs).
  Vec<2 * kNd> link_force(std::size_t l, const VecX& u) const {
    const NodeLink& link = link_values_[l];
    return link.template element_stiffness<kNd>() * gather(links_[l], u) - link.template element_load<kNd>();
  }

  /// Node links into the stiffness values and the right-hand side (after the element assembly).
  void add_links() {
    constexpr int n = 2 * kNd;
    double* values  = k_.valuePtr();
    for (std::size_t l = 0; l < links_.size(); ++l) {
      const NodeLink& link = link_values_[l];
      if (link.zero()) continue;
      const Mat<n, n> k = link.template element_stiffness<kNd>();
      scatter(values, link_offsets_.data() + l * (n * (n + 1) / 2), k);
      add_element_rhs(links_[l], link.template element_load<kNd>(), [&](int i, int j) { return k(i, j); });
    }
  }

  // ---------------------------------------------------------------- element evaluation
  template <class E>
  struct Group;  // connectivity, tags and offsets of one element type

  template <class E, std::size_t NPC>
  Mat<E::kNodes, 2> coords(const std::array<int, NPC>& cell) const {
    Mat<E::kNodes, 2> x;
    for (int a = 0; a < E::kNodes; ++a) x.row(a) = p_.mesh.nodes[cell[a]].transpose();
    return x;
  }
  template <std::size_t NPC>
  double cell_temperature(const std::array<int, NPC>& cell) const {
    if (p_.temperature.size() == 0) return p_.reference_temperature;
    double t = 0;
    for (int n : cell) t += p_.temperature(n);
    return t / static_cast<double>(NPC);
  }
  /// The law resolved for a cell; consecutive cells with the same material, frame and temperature
  /// (the usual case in structured meshes) share one evaluation.
  const typename Law::Local& local(const CellTag& tag, double T) const {
    if (!cache_valid_ || tag.material != cache_tag_.material || !(tag.frame == cache_tag_.frame) ||
        T != cache_T_) {
      cache_local_ = p_.materials[tag.material].localize(tag.frame, T, p_.reference_temperature);
      cache_tag_ = tag, cache_T_ = T, cache_valid_ = true;
    }
    return cache_local_;
  }
  BodyForce body_force(double density) const {
    return {density * p_.inertia.angular_velocity * p_.inertia.angular_velocity,
            -density * p_.inertia.axial_acceleration, -density * p_.inertia.angular_acceleration};
  }

  /// Visit every cell of both groups: f(kernel tag, cell index, cell nodes, cell tag, offsets base).
  template <class F>
  void for_each_cell(F&& f) const {
    const auto& m = p_.mesh;
    for (std::size_t e = 0; e < m.cells.size(); ++e)
      f(std::type_identity<Elem>{}, e, m.cells[e], m.cell_tag(e));
    if constexpr (kTri)
      for (std::size_t e = 0; e < m.triangles.size(); ++e)
        f(std::type_identity<Tri>{}, e, m.triangles[e], m.triangle_tag(e));
  }

  /// Condensed element stiffness and load (body + thermal) of one cell.
  template <class E, std::size_t NPC>
  void element_system(const std::array<int, NPC>& cell, const CellTag& tag,
                      typename ElementKernel<Kin, E>::Matrix& k,
                      typename ElementKernel<Kin, E>::Vector& f) const {
    using Kernel                           = ElementKernel<Kin, E>;
    const auto x                           = coords<E>(cell);
    const auto& lp                         = local(tag, cell_temperature(cell));
    const typename Kernel::StrainMatrix d  = Kernel::restrict(lp.stiffness);
    const typename Kernel::StrainVector th = Kernel::restrict(lp.thermal_strain);
    const BodyForce body                   = body_force(lp.density);
    if (!body.any() && th.isZero(0.0)) {
      k = Kernel::stiffness(x, d);
      f.setZero();
    } else {
      Kernel::condense(Kernel::shape_stiffness(x, d), Kernel::shape_load(x, d, th, body), k, f);
    }
  }

  // ---------------------------------------------------------------- assembly
  void assemble() {
    Eigen::Map<VecX>(k_.valuePtr(), k_.nonZeros()).setZero();
    rhs_         = VecX::Zero(dofs_.free_count);
    external_    = dofs_.nodal_force;
    cache_valid_ = false;
    add_edge_loads();
    for (std::size_t d = 0; d < dofs_.equation.size(); ++d)
      if (dofs_.equation[d] >= 0) rhs_(dofs_.equation[d]) += external_(static_cast<Eigen::Index>(d));
    double* values = k_.valuePtr();
    for_each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                const std::array<int, NPC>& cell, const CellTag& tag) {
      if constexpr (kBatchedQuad4 && std::is_same_v<E, Elem>) return;  // done in batches below
      using Kernel    = ElementKernel<Kin, E>;
      constexpr int n = Kernel::kDofs;
      const int* off =
          (std::is_same_v<E, Elem> ? cell_offsets_ : tri_offsets_).data() + e * (n * (n + 1) / 2);
      typename Kernel::Matrix k;
      typename Kernel::Vector f;
      element_system<E>(cell, tag, k, f);
      scatter(values, off, k);
      add_element_rhs(cell, f, [&](int i, int j) { return k(i, j); });
    });
    if constexpr (kBatchedQuad4) assemble_quad4_batched(values);
  }

  /// Element load into the right-hand side, and the prescribed-displacement columns moved there:
  /// rhs_i += f_i - sum_j K_ij u_j over prescribed j. `k(i, j)` gives the element stiffness.
  template <std::size_t NPC, class Vector, class Stiffness>
  void add_element_rhs(const std::array<int, NPC>& cell, const Vector& f, Stiffness&& k) {
    constexpr int n = kNd * static_cast<int>(NPC);
    std::array<int, n> dof;
    bool moved = false;
    for (int a = 0; a < static_cast<int>(NPC); ++a)
      for (int c = 0; c < kNd; ++c) {
        dof[a * kNd + c] = dofs_.dof(cell[a], c);
        moved |= dofs_.equation[dof[a * kNd + c]] < 0 && dofs_.prescribed(dof[a * kNd + c]) != 0;
      }
    for (int i = 0; i < n; ++i) {
      const int eq = dofs_.equation[dof[i]];
      if (eq < 0) continue;
      double r = f(i);
      if (moved)
        for (int j = 0; j < n; ++j)
          if (dofs_.equation[dof[j]] < 0) r -= k(i, j) * dofs_.prescribed(dof[j]);
      rhs_(eq) += r;
    }
  }

  /// Quad4 cells with 2 DOF: stiffness from the vectorized batch kernel (assembly/quad4_batch.hpp), W
  /// cells at a time; loads, when there are any, from the generic kernel.
  void assemble_quad4_batched(double* values) {
    using Kernel                 = ElementKernel<Kin, Elem>;
    using Batch                  = Quad4Axisym2Batch<8>;
    const auto& m                = p_.mesh;
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
        batch.set_material(
            l, local(m.cell_tag(e), cell_temperature(m.cells[e])).stiffness.template topLeftCorner<4, 4>());
      }
      batch.compute();
      for (int l = 0; l < lanes; ++l) {
        const std::size_t e = e0 + static_cast<std::size_t>(l);
        const int* off      = cell_offsets_.data() + e * 36;
        for (int c = 0; c < 36; ++c)
          if (off[c] >= 0) values[off[c]] += batch.k[c][l];
        const auto& lp                         = local(m.cell_tag(e), cell_temperature(m.cells[e]));
        const typename Kernel::StrainVector th = Kernel::restrict(lp.thermal_strain);
        const BodyForce body                   = body_force(lp.density);
        typename Kernel::Vector f              = Kernel::Vector::Zero();
        if (body.any() || !th.isZero(0.0))
          f = Kernel::shape_load(coords<Elem>(m.cells[e]), Kernel::restrict(lp.stiffness), th, body);
        add_element_rhs(m.cells[e], f, [&](int i, int j) { return batch.k[kUpper[i][j]][l]; });
      }
    }
  }

  /// Edge tractions into external_ (all DOFs). The edge must belong to a cell that has it from M to N
  /// counterclockwise, i.e. the cell lies to the left (seed Data 13).
  void add_edge_loads() {
    if (p_.edge_loads.empty()) return;
    build_edge_index();
    for (std::size_t k = 0; k < p_.edge_loads.size(); ++k) {
      const EdgeLoad& l = p_.edge_loads[k];
      const auto it     = edges_.find(edge_key(l.node_m, l.node_n));
      if (it == edges_.end()) {
        const std::string what = "edge load " + std::to_string(k + 1) + " from node " +
                                 std::to_string(l.node_m + 1) + " to node " + std::to_string(l.node_n + 1);
        if (edges_.count(edge_key(l.node_n, l.node_m)))
          throw InputError(what + ": the element must lie to the left going from M to N; swap M and N");
        throw InputError(what + ": the two nodes are not the ends of an element edge");
      }
      const auto [triangle, cell, edge] = it->second;
      if (!triangle) apply_edge<Elem>(p_.mesh.cells[cell], edge, l);
      if constexpr (kTri)
        if (triangle) apply_edge<Tri>(p_.mesh.triangles[cell], edge, l);
    }
  }
  template <class E, std::size_t NPC>
  void apply_edge(const std::array<int, NPC>& cell, int edge, const EdgeLoad& l) {
    constexpr int en = E::kEdgeNodes;
    Mat<en, 2> x;
    std::array<int, en> node;
    // kEdges lists (start, end) for 2-node edges and (start, mid, end) for 3-node edges.
    for (int a = 0; a < en; ++a)
      node[a] = cell[E::kEdges[edge][a]], x.row(a) = p_.mesh.nodes[node[a]].transpose();
    const Mat<en, 3> f = edge_forces<en>(x, l.pressure, l.shear, l.transverse_shear);
    for (int a = 0; a < en; ++a)
      for (int c = 0; c < kNd; ++c) external_(dofs_.dof(node[a], c)) += f(a, c);
  }
  static std::uint64_t edge_key(int m, int n) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(m)) << 32) | static_cast<std::uint32_t>(n);
  }
  struct EdgeRef {
    bool triangle;
    std::size_t cell;
    int edge;
  };
  void build_edge_index() {
    if (!edges_.empty()) return;
    for_each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                const std::array<int, NPC>& cell, const CellTag&) {
      for (int k = 0; k < static_cast<int>(E::kEdges.size()); ++k)
        edges_[edge_key(cell[E::kEdges[k].front()], cell[E::kEdges[k].back()])] = {!std::is_same_v<E, Elem>,
                                                                                   e, k};
    });
  }

  // ---------------------------------------------------------------- reactions
  void reactions() const {
    VecX internal = VecX::Zero(u_.size());
    cache_valid_  = false;
    for_each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                const std::array<int, NPC>& cell, const CellTag& tag) {
      using Kernel = ElementKernel<Kin, E>;
      typename Kernel::Matrix k;
      typename Kernel::Vector f;
      element_system<E>(cell, tag, k, f);
      const auto ue                    = gather(cell, u_);
      const typename Kernel::Vector fe = k * ue - f;
      add_to(cell, fe, internal);
    });
    for (std::size_t l = 0; l < links_.size(); ++l) {  // internal force of a link: K u_e - f_e
      const NodeLink& link = link_values_[l];
      if (link.zero()) continue;
      add_to(links_[l], link_force(l, u_), internal);
    }
    balance(internal);
  }

  /// sol_ from u_ and the internal forces (all DOFs): displacements, reactions = internal - external at
  /// prescribed DOFs, and the relative out-of-balance |internal - external| / |internal| at free DOFs.
  void balance(const VecX& internal) const {
    const int nn = p_.mesh.node_count();
    sol_.displacement.setZero(nn, 3);
    sol_.reaction.setZero(nn, 3);
    double out_of_balance = 0, applied = 0;
    for (int n = 0; n < nn; ++n)
      for (int c = 0; c < kNd; ++c) {
        const int d             = dofs_.dof(n, c);
        sol_.displacement(n, c) = u_(d);
        const double unbalanced = internal(d) - external_(d);
        if (dofs_.equation[d] < 0) {
          sol_.reaction(n, c) = unbalanced;
        } else {
          out_of_balance += unbalanced * unbalanced;
        }
        applied += internal(d) * internal(d);
      }
    sol_.residual = applied > 0 ? std::sqrt(out_of_balance / applied) : 0.0;
  }

  // ---------------------------------------------------------------- recovery
  std::vector<PointValues> recover(bool centroids) const {
    std::vector<PointValues> out;
    cache_valid_ = false;
    for_each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                const std::array<int, NPC>& cell, const CellTag& tag) {
      using Kernel                          = ElementKernel<Kin, E>;
      const auto x                          = coords<E>(cell);
      const auto& lp                        = local(tag, cell_temperature(cell));
      const typename Kernel::StrainMatrix d = Kernel::restrict(lp.stiffness);
      const typename Kernel::Vector ue      = gather(cell, u_);
      typename Kernel::ShapeVector us;
      if constexpr (Kernel::kInner > 0) {
        us = Kernel::expand(
            Kernel::shape_stiffness(x, d),
            Kernel::shape_load(x, d, Kernel::restrict(lp.thermal_strain), body_force(lp.density)), ue);
      } else {
        us = ue;
      }
      const Mat<E::kShapeNodes, 2> xs = E::shape_coords(x);
      const bool triangle             = !std::is_same_v<E, Elem>;
      const Mat66 to_strain_material  = strain_rotation(lp.to_material);
      const auto mean_vol             = Kernel::mean_volumetric(x);
      auto values_at                  = [&](const PointGeometry<E::kShapeNodes>& g, int point) {
        PointValues v;
        v.cell = static_cast<int>(e), v.triangle = triangle, v.point = point;
        v.r = g.r, v.z = g.N.dot(xs.col(1));
        v.strain          = Kernel::strain(g, mean_vol, us);
        v.stress          = Law::update(lp, v.strain, typename Law::State{}, StepContext{}).stress;
        v.strain_material = to_strain_material * v.strain;
        v.stress_material = lp.to_material * v.stress;
        return v;
      };
      double det = 0;
      if (!centroids) {
        for (int q = 0; q < E::kStiffnessPoints; ++q)
          out.push_back(values_at(E::stiffness_point(x, q, det), q));
      } else if constexpr (requires { E::centroid_point(x, det); }) {
        out.push_back(values_at(E::centroid_point(x, det), -1));
      } else {  // weighted mean of the stiffness points (LegacyQuad)
        PointValues mean{};
        double w = 0;
        mean.strain.setZero(), mean.stress.setZero(), mean.strain_material.setZero(),
            mean.stress_material.setZero();
        for (int q = 0; q < E::kStiffnessPoints; ++q) {
          const auto g        = E::stiffness_point(x, q, det);
          const PointValues v = values_at(g, q);
          w += g.weight;
          mean.r += g.weight * v.r, mean.z += g.weight * v.z;
          mean.strain += g.weight * v.strain, mean.stress += g.weight * v.stress;
          mean.strain_material += g.weight * v.strain_material,
              mean.stress_material += g.weight * v.stress_material;
        }
        mean.r /= w, mean.z /= w, mean.strain /= w, mean.stress /= w;
        mean.strain_material /= w, mean.stress_material /= w;
        mean.cell = static_cast<int>(e), mean.triangle = triangle, mean.point = -1;
        out.push_back(mean);
      }
    });
    return out;
  }

  // ---------------------------------------------------------------- checks
  void validate() const {
    const auto& m = p_.mesh;
    if (m.nodes.empty()) throw InputError("the mesh has no nodes");
    if (m.cells.empty() && m.triangles.empty()) throw InputError("the mesh has no cells");
    if (p_.materials.empty()) throw InputError("no materials given");
    for (std::size_t i = 0; i < p_.materials.size(); ++i)
      p_.materials[i].validate("material " + std::to_string(i + 1));
    if (!m.cell_tags.empty() && m.cell_tags.size() != m.cells.size())
      throw InputError("mesh: cell_tags must be empty or one per cell");
    if (!m.triangle_tags.empty() && m.triangle_tags.size() != m.triangles.size())
      throw InputError("mesh: triangle_tags must be empty or one per triangle");
    if constexpr (!kTri)
      if (!m.triangles.empty())
        throw InputError("this element type has no 3-node companion: the mesh must not contain triangles");
    for (const auto& x : m.nodes)
      if (!x.allFinite()) throw InputError("mesh: a node has non-finite coordinates");
    for_each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                const std::array<int, NPC>& cell, const CellTag& tag) {
      const std::string name =
          std::string(std::is_same_v<E, Elem> ? "element " : "triangle ") + std::to_string(e + 1);
      for (int n : cell)
        if (n < 0 || n >= m.node_count()) throw InputError(name + ": node index out of range");
      if (tag.material < 0 || tag.material >= static_cast<int>(p_.materials.size()))
        throw InputError(name + ": material " + std::to_string(tag.material + 1) + " is not defined");
      if (!std::isfinite(tag.frame.beta) || !std::isfinite(tag.frame.alpha))
        throw InputError(name + ": non-finite material angle");
      const auto x = coords<E>(cell);
      double det   = 0;
      for (int q = 0; q < E::kStiffnessPoints; ++q) {
        const auto g = E::stiffness_point(x, q, det);
        if (!(det > 0) || !(g.r > 0)) {
          std::string nodes;
          for (int n : cell) nodes += " " + std::to_string(n + 1);
          throw InputError(name + " (nodes" + nodes +
                           ") is inverted, degenerate or not counterclockwise (Jacobian " +
                           std::to_string(det) + " at point " + std::to_string(q + 1) + ")");
        }
      }
    });
    if (p_.temperature.size() != 0 && p_.temperature.size() != m.node_count())
      throw InputError("temperature: one value per node expected, got " +
                       std::to_string(p_.temperature.size()));
  }
  /// Condition values may change between solves; which DOFs they prescribe may not.
  void refresh_condition_values() {
    DofMap<kNd> now = DofMap<kNd>::build(p_.mesh, p_.conditions);
    if (now.equation != dofs_.equation)
      throw InputError("boundary conditions: the set of prescribed DOFs changed after construction");
    dofs_ = std::move(now);
  }

  void validate_loads() const {
    if (!p_.temperature.allFinite() || !std::isfinite(p_.reference_temperature))
      throw InputError("temperature: non-finite value");
    const auto& in = p_.inertia;
    if (!std::isfinite(in.axial_acceleration) || !std::isfinite(in.angular_velocity) ||
        !std::isfinite(in.angular_acceleration))
      throw InputError("inertia load: non-finite value");
    for (std::size_t k = 0; k < p_.edge_loads.size(); ++k) {
      const auto& l = p_.edge_loads[k];
      if (!std::isfinite(l.pressure) || !std::isfinite(l.shear) || !std::isfinite(l.transverse_shear))
        throw InputError("edge load " + std::to_string(k + 1) + ": non-finite value");
      if (kNd == 2 && l.transverse_shear != 0)
        throw InputError("edge load " + std::to_string(k + 1) +
                         ": a transverse (theta) shear needs the 3-DOF (SAGA) kinematics");
    }
    if (kNd == 2 && in.angular_acceleration != 0)
      throw InputError(
          "inertia load: angular acceleration loads u_theta and needs the 3-DOF (SAGA) kinematics");
  }
  std::string describe_equation(int eq) const {
    for (std::size_t d = 0; d < dofs_.equation.size(); ++d)
      if (dofs_.equation[d] == eq) return "node " + std::to_string(d / kNd + 1) + " " + dof::kName[d % kNd];
    return "equation " + std::to_string(eq);
  }

  Problem<M> p_;
  DofMap<kNd> dofs_;
  SpMat k_;
  VecX rhs_, external_, u_;
  std::vector<int> cell_offsets_, tri_offsets_;
  Connectivity<2> links_;
  std::vector<NodeLink> link_values_;
  std::vector<int> link_offsets_;
  std::vector<double> k_elements_;  // element-only stiffness values (scenes with links)
  VecX rhs_elements_;               // element-only right-hand side (scenes with links)
  int factorization_count_        = 0;
  std::unique_ptr<Solver> solver_ = std::make_unique<Solver>();  // solvers are not movable
  bool factorized_                = false;                       // solver_ holds a factorization of k_
  mutable Solution sol_;  // reactions and residual filled lazily with defer_reactions()
  mutable SolveTimings time_;
  mutable bool reactions_stale_ = false;
  bool defer_reactions_         = false;
  std::unordered_map<std::uint64_t, EdgeRef> edges_;
  mutable typename Law::Local cache_local_{};
  mutable CellTag cache_tag_{};
  mutable double cache_T_   = 0;
  mutable bool cache_valid_ = false;
};

}  // namespace gapfe

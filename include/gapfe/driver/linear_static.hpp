#pragma once
// LinearStatic: one linear-elastic analysis of a Problem with a compile-time Model, as a short sequence
// of the engine's pieces: the Assembler (assembly/assembler.hpp) builds the DOF map, the pattern and the
// scatter offsets once; the System (solver/system.hpp) holds the values and runs the solver's symbolic
// analysis once; recovery (post/recovery.hpp) turns displacements into reactions and point values.
// solve() re-assembles the right-hand side, and the stiffness values only when a material law or a
// temperature changed since the last assembly (laws compared with ==; a law type without == is taken as
// changed): loads, temperatures and material constants may change between calls; which DOFs are
// prescribed and the mesh may not.
//
// Node links (assembly/node_links.hpp), declared at construction so that the pattern holds their
// couplings, add two-node springs whose values may change between solves: what contact policies use.
//
// Conventions: full ring (core/types.hpp). Reactions are total ring forces at prescribed DOFs.
#include <algorithm>
#include <chrono>
#include <concepts>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "gapfe/assembly/assembler.hpp"
#include "gapfe/driver/system_setup.hpp"
#include "gapfe/post/balance.hpp"
#include "gapfe/post/error_estimate.hpp"
#include "gapfe/post/recovery.hpp"
#include "gapfe/problem/problem.hpp"
#include "gapfe/problem/results.hpp"
#include "gapfe/solver/system.hpp"

namespace gapfe {

template <class M>
class LinearStatic {
 public:
  using Law                = typename M::Material;
  static constexpr int kNd = M::kDofsPerNode;

  /// `links`: node pairs (a, b) that may carry node links; their values start at zero (link_values()).
  /// `solver`: the linear solver (empty: a default-constructed M::LinearSolver).
  explicit LinearStatic(Problem<M> problem, Connectivity<2> links = {},
                        std::unique_ptr<typename M::LinearSolver> solver = nullptr)
      : p_(std::move(problem)),
        assembler_(p_, std::move(links)),
        system_(make_system<typename M::LinearSolver>(assembler_, p_, std::move(solver))) {}

  /// Loads, temperatures and materials may be changed here between solves.
  Problem<M>& problem() { return p_; }
  const Problem<M>& problem() const { return p_; }
  const DofMap<kNd>& dofs() const { return assembler_.dofs(); }
  const SpMat& stiffness() const { return system_.matrix(); }  ///< free DOFs, solver storage
  const VecX& rhs() const { return system_.rhs(); }
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
  const SolveTimings& timings() const { return time_; }  ///< of the last solve
  /// Summed over every solve so far (a contact increment's Newton and Uzawa re-solves included).
  const SolveTimings& total_timings() const { return total_; }
  const Connectivity<2>& links() const { return assembler_.links(); }
  /// Values of the node links, parallel to links(); change them, then solve() or resolve_links().
  std::vector<NodeLink>& link_values() { return assembler_.link_values(); }
  const std::vector<NodeLink>& link_values() const { return assembler_.link_values(); }
  /// The last solve is done: frees the factorization and the stiffness (System::release; a partitioned
  /// problem's distributed system keeps them). The recovery, the error estimate and the files read the
  /// displacements, the problem and the assembler only. solve() and resolve_links() after it are logic
  /// errors.
  void release_solver() {
    (void)solution();  // deferred reactions read the matrix: now or never
    system_.release();
  }
  /// The last factorization's size and work, when the solver counts them (System::statistics).
  const FactorStatistics& factor_statistics() const { return system_.statistics(); }
  /// Number of numeric factorizations so far.
  int factorizations() const { return system_.factorizations(); }
  /// The "adjacent structure's stiffness" per node over the cells whose tag passes `keep`.
  template <class Keep>
  std::vector<Mat33> nodal_stiffness(Keep&& keep) const {
    return assembler_.nodal_stiffness(p_, std::forward<Keep>(keep));
  }

  /// Assemble (the right-hand side; the stiffness too when a law or temperature changed), factorize,
  /// solve, recover reactions. Throws SolveError when the stiffness is singular
  /// (say, a missing constraint) and InputError for loads that do not fit the mesh or the kinematics.
  /// `same_stiffness`: the caller changed only loads and prescribed values since the last solve (not
  /// materials or temperatures) and kept the link stiffnesses, so the last factorization is reused.
  const Solution& solve(bool same_stiffness = false) {
    if (system_.released()) throw std::logic_error("LinearStatic::solve() after release_solver()");
    const auto t0 = std::chrono::steady_clock::now();
    if (stiffness_current()) {  // loads only: the element values are those of the last assembly
      if (!links().empty() && system_.saved()) system_.restore();
      assembler_.refresh(p_);
      external_ = assembler_.external_forces(p_);
      assembler_.linear_rhs(p_, external_, system_.rhs());
    } else {
      assemble_system();
    }
    if (!links().empty()) {  // keep the element-only system for resolve_links()
      system_.save();
      assembler_.add_links(system_.values(), system_.rhs());
    }
    return finish(!(same_stiffness && system_.factorized()), std::chrono::steady_clock::now() - t0);
  }

  /// Solve again after changing only link_values() since the last solve(): loads, materials and
  /// conditions are as they were, so the element system is reused and, when `same_link_stiffness`,
  /// the factorization too (one back-substitution: an augmented-Lagrangian update, a split step).
  const Solution& resolve_links(bool same_link_stiffness) {
    if (links().empty() || !system_.saved() || system_.released())
      throw std::logic_error(
          "resolve_links() needs node links and a solve() before it, and no release_solver()");
    const auto t0 = std::chrono::steady_clock::now();
    system_.restore();
    assembler_.add_links(system_.values(), system_.rhs());
    return finish(!(same_link_stiffness && system_.factorized()), std::chrono::steady_clock::now() - t0);
  }

  /// Assemble stiffness values and right-hand side only (what solve() does first, without the links);
  /// for benchmarks and for callers that want the system without solving it.
  void assemble_system() {
    if (system_.released()) throw std::logic_error("LinearStatic: assembling after release_solver()");
    assembler_.refresh(p_);
    external_ = assembler_.external_forces(p_);
    assembler_.linear_system(p_, external_, system_.values(), system_.rhs());
    assembler_.forget_kept_stiffness();
    if constexpr (std::equality_comparable<Law>) {
      assembled_.materials             = p_.materials;
      assembled_.temperature           = p_.temperature;
      assembled_.reference_temperature = p_.reference_temperature;
      assembled_.valid                 = true;
    }
  }
  /// Whether the stiffness values in the system are those of the current laws and temperatures (the
  /// last assembly's inputs are kept for this: the laws and one temperature per node).
  bool stiffness_current() const {
    if constexpr (std::equality_comparable<Law>) {
      const auto& a = assembled_;
      return a.valid && a.reference_temperature == p_.reference_temperature && a.materials == p_.materials &&
             a.temperature.size() == p_.temperature.size() && a.temperature.cwiseEqual(p_.temperature).all();
    } else {
      return false;
    }
  }

  /// Strain and stress at every stiffness point of every cell (after solve()).
  std::vector<PointValues> point_values() const {
    return recover(assembler_, p_, u_, ElasticStress<Law>{}, false);
  }
  /// Strain and stress at every cell's centroid (LegacyQuad: the r-bar A weighted mean of its four
  /// sub-triangles, docs/theory.md 2 item 4).
  /// `what`: Recovered::stress leaves strain and the material-axes values out (post/recovery.hpp).
  std::vector<PointValues> centroid_values(Recovered what = Recovered::all) const {
    return recover(assembler_, p_, u_, ElasticStress<Law>{}, true, what);
  }
  /// The recovery estimate of the energy-norm error, per cell and whole, leaving out cells of the `skip`
  /// materials (post/error_estimate.hpp); and, into `centroids` when given,
  /// centroid_values(Recovered::stress) from the same pass; `weights`, when given, keeps the recovery's fit
  /// for the next estimate on this mesh (post/recovery_weights.hpp: a mesh changed in place, nodes moved, is
  /// noticed by its fingerprint and fitted again).
  ErrorEstimate error_estimate(const std::vector<int>& skip        = {},
                               std::vector<PointValues>* centroids = nullptr,
                               RecoveryWeights* weights            = nullptr) const {
    return estimate_error(assembler_, p_, u_, ElasticStress<Law>{}, skip, centroids, weights);
  }

 private:
  /// Factorize (when asked), solve, recover reactions; `assembly` is the time already spent assembling.
  template <class Duration>
  const Solution& finish(bool refactor, Duration assembly) {
    using clock        = std::chrono::steady_clock;
    const auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
    const auto& dofs   = assembler_.dofs();
    auto t1            = clock::now();
    if (system_.active() && refactor) system_.factorize([&](int eq) { return dofs.describe(eq); });
    auto t2        = clock::now();
    const VecX u_f = system_.active() ? system_.solve(system_.rhs()) : VecX();
    auto t3        = clock::now();
    if (!u_f.allFinite()) throw SolveError("the solution has non-finite values (singular stiffness?)");
    u_ = dofs.prescribed;
    for (std::size_t d = 0; d < dofs.equation.size(); ++d)
      if (dofs.equation[d] >= 0) u_(static_cast<Eigen::Index>(d)) = u_f(dofs.equation[d]);
    nodal_displacements<kNd>(u_, p_.mesh.node_count(), sol_);
    reactions_stale_ = defer_reactions_;
    if (!defer_reactions_) reactions();
    auto t4 = clock::now();
    time_   = {std::chrono::duration<double>(assembly).count(), seconds(t1, t2), seconds(t2, t3),
               seconds(t3, t4)};
    total_.assemble += time_.assemble, total_.factorize += time_.factorize, total_.solve += time_.solve,
        total_.reactions += time_.reactions;
    return sol_;
  }
  /// Reactions and the equilibrium residual. The free rows come from the assembled system, node links
  /// included, K_ff u_f - rhs_f = F_int,f - F_ext,f (a sparse product), and only the cells with a
  /// prescribed DOF are visited for the reactions (the links' forces are added at every DOF): a pass over
  /// the boundary, not the mesh (BENCHMARKS.md "Levers, each measured": the full pass was 4% of a
  /// 1e6-equation run and, with links, 10% of the two-tube contact run).
  void reactions() const {
    const auto& dofs = assembler_.dofs();
    // The global balance's terms no nodal vector holds: the body forces (element loads) and the links'
    // torque.
    const Vec2 body = body_force_totals(assembler_, p_);
    double terms[3] = {body(0), body(1), link_torque(assembler_, p_, u_)};
    if (const Subdomain* part = p_.subdomain.get()) part->sum(terms, 3);
    SolveLoads solved{nullptr, load_peak_, Vec2(terms[0], terms[1]), terms[2]};
    if (dofs.free_count == 0) {  // (the `load` too: a part's calls are collective, every part makes them)
      const VecX none = VecX::Zero(external_.size());
      solved.load     = &none;
      nodal_results(dofs, u_, assembler_.linear_internal(p_, u_), external_, p_.mesh.nodes, sol_,
                    p_.subdomain.get(), solved);
      return;
    }
    VecX internal = assembler_.linear_internal(p_, u_, /*prescribed_only=*/true);
    VecX u_free(dofs.free_count);
    for (std::size_t d = 0; d < dofs.equation.size(); ++d)
      if (const int eq = dofs.equation[d]; eq >= 0) u_free(eq) = u_(static_cast<Eigen::Index>(d));
    const SpMat& k = system_.matrix();
    VecX out_of_balance;
    if constexpr (storage_of<typename M::LinearSolver>() == MatrixStorage::lower)
      out_of_balance = k.selfadjointView<Eigen::Lower>() * u_free;
    else
      out_of_balance = k * u_free;
    out_of_balance -= system_.rhs();
    // The whole load of the free rows is the solved system's right-hand side without the node links
    // (nodal_results' `load`): a closed gap pair's link force is its penalty times its gap, and it would
    // hide the round-off a large penalty brings, which the residual is there to show.
    const VecX& loads = links().empty() ? system_.rhs() : system_.saved_rhs();
    VecX load         = VecX::Zero(external_.size());
    for (std::size_t d = 0; d < dofs.equation.size(); ++d)
      if (const int eq = dofs.equation[d]; eq >= 0) {
        internal(static_cast<Eigen::Index>(d)) = out_of_balance(eq) + external_(static_cast<Eigen::Index>(d));
        load(static_cast<Eigen::Index>(d))     = loads(eq);
      }
    solved.load = &load;
    load_peak_ =
        nodal_results(dofs, u_, internal, external_, p_.mesh.nodes, sol_, p_.subdomain.get(), solved);
  }

  Problem<M> p_;
  Assembler<M> assembler_;
  System<typename M::LinearSolver> system_;
  VecX external_, u_;     ///< all DOFs
  mutable Solution sol_;  // reactions and residual filled lazily with defer_reactions()
  mutable double load_peak_ =
      0;  ///< the largest |load|^2 and |F_int|^2 of the solves so far (SolveLoads::peak)
  mutable SolveTimings time_;
  SolveTimings total_;
  mutable bool reactions_stale_ = false;
  bool defer_reactions_         = false;
  struct {  // what the stiffness values in system_ were assembled from (stiffness_current())
    std::vector<Law> materials;
    VecX temperature;
    double reference_temperature = 0;
    bool valid                   = false;
  } assembled_;
};

}  // namespace gapfe

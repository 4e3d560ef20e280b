#pragma once
// NonlinearStatic: load-stepped equilibrium of a Model whose material law has history (Hill plasticity,
// material/hill.hpp). The same pieces as LinearStatic (assembler, system, recovery), plus the history of
// every stiffness point (core/history.hpp) and Newton iterations.
//
// One step: the loads and prescribed values now in problem() are the totals at the end of the step.
//   R(u) = F_ext - F_int(u),   F_int = sum_e int B^T sigma dV (+ node links),   K_t = sum_e int B^T D B dV,
// with sigma and D from Law::update(local, eps(u), committed state, context()). Iteration 0 starts from
// the committed displacements and takes the change of the prescribed values through K_fp (a linearized
// predictor), or, for laws with kIterate after a first accepted step, from the last step's displacement
// change extrapolated (NewtonOptions::extrapolate; no solve at all when that start is already in
// equilibrium). Each iteration refactorizes K_t unless it is bit for bit the last factorized one (every
// point elastic: System::skip_unchanged); the pattern and its analysis never change. An evaluation that is
// expected to end the step (converged_next()) computes F_int alone: its tangent would never be factorized.
//   * Laws with kIterate (ReturnMapping): Newton until |R_free| <= tolerance |F_int| (over all DOFs, so
//     reactions count and displacement-controlled steps are measured too; or the loads the step starts
//     from, and the accepted steps', where larger: start_scale(), docs/checks.md). Every iteration's residual
//     is kept in the report (the quadratic-convergence test reads it).
//   * Laws without (Tangent): the seed's one linear solve per increment with the start-of-step tangent.
//     The out-of-balance left is reported; the next step's residual carries it (equilibrium correction),
//     so the error does not accumulate as in a purely incremental scheme.
// History is committed only by commit(): a rejected, repeated or split step leaves no trace. The caller
// sets the step's time and dt in context() before solve(); rate-dependent laws read them.
//
// Not LegacyQuad: its condensed interior displacements would need history too (Quad4, Quad4BBar, Quad8 are).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

#include "gapfe/assembly/assembler.hpp"
#include "gapfe/core/combinations.hpp"
#include "gapfe/core/history.hpp"
#include "gapfe/driver/newton_options.hpp"
#include "gapfe/driver/system_setup.hpp"
#include "gapfe/post/balance.hpp"
#include "gapfe/post/error_estimate.hpp"
#include "gapfe/post/recovery.hpp"
#include "gapfe/problem/problem.hpp"
#include "gapfe/problem/results.hpp"
#include "gapfe/solver/system.hpp"

namespace gapfe {

template <class M>
class NonlinearStatic {
 public:
  using Kin                = typename M::Kinematics;
  using Elem               = typename M::Element;
  using Law                = typename M::Material;
  using State              = typename Law::State;
  static constexpr int kNd = Kin::kDofsPerNode;
  static_assert(unsupported({.history = true, .condensed = condensed<Elem>()}).empty(),
                "NonlinearStatic: elements with condensed interior nodes (LegacyQuad) are not supported; "
                "use Quad4BBar, Quad4 or Quad8");

  /// `solver`: the linear solver (empty: a default-constructed M::LinearSolver).
  explicit NonlinearStatic(Problem<M> scene, Connectivity<2> link_pairs = {}, NewtonOptions options = {},
                           std::unique_ptr<typename M::LinearSolver> solver = nullptr)
      : p_(std::move(scene)),
        assembler_(p_, std::move(link_pairs)),
        system_(make_system<typename M::LinearSolver>(assembler_, p_, std::move(solver))),
        options_(options),
        points_(assembler_.point_count()),
        stress_(assembler_.point_count(), Vec6::Zero()),
        u_(VecX::Zero(kNd * p_.mesh.node_count())),
        u_committed_(u_) {
    if (!(options_.tolerance > 0) || options_.max_iterations < 1 || !(options_.stall_factor >= 0))
      throw InputError("Newton options: tolerance must be > 0, max_iterations >= 1 and stall_factor >= 0");
    system_.skip_unchanged(true);  // elastic iterations reassemble the same stiffness: factorize it once
  }

  Problem<M>& problem() { return p_; }
  const Problem<M>& problem() const { return p_; }
  const DofMap<kNd>& dofs() const { return assembler_.dofs(); }
  const SpMat& stiffness() const { return system_.matrix(); }  ///< the last tangent assembled, solver storage
  const Solution& solution() const { return sol_; }
  const Eigen::Matrix<double, Eigen::Dynamic, 3>& displacement() const { return sol_.displacement; }
  void defer_reactions(bool) {}  // a no-op: every Newton iteration computes the internal forces
  /// Of the last solve(): `assemble` the element passes (return maps, tangent, internal forces),
  /// `factorize` and `solve` the linear algebra, `reactions` the residual and nodal results.
  const SolveTimings& timings() const { return time_; }
  const SolveTimings& total_timings() const { return total_; }  ///< summed over every solve() so far
  const Connectivity<2>& links() const { return assembler_.links(); }
  std::vector<NodeLink>& link_values() { return assembler_.link_values(); }
  const std::vector<NodeLink>& link_values() const { return assembler_.link_values(); }
  /// Numeric factorizations so far (an iteration whose tangent is the last one, bit for bit, reuses it).
  int factorizations() const { return system_.factorizations(); }
  const FactorStatistics& factor_statistics() const { return system_.statistics(); }  ///< the last one's
  /// Elastic stiffness per node over the cells `keep` passes: what a contact penalty is scaled by.
  template <class Keep>
  std::vector<Mat33> nodal_stiffness(Keep&& keep) const {
    return assembler_.nodal_stiffness(p_, std::forward<Keep>(keep));
  }

  /// `update(u, start)` sets link_values() for u (all DOFs) before each internal-force evaluation (`start`: a
  /// Newton pass's first), so links nonlinear in u (Coulomb friction, driver/contact_static.hpp) converge in
  /// the Newton loop with the material history. Empty: the links stay as set.
  void set_link_update(std::function<void(const VecX&, bool)> update) { link_update_ = std::move(update); }

  /// Time and step size handed to the law (rate-dependent laws read them).
  StepContext& context() { return context_; }
  const StepReport& report() const { return report_; }
  /// History at every stiffness point, cells then triangles, committed by the last commit().
  const std::vector<State>& states() const { return points_.committed(); }
  /// History after the last solve() (what commit() would keep).
  const std::vector<State>& trial_states() const { return points_.trial(); }

  /// Equilibrium at the loads now in problem(), from the committed state. Throws SolveError when the
  /// iterations do not converge (the committed state is untouched: reject() and cut the step).
  const Solution& solve() {
    const bool extrapolate = Law::kIterate && options_.extrapolate && previous_dt_ > 0 && context_.dt > 0 &&
                             u_previous_.size() > 0;
    if (!extrapolate) return newton(false);
    try {
      return newton(true);
    } catch (const SolveError&) {
      // The trend broke (a new load program, as SAAC3X's switch from stress to strain rate): start again
      // from the committed state, the linearized predictor's start, before the caller cuts the step.
      const StepReport spent = report_;
      points_.reject();
      newton(false);
      report_.iterations += spent.iterations;
      report_.evaluations += spent.evaluations;
      report_.tangents += spent.tangents;
      return sol_;
    }
  }

  /// The LinearStatic calls of a contact driver: both iterate from the committed state (the
  /// stiffness changes anyway).
  const Solution& solve(bool /*same_stiffness*/) { return solve(); }
  const Solution& resolve_links(bool /*same_link_stiffness*/) { return solve(); }

  /// Accept the last solve(): its history becomes the committed state.
  void commit() {
    points_.commit();
    u_previous_  = std::move(u_committed_);
    u_committed_ = u_;
    previous_dt_ = context_.dt;
    last_solves_ = report_.converged ? report_.iterations : -1;
    load_peak_   = std::max(load_peak_, step_scale_);
  }
  /// Forget the last solve(): back to the committed state.
  void reject() { points_.reject(), u_ = u_committed_; }
  /// Strain, stress and eqps at every stiffness point (the last solve()).
  std::vector<PointValues> point_values() const { return recover(assembler_, p_, u_, stored(), false); }
  /// Their volume-weighted mean per cell; `what` = Recovered::stress: no strain, no material axes.
  std::vector<PointValues> centroid_values(Recovered what = Recovered::all) const {
    return recover(assembler_, p_, u_, stored(), true, what);
  }
  /// The recovery estimate of the energy-norm error (post/error_estimate.hpp), without `skip` materials;
  /// `centroids` and `weights` as LinearStatic's.
  ErrorEstimate error_estimate(const std::vector<int>& skip        = {},
                               std::vector<PointValues>* centroids = nullptr,
                               RecoveryWeights* weights            = nullptr) const {
    return estimate_error(assembler_, p_, u_, stored(), skip, centroids, weights);
  }

 private:
  /// Newton from the committed state (extrapolate: from the extrapolated trend, NewtonOptions).
  const Solution& newton(bool extrapolate) {
    // Each phase's time goes to the last solve's and to the totals as it ends, so that a solve that
    // throws (a step the driver cuts) is counted too.
    using clock = std::chrono::steady_clock;
    auto lap    = [this, last = clock::now()](double SolveTimings::*phase) mutable {
      const auto now = clock::now();
      const double t = std::chrono::duration<double>(now - last).count();
      time_.*phase += t, total_.*phase += t;
      last = now;
    };
    time_ = {};
    assembler_.refresh(p_);
    const auto& dofs = assembler_.dofs();
    external_        = assembler_.external_forces(p_);
    assembler_.add_body_forces(p_, external_);
    u_                   = u_committed_;
    VecX prescribed_step = VecX::Zero(u_.size());  // change of the prescribed values over the step
    if (extrapolate) u_ += (context_.dt / previous_dt_) * (u_committed_ - u_previous_);
    for (Eigen::Index d = 0; d < u_.size(); ++d)
      if (dofs.equation[d] < 0) {
        if (extrapolate)
          u_(d) = dofs.prescribed(d);
        else
          prescribed_step(d) = dofs.prescribed(d) - u_(d);
      }
    report_ = {};
    // The residuals of the last two evaluations (NaN: none), for converged_next().
    double last = std::numeric_limits<double>::quiet_NaN(), before_last = last;
    // After a step whose extrapolated start was in equilibrium (elastic and proportional), expect the same.
    bool tangent = !(extrapolate && last_solves_ == 0 && options_.predict_convergence);
    evaluate(tangent, &prescribed_step);
    lap(&SolveTimings::assemble);
    step_scale_       = start_scale(!extrapolate);
    const double peak = std::max(load_peak_, step_scale_);  // SolveLoads::peak of every residual below
    if (extrapolate) {  // the extrapolated start may already be in equilibrium (a proportional elastic step)
      nodal_results(dofs, u_, internal_, external_, p_.mesh.nodes, sol_, p_.subdomain.get(),
                    {&external_, peak, Vec2::Zero(), links_torque()});
      if (!std::isfinite(sol_.residual)) throw SolveError("the residual is not finite");
      report_.converged = sol_.residual <= options_.tolerance;
      if (report_.converged) report_.residuals.push_back(sol_.residual);
      lap(&SolveTimings::reactions);
      last = sol_.residual;
      if (!report_.converged && !tangent) {  // expected wrongly: the same state again, with its tangent
        evaluate(true, &prescribed_step);
        lap(&SolveTimings::assemble);
      }
    }
    for (int it = 0; !report_.converged; ++it) {
      VecX rhs = predictor_;
      for (Eigen::Index d = 0; d < u_.size(); ++d)
        if (const int eq = dofs.equation[d]; eq >= 0) rhs(eq) += external_(d) - internal_(d);
      VecX du_free;
      if (system_.active()) {
        system_.factorize([&](int eq) { return dofs.describe(eq); });
        lap(&SolveTimings::factorize);
        du_free = system_.solve(rhs);
        if (!du_free.allFinite()) throw SolveError("the Newton correction has non-finite values");
      }
      for (Eigen::Index d = 0; d < u_.size(); ++d) {
        const int eq = dofs.equation[d];
        u_(d) += eq >= 0 ? du_free(eq) : prescribed_step(d);
      }
      prescribed_step.setZero();
      lap(&SolveTimings::solve);
      const bool again = Law::kIterate;
      tangent          = again && !converged_next(it + 1, before_last, last);
      evaluate(tangent, nullptr);
      lap(&SolveTimings::assemble);
      nodal_results(dofs, u_, internal_, external_, p_.mesh.nodes, sol_, p_.subdomain.get(),
                    {&external_, peak, Vec2::Zero(), links_torque()});
      report_.residuals.push_back(sol_.residual);
      report_.iterations = it + 1;
      if (!std::isfinite(sol_.residual)) throw SolveError("the residual is not finite");
      if (sol_.residual <= options_.tolerance) report_.converged = true;
      if (!report_.converged && stalled()) report_.converged = report_.stalled = true;
      lap(&SolveTimings::reactions);
      if (!again || report_.converged) break;
      if (it + 1 >= options_.max_iterations) {
        std::ostringstream s;
        s << "Newton did not converge in " << options_.max_iterations << " iterations (relative residuals";
        for (double r : report_.residuals) s << " " << r;
        s << "; tolerance " << options_.tolerance << "): cut the load step";
        throw SolveError(s.str());
      }
      if (!tangent) {  // expected to converge and did not: the same state again, with its tangent
        evaluate(true, nullptr);
        lap(&SolveTimings::assemble);
      }
      before_last = last;
      last        = sol_.residual;
    }
    for (const State& s : points_.trial()) report_.plastic_points += s.plastic;
    report_.drift      = drift();
    report_.time_error = time_error();
    if (const Subdomain* part = p_.subdomain.get()) {  // a part's points are its own: sum and max over parts
      double points = report_.plastic_points;
      part->sum(&points, 1);
      report_.plastic_points = static_cast<int>(points);
      report_.drift          = part->max(report_.drift);
      report_.time_error     = part->max(report_.time_error);
    }
    lap(&SolveTimings::reactions);
    return sol_;
  }

  /// The loads a step starts from, a sum of squares: the external loads and, from the committed state
  /// (`committed`), the structure's internal force there without the node links' (collective). A heated
  /// body starts with its thermal load there, which a free expansion relaxes to nothing, so that its
  /// residual, measured against its internal force alone, would be round-off over round-off; a step that
  /// unloads starts with the load it takes off. Not an extrapolated start's internal force (a guess, which
  /// grows with the ratio of the steps' dt), nor the iterates' (a diverging one must not loosen the test of
  /// the next), nor the links' (a gap pair's penalty times an overlap is no load).
  double start_scale(bool committed) const {
    VecX structure = committed ? internal_ : VecX::Zero(internal_.size()), loads = external_;
    if (committed && !links().empty()) {
      VecX link_forces = VecX::Zero(u_.size());
      assembler_.add_link_forces(u_, link_forces);
      structure -= link_forces;
    }
    const Subdomain* part = p_.subdomain.get();
    if (part) part->sum_shared(structure.data(), kNd), part->sum_shared(loads.data(), kNd);
    const int counted = part ? part->owned_nodes() : p_.mesh.node_count();
    double sums[2]    = {0, 0};
    for (int n = 0; n < counted; ++n)
      for (int c = 0; c < kNd; ++c) {
        const int d = assembler_.dofs().dof(n, c);
        sums[0] += structure(d) * structure(d), sums[1] += loads(d) * loads(d);
      }
    if (part) part->sum(sums, 2);
    return std::max(sums[0], sums[1]);
  }
  /// The node links' torque at u_ over every part (the global balance's gap term; collective).
  double links_torque() const {
    double torque = link_torque(assembler_, p_, u_);
    if (const Subdomain* part = p_.subdomain.get()) part->sum(&torque, 1);
    return torque;
  }
  /// NewtonOptions::stall_factor's test on this step's residuals so far.
  bool stalled() const {
    const auto& r                 = report_.residuals;
    constexpr std::size_t kWindow = 3;
    if (r.size() <= kWindow || !(r.back() <= options_.stall_factor * options_.tolerance)) return false;
    const double before = *std::min_element(r.begin(), r.end() - kWindow);
    return *std::min_element(r.end() - kWindow, r.end()) > 0.5 * before;
  }

  StoredStress<State> stored() const { return {stress_, points_.trial()}; }
  /// Whether the evaluation after Newton's correction number `solves` is expected to meet the tolerance:
  /// from the residuals of the last two evaluations (NaN: none) by quadratic convergence, r' = C r^2 with
  /// C = r / r_before^2 from that pair; without them, when this is the first correction and the last
  /// step needed one (an elastic step; with extrapolation such steps need none, see newton()). Then that
  /// evaluation computes F_int without the tangent, which only a further iteration would factorize.
  /// Every step ends with such an evaluation: the plastic tube of BENCHMARKS.md ("`gapfe run` against
  /// CalculiX") skips 19 of its 47 tangents. A wrong guess costs the state's evaluation once more, with the
  /// tangent; the iterates, and so the answers, are the same either way.
  bool converged_next(int solves, double before_last, double last) const {
    if (!options_.predict_convergence) return false;
    if (before_last > 0 && last >= 0 && last < before_last) {
      const double ratio = last / before_last;
      return last * ratio * ratio <= options_.tolerance;
    }
    return solves == 1 && last_solves_ == 1;
  }
  void evaluate(bool tangent, const VecX* prescribed_step) {
    ++report_.evaluations;
    report_.tangents += tangent;
    if (link_update_) link_update_(u_, prescribed_step != nullptr);
    // A point's return map that fails (a SolveError: the caller cuts the step) fails every part's step.
    on_every_part(p_.subdomain.get(), [&] {
      // The predictor -K_fp du_p exists at iteration 0 with a tangent; every other evaluation clears it.
      if (!tangent || !prescribed_step) predictor_.setZero(assembler_.dofs().free_count);
      if (!tangent)
        assembler_.residual(p_, u_, points_, stress_, context_, internal_);
      else if (prescribed_step)
        assembler_.tangent(p_, u_, points_, stress_, context_, system_.values(), internal_, *prescribed_step,
                           predictor_);
      else
        assembler_.tangent(p_, u_, points_, stress_, context_, system_.values(), internal_);
    });
  }
  /// The largest of `value(local, q)` over the stiffness points q (0 without points).
  template <class Value>
  double max_over_points(Value&& value) const {
    double worst = 0;
    assembler_.reset_cache();
    for_each_cell<Elem>(p_.mesh,
                        [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                      const std::array<int, NPC>& cell, const CellTag& tag) {
                          const auto& lp          = assembler_.local(p_, tag, cell);
                          const std::size_t first = assembler_.template first_point<E>(e);
                          for (std::size_t q = first; q < first + E::kStiffnessPoints; ++q)
                            worst = std::max(worst, value(lp, q));
                        });
    return worst;
  }
  /// max |sqrt(f) - 1| over the points on the yield surface (laws that expose yield_ratio).
  double drift() const {
    if constexpr (requires(const typename Law::Local& p) { Law::yield_ratio(p, Vec6{}, State{}); })
      return max_over_points([&](const typename Law::Local& lp, std::size_t q) {
        return points_.trial(q).plastic ? std::abs(Law::yield_ratio(lp, stress_[q], points_.trial(q)) - 1)
                                        : 0.0;
      });
    return 0.0;
  }
  /// max of the law's time_error over the points (laws that estimate one: rate-dependent ones).
  double time_error() const {
    if constexpr (requires(const typename Law::Local& p, const State& s) { Law::time_error(p, s, s, 1.0); })
      return max_over_points([&](const typename Law::Local& lp, std::size_t q) {
        return Law::time_error(lp, points_.committed(q), points_.trial(q), context_.dt);
      });
    return 0.0;
  }

  Problem<M> p_;
  Assembler<M> assembler_;
  System<typename M::LinearSolver> system_;
  NewtonOptions options_;
  StepContext context_;
  StepReport report_;
  History<State> points_;     ///< per stiffness point, cells then triangles (Assembler::first_point)
  std::vector<Vec6> stress_;  ///< at the last evaluation, global axes
  VecX u_, u_committed_;      ///< all DOFs
  VecX u_previous_;           ///< committed before the last commit() (extrapolation)
  double previous_dt_ = 0;    ///< the last accepted step's dt
  int last_solves_    = -1;   ///< Newton corrections of the last accepted step (-1: none, or not converged)
  VecX external_, internal_, predictor_;
  /// Sums of squares the residual is measured against besides the evaluation's own forces
  /// (SolveLoads::peak): this step's start_scale() and the largest of the accepted steps'.
  double load_peak_ = 0, step_scale_ = 0;
  Solution sol_;
  SolveTimings time_, total_;
  std::function<void(const VecX&, bool)> link_update_;
};

}  // namespace gapfe

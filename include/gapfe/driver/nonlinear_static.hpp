#pragma once
// NonlinearStatic: load-stepped equilibrium of a Model whose material law has history (Hill plasticity,
// material/hill.hpp). It derives privately from LinearStatic for the DOF map, the sparsity pattern and
// its one symbolic analysis, the loads and the node links, and adds per-point history with commit and
// reject, and Newton iterations.
//
// One step: the loads and prescribed values now in problem() are the totals at the end of the step.
//   R(u) = F_ext - F_int(u),   F_int = sum_e int B^T sigma dV (+ node links),   K_t = sum_e int B^T D B dV,
// with sigma and D from Law::update(local, eps(u), committed state). Iteration 0 starts from the
// committed displacements and takes the change of the prescribed values through K_fp (a linearized
// predictor). Each iteration refactorizes K_t; the pattern and its analysis never change.
//   * Laws with kIterate (ReturnMapping): Newton until |R_free| <= tolerance |F_int| (over all DOFs, so
//     reactions count and displacement-controlled steps are measured too). Every iteration's residual is
//     kept in the report (the quadratic-convergence test reads it).
//   * Laws without (Tangent): the seed's one linear solve per increment with the start-of-step tangent.
//     The out-of-balance left is reported; the next step's residual carries it (equilibrium correction),
//     so the error does not accumulate as in a purely incremental scheme.
// History is committed only by commit(): a rejected, repeated or split step leaves no trace.
//
// Elements with condensed interior nodes (LegacyQuad) are not supported here yet: their interior
// displacements would need to be history too. Use Quad4BBar, Quad4 or Quad8.
#include <cmath>
#include <sstream>
#include <vector>

#include "gapfe/driver/linear_static.hpp"

namespace gapfe {

/// Newton's stopping rule.
struct NewtonOptions {
  double tolerance   = 1e-10;  ///< |R_free| / |F_int| to stop at [-]
  int max_iterations = 30;     ///< a SolveError beyond this (the caller may cut the step)
};

/// What the last step did.
struct StepReport {
  std::vector<double> residuals;  ///< |R_free| / |F_int| after each linear solve
  int iterations     = 0;         ///< linear solves (1 for Tangent)
  bool converged     = false;     ///< residual <= tolerance (Tangent: never required)
  int plastic_points = 0;         ///< points on the yield surface at the end of the step
  double drift       = 0.0;       ///< max |sqrt(f) - 1| over those points: off the surface [-]
};

template <class M>
class NonlinearStatic : private LinearStatic<M> {
  using Base = LinearStatic<M>;

 public:
  using Kin                = typename Base::Kin;
  using Elem               = typename Base::Elem;
  using Tri                = typename Base::Tri;
  using Law                = typename Base::Law;
  using State              = typename Law::State;
  static constexpr int kNd = Base::kNd;
  static_assert(ElementKernel<Kin, Elem>::kInner == 0,
                "NonlinearStatic: elements with condensed interior nodes (LegacyQuad) are not supported; "
                "use Quad4BBar, Quad4 or Quad8");

  explicit NonlinearStatic(Problem<M> scene, Connectivity<2> link_pairs = {}, NewtonOptions options = {})
      : Base(std::move(scene), std::move(link_pairs)), options_(options) {
    if (!(options_.tolerance > 0) || options_.max_iterations < 1)
      throw InputError("Newton options: tolerance must be > 0 and max_iterations >= 1");
    std::size_t points = 0;
    first_point_.clear();
    this->for_each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                      const std::array<int, NPC>&, const CellTag&) {
      first_point_.push_back(points);
      points += E::kStiffnessPoints;
    });
    committed_.assign(points, State{});
    trial_ = committed_;
    stress_.assign(points, Vec6::Zero());
    this->u_     = VecX::Zero(kNd * this->p_.mesh.node_count());
    u_committed_ = this->u_;
  }

  using Base::defer_reactions;  // a no-op here: every Newton iteration computes the internal forces
  using Base::displacement;
  using Base::dofs;
  using Base::factorizations;
  using Base::link_values;
  using Base::links;
  using Base::nodal_stiffness;  // elastic stiffness: what a contact penalty is scaled by
  using Base::problem;
  using Base::solution;
  using Base::stiffness;
  using Base::timings;  // of the elastic path: the Newton solve's time is solve_seconds()

  /// Time and step size handed to the law (rate-dependent laws read them).
  StepContext& context() { return context_; }
  const StepReport& report() const { return report_; }
  /// History at every stiffness point, cells then triangles, committed by the last commit().
  const std::vector<State>& states() const { return committed_; }
  /// History after the last solve() (what commit() would keep).
  const std::vector<State>& trial_states() const { return trial_; }
  double solve_seconds() const { return seconds_; }

  /// Equilibrium at the loads now in problem(), from the committed state. Throws SolveError when the
  /// iterations do not converge (the committed state is untouched: reject() and cut the step).
  const Solution& solve() {
    const auto t0 = std::chrono::steady_clock::now();
    this->validate_loads();
    this->refresh_condition_values();
    external_forces();
    this->u_             = u_committed_;
    VecX prescribed_step = VecX::Zero(this->u_.size());  // change of the prescribed values over the step
    for (Eigen::Index d = 0; d < this->u_.size(); ++d)
      if (this->dofs_.equation[d] < 0) prescribed_step(d) = this->dofs_.prescribed(d) - this->u_(d);
    report_ = {};
    evaluate(true, &prescribed_step);
    for (int it = 0;; ++it) {
      VecX rhs = predictor_;
      for (Eigen::Index d = 0; d < this->u_.size(); ++d)
        if (const int eq = this->dofs_.equation[d]; eq >= 0) rhs(eq) += this->external_(d) - internal_(d);
      VecX du_free;
      if (this->dofs_.free_count > 0) {
        this->factorize();
        du_free = this->solver_->solve(rhs);
        if (!du_free.allFinite()) throw SolveError("the Newton correction has non-finite values");
      }
      for (Eigen::Index d = 0; d < this->u_.size(); ++d) {
        const int eq = this->dofs_.equation[d];
        this->u_(d) += eq >= 0 ? du_free(eq) : prescribed_step(d);
      }
      prescribed_step.setZero();
      const bool again = Law::kIterate;
      evaluate(again, nullptr);
      this->balance(internal_);
      report_.residuals.push_back(this->sol_.residual);
      report_.iterations = it + 1;
      if (!std::isfinite(this->sol_.residual)) throw SolveError("the residual is not finite");
      if (this->sol_.residual <= options_.tolerance) report_.converged = true;
      if (!again || report_.converged) break;
      if (it + 1 >= options_.max_iterations) {
        std::ostringstream s;
        s << "Newton did not converge in " << options_.max_iterations << " iterations (relative residuals";
        for (double r : report_.residuals) s << " " << r;
        s << "; tolerance " << options_.tolerance << "): cut the load step";
        throw SolveError(s.str());
      }
    }
    for (const State& s : trial_) report_.plastic_points += s.plastic;
    if constexpr (requires(const typename Law::Local& p) { Law::yield_ratio(p, Vec6{}, State{}); }) {
      report_.drift      = 0;
      this->cache_valid_ = false;
      this->for_each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                        const std::array<int, NPC>& cell,
                                                        const CellTag& tag) {
        const auto& lp          = this->local(tag, this->cell_temperature(cell));
        const std::size_t first = first_point_[index_of<E>(e)];
        for (std::size_t q = first; q < first + E::kStiffnessPoints; ++q)
          if (trial_[q].plastic)
            report_.drift =
                std::max(report_.drift, std::abs(Law::yield_ratio(lp, stress_[q], trial_[q]) - 1));
      });
    }
    seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return this->sol_;
  }

  /// The LinearStatic stepper calls of a contact driver: both iterate from the committed state (the
  /// stiffness changes anyway).
  const Solution& solve(bool /*same_stiffness*/) { return solve(); }
  const Solution& resolve_links(bool /*same_link_stiffness*/) { return solve(); }

  /// Accept the last solve(): its history becomes the committed state.
  void commit() {
    committed_   = trial_;
    u_committed_ = this->u_;
  }
  /// Forget the last solve(): back to the committed state.
  void reject() {
    trial_   = committed_;
    this->u_ = u_committed_;
  }

  /// Strain, stress and eqps at every stiffness point (the last solve()).
  std::vector<PointValues> point_values() const { return recover(false); }
  /// Their volume-weighted mean per cell.
  std::vector<PointValues> centroid_values() const { return recover(true); }

 private:
  template <class E>
  std::size_t index_of(std::size_t e) const {
    return std::is_same_v<E, Elem> ? e : this->p_.mesh.cells.size() + e;
  }

  /// F_ext over all DOFs: nodal forces, edge tractions and body forces (thermal strain is in the law).
  void external_forces() {
    this->external_    = this->dofs_.nodal_force;
    this->cache_valid_ = false;
    this->add_edge_loads();
    this->for_each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                      const std::array<int, NPC>& cell, const CellTag& tag) {
      using Kernel         = ElementKernel<Kin, E>;
      const auto& lp       = this->local(tag, this->cell_temperature(cell));
      const BodyForce body = this->body_force(lp.density);
      if (!body.any()) return;
      const typename Kernel::Vector f = Kernel::shape_load(
          this->template coords<E>(cell), Kernel::restrict(lp.stiffness), Kernel::StrainVector::Zero(), body);
      this->add_to(cell, f, this->external_);
    });
  }

  /// Stresses, trial history and internal forces at this->u_; with `tangent`, K_t into the stiffness values;
  /// with `prescribed_step`, predictor_ = -K_fp du_p (the free rows).
  void evaluate(bool tangent, const VecX* prescribed_step) {
    double* values = this->k_.valuePtr();
    if (tangent) Eigen::Map<VecX>(values, this->k_.nonZeros()).setZero();
    internal_.setZero(this->u_.size());
    predictor_.setZero(this->dofs_.free_count);
    this->cache_valid_ = false;
    this->for_each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                      const std::array<int, NPC>& cell, const CellTag& tag) {
      using Kernel              = ElementKernel<Kin, E>;
      constexpr int n           = Kernel::kDofs;
      const auto x              = this->template coords<E>(cell);
      const auto& lp            = this->local(tag, this->cell_temperature(cell));
      const auto mean           = Kernel::mean_volumetric(x);
      const auto ue             = this->gather(cell, this->u_);
      const std::size_t first   = first_point_[index_of<E>(e)];
      typename Kernel::Matrix k = Kernel::Matrix::Zero();
      typename Kernel::Vector f = Kernel::Vector::Zero();
      double det                = 0;
      for (int q = 0; q < E::kStiffnessPoints; ++q) {
        const auto g    = E::stiffness_point(x, q, det);
        const auto b    = Kernel::point_B(g, mean);
        const auto resp = Law::update(lp, Kernel::extend(b * ue), committed_[first + q], context_);
        f.noalias() += g.weight * (b.transpose() * Kernel::restrict(resp.stress));
        if (tangent) k.noalias() += g.weight * (b.transpose() * (Kernel::restrict(resp.tangent) * b));
        trial_[first + q]  = resp.state;
        stress_[first + q] = resp.stress;
      }
      this->add_to(cell, f, internal_);
      if (!tangent) return;
      const bool triangle = !std::is_same_v<E, Elem>;
      this->scatter(values,
                    (triangle ? this->tri_offsets_ : this->cell_offsets_).data() + e * (n * (n + 1) / 2), k);
      if (prescribed_step) add_predictor(cell, k, *prescribed_step);
    });
    for (std::size_t l = 0; l < this->links_.size(); ++l) {
      const NodeLink& link = this->link_values_[l];
      if (link.zero()) continue;
      this->add_to(this->links_[l], this->link_force(l, this->u_), internal_);
      if (!tangent) continue;
      constexpr int n   = 2 * kNd;
      const Mat<n, n> k = link.template element_stiffness<kNd>();
      this->scatter(values, this->link_offsets_.data() + l * (n * (n + 1) / 2), k);
      if (prescribed_step) add_predictor(this->links_[l], k, *prescribed_step);
    }
  }
  /// predictor_ -= K_fp du_p over one element's free rows and prescribed columns.
  template <std::size_t NPC, class Matrix>
  void add_predictor(const std::array<int, NPC>& nodes, const Matrix& k, const VecX& du_p) {
    const auto step = this->gather(nodes, du_p);
    if (step.isZero(0.0)) return;
    for (int i = 0; i < k.rows(); ++i) {
      const int eq = this->dofs_.equation[this->dofs_.dof(nodes[i / kNd], i % kNd)];
      if (eq >= 0) predictor_(eq) -= k.row(i).dot(step);
    }
  }

  std::vector<PointValues> recover(bool centroids) const {
    std::vector<PointValues> out;
    this->cache_valid_ = false;
    this->for_each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                      const std::array<int, NPC>& cell, const CellTag& tag) {
      using Kernel                   = ElementKernel<Kin, E>;
      const auto x                   = this->template coords<E>(cell);
      const auto& lp                 = this->local(tag, this->cell_temperature(cell));
      const auto mean                = Kernel::mean_volumetric(x);
      const auto ue                  = this->gather(cell, this->u_);
      const std::size_t first        = first_point_[index_of<E>(e)];
      const Mat66 to_strain_material = strain_rotation(lp.to_material);
      PointValues sum{};
      sum.strain.setZero(), sum.stress.setZero(), sum.strain_material.setZero(),
          sum.stress_material.setZero();
      double volume = 0, det = 0;
      for (int q = 0; q < E::kStiffnessPoints; ++q) {
        const auto g = E::stiffness_point(x, q, det);
        PointValues v;
        v.cell = static_cast<int>(e), v.triangle = !std::is_same_v<E, Elem>, v.point = q;
        v.r = g.r, v.z = g.N.dot(x.col(1));
        v.strain          = Kernel::strain(g, mean, ue);
        v.stress          = stress_[first + q];
        v.strain_material = to_strain_material * v.strain;
        v.stress_material = lp.to_material * v.stress;
        if constexpr (requires { trial_[0].eqps; }) v.eqps = trial_[first + q].eqps;
        if (!centroids) {
          out.push_back(v);
          continue;
        }
        volume += g.weight;
        sum.r += g.weight * v.r, sum.z += g.weight * v.z, sum.eqps += g.weight * v.eqps;
        sum.strain += g.weight * v.strain, sum.stress += g.weight * v.stress;
        sum.strain_material += g.weight * v.strain_material,
            sum.stress_material += g.weight * v.stress_material;
      }
      if (!centroids) return;
      sum.r /= volume, sum.z /= volume, sum.eqps /= volume, sum.strain /= volume, sum.stress /= volume;
      sum.strain_material /= volume, sum.stress_material /= volume;
      sum.cell = static_cast<int>(e), sum.triangle = !std::is_same_v<E, Elem>, sum.point = -1;
      out.push_back(sum);
    });
    return out;
  }

  NewtonOptions options_;
  StepContext context_;
  StepReport report_;
  std::vector<std::size_t> first_point_;  ///< first history slot of each cell, then of each triangle
  std::vector<State> committed_, trial_;
  std::vector<Vec6> stress_;  ///< at the last evaluation, global axes
  VecX u_committed_;          ///< all DOFs
  VecX internal_, predictor_;
  double seconds_ = 0;
};

}  // namespace gapfe

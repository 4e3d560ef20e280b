#pragma once
// System<Solver>: the matrix values, the right-hand side and the solver of one analysis. It takes the
// assembler's pattern once and runs the solver's symbolic analysis on it once; after that only values
// change, and factorize() is the numeric factorization alone (Eigen's SparseLinearSystems advice).
// A factorization that breaks down is a SolveError naming the equation, never a NaN.
//
// Storage: whatever the solver reads (MatrixStorage, core/concepts.hpp): the lower triangle of the free
// DOFs for the symmetric policies (EigenLdlt, CHOLMOD), every entry for EigenLu, the unsymmetric one
// (friction's tangent). The assembler builds the pattern in that storage; the System takes it as it is.
#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "gapfe/core/concepts.hpp"
#include "gapfe/core/error.hpp"

namespace gapfe {

template <LinearSolver Solver>
class System {
 public:
  /// `pattern`: the structure, values ignored. No analysis when there is no free DOF (a pure recovery) and
  /// the system is not distributed.
  /// `order`: a fill-reducing elimination order (driver/system_setup.hpp, fill_reducing_order) for solvers
  /// that take one (OrderedSolver); others, or an empty order, order the pattern themselves. `layout`: where
  /// the equations sit in a partitioned system (a part of a partitioned problem, or a distributed solver's
  /// near-null space); only a DistributedSolver takes one. `solver`: the solver object (one a caller chose
  /// and set up, e.g. a RuntimeSolver); empty: a default-constructed one.
  explicit System(SpMat pattern, const std::vector<int>& order = {}, const EquationLayout* layout = nullptr,
                  std::unique_ptr<Solver> solver = nullptr)
      : solver_(solver ? std::move(solver) : std::make_unique<Solver>()) {
    k_.swap(pattern);  // Eigen 3.4's SparseMatrix has no move constructor: std::move would copy it
    if (layout) {
      if constexpr (DistributedSolver<Solver>) {
        solver_->distribute(*layout);
        // Every part factorizes and solves, with or without rows of its own, unless no part has any.
        distributed_ = layout->partitioned && layout->total > 0;
      } else {
        throw InputError(std::string("the solver ") + Solver::kName +
                         " solves on one process; a partitioned problem needs a distributed solver "
                         "(PetscSolver, gapfe/solver/petsc.hpp)");
      }
    }
    if (!active()) return;
    if constexpr (OrderedSolver<Solver>)
      if (static_cast<Eigen::Index>(order.size()) == k_.rows()) {
        solver_->analyze(k_, order);
        return;
      }
    solver_->analyze(k_);
  }

  /// Whether this process factorizes and solves: it has equations, or the system is distributed (then
  /// every part joins every factorization and solve, with or without rows of its own).
  bool active() const { return distributed_ || k_.rows() > 0; }
  SpMat& matrix() { return k_; }
  const SpMat& matrix() const { return k_; }
  double* values() { return k_.valuePtr(); }
  VecX& rhs() { return rhs_; }
  const VecX& rhs() const { return rhs_; }
  /// Numeric factorizations so far (the symbolic analysis is done once, in the constructor); a distributed
  /// system's solver counts its own (it skips unchanged values itself).
  int factorizations() const {
    if constexpr (requires { solver_->factorizations(); })
      if (distributed_)
        if (const int n = solver_->factorizations(); n >= 0) return n;
    return factorizations_;
  }
  /// Whether the solver holds a factorization of the current values.
  bool factorized() const { return factorized_; }
  /// Numeric factorizations skipped because the values were those of the last one (skip_unchanged).
  int reuses() const { return reuses_; }
  /// Keep a copy of the values of every factorization and skip the next one when the values are the
  /// same bit for bit: a Newton driver that reassembles its tangent every iteration (NonlinearStatic)
  /// then pays no factorization while every point is elastic (the tangent is the elastic stiffness).
  /// Costs one more value array; off by default (a linear driver knows when its stiffness is unchanged).
  /// A distributed system hands the test to its solver (skip_unchanged(on), when it has one), which must
  /// decide it over every part together.
  void skip_unchanged(bool on) {
    skip_unchanged_ = on;
    if (!on) std::vector<double>().swap(factorized_values_);
    if constexpr (requires { solver_->skip_unchanged(on); })
      if (distributed_) solver_->skip_unchanged(on);
  }

  /// Numeric factorization; on failure a SolveError with the solver's reason and, when it names one,
  /// the equation where it broke down (`describe(equation)` says which node and component that is).
  template <class Describe>
  void factorize(Describe&& describe) {
    // A distributed system leaves the test to its solver: whether to factorize must be decided over every
    // part together, or one part would skip a factorization the others join.
    if (skip_unchanged_ && !distributed_ && factorized_ &&
        std::equal(k_.valuePtr(), k_.valuePtr() + k_.nonZeros(), factorized_values_.begin(),
                   factorized_values_.end())) {
      ++reuses_;
      return;
    }
    if (released_) throw std::logic_error("System::factorize() after release()");
    ++factorizations_;
    if (!(factorized_ = solver_->factorize(k_))) {
      std::string where;
      if (const int eq = failed_equation(); eq >= 0) where = " near " + describe(eq);
      // The hint for a stiffness that cannot be factorized, unless the solver says the failure is its own
      // (LinearSolver, core/concepts.hpp: PETSc refusing its options).
      const std::string failure = solver_->failure();
      throw SolveError(failure + where +
                       (failure.rfind("the solver failed", 0) == 0
                            ? std::string()
                            : std::string(": ") + kRigidBodyHint + " and that no element is degenerate"));
    }
    if constexpr (requires { solver_->statistics(); }) statistics_ = solver_->statistics();
    if (skip_unchanged_ && !distributed_)
      factorized_values_.assign(k_.valuePtr(), k_.valuePtr() + k_.nonZeros());
  }
  VecX solve(const VecX& b) const {
    if (!solver_) throw std::logic_error("System::solve() after release()");
    return solver_->solve(b);
  }

  /// The last solve is done: frees the factorization, the matrix and the values kept beside it (on the
  /// 1e6-equation tube the factor alone is about 1 GB, half the run's memory, which the recovery and the
  /// files written after the last solve can then have). factorize() and solve() after it are logic
  /// errors. A distributed system keeps everything (its solver's objects are freed collectively, at its
  /// end).
  void release() {
    if (distributed_) return;
    solver_.reset();
    SpMat().swap(k_);
    std::vector<double>().swap(factorized_values_), std::vector<double>().swap(saved_values_);
    rhs_.resize(0), saved_rhs_.resize(0);
    factorized_ = false, released_ = true;
  }
  /// The last numeric factorization's size and work (FactorStatistics), kept past release(); zeros when the
  /// solver counts none.
  const FactorStatistics& statistics() const { return statistics_; }
  /// Whether release() freed the solver.
  bool released() const { return released_; }

  /// Keep the current values and right-hand side (the elements' system) to come back to them with
  /// restore() after changing only node links: a contact step re-solves without re-assembling.
  void save() {
    saved_values_.assign(k_.valuePtr(), k_.valuePtr() + k_.nonZeros());
    saved_rhs_ = rhs_;
  }
  bool saved() const { return saved_values_.size() == static_cast<std::size_t>(k_.nonZeros()); }
  /// The right-hand side save() kept (a contact driver's: the loads without its node links).
  const VecX& saved_rhs() const { return saved_rhs_; }
  void restore() {
    std::copy(saved_values_.begin(), saved_values_.end(), k_.valuePtr());
    rhs_ = saved_rhs_;
  }

 private:
  int failed_equation() const {
    if constexpr (requires { solver_->failed_equation(); })
      return solver_->failed_equation();
    else
      return -1;
  }

  SpMat k_;
  VecX rhs_;
  std::unique_ptr<Solver> solver_;  // solvers are not movable
  int factorizations_  = 0;
  int reuses_          = 0;
  bool factorized_     = false;
  bool skip_unchanged_ = false;
  bool distributed_    = false;
  bool released_       = false;
  FactorStatistics statistics_;
  std::vector<double> factorized_values_;  ///< skip_unchanged: the values of the last factorization
  std::vector<double> saved_values_;
  VecX saved_rhs_;
};

}  // namespace gapfe

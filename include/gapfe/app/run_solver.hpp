#pragma once
// The solver of every compiled variant: chosen per run from the plan, among the solvers this build has (so
// each model is instantiated once, not once per solver). The Coulomb rows' slip tangent is unsymmetric, so
// theirs is an LU on full storage: UMFPACK when SuiteSparse has it (solver = auto | cholmod), else Eigen's
// SparseLU (and solver = eigen); MUMPS' LU through PETSc with solver = petsc.
//
// Its members are only declared here and compiled once, with the command's definitions
// (app/run_solver_impl.hpp): a variant shard that sees only declarations compiles none of the solvers' code
// (Eigen's sparse factorizations, the CHOLMOD, UMFPACK and PETSc wrappers), which had been 10% of every
// shard's (BENCHMARKS.md "CI time").
#include <cstddef>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "gapfe/core/choices.hpp"
#include "gapfe/core/concepts.hpp"

namespace gapfe::app {

/// A LinearSolver (core/concepts.hpp) reading `Storage`, one of this build's solvers chosen when it is
/// constructed; an OrderedSolver, and a DistributedSolver in a build with PETSc.
template <MatrixStorage Storage>
class ChosenSolver {
 public:
  static constexpr const char* kName      = "chosen at run time (the plan's solver)";
  static constexpr MatrixStorage kStorage = Storage;

  /// Eigen's (SimplicialLDLT for the lower triangle, SparseLU for full storage).
  ChosenSolver();
  /// The plan's choice (never automatic): eigen, cholmod (UMFPACK for full storage) or petsc, each where
  /// the build has it.
  explicit ChosenSolver(SolverChoice choice);
  ~ChosenSolver();
  ChosenSolver(const ChosenSolver&)            = delete;
  ChosenSolver& operator=(const ChosenSolver&) = delete;

  void analyze(const SpMat& k);
  void analyze(const SpMat& k, const std::vector<int>& order);
#ifdef GAPFE_HAS_PETSC
  void distribute(const EquationLayout& layout);
#endif
  void skip_unchanged(bool on);
  int factorizations() const;
  bool factorize(const SpMat& k);
  VecX solve(const VecX& b) const;
  std::string failure() const;
  int failed_equation() const;
  FactorStatistics statistics();

 private:
  struct Chosen;  // the RuntimeSolver over this build's solvers (app/run_solver_impl.hpp)
  std::unique_ptr<Chosen> chosen_;
};

using RunSolver   = ChosenSolver<MatrixStorage::lower>;
using RunLuSolver = ChosenSolver<MatrixStorage::full>;
extern template class ChosenSolver<MatrixStorage::lower>;
extern template class ChosenSolver<MatrixStorage::full>;

/// The solver object of a run whose plan chose `choice` (never automatic) when S is RunSolver or RunLuSolver;
/// for a variant compiled with one fixed solver type, empty (the driver default-constructs it).
template <class S>
std::unique_ptr<S> make_run_solver([[maybe_unused]] SolverChoice choice) {
  if constexpr (std::is_same_v<S, RunSolver> || std::is_same_v<S, RunLuSolver>)
    return std::make_unique<S>(choice);
  else
    return nullptr;
}

}  // namespace gapfe::app

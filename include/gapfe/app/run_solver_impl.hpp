#pragma once
// The definitions of app/run_solver.hpp's ChosenSolver, for exactly one translation unit of a program (the
// gapfe::app target's command.cpp, through app/command_impl.hpp): the solvers' code is compiled there once.
#include "gapfe/app/run_solver.hpp"
#include "gapfe/solver/eigen_ldlt.hpp"
#include "gapfe/solver/eigen_lu.hpp"
#include "gapfe/solver/runtime_solver.hpp"
#ifdef GAPFE_HAS_CHOLMOD
#include "gapfe/solver/cholmod.hpp"
#endif
#ifdef GAPFE_HAS_UMFPACK
#include "gapfe/solver/umfpack.hpp"
#endif
#ifdef GAPFE_HAS_PETSC
#include "gapfe/solver/petsc.hpp"
#endif

namespace gapfe::app {
namespace built {  // this build's solvers

/// This build's solvers for each storage, Eigen's first (RuntimeSolver's default).
#if defined(GAPFE_HAS_CHOLMOD) && defined(GAPFE_HAS_PETSC)
using LowerSolvers = RuntimeSolver<EigenLdlt, CholmodLlt, PetscSolver<>>;
#elif defined(GAPFE_HAS_CHOLMOD)
using LowerSolvers = RuntimeSolver<EigenLdlt, CholmodLlt>;
#elif defined(GAPFE_HAS_PETSC)
using LowerSolvers = RuntimeSolver<EigenLdlt, PetscSolver<>>;
#else
using LowerSolvers = RuntimeSolver<EigenLdlt>;
#endif
#if defined(GAPFE_HAS_UMFPACK) && defined(GAPFE_HAS_PETSC)
using FullSolvers = RuntimeSolver<EigenLu, UmfpackLu, PetscSolver<MatrixStorage::full>>;
#elif defined(GAPFE_HAS_UMFPACK)
using FullSolvers  = RuntimeSolver<EigenLu, UmfpackLu>;
#elif defined(GAPFE_HAS_PETSC)
using FullSolvers  = RuntimeSolver<EigenLu, PetscSolver<MatrixStorage::full>>;
#else
using FullSolvers  = RuntimeSolver<EigenLu>;
#endif

/// The position among this build's solvers for `Storage` of the plan's choice. Full storage: UMFPACK unless
/// the plan says eigen (or the build has none), MUMPS through PETSc for petsc. The lower triangle: CHOLMOD
/// for cholmod, PETSc for petsc, Eigen's LDLT otherwise.
template <MatrixStorage Storage>
std::size_t chosen_index([[maybe_unused]] SolverChoice choice) {
  if constexpr (Storage == MatrixStorage::full) {
    std::size_t index = FullSolvers::index_of<EigenLu>();
#ifdef GAPFE_HAS_UMFPACK
    if (choice != SolverChoice::eigen) index = FullSolvers::index_of<UmfpackLu>();
#endif
#ifdef GAPFE_HAS_PETSC
    if (choice == SolverChoice::petsc) index = FullSolvers::index_of<PetscSolver<MatrixStorage::full>>();
#endif
    return index;
  } else {
    std::size_t index = LowerSolvers::index_of<EigenLdlt>();
#ifdef GAPFE_HAS_CHOLMOD
    if (choice == SolverChoice::cholmod) index = LowerSolvers::index_of<CholmodLlt>();
#endif
#ifdef GAPFE_HAS_PETSC
    if (choice == SolverChoice::petsc) index = LowerSolvers::index_of<PetscSolver<>>();
#endif
    return index;
  }
}

}  // namespace built

/// What the command does to this build's solver libraries beside their threads (solver/threads.hpp):
/// CHOLMOD's large blocks touched on gapfe's threads (solver/cholmod.hpp).
inline void prepare_solvers() {
#ifdef GAPFE_HAS_CHOLMOD
  touch_cholmod_blocks_on_workers();
#endif
}

template <MatrixStorage Storage>
struct ChosenSolver<Storage>::Chosen {
  std::conditional_t<Storage == MatrixStorage::lower, built::LowerSolvers, built::FullSolvers> solver;
  explicit Chosen(std::size_t index = 0) : solver(index) {}
};

template <MatrixStorage Storage>
ChosenSolver<Storage>::ChosenSolver() : chosen_(std::make_unique<Chosen>()) {}
template <MatrixStorage Storage>
ChosenSolver<Storage>::ChosenSolver(SolverChoice choice)
    : chosen_(std::make_unique<Chosen>(built::chosen_index<Storage>(choice))) {}
template <MatrixStorage Storage>
ChosenSolver<Storage>::~ChosenSolver() = default;

template <MatrixStorage Storage>
void ChosenSolver<Storage>::analyze(const SpMat& k) {
  chosen_->solver.analyze(k);
}
template <MatrixStorage Storage>
void ChosenSolver<Storage>::analyze(const SpMat& k, const std::vector<int>& order) {
  chosen_->solver.analyze(k, order);
}
#ifdef GAPFE_HAS_PETSC
template <MatrixStorage Storage>
void ChosenSolver<Storage>::distribute(const EquationLayout& layout) {
  chosen_->solver.distribute(layout);
}
#endif
template <MatrixStorage Storage>
void ChosenSolver<Storage>::skip_unchanged(bool on) {
  chosen_->solver.skip_unchanged(on);
}
template <MatrixStorage Storage>
int ChosenSolver<Storage>::factorizations() const {
  return chosen_->solver.factorizations();
}
template <MatrixStorage Storage>
bool ChosenSolver<Storage>::factorize(const SpMat& k) {
  return chosen_->solver.factorize(k);
}
template <MatrixStorage Storage>
VecX ChosenSolver<Storage>::solve(const VecX& b) const {
  return chosen_->solver.solve(b);
}
template <MatrixStorage Storage>
std::string ChosenSolver<Storage>::failure() const {
  return chosen_->solver.failure();
}
template <MatrixStorage Storage>
int ChosenSolver<Storage>::failed_equation() const {
  return chosen_->solver.failed_equation();
}

template <MatrixStorage Storage>
FactorStatistics ChosenSolver<Storage>::statistics() {
  return chosen_->solver.statistics();
}

template class ChosenSolver<MatrixStorage::lower>;
template class ChosenSolver<MatrixStorage::full>;

}  // namespace gapfe::app

#pragma once
// The solver of every compiled variant: one RuntimeSolver over the solvers this build has, chosen per run
// from the plan (so each model is instantiated once, not once per solver). The Coulomb rows' slip tangent
// is unsymmetric, so theirs is an LU on full storage: UMFPACK when SuiteSparse has it (solver = auto |
// cholmod), else Eigen's SparseLU (and solver = eigen); MUMPS' LU through PETSc with solver = petsc.
#include <cstddef>
#include <memory>
#include <type_traits>

#include "gapfe/core/choices.hpp"
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

#if defined(GAPFE_HAS_CHOLMOD) && defined(GAPFE_HAS_PETSC)
using RunSolver = RuntimeSolver<EigenLdlt, CholmodLlt, PetscSolver<>>;
#elif defined(GAPFE_HAS_CHOLMOD)
using RunSolver   = RuntimeSolver<EigenLdlt, CholmodLlt>;
#elif defined(GAPFE_HAS_PETSC)
using RunSolver   = RuntimeSolver<EigenLdlt, PetscSolver<>>;
#else
using RunSolver   = RuntimeSolver<EigenLdlt>;
#endif
#if defined(GAPFE_HAS_UMFPACK) && defined(GAPFE_HAS_PETSC)
using RunLuSolver = RuntimeSolver<EigenLu, UmfpackLu, PetscSolver<MatrixStorage::full>>;
#elif defined(GAPFE_HAS_UMFPACK)
using RunLuSolver = RuntimeSolver<EigenLu, UmfpackLu>;
#elif defined(GAPFE_HAS_PETSC)
using RunLuSolver = RuntimeSolver<EigenLu, PetscSolver<MatrixStorage::full>>;
#else
using RunLuSolver = RuntimeSolver<EigenLu>;
#endif

/// The solver object of a run whose plan chose `choice` (never automatic) when S is RunSolver or RunLuSolver;
/// for a variant compiled with one fixed solver type, empty (the driver default-constructs it).
template <class S>
std::unique_ptr<S> make_run_solver([[maybe_unused]] SolverChoice choice) {
  if constexpr (std::is_same_v<S, RunLuSolver>) {
    std::size_t index = S::template index_of<EigenLu>();
#ifdef GAPFE_HAS_UMFPACK
    if (choice != SolverChoice::eigen) index = S::template index_of<UmfpackLu>();
#endif
#ifdef GAPFE_HAS_PETSC
    if (choice == SolverChoice::petsc) index = S::template index_of<PetscSolver<MatrixStorage::full>>();
#endif
    return std::make_unique<S>(index);
  } else if constexpr (std::is_same_v<S, RunSolver>) {
    std::size_t index = S::template index_of<EigenLdlt>();
#ifdef GAPFE_HAS_CHOLMOD
    if (choice == SolverChoice::cholmod) index = S::template index_of<CholmodLlt>();
#endif
#ifdef GAPFE_HAS_PETSC
    if (choice == SolverChoice::petsc) index = S::template index_of<PetscSolver<>>();
#endif
    return std::make_unique<S>(index);
  } else {
    return nullptr;
  }
}

}  // namespace gapfe::app

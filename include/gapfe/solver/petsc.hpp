#pragma once
// PetscSolver: a LinearSolver and DistributedSolver (core/concepts.hpp) over PETSc, for problems partitioned
// over several processes (core/subdomain.hpp) and for PETSc's solvers on one. Storage: the lower triangle
// (PetscSolver<>, symmetric tangents: the default Cholesky) or every entry (PetscSolver<MatrixStorage::full>,
// friction's unsymmetric slip tangent: LU).
//
// Assembly is distributed, never gathered: each part hands the entries of its own cells to PETSc as rows in
// global equation numbers (solver/petsc_rows.hpp: a lower-triangle entry in both of its rows, AIJ holding
// the whole matrix that every PETSc preconditioner reads): once as a pattern, whose entries per row,
// counted over every part, size the matrix (solver/petsc_matrix.hpp), then its values at every
// factorization (MatSetValues per row, added where parts share an equation). The right-hand side is the
// part's partial sum over its local equations, added into the global vector through one VecScatter; the
// solution comes back through it at every local equation, owned or ghost.
//
// The solver is PETSc's choice at run time, from its options database (the program's command line after
// PetscInitialize, PETSC_OPTIONS, .petscrc): -ksp_type, -pc_type, -pc_factor_mat_solver_type, ... The
// defaults, set before the options are read, so that any of them can be overridden:
//   -ksp_type preonly -pc_type cholesky (lu for full storage) -pc_factor_mat_solver_type mumps
//     MUMPS' multifrontal factorization, distributed over the ranks: the robust choice for contact (penalty
//     links make the stiffness ill-conditioned) and plasticity (a tangent that may lose definiteness);
//     MUMPS' null-pivot detection (ICNTL(24) = 1) reports a singular stiffness instead of a huge answer;
//   -ksp_rtol 1e-10 for an iterative choice (-ksp_type cg -pc_type gamg, or -pc_type hypre): PETSc's 1e-5
//     would leave answers far less accurate than the direct solve's; CG measures it on the unpreconditioned
//     residual (-ksp_norm_type unpreconditioned), the relative residual the drivers report.
// With -pc_type gamg the layout's near-null space (the axisymmetric rigid and near-rigid modes,
// assembly/equation_layout.hpp) is attached to the matrix, and -pc_gamg_reuse_interpolation defaults to true.
//
// Repeated solves on one pattern: the pattern is set once; PETSc keeps its matrix's nonzero structure,
// so its factorizations after the first are numeric only (MUMPS' analysis, PETSc's symbolic factorization,
// is done once), and GAMG rebuilds only its Galerkin products on the kept interpolation. With
// skip_unchanged (System::skip_unchanged hands the test to a distributed solver, which must decide it on all
// parts together) a factorize() whose values are those of the last one bit for bit on every part is skipped.
//
// Every call is collective over the communicator: PETSC_COMM_WORLD for a part of a partitioned problem
// (EquationLayout::partitioned), PETSC_COMM_SELF for a whole problem (each process solves its own). PETSc
// must be initialized by the program, and the solver destroyed before PetscFinalize; gapfe never initializes
// or finalizes PETSc. Needs the gapfe::petsc CMake target.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <numeric>
#include <petscksp.h>
#include <string>
#include <type_traits>
#include <vector>

#include "gapfe/core/concepts.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/solver/petsc_matrix.hpp"
#include "gapfe/solver/petsc_subdomain.hpp"

namespace gapfe {

// The build's PETSc must be what gapfe's doubles and the CMake configuration expect.
static_assert(
    std::is_same_v<PetscScalar, double> && std::is_same_v<PetscReal, double>,
    "gapfe needs a PETSc built with real double scalars (--with-scalar-type=real --with-precision=double)");
#ifdef GAPFE_PETSC_INT_BITS
static_assert(sizeof(PetscInt) * 8 == GAPFE_PETSC_INT_BITS,
              "PETSc's PetscInt is not the width CMake configured (GAPFE_PETSC_INT_BITS): the headers are "
              "another PETSc's than the one found at configure time");
#endif

template <MatrixStorage Storage = MatrixStorage::lower>
class PetscSolver {
 public:
  static constexpr const char* kName =
      Storage == MatrixStorage::lower ? "PETSc (symmetric storage)" : "PETSc (unsymmetric storage)";
  static constexpr MatrixStorage kStorage = Storage;

  PetscSolver() {
    PetscBool up = PETSC_FALSE;
    detail::petsc_check(PetscInitialized(&up), "PetscInitialized");
    if (!up)
      throw InputError(
          "PetscSolver: PETSc is not initialized; the program calls PetscInitialize (gapfe never "
          "does)");
  }
  ~PetscSolver() {
    PetscBool finalized = PETSC_TRUE;
    if (PetscFinalized(&finalized) != 0 || finalized) return;
    // Unwinding an error on several ranks: the others may not be unwinding with this one (an error of this
    // rank alone), and destroying the KSP is collective (MUMPS ends its instance over the communicator), so
    // this rank would wait here for ever instead of reaching the program, which ends the launch
    // (docs/cluster.md "When a rank fails"). The objects are left to the process's end.
    int ranks = 1;
    if (std::uncaught_exceptions() > 0 && MPI_Comm_size(comm_, &ranks) == MPI_SUCCESS && ranks > 1) return;
    KSPDestroy(&ksp_), MatDestroy(&a_), VecDestroy(&x_), VecDestroy(&b_), VecDestroy(&local_);
    VecScatterDestroy(&scatter_);
  }
  PetscSolver(const PetscSolver&)            = delete;
  PetscSolver& operator=(const PetscSolver&) = delete;

  /// Where the equations sit in the global system (a part of a partitioned problem, or the identity with
  /// the near-null space); before analyze().
  void distribute(const EquationLayout& layout) {
    if (layout.total > static_cast<std::int64_t>(std::numeric_limits<PetscInt>::max()))
      throw InputError(
          "PetscSolver: " + std::to_string(layout.total) + " equations do not fit this PETSc's " +
          std::to_string(8 * sizeof(PetscInt)) +
          "-bit indices; use a PETSc configured --with-64-bit-indices (Debian: libpetsc64-real-dev)");
    layout_      = layout;
    distributed_ = layout.partitioned;
  }

  void analyze(const SpMat& k) {
    using detail::petsc_check;
    // A whole problem on this process alone: the identity layout (equation_layout's for a whole problem,
    // with its near-null space, or made here when none was given).
    if (!distributed_ && static_cast<Eigen::Index>(layout_.global.size()) != k.rows()) {
      layout_       = {};
      layout_.owned = static_cast<int>(k.rows());
      layout_.total = k.rows();
      layout_.global.resize(static_cast<std::size_t>(k.rows()));
      std::iota(layout_.global.begin(), layout_.global.end(), std::int64_t{0});
    }
    comm_ = distributed_ ? PETSC_COMM_WORLD : PETSC_COMM_SELF;
    if (static_cast<Eigen::Index>(layout_.global.size()) != k.rows())
      throw InputError("PetscSolver: the layout has " + std::to_string(layout_.global.size()) +
                       " equations, the pattern " + std::to_string(k.rows()));
    rows_            = global_rows<kStorage, PetscInt>(k, layout_.global);
    const auto owned = static_cast<PetscInt>(layout_.owned), total = static_cast<PetscInt>(layout_.total);
    petsc_check(MatCreate(comm_, &a_), "MatCreate");
    petsc_check(MatSetSizes(a_, owned, owned, total, total), "MatSetSizes");
    petsc_check(MatSetType(a_, MATAIJ), "MatSetType");
    detail::preallocate(a_, comm_, rows_, owned, total);
    detail::add_rows(a_, rows_, nullptr);  // the structure, as zeros; fixed: a value outside it is an error
    petsc_check(MatSetOption(a_, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE), "MatSetOption");
    if constexpr (kStorage == MatrixStorage::lower) {
      petsc_check(MatSetOption(a_, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
      petsc_check(MatSetOption(a_, MAT_SYMMETRY_ETERNAL, PETSC_TRUE), "MatSetOption");
    }
    attach_near_null_space();
    // The right-hand side in, the solution out: local equations <-> global rows.
    petsc_check(MatCreateVecs(a_, &x_, &b_), "MatCreateVecs");
    petsc_check(VecCreateSeq(PETSC_COMM_SELF, static_cast<PetscInt>(k.rows()), &local_), "VecCreateSeq");
    std::vector<PetscInt> global(layout_.global.begin(), layout_.global.end());
    IS is = nullptr;
    petsc_check(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(global.size()), global.data(),
                                PETSC_COPY_VALUES, &is),
                "ISCreateGeneral");
    petsc_check(VecScatterCreate(x_, is, local_, nullptr, &scatter_), "VecScatterCreate");
    ISDestroy(&is);
    // The solver: defaults first, then the options database.
    petsc_check(KSPCreate(comm_, &ksp_), "KSPCreate");
    petsc_check(KSPSetOperators(ksp_, a_, a_), "KSPSetOperators");
    PC pc = nullptr;
    petsc_check(KSPGetPC(ksp_, &pc), "KSPGetPC");
    petsc_check(KSPSetType(ksp_, KSPPREONLY), "KSPSetType");
    petsc_check(PCSetType(pc, kStorage == MatrixStorage::lower ? PCCHOLESKY : PCLU), "PCSetType");
    petsc_check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    petsc_check(KSPSetTolerances(ksp_, 1e-10, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT),
                "KSPSetTolerances");
    petsc_check(KSPSetFromOptions(ksp_), "KSPSetFromOptions");
    // CG stops on the preconditioned residual by default; with GAMG that left the true relative residual
    // |K u - f| / |f| (what the drivers report) 500 x above -ksp_rtol on the thick tube. The unpreconditioned
    // norm makes -ksp_rtol that residual.
    KSPType krylov = nullptr;
    petsc_check(KSPGetType(ksp_, &krylov), "KSPGetType");
    if (std::string(krylov) == KSPCG && !has_option("-ksp_norm_type"))
      petsc_check(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
    PCType type = nullptr;
    petsc_check(PCGetType(pc, &type), "PCGetType");
    if (std::string(type) == PCGAMG && !has_option("-pc_gamg_reuse_interpolation"))
      petsc_check(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE), "PCGAMGSetReuseInterpolation");
    mumps_ = false;
    if (std::string(type) == PCLU || std::string(type) == PCCHOLESKY) {
      MatSolverType package = nullptr;
      petsc_check(PCFactorGetMatSolverType(pc, &package), "PCFactorGetMatSolverType");
      mumps_ = package && std::string(package) == MATSOLVERMUMPS;
      if (mumps_) set_up_mumps(pc);
    }
  }

  bool factorize(const SpMat& k) {
    using detail::petsc_check;
    failure_.clear();
    const double* values = k.valuePtr();
    // With skip_unchanged: the same values on every part as at the last factorization keep it (decided
    // together).
    if (skip_unchanged_) {
      int changed = !factorized_ || !std::equal(values, values + k.nonZeros(), factorized_values_.begin(),
                                                factorized_values_.end());
      detail::mpi_check(MPI_Allreduce(MPI_IN_PLACE, &changed, 1, MPI_INT, MPI_LOR, comm_), "MPI_Allreduce");
      if (!changed) return true;
    }
    factorized_ = false;  // PETSc's matrix holds other values from here on, until they are factorized
    petsc_check(MatZeroEntries(a_), "MatZeroEntries");
    detail::add_rows(a_, rows_, values);
    PC pc = nullptr;
    petsc_check(KSPGetPC(ksp_, &pc), "KSPGetPC");
    // A failure reported once is not this factorization's: PETSc clears it only in a factorization's own
    // set-up, not in block or multigrid preconditioners' (their sub-solvers' failures would stay).
    petsc_check(PCSetFailedReason(pc, PC_NOERROR), "PCSetFailedReason");
    if (mumps_ && !mumps_failed_ && factorizations_ > 0)  // an error MUMPS met in a solve stays too
      mumps_failed_ = mumps_infog(pc, 1) < 0;             // the same on every rank: they reset together
    if (mumps_failed_) {  // PETSc's MUMPS interface skips every factorization after a failed one
      petsc_check(PCReset(pc), "PCReset");
      petsc_check(KSPSetOperators(ksp_, a_, a_), "KSPSetOperators");
      set_up_mumps(pc);
      mumps_failed_ = false;
    }
    petsc_check(KSPSetUp(ksp_), "KSPSetUp");
    // KSPSetUp sets the preconditioner up only at its first call; after that it returns at once, and PETSc
    // would factorize the new values inside the next KSPSolve, past the checks below (a singular
    // refactorization, MUMPS' null pivots, would go unseen). PCSetUp factorizes now whenever the values
    // changed (KSPSetUpOnBlocks: a block preconditioner's blocks), and KSPSolve then finds nothing to do.
    petsc_check(PCSetUp(pc), "PCSetUp");
    petsc_check(KSPSetUpOnBlocks(ksp_), "KSPSetUpOnBlocks");
    ++factorizations_;
    PCFailedReason reason = PC_NOERROR;
    petsc_check(PCGetFailedReasonRank(pc, &reason), "PCGetFailedReasonRank");
    // Reduced as reason - PC_SETUP_ERROR + 1 (0: no error), so that PC_SETUP_ERROR (-1) is not lost to a
    // maximum against PC_NOERROR (0).
    int code = reason == PC_NOERROR ? 0 : static_cast<int>(reason) - static_cast<int>(PC_SETUP_ERROR) + 1;
    detail::mpi_check(MPI_Allreduce(MPI_IN_PLACE, &code, 1, MPI_INT, MPI_MAX, comm_), "MPI_Allreduce");
    const int worst = code == 0 ? static_cast<int>(PC_NOERROR) : code - 1 + static_cast<int>(PC_SETUP_ERROR);
    if (worst != PC_NOERROR) {
      std::string why = std::string("PETSc: ") + PCFailedReasons[worst];
      if (mumps_) {  // MUMPS' own error code (its users' guide, "Error diagnostics"): -10 is a singular
                     // matrix
        const PetscInt info = mumps_infog(pc, 1);
        why += ", MUMPS INFOG(1) = " + std::to_string(info) +
               ", INFOG(2) = " + std::to_string(mumps_infog(pc, 2));
        mumps_failed_ = info < 0;
      }
      const bool singular = worst == PC_FACTOR_STRUCT_ZEROPIVOT || worst == PC_FACTOR_NUMERIC_ZEROPIVOT;
      return fail(singular ? "stiffness is singular (" + why + ")"
                           : "the solver failed (" + why + "; MUMPS' users' guide lists its codes)");
    }
    if (mumps_) {
      const PetscInt info = mumps_infog(pc, 1), null_pivots = mumps_infog(pc, 28);
      if (info < 0) {  // an error PETSc did not pass on as the preconditioner's
        mumps_failed_ = true;
        return fail("the solver failed (MUMPS INFOG(1) = " + std::to_string(info) +
                    "; MUMPS' users' guide lists its codes)");
      }
      if (null_pivots > 0)
        return fail("stiffness is singular (MUMPS found " + std::to_string(null_pivots) + " null pivot" +
                    (null_pivots > 1 ? "s" : "") + ")");
    }
    if (skip_unchanged_) factorized_values_.assign(values, values + k.nonZeros());
    factorized_ = true;
    return true;
  }

  /// Skip a factorization whose values are, on every part, those of the last one bit for bit (the System
  /// asks for it: NonlinearStatic's elastic iterations). Costs a copy of the values; off by default.
  void skip_unchanged(bool on) {
    skip_unchanged_ = on;
    if (!on) std::vector<PetscScalar>().swap(factorized_values_);
  }

  VecX solve(const VecX& b) const {
    using detail::petsc_check;
    VecX x(b.size());
    petsc_check(VecZeroEntries(b_), "VecZeroEntries");
    copy_in(b, local_);
    petsc_check(VecScatterBegin(scatter_, local_, b_, ADD_VALUES, SCATTER_REVERSE), "VecScatterBegin");
    petsc_check(VecScatterEnd(scatter_, local_, b_, ADD_VALUES, SCATTER_REVERSE), "VecScatterEnd");
    petsc_check(KSPSolve(ksp_, b_, x_), "KSPSolve");
    KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
    PetscInt its              = 0;
    petsc_check(KSPGetConvergedReason(ksp_, &reason), "KSPGetConvergedReason");
    petsc_check(KSPGetIterationNumber(ksp_, &its), "KSPGetIterationNumber");
    iterations_ += static_cast<long>(its);
    if (reason < 0)
      throw SolveError(std::string("PETSc's solve failed: ") + KSPConvergedReasons[reason] + " after " +
                       std::to_string(its) + " iterations (-ksp_converged_reason, -ksp_monitor: see why)");
    petsc_check(VecScatterBegin(scatter_, x_, local_, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
    petsc_check(VecScatterEnd(scatter_, x_, local_, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
    const PetscScalar* values = nullptr;
    petsc_check(VecGetArrayRead(local_, &values), "VecGetArrayRead");
    std::copy_n(values, x.size(), x.data());
    petsc_check(VecRestoreArrayRead(local_, &values), "VecRestoreArrayRead");
    int finite = x.allFinite();  // decided together: one part's NaN fails the solve on every part
    detail::mpi_check(MPI_Allreduce(MPI_IN_PLACE, &finite, 1, MPI_INT, MPI_LAND, comm_), "MPI_Allreduce");
    if (!finite) throw SolveError("PETSc's solve gave non-finite values (singular stiffness?)");
    return x;
  }

  const std::string& failure() const { return failure_; }
  /// Numeric factorizations PETSc did (not counting those skipped for unchanged values).
  int factorizations() const { return factorizations_; }
  /// Krylov iterations over every solve so far (1 per solve for a direct solver).
  long iterations() const { return iterations_; }
  /// PETSc's matrix and solver, to inspect (KSPView) or tune after analyze().
  ::Mat matrix() const { return a_; }
  KSP ksp() const { return ksp_; }

 private:
  /// MUMPS' null-pivot detection (ICNTL(24) = 1) unless the options set it: a singular stiffness is then
  /// reported (INFOG(28)) instead of factorized into a huge answer.
  void set_up_mumps(PC pc) {
    using detail::petsc_check;
    if (has_option("-mat_mumps_icntl_24")) return;
    ::Mat factor = nullptr;
    petsc_check(PCFactorSetUpMatSolverType(pc), "PCFactorSetUpMatSolverType");
    petsc_check(PCFactorGetMatrix(pc, &factor), "PCFactorGetMatrix");
    petsc_check(MatMumpsSetIcntl(factor, 24, 1), "MatMumpsSetIcntl");
  }
  /// MUMPS' INFOG(k) from the preconditioner's factor: the same on every rank (MUMPS' global information).
  static PetscInt mumps_infog(PC pc, PetscInt k) {
    ::Mat factor  = nullptr;
    PetscInt info = 0;
    detail::petsc_check(PCFactorGetMatrix(pc, &factor), "PCFactorGetMatrix");
    detail::petsc_check(MatMumpsGetInfog(factor, k, &info), "MatMumpsGetInfog");
    return info;
  }
  static bool has_option(const char* name) {
    PetscBool set = PETSC_FALSE;
    detail::petsc_check(PetscOptionsHasName(nullptr, nullptr, name, &set), "PetscOptionsHasName");
    return set;
  }
  static void copy_in(const VecX& from, ::Vec to) {
    PetscScalar* values = nullptr;
    detail::petsc_check(VecGetArray(to, &values), "VecGetArray");
    std::copy_n(from.data(), from.size(), values);
    detail::petsc_check(VecRestoreArray(to, &values), "VecRestoreArray");
  }
  /// The layout's near-null modes, orthonormalized, as the matrix's near-null space (GAMG reads it).
  void attach_near_null_space() {
    using detail::petsc_check;
    if (layout_.modes == 0) return;
    std::vector<::Vec> modes(static_cast<std::size_t>(layout_.modes));
    for (int m = 0; m < layout_.modes; ++m) {
      ::Vec& v = modes[static_cast<std::size_t>(m)];
      petsc_check(MatCreateVecs(a_, &v, nullptr), "MatCreateVecs");
      PetscScalar* values = nullptr;
      petsc_check(VecGetArray(v, &values), "VecGetArray");
      std::copy_n(
          layout_.near_null.data() + static_cast<std::size_t>(m) * static_cast<std::size_t>(layout_.owned),
          layout_.owned, values);
      petsc_check(VecRestoreArray(v, &values), "VecRestoreArray");
    }
    // Modified Gram-Schmidt; a mode the others span (or zero: every such DOF prescribed) is dropped.
    std::vector<::Vec> basis;
    for (::Vec v : modes) {
      for (::Vec u : basis) {
        PetscScalar dot = 0;
        petsc_check(VecDot(v, u, &dot), "VecDot");
        petsc_check(VecAXPY(v, -dot, u), "VecAXPY");
      }
      PetscReal norm = 0;
      petsc_check(VecNorm(v, NORM_2, &norm), "VecNorm");
      if (norm > 1e-10 * std::sqrt(static_cast<double>(layout_.total))) {
        petsc_check(VecScale(v, 1 / norm), "VecScale");
        basis.push_back(v);
      } else {
        VecDestroy(&v);
      }
    }
    if (basis.empty()) return;  // every mode's DOFs prescribed: GAMG falls back to its constant vector
    MatNullSpace space = nullptr;
    petsc_check(
        MatNullSpaceCreate(comm_, PETSC_FALSE, static_cast<PetscInt>(basis.size()), basis.data(), &space),
        "MatNullSpaceCreate");
    petsc_check(MatSetNearNullSpace(a_, space), "MatSetNearNullSpace");
    MatNullSpaceDestroy(&space);
    for (::Vec& v : basis) VecDestroy(&v);
  }
  bool fail(const std::string& what) {
    failure_ = what;
    return false;
  }

  EquationLayout layout_;
  bool distributed_ = false, factorized_ = false, mumps_ = false, skip_unchanged_ = false;
  bool mumps_failed_ = false;  ///< MUMPS' instance failed: set up afresh at the next factorize()
  MPI_Comm comm_     = PETSC_COMM_SELF;
  ::Mat a_           = nullptr;
  ::Vec x_ = nullptr, b_ = nullptr, local_ = nullptr;
  VecScatter scatter_ = nullptr;
  KSP ksp_            = nullptr;
  GlobalRows<PetscInt> rows_;              ///< the pattern as PETSc's rows (analyze)
  std::vector<double> factorized_values_;  ///< skip_unchanged: the pattern's values at the last factorization
  std::string failure_;
  int factorizations_      = 0;
  mutable long iterations_ = 0;
};
static_assert(DistributedSolver<PetscSolver<>>);
static_assert(DistributedSolver<PetscSolver<MatrixStorage::full>>);

}  // namespace gapfe

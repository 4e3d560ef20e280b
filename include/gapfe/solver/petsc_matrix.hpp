#pragma once
// PETSc's matrix from a part's rows (solver/petsc_rows.hpp), for PetscSolver (solver/petsc.hpp): its room
// counted once, then values added row by row at every factorization. Collective over the matrix's
// communicator.
#include <algorithm>
#include <numeric>
#include <petscmat.h>
#include <vector>

#include "gapfe/solver/petsc_rows.hpp"
#include "gapfe/solver/petsc_subdomain.hpp"

namespace gapfe::detail {

/// Each owned row's entries in the diagonal block (the columns this rank owns) and off it, summed over
/// the parts that hold the row (VecSetValue sends a shared row's counts to its owner): exact for a row
/// that one part holds, above it where two parts' rows of an equation on their cut share a column; the
/// first assembly squeezes the spare room out. (PETSc's MATPREALLOCATOR, which counts exactly with hash
/// sets, took 2.8 s more at 1e6 equations: BENCHMARKS.md "What a rank holds at its peak".)
inline void preallocate(::Mat a, MPI_Comm comm, const GlobalRows<PetscInt>& rows, PetscInt owned,
                        PetscInt total) {
  int ranks = 1;
  mpi_check(MPI_Comm_size(comm, &ranks), "MPI_Comm_size");
  std::vector<PetscInt> start(static_cast<std::size_t>(ranks) + 1, 0);  // rank q: [start[q], start[q + 1])
  mpi_check(MPI_Allgather(&owned, 1, MPIU_INT, start.data() + 1, 1, MPIU_INT, comm), "MPI_Allgather");
  std::partial_sum(start.begin(), start.end(), start.begin());
  ::Vec count[2] = {nullptr, nullptr};  // per row: entries in the diagonal block, off it
  for (::Vec& v : count) {
    petsc_check(VecCreate(comm, &v), "VecCreate");
    petsc_check(VecSetSizes(v, owned, total), "VecSetSizes");
    petsc_check(VecSetType(v, VECSTANDARD), "VecSetType");
    petsc_check(VecSet(v, 0.0), "VecSet");
  }
  for (std::size_t r = 0; r < rows.rows(); ++r) {
    const PetscInt g = rows.row[r];
    const auto q =
        static_cast<std::size_t>(std::upper_bound(start.begin(), start.end(), g) - start.begin()) - 1;
    const PetscInt* first = rows.column.data() + rows.start[r];
    const PetscInt* last  = rows.column.data() + rows.start[r + 1];
    const auto in = std::count_if(first, last, [&](PetscInt c) { return c >= start[q] && c < start[q + 1]; });
    petsc_check(VecSetValue(count[0], g, static_cast<PetscScalar>(in), ADD_VALUES), "VecSetValue");
    petsc_check(VecSetValue(count[1], g, static_cast<PetscScalar>((last - first) - in), ADD_VALUES),
                "VecSetValue");
  }
  std::vector<PetscInt> room[2];
  for (int b = 0; b < 2; ++b) {
    petsc_check(VecAssemblyBegin(count[b]), "VecAssemblyBegin");
    petsc_check(VecAssemblyEnd(count[b]), "VecAssemblyEnd");
    const PetscScalar* values = nullptr;
    petsc_check(VecGetArrayRead(count[b], &values), "VecGetArrayRead");
    const PetscInt most = b == 0 ? owned : total - owned;
    room[b].resize(static_cast<std::size_t>(owned));
    for (PetscInt i = 0; i < owned; ++i)
      room[b][static_cast<std::size_t>(i)] = std::min(static_cast<PetscInt>(values[i] + 0.5), most);
    petsc_check(VecRestoreArrayRead(count[b], &values), "VecRestoreArrayRead");
    VecDestroy(&count[b]);
  }
  petsc_check(MatXAIJSetPreallocation(a, 1, room[0].data(), room[1].data(), nullptr, nullptr),
              "MatXAIJSetPreallocation");
}

/// Each row of `rows` into `m` with the pattern's `values` (zeros when null: the structure alone),
/// added to what other parts give the same entries; then assembled (collective).
inline void add_rows(::Mat m, const GlobalRows<PetscInt>& rows, const double* values) {
  std::vector<double> row;
  for (std::size_t r = 0; r < rows.rows(); ++r) {
    rows.values(r, values, row);
    petsc_check(MatSetValues(m, 1, &rows.row[r], static_cast<PetscInt>(row.size()),
                             rows.column.data() + rows.start[r], row.data(), ADD_VALUES),
                "MatSetValues");
  }
  petsc_check(MatAssemblyBegin(m, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  petsc_check(MatAssemblyEnd(m, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
}

}  // namespace gapfe::detail

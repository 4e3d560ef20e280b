// main() of the partitioned-run tests (test_petsc.cpp), run under mpirun on 1, 2 and 3 ranks: PETSc (and
// with it MPI) is initialized and finalized here, by the program, as gapfe requires. Every rank runs every
// test case; the cases call the collective operations in the same order on every rank and check values
// that are the same on every rank (gathered or reduced first), so a failure is reported by all of them.
#define DOCTEST_CONFIG_IMPLEMENT
#include <petscsys.h>

#include <doctest/doctest.h>

int main(int argc, char** argv) {
  // PETSc reads its options (-ksp_type ...) from the command line; doctest gets it too and ignores them.
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  PetscLogDefaultBegin();  // event counts: a test reads how often PETSc factorized
  int result = 0;
  {
    doctest::Context context(argc, argv);
    int rank = 0;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    if (rank != 0) context.setOption("out", "/dev/null");  // one rank's report (all of them fail alike)
    result = context.run();
  }
  int worst = result;
  MPI_Allreduce(&result, &worst, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  PetscFinalize();
  return worst;
}

// The README's example partitioned over the ranks of an mpirun: the program starts and ends PETSc (gapfe
// never does), cuts the tube into one part per rank, solves with PetscSolver (MUMPS by default; PETSc's
// options from the command line, e.g. -ksp_type cg -pc_type gamg) and checks the bore displacement, which
// every rank holds for its own nodes, against Lame's closed form. Exits 1 if it is off by more than 1%.
#include <cmath>
#include <iostream>
#include <memory>

#include "gapfe/assembly/problem_part.hpp"
#include "gapfe/gapfe.hpp"
#include "gapfe/solver/petsc.hpp"

int main(int argc, char** argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  int rank = 0, ranks = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &ranks);
  int status = 0;
  {
    using Tube = gapfe::Model<gapfe::Axisym2, gapfe::Quad4, gapfe::Isotropic, gapfe::PetscSolver<>>;
    gapfe::Problem<Tube> whole;  // every rank builds the whole problem, then keeps its part
    whole.mesh      = gapfe::rectangle_mesh<4>(0.1, 0.2, 0.0, 0.02, 16, 2);
    whole.materials = {gapfe::Isotropic::constant(200e9, 0.3)};
    for (int j = 0; j < 2; ++j) {
      const auto& cell = whole.mesh.cells[j * 16];
      whole.edge_loads.push_back({cell[3], cell[0], 100e6});
    }
    for (int n = 0; n < whole.mesh.node_count(); ++n)
      if (whole.mesh.nodes[n].y() == 0.0 || whole.mesh.nodes[n].y() == 0.02)
        whole.conditions.push_back({n, 2});
    auto piece  = gapfe::mesh_part(whole.mesh, gapfe::partition_cells(whole.mesh, ranks), ranks, rank);
    auto domain = std::make_shared<const gapfe::PetscSubdomain>(std::move(piece.layout));
    gapfe::LinearStatic<Tube> fe(gapfe::problem_part(whole, std::move(piece.mesh), domain));
    const auto& u = fe.solve().displacement;
    // Node 0 of the whole mesh, at (a, 0): the part that holds it checks it; the worst status wins.
    if (const int local = domain->layout().local_node[0]; local >= 0) {
      std::cout << "rank " << rank << " of " << ranks << ": bore u_r = " << u(local, 0)
                << " m (Lame: 9.5333e-05 m)\n";
      status = std::abs(u(local, 0) / 9.5333e-5 - 1) < 0.01 ? 0 : 1;
    }
  }
  int worst = status;
  MPI_Allreduce(&status, &worst, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  PetscFinalize();
  return worst;
}

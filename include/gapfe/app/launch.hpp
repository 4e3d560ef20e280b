#pragma once
// The command's dealings with its process's launch: whether a run may use it (check_process), MPI started
// early in a launch of several processes (start_launch), a partitioned run's part (partition), and what the
// program records in a run's folder should it end the launch (EndedRecord). docs/cluster.md.
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "gapfe/app/command.hpp"
#include "gapfe/app/command_line.hpp"
#include "gapfe/app/plan.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/mesh/cell_partition.hpp"
#include "gapfe/output/run_folder.hpp"
#include "gapfe/run/scene_run.hpp"
#ifdef GAPFE_HAS_PETSC
#include "gapfe/solver/petsc_subdomain.hpp"
#endif

namespace gapfe::app {

/// A launch of several processes starts MPI (and PETSc, with the command line's options) before a run reads
/// its deck, so that a process that cannot read it is heard by the others, which would otherwise wait for it
/// (docs/cluster.md "When a rank fails"); partition() then finds MPI started. A launch of several processes
/// is a partitioned run or a refused one (check_process).
inline void start_launch(const Args& a, const Process& process) {
  if (a.command == "run" && process.start_mpi && launcher_ranks().second > 1)
    process.start_mpi(a.petsc_options);
}

/// The process checks of a run: a launch of several processes needs solver = petsc, PETSc's options too,
/// and solver = petsc a program that starts MPI.
inline void check_process(const Args& a, const Plan& p, int launch_size, const StartMpi& start_mpi) {
  check_solver_built(p.solver);
  if (p.solver != SolverChoice::petsc) {
    if (launch_size > 1)
      throw InputError(
          "gapfe run started as " + std::to_string(launch_size) +
          " processes (mpirun) with solver = " + std::string(name_of(p.solver)) +
          ", which solves on one process (each would write the same files): give --solver petsc");
    if (!a.petsc_options.empty())
      throw InputError("the PETSc option " + a.petsc_options.front() +
                       " needs solver = petsc (--solver petsc)");
  } else if (!start_mpi) {
    throw InputError(
        "solver = petsc: MPI and PETSc are started by the program, and this one does not (the gapfe "
        "command does)");
  }
}

/// A partitioned run: MPI and PETSc start here, unless a launch of several processes started them already
/// (start_launch); this process keeps its part of the scene, and the log lists every rank's share. Returns
/// this process's rank.
inline int partition(const Args& a, const Scene& s, const StartMpi& start_mpi, std::optional<ScenePart>& part,
                     std::ostream& log) {
#ifdef GAPFE_HAS_PETSC
  const auto [rank, ranks] = start_mpi(a.petsc_options);
  auto piece = mesh_part(s.mesh, partition_cells(s.mesh, ranks), ranks, rank, pair_nodes(s.gaps.pairs));
  std::vector<double> counts(3 * static_cast<std::size_t>(ranks), 0.0);  // cells, owned nodes, ghosts
  counts[static_cast<std::size_t>(3 * rank)] =
      static_cast<double>(piece.mesh.cells.size() + piece.mesh.triangles.size());
  counts[static_cast<std::size_t>(3 * rank + 1)] = piece.layout.owned_nodes;
  counts[static_cast<std::size_t>(3 * rank + 2)] = static_cast<double>(piece.layout.ghost_part.size());
  auto pairs                                     = part_pairs(piece.layout, s.gaps.pairs);
  auto domain = std::make_shared<const PetscSubdomain>(std::move(piece.layout));
  domain->sum(counts.data(), static_cast<int>(counts.size()));
  log << "partition: " << ranks
      << " rank(s), recursive coordinate bisection of the cells; cells / nodes owned / "
      << "ghost nodes per rank:";
  for (int k = 0; k < ranks; ++k)
    log << (k ? "," : "") << " " << static_cast<long long>(counts[static_cast<std::size_t>(3 * k)]) << " / "
        << static_cast<long long>(counts[static_cast<std::size_t>(3 * k + 1)]) << " / "
        << static_cast<long long>(counts[static_cast<std::size_t>(3 * k + 2)]);
  log << "\n";
  part.emplace(ScenePart{std::move(piece.mesh), std::move(pairs), std::move(domain)});
  return rank;
#else
  (void)a, (void)s, (void)start_mpi, (void)part, (void)log;
  throw InputError("solver = petsc: this gapfe was built without PETSc");
#endif
}

/// Hands the program, while a run writes its folder, what to record there should the program end the launch
/// from outside this rank's work (Process::on_ended); withdraws it when the run is over.
struct EndedRecord {
  const Process& process;
  const bool active;
  EndedRecord(const Process& p, bool writes, const std::string& dir, const std::string& what)
      : process(p), active(writes && p.on_ended) {
    if (active)
      process.on_ended([dir, what](const std::string& why) { RunFolder::record_stopped(dir, what, why); });
  }
  ~EndedRecord() {
    if (active) process.on_ended({});
  }
  EndedRecord(const EndedRecord&)            = delete;
  EndedRecord& operator=(const EndedRecord&) = delete;
};

}  // namespace gapfe::app

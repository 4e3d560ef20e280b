#pragma once
// PetscSubdomain: the collective operations of a Subdomain (core/subdomain.hpp) over MPI, one part per rank
// of PETSC_COMM_WORLD (the communicator PetscSolver solves on). The ghost exchanges are PETSc star forests
// (PetscSF): a ghost node's values are a leaf of its owner's values, the root; adding the leaves into the
// roots and broadcasting the roots back turns partial sums into totals. One forest per width (values per
// node), made on first use. The reductions and the gather for output are plain MPI collectives.
//
// Needs the gapfe::petsc CMake target; PETSc must be initialized by the program (PetscInitialize), never by
// gapfe. The subdomain must be destroyed before PetscFinalize.
#include <limits>
#include <map>
#include <numeric>
#include <petscsf.h>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/subdomain.hpp"

namespace gapfe {

namespace detail {
/// A PETSc or MPI call that failed: PETSc has printed its trace; this says which call, for the caller.
inline void petsc_check(PetscErrorCode code, const char* what) {
  if (code != 0)
    throw SolveError(std::string("PETSc: ") + what + " failed (error code " + std::to_string(code) + ")");
}
inline void mpi_check(int code, const char* what) {
  if (code != MPI_SUCCESS)
    throw SolveError(std::string("MPI: ") + what + " failed (error code " + std::to_string(code) + ")");
}
}  // namespace detail

class PetscSubdomain final : public Subdomain {
 public:
  /// `layout` from mesh_part with part = this rank of PETSC_COMM_WORLD and parts = its size: the
  /// communicator PetscSolver solves on (a program that runs gapfe on a subset of its processes sets
  /// PETSC_COMM_WORLD to it before PetscInitialize, PETSc's way).
  explicit PetscSubdomain(PartLayout layout) : Subdomain(std::move(layout)), comm_(PETSC_COMM_WORLD) {
    PetscBool up = PETSC_FALSE;
    detail::petsc_check(PetscInitialized(&up), "PetscInitialized");
    if (!up) throw InputError("PetscSubdomain: PETSc is not initialized (the program calls PetscInitialize)");
    int rank = 0, size = 1;
    detail::mpi_check(MPI_Comm_rank(comm_, &rank), "MPI_Comm_rank");
    detail::mpi_check(MPI_Comm_size(comm_, &size), "MPI_Comm_size");
    if (rank != part() || size != parts())
      throw InputError("PetscSubdomain: part " + std::to_string(part()) + " of " + std::to_string(parts()) +
                       " on rank " + std::to_string(rank) + " of " + std::to_string(size) +
                       ": one part per rank, numbered as the ranks");
    const PartLayout& l = this->layout();
    if (l.ghost_part.size() != l.ghost_index.size() ||
        l.owned_nodes + static_cast<int>(l.ghost_part.size()) != l.local_nodes())
      throw InputError("PetscSubdomain: the layout's ghosts do not match its nodes");
  }
  ~PetscSubdomain() override {
    PetscBool finalized = PETSC_TRUE;
    if (PetscFinalized(&finalized) != 0 || finalized) return;
    for (auto& [width, forest] : forests_) PetscSFDestroy(&forest);
  }

  MPI_Comm communicator() const { return comm_; }

  void sum_shared(double* values, int width) const override {
    PetscSF sf = forest(width);
    detail::petsc_check(PetscSFReduceBegin(sf, MPIU_SCALAR, values, values, MPIU_SUM), "PetscSFReduceBegin");
    detail::petsc_check(PetscSFReduceEnd(sf, MPIU_SCALAR, values, values, MPIU_SUM), "PetscSFReduceEnd");
    copy_to_ghosts(values, width);
  }
  void copy_to_ghosts(double* values, int width) const override {
    PetscSF sf = forest(width);
    detail::petsc_check(PetscSFBcastBegin(sf, MPIU_SCALAR, values, values, MPI_REPLACE), "PetscSFBcastBegin");
    detail::petsc_check(PetscSFBcastEnd(sf, MPIU_SCALAR, values, values, MPI_REPLACE), "PetscSFBcastEnd");
  }
  void sum(double* values, int count) const override {
    detail::mpi_check(MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_SUM, comm_),
                      "MPI_Allreduce");
  }
  double max(double value) const override {
    double out = value;
    detail::mpi_check(MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, comm_), "MPI_Allreduce");
    return out;
  }
  std::vector<double> gather_rows(const double* values, int count, int width, const int* row,
                                  int rows) const override {
    // Checked on every part together, before any data moves: rows in range, and the table within MPI's int
    // counts (a table past 2^31 values cannot be gathered in one call).
    double checks[2] = {static_cast<double>(count) * width, 0.0};  // values, rows out of range
    for (int k = 0; k < count; ++k) checks[1] += row[k] < 0 || row[k] >= rows;
    sum(checks, 2);
    if (checks[1] > 0)
      throw SolveError("gather_rows: a part gave rows outside the table's " + std::to_string(rows));
    if (checks[0] > static_cast<double>(std::numeric_limits<int>::max()))
      throw SolveError("gathering " + std::to_string(static_cast<long long>(checks[0])) +
                       " values to rank 0 exceeds MPI's int counts: run with output = none");
    std::vector<int> counts(static_cast<std::size_t>(parts())), starts(counts.size());
    detail::mpi_check(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_), "MPI_Gather");
    const bool root = part() == 0;
    std::partial_sum(counts.begin(), counts.end() - 1, starts.begin() + 1);
    const int total = root ? starts.back() + counts.back() : 0;
    std::vector<int> all_rows(static_cast<std::size_t>(total));
    detail::mpi_check(
        MPI_Gatherv(row, count, MPI_INT, all_rows.data(), counts.data(), starts.data(), MPI_INT, 0, comm_),
        "MPI_Gatherv");
    for (std::size_t k = 0; k < counts.size(); ++k) counts[k] *= width, starts[k] *= width;
    std::vector<double> all(static_cast<std::size_t>(total) * static_cast<std::size_t>(width));
    detail::mpi_check(MPI_Gatherv(values, count * width, MPI_DOUBLE, all.data(), counts.data(), starts.data(),
                                  MPI_DOUBLE, 0, comm_),
                      "MPI_Gatherv");
    if (!root) return {};
    std::vector<double> table(static_cast<std::size_t>(rows) * static_cast<std::size_t>(width), 0.0);
    for (int k = 0; k < total; ++k) {
      const int r = all_rows[static_cast<std::size_t>(k)];
      std::copy_n(all.data() + static_cast<std::size_t>(k) * static_cast<std::size_t>(width), width,
                  table.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(width));
    }
    return table;
  }

  std::string broadcast(const std::string& text, int from) const override {
    int size = static_cast<int>(text.size());
    detail::mpi_check(MPI_Bcast(&size, 1, MPI_INT, from, comm_), "MPI_Bcast");
    std::string out = part() == from ? text : std::string(static_cast<std::size_t>(size), '\0');
    detail::mpi_check(MPI_Bcast(out.data(), size, MPI_CHAR, from, comm_), "MPI_Bcast");
    return out;
  }

 private:
  /// The star forest for `width` values per node: roots are the owned nodes' values, leaves the ghosts'.
  PetscSF forest(int width) const {
    if (const auto it = forests_.find(width); it != forests_.end()) return it->second;
    const PartLayout& l = layout();
    const auto ghosts   = static_cast<PetscInt>(l.ghost_part.size());
    PetscInt* leaf      = nullptr;
    PetscSFNode* root   = nullptr;
    detail::petsc_check(PetscMalloc1(ghosts * width, &leaf), "PetscMalloc1");
    detail::petsc_check(PetscMalloc1(ghosts * width, &root), "PetscMalloc1");
    for (PetscInt k = 0; k < ghosts; ++k)
      for (int c = 0; c < width; ++c) {
        leaf[k * width + c]      = (l.owned_nodes + k) * width + c;
        root[k * width + c].rank = l.ghost_part[static_cast<std::size_t>(k)];
        root[k * width + c].index =
            static_cast<PetscInt>(l.ghost_index[static_cast<std::size_t>(k)]) * width + c;
      }
    PetscSF sf = nullptr;
    detail::petsc_check(PetscSFCreate(comm_, &sf), "PetscSFCreate");
    detail::petsc_check(PetscSFSetGraph(sf, static_cast<PetscInt>(l.owned_nodes) * width, ghosts * width,
                                        leaf, PETSC_OWN_POINTER, root, PETSC_OWN_POINTER),
                        "PetscSFSetGraph");
    detail::petsc_check(PetscSFSetUp(sf), "PetscSFSetUp");
    forests_[width] = sf;
    return sf;
  }

  MPI_Comm comm_;
  mutable std::map<int, PetscSF> forests_;
};

}  // namespace gapfe

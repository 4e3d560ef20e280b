#pragma once
// Subdomain: this process's part of a problem partitioned over several (MPI ranks), as the drivers see it.
// A Problem with one (Problem::subdomain) holds only its part's cells and the nodes they use, numbered
// locally; the drivers then assemble, evaluate and recover over those cells only, and a distributed solver
// (DistributedSolver, core/concepts.hpp) sums the parts' systems. What the drivers still need from the other
// parts is a handful of collective operations, the virtual functions below (one call per solve or per
// Newton iteration, never per element). mesh/cell_partition.hpp makes the layout; solver/petsc_subdomain.hpp
// implements the operations over MPI. Without a subdomain a problem is whole and none of this runs.
//
// Local numbering: nodes [0, owned_nodes) are the part's own; the rest are ghosts, nodes of its cells (or of
// gap pairs, which every part keeps) that another part owns. Each node of the whole mesh is owned by exactly
// one part. A "node vector" holds `width` values per local node, node-major (DOF vectors have width kNd).
//
// Partial and total: a part's element loop gives, at a node shared with another part, only its own cells'
// contribution (a partial sum); sum_shared() adds the parts' contributions so that every part holds the
// total there. Every collective must be called by every part, in the same order: the drivers keep their
// decisions (convergence, contact status) on totals, which are the same on every part.
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "gapfe/core/error.hpp"

namespace gapfe {

/// Where a part's nodes and cells sit in the whole mesh, and which nodes it owns.
struct PartLayout {
  int part  = 0;  ///< this part, 0 .. parts - 1 (an MPI rank)
  int parts = 1;
  std::vector<int> global_node;      ///< local node -> node of the whole mesh (owned ones first)
  std::vector<int> global_cell;      ///< local cell -> cell of the whole mesh
  std::vector<int> global_triangle;  ///< local triangle -> triangle of the whole mesh
  std::vector<int> local_node;       ///< node of the whole mesh -> local node; -1 where the part has none
  int owned_nodes = 0;               ///< local nodes [0, owned_nodes) are this part's own
  /// Per ghost k (local node owned_nodes + k): the part that owns it, and its index among that part's
  /// owned nodes (its local number there).
  std::vector<int> ghost_part, ghost_index;
  int whole_cells = 0, whole_triangles = 0;  ///< cell counts of the whole mesh

  int local_nodes() const { return static_cast<int>(global_node.size()); }
  bool owns(int local) const { return local < owned_nodes; }
};

class Subdomain {
 public:
  explicit Subdomain(PartLayout layout) : layout_(std::move(layout)) {}
  virtual ~Subdomain()                   = default;
  Subdomain(const Subdomain&)            = delete;
  Subdomain& operator=(const Subdomain&) = delete;

  const PartLayout& layout() const { return layout_; }
  int part() const { return layout_.part; }
  int parts() const { return layout_.parts; }
  int owned_nodes() const { return layout_.owned_nodes; }

  /// Partial sums to totals: every local node's `width` values in `values` (a node vector) become the sum
  /// over every part that holds the node, on each of them.
  virtual void sum_shared(double* values, int width) const = 0;
  /// The owners' values to the ghosts: the ghost nodes' `width` values are overwritten with their owner's.
  virtual void copy_to_ghosts(double* values, int width) const = 0;
  /// `count` values summed over the parts, elementwise, in place (each part passes its own).
  virtual void sum(double* values, int count) const = 0;
  /// The largest of the parts' values.
  virtual double max(double value) const = 0;
  /// Rows of a table whose rows are spread over the parts: `count` rows of `width` values from this part,
  /// row k going to row `row[k]` of a table of `rows` rows. Returns that table on part 0 (rows that no part
  /// gave stay zero) and an empty vector elsewhere: output is written from part 0.
  virtual std::vector<double> gather_rows(const double* values, int count, int width, const int* row,
                                          int rows) const = 0;
  /// Part `from`'s `text` on every part.
  virtual std::string broadcast(const std::string& text, int from) const = 0;

 private:
  PartLayout layout_;
};

/// Runs `work` here; when it throws an InputError, a SolveError, a FileError or std::bad_alloc on any part of
/// a partitioned problem, every part throws that error (the lowest failing part's, with its message): for a
/// check, an element pass or a write that can fail on one part alone (a point's return map, a card at a node
/// only one part holds, the files rank 0 writes), which would otherwise leave the other parts waiting in
/// their next collective call. Collective; without a subdomain, `work` simply runs.
template <class Work>
void on_every_part(const Subdomain* part, Work&& work) {
  if (!part) {
    work();
    return;
  }
  int kind = 0;  // 0 none, 1 InputError, 2 SolveError, 3 FileError, 4 std::bad_alloc
  std::string what;
  try {
    work();
  } catch (const InputError& e) {
    kind = 1, what = e.what();
  } catch (const SolveError& e) {
    kind = 2, what = e.what();
  } catch (const FileError& e) {
    kind = 3, what = e.what();
  } catch (const std::bad_alloc&) {
    kind = 4;
  }
  // The lowest failing part: the smallest part number among those that failed (max of -part).
  const double first =
      -part->max(kind ? -static_cast<double>(part->part()) : -static_cast<double>(part->parts()));
  if (first >= part->parts()) return;
  const int from = static_cast<int>(first);
  std::vector<double> kinds(static_cast<std::size_t>(part->parts()), 0.0);
  kinds[static_cast<std::size_t>(part->part())] = kind;
  part->sum(kinds.data(), static_cast<int>(kinds.size()));
  what = part->broadcast(what, from);
  switch (static_cast<int>(kinds[static_cast<std::size_t>(from)])) {
    case 1:
      throw InputError(what);
    case 3:
      throw FileError(what);
    case 4:
      throw std::bad_alloc();
    default:
      throw SolveError(what);
  }
}

}  // namespace gapfe

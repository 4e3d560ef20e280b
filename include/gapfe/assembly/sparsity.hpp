#pragma once
// The stiffness pattern, built once, and per-element offsets into its value array, so that every
// later assembly is `values.setZero()` plus indexed adds: no triplets, no searches per step.
//
// Storage (MatrixStorage, core/concepts.hpp): Eigen column-major over the free DOFs, either the lower
// triangle only (row >= column), which is what SimplicialLDLT and CHOLMOD read, or every entry, for LU
// solvers of unsymmetric tangents. For an element with n DOFs the offsets cover its local upper triangle
// (i <= j, row-major, n (n + 1) / 2 entries) or its whole matrix (row-major, n^2 entries); -1 where
// either DOF is prescribed.
#include <algorithm>
#include <array>
#include <vector>

#include "gapfe/core/concepts.hpp"
#include "gapfe/core/types.hpp"
#include "gapfe/core/workers.hpp"
#include "gapfe/mesh/mesh.hpp"

namespace gapfe {

template <int DofsPerNode>
class SparsityBuilder {
 public:
  SparsityBuilder(int node_count, const std::vector<int>& equation, int free_count)
      : nn_(node_count), equation_(equation), free_count_(free_count), incident_ptr_(node_count + 1, 0) {}

  /// Register a group of cells (call for every group, then build()).
  template <std::size_t NPC>
  void add(const Connectivity<NPC>& cells) {
    groups_.push_back(
        {static_cast<int>(NPC), reinterpret_cast<const int*>(cells.data()), static_cast<int>(cells.size())});
  }

  /// Build the pattern (values zero): the lower triangle, or every entry.
  SpMat build(MatrixStorage storage = MatrixStorage::lower) {
    const bool full = storage == MatrixStorage::full;
    // node -> incident cells (over all groups), CSR.
    for (const auto& g : groups_)
      for (int k = 0; k < g.count * g.npc; ++k) ++incident_ptr_[g.nodes[k] + 1];
    for (int n = 0; n < nn_; ++n) incident_ptr_[n + 1] += incident_ptr_[n];
    std::vector<int> fill(incident_ptr_.begin(), incident_ptr_.end() - 1);
    incident_.resize(static_cast<std::size_t>(incident_ptr_[nn_]));
    for (std::size_t gi = 0; gi < groups_.size(); ++gi)
      for (int e = 0; e < groups_[gi].count; ++e)
        for (int a = 0; a < groups_[gi].npc; ++a)
          incident_[fill[groups_[gi].nodes[e * groups_[gi].npc + a]]++] = {static_cast<int>(gi), e};

    // Column by column: rows are the free DOFs of the neighbours (lower: those m >= n with equation >= the
    // column's). Equations grow with (node, component), so rows come sorted.
    std::vector<int> outer(static_cast<std::size_t>(free_count_) + 1, 0), inner, mark(nn_, -1), neighbours;
    inner.reserve(static_cast<std::size_t>(free_count_) * 10 * DofsPerNode);
    for (int n = 0; n < nn_; ++n) {
      neighbours.clear();
      for (int k = incident_ptr_[n]; k < incident_ptr_[n + 1]; ++k) {
        const auto& g = groups_[incident_[k].group];
        for (int a = 0; a < g.npc; ++a) {
          const int m = g.nodes[incident_[k].cell * g.npc + a];
          if ((full || m >= n) && mark[m] != n) mark[m] = n, neighbours.push_back(m);
        }
      }
      std::sort(neighbours.begin(), neighbours.end());
      for (int c = 0; c < DofsPerNode; ++c) {
        const int col = equation_[n * DofsPerNode + c];
        if (col < 0) continue;
        for (int m : neighbours)
          for (int c2 = 0; c2 < DofsPerNode; ++c2) {
            const int row = equation_[m * DofsPerNode + c2];
            if (row >= 0 && (full || row >= col)) inner.push_back(row);
          }
        outer[col + 1] = static_cast<int>(inner.size());
      }
    }
    // Into the matrix's own arrays at their exact size: Eigen's assignment from a Map grows its arrays by
    // doubling, which at 1e6 equations left about 200 MB of freed copies in the heap and a value array
    // twice the entries' size.
    SpMat pattern(free_count_, free_count_);
    pattern.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
    std::copy(outer.begin(), outer.end(), pattern.outerIndexPtr());
    std::copy(inner.begin(), inner.end(), pattern.innerIndexPtr());
    std::fill_n(pattern.valuePtr(), inner.size(), 0.0);
    return pattern;
  }

 private:
  struct Group {
    int npc;
    const int* nodes;
    int count;
  };
  struct Incident {
    int group, cell;
  };
  int nn_;
  const std::vector<int>& equation_;
  int free_count_;
  std::vector<Group> groups_;
  std::vector<int> incident_ptr_;
  std::vector<Incident> incident_;
};

/// Entries in the offset list of an element with n DOFs.
constexpr int offset_count(int n, MatrixStorage storage) {
  return storage == MatrixStorage::full ? n * n : n * (n + 1) / 2;
}

/// Offsets of each element's entries (local upper triangle, or all) into the value array of `pattern`.
template <int DofsPerNode, std::size_t NPC>
std::vector<int> scatter_offsets(const SpMat& pattern, const std::vector<int>& equation,
                                 const Connectivity<NPC>& cells,
                                 MatrixStorage storage = MatrixStorage::lower) {
  constexpr int n = DofsPerNode * static_cast<int>(NPC);
  const int per   = offset_count(n, storage);
  const bool full = storage == MatrixStorage::full;
  std::vector<int> off(cells.size() * static_cast<std::size_t>(per));
  const int* outer               = pattern.outerIndexPtr();
  const int* inner               = pattern.innerIndexPtr();
  constexpr std::size_t kPerTask = 4096;  // each cell's offsets its own: any thread (core/workers.hpp)
  parallel_for((cells.size() + kPerTask - 1) / kPerTask, [&](std::size_t task) {
    std::array<int, n> eq;
    for (std::size_t e = task * kPerTask; e < std::min(cells.size(), (task + 1) * kPerTask); ++e) {
      for (int a = 0; a < static_cast<int>(NPC); ++a)
        for (int c = 0; c < DofsPerNode; ++c)
          eq[a * DofsPerNode + c] = equation[cells[e][a] * DofsPerNode + c];
      int k = 0;
      for (int i = 0; i < n; ++i)
        for (int j = full ? 0 : i; j < n; ++j, ++k) {
          if (eq[i] < 0 || eq[j] < 0) {
            off[e * per + k] = -1;
            continue;
          }
          // Entry (eq_i, eq_j); the lower triangle keeps a symmetric pair once, at (max, min).
          const int row = full ? eq[i] : std::max(eq[i], eq[j]), col = full ? eq[j] : std::min(eq[i], eq[j]);
          off[e * per + k] =
              static_cast<int>(std::lower_bound(inner + outer[col], inner + outer[col + 1], row) - inner);
        }
    }
  });
  return off;
}

/// An element matrix into the stiffness values through its offsets (scatter_offsets, same storage).
template <MatrixStorage Storage, class Matrix>
void scatter(double* values, const int* off, const Matrix& k) {
  for (int i = 0, c = 0; i < k.rows(); ++i)
    for (int j = Storage == MatrixStorage::full ? 0 : i; j < k.cols(); ++j, ++c)
      if (off[c] >= 0) values[off[c]] += k(i, j);
}

}  // namespace gapfe

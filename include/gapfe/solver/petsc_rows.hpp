#pragma once
// The rows a part hands PETSc (solver/petsc.hpp): its stiffness pattern (Eigen's compressed columns, local
// equations; the lower triangle or every entry) as rows in global equation numbers, each row's columns
// sorted, and where each entry's value sits in the pattern's value array. A lower-triangle entry (i, j),
// i > j, is in row i and, as (j, i), in row j: PETSc's AIJ matrix holds the whole matrix, which every PETSc
// preconditioner reads. A part's ghost equations are rows too: their entries go to the rows' owners, which
// add every part's.
//
// Why rows, not PETSc's COO interface (MatSetPreallocationCOO, MatSetValuesCOO): COO keeps two maps of
// 8-byte counts per entry beside the matrix, about 290 B per equation, for as long as the matrix lives, and
// needs the values in COO order at every factorization, another 144 B per equation; without them a rank's
// heap at its peak (CG + GAMG) is 12% smaller (BENCHMARKS.md "What a rank holds at its peak"). These rows
// keep 8 B per entry (column and source; 12 with 64-bit PETSc indices), and each row's values go in with one
// MatSetValues of sorted columns.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include "gapfe/core/concepts.hpp"
#include "gapfe/core/types.hpp"

namespace gapfe {

/// A pattern as rows in global numbers (petsc_rows), ordered by global row.
template <class Index>
struct GlobalRows {
  std::vector<Index> row;          ///< the global number of each row
  std::vector<std::size_t> start;  ///< row r's entries are [start[r], start[r + 1])
  std::vector<Index> column;       ///< each entry's global column, ascending within its row
  std::vector<int> source;         ///< each entry's position in the pattern's value array

  std::size_t rows() const { return row.size(); }
  /// Row r's values from the pattern's `values` into `out` (resized); zeros when `values` is null.
  void values(std::size_t r, const double* values, std::vector<double>& out) const {
    out.resize(start[r + 1] - start[r]);
    for (std::size_t c = start[r]; c < start[r + 1]; ++c)
      out[c - start[r]] = values ? values[source[c]] : 0.0;
  }
};

/// The rows of pattern `k` (local equations) whose local equation e is global equation `global[e]`.
/// Rows are gathered by a counting sort (scanning the columns in order leaves each row's columns in local
/// order), then put in global order, rows and each row's few columns.
template <MatrixStorage Storage, class Index>
GlobalRows<Index> global_rows(const SpMat& k, const std::vector<std::int64_t>& global) {
  const auto n        = static_cast<std::size_t>(k.rows());
  const int* outer    = k.outerIndexPtr();
  const int* inner    = k.innerIndexPtr();
  const auto add_both = [](int i, int j) { return Storage == MatrixStorage::lower && i != j; };
  std::vector<std::size_t> start(n + 1, 0);
  for (std::size_t j = 0; j < n; ++j)
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      ++start[static_cast<std::size_t>(inner[p]) + 1];
      if (add_both(inner[p], static_cast<int>(j))) ++start[j + 1];
    }
  for (std::size_t r = 0; r < n; ++r) start[r + 1] += start[r];
  std::vector<int> column(start[n]), source(start[n]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t j = 0; j < n; ++j)
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      const auto i    = static_cast<std::size_t>(inner[p]);
      column[fill[i]] = static_cast<int>(j), source[fill[i]++] = p;
      if (add_both(inner[p], static_cast<int>(j))) column[fill[j]] = inner[p], source[fill[j]++] = p;
    }
  std::vector<std::size_t>().swap(fill);
  const auto to_global = [&](std::size_t local) { return static_cast<Index>(global[local]); };
  std::vector<std::size_t> order(n);  // local rows by global number (a part's ghosts after its own)
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return to_global(a) < to_global(b); });
  GlobalRows<Index> out;
  out.row.reserve(n), out.start.reserve(n + 1), out.column.reserve(start[n]), out.source.reserve(start[n]);
  out.start.push_back(0);
  std::vector<std::pair<Index, int>> row;  // (global column, source) of one row
  for (const std::size_t r : order) {
    row.clear();
    for (std::size_t c = start[r]; c < start[r + 1]; ++c)
      row.emplace_back(to_global(static_cast<std::size_t>(column[c])), source[c]);
    std::sort(row.begin(), row.end());
    for (const auto& [g, src] : row) out.column.push_back(g), out.source.push_back(src);
    out.row.push_back(to_global(r)), out.start.push_back(out.column.size());
  }
  return out;
}

}  // namespace gapfe

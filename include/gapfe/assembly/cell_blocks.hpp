#pragma once
// for_each_cell (assembly/cells.hpp) on every thread of the pool (core/workers.hpp):
//
//   for_each_cell_parallel  each cell's work on any thread, for passes whose cells write only their own
//                           results (a recovery's values at the cell's points, a cell's error);
//   for_each_cell_ordered   each cell's work on any thread into a slot of its own, then the slots added
//                           into shared sums (stiffness values, force vectors) by one thread at a time in
//                           the cells' order: every sum is added in the order of a serial loop, so the
//                           results are the same bit for bit on any number of threads.
//
// Cells go to the threads in tasks of kCellsPerTask consecutive cells, each task with a law cache of its
// own (LocalLawCache: consecutive cells usually share a material); the ordered loop works through the
// mesh in rounds of about kRoundBytes of slots (8,192 cells of 8 x 8 element matrices with their loads, at
// least kCellsPerTask cells), adding one round while the next is computed, so at most two rounds of slots
// are alive whatever the mesh.
#include <algorithm>
#include <array>
#include <cstddef>
#include <type_traits>
#include <vector>

#include "gapfe/assembly/cells.hpp"
#include "gapfe/core/workers.hpp"

namespace gapfe {

/// Which of for_each_cell's groups a loop visits.
enum class CellGroups { all, triangles };

inline constexpr std::size_t kCellsPerTask = 256;
inline constexpr std::size_t kRoundBytes   = std::size_t(4608) << 10;  ///< 4.5 MiB: 8,192 slots of 576 B

/// [0, count) in tasks of kCellsPerTask: task(begin, end, slots for begin..end) on the pool's threads,
/// then commit(i, slot i) for every i in increasing order, in rounds of about kRoundBytes of slots
/// (ordered_rounds, core/workers.hpp: one thread adds a round while the others compute the next; two
/// rounds' slots are alive, see the top).
template <class Slot, class Task, class Commit>
void ordered_tasks(std::size_t count, Task& task, Commit& commit) {
  constexpr std::size_t kRound =
      std::max<std::size_t>(1, kRoundBytes / sizeof(Slot) / kCellsPerTask) * kCellsPerTask;
  const std::size_t round  = std::min(count, kRound);
  const std::size_t rounds = round == 0 ? 0 : (count + round - 1) / round;
  std::vector<Slot> slots(std::min<std::size_t>(rounds, 2) * round);
  const auto size = [&](std::size_t r) { return std::min(round, count - r * round); };
  ordered_rounds(
      rounds, [&](std::size_t r) { return (size(r) + kCellsPerTask - 1) / kCellsPerTask; },
      [&](std::size_t r, std::size_t t) {
        const std::size_t begin = r * round + t * kCellsPerTask;
        task(begin, std::min(r * round + size(r), begin + kCellsPerTask),
             slots.data() + (r % 2) * round + t * kCellsPerTask);
      },
      [&](std::size_t r) {
        const Slot* s = slots.data() + (r % 2) * round;
        for (std::size_t i = 0; i < size(r); ++i) commit(r * round + i, s[i]);
      });
}

namespace detail {

/// One group of for_each_cell's (the model's cells, or the triangles) in tasks of kCellsPerTask cells.
template <class E, class Cache, class Cells, class TagOf, class F>
void cell_tasks(const Cells& cells, TagOf&& tag_of, F& f) {
  const std::size_t count = cells.size();
  parallel_for((count + kCellsPerTask - 1) / kCellsPerTask, [&](std::size_t task) {
    Cache cache;
    const std::size_t begin = task * kCellsPerTask, end = std::min(count, begin + kCellsPerTask);
    for (std::size_t e = begin; e < end; ++e) f(std::type_identity<E>{}, e, cells[e], tag_of(e), cache);
  });
}

template <class E, template <class> class Slot, class Cache, class Cells, class TagOf, class Compute,
          class Commit>
void ordered_group(const Cells& cells, TagOf&& tag_of, Compute& compute, Commit& commit) {
  auto task = [&](std::size_t begin, std::size_t end, Slot<E>* slot) {
    Cache cache;
    for (std::size_t e = begin; e < end; ++e)
      compute(std::type_identity<E>{}, e, cells[e], tag_of(e), *slot++, cache);
  };
  auto add = [&](std::size_t e, const Slot<E>& slot) {
    commit(std::type_identity<E>{}, e, cells[e], tag_of(e), slot);
  };
  gapfe::ordered_tasks<Slot<E>>(cells.size(), task, add);
}

}  // namespace detail

/// f(std::type_identity<E>{}, e, cell nodes, tag, cache) for every cell of `m` (for_each_cell's
/// arguments and a Cache of the task's), on the pool's threads in any order.
template <class Elem, class Cache, class MeshT, class F>
void for_each_cell_parallel(const MeshT& m, F&& f) {
  detail::cell_tasks<Elem, Cache>(
      m.cells, [&](std::size_t e) { return m.cell_tag(e); }, f);
  if constexpr (kHasTriangles<Elem>)
    detail::cell_tasks<typename Elem::Degenerate, Cache>(
        m.triangles, [&](std::size_t e) { return m.triangle_tag(e); }, f);
}

/// compute(std::type_identity<E>{}, e, cell, tag, Slot<E>& slot, Cache& cache) for every cell on the
/// pool's threads, then commit(std::type_identity<E>{}, e, cell, tag, const Slot<E>& slot) by one thread
/// at a time in for_each_cell's order (see the top); the triangles alone when `groups` says so.
template <class Elem, template <class> class Slot, class Cache, class MeshT, class Compute, class Commit>
void for_each_cell_ordered(const MeshT& m, CellGroups groups, Compute&& compute, Commit&& commit) {
  if (groups == CellGroups::all)
    detail::ordered_group<Elem, Slot, Cache>(
        m.cells, [&](std::size_t e) { return m.cell_tag(e); }, compute, commit);
  if constexpr (kHasTriangles<Elem>)
    detail::ordered_group<typename Elem::Degenerate, Slot, Cache>(
        m.triangles, [&](std::size_t e) { return m.triangle_tag(e); }, compute, commit);
}

}  // namespace gapfe

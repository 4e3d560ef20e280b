#pragma once
// gapfe's own threads: the passes over the cells (assembly, recovery, the error estimate) and the
// encoding of the output files run on the calling thread and the workers of one process-wide pool,
// sized by set_worker_threads(n) (the `gapfe` command's --threads N). Until a caller asks there are no
// workers and every loop runs on the calling thread: a library does not start threads unasked.
//
// Results never depend on the number of threads. parallel_for(count, f) calls f(task) once for every
// task in [0, count), on whichever thread is free; its callers write each task's results to a place of
// their own and add shared sums on one thread at a time in task order (assembly/cell_blocks.hpp), so
// every sum is added in the same order for any n. When tasks throw, the exception of the lowest failing task
// is rethrown, the one a serial loop would have met first.
//
// Why a pool of our own rather than OpenMP or the parallel algorithms: the process keeps OpenMP on one
// thread (solver/threads.hpp: CHOLMOD's num_threads clauses oversubscribe the cores), and libstdc++'s
// std::execution::par needs TBB, a dependency for what here is one loop. A task's own parallel_for runs
// on the thread that makes it.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace gapfe {

/// threads - 1 workers that sleep until run() hands them tasks (see the top).
class WorkerPool {
 public:
  explicit WorkerPool(int threads) {
    try {
      for (int t = 1; t < threads; ++t) workers_.emplace_back([this] { work(); });
    } catch (...) {  // a thread the system would not start: end those that did
      stop_workers();
      throw;
    }
  }
  WorkerPool(const WorkerPool&)            = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;
  ~WorkerPool() { stop_workers(); }
  int threads() const { return static_cast<int>(workers_.size()) + 1; }
  /// Loops started on the calling thread run on it alone from now on. For a thread of a program's own
  /// beside the pool's loops (the run's file writer, app/run_output_impl.hpp): run() hands out one loop at a
  /// time, and that thread's loops would otherwise meet another thread's.
  static void run_loops_here() { inside_ = true; }

  /// f(task) for every task in [0, count), the calling thread working too; returns when all are done.
  template <class F>
  void run(std::size_t count, F& f) {
    if (workers_.empty() || count <= 1 || inside_) {
      for (std::size_t t = 0; t < count; ++t) f(t);
      return;
    }
    Job job;
    job.call  = [](void* g, std::size_t t) { (*static_cast<F*>(g))(t); };  // F may be const
    job.f     = const_cast<void*>(static_cast<const void*>(&f));
    job.count = count;
    {
      std::lock_guard lock(mutex_);
      job_ = &job, ++generation_;
    }
    wake_.notify_all();
    take(job);
    std::unique_lock lock(mutex_);
    job_ = nullptr;  // no worker joins it from now on
    done_.wait(lock, [&] { return job.active == 0; });
    if (job.error) std::rethrow_exception(job.error);
  }

 private:
  struct Job {
    void (*call)(void*, std::size_t) = nullptr;
    void* f                          = nullptr;
    std::size_t count                = 0;
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    int active              = 0;                                        ///< workers inside (mutex_)
    std::size_t failed_task = std::numeric_limits<std::size_t>::max();  ///< (mutex_)
    std::exception_ptr error;  ///< the lowest failing task's (mutex_)
  };

  void stop_workers() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
  }
  /// Tasks in increasing order until none is left or one has failed: every task below a failing one has
  /// been handed out and runs to its end, so the lowest failure is always seen.
  void take(Job& job) {
    inside_ = true;
    for (std::size_t t;
         !job.failed.load(std::memory_order_relaxed) && (t = job.next.fetch_add(1)) < job.count;) {
      try {
        job.call(job.f, t);
      } catch (...) {
        std::lock_guard lock(mutex_);
        if (t < job.failed_task) job.failed_task = t, job.error = std::current_exception();
        job.failed = true;
      }
    }
    inside_ = false;
  }
  void work() {
    std::uint64_t seen = 0;
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return stop_ || (job_ && generation_ != seen); });
      if (stop_) return;
      seen     = generation_;
      Job& job = *job_;
      ++job.active;
      lock.unlock();
      take(job);
      lock.lock();
      if (--job.active == 0) done_.notify_all();
    }
  }

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  Job* job_                               = nullptr;  ///< the job running, (mutex_)
  std::uint64_t generation_               = 0;        ///< jobs started (mutex_)
  bool stop_                              = false;
  static inline thread_local bool inside_ = false;  ///< this thread is running a task
};

namespace detail {
inline std::unique_ptr<WorkerPool>& worker_pool() {
  static std::unique_ptr<WorkerPool> pool;
  return pool;
}
}  // namespace detail

/// From now on gapfe's loops run on n >= 1 threads (the calling one and n - 1 workers). Call it between
/// runs, never while a loop runs.
inline void set_worker_threads(int n) {
  auto& pool = detail::worker_pool();
  pool.reset();
  if (n > 1) pool = std::make_unique<WorkerPool>(n);
}
/// The threads gapfe's loops run on.
inline int worker_threads() {
  const auto& pool = detail::worker_pool();
  return pool ? pool->threads() : 1;
}

/// f(task) for every task in [0, count) on the pool's threads (see the top); f must not touch what
/// another task writes.
template <class F>
void parallel_for(std::size_t count, F&& f) {
  if (auto& pool = detail::worker_pool()) return pool->run(count, f);
  for (std::size_t t = 0; t < count; ++t) f(t);
}

/// Rounds 0 .. rounds - 1 of work, pipelined so that results are consumed in order while later ones are
/// made: round r's tasks(r) tasks, work(r, t), run on the pool together with finish(r - 1) as one more
/// task, which consumes round r - 1's results in order on one thread (adds them into shared sums, appends
/// them to a file) while the other threads compute round r. A caller keeps two rounds of results (round r
/// into the buffer r % 2) and finish must touch nothing work writes.
template <class Tasks, class Work, class Finish>
void ordered_rounds(std::size_t rounds, Tasks&& tasks, Work&& work, Finish&& finish) {
  for (std::size_t r = 0; r <= rounds; ++r) {
    const std::size_t finishing = r > 0 ? 1 : 0, working = r < rounds ? tasks(r) : 0;
    parallel_for(finishing + working, [&](std::size_t t) {
      if (t < finishing)
        finish(r - 1);
      else
        work(r, t - finishing);
    });
  }
}

}  // namespace gapfe

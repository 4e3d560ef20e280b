#pragma once
// The definitions of app/run_output.hpp's RunFiles, for exactly one translation unit of a program (the
// gapfe::app target's command.cpp, through app/command_impl.hpp): the writers and the pictures are
// compiled there once.
#include <chrono>
#include <exception>
#include <functional>
#include <system_error>
#include <thread>
#include <utility>

#include "gapfe/app/run_output.hpp"
#include "gapfe/core/workers.hpp"

namespace gapfe::app {

/// One increment's files at a time, on a thread of their own, while the run computes the next increment:
/// with two threads or more the writing (about a tenth of a plastic run's time, most of it one thread
/// appending to the files) otherwise holds every other thread idle. The bytes are the same: the files are
/// written in the same order by the same code, its loops on the writer's thread alone
/// (WorkerPool::run_loops_here).
class RunFiles::Writer {
 public:
  /// `steps`: the run's load steps, the load factor of its last increment.
  explicit Writer(int steps) : steps_(steps) {}
  Writer(const Writer&)            = delete;
  Writer& operator=(const Writer&) = delete;
  ~Writer() {
    if (thread_.joinable()) thread_.join();
  }
  /// Waits for the increment being written, and throws what writing it threw.
  void wait() {
    if (thread_.joinable()) thread_.join();
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }
  /// write() on the writer's thread, after the last increment's (wait() first). When the system starts no
  /// thread it is written here instead, and what it throws is thrown here.
  void start(std::function<void()> write) {
    wait();
    job_ = std::move(write);
    try {
      thread_ = std::thread([this] {
        WorkerPool::run_loops_here();
        run();
      });
      used_   = true;
    } catch (const std::system_error&) {
      run();
      wait();
    }
  }
  /// The seconds the writer's thread spent writing (read after wait()).
  double seconds() const { return seconds_; }
  /// Whether increment `inc` is written beside the next: with two threads or more (core/workers.hpp), and
  /// not the run's last increment, which has no next one and is written on every thread by the caller.
  bool beside(double inc) const { return worker_threads() > 1 && !last(inc); }
  /// Whether increment `inc` is the run's last (its load factor the last step's).
  bool last(double inc) const { return inc >= steps_ * (1 - 1e-12); }
  /// Whether any increment was.
  bool used() const { return used_; }

 private:
  void run() {
    const auto begin = std::chrono::steady_clock::now();
    try {
      job_();
    } catch (...) {
      error_ = std::current_exception();
    }
    job_ = nullptr;  // the increment's copies
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  }

  std::function<void()> job_;
  std::thread thread_;
  std::exception_ptr error_;
  double seconds_ = 0;
  int steps_      = 0;
  bool used_      = false;
};

RunFiles::RunFiles(const RunRequest& r) {
  // One process writes a serial run's files: a partition of one part has no pieces to speak of.
  const bool parts = r.part && r.part->subdomain->parts() > 1 && !r.model.options.output_gathered;
  // Collective in a partitioned run: a rank that cannot open its files (a folder the others do not share)
  // fails every rank with its message.
  on_every_part(r.part ? r.part->subdomain.get() : nullptr, [&] {
    if (!r.writes && !parts) return;
    if (parts) {
      rows_.emplace(part_rows(r.scene, r.part->subdomain->layout()));
      if (r.model.steps() > 1) cards_.emplace(card_nodes(r.scene));
    }
    writer_ = std::make_unique<Writer>(r.model.steps());
    files_  = std::make_unique<StepFiles>(r.dir, r.scene, r.model.step_time(), r.model.options.output_csv,
                                         r.model.options.output_vtu, rows());
    if (!r.writes) return;  // a part other than rank 0: its own tables and pieces only
    files_->draw_fields(r.pictures, r.units);
    files_->keep_history(r.model.steps(), {r.plan.key.friction != FrictionChoice::none,
                                           r.plan.key.kinematics == VariantChoice::saga});
  });
}
RunFiles::~RunFiles() = default;

void RunFiles::agreed(double inc) {
  if (!files_) return;
  // Every part has returned from write(): its increments before this one are on disk (write() waits for
  // the one before), and this one too when it is the run's last, which no part writes beside the next
  // (Writer::beside). Part 0 lists them while this one may still be written on the writer's thread.
  ++agreed_;
  complete_ = writer_->last(inc) ? agreed_ : agreed_ - 1;
  files_->publish(complete_);
}

void RunFiles::close_series(bool complete) {
  if (!files_) return;
  if (!complete) files_->publish(complete_);  // what the last agreement proved on disk everywhere
  files_->close_series(complete);
}

std::vector<double> RunFiles::node_figures(const Solution& part) const {
  return cards_ ? history_node_figures(*cards_, part, rows()) : std::vector<double>{};
}

bool RunFiles::draws() const {
  return files_ && files_->draws();
}

void RunFiles::keep_last(const Solution& whole, const std::vector<PointValues>& values,
                         const std::vector<VtuField>& extra_cells) {
  if (!files_) return;
  writer_->wait();  // the increment before writes on the writer's thread, and keeps nothing of its own
  files_->keep_last(whole, values, extra_cells);
}

void RunFiles::write(int step, double inc, const Solution& solution, std::vector<PointValues> values,
                     std::vector<VtuField> extra_cells, const IncrementSummary& summary) {
  if (!files_) return;  // a process that writes no files (RunRequest::writes)
  if (writer_->beside(inc)) {
    // The solution is the driver's, which the next increment changes: the writer gets a copy.
    writer_->start(
        [this, step, inc, solution, values = std::move(values), extra = std::move(extra_cells),
         summary]() mutable { files_->write(step, inc, solution, values, std::move(extra), summary); });
    return;
  }
  writer_->wait();  // the increment before, if it is still being written
  const auto begin = std::chrono::steady_clock::now();
  files_->write(step, inc, solution, values, std::move(extra_cells), summary);
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
}

void RunFiles::finish(const std::string& title, RunResult& times) {
  if (!files_) return;
  // A failure of the last increment written beside is thrown after the files are closed and the pictures
  // drawn, as it is with one thread, where write() threw it and the run's end still came here.
  std::exception_ptr writing;
  try {
    writer_->wait();
  } catch (...) {
    writing = std::current_exception();
  }
  const auto begin = std::chrono::steady_clock::now();
  try {
    files_->finish(title);
  } catch (...) {
    if (!writing) throw;
  }
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  times.pictures = files_->pictures_written(), times.pictures_skipped = files_->pictures_skipped();
  times.files_seconds = seconds_ + writer_->seconds();
  times.files_beside  = writer_->used();
  writer_failed_      = writing != nullptr;
  if (writing) std::rethrow_exception(writing);
}

}  // namespace gapfe::app

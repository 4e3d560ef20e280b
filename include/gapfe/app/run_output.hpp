#pragma once
// What a run's loops share (app/run_loops.hpp): the request, and the write of one increment with its
// record in the RunResult.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "gapfe/app/plan.hpp"
#include "gapfe/app/read_quantities.hpp"
#include "gapfe/app/run_result.hpp"
#include "gapfe/input/scene.hpp"
#include "gapfe/output/step_files.hpp"
#include "gapfe/post/gather.hpp"
#include "gapfe/post/recovery_weights.hpp"
#include "gapfe/run/scene_run.hpp"

namespace gapfe::app {

/// What a run needs: the model, its plan, where to write and how to speak.
struct RunRequest {
  const ModelDescription& model;
  const Scene& scene;
  const Plan& plan;
  std::string dir;
  std::ostream& err;
  bool progress;
  std::vector<std::string> pictures;  ///< fields drawn for the last increment (StepFiles::draw_fields)
  PlotUnits units;
  /// A partitioned run (solver = petsc): this process's part of the scene; nullptr: the whole scene here.
  const ScenePart* part = nullptr;
  /// Whether this process writes the files (rank 0 of a partitioned run, which gathers the results).
  bool writes = true;
  /// Whether the run records the quantities `--estimate` gives error bars (RunResult::quantities).
  bool read_quantities = false;
  /// The error estimate's patch fit, kept across the run's increments (post/recovery_weights.hpp; the mesh
  /// of a run stays as it is); nullptr: each increment's estimate fits its own.
  RecoveryWeights* recovery = nullptr;
  /// Called when the run fails, before its files are closed (Process::failing); may be empty.
  std::function<void()> failing = {};
};

/// The result files of a run (output/step_files.hpp): on the process that writes them (every process of a
/// whole run; rank 0 of a partitioned one), none elsewhere. Its members are only declared here and compiled
/// once, with the command's definitions (app/run_output_impl.hpp): the writers and the pictures do not
/// depend on the variant, and had been 8% of every variant shard's machine code (BENCHMARKS.md "CI time").
class RunFiles {
 public:
  /// The deck's output options and the pictures it asks for, on the process that writes (r.writes).
  explicit RunFiles(const RunRequest& r);
  ~RunFiles();
  RunFiles(const RunFiles&)            = delete;
  RunFiles& operator=(const RunFiles&) = delete;
  explicit operator bool() const { return files_ != nullptr; }
  /// One increment (StepFiles::write). With two threads or more (core/workers.hpp) its files are written on
  /// a thread of their own while the run goes on to the next increment, one increment at a time: this call
  /// first waits for the last one's files, and a failure to write them is thrown here or by finish().
  void write(int step, double inc, const Solution& solution, std::vector<PointValues> values,
             std::vector<VtuField> extra_cells, const IncrementSummary& summary);
  /// The end of the run (StepFiles::finish, after the last increment's files): the held increment,
  /// deformed.svg and the pictures, recorded in `times` (RunResult::pictures, pictures_skipped,
  /// files_seconds).
  void finish(const std::string& title, RunResult& times);
  /// Whether finish() threw the failure of an increment written beside the run's work.
  bool writer_failed() const { return writer_failed_; }

 private:
  class Writer;
  std::unique_ptr<StepFiles> files_;
  std::unique_ptr<Writer> writer_;  ///< the thread writing an increment's files, with two threads or more
  double seconds_     = 0;          ///< spent writing on the run's own thread
  bool writer_failed_ = false;
};

/// The log's progress line.
inline void progress_line(const RunRequest& r, int step) {
  if (r.progress) r.err << "\rstep " << step << "/" << r.model.steps() << std::flush;
}
inline void progress_done(const RunRequest& r) {
  if (r.progress) r.err << "\r" << std::string(32, ' ') << "\r" << std::flush;
}

/// `per_step[step - 1]` becomes the largest of it and `value` (a figure per load step: its worst increment).
inline void keep_largest(std::vector<double>& per_step, int step, double value) {
  if (per_step.size() < static_cast<std::size_t>(step)) per_step.resize(static_cast<std::size_t>(step), 0.0);
  double& worst = per_step[static_cast<std::size_t>(step - 1)];
  worst         = std::isnan(value) ? value : std::max(worst, value);  // a NaN is kept, never passed over
}

/// The recovery estimate of an accepted increment's discretization error (post/error_estimate.hpp), timed:
/// recorded in `times` (per load step and the last) and returned as the VTU cell array `error_estimate`, one
/// value per deck element (gap elements 0), on the process that writes; empty elsewhere. The same pass gives
/// the output's centroid stresses (`centroids`: the driver's centroid_values(Recovered::stress)), so the
/// phase's time (RunResult::recovery) holds theirs, and `peak` the recovered field's largest von Mises.
template <class Fe>
VtuField estimate_increment(const RunRequest& r, RunResult& times, int step, const Fe& fe,
                            std::vector<PointValues>& centroids, PeakStress& peak) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<int> gap_materials;
  if (r.scene.gap_material >= 0) gap_materials.push_back(r.scene.gap_material);
  ErrorEstimate estimate = fe.error_estimate(gap_materials, &centroids, r.recovery);
  keep_largest(times.step_error, step, estimate.relative());
  times.error = estimate.relative(), times.error_stress_free = estimate.stress_free;
  peak                  = {estimate.peak_mises, estimate.peak_node};
  const Subdomain* part = fe.problem().subdomain.get();
  const std::vector<double> cells =
      part ? gather_cell_values(*part, estimate.cell) : std::move(estimate.cell);
  VtuField field{"error_estimate", 1, {}};
  if (!cells.empty()) {
    const IJGrid& g = r.scene.grid;
    field.values.resize(g.cells.size());
    for (std::size_t e = 0; e < g.cells.size(); ++e) {
      const GridCell& c = g.cells[e];
      field.values[e] =
          cells[(c.corners == 4 ? 0 : r.scene.mesh.cells.size()) + static_cast<std::size_t>(c.group_index)];
    }
    const auto worst    = std::max_element(field.values.begin(), field.values.end());
    times.error_element = -1;
    if (worst != field.values.end() && *worst > 0) {
      const GridCell& c      = g.cells[static_cast<std::size_t>(worst - field.values.begin())];
      times.error_element    = static_cast<int>(worst - field.values.begin());
      times.error_element_at = Vec2::Zero();
      for (int k = 0; k < c.corners; ++k) times.error_element_at += g.nodes[c.node[k]] / c.corners;
    }
  }
  times.recovery += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return field;
}

/// One accepted increment: refuse a non-finite solution, estimate its error, write the files (timed; a
/// partitioned run gathers the whole mesh's results to the writing rank first), show progress.
template <class Fe>
void write_increment(const RunRequest& r, RunResult& times, RunFiles& files, int step, double inc,
                     const Fe& fe, std::vector<VtuField> extra_cells = {},
                     const IncrementSummary& summary = {}) {
  if constexpr (requires { fe.factor_statistics(); })
    times.factor = fe.factor_statistics(), times.factorizations = fe.factorizations();
  const Solution& solution = fe.solution();
  if (!std::isfinite(solution.residual) || !solution.displacement.allFinite() ||
      !solution.reaction.allFinite() || !std::isfinite(solution.balance.relative()))
    throw SolveError("load step " + std::to_string(step) + ": the solution is not finite");
  // A law with history reports Newton's out-of-balance here instead (the tangent integration leaves
  // one by design), so only a linear law's residual measures the solve.
  const double residual = fe.solution().residual;
  if constexpr (Fe::Law::kLinear)
    if (residual > times.equilibrium) times.equilibrium = residual, times.equilibrium_step = step;
  keep_largest(times.step_residual, step, residual);
  const Balance& balance = fe.solution().balance;
  keep_largest(times.step_balance, step, balance.relative());
  if (balance.relative() > times.balance) times.balance = balance.relative(), times.balance_step = step;
  times.last_balance = balance;
  std::vector<PointValues> centroids;
  PeakStress peak;
  if (r.model.options.error_estimate) {
    extra_cells.push_back(estimate_increment(r, times, step, fe, centroids, peak));
  } else {
    const auto start = std::chrono::steady_clock::now();
    centroids        = fe.centroid_values(Recovered::stress);
    times.recovery += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const auto start = std::chrono::steady_clock::now();
  if (const Subdomain* part = fe.problem().subdomain.get()) {
    const Solution whole = gather_solution(*part, fe.solution());
    auto values          = gather_cells(*part, centroids, Recovered::stress);
    // Rank 0 writes; a failure there is every rank's (core/subdomain.hpp), so that all unwind together.
    on_every_part(part, [&] {
      if (files) files.write(step, inc, whole, std::move(values), std::move(extra_cells), summary);
    });
  } else {
    if (r.read_quantities)
      times.quantities = read_quantities(r.scene, fe.solution(), centroids, peak, r.plan.plastic);
    if (files) files.write(step, inc, fe.solution(), std::move(centroids), std::move(extra_cells), summary);
  }
  times.write += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress_line(r, step);
}

/// The end of a run, however it ends: the held increment (output = last), deformed.svg and the pictures,
/// timed as writing. A run that fails (a step Newton cannot take) still leaves them for the increments it
/// accepted; an error while writing them then gives way to the run's own.
struct FinishFiles {
  const RunRequest& r;
  RunResult& times;
  RunFiles& files;
  bool done = false;

  void now() {
    done = true;
    progress_done(r);
    if (!files) return;
    const auto start = std::chrono::steady_clock::now();
    files.finish(r.model.title, times);
    times.write += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  /// A run that failed: its own error is the one the command reports, so the failure of an increment's
  /// files written beside the failing work (RunFiles::writer_failed) is said here.
  ~FinishFiles() {
    if (done) return;
    try {
      if (r.failing) r.failing();
      now();
    } catch (const std::exception& e) {
      if (!files.writer_failed()) return;
      try {
        r.err << "gapfe: the files of the increments before the failure are incomplete: "
              << detail::visible_text(e.what(), /*lines=*/true) << "\n";
      } catch (...) {  // nothing may leave a destructor
      }
    } catch (...) {
    }
  }
};

}  // namespace gapfe::app

#pragma once
// What a run's loops share (app/run_loops.hpp): the request, and the write of one increment with its
// record in the RunResult.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
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
  /// Whether this process writes the run's files: every file of a whole run; of a partitioned one, those of
  /// the whole run (history.csv, gaps.csv, plasticity.csv, result.pvd, the pictures), on rank 0, which
  /// also writes the tables and VTU files when the run gathers its results (output_parts = gathered).
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
/// whole run; rank 0 of a partitioned one that gathers its results), none elsewhere; on every process of a
/// partitioned run that writes its parts (output_parts = pieces, the default: rows()). Its members are only
/// declared here and compiled
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

  /// A partitioned run that writes its parts: this process's rows (output/part_rows.hpp); else nullptr.
  const PartRows* rows() const { return rows_ ? &*rows_ : nullptr; }
  /// A part's share of history.csv's node figures (history_node_figures), or nothing for a run of one step.
  std::vector<double> node_figures(const Solution& part) const;
  /// Whether the whole mesh's results are gathered for deformed.svg and the pictures (StepFiles::draws).
  bool draws() const;
  /// A partitioned run that writes its parts: every part has returned from write() of increment `inc`
  /// (an agreement, core/subdomain.hpp), so rank 0 lists its earlier increments (StepFiles::publish).
  void agreed(double inc);
  /// After finish(): a partitioned run's VTU series closed (StepFiles::close_series), every increment listed
  /// when `complete` (every part finished its files), else those the last agreement proved written.
  void close_series(bool complete);
  /// StepFiles::keep_last, on the process that draws (rank 0), after the increment before is written.
  void keep_last(const Solution& whole, const std::vector<PointValues>& values,
                 const std::vector<VtuField>& extra_cells);

 private:
  class Writer;
  std::optional<PartRows> rows_;  ///< a partitioned run that writes its parts
  /// and, for a run of several steps, history.csv's cards, whose reactions each part sums
  std::optional<std::vector<CardNodes>> cards_;
  std::size_t agreed_   = 0;  ///< write() calls every part has returned from (agreed())
  std::size_t complete_ = 0;  ///< of those, the ones every part has on disk
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

/// One value per cell in the order of centroid values (cells, then triangles) as the VTU cell array `name`,
/// one value per deck element.
inline VtuField deck_field(const Scene& scene, std::string name, const std::vector<double>& cells) {
  VtuField f{std::move(name), 1, std::vector<double>(scene.grid.cells.size())};
  for (std::size_t e = 0; e < f.values.size(); ++e) f.values[e] = cells[element_index(scene, e)];
  return f;
}

/// The deck element of the largest value of `field` (one per cell of `rows`' part, or per deck element
/// without it) and its centroid, into `times` (RunResult::error_element, -1 where every value is 0): over
/// every part, the lowest part's where several hold the largest. Collective with `rows`.
inline void note_worst_element(const RunRequest& r, RunResult& times, const std::vector<double>& field,
                               const PartRows* rows, const Subdomain* part) {
  const auto worst     = std::max_element(field.begin(), field.end());
  const double largest = worst == field.end() ? 0.0 : *worst;
  int element          = worst == field.end() ? -1 : static_cast<int>(worst - field.begin());
  if (rows && element >= 0) element = rows->element[static_cast<std::size_t>(element)];
  std::array<double, 3> at{-1, 0, 0};  // element, r, z
  if (largest > 0) {
    const GridCell& c = r.scene.grid.cells[static_cast<std::size_t>(element)];
    Vec2 centroid     = Vec2::Zero();
    for (int k = 0; k < c.corners; ++k) centroid += r.scene.grid.nodes[c.node[k]] / c.corners;
    at = {static_cast<double>(element), centroid(0), centroid(1)};
  }
  if (rows) {  // the part holding the largest value (the lowest of several) tells the others
    const double top   = part->max(largest);
    const double owner = -part->max(largest == top && top > 0 ? -rows->part : -rows->parts);
    if (rows->part != owner) at = {0, 0, 0};
    part->sum(at.data(), 3);
    if (owner == rows->parts) at[0] = -1;  // every value 0: no part is the owner
  }
  times.error_element = static_cast<int>(at[0]);
  if (times.error_element >= 0) times.error_element_at = Vec2(at[1], at[2]);
}

/// The recovery estimate of an accepted increment's discretization error (post/error_estimate.hpp), timed:
/// recorded in `times` (per load step and the last) and returned as the VTU cell array `error_estimate`, one
/// value per deck element (gap elements 0), on the process that writes; empty elsewhere; a part's own cells'
/// on every part of a partitioned run that writes its parts (`rows`). The same pass gives
/// the output's centroid stresses (`centroids`: the driver's centroid_values(Recovered::stress)), so the
/// phase's time (RunResult::recovery) holds theirs, and `peak` the recovered field's largest von Mises.
template <class Fe>
VtuField estimate_increment(const RunRequest& r, RunResult& times, int step, const Fe& fe,
                            std::vector<PointValues>& centroids, PeakStress& peak, const PartRows* rows) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<int> gap_materials;
  if (r.scene.gap_material >= 0) gap_materials.push_back(r.scene.gap_material);
  ErrorEstimate estimate = fe.error_estimate(gap_materials, &centroids, r.recovery);
  keep_largest(times.step_error, step, estimate.relative());
  times.error = estimate.relative(), times.error_stress_free = estimate.stress_free;
  peak                  = {estimate.peak_mises, estimate.peak_node};
  const Subdomain* part = fe.problem().subdomain.get();
  VtuField field{"error_estimate", 1, {}};
  if (rows) {  // the part's cells, in its order (output/part_rows.hpp)
    field.values = std::move(estimate.cell);
    note_worst_element(r, times, field.values, rows, part);
  } else {
    const std::vector<double> cells =
        part ? gather_cell_values(*part, estimate.cell) : std::move(estimate.cell);
    if (!cells.empty()) {
      field = deck_field(r.scene, field.name, cells);
      note_worst_element(r, times, field.values, nullptr, nullptr);
    }
  }
  times.recovery += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return field;
}

/// A partitioned run's increment written by its parts (RunFiles::rows): each part its own rows, the ghost
/// nodes' taken from their owners; history.csv's node figures summed over the parts; the whole mesh's
/// results gathered only for the pictures of a mesh small enough to draw. Collective.
inline void write_parts(RunFiles& files, const Scene& scene, const Subdomain& part, int step, double inc,
                        const Solution& own, std::vector<PointValues> centroids,
                        std::vector<VtuField> extra_cells, std::optional<VtuField> estimate,
                        IncrementSummary summary) {
  const PartRows& rows           = *files.rows();
  Solution local                 = own;
  std::vector<double> ghost_rows = node_rows(own, rows.local_nodes());  // the ghosts' from their owners
  part.copy_to_ghosts(ghost_rows.data(), 6);
  set_node_rows(local, ghost_rows.data(), rows.owned_nodes(), rows.local_nodes());
  if (std::vector<double> figures = files.node_figures(local); !figures.empty()) {
    const double u_max = part.max(figures.back());
    part.sum(figures.data(), static_cast<int>(figures.size()));
    figures.back()       = u_max;
    summary.node_figures = std::move(figures);
  }
  if (files.draws()) {  // deformed.svg and the pictures, on rank 0
    const Solution whole                  = gather_solution(part, local);
    const std::vector<PointValues> values = gather_cells(part, centroids, Recovered::stress);
    std::vector<VtuField> whole_cells     = extra_cells;  // the gap fields are whole already
    if (estimate)                                         // every part estimates, or none
      if (const std::vector<double> cells = gather_cell_values(part, estimate->values); !cells.empty())
        whole_cells.push_back(deck_field(scene, estimate->name, cells));
    on_every_part(&part, [&] {
      if (!values.empty()) files.keep_last(whole, values, whole_cells);
    });
  }
  // The gap fields are the whole mesh's (every part holds every pair): each part writes its cells' values.
  for (VtuField& f : extra_cells) {
    std::vector<double> mine(rows.element.size() * static_cast<std::size_t>(f.components));
    for (std::size_t k = 0; k < rows.element.size(); ++k)
      for (int c = 0; c < f.components; ++c)
        mine[k * static_cast<std::size_t>(f.components) + static_cast<std::size_t>(c)] =
            f.values[static_cast<std::size_t>(rows.element[k] * f.components + c)];
    f.values = std::move(mine);
  }
  if (estimate) extra_cells.push_back(std::move(*estimate));
  on_every_part(
      &part, [&] { files.write(step, inc, local, std::move(centroids), std::move(extra_cells), summary); });
  on_every_part(&part, [&] { files.agreed(inc); });  // rank 0 lists what every part has written
}
/// One accepted increment: refuse a non-finite solution, estimate its error, write the files (timed; a
/// partitioned run writes its parts, write_parts, or gathers the whole mesh's results to rank 0 first),
/// show progress.
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
  std::optional<VtuField> estimate;  // with the estimate on (the same on every part)
  if (r.model.options.error_estimate) {
    estimate = estimate_increment(r, times, step, fe, centroids, peak, files.rows());
  } else {
    const auto start = std::chrono::steady_clock::now();
    centroids        = fe.centroid_values(Recovered::stress);
    times.recovery += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const auto start      = std::chrono::steady_clock::now();
  const Subdomain* part = fe.problem().subdomain.get();
  if (part && files.rows()) {
    write_parts(files, r.scene, *part, step, inc, fe.solution(), std::move(centroids), std::move(extra_cells),
                std::move(estimate), summary);
  } else if (part) {
    if (estimate) extra_cells.push_back(std::move(*estimate));
    const Solution whole = gather_solution(*part, fe.solution());
    auto values          = gather_cells(*part, centroids, Recovered::stress);
    // Rank 0 writes; a failure there is every rank's (core/subdomain.hpp), so that all unwind together.
    on_every_part(part, [&] {
      if (files) files.write(step, inc, whole, std::move(values), std::move(extra_cells), summary);
    });
  } else {
    if (estimate) extra_cells.push_back(std::move(*estimate));
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

  /// `agreed`: on a run's normal end every rank of a partitioned run comes here, and a rank that cannot
  /// finish its files fails every rank (core/subdomain.hpp), so that rank 0 never records a run complete
  /// whose other parts are not; the files' seconds are then the slowest rank's.
  void now(bool agreed = true) {
    done = true;
    progress_done(r);
    const Subdomain* part = agreed && r.part ? r.part->subdomain.get() : nullptr;
    const auto start      = std::chrono::steady_clock::now();
    try {
      on_every_part(part, [&] {
        if (files) files.finish(r.model.title, times);
      });
    } catch (...) {  // the series still lists what every part is known to have written
      try {
        files.close_series(false);
      } catch (...) {  // the first failure is the one to report
      }
      throw;
    }
    if (part) times.files_seconds = part->max(times.files_seconds);
    // Agreed, every part has finished its files and the series lists every increment; after a failure,
    // those the last agreement proved written everywhere.
    on_every_part(part, [&] { files.close_series(agreed); });
    times.write += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  /// A run that failed: its own error is the one the command reports, so the failure of an increment's
  /// files written beside the failing work (RunFiles::writer_failed) is said here.
  ~FinishFiles() {
    if (done) return;
    try {
      if (r.failing) r.failing();
      now(/*agreed=*/false);  // a rank failing alone must not wait for the others here
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

#pragma once
// `gapfe run --estimate`: error bars on the quantities a user reads (app/read_quantities.hpp). The model is
// solved again on its mesh at 1/2 the spacing, and at 1/4 where that mesh is small enough (kThirdLevelNodes):
// a deck's or a grid scene's grid from the same cards (input/deck_refine.hpp), a Gmsh mesh with every cell
// split in four (input/gmsh_refine.hpp); each quantity's values are extrapolated
// (post/extrapolation.hpp) and its error bar is the distance of this run's value to the limit. The finer runs
// write no files: the log and estimates.csv carry what they found. docs/accuracy.md "Error bars".
#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <new>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "gapfe/app/plan.hpp"
#include "gapfe/app/read_quantities.hpp"
#include "gapfe/app/run.hpp"
#include "gapfe/input/deck_refine.hpp"
#include "gapfe/input/scene.hpp"
#include "gapfe/output/csv_rows.hpp"
#include "gapfe/output/output_file.hpp"
#include "gapfe/post/extrapolation.hpp"

namespace gapfe::app {

/// The mesh at 1/4 the spacing is solved too when it has at most this many nodes (16 times the deck's): 2e6
/// equations with 2 DOF per node, about 4 GB and 20 s per factorization by BENCHMARKS.md's 1e6-equation tube
/// (2 GB, 8 s), more for 3 DOF and for steps with many solves. Three meshes give each quantity's observed
/// order and show one that does not converge; two can only assume the order.
inline constexpr long kThirdLevelNodes = 1'000'000;

/// One mesh's run: its spacing level (0 the deck's own; k: 1 / 2^k of it), size, time and quantities.
struct LevelRun {
  int level      = 0;
  long nodes     = 0;
  double seconds = 0;
  std::vector<ReadQuantity> quantities;
};

/// The model on its mesh refined `times` times (1: half the spacing): a deck's from its grid cards
/// (refine_deck), a scene file's read again refined (read_scene_file). Throws InputError when it cannot.
using Refiner = std::function<SceneModel(int times)>;

/// A deck's Refiner: `deck`, whose scene is `scene`, through refine_deck (both must outlive it).
inline Refiner deck_refiner(const Deck& deck, const Scene& scene) {
  return [&deck, &scene](int times) {
    RefinedDeck r = refine_deck(deck, scene, times);
    return SceneModel{std::move(r.deck), std::move(r.scene), "",
                      "the grid at 1/" + std::to_string(1 << times) + " of its spacing"};
  };
}

/// Why `gapfe run --estimate` cannot refine this model, before any run: empty when it can.
inline std::string estimate_refused(const Plan& p) {
  if (p.solver == SolverChoice::petsc) return "--estimate runs on one process: not with solver = petsc";
  return "";
}

/// A note in `log` when BC cards hold single grid points (an edge held node by node): on the finer meshes
/// they hold those points only, the new points between them free (input/deck_refine.hpp).
inline void note_point_supports(const Deck& deck, std::ostream& log) {
  int points = 0;
  for (const BoundaryCard& b : deck.boundary) points += b.code != 0 && b.i1 == b.i2 && b.j1 == b.j2;
  if (points > 1)
    log << "error bars: " << points << " BC cards hold one grid point each; on the finer meshes they hold "
        << "those points only, not the points between them (an edge held along its length: one card)\n";
}

/// The plan of a finer mesh of the model `plan` is for: the same, or InputError.
inline Plan finer_plan(const SceneModel& refined, const Plan& plan) {
  Plan p = make_plan(refined.description, refined.scene, plan.key.kinematics);
  if (!(p.key == plan.key) || p.solver != plan.solver)
    throw InputError("the finer mesh needs another variant than the model's (" + p.variant_reason + ")");
  return p;
}

/// One run of the model (`d` on `s`, with `plan`'s choices) for the error bars, timed: into `dir` with its
/// files, `pictures` and its error estimate as `d` asks (then its RunResult into `result` when given), or
/// writing nothing when `dir` is empty, and then estimating only on quadratic cells (whose largest von Mises
/// is the estimate's: app/read_quantities.hpp). Its warnings repeat the model's own run's and are not shown.
inline LevelRun run_level(ModelDescription& d, const Scene& s, int level, const Plan& plan, PlotUnits units,
                          const std::string& dir = "", const std::vector<std::string>& pictures = {},
                          RunResult* result = nullptr) {
  const auto start         = std::chrono::steady_clock::now();
  const bool files         = !dir.empty();
  d.options.error_estimate = (files || s.is_quadratic()) && d.options.error_estimate;
  std::ostringstream quiet;
  RecoveryWeights recovery;
  recovery.several = d.steps() > 1;  // every step estimates: fit the patches once, at the first
  const RunRequest r{d, s, plan, dir, quiet, false, pictures, units, nullptr, files, true, &recovery, {}};
  RunResult run_result = app::run(r);
  LevelRun out{level, s.mesh.node_count(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
               std::move(run_result.quantities)};
  if (result) *result = std::move(run_result);
  return out;
}

/// The run of one finer mesh (`refined`, level `level`) with `plan`'s choices, reported in `log`.
inline LevelRun solve_level(SceneModel& refined, int level, const Plan& plan, PlotUnits units,
                            std::ostream& log) {
  const Plan refined_plan = finer_plan(refined, plan);
  const LevelRun finer    = run_level(refined.description, refined.scene, level, refined_plan, units);
  log << "error bars: the mesh at 1/" << (1 << level) << " of the spacing ("
      << (refined.refined.empty() ? "refined" : refined.refined) << "), " << finer.nodes
      << " nodes, solved in " << finer.seconds << " s\n";
  return finer;
}

/// The runs of the finer meshes after the run of the model's own: `first`, its mesh at 1/2 the spacing
/// (`refine(1)`, built before the model's run so that a model it refuses is refused first), and the one at
/// 1/4 (`refine(2)`) when it has at most kThirdLevelNodes nodes. A run that fails throws, naming its mesh;
/// but the one at 1/4, which only sharpens the order, is left out with a line in `log`.
inline std::vector<LevelRun> solve_finer(const Refiner& refine, SceneModel first, const Plan& plan,
                                         PlotUnits units, std::ostream& log) {
  std::vector<LevelRun> runs;
  const auto what = [](int level) {
    return "--estimate, the mesh at 1/" + std::to_string(1 << level) + " of the spacing: ";
  };
  try {
    runs.push_back(solve_level(first, 1, plan, units, log));
  } catch (const InputError& e) {  // the deck's own run is done: say which run failed
    throw InputError(what(1) + e.what());
  } catch (const SolveError& e) {
    throw SolveError(what(1) + e.what());
  } catch (const std::bad_alloc&) {
    throw SolveError(what(1) + "out of memory");
  }
  const long nodes = 4L * first.scene.grid.node_count();  // about
  if (nodes > kThirdLevelNodes) {
    log << "error bars: the mesh at 1/4 of the spacing (about " << nodes << " nodes) is past "
        << kThirdLevelNodes << ": two meshes, the order assumed\n";
    return runs;
  }
  first = {};  // its memory, before the next
  try {
    SceneModel second = refine(2);
    runs.push_back(solve_level(second, 2, plan, units, log));
  } catch (const std::bad_alloc&) {  // two meshes will do
    log << "error bars: " << what(2) << "not solved (out of memory); two meshes, the order assumed\n";
  } catch (const std::runtime_error& e) {  // InputError, SolveError, FileError: two meshes will do
    log << "error bars: " << what(2) << "not solved (" << e.what() << "); two meshes, the order assumed\n";
  }
  return runs;
}

/// Whether a model's answer depends on its load path, so that its load steps have an error of their own: a
/// law with history, friction, and the seed's saac policy (it splits an increment once, at the first closure,
/// and closes every other pair overlapping by the increment's end at its gap there). Frictionless contact
/// under active-set or augmented-lagrangian ends where its loads end, however reached.
inline bool path_dependent(const Plan& p) {
  return p.plastic || p.key.friction != FrictionChoice::none ||
         (p.gaps && p.key.contact == ContactChoice::saac);
}

/// The runs of the model's own mesh with its load steps in 2 and 4 times the pieces (ModelOptions::
/// load_pieces), for a path-dependent model: its load-step error, as the mesh's. A run that fails is left out
/// with a line in `log` (the load-step error then not measured).
inline std::vector<LevelRun> solve_finer_steps(const ModelDescription& d, const Scene& s, const Plan& plan,
                                               PlotUnits units, std::ostream& log) {
  std::vector<LevelRun> runs;
  for (int level = 1; level <= 2; ++level) {
    ModelDescription finer = d;
    finer.options.load_pieces *= 1 << level;
    try {
      runs.push_back(run_level(finer, s, level, plan, units));
    } catch (const std::runtime_error& e) {
      log << "error bars: the load steps in " << finer.options.load_pieces << " pieces not solved ("
          << e.what() << "); the load-step error not measured\n";
      return {};
    }
    log << "error bars: the load steps in " << finer.options.load_pieces << " pieces, solved in "
        << runs.back().seconds << " s\n";
  }
  return runs;
}

/// Quantity q's values on `runs` (NaN where a run lacks it) and its error bar; `first` is its own run's.
inline std::pair<std::vector<double>, ErrorBar> quantity_bar(const ReadQuantity& first,
                                                             const std::vector<LevelRun>& runs, std::size_t q,
                                                             double assumed_order) {
  std::vector<double> values{first.value};
  double scale = first.scale;
  for (const LevelRun& run : runs) {
    const bool has = q < run.quantities.size() && run.quantities[q].name == first.name;
    values.push_back(has ? run.quantities[q].value : std::nan(""));
    if (has) scale = std::max(scale, run.quantities[q].scale);
  }
  return {values, error_bar(values, assumed_order, scale)};
}

/// What quantity q's error is relative to: its value's size, and for a force (a reaction, a contact force)
/// at least the largest force among `all`'s, so that a reaction that tends to 0 (a support on the axis) is
/// small against the model's loads, not large against itself.
inline double relative_size(const std::vector<ReadQuantity>& all, std::size_t q, double value) {
  const auto force = [](const std::string& name) {
    return name.rfind("reaction ", 0) == 0 || name.rfind("contact ", 0) == 0;
  };
  double size = std::abs(value);
  if (force(all[q].name))
    for (const ReadQuantity& other : all)
      if (force(other.name)) size = std::max(size, std::abs(other.value));
  return size;
}

/// The relative error a bar stands for: its error over the largest of its limit, its value and `size`
/// (relative_size); 0 when the values agree.
inline double relative_error(const ErrorBar& bar, double size) {
  if (bar.status == ErrorBar::Status::exact) return 0;
  const double of =
      std::max({std::isfinite(bar.limit) ? std::abs(bar.limit) : 0.0, std::abs(bar.value), size});
  return of > 0 ? bar.error / of : 0.0;
}

/// A bar's status as estimates.csv gives it.
inline const char* status_word(const ErrorBar& b) {
  return b.status == ErrorBar::Status::exact      ? "exact"
         : b.status == ErrorBar::Status::observed ? "observed"
         : b.status == ErrorBar::Status::assumed  ? "assumed"
         : b.status == ErrorBar::Status::settled  ? "settled"
                                                  : "not_converging";
}

/// A bar in the log's words: "+- 0.1 (0.5%; observed order 2)", and its CSV fields error,relative,status,
/// order,limit; the relative error against `size` (relative_size) or the limit, whichever is larger; `what`
/// names the refinement ("meshes", "load steps"), `halves` what halves, and `hint` the likely cause when the
/// values do not converge.
inline void write_bar(std::ostream& log, std::ostream& csv, const ErrorBar& bar,
                      const std::vector<double>& values, double size_of, const char* what, const char* halves,
                      const char* hint) {
  if (bar.status == ErrorBar::Status::exact) {
    log << "(the " << what << " agree, to the solvers' tolerance)";
    csv << ",0,0," << status_word(bar) << ",," << bar.limit;
  } else if (bar.converges()) {
    const double relative = relative_error(bar, size_of);
    log << "+- " << bar.error << " (" << 100 * relative << "%";
    if (bar.status == ErrorBar::Status::observed && std::isfinite(bar.order))
      log << "; observed order " << bar.order;
    else if (bar.status == ErrorBar::Status::assumed)
      log << "; order " << bar.order << " assumed, two " << what;
    else if (bar.status == ErrorBar::Status::settled)
      log << "; not converging, but moving by less than a tenth of the target: the last difference";
    log << ")";
    csv << "," << bar.error << "," << relative << "," << status_word(bar) << ",";
    if (!std::isnan(bar.order)) csv << bar.order;  // settled: no order
    csv << "," << bar.limit;
  } else {
    log << "not converging (";
    for (std::size_t k = 0; k < values.size(); ++k) log << (k ? ", " : "") << values[k];
    log << " as the " << halves << " halves: " << hint << ")";
    csv << ",,," << status_word(bar) << ",,";
  }
}

/// The bar of the last of `values` instead of the first (`gapfe run --accuracy`): its distance to the same
/// limit; and values that do not converge because their differences change sign, the last below a tenth of
/// `target` x `size` (a reaction on the axis, tending to 0 and changing sign on the way), settled: the limit
/// lies between the last two values, so their difference bounds the error. (Differences of one sign that
/// shrink too slowly bound nothing.)
inline ErrorBar bar_of_last(ErrorBar b, const std::vector<double>& values, double size, double target) {
  if (b.converges()) {
    b.value = values.back(),
    b.error = b.status == ErrorBar::Status::exact ? 0.0 : std::abs(b.value - b.limit);
  } else if (values.size() >= 3) {  // changing sign: the limit lies between the last two values
    const std::size_t n = values.size();
    const double d1 = values[n - 2] - values[n - 3], d2 = values[n - 1] - values[n - 2];
    if (d1 * d2 < 0 && std::abs(d2) <= 0.1 * target * size)
      b.status = ErrorBar::Status::settled, b.value = b.limit = values.back(), b.error = std::abs(d2);
  }
  return b;
}

/// Each quantity's error bar from the runs (the model's own first, then the finer meshes), and from `steps`
/// (the model's own mesh with finer load steps; empty: not measured), in the log and in `dir`/estimates.csv.
/// `target` > 0 (`gapfe run --accuracy TOL`): the bars of the last runs' values instead (bar_of_last), `runs`
/// the last meshes, `steps` the last mesh with its load steps split.
inline void report_error_bars(std::ostream& log, const std::string& dir, const std::vector<LevelRun>& runs,
                              const std::vector<LevelRun>& steps = {}, double target = 0) {
  const bool finest                    = target > 0;
  const std::vector<ReadQuantity>& own = (finest ? runs.back() : runs.front()).quantities;
  const std::vector<LevelRun> finer(runs.begin() + 1, runs.end());
  std::ostringstream csv;
  csv << std::setprecision(17);
  csv << "quantity,value,error,relative_error,status,order,limit,r,z";
  for (const LevelRun& run : runs) csv << ",spacing_1/" << (1 << run.level);
  if (!steps.empty()) {
    csv << ",step_error,step_relative_error,step_status,step_order,step_limit";
    for (const LevelRun& run : steps) csv << ",steps_x" << (1 << run.level);
  }
  csv << "\n";
  log << "error bars (" << runs.size() << " meshes"
      << (steps.empty() ? ""
          : finest      ? ", and load steps split"
                        : ", and load steps in 1, 2 and 4 pieces")
      << (finest ? "; the error of the last run's value" : "; the error of this run's value")
      << ", from its values on the " << (finest ? "coarser" : "finer")
      << " ones; docs/accuracy.md \"Error bars\"):\n";
  for (std::size_t q = 0; q < own.size(); ++q) {
    const ReadQuantity& v = own[q];
    auto [values, bar]    = quantity_bar(runs.front().quantities[q], finer, q, v.order);
    const double shown    = finest && !steps.empty() && q < steps.back().quantities.size()
                                ? steps.back().quantities[q].value
                                : v.value;
    const double size     = relative_size(own, q, shown);
    if (finest) bar = bar_of_last(bar, values, size, target);
    log << "  " << v.name;
    if (v.located) log << " (at r = " << v.at(0) << ", z = " << v.at(1) << ")";
    log << ": " << shown << " ";
    csv << detail::csv_name(v.name) << "," << shown;
    write_bar(log, csv, bar, values, size, "meshes", "spacing",
              "a singular point such as a re-entrant corner or a point load?");
    if (v.located)
      csv << "," << v.at(0) << "," << v.at(1);
    else
      csv << ",,";
    for (const double value : values) csv << "," << value;
    if (!steps.empty()) {  // the load-step error: first order in the step for the integration of a history
      const std::vector<LevelRun> split(steps.begin() + (finest ? 1 : 0), steps.end());
      auto [step_values, step_bar] = quantity_bar(finest ? steps.front().quantities[q] : v, split, q, 1.0);
      // A force's load-step error against the forces of the run it ends on, as the ladder judged it.
      const double step_size = finest ? relative_size(steps.back().quantities, q, shown) : size;
      if (finest) step_bar = bar_of_last(step_bar, step_values, step_size, target);
      log << "; load steps: ";
      write_bar(log, csv, step_bar, step_values, step_size, "load steps", "step",
                "steps too large to show their order: more load steps, or load_pieces");
      for (std::size_t k = finest ? 0 : 1; k < step_values.size(); ++k) csv << "," << step_values[k];
    }
    log << "\n";
    csv << "\n";
  }
  OutputFile file(dir + "/estimates.csv");
  file.append(csv.str());
  file.close();
}

}  // namespace gapfe::app

#pragma once
// `gapfe run --estimate`: error bars on the quantities a user reads (app/read_quantities.hpp). The deck is
// solved again on its grid at 1/2 the spacing, and at 1/4 where that mesh is small enough (kThirdLevelNodes),
// from the same cards (input/deck_refine.hpp); each quantity's values are extrapolated
// (post/extrapolation.hpp) and its error bar is the distance of this run's value to the limit. The finer runs
// write no files: the log and estimates.csv carry what they found. docs/accuracy.md "Error bars".
#include <chrono>
#include <cmath>
#include <iomanip>
#include <new>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "gapfe/app/plan.hpp"
#include "gapfe/app/read_quantities.hpp"
#include "gapfe/app/run.hpp"
#include "gapfe/input/deck_refine.hpp"
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

/// Why `gapfe run --estimate` cannot refine this model, before any run: empty when it can.
inline std::string estimate_refused(bool scene_file, const Plan& p) {
  if (scene_file)
    return "--estimate refines card decks (their I-J grids) only so far; a scene file's mesh is not refined";
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

/// The run of one finer mesh (`refined`, level `level`) with `plan`'s choices, reported in `log`. The finer
/// runs make no error estimate of their own (their centroid stresses are the same without it).
inline LevelRun solve_level(RefinedDeck& refined, int level, const Plan& plan, PlotUnits units,
                            std::ostream& log) {
  const auto start                    = std::chrono::steady_clock::now();
  refined.deck.options.error_estimate = false;
  const Plan refined_plan             = make_plan(refined.deck, refined.scene, plan.key.kinematics);
  if (!(refined_plan.key == plan.key) || refined_plan.solver != plan.solver)
    throw InputError("the finer mesh needs another variant than the deck's (" + refined_plan.variant_reason +
                     ")");
  std::ostringstream quiet;  // the finer runs' warnings repeat the deck's own run's
  const RunRequest r{refined.deck, refined.scene, refined_plan, "",    quiet, false,
                     {},           units,         nullptr,      false, true};
  LevelRun finer{level, refined.scene.grid.node_count(), 0, app::run(r).quantities};
  finer.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  log << "error bars: the mesh at 1/" << (1 << level) << " of the spacing, " << finer.nodes
      << " nodes, solved in " << finer.seconds << " s\n";
  return finer;
}

/// The runs of the finer meshes of `deck` (whose scene is `scene`), after the run of its own mesh: `first`,
/// its mesh at 1/2 the spacing (refine_deck, built before the deck's run so that a deck it refuses is refused
/// first), and the one at 1/4 when it has at most kThirdLevelNodes nodes. A run that fails throws, naming its
/// mesh; but the one at 1/4, which only sharpens the order, is left out with a line in `log`.
inline std::vector<LevelRun> solve_finer(const Deck& deck, const Scene& scene, RefinedDeck first,
                                         const Plan& plan, PlotUnits units, std::ostream& log) {
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
    RefinedDeck second = refine_deck(deck, scene, 2);
    runs.push_back(solve_level(second, 2, plan, units, log));
  } catch (const std::bad_alloc&) {  // two meshes will do
    log << "error bars: " << what(2) << "not solved (out of memory); two meshes, the order assumed\n";
  } catch (const std::runtime_error& e) {  // InputError, SolveError, FileError: two meshes will do
    log << "error bars: " << what(2) << "not solved (" << e.what() << "); two meshes, the order assumed\n";
  }
  return runs;
}

/// Each quantity's error bar from the runs (the deck's own first), in the log and in `dir`/estimates.csv.
inline void report_error_bars(std::ostream& log, const std::string& dir, const std::vector<LevelRun>& runs) {
  const std::vector<ReadQuantity>& own = runs.front().quantities;
  std::ostringstream csv;
  csv << std::setprecision(17);
  csv << "quantity,value,error,relative_error,status,order,limit,r,z";
  for (const LevelRun& run : runs) csv << ",spacing_1/" << (1 << run.level);
  csv << "\n";
  log << "error bars (" << runs.size()
      << " meshes; the error of this run's value, from its values on the finer "
      << "meshes; docs/accuracy.md \"Error bars\"):\n";
  for (std::size_t q = 0; q < own.size(); ++q) {
    std::vector<double> values;
    for (const LevelRun& run : runs)
      values.push_back(q < run.quantities.size() && run.quantities[q].name == own[q].name
                           ? run.quantities[q].value
                           : std::nan(""));
    double scale = 0;
    for (const LevelRun& run : runs)
      if (q < run.quantities.size()) scale = std::max(scale, run.quantities[q].scale);
    const ErrorBar bar    = error_bar(values, own[q].order, scale);
    const ReadQuantity& v = own[q];
    log << "  " << v.name;
    if (v.located) log << " (at r = " << v.at(0) << ", z = " << v.at(1) << ")";
    log << ": ";
    const std::string status = bar.status == ErrorBar::Status::exact      ? "exact"
                               : bar.status == ErrorBar::Status::observed ? "observed"
                               : bar.status == ErrorBar::Status::assumed  ? "assumed"
                                                                          : "not_converging";
    if (bar.status == ErrorBar::Status::exact) {
      log << v.value << " (the meshes agree, to the solvers' tolerance)\n";
      csv << detail::csv_name(v.name) << "," << v.value << ",0,0," << status << ",," << bar.limit;
    } else if (bar.converges()) {
      const double size     = std::max(std::abs(bar.limit), std::abs(v.value));
      const double relative = size > 0 ? bar.error / size : 0.0;
      log << v.value << " +- " << bar.error << " (" << 100 * relative << "%";
      if (bar.status == ErrorBar::Status::observed && std::isfinite(bar.order))
        log << "; observed order " << bar.order;
      else if (bar.status == ErrorBar::Status::assumed)
        log << "; order " << bar.order << " assumed, two meshes";
      log << ")\n";
      csv << detail::csv_name(v.name) << "," << v.value << "," << bar.error << "," << relative << ","
          << status << "," << bar.order << "," << bar.limit;
    } else {
      log << "not converging (";
      for (std::size_t k = 0; k < values.size(); ++k) log << (k ? ", " : "") << values[k];
      log << " as the spacing halves: a singular point such as a re-entrant corner or a point load?)\n";
      csv << detail::csv_name(v.name) << "," << v.value << ",,," << status << ",,";
    }
    if (v.located)
      csv << "," << v.at(0) << "," << v.at(1);
    else
      csv << ",,";
    for (const double value : values) csv << "," << value;
    csv << "\n";
  }
  OutputFile file(dir + "/estimates.csv");
  file.append(csv.str());
  file.close();
}

}  // namespace gapfe::app

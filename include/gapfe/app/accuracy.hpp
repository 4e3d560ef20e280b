#pragma once
// `gapfe run --accuracy TOL`: the mesh halved, then (plasticity, friction) the load steps split, until
// every quantity `--estimate` reports (app/read_quantities.hpp) has an estimated relative error of at most
// TOL on the last run, whose files the folder holds; docs/accuracy.md "A target accuracy". Each rung of the
// ladder is one run: rung k of the mesh's is the model at 1/2^k of its spacing (the Refiner of
// app/error_bars.hpp), rung k of the steps' the finest mesh with every load step in 2^k pieces. A quantity's
// error on rung k is its value's distance to the limit Richardson's extrapolation gives from rungs k - 2, k -
// 1 and k (post/extrapolation.hpp); the target counts only from three rungs on, so every run from the third
// writes its files. Before each rung, its size and time are foreseen from the last ones; one past the memory
// or the time left stops the ladder with the reason, and so does a quantity that does not converge.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <new>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "gapfe/app/accuracy_order.hpp"
#include "gapfe/app/error_bars.hpp"
#include "gapfe/app/run.hpp"

namespace gapfe::app {

/// What `--accuracy` aims at and may spend.
struct AccuracyTarget {
  double tolerance = 1e-3;  ///< every quantity's estimated relative error at most this [-]
  long max_nodes   = 0;     ///< the largest mesh it may solve (0: what the memory available allows)
  double seconds   = 3600;  ///< the time the whole ladder may take [s]
};

/// The nodes a mesh may have in `bytes` of memory: about 6 KB a node with 3 DOF, 4 KB with 2
/// (BENCHMARKS.md: the 1e6-equation tube peaks at 2.1 GB, 4.2 KB a node, most of it the factor).
inline long nodes_in_memory(double bytes, int dofs_per_node) {
  return static_cast<long>(bytes / (2100.0 * std::max(2, dofs_per_node)));
}

/// The memory this process may still use [bytes]: the machine's MemAvailable (/proc/meminfo), no more than
/// what its cgroup v2 (a container, a batch job: its path in /proc/self/cgroup) has left below memory.max,
/// counting the page cache the kernel would drop (memory.stat's inactive_file) as free; 0 when neither tells
/// (cgroup v1 is not read).
inline double available_memory() {
  const auto field = [](const std::string& path, const std::string& name) {
    std::ifstream in(path);
    std::string key;
    double value = 0;
    while (in >> key >> value) {
      if (key == name) return value;
      in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    }
    return -1.0;
  };
  double available = std::max(0.0, field("/proc/meminfo", "MemAvailable:") * 1024);
  std::string group, line;
  for (std::ifstream in("/proc/self/cgroup"); std::getline(in, line);)
    if (line.rfind("0::", 0) == 0) group = line.substr(3);
  const std::string dir = "/sys/fs/cgroup" + (group == "/" ? std::string() : group);
  double limit = 0, used = 0;  // "max" does not read as a number: no limit
  if (std::ifstream in(dir + "/memory.max"); in >> limit) {
    if (std::ifstream current(dir + "/memory.current"); current >> used) {
      const double cache = std::max(0.0, field(dir + "/memory.stat", "inactive_file"));
      const double left  = std::max(0.0, limit - std::max(0.0, used - cache));
      available          = available > 0 ? std::min(available, left) : left;
    }
  }
  return available;
}

/// A rung's quantities judged: the largest relative error among them and which, or why there is none.
struct RungVerdict {
  double worst = 0;    ///< the largest estimated relative error of the last rung's values
  std::string which;   ///< its quantity
  std::string failed;  ///< a quantity that does not converge, or "" (then worst is meaningful)
  double rate = 2;     ///< the smallest order among the quantities not yet within the target
};

/// The error of the last of `rungs` (each twice as fine as the one before) for every quantity, against
/// `target`: its bar (bar_of_last) from the last three rungs (two: the order `assumed`, 0 for the quantity's
/// own), relative as the report gives it (relative_error).
inline RungVerdict judge(const std::vector<LevelRun>& rungs, double target, double assumed) {
  RungVerdict v;
  const std::size_t from = rungs.size() >= 3 ? rungs.size() - 3 : 0;
  const std::vector<LevelRun> last(rungs.begin() + static_cast<std::ptrdiff_t>(from) + 1, rungs.end());
  const std::vector<ReadQuantity>& first = rungs[from].quantities;
  v.rate                                 = std::numeric_limits<double>::infinity();
  for (std::size_t q = 0; q < first.size(); ++q) {
    const auto [values, bar] = quantity_bar(first[q], last, q, assumed > 0 ? assumed : first[q].order);
    const double size        = relative_size(rungs.back().quantities, q, values.back());
    const ErrorBar finest    = bar_of_last(bar, values, size, target);
    if (!finest.converges()) {
      v.failed = first[q].name;
      return v;
    }
    const double rel = relative_error(finest, size);
    if (!(rel <= v.worst)) v.worst = rel, v.which = first[q].name;
    if (rel > target && std::isfinite(finest.order)) v.rate = std::min(v.rate, finest.order);
  }
  if (!std::isfinite(v.rate)) v.rate = 2;
  return v;
}

/// What the rest of a mesh ladder (`rungs`, two or more, each twice as fine as the one before) is foreseen
/// to take to reach `tolerance` on three rungs or more: its worst quantity's error shrinking by 2^p a rung (p
/// the smallest order among those above the target, as judge gives them), each rung's time the last's times
/// the last two's ratio (at least 4, the nodes' growth). Infinite when a quantity does not converge.
struct Foreseen {
  int rungs      = 0;
  double seconds = 0;
};
inline Foreseen foresee(const std::vector<LevelRun>& rungs, double tolerance) {
  const RungVerdict v = judge(rungs, tolerance, 0.0);
  if (!v.failed.empty()) return {0, HUGE_VAL};
  const double halvings =
      v.worst > tolerance ? std::ceil(std::log2(v.worst / tolerance) / std::max(v.rate, 0.5)) : 0;
  Foreseen f{static_cast<int>(std::max(halvings, 3.0 - static_cast<double>(rungs.size()))), 0};
  const double ratio = std::max(4.0, rungs.back().seconds / std::max(rungs[rungs.size() - 2].seconds, 1e-9));
  for (double next = rungs.back().seconds, k = 0; k < f.rungs; ++k) next *= ratio, f.seconds += next;
  return f;
}

/// The line of the path for the last of `rungs`, and its verdict (none for the first).
inline void log_rung(std::ostream& log, const std::vector<LevelRun>& rungs, const char* what, bool files,
                     const std::optional<RungVerdict>& v) {
  log << "accuracy: " << what << " " << rungs.back().level << ": " << rungs.back().nodes << " nodes, "
      << rungs.back().seconds << " s" << (files ? ", its files written" : "");
  if (v && !v->failed.empty())
    log << "; " << v->failed << " does not converge yet";
  else if (v)
    log << "; largest estimated error " << v->worst << " (" << v->which << ")";
  log << "\n";
}

/// One ladder of `gapfe run --accuracy` (see the top): rungs made by `make(k)` from k = rungs.size() on,
/// after `rungs` (the first: a run whose files are written, `written` naming it), each run through
/// `solve(model, files)`; `growth` the factor its nodes grow by a rung (4 for the mesh, 1 for the steps),
/// `assumed` the order with two rungs (0: each quantity's own). Returns the rung the target was reached on,
/// the last, whose files are written, or `last_rung` when it gets there first; throws SolveError naming why
/// it cannot be: the next rung past `max_nodes` or the time left, a quantity that does not converge on two
/// rungs in a row, or a run that fails.
template <class Make, class Solve>
int climb(std::vector<LevelRun>& rungs, Make&& make, Solve&& solve, const AccuracyTarget& target,
          long max_nodes, double growth, double assumed, const char* what, double start_seconds,
          std::string& written, std::ostream& log, int last_rung = std::numeric_limits<int>::max()) {
  const auto now = [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  };
  const std::string aim = "--accuracy " + detail::number_text(target.tolerance) + " not reached: ";
  std::optional<RungVerdict> v;
  if (rungs.size() >= 2) v = judge(rungs, target.tolerance, assumed);
  // Rungs in a row on which a quantity did not converge, the last rung's verdict counted (a ladder resumed).
  int diverging = rungs.size() >= 3 && v && !v->failed.empty() ? 1 : 0;
  for (int k = static_cast<int>(rungs.size());; ++k) {
    // The next rung, foreseen: its nodes, and its time from the last two rungs' ratio (at least `growth`).
    const LevelRun& last = rungs.back();
    const double ratio   = rungs.size() >= 2 && rungs[rungs.size() - 2].seconds > 0
                               ? std::max(growth, last.seconds / rungs[rungs.size() - 2].seconds)
                               : std::max(2.0, growth * 1.5);
    const double nodes = static_cast<double>(last.nodes) * growth, spent = now() - start_seconds;
    std::ostringstream why;
    if (nodes > static_cast<double>(max_nodes))
      why << "the next " << what << " would have about " << static_cast<long>(nodes) << " nodes, past the "
          << max_nodes << " this machine's memory allows";
    else if (spent + last.seconds * ratio > target.seconds)
      why << "the next " << what << " would take about " << last.seconds * ratio << " s, past the time left ("
          << target.seconds - spent << " s of " << target.seconds << "; --time-limit)";
    if (!why.str().empty()) {
      const bool known = v && v->failed.empty() && v->worst > 0;
      const double needed =
          known ? std::ceil(std::log2(v->worst / target.tolerance) / std::max(v->rate, 0.5)) : 0;
      throw SolveError(
          aim + why.str() +
          (needed > 0 ? " (about " + detail::number_text(needed) + " more halvings needed)" : "") +
          "; the files are those of " + written);
    }
    // From the third rung on, a run may be the last: it writes its files (replacing the last ones).
    const bool files       = rungs.size() >= 2;
    const std::string name = std::string(what) + " " + std::to_string(k);
    bool cleared           = false;  // whether the folder was emptied for this rung's files
    const auto failed      = [&](const std::string& why) {
      return SolveError(aim + name + ": " + why + "; the files are those of " +
                             (cleared ? name + " (stopped)" : written));
    };
    try {
      SceneModel model = make(k);
      rungs.push_back(solve(model, files, cleared));
    } catch (const std::bad_alloc&) {
      throw failed("out of memory");
    } catch (const InputError& e) {  // a finer mesh refused
      throw failed(e.what());
    } catch (const SolveError& e) {  // a step not solved; file errors keep their own kind (exit 3)
      throw failed(e.what());
    }
    if (files) written = name;
    rungs.back().level = k;
    v                  = judge(rungs, target.tolerance, assumed);
    log_rung(log, rungs, what, files, v);
    if (!v->failed.empty()) {
      // Three rungs can still be short of the asymptotic range (noise between a maximum's nodes): two
      // verdicts in a row end the ladder.
      if (++diverging >= 2 && rungs.size() >= 3)
        throw SolveError(aim + v->failed + " does not converge as the " + what +
                         " is refined (a singular point, such as a re-entrant corner or a point load?); the "
                         "files are those of " +
                         written);
      if (k >= last_rung) return k;
      continue;
    }
    diverging = 0;
    if ((rungs.size() >= 3 && v->worst <= target.tolerance) || k >= last_rung) return k;
  }
}

/// The probe of the order choice (app/accuracy_order.hpp), after the mesh's first three rungs, `mesh`:
/// `order`'s quadratic model on the first two meshes, then both ladders' rest foreseen (foresee: the linear
/// one at its observed orders, the quadratic one at its assumed ones), in `log`. Returns the quadratic rungs
/// and their plan when they are foreseen to reach `tolerance` sooner; nothing when not, when the linear
/// ladder needs only a fourth rung (the probe and quad8's third mesh would cost more), when the probe would
/// pass `max_nodes` or `seconds_left` (quad8's third mesh about 12 times the linear second's nodes; the
/// probe's time about one and a half times the third linear run's at most), or when a quadratic run fails or
/// is refused (said in `log`).
inline std::optional<std::pair<std::vector<LevelRun>, Plan>> probe_quadratic(
    const OrderChoice& order, const std::vector<LevelRun>& mesh, const RunRequest& own, double tolerance,
    long max_nodes, double seconds_left, std::ostream& log) {
  const Foreseen linear = foresee(mesh, tolerance);
  if (!order.refine || mesh.size() != 3 || linear.rungs <= 1) return std::nullopt;
  if (12.0 * static_cast<double>(mesh[1].nodes) > static_cast<double>(max_nodes) ||
      1.5 * mesh[2].seconds > seconds_left) {
    log << "accuracy: quadratic cells not tried (the probe would pass the memory or the time left)\n";
    return std::nullopt;
  }
  std::vector<LevelRun> quadratic;
  Plan plan;
  try {
    for (int k = 0; k < 2; ++k) {
      SceneModel m = order.refine(k);
      if (k == 0) {
        plan = make_plan(m.description, m.scene, own.plan.key.kinematics);
        check_plan(plan, m.description, m.scene);
        check_compiled(plan);
      }
      quadratic.push_back(run_level(m.description, m.scene, k, finer_plan(m, plan), own.units));
    }
  } catch (const std::exception& e) {
    log << "accuracy: quadratic cells not tried (" << e.what() << ")\n";
    return std::nullopt;
  }
  const Foreseen raised = foresee(quadratic, tolerance);
  log << "accuracy: quad8 on meshes 0 and 1: " << quadratic[0].nodes << " and " << quadratic[1].nodes
      << " nodes, " << quadratic[0].seconds + quadratic[1].seconds
      << " s; foreseen to the target: " << raised.rungs
      << (raised.rungs == 1 ? " more mesh (" : " more meshes (") << raised.seconds << " s) against "
      << linear.rungs << " (" << linear.seconds << " s) in " << name_of(own.plan.key.element) << "; "
      << (raised.seconds < linear.seconds
              ? "raising the order: the next meshes and the files have 8-node cells"
              : "keeping the order")
      << "\n";
  if (!(raised.seconds < linear.seconds)) return std::nullopt;
  return std::pair{std::move(quadratic), plan};
}

/// What `gapfe run --accuracy` leaves: the last run's result (its files in the run's folder), and the error
/// bars reported.
struct AccuracyRun {
  RunResult result;
  std::string reached;  ///< "the mesh at 1/8 of the spacing with every load step in 4 pieces"
};

/// `gapfe run --accuracy` (see the top) after the model's own run, `own` (its files written into own.dir),
/// which took `own_seconds` and found `quantities`: the mesh's ladder through `refine`, then for a
/// path-dependent model (path_dependent: plasticity, friction) the load steps', the path in `log`, the last
/// runs' error bars in the log and in estimates.csv. `clear_folder` empties own.dir before a run that writes
/// there. SolveError when the target cannot be reached within `target`'s memory and time, a quantity does not
/// converge, or a run fails.
inline AccuracyRun reach_accuracy(const Refiner& refine, const RunRequest& own,
                                  std::vector<ReadQuantity> quantities, double own_seconds,
                                  const AccuracyTarget& target, const std::function<void()>& clear_folder,
                                  std::ostream& log, const OrderChoice& order = {}) {
  using clock          = std::chrono::steady_clock;
  const double start   = std::chrono::duration<double>(clock::now().time_since_epoch()).count() - own_seconds;
  const int dofs       = own.plan.key.kinematics == VariantChoice::saga ? 3 : 2;
  const double bytes   = available_memory();
  const long max_nodes = target.max_nodes > 0 ? target.max_nodes
                         : bytes > 0          ? nodes_in_memory(0.8 * bytes, dofs)
                                              : std::numeric_limits<long>::max();
  log << "accuracy: every quantity within " << target.tolerance << " (relative); meshes up to "
      << (bytes > 0 || target.max_nodes > 0 ? std::to_string(max_nodes) + " nodes" : std::string("any size"))
      << (target.max_nodes > 0 ? ""
          : bytes > 0          ? " (this machine's memory)"
                               : " (the memory available unknown)")
      << ", " << target.seconds << " s in all\n";
  AccuracyRun out;
  Plan plan        = own.plan;  // the ladder's: the model's, or quad8's once the order is raised
  Refiner ladder   = refine;
  const auto solve = [&](SceneModel& m, bool files, bool& cleared) {
    const Plan p = finer_plan(m, plan);
    if (files) clear_folder(), cleared = true;
    // Its warnings are in the last run's report (report_run), once.
    return run_level(m.description, m.scene, 0, p, own.units, files ? own.dir : std::string(), own.pictures,
                     files ? &out.result : nullptr);
  };
  std::vector<LevelRun> mesh{{0, own.scene.mesh.node_count(), own_seconds, std::move(quantities)}};
  log_rung(log, mesh, "mesh", true, std::nullopt);
  if (!order.kept.empty()) log << "accuracy: the cells' order stays: " << order.kept << "\n";
  std::string written = "mesh 0 (the model's own run)";
  int level           = -1;
  if (order.refine) {  // three rungs, then the order choice, unless the third reached the target
    const int k = climb(mesh, ladder, solve, target, max_nodes, 4.0, 0.0, "mesh", start, written, log, 2);
    const RungVerdict v  = judge(mesh, target.tolerance, 0.0);
    const double elapsed = std::chrono::duration<double>(clock::now().time_since_epoch()).count() - start;
    if (v.failed.empty() && v.worst <= target.tolerance)
      level = k;
    else if (!v.failed.empty())
      log << "accuracy: quadratic cells not tried (" << v.failed << " does not converge yet)\n";
    else if (auto raised = probe_quadratic(order, mesh, own, target.tolerance, max_nodes,
                                           target.seconds - elapsed, log))
      mesh = std::move(raised->first), plan = raised->second, ladder = order.refine;
  }
  if (level < 0)
    level = climb(mesh, ladder, solve, target, max_nodes, 4.0, 0.0,
                  plan.key.element == own.plan.key.element ? "mesh" : "mesh (quad8)", start, written, log);
  out.reached = "the mesh at 1/" + std::to_string(1 << level) + " of the spacing" +
                (plan.key.element == own.plan.key.element ? "" : ", quadratic cells (quad8)");
  std::vector<LevelRun> steps;
  if (path_dependent(own.plan)) {  // plasticity or friction: the load steps' error on that mesh
    const SceneModel finest = ladder(level);
    steps.push_back(mesh.back());
    steps.back().level = 0;
    const auto split   = [&](int k) {
      SceneModel m = finest;
      m.description.options.load_pieces *= 1 << k;
      return m;
    };
    const int pieces =
        climb(steps, split, solve, target, max_nodes, 1.0, 1.0, "load-step split", start, written, log);
    out.reached += " with every load step in " + std::to_string(1 << pieces) + " pieces";
  }
  const auto last_three = [](const std::vector<LevelRun>& v) {
    return std::vector<LevelRun>(v.end() - static_cast<std::ptrdiff_t>(std::min<std::size_t>(v.size(), 3)),
                                 v.end());
  };
  log << "accuracy: reached on " << out.reached << "; the files are that run's\n";
  report_error_bars(log, own.dir, last_three(mesh),
                    steps.empty() ? std::vector<LevelRun>{} : last_three(steps), target.tolerance);
  return out;
}

}  // namespace gapfe::app

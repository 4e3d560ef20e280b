// The `gapfe` command: run, mesh and info on a card deck (BRL-CR-670 Appendix A). The deck picks the
// smallest compiled model variant that represents it; --variant forces a richer one.
#include "gapfe_cli.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <spawn.h>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "gapfe/core/text.hpp"
#include "gapfe/io/deck_output.hpp"
#include "gapfe/io/field_plot.hpp"
#include "gapfe/io/input_file.hpp"
#include "gapfe/io/run_folder.hpp"
#include "gapfe/io/vtu_reader.hpp"
#ifdef GAPFE_HAS_SCENE
#include "gapfe/io/scene_file.hpp"
#endif
#include "gapfe/mesh/partition.hpp"
#include "gapfe/solver/threads.hpp"
#include "gapfe/version.hpp"

#include "cli_args.hpp"
#include "cli_run.hpp"

namespace gapfe::cli {
namespace {

/// Above this Poisson's ratio `gapfe run` warns that element = quad4 locks (issue 15).
constexpr double kLockingPoisson = 0.49;

/// Above this relative residual |K u - f| / |f| of a linear solve `gapfe run` warns of ill-conditioning
/// (issue 15). A well-posed model solves to about 1e-14 (machine epsilon times a modest condition number).
/// The example two-tube deck under the active-set penalty reaches 4e-10 at the default 100 x the adjacent
/// stiffness, 5e-6 at 1e8, 4e-4 at 1e10 and 4e-3 at 1e11; tests/test_contact.cpp's penalty sweep keeps its
/// answers to the discretization error up to 1e9 and loses them beyond, which this threshold marks.
constexpr double kResidualWarning = 1e-4;

/// Above this Balance::relative() of an accepted increment `gapfe run` warns that the run is out of global
/// equilibrium (docs/checks.md). Round-off gives 1e-16 (the thick tube) to 6e-11 (the SAAC3X tube) on the
/// examples.
constexpr double kBalanceWarning = 1e-8;

/// The largest Poisson's ratio of any material table row, and its material's deck number.
std::pair<int, double> largest_poisson(const Deck& d) {
  std::pair<int, double> worst{0, -1.0};
  for (const DeckMaterial& m : d.materials)
    for (const ElasticConstants& c : m.table.rows)
      if (const double nu = std::max({c.nu_NS, c.nu_NT, c.nu_ST}); nu > worst.second) worst = {m.id, nu};
  return worst;
}

/// Up to this many load steps the log lists a per-step figure (the relative residual, the friction cone)
/// for each step; beyond, their median and the largest with its step.
constexpr std::size_t kListedSteps = 50;

/// A friction force past this multiple of mu f_n is reported: the seed's models leave Coulomb's cone.
constexpr double kConeWarning = 1.1;

/// The warning of a run whose friction forces left Coulomb's cone |f_t| <= mu f_n (slip model `model`):
/// where it was worst, and the likely cause.
std::string cone_warning(const RunTimes::ConeWorst& w, const std::string& model) {
  std::ostringstream m;
  m << "gapfe: warning: gap element " << w.element + 1 << ", pair " << w.pair + 1 << " (nodes "
    << w.node_a + 1 << " and " << w.node_b + 1 << ") carries a friction force " << std::setprecision(3)
    << w.ratio << std::setprecision(6) << " times mu f_n at load step " << w.step << " (inc " << w.inc
    << "), outside Coulomb's cone |f_t| <= mu f_n: ";
  if (model == "proportional")
    m << "slip = proportional (SAACFR) has no slip limit, mu only scales its tangential springs, so a pair's "
         "force grows with its slide";
  else if (!(w.normal_force > 0))
    m << "the pair carries its friction force in tension (the seed's model keeps a pair's force until it "
         "opens)";
  else if (w.slipping)
    m << "the pair slips but keeps the force it gained while stuck (the seed's slip does not return a pair "
         "to "
         "the cone)";
  else if (w.outline)
    m << "the pair was stuck for the step next to a free surface or an end of the fit, where the averaged "
         "stresses of the elements around it (the seed's stick check) carry little shear, so its force grew "
         "by the stick stiffness times its slide";
  else
    m << "the pair was stuck for the step: the seed's check takes stick or slip from the stresses before the "
         "step, so a step whose slide times the stick stiffness passes mu f_n overshoots (smaller load "
         "steps)";
  m << "; slip = coulomb (with contact = active-set or augmented-lagrangian) keeps every pair on the cone\n";
  return m.str();
}

/// One number per load step, after `what`: each, up to kListedSteps steps, else their median and the
/// largest with its step.
void log_per_step(std::ostream& log, const std::string& what, const std::vector<double>& per_step) {
  if (per_step.empty()) return;
  log << what << ":";
  if (per_step.size() <= kListedSteps) {
    for (std::size_t k = 0; k < per_step.size(); ++k)
      log << (k % 10 == 0 ? "\n   " : "") << " " << per_step[k];
    log << "\n";
    return;
  }
  std::vector<double> sorted = per_step;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                   sorted.end());
  const auto worst = std::max_element(per_step.begin(), per_step.end());
  log << " " << per_step.size() << " steps, median " << sorted[sorted.size() / 2] << ", largest " << *worst
      << " (step " << (worst - per_step.begin()) + 1 << ")\n";
}

/// Above this relative residual an accepted increment of the seed's one-solve plasticity (plasticity =
/// tangent, rate-dependent or not) is warned of. Measured on thick tubes against return-mapping: the
/// SAAC3 tube of docs/checks.md at 20 and 200 steps reached 0.19 and 0.15 with bore displacements 3 and 20
/// times the converged one (0.0027 at 2000 steps: 3% off); the rate-independent tube at 0.97 of its limit
/// 0.036 in 20 steps (6.6% low) and 0.0042 in 200 (0.3% low).
constexpr double kSeedResidualWarning = 1e-2;

/// The warning of a run of the seed's one-solve plasticity whose out-of-balance passed kSeedResidualWarning;
/// whether it was given.
bool warn_seed_residual(std::ostream& err, const RunTimes& times) {
  const auto& r    = times.step_residual;
  const auto worst = std::max_element(r.begin(), r.end());
  if (worst == r.end() || !(*worst > kSeedResidualWarning)) return false;
  err << "gapfe: warning: load step " << (worst - r.begin()) + 1 << " was accepted with a relative residual "
      << *worst << " (above " << kSeedResidualWarning
      << "): plasticity = tangent (the seed's one solve per increment) does not iterate, and out-of-balances "
         "this large have put its answers off by 7% to 20 times (docs/plasticity.md); plasticity = "
         "return-mapping (the default) iterates every increment to newton_tolerance\n";
  return true;
}

/// A rate-dependent run under return-mapping: the largest estimated time error of an accepted increment in
/// the log (DrysdaleZak::time_error, docs/plasticity.md "Time steps"), and a warning when it stayed above
/// time_tolerance (a step cut to its smallest pieces, 1/1024, and still above it).
void report_time_error(std::ostream& log, std::ostream& err, const RunTimes& times, const Deck& d) {
  const double tol = d.options.time_tolerance;
  log << "time steps: largest estimated time error of an increment " << times.time_error
      << (tol > 0 ? " (time_tolerance " + detail::number_text(tol) + ")"
                  : std::string(" (time_tolerance 0: off)"))
      << "\n";
  if (tol > 0 && times.time_error > tol)
    err << "gapfe: warning: an increment kept an estimated time error " << times.time_error
        << " (above time_tolerance " << tol
        << "): load steps cut to 1/1024 did not meet it; more load steps, or a larger time_tolerance to "
           "accept it (docs/plasticity.md)\n";
}

/// The run's global balance (docs/checks.md) in the log, and the warning past its limit: kBalanceWarning, or
/// for runs that iterate (plasticity, contact) at least the residual Newton accepts, newton_tolerance times
/// NewtonOptions::stall_factor (100: a stalled increment). The seed's one-solve plasticity leaves an
/// out-of-balance by design: when its residual was warned of (`seed_warned`), that warning says it.
void report_balance(std::ostream& log, std::ostream& err, const RunTimes& times, const Deck& d, bool torque,
                    bool gaps, bool plastic, bool seed_warned) {
  log_per_step(log,
               "global balance per load step (the loads against the reactions along the axis and about it)",
               times.step_balance);
  const Balance& b = times.last_balance;
  log << "global balance at the end: axial force of the loads " << b.applied_axial << ", of the reactions "
      << b.reaction_axial;
  if (torque) {
    log << "; torque of the loads " << b.applied_torque << ", of the reactions " << b.reaction_torque;
    if (gaps) log << ", of the gap pairs (theta forces at two radii) " << b.gap_torque;
  }
  log << "\n";
  const double limit =
      plastic || gaps ? std::max(kBalanceWarning, NewtonOptions{}.stall_factor * d.options.newton_tolerance)
                      : kBalanceWarning;
  if (seed_warned || times.balance <= limit) return;
  err << "gapfe: warning: load step " << times.balance_step << " is out of global equilibrium: the applied "
      << "loads and the reactions differ by " << times.balance << " of the load (above " << limit << ")"
      << (plastic && d.options.plasticity == "tangent"
              ? ": plasticity = tangent (the seed's one solve per increment) leaves an out-of-balance; "
                "plasticity = return-mapping iterates it away\n"
              : ": the solve did not reach equilibrium (see the residual above), so its results may be "
                "inaccurate\n");
}

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// The model variant the deck needs, and why.
std::string pick_variant(const DeckNeeds& needs, const std::string& forced, std::string& why) {
  if (needs.needs_theta()) {
    why = "3 DOF per node: " + needs.theta.front() +
          (needs.theta.size() > 1 ? " (and " + std::to_string(needs.theta.size() - 1) + " more)" : "");
    if (forced == "saas")
      throw InputError("--variant saas cannot represent this deck: it needs u_theta (" + needs.theta.front() +
                       ")");
    return "saga";
  }
  why =
      "no theta loads, theta displacements, transverse shear, angular acceleration or ALPHA: 2 DOF per node";
  if (!forced.empty() && forced != "saas") {
    why += "; " + forced + " forced by --variant, with u_theta = 0 at every node (its value by symmetry)";
    return forced;
  }
  return "saas";
}

void describe(std::ostream& out, const Deck& d, const DeckScene& s) {
  const char* format = d.options.format == DeckFormat::elastic ? "elastic (SAAS/SAGA, no yield cards)"
                       : d.options.format == DeckFormat::saac3 ? "saac3 (rate card, yield cards)"
                                                               : "saac (yield cards)";
  out << "deck: " << detail::visible_text(d.title) << "\n"
      << "  format " << format << "; element " << d.options.element << "; " << d.materials.size()
      << " material(s)\n"
      << "  mesh " << d.mesh.max_i << " x " << d.mesh.max_j << " index grid: " << s.grid.node_count()
      << " nodes, " << s.mesh.cells.size() << " quadrilaterals, " << s.mesh.triangles.size() << " triangles\n"
      << "  " << d.boundary.size() << " boundary condition card(s), " << d.blocks.size()
      << " material block(s), " << d.steps() << " load step(s)";
  if (d.control.numtc != 0) out << ", temperature field";
  if (d.control.inert != 0) out << ", inertia loads";
  out << "\n";
}

/// Scene files are TOML (issue 16); anything else is read as a card deck.
bool is_scene_file(const std::string& path) {
  return std::filesystem::path(path).extension() == ".toml";
}

void describe_scene(std::ostream& out, const SceneModel& m) {
  const Deck& d      = m.deck;
  const DeckScene& s = m.scene;
  out << "scene: " << detail::visible_text(d.title) << "\n"
      << "  element " << d.options.element << "; " << d.materials.size() << " material(s)"
      << (d.rate ? "; rate card (saac3)" : "") << "\n"
      << "  mesh "
      << (m.mesh_file.empty() ? "of the I-J generator (" + std::to_string(s.grid.max_i) + " x " +
                                    std::to_string(s.grid.max_j) + ")"
                              : m.mesh_file)
      << ": " << s.grid.node_count() << " nodes, " << s.mesh.cells.size() << " quadrilaterals, "
      << s.mesh.triangles.size() << " triangles\n"
      << "  " << s.conditions.size() << " node condition(s), " << d.control.numpc << " pressure, "
      << d.control.numsc << " shear and " << d.control.numst << " transverse shear edge(s), " << d.steps()
      << " load step(s)";
  if (d.control.numtc != 0) out << ", temperature field";
  if (d.control.inert != 0) out << ", inertia loads";
  out << "\n";
}

/// PNG beside an SVG picture through rsvg-convert (Debian's librsvg2-bin) when it is installed: run directly
/// (no shell), its output discarded; false when it is not there or fails.
bool rasterize(const std::string& svg) {
  static const bool present = [] {
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/bin:/bin";
    for (std::size_t at = 0; at <= dirs.size();) {
      const std::size_t end = std::min(dirs.find(':', at), dirs.size());
      if (end > at && ::access((dirs.substr(at, end - at) + "/rsvg-convert").c_str(), X_OK) == 0) return true;
      at = end + 1;
    }
    return false;
  }();
  if (!present) return false;
  const std::string png = svg.substr(0, svg.size() - 4) + ".png";
  std::vector<std::string> words{"rsvg-convert", "--background-color=white", "-o", png, svg};
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid         = 0;
  const int spawned = posix_spawnp(&pid, "rsvg-convert", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  return spawned == 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// Unit names from "L,F,S" (the deck option `units`, or plot --units); generic names when empty.
PlotUnits plot_units(const std::string& text) {
  if (text.empty()) return {};
  const auto names = unit_names(text);
  return {names[0], names[1], names[2]};
}

/// The columns of a CSV file by name (history.csv), every row read as numbers.
std::map<std::string, std::vector<double>> read_columns(const std::string& path) {
  if (!std::filesystem::exists(path))
    throw InputError("there is no '" + path + "' (a run of more than one load step writes it)");
  std::istringstream in(read_input(path, "history"));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names{""};
  for (const char c : line) {
    if (c == ',')
      names.emplace_back();
    else
      names.back().push_back(c);
  }
  std::map<std::string, std::vector<double>> columns;
  for (int row = 2; std::getline(in, line); ++row) {
    std::size_t at = 0;
    for (const auto& name : names) {
      if (at > line.size())
        throw FileError(path + ", line " + std::to_string(row) + ": fewer values than the header's columns");
      const std::size_t end = std::min(line.find(',', at), line.size());
      char* stop            = nullptr;
      std::string word      = line.substr(at, end - at);
      word.erase(word.find_last_not_of(' ') + 1);  // a row's padding (io/output_file.hpp)
      const double v = std::strtod(word.c_str(), &stop);
      if (word.empty() || *stop != '\0')
        throw InputError(path + ", line " + std::to_string(row) + ", column " + name + ": '" + word +
                         "' is not a number");
      columns[name].push_back(v);
      at = end + 1;
    }
  }
  return columns;
}

/// curve_Y_X.svg in `dir`: history.csv's column `y` against column `x`; returns its path.
std::string draw_curve(const std::string& dir, const std::string& x, const std::string& y,
                       const std::string& title) {
  const auto columns = read_columns(dir + "/history.csv");
  for (const std::string* c : {&x, &y})
    if (!columns.count(*c)) {
      std::vector<std::string> names;
      std::string list;
      for (const auto& [name, values] : columns)
        names.push_back(name), list += (list.empty() ? "" : ", ") + name;
      throw InputError("history.csv has no column '" + *c + "'" + suggestion(*c, names) + " (it has " + list +
                       ")");
    }
  const std::string path = dir + "/curve_" + y + "_" + x + ".svg";
  write_curve_svg(path, columns.at(x), columns.at(y), x, y, title);
  return path;
}

#ifdef GAPFE_HAS_PETSC
/// The log's account of PETSc's solver: its options (PETSc's options database) or PetscSolver's defaults.
std::string petsc_solver_text(bool unsymmetric) {
  const auto option = [](const char* name, const std::string& otherwise) {
    char value[256] = {};
    PetscBool set   = PETSC_FALSE;
    PetscOptionsGetString(nullptr, nullptr, name, value, sizeof value, &set);
    return set ? std::string(value) : otherwise;
  };
  const std::string ksp = option("-ksp_type", "preonly"),
                    pc  = option("-pc_type", unsymmetric ? "lu" : "cholesky");
  std::string text      = "PETSc -ksp_type " + ksp + " -pc_type " + pc;
  if (pc == "lu" || pc == "cholesky")
    text += " -pc_factor_mat_solver_type " + option("-pc_factor_mat_solver_type", "mumps");
  return text + (unsymmetric ? " (the Coulomb slip tangent is unsymmetric)" : "");
}
#else
std::string petsc_solver_text(bool) {
  return "PETSc";
}
#endif

int execute(const Args& a, std::ostream& out, std::ostream& err, bool progress,
            const std::function<void()>& large_model, const StartMpi& start_mpi) {
  std::ostringstream null_stream;
  std::ostream& log = a.quiet ? null_stream : out;
  log << std::setprecision(3);
  auto t0 = Clock::now();
  // A deck or a scene file (issue 16) becomes the same Deck and DeckScene: one path from here on.
  SceneModel model;
  const bool scene_file = is_scene_file(a.deck);
  if (scene_file) {
#ifdef GAPFE_HAS_SCENE
    model = read_scene_file(a.deck, a.options);
#else
    throw InputError("this gapfe was built without toml++ (libtomlplusplus-dev), so it reads decks only");
#endif
  } else {
    model.deck = read_deck(read_input(a.deck, "deck"), a.options);
  }
  const Deck& d    = model.deck;
  const long steps = a.command == "run" ? std::max(1, d.steps()) : 1;
  const long grid  = scene_file ? static_cast<long>(model.scene.grid.node_count())
                                : static_cast<long>(d.mesh.max_i) * static_cast<long>(d.mesh.max_j);
  // (Not for standard input: the re-executed process would find it read already.)
  if (large_model && a.command != "info" && !is_standard_input(a.deck) && grid * steps >= kLargeModel)
    large_model();
  const double t_read = since(t0);
  t0                  = Clock::now();
  if (!scene_file) model.scene = build_scene(d);
  const DeckScene& s  = model.scene;
  const double t_mesh = since(t0);
  if (scene_file)
    describe_scene(log, model);
  else
    describe(log, d, s);

  std::string why;
  const std::string variant = pick_variant(s.needs, a.variant, why);
  log << "variant: " << variant << " (" << why << ")\n";
  if (!s.needs.gaps.empty()) {
    log << "  gaps: " << s.needs.gaps.front() << (s.needs.gaps.size() > 1 ? " and more" : "") << "; "
        << s.gaps.pairs.size() << " node pairs, " << s.gaps.soft.size()
        << " gap element(s) soft throughout (without a node pair: corners, IJDIR 0)\n"
        << "  contact: " << d.options.contact << "; friction: "
        << (d.options.friction_model() == "none"
                ? std::string("none")
                : d.options.friction_model() + ", mu = " + detail::number_text(d.options.friction))
        << (d.options.gap_direction ? "; one gap direction for all (SAAC's LGAP = " +
                                          std::to_string(d.options.gap_direction) + ")"
                                    : "")
        << "\n";
  }
  if (!s.needs.plasticity.empty())
    log << "  plasticity: " << s.needs.plasticity.front() << "\n  integration: "
        << (d.options.plasticity == "tangent"
                ? std::string(
                      "tangent (the seed's one solve per increment, for reproducing legacy results: not "
                      "iterated, the log reports its out-of-balance") +
                      (d.rate_dependent() ? "; one increment per step, time_tolerance does not apply)" : ")")
                : "return-mapping (backward Euler, Newton to newton_tolerance " +
                      detail::number_text(d.options.newton_tolerance) + " in every increment" +
                      (d.rate_dependent() && d.options.time_tolerance > 0
                           ? "; steps cut to time_tolerance " + detail::number_text(d.options.time_tolerance)
                           : std::string()) +
                      ")")
        << "\n";
  if (d.rate_dependent())
    log << "  rate: "
        << (s.needs.plasticity.empty() ? "ignored, no yield card (elastic)"
                                       : "rate-dependent " + d.options.plasticity)
        << " (Drysdale-Zak, SAAC3: card 0 has b = " << detail::number_text(d.rate->rate_b)
        << " != 0; transition rate " << detail::number_text(d.rate->rate_plastic_strain)
        << ", each load step lasts " << detail::number_text(d.rate->time_step) << ")\n";
  if (const StrainRateTest& x = s.strain_rate_test; x.active())
    log << "  saac3x: constant strain rate " << detail::number_text(x.strain_rate)
        << " over L = " << detail::number_text(x.length) << ": u_z = rate L (t - delta t) on the "
        << x.top.size() << " nodes at z = " << detail::number_text(x.top_z)
        << " from step 2 on; u_z = u_theta = 0 on the " << x.bottom.size()
        << " nodes at z = " << detail::number_text(x.bottom_z)
        << (x.shear_step != 0 ? "; theta traction " + detail::number_text(x.shear_step) + " on the " +
                                    std::to_string(x.top_edges.size()) + " top edges, ramped over step 1"
                              : std::string())
        << " (card 0's STRRATE, STRSTEP)\n";

  if (a.command == "info") return ok;
  const auto [launch_rank, launch_size] = launcher_ranks();
  const std::string run_what            = "gapfe run " + a.deck;
  if (a.command == "mesh") {
    if (launch_rank != 0) return ok;
    std::filesystem::create_directories(a.out);
    write_mesh_files(a.out, d, s);
    log << "wrote " << a.out << "/mesh.svg, mesh_nodes.csv, mesh_elements.csv, mesh.vtu\n";
    return ok;
  }
  const bool plastic = !s.needs.plasticity.empty();
  std::string solver = d.options.solver;
#ifdef GAPFE_HAS_CHOLMOD
  if (solver == "auto") solver = "cholmod";
#else
  if (solver == "auto") solver = "eigen";
  if (solver == "cholmod")
    throw InputError("solver = cholmod: this gapfe was built without CHOLMOD (SuiteSparse)");
#endif
  if (solver != "petsc") {
    if (launch_size > 1)
      throw InputError(
          "gapfe run started as " + std::to_string(launch_size) + " processes (mpirun) with solver = " +
          solver + ", which solves on one process (each would write the same files): give --solver petsc");
    if (!a.petsc_options.empty())
      throw InputError("the PETSc option " + a.petsc_options.front() +
                       " needs solver = petsc (--solver petsc)");
  }
#ifndef GAPFE_HAS_PETSC
  (void)start_mpi;
  if (solver == "petsc")
    throw InputError(
        "solver = petsc: this gapfe was built without PETSc (cmake -DGAPFE_WITH_PETSC=ON; README "
        "\"Past one machine\")");
#else
  if (solver == "petsc" && !start_mpi)
    throw InputError(
        "solver = petsc: MPI and PETSc are started by the program, and this one does not (the gapfe "
        "command does)");
#endif
  const std::string element = d.options.element != "auto" ? d.options.element
                              : plastic                   ? "quad4bbar"
                                                          : "legacy";
  // Issue 15: the fully integrated bilinear quad locks near incompressibility (its volumetric strain is
  // enforced at every Gauss point), so its displacements come out too small; said on the error stream so
  // that --quiet keeps it. B-bar (the mean dilatation, element_kernel.hpp) relieves it.
  if (element == "quad4")
    if (const auto [material, nu] = largest_poisson(d); nu > kLockingPoisson)
      err << "gapfe: warning: element = quad4 with Poisson's ratio " << nu << " (material " << material
          << "): the bilinear quad locks near incompressibility and its displacements come out too "
             "small; use element = quad4bbar or legacy\n";
  const bool unsymmetric = !s.needs.gaps.empty() && d.options.friction_model() == "coulomb";
#ifdef GAPFE_HAS_UMFPACK
  constexpr bool kHasUmfpack = true;
#else
  constexpr bool kHasUmfpack = false;
#endif
  // A partitioned run: MPI and PETSc start here (the deck is read and checked on every process, so bad input
  // fails alike everywhere before any collective call); this process keeps its part of the scene.
  std::optional<DeckPart> part;
  int rank = 0;
#ifdef GAPFE_HAS_PETSC
  if (solver == "petsc") {
    const auto [my_rank, ranks] = start_mpi(a.petsc_options);
    rank                        = my_rank;
    auto piece = mesh_part(s.mesh, partition_cells(s.mesh, ranks), ranks, rank, pair_nodes(s.gaps.pairs));
    std::vector<double> counts(3 * static_cast<std::size_t>(ranks), 0.0);  // cells, owned nodes, ghosts
    counts[static_cast<std::size_t>(3 * rank)] =
        static_cast<double>(piece.mesh.cells.size() + piece.mesh.triangles.size());
    counts[static_cast<std::size_t>(3 * rank + 1)] = piece.layout.owned_nodes;
    counts[static_cast<std::size_t>(3 * rank + 2)] = static_cast<double>(piece.layout.ghost_part.size());
    auto pairs                                     = part_pairs(piece.layout, s.gaps.pairs);
    auto domain = std::make_shared<const PetscSubdomain>(std::move(piece.layout));
    domain->sum(counts.data(), static_cast<int>(counts.size()));
    log << "partition: " << ranks
        << " rank(s), recursive coordinate bisection of the cells; cells / nodes owned / "
        << "ghost nodes per rank:";
    for (int k = 0; k < ranks; ++k)
      log << (k ? "," : "") << " " << static_cast<long long>(counts[static_cast<std::size_t>(3 * k)]) << " / "
          << static_cast<long long>(counts[static_cast<std::size_t>(3 * k + 1)]) << " / "
          << static_cast<long long>(counts[static_cast<std::size_t>(3 * k + 2)]);
    log << "\n";
    part.emplace(DeckPart{std::move(piece.mesh), std::move(pairs), std::move(domain)});
  }
#endif
  log << "solver: "
      << (solver == "petsc" ? petsc_solver_text(unsymmetric)
          : unsymmetric
              ? std::string(solver == "eigen" || !kHasUmfpack ? "Eigen SparseLU (COLAMD)" : "UMFPACK LU") +
                    " (the Coulomb slip tangent is unsymmetric)"
          : solver == "eigen" ? std::string(EigenLdlt::kName)
                              : std::string("CHOLMOD supernodal LLT (nested dissection of the mesh)"))
      << "; element " << element << "\n";
  set_solver_threads(a.threads);  // CHOLMOD's OpenMP and OpenBLAS; one thread unless asked (threads.hpp)
  log << "threads: " << a.threads << (a.threads == 1 ? " (--threads N for more)" : "") << "\n";
  RunTimes times;
  const RunRequest request{d,
                           s,
                           a.out,
                           variant,
                           element,
                           solver,
                           err,
                           progress,
                           a.plots.value_or(std::vector<std::string>{"mises"}),
                           plot_units(d.options.units),
                           part ? &*part : nullptr,
                           rank == 0};
  // Rank 0 of a launch writes the files; a run's folder holds one run (run_folder.hpp). Made ready only
  // now, after every check of the request: a run refused before it starts leaves the last run's files.
  if (launch_rank == 0) RunFolder::prepare(a.out, a.overwrite, run_what);
  const bool writes  = launch_rank == 0;  // (a structured binding cannot be captured before C++20's P1091)
  const auto stopped = [&](const std::exception& e) {  // the manifest says the files stop short, and why
    if (writes) RunFolder::record_stopped(a.out, run_what, e.what());
  };
  t0 = Clock::now();
  try {
    run_deck_request(request, times);
  } catch (const std::exception& e) {
    stopped(e);
    throw;
  }
  // setup: the Problem, DOF map, sparsity pattern, symbolic analysis and stress recovery.
  const double setup = since(t0) - times.assemble - times.factorize - times.solve - times.write;
  log << "time [s]: read " << t_read << ", mesh " << t_mesh << ", setup " << setup << ", assemble "
      << times.assemble << ", factorize " << times.factorize << ", solve " << times.solve << ", write "
      << times.write << "\n";
  // Each load step's worst relative residual: a step the solver could not hold to round-off shows where.
  log_per_step(log,
               std::string("residual per load step (") +
                   (plastic ? "Newton's |R| / (|F_int| or the loads)" : "|K u - f| / |f|") +
                   ", the largest of its increments)",
               times.step_residual);
  if (!plastic) {
    log << "equilibrium: largest relative residual |K u - f| / |f| " << times.equilibrium << " (load step "
        << times.equilibrium_step << ")\n";
    if (times.equilibrium > kResidualWarning)
      err << "gapfe: warning: load step " << times.equilibrium_step << " was solved to a relative residual "
          << times.equilibrium << " (above " << kResidualWarning
          << "): the stiffness is ill-conditioned (a large gap_penalty? a nearly incompressible material? a "
             "body held by little more than its gaps?), so its results may be inaccurate\n";
  }
  const bool seed = plastic && d.options.plasticity == "tangent";
  report_balance(log, err, times, d, variant == "saga", !s.needs.gaps.empty(), plastic,
                 seed && warn_seed_residual(err, times));
  if (plastic && s.needs.gaps.empty())
    log << "plasticity: " << d.options.plasticity << "; " << times.increments << " increments ("
        << times.cut_steps << " from cut steps), " << times.newton_iterations << " linear solves ("
        << times.factorizations << " factorizations; " << times.tangents << " tangents in "
        << times.element_passes << " element passes); worst residual " << times.worst_residual
        << ", largest drift off the yield surface " << times.drift << "; " << times.plastic_points
        << " plastic points at the end\n";
  if (plastic && d.rate_dependent() && !seed) report_time_error(log, err, times, d);
  if (plastic && s.needs.gaps.empty() && times.stalled > 0)
    err << "gapfe: warning: " << times.stalled << " increment(s) stopped where the residual stopped falling, "
        << "at most 100 x newton_tolerance (" << d.options.newton_tolerance  // NewtonOptions::stall_factor
        << "; worst " << times.worst_residual
        << "): the round-off of a nearly singular tangent (loads near a collapse load? very small "
           "hardening?); accepted\n";
  if (!s.needs.gaps.empty())
    log << "contact: " << times.increments << " increments ("
        << (d.options.events == "step-end"
                ? "statuses settled at step ends: " + std::to_string(times.contact.status_rounds) +
                      " re-solves"
                : std::to_string(times.contact.splits) + " split points" +
                      (times.contact.status_rounds > 0 ? ", " + std::to_string(times.contact.status_rounds) +
                                                             " re-solves after pulling pairs opened"
                                                       : std::string()))
        << (times.contact.cuts > 0 ? ", " + std::to_string(times.contact.cuts) + " intervals halved" : "")
        << "), " << times.contact.solves << " linear solves, " << times.contact.factorizations
        << " factorizations, " << times.contact.multiplier_updates << " multiplier updates; penalty "
        << times.penalty << " x adjacent; " << times.closed << " of " << times.pairs
        << " pairs closed at the end"
        << (d.options.friction_model() == "coulomb"
                ? "; friction: " + std::to_string(times.contact.friction_iterations) + " Newton re-solves, " +
                      std::to_string(times.contact.friction_stalls) + " stalled below 1e-4"
                : std::string())
        << "\n";
  if (d.options.friction_model() != "none") {
    log_per_step(
        log,
        "friction cone per load step (the largest |f_t| / (mu f_n) of a closed pair; at most 1 under "
        "Coulomb)",
        times.step_cone);
    if (times.cone.ratio > kConeWarning) err << cone_warning(times.cone, d.options.friction_model());
  }
  if (!times.relaxation.empty()) {
    log << "rate-dependent increments (t = inc x delta t of card 0):\n";
    for (const auto& line : times.relaxation) log << line << "\n";
  }
  const bool tables = d.options.output_csv != "none", fields = d.options.output_vtu != "none";
  log << "wrote " << a.out << "/" << (tables ? "nodes.csv, elements.csv, reactions.csv, " : "")
      << (s.needs.gaps.empty() ? "" : "gaps.csv, ")
      << (plastic && s.needs.gaps.empty() ? "plasticity.csv, " : "") << (fields ? "result.pvd, " : "")
      << "deformed.svg\n";
  std::vector<std::string> pictures = times.pictures;
  if (d.steps() > 1 && !pictures.empty()) try {  // the load-displacement curve of history.csv
      pictures.push_back(draw_curve(a.out, "u_max", "load_factor", d.title));
    } catch (const std::exception& e) {
      stopped(e);
      throw;
    }
  for (const std::string& picture : pictures)
    log << "wrote " << picture << (a.png && rasterize(picture) ? " and its .png" : "") << "\n";
  if (!times.pictures_skipped.empty()) log << "pictures not drawn: " << times.pictures_skipped << "\n";
  if (launch_rank == 0) RunFolder::record(a.out, run_what, "complete");
  return ok;
}

/// `gapfe plot DIR`: a field of one step (result.pvd's VTU files) or a curve of history.csv.
int plot(const Args& a, std::ostream& out, std::ostream& err) {
  std::ostringstream null_stream;
  std::ostream& log     = a.quiet ? null_stream : out;
  const std::string dir = a.deck;
  if (const std::string status = RunFolder::check(dir); status != "complete")
    err << "gapfe: note: the run in " << detail::visible_text(dir) << " did not complete (" << status
        << "): its files stop there\n";
  const PlotUnits units = plot_units(a.units);
  std::vector<std::string> written;
  if (!a.curve_x.empty()) {
    written.push_back(draw_curve(dir, a.curve_x, a.curve_y, std::filesystem::path(dir).filename().string()));
  } else {
    const std::string pvd = dir + "/result.pvd";
    if (!std::filesystem::exists(pvd))
      throw InputError("there is no '" + pvd + "' (a run with output_vtu = none writes no VTU files)");
    const auto datasets = read_pvd(read_input(pvd, "collection"), pvd);
    if (datasets.empty()) throw FileError(pvd + " lists no files");
    std::string file = datasets.back().second;
    if (a.step > 0) {
      char name[32];
      std::snprintf(name, sizeof name, "step_%04d.vtu", a.step);
      const auto it =
          std::find_if(datasets.begin(), datasets.end(), [&](const auto& d) { return d.second == name; });
      if (it == datasets.end()) {
        std::string steps;
        for (const auto& d : datasets)
          if (d.second.find("_split_") == std::string::npos) steps += (steps.empty() ? "" : ", ") + d.second;
        throw InputError("load step " + std::to_string(a.step) + " is not in " + pvd + " (it has " + steps +
                         ")");
      }
      file = it->second;
    }
    if (file.find('/') != std::string::npos || !RunFolder::run_file(file))
      throw FileError(pvd + " lists '" + file + "', which is not a file a run writes beside it");
    const VtuData data     = read_vtu(read_input(dir + "/" + file, "VTU file"), dir + "/" + file);
    const std::string stem = file.substr(0, file.size() - 4);
    for (const std::string& field : a.plots.value_or(std::vector<std::string>{"mises"})) {
      const std::string path = dir + "/plot_" + field + (a.step > 0 ? "_" + stem : std::string()) + ".svg";
      write_field_svg(path, data, plot_field(data, field, units),
                      std::filesystem::path(dir).filename().string() + ", " + stem, units);
      written.push_back(path);
    }
  }
  for (const std::string& path : written) {
    const bool png = !a.no_png && rasterize(path);
    log << "wrote " << path << (png ? " and its .png" : "") << "\n";
  }
  return ok;
}

}  // namespace

std::pair<int, int> launcher_ranks() {
  // OpenMPI's mpirun, MPICH's and Intel MPI's mpiexec (PMI), and Slurm's srun.
  const auto number = [](const char* name) {
    const char* value = std::getenv(name);
    return value ? std::atoi(value) : -1;
  };
  // Slurm: a step's variables (srun), not the allocation's (sbatch's SLURM_NTASKS, which a serial run inside
  // a batch script also sees).
  for (const auto& [rank, size] :
       {std::pair{"OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE"}, std::pair{"PMI_RANK", "PMI_SIZE"},
        std::pair{"SLURM_PROCID", "SLURM_STEP_NUM_TASKS"}})
    if (number(size) > 0) return {std::max(0, number(rank)), number(size)};
  return {0, 1};
}

int main(const std::vector<std::string>& args, std::ostream& out_stream, std::ostream& err_stream,
         bool progress, const std::function<void()>& large_model, const StartMpi& start_mpi) {
  // Several processes of one launch: rank 0 speaks for all (they read, check and decide alike).
  std::ostringstream unheard;
  const bool speaks = launcher_ranks().first == 0;
  std::ostream& out = speaks ? out_stream : unheard;
  std::ostream& err = speaks ? err_stream : unheard;
  progress          = progress && speaks;
  Args a;
  try {
    a = parse(args);
  } catch (const UsageError& e) {
    err << "gapfe: " << detail::visible_text(e.what()) << "\n"
        << (args.empty() ? help_text("")
                         : "(gapfe --help lists the commands, gapfe COMMAND --help the options)\n");
    return usage;
  }
  if (a.help) {
    out << help_text(a.command);
    return ok;
  }
  if (a.version) {
    out << "gapfe " << GAPFE_VERSION_STRING << "\n";
    return ok;
  }
  // Messages quote the input (names, paths, titles): shown with detail::visible_text, never raw.
  const std::string input_name = detail::visible_text(is_standard_input(a.deck) ? "standard input" : a.deck);
  const auto say               = [&](const std::string& head, const char* what) {
    err << "gapfe: " << head << detail::visible_text(what, /*lines=*/true) << "\n";
  };
  try {
    return a.command == "plot" ? plot(a, out, err) : execute(a, out, err, progress, large_model, start_mpi);
  } catch (const InputError& e) {
    say("error in " + input_name + ": ", e.what());
    return input;
  } catch (const SolveError& e) {
    say("cannot solve " + input_name + ": ", e.what());
    return solve;
  } catch (const FileError& e) {
    say("", e.what());
    return system;
  } catch (const std::bad_alloc&) {
    say("out of memory while processing " + input_name, "");
    return system;
  } catch (const std::exception& e) {
    say("", e.what());
    return system;
  }
}

}  // namespace gapfe::cli

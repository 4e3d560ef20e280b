#pragma once
// The definitions of app/command.hpp, for exactly one translation unit of a program (the gapfe::app
// target's, cmake/app.cmake): run, mesh and info on a card deck (BRL-CR-670 Appendix A) or a scene file,
// and plot on a finished run. A run is read -> plan -> explain -> check -> run -> report; each step is a
// library call a C++ user makes alike (app/plan.hpp, app/explain.hpp, app/run.hpp, app/report.hpp).
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

#include "gapfe/app/accuracy.hpp"
#include "gapfe/app/command.hpp"
#include "gapfe/app/command_line.hpp"
#include "gapfe/app/error_bars.hpp"
#include "gapfe/app/explain.hpp"
#include "gapfe/app/launch.hpp"
#include "gapfe/app/pictures.hpp"
#include "gapfe/app/plan.hpp"
#include "gapfe/app/plot_command.hpp"
#include "gapfe/app/report.hpp"
#include "gapfe/app/run.hpp"
#include "gapfe/app/run_output_impl.hpp"
#include "gapfe/app/run_solver_impl.hpp"
#include "gapfe/core/text.hpp"
#include "gapfe/input/deck.hpp"
#include "gapfe/input/deck_scene.hpp"
#include "gapfe/input/input_file.hpp"
#include "gapfe/output/mesh_files.hpp"
#include "gapfe/output/run_folder.hpp"
#include "gapfe/output/step_files.hpp"
#ifdef GAPFE_HAS_SCENE
#include "gapfe/input/scene_file.hpp"
#endif
#include "gapfe/core/workers.hpp"
#include "gapfe/solver/threads.hpp"
#include "gapfe/version.hpp"

namespace gapfe::app {

namespace command_steps {

using Clock = std::chrono::steady_clock;
inline double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Scene files are TOML (docs/scenes.md "Scene files"); anything else is read as a card deck.
inline bool is_scene_file(const std::string& path) {
  return std::filesystem::path(path).extension() == ".toml";
}

/// A scene file with the command line's --set options, read whole (its mesh too); `refine` > 0: on its mesh
/// refined that many times (--estimate's finer meshes).
inline SceneModel read_scene_model(const Args& a, int refine = 0) {
#ifdef GAPFE_HAS_SCENE
  return read_scene_file(a.deck, a.options, refine);
#else
  (void)a, (void)refine;
  throw InputError("this gapfe was built without toml++ (libtomlplusplus-dev), so it reads decks only");
#endif
}

/// Whether the plan passes the library's checks (check_plan), without throwing: what `info` may call a
/// combination this build lacks, rather than one the library refuses.
inline bool combines(const Plan& p, const ModelDescription& d, const Scene& s) {
  try {
    check_plan(p, d, s);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

/// The files a run wrote, in the log (the pictures rasterized with --png), and the load-displacement curve
/// of history.csv for a run of several steps. `parts`: a partitioned run's processes when each writes its
/// own part (output/step_files.hpp), else 0.
inline void list_files(const Args& a, const Plan& p, const ModelDescription& d, const RunResult& r,
                       std::ostream& log, int parts = 0) {
  const bool tables = d.options.output_csv != Increments::none,
             fields = d.options.output_vtu != Increments::none;
  std::vector<std::string> names;
  if (tables && parts > 0)
    names.push_back("nodes_pK.csv, elements_pK.csv, reactions_pK.csv (K = 0 to " + std::to_string(parts - 1) +
                    ", a part each)");
  else if (tables)
    names.push_back("nodes.csv, elements.csv, reactions.csv");
  if (p.gaps) names.push_back("gaps.csv");
  if (p.plastic && !p.gaps) names.push_back("plasticity.csv");
  if (a.estimate || a.accuracy > 0) names.push_back("estimates.csv");
  if (fields)
    names.push_back(parts > 0 ? "result.pvd (step_NNNN.pvtu of the pieces step_NNNN_pK.vtu)" : "result.pvd");
  if (r.pictures_skipped.rfind("deformed.svg", 0) != 0) names.push_back("deformed.svg");  // StepFiles::finish
  log << "wrote " << a.out << "/";
  for (std::size_t k = 0; k < names.size(); ++k) log << (k > 0 ? ", " : "") << names[k];
  log << "\n";
  std::vector<std::string> pictures = r.pictures;
  if (d.steps() > 1 && !pictures.empty())  // the load-displacement curve of history.csv
    pictures.push_back(draw_curve(a.out, "u_max", "load_factor", d.title));
  for (const std::string& picture : pictures)
    log << "wrote " << picture << (a.png && rasterize(picture) ? " and its .png" : "") << "\n";
  if (!r.pictures_skipped.empty()) log << "pictures not drawn: " << r.pictures_skipped << "\n";
}

/// `gapfe run`, after the plan was explained: the process checks, the partition, the run folder, the run,
/// the report and the record of the folder's run.
inline int run_command(const Args& a, const SceneModel& model, const Plan& plan, std::ostream& log,
                       std::ostream& err, const Process& process, double t_read, double t_mesh,
                       const Deck* cards) {
  const ModelDescription& d             = model.description;
  const Scene& s                        = model.scene;
  const auto [launch_rank, launch_size] = launcher_ranks();
  check_process(a, plan, launch_size, process.start_mpi);
  check_plan(plan, d, s);
  check_compiled(plan);
  // --estimate's finer meshes: a deck's from its grid cards, a scene file's read again; the first built (or
  // refused) before the run.
  const Refiner refine =
      cards ? deck_refiner(*cards, s) : [&a](int times) { return read_scene_model(a, times); };
  std::optional<SceneModel> finer;
  const bool refines = a.estimate || a.accuracy > 0;
  if (refines) {
    const std::string option = a.accuracy > 0 ? "--accuracy" : "--estimate";
    if (const std::string why = estimate_refused(plan); !why.empty()) throw InputError(option + ": " + why);
    try {
      finer = refine(1);
    } catch (const InputError& e) {
      throw InputError(option + ", the mesh at 1/2 of the spacing: " + e.what());
    }
    if (cards) note_point_supports(*cards, log);
  }
  std::optional<ScenePart> part;
  const int rank = plan.solver == SolverChoice::petsc ? partition(a, s, process.start_mpi, part, log) : 0;
  log << "solver: " << solver_text(plan) << "; element " << name_of(plan.key.element) << "\n";
  // CHOLMOD's OpenMP and OpenBLAS; one thread unless asked, and one with an OpenMP-built BLAS (threads.hpp);
  // gapfe's own loops on as many (core/workers.hpp)
  const SolverThreads threads = set_solver_threads(a.threads);
  set_worker_threads(a.threads);
  prepare_solvers();
  if (!threads.limited.empty()) err << "gapfe: warning: " << threads.limited << "\n";
  log << "threads: " << a.threads << (a.threads == 1 ? " (--threads N for more)" : "")
      << (threads.threads != a.threads ? "; OpenBLAS on " + std::to_string(threads.threads) : std::string())
      << "\n";
  RecoveryWeights recovery;
  recovery.several = d.steps() > 1;  // every step estimates: fit the patches once, at the first
  const RunRequest request{d,
                           s,
                           plan,
                           a.out,
                           err,
                           process.progress,
                           a.plots.value_or(std::vector<std::string>{"mises"}),
                           plot_units(d.options.units),
                           part ? &*part : nullptr,
                           rank == 0,
                           refines,
                           &recovery,
                           process.failing};
  // Rank 0 of a launch makes the folder ready and keeps its manifest (the ranks of a partitioned run then
  // write their parts there); a run's folder holds one run (run_folder.hpp). Made ready only now, after
  // every check of the request: a run refused before it starts leaves the last run's files.
  const std::string run_what = "gapfe run " + a.deck;
  const bool writes          = part ? rank == 0 : launch_rank == 0;  // MPI's rank, once it is known
  // Every rank of a partitioned run waits for it (and fails with it): the ranks then write their parts there.
  on_every_part(part ? part->subdomain.get() : nullptr, [&] {
    if (writes) RunFolder::prepare(a.out, a.overwrite, run_what);
  });
  // Ended from outside (another rank failed alone), the manifest says "stopped" and why, not "running".
  const EndedRecord ended(process, writes, a.out, run_what);
  const auto t0 = Clock::now();
  try {
    const RunResult result = run(request);
    // setup: the Problem, DOF map, sparsity pattern and symbolic analysis; recovery: the centroid stresses
    // and the error estimate (app/run_output.hpp).
    const double setup =
        since(t0) - result.assemble - result.factorize - result.solve - result.recovery - result.write;
    log << "time [s]: read " << t_read << ", mesh " << t_mesh << ", setup " << setup << ", assemble "
        << result.assemble << ", factorize " << result.factorize << ", solve " << result.solve
        << ", recovery " << result.recovery << ", write " << result.write << "\n";
    report_throughput(log, result, a.out, writes);
    report_run(log, err, plan, d, result);
    if (a.accuracy > 0) {
      finer.reset();  // the ladder makes its own
      // The order choice: the model on quadratic cells, a deck's from its cards, a scene file's read so.
      OrderChoice order{{}, order_kept(plan, d, s)};
      if (order.kept.empty()) {
        Args quadratic = a;
        quadratic.options.emplace_back("element", "quad8");
        order.refine = cards ? deck_quadratic_refiner(*cards)
                             : Refiner([quadratic](int times) { return read_scene_model(quadratic, times); });
      }
      const AccuracyRun last = reach_accuracy(
          refine, request, result.quantities, since(t0),
          {a.accuracy, 0, a.time_limit > 0 ? a.time_limit : AccuracyTarget{}.seconds},
          [&] { RunFolder::prepare(a.out, true, run_what); }, log, order);
      log << "the last run (" << last.reached << "), whose files these are:\n";
      report_run(log, err, plan, d, last.result);
      list_files(a, plan, d, last.result, log);
      if (writes) RunFolder::record(a.out, run_what, "complete");
      return ok;
    } else if (a.estimate) {
      std::vector<LevelRun> levels{{0, s.mesh.node_count(), since(t0), result.quantities}};
      for (LevelRun& level : solve_finer(refine, std::move(*finer), plan, request.units, log))
        levels.push_back(std::move(level));
      // A path-dependent model (plasticity, friction) has a load-step error too.
      const std::vector<LevelRun> steps =
          path_dependent(plan) ? solve_finer_steps(d, s, plan, request.units, log) : std::vector<LevelRun>{};
      report_error_bars(log, a.out, levels, steps);
    }
    list_files(
        a, plan, d, result, log,
        part && part->subdomain->parts() > 1 && !d.options.output_gathered ? part->subdomain->parts() : 0);
  } catch (const std::exception& e) {  // the manifest says the files stop short, and why
    if (writes) RunFolder::record_stopped(a.out, run_what, e.what());
    throw;
  }
  if (writes) RunFolder::record(a.out, run_what, "complete");
  return ok;
}

/// run, mesh and info: read the model, plan and explain it; info stops there, mesh writes the mesh files.
/// A deck and a scene file become the same SceneModel (a description and its scene); a deck's scene is
/// built from its grid cards after the large-model set-up, which may start the process anew.
inline int execute(const Args& a, std::ostream& out, std::ostream& err, const Process& process) {
  std::ostringstream null_stream;
  std::ostream& log = a.quiet ? null_stream : out;
  log << std::setprecision(3);
  auto t0          = Clock::now();
  const bool scene = is_scene_file(a.deck);
  std::optional<Deck> deck;
  SceneModel model;
  if (scene)
    model = read_scene_model(a);
  else
    deck = read_deck(read_input(a.deck, "deck"), a.options);
  const ModelDescription& read = scene ? model.description : *deck;
  const long steps             = a.command == "run" ? std::max(1, read.steps()) : 1;
  const long grid              = scene ? static_cast<long>(model.scene.grid.node_count())
                                       : static_cast<long>(deck->mesh.max_i) * static_cast<long>(deck->mesh.max_j);
  // (Not for standard input: the re-executed process would find it read already.)
  if (process.large_model && a.command != "info" && !is_standard_input(a.deck) && grid * steps >= kLargeModel)
    process.large_model();
  const double t_read = since(t0);
  t0                  = Clock::now();
  if (!scene) model.scene = build_scene(*deck);
  const double t_mesh = since(t0);
  std::optional<Deck> cards;  // a deck's grid cards, which --estimate refines
  if (scene) {
    describe_scene(log, model);
  } else {
    describe_deck(log, *deck, model.scene);
    if (a.estimate || a.accuracy > 0) cards = *deck;
    model.description = std::move(*deck);  // the description; the grid cards are done with
    deck.reset();
  }
  const ModelDescription& d = model.description;
  const Scene& s            = model.scene;
  const Plan plan           = make_plan(d, s, a.variant);
  explain_plan(log, plan, d, s);
  if (!GAPFE_APP_ALL_VARIANTS && !compiled(plan.key) && combines(plan, d, s))
    log << "  not compiled into this gapfe (built with -DGAPFE_VARIANTS=defaults): run refuses it; "
           "-DGAPFE_VARIANTS=all compiles it\n";
  if (a.command == "info") return ok;
  if (a.command == "mesh") {
    if (launcher_ranks().first != 0) return ok;
    std::filesystem::create_directories(a.out);
    write_mesh_files(a.out, d, s);
    log << "wrote " << a.out << "/mesh.svg, mesh_nodes.csv, mesh_elements.csv, mesh.vtu\n";
    return ok;
  }
  return run_command(a, model, plan, log, err, process, t_read, t_mesh, cards ? &*cards : nullptr);
}

}  // namespace command_steps

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

int command(const std::vector<std::string>& args, std::ostream& out_stream, std::ostream& err_stream,
            const Process& process_in) {
  // Several processes of one launch: rank 0 speaks for all (they read, check and decide alike).
  std::ostringstream unheard;
  const bool speaks = launcher_ranks().first == 0;
  std::ostream& out = speaks ? out_stream : unheard;
  std::ostream& err = speaks ? err_stream : unheard;
  Process process   = process_in;
  process.progress  = process.progress && speaks;
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
  // The message, printed where this rank speaks, and handed to the process (Process::failed) with the code.
  const auto fail = [&](Exit code, const std::string& head, const char* what) {
    const std::string line = "gapfe: " + head + detail::visible_text(what, /*lines=*/true);
    err << line << "\n";
    if (process.failed) process.failed(code, line);
    return code;
  };
  try {
    start_launch(a, process);
    return a.command == "plot" ? plot(a, out, err) : command_steps::execute(a, out, err, process);
  } catch (const InputError& e) {
    return fail(input, "error in " + input_name + ": ", e.what());
  } catch (const SolveError& e) {
    return fail(solve, "cannot solve " + input_name + ": ", e.what());
  } catch (const FileError& e) {
    return fail(system, "", e.what());
  } catch (const std::bad_alloc&) {
    return fail(system, "out of memory while processing " + input_name, "");
  } catch (const std::exception& e) {
    return fail(system, "", e.what());
  }
}

}  // namespace gapfe::app

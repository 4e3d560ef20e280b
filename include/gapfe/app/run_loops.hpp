#pragma once
// The three ways a run steps a model on one compiled variant M, with the files each writes:
//   run_linear   no gaps, linear law: LinearStatic, one factorization (run_scene);
//   run_plastic  no gaps, law with history: NonlinearStatic with step cutting, plus plasticity.csv;
//   run_contact  gap elements under contact policy P and friction model F: ContactStatic (over
//                NonlinearStatic for laws with history: SAAC = SAGAEP + gaps), plus gaps.csv.
// app/variant_table.hpp says which (M, P, F) exist.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>

#include "gapfe/app/run_output.hpp"
#include "gapfe/app/run_solver.hpp"
#include "gapfe/output/gap_file.hpp"
#include "gapfe/output/grid_arrays.hpp"
#include "gapfe/output/plasticity_file.hpp"
#include "gapfe/run/scene_run.hpp"

namespace gapfe::app {

/// A rate-dependent law's load step for the log: lambda dt of its last increment, min and max over the
/// points that yielded in it (how stiff the step was: the relaxation ODE's lambda times the increment's dt;
/// docs/plasticity.md). The pieces time_tolerance cuts a step into are not listed (a step cut in 200 would
/// fill the log). A partitioned run's `part` holds its own points only: the extremes and the count are over
/// every part.
template <class States>
void note_relaxation(RunResult& times, const ModelDescription& d, int step, double inc, const States& states,
                     const Subdomain* part) {
  if constexpr (requires { states.front().relaxation; }) {
    if (inc != std::floor(inc)) return;  // the same on every part: inc is the whole run's
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    double n = 0;
    for (const auto& s : states)
      if (s.plastic && s.relaxation > 0)
        lo = std::min(lo, s.relaxation), hi = std::max(hi, s.relaxation), ++n;
    if (part) lo = -part->max(-lo), hi = part->max(hi), part->sum(&n, 1);
    std::ostringstream line;
    line << std::setprecision(3) << "  step " << step << ", inc " << inc << " (t = " << inc * d.step_time()
         << "): ";
    if (n > 0)
      line << "lambda dt " << lo << " .. " << hi << " over " << static_cast<long long>(n)
           << " yielding point(s)";
    else
      line << "no point yielding";
    times.relaxation.push_back(line.str());
  }
}

template <class M>
void run_linear(const RunRequest& r, RunResult& times) {
  RunFiles files(r);
  FinishFiles finish{r, times, files};
  run_scene<M>(
      r.model, r.scene,
      [&](int step, double inc, const LinearStatic<M>& fe) {
        const auto& t = fe.timings();
        times.assemble += t.assemble, times.factorize += t.factorize, times.solve += t.solve + t.reactions;
        write_increment(r, times, files, step, inc, fe);
      },
      r.part, make_run_solver<typename M::LinearSolver>(r.plan.solver));
  finish.now();
}

template <class M>
void run_plastic(const RunRequest& r, RunResult& times) {
  RunFiles files(r);
  FinishFiles finish{r, times, files};
  PlasticityFile record(nullptr, r.model.step_time());  // plasticity.csv, on rank 0; opening it is agreed
  on_every_part(r.part ? r.part->subdomain.get() : nullptr, [&] {
    if (r.writes) record = PlasticityFile(&r.dir, r.model.step_time());
  });
  int last_step = 0;
  run_scene_plastic<M>(
      r.model, r.scene,
      [&](int step, double inc, const NonlinearStatic<M>& fe) {
        const auto& rep = fe.report();
        const auto& t   = fe.total_timings();  // every Newton solve so far, cut attempts included
        times.assemble = t.assemble, times.factorize = t.factorize, times.solve = t.solve + t.reactions;
        times.newton_iterations += rep.iterations;
        times.element_passes += rep.evaluations;
        times.tangents += rep.tangents;
        times.factorizations = fe.factorizations();
        times.cut_steps += step == last_step || inc != std::floor(inc);
        times.plastic_points = rep.plastic_points;
        times.drift          = std::max(times.drift, rep.drift);
        times.time_error     = std::max(times.time_error, rep.time_error);
        times.worst_residual = std::max(times.worst_residual, rep.residuals.back());
        times.stalled += rep.stalled;
        ++times.increments;
        note_relaxation(times, r.model, step, inc, fe.states(), fe.problem().subdomain.get());
        // Rank 0 writes the table; a failure there is every rank's (core/subdomain.hpp).
        on_every_part(fe.problem().subdomain.get(), [&] { record.write(step, inc, rep); });
        last_step = step;
        write_increment(r, times, files, step, inc, fe, {}, {rep.iterations, rep.plastic_points, 0, 0});
      },
      r.part, make_run_solver<typename M::LinearSolver>(r.plan.solver));
  on_every_part(r.part ? r.part->subdomain.get() : nullptr, [&] { record.close(); });  // rank 0's, agreed
  finish.now();
}

/// A run with friction: the increment's ConeExcess into its history row and the run's record (RunResult).
/// `outline`: per node of the scene, whether it lies on the mesh's outline.
inline void note_cone(RunResult& times, IncrementSummary& summary, int step, double inc,
                      const std::vector<GapPair>& pairs, const std::vector<PairState>& states, double mu,
                      const std::vector<char>& outline) {
  const ConeExcess x = cone_excess(states, mu);
  summary.cone_ratio = x.ratio;
  keep_largest(times.step_cone, step, x.ratio);
  if (!(x.ratio > times.cone.ratio)) return;
  const GapPair& g   = pairs[static_cast<std::size_t>(x.pair)];
  const PairState& s = states[static_cast<std::size_t>(x.pair)];
  times.cone         = {x.ratio,
                        inc,
                        s.normal_force,
                        step,
                        g.element,
                        g.pair,
                        g.node_a,
                        g.node_b,
                        s.slipping,
                        outline[static_cast<std::size_t>(g.node_a)] || outline[static_cast<std::size_t>(g.node_b)]};
}

template <class M, ContactPolicy P, FrictionModel F = NoFriction>
void run_contact(const RunRequest& r, RunResult& times) {
  RunFiles files(r);
  FinishFiles finish{r, times, files};
  std::optional<GapFile> gaps;
  on_every_part(r.part ? r.part->subdomain.get() : nullptr, [&] {  // gaps.csv on rank 0, agreed
    if (r.writes) gaps.emplace(r.dir, F::kFriction, r.model.step_time());
  });
  std::vector<char> outline;  // friction: the nodes on the mesh's outline, for the cone warning's cause
  if constexpr (F::kFriction) {
    outline.assign(static_cast<std::size_t>(r.scene.grid.node_count()), 0);
    for (const auto& side : detail::outline_edges(r.scene.grid, {}))
      for (const int n : side) outline[static_cast<std::size_t>(n)] = 1;
  }
  int solves_before = 0;  // the contact counters' solves at the last increment
  run_scene_contact<M, P, F>(
      r.model, r.scene, r.model.options.gap_penalty,
      [&](int step, double inc, const ContactStatic<M, P, F>& c) {
        // Every solve of the increment (Newton, Uzawa, split points), not only its last.
        const auto& t  = c.fe().total_timings();
        times.assemble = t.assemble, times.factorize = t.factorize, times.solve = t.solve + t.reactions;
        times.contact = c.counters(), ++times.increments, times.penalty = c.penalty_factor();
        times.pairs = static_cast<int>(c.pairs().size()), times.closed = 0;
        IncrementSummary summary{c.counters().solves - solves_before, 0, 0, 0};
        solves_before = c.counters().solves;
        for (const auto& st : c.states())
          times.closed += st.closed, summary.slipping += st.closed && st.slipping;
        summary.closed = times.closed;
        if constexpr (F::kFriction)
          note_cone(times, summary, step, inc, r.scene.gaps.pairs, c.states(), r.model.options.friction,
                    outline);
        if constexpr (!M::Material::kLinear) {
          note_relaxation(times, r.model, step, inc, c.fe().states(), c.fe().problem().subdomain.get());
          summary.plastic_points = c.fe().report().plastic_points;
          times.time_error       = std::max(times.time_error, c.fe().report().time_error);
        }
        // The pairs in the whole mesh's numbering (a part's are renumbered; their states are every part's).
        // Rank 0 writes the table; a failure there is every rank's (core/subdomain.hpp).
        on_every_part(c.fe().problem().subdomain.get(), [&] {
          if (gaps) gaps->write(step, inc, r.scene.gaps.pairs, c.states());
        });
        std::vector<VtuField> pair_fields;
        if (files) pair_fields = gap_fields(r.scene, r.scene.gaps.pairs, c.states());
        write_increment(r, times, files, step, inc, c.fe(), std::move(pair_fields), summary);
        if (r.read_quantities) add_contact_quantities(times.quantities, c.states(), F::kFriction);
      },
      r.part, make_run_solver<typename M::LinearSolver>(r.plan.solver));
  on_every_part(r.part ? r.part->subdomain.get() : nullptr, [&] {  // rank 0's, agreed
    if (gaps) gaps->close();
  });
  finish.now();
}

}  // namespace gapfe::app

#pragma once
// The run layer, above the drivers, input and output: a model's scene (input/scene.hpp) becomes a Problem
// of one compile-time model, and its load steps become a driver's steps. Each step applies the totals of the
// increments so far. Three runs: linear (the seed's elastic codes: materials and temperatures are fixed
// from the first step on, so the stiffness is factorized once and each later step costs an assembly of
// the right-hand side and two triangular solves), plastic (Newton with history, step cutting) and
// contact (a policy's stepping). Time in the StepContext is the load factor: 0 at the start, k at the
// end of load step k.
//
// A partitioned run (core/subdomain.hpp) gives each run a ScenePart: the process's part of the scene. Every
// process builds the whole Problem from the scene and keeps its part (assembly/problem_part.hpp); each step's
// totals, in the whole mesh's numbering, go to the part the same way. The drivers do the rest.
#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>

#include "gapfe/assembly/problem_part.hpp"
#include "gapfe/driver/contact_static.hpp"
#include "gapfe/driver/linear_static.hpp"
#include "gapfe/driver/nonlinear_static.hpp"
#include "gapfe/input/scene.hpp"
#include "gapfe/material/hill.hpp"
#include "gapfe/run/step_loads.hpp"

namespace gapfe {

/// A deck that needs no u_theta (ModelNeeds), run in a 3-DOF variant: u_theta = 0 at every node, its exact
/// value by symmetry, so that the free rotation about the axis does not make the stiffness singular.
/// Every card's code gains the u_theta bit (their XT are zero, or the deck would need u_theta), and
/// nodes without a card get one that prescribes only u_theta = 0.
inline void fix_theta(std::vector<NodalCondition>& conditions, int nodes) {
  for (auto& c : conditions) c.code |= 4;
  std::vector<NodalCondition> all;
  all.reserve(static_cast<std::size_t>(nodes) + conditions.size());
  for (int n = 0; n < nodes; ++n) all.push_back({n, 4, {}});
  all.insert(all.end(), conditions.begin(), conditions.end());
  conditions = std::move(all);
}

/// Put load totals into `p` (and, in a 3-DOF variant of a deck that needs no u_theta, the u_theta = 0
/// conditions).
template <class M>
void set_loads(Problem<M>& p, StepTotals t, const Scene& s) {
  if constexpr (M::kDofsPerNode == 3)
    if (!s.needs.needs_theta()) fix_theta(t.conditions, s.mesh.node_count());
  p.inertia          = t.inertia;
  p.thermal_fraction = t.thermal_fraction;
  if (p.subdomain) {  // a part: the whole problem's totals, each part keeps its own (collective)
    set_part_loads(p, s.mesh.nodes, t.conditions, t.edge_loads);
    return;
  }
  p.conditions = std::move(t.conditions);
  p.edge_loads = std::move(t.edge_loads);
}

/// This process's part of a deck's scene in a partitioned run: its cells and nodes (mesh_part of the
/// scene's mesh, keeping the gap pairs' ends), the gap pairs in its numbering, and the subdomain made from
/// the part's layout (PetscSubdomain over MPI).
struct ScenePart {
  Mesh<4> mesh;
  std::vector<GapPair> pairs;
  std::shared_ptr<const Subdomain> subdomain;
};

/// Put the loads in force after `step` into `p`: the totals of the increments so far.
template <class M>
void set_step_loads(Problem<M>& p, const ModelDescription& d, const Scene& s, int step) {
  set_loads(p, step_totals(d, s, step), s);
}

/// A deck material as law `Law`: the elastic table, and for Hill the yield card (blank or absent: elastic).
/// For the Drysdale-Zak law also card 0's b and transition rate.
template <class Law>
Law deck_law(const Orthotropic& elastic, const std::optional<YieldCard>& card,
             const std::optional<RateCard>& rate = {}) {
  if constexpr (requires(Law l) { l.yield; }) {
    Law law{};
    law.elastic = elastic;
    if (card && !card->blank) {
      const auto& y = card->yield;
      law.yield     = {y[0], y[1], y[2], y[3], y[4], y[5], card->hardening, PragerShear::legacy};
    }
    if constexpr (requires(Law l) { l.rate; })
      if (rate) law.rate = {rate->rate_b, rate->rate_plastic_strain};
    return law;
  } else {
    Law law;
    law.table = elastic.table;
    return law;
  }
}

/// The Problem of a scene under the loads in force after `step`; with `part`, the part of it (collective).
template <class M>
Problem<M> scene_problem(const ModelDescription& d, const Scene& s, int step,
                         const ScenePart* part = nullptr) {
  static_assert(M::Element::kNodes == 4 || M::Element::kNodes == 8,
                "scenes make 4-corner cells (LegacyQuad, Quad4) or quadratic ones (Quad8)");
  Problem<M> p;
  if constexpr (M::Element::kNodes == 8) {
    if (!s.is_quadratic())
      throw InputError("an 8-node element on a scene without middle nodes: read it with element = quad8");
    p.mesh = s.quadratic;
  } else {
    if (s.is_quadratic())
      throw InputError("a 4-corner element on a scene of quadratic cells: run it with element = quad8");
    p.mesh = s.mesh;
  }
  for (std::size_t k = 0; k < s.materials.size(); ++k)
    p.materials.push_back(deck_law<typename M::Material>(s.materials[k], d.materials[k].yield, d.rate));
  set_step_loads(p, d, s, step);
  p.temperature           = s.temperature;
  p.reference_temperature = s.reference_temperature;
  if (!part) return p;
  if constexpr (M::Element::kNodes == 8) {
    throw InputError("element = quad8 runs on one process: not partitioned");
  } else {
    Connectivity<2> links;
    for (const GapPair& g : s.gaps.pairs) links.push_back({g.node_a, g.node_b});
    return problem_part(p, part->mesh, part->subdomain, links);
  }
}

/// Run every load step; `on_step(step, inc, const LinearStatic<M>&)` sees each solved step (inc = the
/// load increments applied so far; whole numbers in a linear run, which never splits a step). The last
/// step's driver has released its factorization and stiffness (LinearStatic::release_solver): what it
/// offers on_step then is the solution, the recovery and the estimate, not stiffness() or another solve.
template <class M, class OnStep>
void run_scene(const ModelDescription& d, const Scene& s, OnStep&& on_step, const ScenePart* part = nullptr,
               std::unique_ptr<typename M::LinearSolver> solver = nullptr) {
  LinearStatic<M> fe(scene_problem<M>(d, s, 1, part), {}, std::move(solver));
  StepLoads loads(d, s);
  for (int step = 1; step <= d.steps(); ++step) {
    if (step > 1) set_loads(fe.problem(), loads.at(step), s);
    fe.solve(/*same_stiffness=*/step > 1);
    // The last step's recovery and files need no factorization.
    if (step == d.steps()) fe.release_solver();
    on_step(step, static_cast<double>(step), static_cast<const LinearStatic<M>&>(fe));
  }
}

/// Whether law L's load steps are cut by their time error: it estimates one (a rate-dependent law,
/// DrysdaleZak::time_error) and its scheme iterates (return-mapping; the seed's scheme keeps its steps).
template <class L>
constexpr bool time_controlled() {
  if constexpr (L::kLinear)
    return false;
  else
    return L::kIterate && requires(const typename L::Local& p, const typename L::State& s) {
      L::time_error(p, s, s, 1.0);
    };
}

/// Run every load step of a deck with yield cards (law with history, NonlinearStatic). A step whose
/// Newton iterations fail is rejected and cut in halves, down to 1/64 of a step (kSmallestTimePiece under
/// the time control below; the load factor
/// interpolates the totals as in run_scene_contact); then a SolveError that names the step and the last
/// accepted load factor goes to the caller (whose files then hold every accepted increment). A rate-
/// dependent law under an iterating scheme is cut in halves too while an increment's estimated time error
/// (StepReport::time_error) exceeds the deck's time_tolerance, down to kSmallestTimePiece of a step (then
/// accepted: the report says how far); a piece grows back by doubling once its error is below half the
/// tolerance (the estimate is first order in the piece), and the next step starts from the last piece.
/// `on_increment(step, inc, const NonlinearStatic<M>&)` sees every accepted increment.
template <class M, class OnIncrement>
void run_scene_plastic(const ModelDescription& d, const Scene& s, OnIncrement&& on_increment,
                       const ScenePart* part                            = nullptr,
                       std::unique_ptr<typename M::LinearSolver> solver = nullptr) {
  NewtonOptions newton;
  newton.tolerance      = d.options.newton_tolerance;
  newton.max_iterations = d.options.newton_iterations;
  NonlinearStatic<M> fe(scene_problem<M>(d, s, 1, part), {}, newton, std::move(solver));
  StepLoads loads(d, s);
  const bool time_control = time_controlled<typename M::Material>() && d.options.time_tolerance > 0;
  const double smallest   = time_control ? kSmallestTimePiece : 1.0 / 64;  // Newton's cuts end here
  const double largest    = 1.0 / d.options.load_pieces;                   // ModelOptions::load_pieces
  double size = largest;  // the next piece of a step; under the time control kept from step to step
  for (int step = 1; step <= d.steps(); ++step) {
    const StepTotals before = loads.at(step - 1), after = loads.at(step);
    double done = 0;
    if (!time_control) size = largest;
    while (done < 1 - 1e-12) {
      const double to = 1 - (done + size) < 1e-12 ? 1.0 : done + size, piece = to - done;  // as below
      set_loads(fe.problem(), interpolate(before, after, to), s);
      fe.context() = {(step - 1 + to) * d.step_time(), piece * d.step_time()};
      try {
        fe.solve();
      } catch (const SolveError& e) {
        fe.reject();
        if (piece <= smallest) {
          std::ostringstream m;
          m << "load step " << step << " fails even when cut to 1/" << std::lround(1 / smallest)
            << ", past load factor " << step - 1 + done << " (the last accepted increment): " << e.what();
          // After accepted increments a singular tangent is rarely a missing constraint: a perfectly
          // plastic part loaded beyond its limit load has no equilibrium (docs/theory.md V6's tube: p_L).
          if (step > 1 || done > 0)
            m << ". Past accepted increments this usually means the loads exceed the limit (collapse) load "
                 "of "
                 "a part without hardening, or a residual tolerance below the round-off of the tangent";
          throw SolveError(m.str());
        }
        size = piece / 2;
        continue;
      }
      const double time_error = fe.report().time_error;
      if (time_control && time_error > d.options.time_tolerance && piece > 1.5 * kSmallestTimePiece) {
        fe.reject();
        size = std::max(piece / 2, kSmallestTimePiece);
        continue;
      }
      fe.commit();
      done = to;
      on_increment(step, step - 1 + done, static_cast<const NonlinearStatic<M>&>(fe));
      if (!time_control || time_error < d.options.time_tolerance / 2)
        size = std::min(largest, 2 * size);  // grow again after a cut
    }
  }
}

/// Run every load step of a deck with gap elements under contact policy P and friction model F (mu from
/// the deck's `friction` option). The load factor t runs from 0 to the number of steps; within step k it
/// moves the totals linearly from those of step k - 1 to those of step k, in `load_pieces` equal advances
/// (ModelOptions; each split further where the policy finds a status change).
/// `on_increment(step, inc, const ContactStatic<M, P, F>&)` sees every accepted increment, inc = t
/// (fractional where a step was split).
template <class M, ContactPolicy P, FrictionModel F = NoFriction, class OnIncrement>
void run_scene_contact(const ModelDescription& d, const Scene& s, double penalty_factor,
                       OnIncrement&& on_increment, const ScenePart* part = nullptr,
                       std::unique_ptr<typename M::LinearSolver> solver = nullptr) {
  using Run = ContactStatic<M, P, F>;
  ContactOptions options;
  options.penalty_factor  = penalty_factor;
  options.locate_events   = d.options.events == EventChoice::locate;
  options.step_time       = d.step_time();
  options.friction        = F::kFriction ? d.options.friction : 0.0;
  const bool time_control = time_controlled<typename M::Material>() && d.options.time_tolerance > 0;
  if (time_control) options.time_tolerance = d.options.time_tolerance;
  if (s.gap_material >= 0) options.gap_materials.push_back(s.gap_material);
  Run fe(scene_problem<M>(d, s, 1, part), part ? part->pairs : s.gaps.pairs, options, std::move(solver));
  StepLoads loads(d, s);
  StepTotals before, after;
  int cached                           = -1;  // the step whose end totals are in `after`
  const typename Run::LoadsAt loads_at = [&](Problem<M>& p, double t) {
    const int step = std::clamp(static_cast<int>(std::ceil(t - 1e-12)), 1, d.steps());
    if (step != cached) before = loads.at(step - 1), after = loads.at(step), cached = step;
    set_loads(p, interpolate(before, after, t - (step - 1)), s);
  };
  int step                               = 1;
  double piece_error                     = 0;  // the largest time error of the accepted increments of a piece
  const typename Run::OnIncrement report = [&](double t, const Run& c) {
    if constexpr (!M::Material::kLinear) piece_error = std::max(piece_error, c.fe().report().time_error);
    on_increment(step, t, c);
  };
  // A rate-dependent law under an iterating scheme advances in pieces of a step sized by the time error,
  // as run_scene_plastic: an increment past the tolerance throws TimeErrorExceeded out of the policy where
  // it would be accepted (those accepted before stay: each met it), and the rest of the piece is repeated
  // in halves. A policy's one split (saac) and the extended model's stick/slip decision then happen per
  // piece.
  const double largest = 1.0 / d.options.load_pieces;  // ModelOptions::load_pieces: at most this a piece
  double piece         = largest;
  for (; step <= d.steps(); ++step) {
    for (double done = 0; done < 1 - 1e-12;) {
      double to = std::min(1.0, done + (time_control ? piece : largest));
      if (1 - to < 1e-12) to = 1.0;  // N pieces of 1/N add up to 1 - 1e-16: end the step on its load factor
      piece_error = 0;
      try {
        fe.advance(step - 1 + to, loads_at, report);
      } catch (const TimeErrorExceeded&) {
        fe.restart();
        done  = fe.load_factor() - (step - 1);
        piece = std::max(std::min(piece, to - done) / 2, kSmallestTimePiece);
        continue;
      }
      done = to;
      if (piece_error < d.options.time_tolerance / 2) piece = std::min(largest, 2 * piece);
    }
  }
}

}  // namespace gapfe

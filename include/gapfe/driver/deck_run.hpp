#pragma once
// A deck's load steps on one compile-time model: the linear run of the seed's elastic codes. Each
// step applies the totals of the increments so far (deck_scene.hpp). Materials and temperatures are
// fixed from the first step on, so the stiffness is factorized once and each later step costs an
// assembly of the right-hand side and two triangular solves.
#include <string>

#include "gapfe/driver/linear_static.hpp"
#include "gapfe/io/deck_scene.hpp"

namespace gapfe {

/// A deck that needs no u_theta (DeckNeeds), run in a 3-DOF variant: u_theta = 0 at every node, its exact
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

/// Put the loads in force after `step` into `p`: the totals of the increments so far (and, in a 3-DOF
/// variant of a deck that needs no u_theta, the u_theta = 0 conditions).
template <class M>
void set_step_loads(Problem<M>& p, const Deck& d, const DeckScene& s, int step) {
  StepTotals t = step_totals(d, s, step);
  p.conditions = std::move(t.conditions);
  if constexpr (M::kDofsPerNode == 3)
    if (!s.needs.needs_theta()) fix_theta(p.conditions, s.mesh.node_count());
  p.inertia    = t.inertia;
  p.edge_loads = std::move(t.edge_loads);
}

/// The Problem of a scene under the loads in force after `step`.
template <class M>
Problem<M> deck_problem(const Deck& d, const DeckScene& s, int step) {
  static_assert(M::Element::kNodes == 4, "I-J decks make 4-corner cells (LegacyQuad or Quad4)");
  Problem<M> p;
  p.mesh = s.mesh;
  for (const auto& law : s.materials) {
    typename M::Material m;
    m.table = law.table;
    p.materials.push_back(m);
  }
  set_step_loads(p, d, s, step);
  p.temperature           = s.temperature;
  p.reference_temperature = s.reference_temperature;
  return p;
}

/// Run every load step; `on_step(step, inc, const LinearStatic<M>&)` sees each solved step (inc = the
/// load increments applied so far; whole numbers in a linear run, which never splits a step).
template <class M, class OnStep>
void run_deck(const Deck& d, const DeckScene& s, OnStep&& on_step) {
  LinearStatic<M> fe(deck_problem<M>(d, s, 1));
  for (int step = 1; step <= d.steps(); ++step) {
    if (step > 1) set_step_loads(fe.problem(), d, s, step);
    fe.solve(/*same_stiffness=*/step > 1);
    on_step(step, static_cast<double>(step), static_cast<const LinearStatic<M>&>(fe));
  }
}

}  // namespace gapfe

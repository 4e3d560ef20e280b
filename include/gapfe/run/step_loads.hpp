#pragma once
// The loads in force after each load step of a scene (input/scene.hpp): the totals of the step
// increments so far, and the loads between two steps (a split step's). docs/decks.md gives the
// readings: each step adds its BC values, inertia increments and surface load increments to the totals of
// the steps before; a block given once (INCI = 0, INCF = 0) repeats every step; angular velocities add, so
// the centrifugal load goes with the square of their sum; the temperature field is a load of the first
// step (ramped with it, then held); a scene file's load histories (LoadProgram::amplitudes) scale their
// loads.
//
// The sums over a deck's load blocks (one per step when INCI or INCF is not 0) are kept as the steps
// advance, so a run's load work is linear in its step count (re-summing blocks 1..k at step k was
// quadratic: 1e5 steps took minutes before the first solve of the last ones).
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>
#include <vector>

#include "gapfe/input/scene.hpp"

namespace gapfe {

/// Loads in force after a load step (totals of the increments so far).
struct StepTotals {
  std::vector<NodalCondition> conditions;
  InertiaLoad inertia;
  std::vector<EdgeLoad> edge_loads;
  double thermal_fraction = 0;  ///< Problem::thermal_fraction: the part of the temperature change in force
};

/// Loads a fraction `f` of the way from totals `a` to totals `b`: every load linear in f. Angular
/// velocities enter squared (centrifugal load), so omega^2 is what is interpolated. `a` and `b` are two
/// steps of one deck, so their conditions list the same nodes with the same codes.
inline StepTotals interpolate(const StepTotals& a, const StepTotals& b, double f) {
  StepTotals t = b;
  for (std::size_t k = 0; k < t.conditions.size(); ++k)
    for (int c = 0; c < 3; ++c)
      t.conditions[k].value[c] =
          a.conditions[k].value[c] + f * (b.conditions[k].value[c] - a.conditions[k].value[c]);
  const auto lerp    = [f](double x, double y) { return x + f * (y - x); };
  t.thermal_fraction = lerp(a.thermal_fraction, b.thermal_fraction);
  const double wa = a.inertia.angular_velocity, wb = b.inertia.angular_velocity;
  t.inertia.axial_acceleration   = lerp(a.inertia.axial_acceleration, b.inertia.axial_acceleration);
  t.inertia.angular_acceleration = lerp(a.inertia.angular_acceleration, b.inertia.angular_acceleration);
  t.inertia.angular_velocity =
      std::copysign(std::sqrt(std::max(lerp(wa * wa, wb * wb), 0.0)), wb != 0 ? wb : wa);
  std::map<std::pair<int, int>, EdgeLoad> edges;
  for (const auto& l : b.edge_loads) edges[{l.node_m, l.node_n}] = l;
  for (auto& [key, l] : edges) l.pressure *= f, l.shear *= f, l.transverse_shear *= f;
  for (const auto& l : a.edge_loads) {
    EdgeLoad& e = edges[{l.node_m, l.node_n}];
    e.node_m = l.node_m, e.node_n = l.node_n;
    e.pressure += (1 - f) * l.pressure, e.shear += (1 - f) * l.shear,
        e.transverse_shear += (1 - f) * l.transverse_shear;
  }
  t.edge_loads.clear();
  for (const auto& [key, l] : edges) t.edge_loads.push_back(l);
  return t;
}

/// The loads in force after each step of one deck and its scene (both outlive it). Asked for steps in
/// increasing order (as the drivers ask: step - 1, then step), each answer costs the cards of one block
/// and the loaded edges, whatever the step; asked for an earlier step, it sums again from the first block.
class StepLoads {
 public:
  StepLoads(const ModelDescription& d, const Scene& s) : d_(d), s_(s) {}

  /// Loads in force after step `step` (1-based; 0: none).
  StepTotals at(int step) {
    const LoadProgram& d = d_.program;
    // A block that repeats (INCI = 0, INCF = 0) adds its increment every step: its total is `step` times it.
    const double inertia_scale = d.inertia_repeats ? step : 1, surface_scale = d.surface_repeats ? step : 1;
    sum_blocks(d.inertia_repeats ? std::min(step, 1) : step, d.surface_repeats ? std::min(step, 1) : step);
    StepTotals t;
    // The temperature field: a deck applies it in the first load step (ramped over it like that step's
    // loads, so that a split of the step splits it too) and holds it; a scene may give it a history.
    t.thermal_fraction = factor(d.temperature_amplitude, step, step < 1 ? 0.0 : 1.0);
    t.conditions       = s_.conditions;
    for (std::size_t k = 0; k < t.conditions.size(); ++k) {
      const double f = factor(s_.condition_amplitude.empty() ? -1 : s_.condition_amplitude[k], step, step);
      for (double& v : t.conditions[k].value) v *= f;
    }
    const int inertia_amplitude    = d.inertia && d.inertia_repeats ? d.blocks[0].inertia_amplitude : -1;
    const double f                 = factor(inertia_amplitude, step, inertia_scale);
    t.inertia.axial_acceleration   = f * inertia_.axial_acceleration;
    t.inertia.angular_velocity     = f * inertia_.angular_velocity;
    t.inertia.angular_acceleration = f * inertia_.angular_acceleration;
    std::map<std::pair<int, int>, EdgeLoad> edges;
    for (const auto& [key, sum] : edges_) {
      const auto [m, n, amplitude] = key;
      const double g               = factor(amplitude, step, surface_scale);
      EdgeLoad& l                  = edges[{m, n}];
      l.node_m = m, l.node_n = n;
      l.pressure += g * sum[0], l.shear += g * sum[1], l.transverse_shear += g * sum[2];
    }
    add_strain_rate_test(t, edges, step);
    for (const auto& [key, load] : edges) t.edge_loads.push_back(load);
    return t;
  }

 private:
  /// A load's factor at `step`: its history's value where a scene gave one (amplitude >= 0), else `scale`.
  double factor(int amplitude, int step, double scale) const {
    return amplitude < 0 ? scale : d_.program.amplitudes[static_cast<std::size_t>(amplitude)].at(step);
  }

  /// Bring the sums to blocks 1..inertia_blocks and 1..surface_blocks (again from block 1 if fewer).
  void sum_blocks(int inertia_blocks, int surface_blocks) {
    if (inertia_blocks < inertia_summed_) inertia_ = {}, inertia_summed_ = 0;
    for (; inertia_summed_ < inertia_blocks; ++inertia_summed_) {
      const InertiaLoad in = d_.inertia(inertia_summed_ + 1);
      inertia_.axial_acceleration += in.axial_acceleration;
      inertia_.angular_velocity += in.angular_velocity;
      inertia_.angular_acceleration += in.angular_acceleration;
    }
    if (surface_blocks < surface_summed_) edges_.clear(), surface_summed_ = 0;
    for (; surface_summed_ < surface_blocks; ++surface_summed_) {
      const LoadBlock& b = d_.surface(surface_summed_ + 1);
      for (int kind = 0; kind < 3; ++kind)
        for (const EdgeCard& c : kind == 0 ? b.pressure : kind == 1 ? b.shear : b.transverse_shear)
          edges_[{c.node_m - 1, c.node_n - 1, c.amplitude}][static_cast<std::size_t>(kind)] += c.value;
    }
  }

  /// SAAC3X's strain-rate test (StrainRateTest): the faces' conditions come last, so they win
  /// (dof_map.hpp); they keep the deck's own components of the node's last card and add u_z (and u_theta
  /// at the bottom); the top face's theta traction from step 1 on.
  void add_strain_rate_test(StepTotals& t, std::map<std::pair<int, int>, EdgeLoad>& edges, int step) const {
    const StrainRateTest& x = s_.strain_rate_test;
    if (!x.active()) return;
    std::map<int, NodalCondition> last;
    for (const auto& c : t.conditions) last[c.node] = c;
    const auto drive = [&](int n, int code, double u_z) {
      const auto it    = last.find(n);
      NodalCondition c = it != last.end() ? it->second : NodalCondition{n, 0, {}};
      c.code |= code, c.sets |= code;  // a middle node's condition sets only what it holds
      c.value[dof::z] = u_z;
      if (code & 4) c.value[dof::theta] = 0;
      t.conditions.push_back(c);
    };
    for (const int n : x.bottom) drive(n, 2 | 4, 0.0);
    for (const int n : x.top) drive(n, 2, x.top_displacement(step));
    if (x.shear_step != 0 && step >= 1)
      for (const auto& [m, n] : x.top_edges) {
        EdgeLoad& l = edges[{m, n}];
        l.node_m = m, l.node_n = n;
        l.transverse_shear += x.shear_step;
      }
  }

  const ModelDescription& d_;
  const Scene& s_;
  int inertia_summed_ = 0, surface_summed_ = 0;  ///< blocks 1..these are in the sums
  InertiaLoad inertia_;                          ///< the inertia blocks' sum
  /// The surface blocks' cards summed by edge (M, N, 0-based) and load history (-1: none), by kind
  /// (pressure, shear, transverse shear), before any factor.
  std::map<std::tuple<int, int, int>, std::array<double, 3>> edges_;
};

/// Loads in force after step `step` (one question; a run asks a StepLoads, which keeps its sums).
inline StepTotals step_totals(const ModelDescription& d, const Scene& s, int step) {
  return StepLoads(d, s).at(step);
}

}  // namespace gapfe

// The plasticity speed/accuracy trade on the thick tube (docs/theory.md V6): a = 0.1, b = 0.2 m, Mises
// sigma_y = 400 MPa, E = 200 GPa, nu = 0.49, plane strain, Quad4BBar, 40 graded cells (the mesh of
// tests/test_plasticity.cpp).
//   BM_Limit<Integration>/steps: bore displacement ramped to 20 x the first-yield value in `steps` steps;
//     counter limit_error = |p - p_L| / p_L with p from the bore reactions and p_L = (2/sqrt 3) sy ln(b/a).
//   BM_Partial<Integration>/steps: bore pressure ramped to p(rho = 0.15) = 288.3 MPa in `steps` steps;
//     counter u_error = bore displacement error against ReturnMapping at 1000 steps on the same mesh (the
//     integration error alone; the mesh error is common to all rows).
//   BM_StepCost/<kind>: one load step of a bigger tube (400 x 8 cells, 7,218 equations): an elastic
//     LinearStatic solve, and one plastic step (half the wall yielding) with each integration.
// bench/plastic_tradeoff.py runs it and makes the table and plot of BENCHMARKS.md.
#include <cmath>

#include <benchmark/benchmark.h>

#include "gapfe/gapfe.hpp"

namespace {
using namespace gapfe;

constexpr double kA = 0.1, kB = 0.2, kSy = 400, kE = 200e3, kNu = 0.49, kHeight = 0.005;

template <class M>
Problem<M> tube(int nr, int nz, double ratio) {
  Problem<M> p;
  p.mesh      = rectangle_mesh<4>(kA, kB, 0, kHeight * nz, nr, nz, ratio);
  p.materials = {{Orthotropic::constant(ElasticConstants::isotropic(kE, kNu)), HillYield::mises(kSy)}};
  for (int n = 0; n < p.mesh.node_count(); ++n) p.conditions.push_back({n, 2, {}});
  return p;
}
template <class M>
void set_pressure(Problem<M>& p, int nr, int nz, double pressure) {
  p.edge_loads.clear();
  for (int j = 0; j < nz; ++j) {
    const auto& c = p.mesh.cells[static_cast<std::size_t>(j) * nr];
    p.edge_loads.push_back({c[3], c[0], pressure, 0, 0});
  }
}
template <class M>
void set_bore_displacement(Problem<M>& p, double u) {
  p.conditions.clear();
  for (int n = 0; n < p.mesh.node_count(); ++n) {
    const bool bore = std::abs(p.mesh.nodes[n](0) - kA) < 1e-12;
    p.conditions.push_back({n, bore ? 3 : 2, {bore ? u : 0.0, 0, 0}});
  }
}
double limit_pressure() {
  return 2 / std::sqrt(3.0) * kSy * std::log(kB / kA);
}
double partial_pressure(double rho) {  // sigma_z = (sigma_r + sigma_theta) / 2 (Hill 1950)
  return 2 / std::sqrt(3.0) * kSy * (std::log(rho / kA) + (kB * kB - rho * rho) / (2 * kB * kB));
}

template <class Integration>
using TubeModel = Model<Axisym2, Quad4BBar, Hill<Integration>>;

template <class Integration>
double bore_displacement_at_partial(int steps) {
  using M = TubeModel<Integration>;
  NonlinearStatic<M> fe(tube<M>(40, 1, 1.03));
  for (int s = 1; s <= steps; ++s) {
    set_pressure(fe.problem(), 40, 1, partial_pressure(0.15) * s / steps);
    fe.solve();
    fe.commit();
  }
  return fe.solution().displacement(0, 0);
}

template <class Integration>
void BM_Limit(benchmark::State& state) {
  using M         = TubeModel<Integration>;
  const int steps = static_cast<int>(state.range(0));
  const double u = 20 * 1.5 * kSy / std::sqrt(3.0) / kE * kA;  // 20 x about the first-yield bore displacement
  double pressure = 0;
  int solves      = 0;
  for (auto _ : state) {
    Problem<M> p = tube<M>(40, 1, 1.03);
    set_bore_displacement(p, 0);
    NonlinearStatic<M> fe(std::move(p));
    solves = 0;
    try {
      for (int s = 1; s <= steps; ++s) {
        set_bore_displacement(fe.problem(), u * s / steps);
        fe.solve();
        fe.commit();
        solves += fe.report().iterations;
      }
    } catch (const SolveError& e) {
      state.SkipWithError(e.what());
      return;
    }
    double force = 0;
    for (int n = 0; n < fe.problem().mesh.node_count(); ++n)
      if (std::abs(fe.problem().mesh.nodes[n](0) - kA) < 1e-12) force += fe.solution().reaction(n, 0);
    pressure = force / (kTwoPi * kA * kHeight);
  }
  state.counters["limit_error"] = std::abs(pressure - limit_pressure()) / limit_pressure();
  state.counters["solves"]      = solves;
}

template <class Integration>
void BM_Partial(benchmark::State& state) {
  static const double reference = bore_displacement_at_partial<ReturnMapping>(1000);
  const int steps               = static_cast<int>(state.range(0));
  double u                      = 0;
  try {
    for (auto _ : state) u = bore_displacement_at_partial<Integration>(steps);
  } catch (const SolveError& e) {
    state.SkipWithError(e.what());
    return;
  }
  state.counters["u_error"] = std::abs(u - reference) / std::abs(reference);
}

constexpr int kBigR = 400, kBigZ = 8;

void BM_StepCost_Elastic(benchmark::State& state) {
  using M = Model<Axisym2, Quad4BBar, Orthotropic>;
  Problem<M> p;
  p.mesh      = rectangle_mesh<4>(kA, kB, 0, kHeight * kBigZ, kBigR, kBigZ);
  p.materials = {Orthotropic::constant(ElasticConstants::isotropic(kE, kNu))};
  for (int n = 0; n < p.mesh.node_count(); ++n) p.conditions.push_back({n, 2, {}});
  set_pressure(p, kBigR, kBigZ, 100);
  LinearStatic<M> fe(std::move(p));
  for (auto _ : state) benchmark::DoNotOptimize(fe.solve().residual);
  state.counters["equations"] = fe.dofs().free_count;
}

template <class Integration>
void BM_StepCost_Plastic(benchmark::State& state) {
  using M      = TubeModel<Integration>;
  Problem<M> p = tube<M>(kBigR, kBigZ, 1.0);
  NonlinearStatic<M> fe(std::move(p));
  // Committed state: yielded to rho = 0.14; the timed step goes on to rho = 0.15 (every point near the
  // front plastic-loads, the rest unloads or stays elastic).
  for (int s = 1; s <= 10; ++s) {
    set_pressure(fe.problem(), kBigR, kBigZ, partial_pressure(0.14) * s / 10);
    fe.solve();
    fe.commit();
  }
  set_pressure(fe.problem(), kBigR, kBigZ, partial_pressure(0.15));
  int solves = 0;
  for (auto _ : state) {
    fe.solve();
    solves = fe.report().iterations;
  }
  state.counters["solves"]    = solves;
  state.counters["equations"] = fe.dofs().free_count;
}

}  // namespace

namespace {
void step_counts(benchmark::internal::Benchmark* b) {
  for (const int steps : {5, 10, 20, 50, 100, 200}) b->Arg(steps);
  b->Unit(benchmark::kMillisecond);
}
}  // namespace

BENCHMARK(BM_Limit<gapfe::Tangent>)->Apply(step_counts);
BENCHMARK(BM_Limit<gapfe::ReturnMapping>)->Apply(step_counts);
BENCHMARK(BM_Partial<gapfe::Tangent>)->Apply(step_counts);
BENCHMARK(BM_Partial<gapfe::ReturnMapping>)->Apply(step_counts);
BENCHMARK(BM_StepCost_Elastic)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepCost_Plastic<gapfe::Tangent>)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepCost_Plastic<gapfe::ReturnMapping>)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();

// The rate-dependent plasticity trade (Drysdale-Zak, SAAC3; material/drysdale_zak.hpp, docs/theory.md 8):
// sigma_0 = 400 MPa, b = 0.05, rate_0 = 1e-3 / s, E = 200 GPa, nu = 0.3, Quad4BBar, time real.
//   BM_ConstantRate<Integration>/k: a solid bar (one cell, r < 1 mm, 1 mm long) pulled at 1 / s from rest to
//     a strain of 4e-3, dt = 10^(k - 3) relaxation times (1 / lambda at the steady rate, docs/theory.md 8.2);
//     counter stress_error = the largest |sigma - sigma_ref(t)| / sigma_ss over the steps, sigma_ref from the
//     1-D ODE sigma' = E (rate - phi(sigma / sigma_0)) by RK4 at 1e-9 s (converged to 1e-9).
//   BM_Saac3x<Integration>/k: docs/theory.md 8.7, the thin-walled tube (0.999..1 m) with tau_0 = sigma_0 /
//     sqrt 3 held by traction, then u_z = rate L t at 1 / s for 5 ms; the same counter against the ODE
//     sigma' = E (rate - phi(sigma_bar) sigma / sigma_bar) (the FE wall's shear varies by 0.1% across it).
//   BM_StepCost/<kind>: one load step of a thick tube (a = 0.1, b = 0.2 m, 400 x 8 cells, 7,218
//     equations, bore pressure): an elastic LinearStatic solve, and a rate-dependent step with half the
//     wall yielding, with each integration.
// bench/rate_tradeoff.py runs it and makes the table and plot of BENCHMARKS.md.
#include <algorithm>
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "gapfe/gapfe.hpp"

namespace {
using namespace gapfe;

constexpr double kE = 200e3, kNu = 0.3, kSigma0 = 400, kB = 0.05, kRate0 = 1e-3, kRate = 1.0;
const double kShear = kE / (2 * (1 + kNu));

double plastic_rate_at(double s) {  // phi: the rate at stress ratio s (seed Eq. 17 inverted)
  return s <= 1 ? 0.0 : kRate0 * std::expm1((s - 1) / kB);
}
double relaxation_time(double r) {  // 1 / lambda, Mises (docs/theory.md 8.2)
  return kB * kSigma0 / (3 * kShear * (kRate0 + r));
}
template <class Integration>
DrysdaleZak<Integration> law() {
  return {
      Orthotropic::constant(ElasticConstants::isotropic(kE, kNu)), HillYield::mises(kSigma0), {kB, kRate0}};
}

/// sigma(t) of sigma' = E (rate - phi(sigma_bar) sigma / sigma_bar), sigma_bar = sqrt(sigma^2 + 3 tau^2), by
/// RK4 at h, sampled at the times `at` (ascending).
std::vector<double> reference(double tau, const std::vector<double>& at, double h = 1e-9) {
  const auto f = [&](double s) {
    const double bar = std::hypot(s, std::sqrt(3.0) * tau);
    return kE * (kRate - (bar > 0 ? plastic_rate_at(bar / kSigma0) * s / bar : 0.0));
  };
  std::vector<double> out;
  double s = 0, t = 0;
  for (const double target : at) {
    while (t < target - 1e-15) {
      const double step = std::min(h, target - t);
      const double k1 = f(s), k2 = f(s + 0.5 * step * k1), k3 = f(s + 0.5 * step * k2), k4 = f(s + step * k3);
      s += step / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      t += step;
    }
    out.push_back(s);
  }
  return out;
}

double mean_axial_stress(const std::vector<PointValues>& v) {
  double s = 0;
  for (const auto& p : v) s += p.stress(voigt::zz);
  return s / static_cast<double>(v.size());
}

/// One cell driven along z at kRate, with the theta traction tau on its top (0: a bar); sigma_zz per step.
template <class Kin, class Integration>
std::vector<double> pull(double r0, double r1, double tau, double dt, double duration,
                         std::vector<double>& times) {
  using M        = Model<Kin, Quad4BBar, DrysdaleZak<Integration>>;
  const double L = 1e-3;
  Problem<M> p;
  p.mesh         = rectangle_mesh<4>(r0, r1, 0, L, 1, 1);
  p.materials    = {law<Integration>()};
  const auto set = [&](Problem<M>& q, double uz) {
    q.conditions.clear();
    for (int n = 0; n < q.mesh.node_count(); ++n) {
      const bool top = std::abs(q.mesh.nodes[n](1) - L) < 1e-12;
      q.conditions.push_back({n, Kin::kDofsPerNode == 3 ? (top ? 2 : 6) : 2, {0, top ? uz : 0.0, 0}});
    }
    if (tau != 0) q.edge_loads = {{q.mesh.cells[0][2], q.mesh.cells[0][3], 0, 0, tau}};
  };
  set(p, 0);
  NonlinearStatic<M> fe(p);
  if (tau != 0) {  // the shear step, at the static yield: elastic
    fe.context() = {1e-3, 1e-3};
    fe.solve();
    fe.commit();
  }
  const int steps = std::max(1, static_cast<int>(std::lround(duration / dt)));
  std::vector<double> out;
  times.clear();
  for (int i = 1; i <= steps; ++i) {
    const double t = duration * i / steps;
    set(fe.problem(), kRate * L * t);
    fe.context() = {t, duration / steps};
    fe.solve();
    fe.commit();
    out.push_back(mean_axial_stress(fe.point_values()));
    times.push_back(t);
  }
  return out;
}

template <class Kin, class Integration>
void run_case(benchmark::State& state, double r0, double r1, double tau) {
  // The steady state and its relaxation time: phi(sigma_bar) sigma / sigma_bar = rate, by bisection.
  double lo = 0, hi = 3 * kSigma0;
  const auto excess = [&](double s) {
    const double bar = std::hypot(s, std::sqrt(3.0) * tau);
    return plastic_rate_at(bar / kSigma0) * s / bar - kRate;
  };
  for (int i = 0; i < 200; ++i) (excess(0.5 * (lo + hi)) > 0 ? hi : lo) = 0.5 * (lo + hi);
  const double steady = 0.5 * (lo + hi), bar = std::hypot(steady, std::sqrt(3.0) * tau);
  const double lambda_dt = std::pow(10.0, static_cast<double>(state.range(0)) - 3);
  const double dt        = lambda_dt * relaxation_time(plastic_rate_at(bar / kSigma0));
  const double duration  = tau != 0 ? 5e-3 : 4e-3;
  std::vector<double> times, sigma;
  for (auto _ : state) sigma = pull<Kin, Integration>(r0, r1, tau, dt, duration, times);
  const auto exact = reference(tau, times);
  double worst     = 0;
  for (std::size_t i = 0; i < sigma.size(); ++i)
    worst = std::max(worst, std::abs(sigma[i] - exact[i]) / steady);
  state.counters["lambda_dt"]    = lambda_dt;
  state.counters["steps"]        = static_cast<double>(sigma.size());
  state.counters["stress_error"] = worst;
  state.counters["end_error"]    = std::abs(sigma.back() - steady) / steady;
}

template <class Integration>
void BM_ConstantRate(benchmark::State& state) {
  run_case<Axisym2, Integration>(state, 0.0, 1e-3, 0.0);
}
template <class Integration>
void BM_Saac3x(benchmark::State& state) {
  run_case<Axisym3, Integration>(state, 0.999, 1.0, kSigma0 / std::sqrt(3.0));
}

// One step of a bigger tube: elastic solve against a rate-dependent step with half the wall yielding.
constexpr double kA = 0.1, kTubeB = 0.2;
template <class M>
Problem<M> tube(const typename M::Material& material) {
  Problem<M> p;
  p.mesh      = rectangle_mesh<4>(kA, kTubeB, 0, 0.04, 400, 8, 1.0);
  p.materials = {material};
  for (int n = 0; n < p.mesh.node_count(); ++n) p.conditions.push_back({n, 2, {}});
  for (int j = 0; j < 8; ++j) {
    const auto& c = p.mesh.cells[static_cast<std::size_t>(j) * 400];
    p.edge_loads.push_back({c[3], c[0], 0.0, 0, 0});
  }
  return p;
}
template <class M>
void set_pressure(Problem<M>& p, double pressure) {
  for (auto& l : p.edge_loads) l.pressure = pressure;
}

void BM_StepCost_Elastic(benchmark::State& state) {
  using M = Model<Axisym2, Quad4BBar, Orthotropic>;
  LinearStatic<M> fe(tube<M>(Orthotropic::constant(ElasticConstants::isotropic(kE, kNu))));
  set_pressure(fe.problem(), 250);
  for (auto _ : state) benchmark::DoNotOptimize(fe.solve().displacement.data());
}
template <class Integration>
void BM_StepCost_Rate(benchmark::State& state) {
  using M = Model<Axisym2, Quad4BBar, DrysdaleZak<Integration>>;
  NonlinearStatic<M> fe(tube<M>(law<Integration>()));
  // Loaded to half-wall yielding in 20 steps of 1 ms, then the timed step (not committed: each repetition
  // is the same step from the same state).
  for (int k = 1; k <= 20; ++k) {
    set_pressure(fe.problem(), 14.0 * k);
    fe.context() = {1e-3 * k, 1e-3};
    fe.solve();
    fe.commit();
  }
  set_pressure(fe.problem(), 14.0 * 21);
  fe.context() = {0.021, 1e-3};
  for (auto _ : state) {
    fe.solve();
    fe.reject();
  }
  state.counters["solves"]         = fe.report().iterations;
  state.counters["plastic_points"] = fe.report().plastic_points;
}

}  // namespace

BENCHMARK_TEMPLATE(BM_ConstantRate, gapfe::ReturnMapping)->DenseRange(0, 5)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_ConstantRate, gapfe::Tangent)->DenseRange(0, 5)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_Saac3x, gapfe::ReturnMapping)->DenseRange(0, 5)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_Saac3x, gapfe::Tangent)->DenseRange(0, 5)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepCost_Elastic)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_StepCost_Rate, gapfe::ReturnMapping)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_StepCost_Rate, gapfe::Tangent)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();

// The Coulomb slip step: the unsymmetric consistent tangent against the tangent without the slip
// coupling (what a symmetric solver can take), on the press fit of tests/press_fit.hpp (the ring pushed
// at its top along a shaft held at its bottom, nu = 0.3 so that slip changes the normal forces; 12 x 40
// shaft and 16 x 40 ring cells, Quad4, active-set). Pressed in one step (untimed), then pushed 10 um in
// 8 steps, every pair slipping from the second on: the time per push step, and counters solves_per_step
// (the linear solves of the pair Newton, with the first) and slipping pairs at the end.
//   BM_SlipStep/0: unsymmetric tangent, EigenLu.   BM_SlipStep/1: without the coupling, EigenLu.
//   BM_SlipStep/2: without the coupling, EigenLdlt (lower triangle, LDL^T).
//   BM_SlipStep/3: unsymmetric tangent, UMFPACK (when SuiteSparse is found).
#include <benchmark/benchmark.h>

#include "gapfe/solver/eigen_lu.hpp"
#ifdef GAPFE_HAS_UMFPACK
#include "gapfe/solver/umfpack.hpp"
#endif

#include "press_fit.hpp"

namespace {
using namespace gapfe;

template <class Solver>
void slip_steps(benchmark::State& state, bool symmetric) {
  using M = Model<Axisym2, Quad4, Isotropic, Solver>;
  test::PressFit fit;
  fit.drive   = test::PressFit::Drive::ends;
  fit.nu      = 0.3;
  fit.n_shaft = 12, fit.n_ring = 16, fit.nz = 40;
  double solves = 0, steps = 0, slipping = 0;
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<GapPair> pairs;
    auto problem = fit.problem<M>(pairs);
    ContactOptions opt;
    opt.gap_materials     = {1};
    opt.friction          = fit.mu;
    opt.symmetric_tangent = symmetric;
    ContactStatic<M, ActiveSet, Coulomb> cs(std::move(problem), pairs, opt);
    const auto loads = [&](Problem<M>& p, double t) {
      fit.set(p, std::min(t, 1.0), t <= 1 ? 0 : -1.25e-6 * (t - 1));
    };
    cs.advance(1.0, loads);
    cs.reset_counters();
    state.ResumeTiming();
    for (int k = 1; k <= 8; ++k) cs.advance(1.0 + k, loads);
    state.PauseTiming();
    solves += cs.counters().solves, steps += 8;
    slipping = 0;
    for (const auto& s : cs.states()) slipping += s.slipping;
    state.ResumeTiming();
  }
  state.counters["solves_per_step"] = solves / steps;
  state.counters["slipping_pairs"]  = slipping;
  state.counters["s_per_step"] =
      benchmark::Counter(steps, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_SlipStep(benchmark::State& state) {
  switch (state.range(0)) {
    case 0:
      slip_steps<EigenLu>(state, false);
      break;
    case 1:
      slip_steps<EigenLu>(state, true);
      break;
    case 2:
      slip_steps<EigenLdlt>(state, true);
      break;
#ifdef GAPFE_HAS_UMFPACK
    case 3:
      slip_steps<UmfpackLu>(state, false);
      break;
#endif
    default:
      state.SkipWithError("no such solver in this build");
  }
}
BENCHMARK(BM_SlipStep)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->Iterations(5);

}  // namespace

BENCHMARK_MAIN();

// Google Benchmark: element stiffness per variant, assembly into the fixed pattern, the error estimate, and a
// whole linear solve (assembly + factorization + solve) of the thick tube, embedded and CHOLMOD solvers.
//   build/bench/bench_kernels --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "gapfe/gapfe.hpp"
#ifdef GAPFE_HAS_CHOLMOD
#include "gapfe/solver/cholmod.hpp"
#endif

using namespace gapfe;

namespace {

template <class Kin, class Elem>
void BM_ElementStiffness(benchmark::State& state) {
  using K = ElementKernel<Kin, Elem>;
  // A general (fully populated, plasticity-like) material matrix: helical orthotropic.
  ElasticConstants c;
  c.E_N = 140e9, c.E_S = 10e9, c.E_T = 9e9, c.nu_NS = 0.3, c.nu_NT = 0.28, c.nu_ST = 0.4;
  c.G_NS = 5e9, c.G_ST = 3.5e9, c.G_TN = 4.5e9;
  const typename K::StrainMatrix d =
      K::restrict(Orthotropic::constant(c).localize({0.3, 0.5}, 0, 0).stiffness);
  const auto quads = rectangle_mesh<Elem::kNodes>(0.1, 0.2, 0, 0.1, 32, 32);
  std::vector<typename K::Coords> xs;
  for (const auto& cell : quads.cells) {
    typename K::Coords x;
    for (int a = 0; a < Elem::kNodes; ++a) x.row(a) = quads.nodes[cell[a]].transpose();
    xs.push_back(x);
  }
  std::size_t i = 0;
  for (auto _ : state) {
    typename K::Matrix k = K::stiffness(xs[i], d);
    benchmark::DoNotOptimize(k.data());
    i = (i + 1) % xs.size();
  }
  state.SetItemsProcessed(state.iterations());
}

/// The vectorized Quad4 2-DOF kernel (what the assembler uses): 8 elements per call, a general material
/// block per Gauss point (plasticity-ready layout), coordinates streamed from a 1024-element mesh.
void BM_ElementStiffnessBatch(benchmark::State& state) {
  using K = ElementKernel<Axisym2, Quad4>;
  ElasticConstants c;
  c.E_N = 140e9, c.E_S = 10e9, c.E_T = 9e9, c.nu_NS = 0.3, c.nu_NT = 0.28, c.nu_ST = 0.4;
  c.G_NS = 5e9, c.G_ST = 3.5e9, c.G_TN = 4.5e9;
  const K::StrainMatrix d = K::restrict(Orthotropic::constant(c).localize({0.3, 0.5}, 0, 0).stiffness);
  const auto mesh         = rectangle_mesh<4>(0.1, 0.2, 0, 0.1, 32, 32);
  Quad4Axisym2Batch<8> batch;
  for (int l = 0; l < 8; ++l) batch.set_material(l, d);
  std::size_t e = 0;
  double sink   = 0;
  for (auto _ : state) {
    for (int l = 0; l < 8; ++l, e = (e + 1) % mesh.cells.size())
      for (int a = 0; a < 4; ++a)
        batch.r[a][l] = mesh.nodes[mesh.cells[e][a]](0), batch.z[a][l] = mesh.nodes[mesh.cells[e][a]](1);
    batch.compute();
    benchmark::DoNotOptimize(batch.k);
    sink += batch.k[0][0];
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * 8);
}

template <class M>
Problem<M> tube(int nr, int nz) {
  constexpr int NPC = M::Element::kNodes;
  const double a = 0.1, b = 0.2, L = nz * (b - a) / nr;
  Problem<M> p;
  p.mesh      = rectangle_mesh<NPC>(a, b, 0, L, nr, nz);
  p.materials = {Isotropic::constant(200e9, 0.3)};
  for (int j = 0; j < nz; ++j) {
    const auto& c = p.mesh.cells[static_cast<std::size_t>(j) * nr];
    p.edge_loads.push_back({c[3], c[0], 100e6, 0, 0});
  }
  for (int n = 0; n < p.mesh.node_count(); ++n)
    if (p.mesh.nodes[n](1) == 0 || p.mesh.nodes[n](1) == L) p.conditions.push_back({n, 6, {}});
  return p;
}

template <class M>
void BM_Assembly(benchmark::State& state) {
  const int nr = static_cast<int>(state.range(0)), nz = nr / 2;
  LinearStatic<M> fe(tube<M>(nr, nz));
  for (auto _ : state) {
    fe.assemble_system();
    benchmark::DoNotOptimize(fe.stiffness().valuePtr());
  }
  state.SetItemsProcessed(state.iterations() * nr * nz);
  state.counters["dofs"] = fe.dofs().free_count;
}

template <class M>
void BM_LinearSolve(benchmark::State& state) {
  const int nr = static_cast<int>(state.range(0)), nz = nr / 2;
  LinearStatic<M> fe(tube<M>(nr, nz));
  for (auto _ : state) benchmark::DoNotOptimize(fe.solve().displacement.data());
  state.counters["dofs"] = fe.dofs().free_count;
}

/// The recovery error estimate of a solved tube (post/error_estimate.hpp) with the centroid stresses from the
/// same pass, as a run makes it per increment: Arg 0 fits the patches afresh each time (a run's first
/// increment, a single solve), Arg 1 reuses the kept fit (post/recovery_weights.hpp; a run's later ones).
template <class M>
void BM_ErrorEstimate(benchmark::State& state) {
  LinearStatic<M> fe(tube<M>(316, 158));
  fe.solve();
  RecoveryWeights kept;
  RecoveryWeights* weights = state.range(0) ? &kept : nullptr;
  if (weights) (void)fe.error_estimate({}, nullptr, weights), (void)fe.error_estimate({}, nullptr, weights);
  std::vector<PointValues> centroids;
  for (auto _ : state) benchmark::DoNotOptimize(fe.error_estimate({}, &centroids, weights).error_squared);
  state.SetItemsProcessed(state.iterations() * 316 * 158);
}

using Q4x2    = Model<Axisym2, Quad4, Isotropic>;
using Q4x3    = Model<Axisym3, Quad4, Isotropic>;
using Legacy2 = Model<Axisym2, LegacyQuad, Isotropic>;

}  // namespace

BENCHMARK_TEMPLATE(BM_ElementStiffness, Axisym2, Quad4);
BENCHMARK_TEMPLATE(BM_ElementStiffness, Axisym3, Quad4);
BENCHMARK_TEMPLATE(BM_ElementStiffness, Axisym2, LegacyQuad);
BENCHMARK_TEMPLATE(BM_ElementStiffness, Axisym3, LegacyQuad);
BENCHMARK_TEMPLATE(BM_ElementStiffness, Axisym2, Quad8);
BENCHMARK_TEMPLATE(BM_ElementStiffness, Axisym3, Quad8);

BENCHMARK(BM_ElementStiffnessBatch);

// nr x nr/2 quads: nr = 100 -> ~1e4 DOFs, 316 -> ~1e5, 1000 -> ~1e6 (2 DOF).
BENCHMARK_TEMPLATE(BM_Assembly, Q4x2)->Arg(100)->Arg(316)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_Assembly, Q4x3)->Arg(316)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_Assembly, Legacy2)->Arg(316)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_ErrorEstimate, Q4x2)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_ErrorEstimate, Legacy2)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_LinearSolve, Q4x2)->Arg(100)->Arg(316)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_LinearSolve, Q4x2)->Arg(1000)->Unit(benchmark::kMillisecond)->Iterations(1);
#ifdef GAPFE_HAS_CHOLMOD
using Q4x2Cholmod = Model<Axisym2, Quad4, Isotropic, CholmodLlt>;
BENCHMARK_TEMPLATE(BM_LinearSolve, Q4x2Cholmod)->Arg(100)->Arg(316)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_LinearSolve, Q4x2Cholmod)->Arg(1000)->Unit(benchmark::kMillisecond)->Iterations(3);
#endif

BENCHMARK_MAIN();

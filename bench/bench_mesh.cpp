// The I-J mesh generator (mesh/ij_grid.hpp) on an n x n square whose boundary is given by four line
// segments: every interior point comes from the Laplace solve. Counter: grid points per second.
//   build/bench/bench/bench_mesh --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <cmath>

#include <benchmark/benchmark.h>

#include "gapfe/mesh/ij_grid.hpp"

namespace {

std::vector<gapfe::Segment> square(int n) {
  using gapfe::GridPoint;
  const auto line = [](int i1, int j1, double r1, double z1, int i2, int j2, double r2, double z2) {
    return gapfe::Segment{{GridPoint{i1, j1, {r1, z1}}, GridPoint{i2, j2, {r2, z2}}, GridPoint{}},
                          gapfe::SegmentType::line};
  };
  return {line(1, 1, 1, 0, n, 1, 2, 0), line(n, 1, 2, 0, n, n, 2, 1), line(n, n, 2, 1, 1, n, 1, 1),
          line(1, n, 1, 1, 1, 1, 1, 0)};
}

/// A quarter annulus 1 < r < 2 on an ni x nj grid, I along the radius: two straight sides and two arcs
/// (types 3 and 4). The index aspect follows the geometry (ni = nj / 2), so the Laplace fill does not fold
/// at the concave inner arc (it does with ni = nj, docs/theory.md 9).
std::vector<gapfe::Segment> quarter_annulus(int nj) {
  const int n = nj / 2, m = nj;
  using gapfe::GridPoint;
  const double h = std::sqrt(0.5);
  return {{{GridPoint{1, 1, {1, 0}}, GridPoint{n, 1, {2, 0}}, GridPoint{}}, gapfe::SegmentType::line},
          {{GridPoint{n, m, {0, 2}}, GridPoint{1, m, {0, 1}}, GridPoint{}}, gapfe::SegmentType::line},
          {{GridPoint{n, 1, {2, 0}}, GridPoint{n, m, {0, 2}}, GridPoint{0, 0, {0, 0}}},
           gapfe::SegmentType::arc_centre},
          {{GridPoint{1, 1, {1, 0}}, GridPoint{1, (m + 1) / 2, {h, h}}, GridPoint{1, m, {0, 1}}},
           gapfe::SegmentType::arc_three_points}};
}

template <bool Annulus>
void BM_IJGrid(benchmark::State& state) {
  const int n         = static_cast<int>(state.range(0));
  const auto segments = Annulus ? quarter_annulus(n) : square(n);
  for (auto _ : state) {
    auto g = gapfe::generate_ij_grid(Annulus ? n / 2 : n, n, segments);
    benchmark::DoNotOptimize(g.nodes.data());
  }
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(Annulus ? n / 2 : n) * n,
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

// Square: the row-wise initial guess is already the answer. Annulus: curved rows, CG does the work; 707 x
// 1414 is the curved 1e6-point grid of BENCHMARKS.md's run-vs-CalculiX cases (1000 x 1000 folds at the inner
// arc).
BENCHMARK(BM_IJGrid<false>)->Arg(100)->Arg(300)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IJGrid<true>)  // nj; ni = nj / 2
    ->Arg(200)
    ->Arg(600)
    ->Arg(1000)
    ->Arg(1414)
    ->Arg(2000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();

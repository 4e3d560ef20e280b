// Solver policies without a mesh: the nested-dissection ordering is a valid permutation (connected or
// not), gives the same solution as AMD, and less fill than the natural order on a grid; the coordinate
// dissection cuts a grid along grid lines. (EigenLu, the
// full-storage policy, is checked through the drivers in test_verification.cpp.) And the worker pool's
// loop (core/workers.hpp).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "gapfe/core/workers.hpp"
#include "gapfe/solver/coordinate_dissection.hpp"
#include "gapfe/solver/eigen_ldlt.hpp"

#include "support.hpp"

using namespace gapfe;

namespace {
/// 5-point Laplacian (+ a shift, SPD) on an nx x ny grid, lower triangle; `cut` removes the couplings
/// across column `cut` so the graph falls apart into two components.
SpMat grid_laplacian(int nx, int ny, int cut = -1) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [&](int i, int j) { return j * nx + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      t.emplace_back(id(i, j), id(i, j), 4.1);
      if (i + 1 < nx && i != cut) t.emplace_back(id(i + 1, j), id(i, j), -1.0);
      if (j + 1 < ny) t.emplace_back(id(i, j + 1), id(i, j), -1.0);
    }
  SpMat a(nx * ny, nx * ny);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}
bool is_permutation(const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>& p) {
  std::vector<int> seen(static_cast<std::size_t>(p.size()), 0);
  for (int k = 0; k < p.size(); ++k) {
    const int v = p.indices()[k];
    if (v < 0 || v >= p.size() || seen[v]++) return false;
  }
  return true;
}
}  // namespace

TEST_CASE("[solver] nested dissection: a valid permutation, also for disconnected graphs") {
  for (int cut : {-1, 20}) {
    const SpMat lower = grid_laplacian(60, 40, cut);
    const SpMat full  = lower.selfadjointView<Eigen::Lower>();
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p;
    NestedDissectionOrdering{}(full, p);
    CHECK(p.size() == full.cols());
    CHECK(is_permutation(p));
  }
  SpMat diagonal(10, 10);  // no couplings at all: ten components
  diagonal.setIdentity();
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p;
  NestedDissectionOrdering{}(diagonal, p);
  CHECK(is_permutation(p));
}

TEST_CASE("[solver] nested dissection and AMD give the same solution; ND fills less than the natural order") {
  const SpMat a = grid_laplacian(80, 60);
  const VecX b  = VecX::LinSpaced(a.rows(), -1.0, 2.0);
  EigenLdlt nd;
  EigenLdltAmd amd;
  nd.analyze(a), amd.analyze(a);
  REQUIRE(nd.factorize(a));
  REQUIRE(amd.factorize(a));
  const VecX x = nd.solve(b), y = amd.solve(b);
  CHECK((x - y).norm() <= 1e-12 * y.norm());
  const SpMat full = a.selfadjointView<Eigen::Lower>();
  CHECK((full * x - b).norm() <= 1e-12 * b.norm());
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower, NestedDissectionOrdering> with_nd(a);
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower, Eigen::NaturalOrdering<int>> natural(a);
  const SpMat l_nd = with_nd.matrixL(), l_nat = natural.matrixL();
  MESSAGE("nnz(L): nested dissection " << l_nd.nonZeros() << ", natural " << l_nat.nonZeros());
  CHECK(l_nd.nonZeros() < l_nat.nonZeros());
}

namespace {
/// Node adjacency (CSR) of the nx x ny 5-point grid of grid_laplacian, with its coordinates (i, j) h.
struct Grid {
  std::vector<Vec2> x;
  std::vector<int> ptr{0}, adj;
};
Grid grid_graph(int nx, int ny, double h) {
  Grid g;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      g.x.emplace_back(1.0 + i * h, j * h);
      for (const auto& [di, dj] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}})
        if (i + di >= 0 && i + di < nx && j + dj >= 0 && j + dj < ny) g.adj.push_back((j + dj) * nx + i + di);
      g.ptr.push_back(static_cast<int>(g.adj.size()));
    }
  return g;
}
/// Operations of an LDLT factorization with `ordering`: sum over the columns of L of count^2.
template <class Ordering>
double factor_operations(const SpMat& a) {
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower, Ordering> f(a);
  const SpMat l = f.matrixL();
  double ops    = 0;
  for (Eigen::Index c = 0; c < l.cols(); ++c) {
    const double count = static_cast<double>(l.outerIndexPtr()[c + 1] - l.outerIndexPtr()[c]);
    ops += count * count;
  }
  return ops;
}
}  // namespace

TEST_CASE(
    "[solver] coordinate dissection: a permutation; a grid is cut along a grid line; fewer operations than "
    "AMD") {
  const int nx = 121, ny = 81;
  const Grid g                 = grid_graph(nx, ny, 0.01);
  const std::vector<int> order = coordinate_dissection(g.x, g.ptr, g.adj);
  REQUIRE(order.size() == static_cast<std::size_t>(nx * ny));
  std::vector<int> seen(order.size(), 0);
  for (const int n : order) REQUIRE(++seen[static_cast<std::size_t>(n)] == 1);
  // The grid is wider than high, so the first cut is across r: the last ny nodes eliminated are one
  // column (George's separator), the median one.
  const double r_last = g.x[static_cast<std::size_t>(order.back())](0);
  for (std::size_t k = order.size() - ny; k < order.size(); ++k)
    CHECK(g.x[static_cast<std::size_t>(order[k])](0) == r_last);
  CHECK(std::abs(r_last - (1.0 + 0.01 * (nx / 2))) < 1e-12);

  // The same order through EigenLdlt::analyze(K, order): the solution AMD gives. Operations (George: ND is
  // O(n^1.5), the natural band order O(n^2)): far below the band's; at this size (1e4 unknowns) minimum
  // degree is still a little ahead (1.59e7 against 1.31e7, deterministic); the dissection's lead shows at
  // scale: a third of AMD's flops at 1e6 equations (BENCHMARKS.md, "Levers, each measured").
  const SpMat a = grid_laplacian(nx, ny);
  const VecX b  = VecX::LinSpaced(a.rows(), -1.0, 2.0);
  EigenLdlt given;
  EigenLdltAmd amd;
  given.analyze(a, order), amd.analyze(a);
  REQUIRE(given.factorize(a));
  REQUIRE(amd.factorize(a));
  CHECK((given.solve(b) - amd.solve(b)).norm() <= 1e-12 * amd.solve(b).norm());
  GivenOrFallbackOrdering<NestedDissectionOrdering>::slot = &order;
  const double ops_given = factor_operations<GivenOrFallbackOrdering<NestedDissectionOrdering>>(a);
  GivenOrFallbackOrdering<NestedDissectionOrdering>::slot = nullptr;
  const double ops_amd                                    = factor_operations<Eigen::AMDOrdering<int>>(a);
  const double ops_natural                                = factor_operations<Eigen::NaturalOrdering<int>>(a);
  MESSAGE("LDLT operations: coordinate dissection " << ops_given << ", AMD " << ops_amd << ", natural "
                                                    << ops_natural);
  CHECK(ops_given < ops_natural / 5);
  CHECK(ops_given < 1.3 * ops_amd);
}

TEST_CASE(
    "[threads] parallel_for runs every task once, nested loops inline, and rethrows the lowest failure") {
  // core/workers.hpp: on 3 threads (more than this machine may have: the pool must not care) and on 1.
  for (const int threads : {3, 1}) {
    set_worker_threads(threads);
    CHECK(worker_threads() == threads);
    std::vector<std::atomic<int>> runs(1000);
    std::vector<long> inner(1000, 0);
    parallel_for(runs.size(), [&](std::size_t t) {
      runs[t].fetch_add(1);
      parallel_for(10, [&](std::size_t k) { inner[t] += static_cast<long>(k); });  // on the task's thread
    });
    CHECK(std::all_of(runs.begin(), runs.end(), [](const std::atomic<int>& r) { return r.load() == 1; }));
    CHECK(std::all_of(inner.begin(), inner.end(), [](long s) { return s == 45; }));
    // Tasks 700 and 100 fail (700 may well fail first on another thread): a serial loop meets 100 first.
    for (int repeat = 0; repeat < 20; ++repeat)
      CHECK_THROWS_WITH(parallel_for(1000,
                                     [&](std::size_t t) {
                                       if (t == 700) throw std::runtime_error("task 700");
                                       if (t == 100) {
                                         std::this_thread::sleep_for(std::chrono::microseconds(200));
                                         throw std::runtime_error("task 100");
                                       }
                                     }),
                        "task 100");
  }
}

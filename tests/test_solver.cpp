// Solver policies without a mesh: the nested-dissection ordering is a valid permutation (connected or
// not), gives the same solution as AMD, and less fill than the natural order on a grid. (EigenLu, the
// full-storage policy, is checked through the drivers in test_verification.cpp.)
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

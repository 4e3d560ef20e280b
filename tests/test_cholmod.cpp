// The CHOLMOD policy gives the Eigen default's answer and detects singular systems the same way.
#include "gapfe/solver/cholmod.hpp"

#include "support.hpp"

using namespace gapfe;
using namespace gapfe::test;

namespace {
/// The Lame tube 0.1 < r < 0.2 m, 0 < z < 0.05 m on nr x nz Quad4 cells, 100 MPa on the bore; `held`: u_z = 0
/// on both ends (else nothing holds it: singular).
template <class M>
Problem<M> lame_tube(int nr, int nz, bool held = true) {
  Problem<M> p;
  p.mesh       = rectangle_mesh<4>(0.1, 0.2, 0, 0.05, nr, nz);
  p.materials  = {Isotropic::constant(200e9, 0.3)};
  p.edge_loads = bore_pressure(p.mesh, nr, nz, 100e6);
  if (held) {
    fix_plane(p.conditions, p.mesh, 0.0, 2, zero3);
    fix_plane(p.conditions, p.mesh, 0.05, 2, zero3);
  }
  return p;
}

/// The Lame tube (held) and a ring around it, 0.21 < r < 0.3 m, joined to it only by node links whose values
/// stay zero. check_held (assembly/problem_check.hpp) counts the ring held through the links (whether a link
/// holds is the factorization's to find); its stiffness is singular, as the tube free in z was.
template <class M>
LinearStatic<M> tube_and_loose_ring(int nr, int nz) {
  Problem<M> p    = lame_tube<M>(nr, nz);
  const int first = p.mesh.node_count();
  const auto ring = rectangle_mesh<4>(0.21, 0.3, 0, 0.05, nr, nz);
  for (const auto& x : ring.nodes) p.mesh.nodes.push_back(x);
  for (auto c : ring.cells) {
    for (int& n : c) n += first;
    p.mesh.cells.push_back(c);
  }
  Connectivity<2> links;
  for (int j = 0; j <= nz; ++j) links.push_back({j * (nr + 1) + nr, first + j * (nr + 1)});
  return LinearStatic<M>(std::move(p), std::move(links));
}

/// The 120 x 60 cell Lame tube's stiffness, loads and the mesh's coordinate dissection order: its top
/// separator is the grid line across the longer side, 61 nodes.
struct TubeSystem {
  using M = Model<Axisym2, Quad4, Isotropic, CholmodLlt>;
  SpMat k;
  VecX b;
  std::vector<int> order;
  TubeSystem() {
    const Problem<M> p = lame_tube<M>(120, 60);
    LinearStatic<M> fe(p);
    fe.solve();
    k = fe.stiffness(), b = fe.rhs();
    Assembler<M> assembler(p, {});
    order = fill_reducing_order(assembler, p);
  }
};
}  // namespace

TEST_CASE("[solver] CHOLMOD and Eigen LDLT agree on the Lame tube and reuse the symbolic analysis") {
  using Fast    = Model<Axisym2, Quad4, Isotropic, CholmodLlt>;
  using Slow    = Model<Axisym2, Quad4, Isotropic, EigenLdlt>;
  auto build    = [&]<class M>(std::type_identity<M>) { return LinearStatic<M>(lame_tube<M>(20, 10)); };
  auto fast     = build(std::type_identity<Fast>{});
  auto slow     = build(std::type_identity<Slow>{});
  const auto u1 = fast.solve().displacement, u2 = slow.solve().displacement;
  CHECK((u1 - u2).cwiseAbs().maxCoeff() < 1e-10 * u2.cwiseAbs().maxCoeff());
  // Second solve with doubled load on the same factorization pattern: doubled answer.
  for (auto& l : fast.problem().edge_loads) l.pressure *= 2;
  const auto u3 = fast.solve().displacement;
  CHECK((u3 - 2 * u1).cwiseAbs().maxCoeff() < 1e-10 * u1.cwiseAbs().maxCoeff());
  const Lame exact{0.1, 0.2, 100e6, 200e9, 0.3};
  CHECK(rel(u1(0, 0), exact.displacement(0.1)) < 0.005);
}

TEST_CASE("[solver] CHOLMOD in the mesh's coordinate dissection order: the solution AMD gives") {
  // The drivers hand CHOLMOD fill_reducing_order (driver/system_setup.hpp); here the same on a 120 x 60 cell
  // tube, against CHOLMOD's own AMD on the same matrix.
  using M            = Model<Axisym2, Quad4, Isotropic, CholmodLlt>;
  const Problem<M> p = lame_tube<M>(120, 60);
  LinearStatic<M> fe(p);
  const auto u   = fe.solve().displacement;
  const SpMat& k = fe.stiffness();
  const VecX& b  = fe.rhs();
  Assembler<M> assembler(p, {});
  const std::vector<int> order = fill_reducing_order(assembler, p);
  REQUIRE(order.size() == static_cast<std::size_t>(k.rows()));
  CholmodLlt given, amd;
  given.analyze(k, order), amd.analyze(k);
  REQUIRE(given.factorize(k));
  REQUIRE(amd.factorize(k));
  const VecX x = given.solve(b), y = amd.solve(b);
  CHECK((x - y).norm() <= 1e-12 * y.norm());
  CHECK(u(0, 0) == doctest::Approx(x(fe.dofs().equation[0])).epsilon(1e-12));
}

TEST_CASE("[solver] CHOLMOD's factor statistics are its factor's; release_solver() keeps the results") {
  // An independent count: Eigen's simplicial LLT on the matrix permuted into the same elimination order has
  // the same pattern of L (the fill depends on the order alone), whose column counts c_j (diagonal
  // included) give nnz(L) = sum c_j and the LL' flops sum c_j^2: per column its square root and c_j - 1
  // divisions, and the c_j (c_j - 1) of the update it sends on (CHOLMOD's count; cholmod_core.h: less n
  // for LDL').
  using M            = Model<Axisym2, Quad4, Isotropic, CholmodLlt>;
  const Problem<M> p = lame_tube<M>(40, 20);
  LinearStatic<M> fe(p);
  const Eigen::MatrixX3d u = fe.solve().displacement;
  const FactorStatistics s = fe.factor_statistics();
  const SpMat& k           = fe.stiffness();
  Assembler<M> assembler(p, {});
  const std::vector<int> order = fill_reducing_order(assembler, p);
  REQUIRE(order.size() == static_cast<std::size_t>(k.rows()));
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> to_order(k.rows());
  for (std::size_t i = 0; i < order.size(); ++i) to_order.indices()[order[i]] = static_cast<int>(i);
  SpMat permuted;
  permuted.selfadjointView<Eigen::Lower>() = k.selfadjointView<Eigen::Lower>().twistedBy(to_order);
  Eigen::SimplicialLLT<SpMat, Eigen::Lower, Eigen::NaturalOrdering<int>> llt(permuted);
  REQUIRE(llt.info() == Eigen::Success);
  const SpMat l  = llt.matrixL();
  double entries = 0, flops = 0;
  for (Eigen::Index j = 0; j < l.outerSize(); ++j) {
    const double c = l.outerIndexPtr()[j + 1] - l.outerIndexPtr()[j];
    entries += c, flops += c * c;
  }
  CHECK(s.entries == entries);
  CHECK(s.flops == flops);
  CHECK(s.stored >= s.entries);  // with the relaxed supernodes' zeros and their dense triangles
  // The factorization freed: the displacements, the estimate and the statistics stand; solving again is a
  // logic error, not a solve on an empty matrix.
  const double estimate = fe.error_estimate().relative();
  fe.release_solver();
  CHECK(fe.stiffness().nonZeros() == 0);
  CHECK(fe.solution().displacement == u);
  CHECK(fe.error_estimate().relative() == estimate);
  CHECK(fe.factor_statistics().flops == s.flops);
  CHECK_THROWS_AS(fe.solve(), std::logic_error);
}

TEST_CASE("[solver] CHOLMOD reports a singular system instead of returning garbage") {
  using Fast = Model<Axisym2, Quad4, Isotropic, CholmodLlt>;
  CHECK_THROWS_WITH_AS(LinearStatic<Fast>(lame_tube<Fast>(4, 2, /*held=*/false)),
                       doctest::Contains("singular"),
                       SolveError);  // refused before any factorization (check_held)
  LinearStatic<Fast> fe = tube_and_loose_ring<Fast>(4, 2);
  CHECK_THROWS_WITH_AS(fe.solve(), doctest::Contains("singular"), SolveError);
}

TEST_CASE("[solver][threads] CHOLMOD split into two halves and their separator: the whole factor's answer") {
  // The tube of 120 x 60 cells (TubeSystem). Factorized whole and split (SplitCholmod,
  // solver/split_cholmod.hpp), against each other and against Eigen's LDLT, an independent factorization; the
  // split on 1 and 3 threads bit for bit.
  const TubeSystem tube;
  const SpMat& k                = tube.k;
  const VecX& b                 = tube.b;
  const std::vector<int>& order = tube.order;
  const OneThreadAfter restore;
  const auto solve = [&](Eigen::Index split_from, int threads, CholmodLlt& solver) {
    set_worker_threads(threads);
    solver.split_from = split_from;
    solver.analyze(k, order);
    REQUIRE(solver.factorize(k));
    return solver.solve(b);
  };
  CholmodLlt whole, split, split3;
  const VecX x_whole = solve(k.rows() + 1, 1, whole), x_split = solve(0, 1, split);
  CHECK_FALSE(whole.split());
  REQUIRE(split.split());
  const int ns = split.split_separator();
  CHECK(ns > 100);  // 61 nodes, 2 equations each, fewer where u_z is held
  CHECK(ns <= 2 * 61);
  const Eigen::SimplicialLDLT<SpMat, Eigen::Lower> ldlt(k);
  const VecX x_ldlt = ldlt.solve(b);
  CHECK((x_split - x_whole).norm() <= 1e-11 * x_whole.norm());
  CHECK((x_split - x_ldlt).norm() <= 1e-11 * x_ldlt.norm());
  // Normwise backward error |K x - b| / (|K| |x| + |b|) in the infinity norm: a stable factorization's,
  // a small multiple of the unit roundoff.
  const auto backward_error = [&](const VecX& x) {
    VecX row_sums = VecX::Zero(k.rows());
    for (int c = 0; c < k.outerSize(); ++c)
      for (SpMat::InnerIterator it(k, c); it; ++it) {
        row_sums[it.row()] += std::abs(it.value());
        if (it.row() != c) row_sums[c] += std::abs(it.value());
      }
    const VecX r = k.selfadjointView<Eigen::Lower>() * x - b;
    return r.lpNorm<Eigen::Infinity>() /
           (row_sums.maxCoeff() * x.lpNorm<Eigen::Infinity>() + b.lpNorm<Eigen::Infinity>());
  };
  MESSAGE("backward error: split ", backward_error(x_split), ", whole ", backward_error(x_whole));
  CHECK(backward_error(x_split) < 1e-14);
  // The factor's entries are the whole one's: a half's columns couple to nothing of the other half, and
  // the separator's block is dense in both. The flops add the separator's dense work (at most 4 n_s^3 / 3).
  const FactorStatistics sw = whole.statistics(), ss = split.statistics();
  CHECK(ss.entries == sw.entries);
  CHECK(ss.flops > sw.flops);
  CHECK(ss.flops < sw.flops + 4.0 / 3 * ns * ns * ns + 1e6);
  const VecX x_three = solve(0, 3, split3);
  CHECK(split3.split_separator() == ns);
  CHECK(x_three == x_split);
  // K as two tubes with no stiffness between them: halves without a separator.
  SpMat two(2 * k.rows(), 2 * k.rows());
  std::vector<Eigen::Triplet<double>> entries;
  for (int c = 0; c < k.outerSize(); ++c)
    for (SpMat::InnerIterator it(k, c); it; ++it)
      for (const int shift : {0, int(k.rows())})
        entries.push_back({int(it.row()) + shift, int(it.col()) + shift, it.value()});
  two.setFromTriplets(entries.begin(), entries.end());
  std::vector<int> order_two = order;
  for (const int eq : order) order_two.push_back(eq + int(k.rows()));
  CholmodLlt apart;
  apart.split_from = 0;
  apart.analyze(two, order_two);
  REQUIRE(apart.factorize(two));
  REQUIRE(apart.split());
  CHECK(apart.split_separator() == 0);
  SplitCholmod halves;
  REQUIRE(halves.analyze(two, order_two));
  CHECK(halves.half_size(0) == k.rows());  // one tube each
  CHECK(halves.half_size(1) == k.rows());
  VecX b_two(2 * k.rows());
  b_two << b, 2 * b;
  const VecX x_two = apart.solve(b_two);
  CHECK((x_two.head(k.rows()) - x_whole).norm() <= 1e-11 * x_whole.norm());
  CHECK((x_two.tail(k.rows()) - 2 * x_whole).norm() <= 2e-11 * x_whole.norm());
}

TEST_CASE("[solver] A split CHOLMOD factorization with a stiff separator row, and a small body apart") {
  // One separator equation scaled by 1e4 (its diagonal by 1e8: a contact penalty's beside steel's): K' = D K
  // D, x' = D^-1 x. The separator's block C is scaled row by row, so the split keeps the whole
  // factorization's digits; one C for every row (the largest) would lose about eight.
  const TubeSystem tube;
  const SpMat& k                = tube.k;
  const VecX& b                 = tube.b;
  const std::vector<int>& order = tube.order;
  SplitCholmod probe;
  REQUIRE(probe.analyze(k, order));
  VecX d                                                        = VecX::Ones(k.rows());
  d[probe.separator()[std::size_t(probe.separator_size() / 2)]] = 1e4;
  const SpMat full                                              = k.selfadjointView<Eigen::Lower>();
  const SpMat dkd                                               = d.asDiagonal() * full * d.asDiagonal();
  const SpMat lower                                             = dkd.triangularView<Eigen::Lower>();
  const VecX db                                                 = d.cwiseProduct(b);
  CholmodLlt whole, split;
  whole.split_from = k.rows() + 1, split.split_from = 0;
  whole.analyze(lower, order), split.analyze(lower, order);
  REQUIRE(whole.factorize(lower));
  REQUIRE(split.factorize(lower));
  REQUIRE(split.split());
  const VecX x_whole = d.cwiseProduct(whole.solve(db)), x_split = d.cwiseProduct(split.solve(db));
  CHECK((x_split - x_whole).norm() <= 1e-11 * x_whole.norm());
  // A 4 x 2 cell tube apart, eliminated after the large one: a component of every prefix of the order, yet
  // the large tube's top separator is found (halves of at least kMinShare each).
  using M = TubeSystem::M;
  LinearStatic<M> small_fe(lame_tube<M>(4, 2));
  small_fe.solve();
  const SpMat& small = small_fe.stiffness();
  const int n = int(k.rows()), m = int(small.rows());
  std::vector<Eigen::Triplet<double>> entries;
  for (const SpMat* part : {&k, &small})
    for (int c = 0; c < part->outerSize(); ++c)
      for (SpMat::InnerIterator it(*part, c); it; ++it)
        entries.push_back(
            {int(it.row()) + (part == &k ? 0 : n), int(it.col()) + (part == &k ? 0 : n), it.value()});
  SpMat both(n + m, n + m);
  both.setFromTriplets(entries.begin(), entries.end());
  std::vector<int> order_both = order;
  for (int i = 0; i < m; ++i) order_both.push_back(n + i);
  SplitCholmod apart;
  REQUIRE(apart.analyze(both, order_both));
  CHECK(apart.separator_size() == probe.separator_size() + m);
  CHECK(std::min(apart.half_size(0), apart.half_size(1)) >= SplitCholmod::kMinShare * (n + m));
}

TEST_CASE("[solver] A split CHOLMOD factorization of a singular system: re-done whole, the same report") {
  using M = Model<Axisym2, Quad4, Isotropic, CholmodLlt>;
  // The held tube's stiffness with equation 100's row and column zeroed: singular in every order.
  LinearStatic<M> fe(lame_tube<M>(20, 10));
  fe.solve();
  SpMat k = fe.stiffness();
  for (Eigen::Index j = 0; j < k.outerSize(); ++j)
    for (SpMat::InnerIterator it(k, j); it; ++it)
      if (it.row() == 100 || it.col() == 100) it.valueRef() = 0;
  Assembler<M> assembler(fe.problem(), {});
  const std::vector<int> order = fill_reducing_order(assembler, fe.problem());
  CholmodLlt whole, split;
  whole.split_from = k.rows() + 1, split.split_from = 0;
  whole.analyze(k, order), split.analyze(k, order);
  REQUIRE(SplitCholmod().analyze(k, order));  // the split is tried, and fails
  CHECK_FALSE(whole.factorize(k));
  CHECK_FALSE(split.factorize(k));
  CHECK_FALSE(split.split());
  CHECK(split.failure() == whole.failure());
  CHECK(split.failure().find("singular") != std::string::npos);
  CHECK(split.failed_equation() == whole.failed_equation());
  CHECK(split.failed_equation() >= 0);
}

#ifdef GAPFE_HAS_UMFPACK
#include "gapfe/solver/eigen_lu.hpp"
#include "gapfe/solver/umfpack.hpp"

#include "contact_support.hpp"

namespace gapfe::test {

TEST_CASE("UmfpackLu: the Coulomb push-out of the press fit as EigenLu gives it, singular systems refused") {
  const auto push_out = [&]<class Solver>(std::type_identity<Solver>) {
    using M = Model<Axisym2, Quad4, Isotropic, Solver>;
    const PressFit fit;
    std::vector<GapPair> pairs;
    auto problem = fit.problem<M>(pairs);
    ContactOptions opt;
    opt.gap_materials = {1};
    opt.friction      = fit.mu;
    ContactStatic<M, ActiveSet, Coulomb> cs(std::move(problem), pairs, opt);
    const auto loads = [&](Problem<M>& p, double t) {
      fit.set(p, std::min(t, 1.0), t <= 1 ? 0 : 1e-6 * (t - 1));
    };
    cs.advance(1.0, loads);
    cs.advance(2.0, loads);
    return fit.push_force(cs.fe().solution());
  };
  const double lu      = push_out(std::type_identity<EigenLu>{}),
               umfpack = push_out(std::type_identity<UmfpackLu>{});
  CHECK(rel(umfpack, lu) < 1e-9);
  CHECK(rel(umfpack, PressFit{}.slip_force()) < 0.01);

  UmfpackLu solver;
  SpMat k(2, 2);
  k.insert(0, 0) = 1, k.insert(0, 1) = 2, k.insert(1, 0) = 2, k.insert(1, 1) = 4;  // rank 1
  solver.analyze(k);
  CHECK_FALSE(solver.factorize(k));
  CHECK(solver.failure().find("singular") != std::string::npos);
}

}  // namespace gapfe::test
#endif

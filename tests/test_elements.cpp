// Element-level checks: zero-energy modes and consistent edge loads.
#include <Eigen/Eigenvalues>

#include "support.hpp"

using namespace gapfe;
using test::rel;

namespace {

template <class Kin, class Elem>
int zero_modes(const Mat<Elem::kNodes, 2>& x) {
  const Mat66 C              = Isotropic::constant(200e9, 0.3).localize({}, 0, 0).stiffness;
  using K                    = ElementKernel<Kin, Elem>;
  const typename K::Matrix k = K::stiffness(x, K::restrict(C));
  CHECK((k - k.transpose()).norm() <= 1e-12 * k.norm());
  // Dynamic size: a fixed-size eigensolver per element type costs minutes of compile time, not speed.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd{k});
  int zeros = 0;
  for (int i = 0; i < K::kDofs; ++i)
    zeros += std::abs(eig.eigenvalues()(i)) < 1e-10 * eig.eigenvalues().maxCoeff();
  return zeros;
}

}  // namespace

TEST_CASE("[element] zero-energy modes: axial translation (2 DOF), plus rigid spin u_theta = w r (3 DOF)") {
  Mat<4, 2> q;
  q << 1.0, 0.0, 2.1, 0.2, 1.9, 1.3, 0.9, 1.0;
  Mat<3, 2> t = q.topRows<3>();
  Mat<8, 2> q8;
  q8.topRows<4>() = q;
  for (int a = 0; a < 4; ++a) q8.row(4 + a) = 0.5 * (q.row(a) + q.row((a + 1) % 4));
  CHECK(zero_modes<Axisym2, Quad4>(q) == 1);
  CHECK(zero_modes<Axisym3, Quad4>(q) == 2);
  CHECK(zero_modes<Axisym2, LegacyQuad>(q) == 1);
  CHECK(zero_modes<Axisym3, LegacyQuad>(q) == 2);
  CHECK(zero_modes<Axisym2, Quad8>(q8) == 1);
  CHECK(zero_modes<Axisym3, Quad8>(q8) == 2);
  // A lone one-point CST has one more: u_r = c (z - zbar), u_z = -c r, whose hoop strain vanishes at the
  // centroid where it is sampled. Any assembly of two or more triangles suppresses it (the patch tests).
  CHECK(zero_modes<Axisym2, Tri3>(t) == 2);
  CHECK(zero_modes<Axisym3, Tri3>(t) == 3);
}

TEST_CASE("[element] legacy quad: condensed stiffness has rank 10 in 3 DOF (docs/theory.md 2 item 5)") {
  Mat<4, 2> q;
  q << 0.5, 0.0, 1.5, 0.1, 1.4, 0.9, 0.6, 1.2;
  CHECK(zero_modes<Axisym3, LegacyQuad>(q) == 2);  // 12 - 10
}

TEST_CASE(
    "[element] edge loads: uniform pressure on a straight edge, closed form 2 pi p L (2 r_M + r_N) / 6") {
  Mat<2, 2> x;
  x << 0.1, 0.3, 0.4, 0.7;  // M = (0.1, 0.3), N = (0.4, 0.7): L = 0.5
  const double p = 3e6, L = 0.5;
  const Mat<2, 3> f = edge_forces<2>(x, p, 0, 0);
  const Vec2 outward(0.8, -0.6);  // (dz, -dr) / L
  const double fm = kTwoPi * p * L * (2 * 0.1 + 0.4) / 6, fn = kTwoPi * p * L * (0.1 + 2 * 0.4) / 6;
  CHECK(rel(f(0, 0), -fm * outward(0)) < 1e-13);
  CHECK(rel(f(0, 1), -fm * outward(1)) < 1e-13);
  CHECK(rel(f(1, 0), -fn * outward(0)) < 1e-13);
  // Shear from M to N and transverse shear: same weights along d and theta.
  const Mat<2, 3> g = edge_forces<2>(x, 0, 2e6, 5e6);
  CHECK(rel(g(1, 0), 2e6 / p * fn * 0.6) < 1e-13);
  CHECK(rel(g(0, 2), 5e6 / p * fm) < 1e-13);
  // A quadratic edge with the mid node at the midpoint carries the same total force.
  Mat<3, 2> x3;
  x3 << 0.1, 0.3, 0.25, 0.5, 0.4, 0.7;
  const Mat<3, 3> f3 = edge_forces<3>(x3, p, 0, 0);
  CHECK(rel(f3.col(0).sum(), f.col(0).sum()) < 1e-13);
  CHECK(rel(f3.col(1).sum(), f.col(1).sum()) < 1e-13);
}

TEST_CASE(
    "[element] the edge index finds a later call's edges too, and refuses an edge the wrong way round") {
  // EdgeIndex indexes only the edges its loads name: a later step's loads on other edges get the forces a
  // fresh index gives, bit for bit, and the closed form's total: a pressure p on the ring r = const of
  // height L pushes 2 pi r L p inward on the outer edge, outward on the bore.
  const int nr = 4, nz = 2;
  const double a = 0.1, b = 0.2, height = 0.05, p = 3e6;
  const Mesh<4> m                = rectangle_mesh<4>(a, b, 0, height, nr, nz);
  const std::array<int, 4>&first = m.cells[0], &last = m.cells[nr - 1];    // the bore's, the outer edge's
  const EdgeLoad bore{first[3], first[0], p}, outer{last[1], last[2], p};  // the cell to the left of M -> N
  EdgeIndex<Quad4> reused, fresh;
  VecX on_bore = VecX::Zero(2 * m.node_count()), later = on_bore, afresh = on_bore;
  reused.add_loads<2>(m, {bore}, on_bore);
  reused.add_loads<2>(m, {outer}, later);
  fresh.add_loads<2>(m, {outer}, afresh);
  CHECK(later == afresh);
  // The interior edge between cells 0 and 1, named the way cell 1 has it (cell 0 has it the other way),
  // after an index built without it, and a subset of the loads already indexed: both as a fresh index.
  const EdgeLoad interior{first[2], first[1], p};
  VecX both = VecX::Zero(2 * m.node_count()), both_afresh = both, subset = both;
  reused.add_loads<2>(m, {interior, outer}, both);
  EdgeIndex<Quad4>().add_loads<2>(m, {interior, outer}, both_afresh);
  CHECK(both == both_afresh);
  reused.add_loads<2>(m, {outer}, subset);
  CHECK(subset == afresh);
  const double cell_height = height / nz;
  CHECK(rel(on_bore(Eigen::seqN(0, m.node_count(), 2)).sum(), kTwoPi * a * cell_height * p) < 1e-13);
  CHECK(rel(later(Eigen::seqN(0, m.node_count(), 2)).sum(), -kTwoPi * b * cell_height * p) < 1e-13);
  VecX unused = on_bore;
  CHECK_THROWS_WITH_AS(reused.add_loads<2>(m, {EdgeLoad{outer.node_n, outer.node_m, p}}, unused),
                       doctest::Contains("swap M and N"), InputError);
  CHECK_THROWS_WITH_AS(reused.add_loads<2>(m, {EdgeLoad{first[0], last[2], p}}, unused),
                       doctest::Contains("not the ends of an element edge"), InputError);
}

TEST_CASE("[element] the vectorized Quad4 2-DOF batch kernel equals the generic kernel (1e-12)") {
  // A general, fully populated 4x4 material block (helical orthotropic) and distorted cells.
  ElasticConstants c;
  c.E_N = 140e9, c.E_S = 10e9, c.E_T = 9e9, c.nu_NS = 0.3, c.nu_NT = 0.28, c.nu_ST = 0.4;
  c.G_NS = 5e9, c.G_ST = 3.5e9, c.G_TN = 4.5e9;
  using K        = ElementKernel<Axisym2, Quad4>;
  const Mat66 d6 = Orthotropic::constant(c).localize({0.3, 0.5}, 0, 0).stiffness;
  Quad4Axisym2Batch<8> batch;
  std::array<Mat<4, 2>, 8> x;
  for (int l = 0; l < 8; ++l) {
    x[l] << 0.0 + 0.1 * l, 0.0, 1.0 + 0.1 * l, 0.1 * l, 1.1, 1.0 + 0.05 * l, 0.05 * l, 0.9;
    for (int a = 0; a < 4; ++a) batch.r[a][l] = x[l](a, 0), batch.z[a][l] = x[l](a, 1);
    batch.set_material(l, d6.topLeftCorner<4, 4>() * (1.0 + 0.1 * l));
  }
  batch.compute();
  for (int l = 0; l < 8; ++l) {
    const K::Matrix k = K::stiffness(x[l], K::restrict(d6) * (1.0 + 0.1 * l));
    for (int i = 0, m = 0; i < 8; ++i)
      for (int j = i; j < 8; ++j, ++m) CHECK(std::abs(batch.k[m][l] - k(i, j)) <= 1e-12 * k.norm());
  }
}

// The recovery error estimate (post/error_estimate.hpp) against the true energy-norm error of problems with
// closed forms. The true error needs no integration of the closed form: for a problem loaded by tractions
// alone (displacements held at zero), Galerkin orthogonality gives |u - u_h|^2 = l(u) - l(u_h), the work of
// the loads on the exact and on the discrete displacements, and for the Lame tube l(u) = p u_r(a) 2 pi a H.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <iterator>
#include <numbers>
#include <vector>

#include "support.hpp"

using namespace gapfe;
using namespace gapfe::test;

namespace {

constexpr double kModulus = 200e9, kPoisson = 0.3;

/// Plane-strain Lame tube a = 0.1, b = 0.2 m, p = 100 MPa on nr x nz cells, `height` tall, the radial spacing
/// graded (`grading` > 1: the outer cells that much larger than the bore's).
template <class M>
Problem<M> tube_problem(int nr, int nz, double height, double grading = 1.0) {
  constexpr int NPC = M::Element::kNodes;
  const double a = 0.1, b = 0.2;
  Problem<M> p;
  p.mesh = rectangle_mesh<NPC>(a, b, 0, height, nr, nz);
  if (grading != 1.0)
    for (auto& x : p.mesh.nodes) {
      const double s = (x(0) - a) / (b - a);  // 0..1 across the wall
      x(0)           = a + (b - a) * (std::pow(grading, s) - 1) / (grading - 1);
    }
  if constexpr (M::Material::kLinear)
    p.materials = {M::Material::constant(kModulus, kPoisson)};
  else  // far from yield: the law's elastic range
    p.materials = {
        {Orthotropic::constant(ElasticConstants::isotropic(kModulus, kPoisson)), HillYield::mises(1e12)}};
  p.edge_loads = bore_pressure(p.mesh, nr, nz, 100e6);
  fix_plane(p.conditions, p.mesh, 0.0, 6, zero3);
  fix_plane(p.conditions, p.mesh, height, 6, zero3);
  return p;
}

/// The complementary energy density sigma^T C^-1 sigma of an isotropic material, for (rr, zz, hoop, rz).
double complementary(const Vec<4>& s, double poisson) {
  return (s.squaredNorm() - s(3) * s(3) - 2 * poisson * (s(0) * s(1) + s(1) * s(2) + s(2) * s(0)) +
          2 * (1 + poisson) * s(3) * s(3)) /
         kModulus;
}

/// The true relative energy-norm error of a solved Lame tube, |u - u_h| / |u|. For an isoparametric element
/// by the loads' work: |u - u_h|^2 = l(u) - l(u_h) (Galerkin orthogonality; u_r along the bore is the
/// element's edge interpolation). For the constant-strain triangles of the legacy quadrilateral that identity
/// does not hold (the hoop strain taken at the centroid is not the exact form), so the error is integrated:
/// the exact stress against each sub-triangle's, on its degree-4 rule. |u|^2 = l(u) = p u_r(a) 2 pi a H
/// either way.
template <class M>
M model_of(const Problem<M>&);

template <class Fe>
double true_relative_error(const Fe& fe, double height, double poisson = kPoisson) {
  using M    = decltype(model_of(fe.problem()));
  using Elem = typename M::Element;
  const Lame exact{0.1, 0.2, 100e6, kModulus, poisson};
  const auto& m      = fe.problem().mesh;
  const double norm2 = 100e6 * exact.displacement(0.1) * 2 * std::numbers::pi * 0.1 * height;
  if constexpr (std::is_same_v<Elem, LegacyQuad>) {
    const auto points = fe.point_values();  // the sub-triangles' stresses, cell by cell
    double error2     = 0;
    for (std::size_t e = 0; e < m.cells.size(); ++e) {
      Mat<4, 2> x;
      for (int c = 0; c < 4; ++c) x.row(c) = m.nodes[m.cells[e][c]].transpose();
      for (int q = 0; q < LegacyQuad::kLoadPoints; ++q) {
        double det    = 0;
        const auto g  = LegacyQuad::load_point(x, q, det);
        const Vec6& h = points[4 * e + q / 6].stress;
        const Vec<4> d(exact.radial_stress(g.r) - h(voigt::rr), exact.axial_stress() - h(voigt::zz),
                       exact.hoop_stress(g.r) - h(voigt::hoop), -h(voigt::rz));
        error2 += g.weight * complementary(d, poisson);
      }
    }
    return std::sqrt(error2 / norm2);
  } else {
    std::vector<std::pair<double, double>> bore;  // (z, u_r) on r = a
    for (int n = 0; n < m.node_count(); ++n)
      if (std::abs(m.nodes[n](0) - 0.1) < 1e-12)
        bore.push_back({m.nodes[n](1), fe.solution().displacement(n, 0)});
    std::sort(bore.begin(), bore.end());
    double work_h = 0;
    if constexpr (Elem::kEdgeNodes == 3)  // quadratic along the bore: Simpson on (corner, mid-side, corner)
      for (std::size_t k = 2; k < bore.size(); k += 2)
        work_h += (bore[k].first - bore[k - 2].first) / 6 *
                  (bore[k - 2].second + 4 * bore[k - 1].second + bore[k].second);
    else  // linear between the nodes
      for (std::size_t k = 1; k < bore.size(); ++k)
        work_h += 0.5 * (bore[k].second + bore[k - 1].second) * (bore[k].first - bore[k - 1].first);
    const double work = exact.displacement(0.1) * height;
    return std::sqrt((work - work_h) / work);
  }
}

}  // namespace

/// The Lame tube on `cells` cells through the wall, uniform and graded 1:3: each effectivity within
/// [0.7, 1.5], the finest within `finest` of 1, and the cells' shares adding up to the whole.
template <class M>
void check_tube_effectivities(std::initializer_list<int> cells, double finest) {
  for (const double grading : {1.0, 3.0})
    for (const int nr : cells) {
      const double height = 0.1 / nr * 2;
      LinearStatic<M> fe(tube_problem<M>(nr, 2, height, grading));
      fe.solve();
      const ErrorEstimate est = fe.error_estimate();
      const double truth      = true_relative_error(fe, height);
      const double ratio      = est.relative() / truth;
      INFO("nr " << nr << " grading " << grading << ": estimate " << est.relative() << ", true " << truth);
      CHECK(ratio >= 0.7);
      CHECK(ratio <= 1.5);
      if (nr == *std::prev(cells.end())) CHECK(std::abs(ratio - 1) < finest);
      double squares = 0;
      for (const double c : est.cell) squares += c * c;
      CHECK(std::sqrt(squares) == doctest::Approx(est.relative()).epsilon(1e-12));
    }
}

TEST_CASE_TEMPLATE(
    "[estimate] Lame tube: the recovery estimate's effectivity within [0.7, 1.5], near 1 when fine", M,
    Model<Axisym2, Quad4, Isotropic>, Model<Axisym2, LegacyQuad, Isotropic>,
    Model<Axisym2, Quad4BBar, Isotropic>, Model<Axisym3, Quad4, Isotropic>) {
  // The recovery is superconvergent on these meshes: the legacy quadrilateral's hoop strain at its
  // sub-triangles' centroids leaves it 5% high (measured 1.052 at 32 cells), the others within 0.5%.
  check_tube_effectivities<M>({4, 8, 16, 32}, std::is_same_v<typename M::Element, LegacyQuad> ? 0.06 : 0.01);
}

TEST_CASE("[estimate] a law with history: stresses kept at the Gauss points estimate as the linear law's") {
  using Plastic = Model<Axisym2, Quad4BBar, Hill<ReturnMapping>>;
  using Linear  = Model<Axisym2, Quad4BBar, Isotropic>;
  for (const int nr : {8, 32}) {
    const double height = 0.1 / nr * 2;
    NonlinearStatic<Plastic> plastic(tube_problem<Plastic>(nr, 2, height, 3.0));
    LinearStatic<Linear> linear(tube_problem<Linear>(nr, 2, height, 3.0));
    plastic.solve(), linear.solve();
    const double stored = plastic.error_estimate().relative(), elastic = linear.error_estimate().relative();
    const double truth = true_relative_error(linear, height);
    INFO("nr " << nr << ": stored " << stored << ", elastic " << elastic << ", true " << truth);
    // Both estimate from the stresses at the 2 x 2 points: they differ by Newton's tolerance only.
    CHECK(stored == doctest::Approx(elastic).epsilon(1e-3));
    CHECK(stored / truth >= 0.7);
    CHECK(stored / truth <= 1.5);
  }
}

TEST_CASE("[estimate] two materials bonded: each recovered on its own, and a skipped material has no share") {
  using M        = Model<Axisym2, Quad4, Isotropic>;
  const int nr   = 16;
  const double h = 0.1 / nr * 2;
  Problem<M> p   = tube_problem<M>(nr, 2, h);
  p.materials    = {M::Material::constant(kModulus, kPoisson), M::Material::constant(kModulus / 3, kPoisson)};
  p.mesh.cell_tags.resize(p.mesh.cells.size());
  const auto inner_r = [&](const auto& mesh, std::size_t e) { return mesh.nodes[mesh.cells[e][0]](0); };
  for (std::size_t e = 0; e < p.mesh.cells.size();
       ++e)  // the outer half soft: the hoop stress jumps at r = 0.15
    if (inner_r(p.mesh, e) >= 0.15 - 1e-12) p.mesh.cell_tags[e].material = 1;
  LinearStatic<M> fe(std::move(p));
  fe.solve();
  const ErrorEstimate both = fe.error_estimate();
  // A recovery across the interface would smear the jump over the two cells beside it, whose share would
  // dwarf the rest. Per material, the cells beside the interface are like any other.
  double beside = 0, elsewhere = 0;
  const auto& mesh = fe.problem().mesh;
  for (std::size_t e = 0; e < mesh.cells.size(); ++e) {
    const double from_interface = std::abs(inner_r(mesh, e) + 0.05 / nr - 0.15);  // the cell's centre
    double& largest             = from_interface < 0.1 / nr ? beside : elsewhere;
    largest                     = std::max(largest, both.cell[e]);
  }
  INFO("largest share beside the interface " << beside << ", elsewhere " << elsewhere);
  CHECK(beside < elsewhere);
  const ErrorEstimate inner = fe.error_estimate({1});
  for (std::size_t e = 0; e < mesh.cells.size(); ++e)
    if (mesh.cell_tag(e).material == 1) CHECK(inner.cell[e] == 0.0);
  CHECK(inner.error_squared < both.error_squared);
  CHECK(inner.energy_squared < both.energy_squared);
}

namespace {

/// Whether two recoveries' values are the same numbers, bit for bit.
void check_same_values(const std::vector<PointValues>& a, const std::vector<PointValues>& b) {
  REQUIRE(a.size() == b.size());
  int differing = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const PointValues &x = a[k], &y = b[k];
    const bool same = x.cell == y.cell && x.triangle == y.triangle && x.point == y.point && x.r == y.r &&
                      x.z == y.z && x.strain == y.strain && x.stress == y.stress && x.eqps == y.eqps &&
                      x.strain_material == y.strain_material && x.stress_material == y.stress_material;
    differing += same ? 0 : 1;
  }
  CHECK(differing == 0);
}

/// The tube with its outer half a second material and its last cell split into two triangles (a mixed mesh).
template <class M>
Problem<M> mixed_tube(int nr = 6, int nz = 2, double height = 0.04) {
  Problem<M> p = tube_problem<M>(nr, nz, height, 2.0);
  p.materials.push_back(p.materials.front());
  p.mesh.cell_tags.resize(p.mesh.cells.size());
  for (std::size_t e = 0; e < p.mesh.cells.size(); ++e)
    if (p.mesh.nodes[p.mesh.cells[e][0]](0) > 0.15) p.mesh.cell_tags[e].material = 1;
  const auto last = p.mesh.cells.back();
  p.mesh.cells.pop_back(), p.mesh.cell_tags.pop_back();
  p.mesh.triangles = {{last[0], last[1], last[2]}, {last[0], last[2], last[3]}};
  p.mesh.triangle_tags.assign(2, CellTag{1, {}});
  return p;
}

}  // namespace

TEST_CASE_TEMPLATE("[estimate] the centroid stresses of the estimate's pass are recover()'s, bit for bit", M,
                   Model<Axisym2, LegacyQuad, Isotropic>, Model<Axisym2, Quad4, Isotropic>,
                   Model<Axisym3, Quad4BBar, Isotropic>) {
  // A run takes the output's centroid stresses from the estimate's pass (one recovery per cell): they must be
  // what centroid_values() gives, for every cell, those of a skipped material too.
  LinearStatic<M> fe(mixed_tube<M>());
  fe.solve();
  for (const std::vector<int>& skip : {std::vector<int>{}, std::vector<int>{1}}) {
    std::vector<PointValues> centroids{PointValues{}};  // a stale value, which the call replaces
    const ErrorEstimate with = fe.error_estimate(skip, &centroids);
    check_same_values(centroids, fe.centroid_values(Recovered::stress));
    const ErrorEstimate alone = fe.error_estimate(skip);
    CHECK(with.error_squared == alone.error_squared);
    CHECK(with.cell == alone.cell);
  }
}

namespace {

/// Whether an estimate from the kept patch fit is the one fitted afresh, to round-off (the same least
/// squares, its solve taken before the stresses are known instead of after).
template <class MeshT>
void check_same_estimate(const ErrorEstimate& kept, const ErrorEstimate& afresh, const MeshT& mesh) {
  CHECK(kept.error_squared == doctest::Approx(afresh.error_squared).epsilon(1e-12));
  CHECK(kept.energy_squared == doctest::Approx(afresh.energy_squared).epsilon(1e-12));
  CHECK(kept.peak_mises == doctest::Approx(afresh.peak_mises).epsilon(1e-12));
  // A tie (the tube's row is the same at its top and its bottom) may go either way: the same radius.
  REQUIRE((kept.peak_node >= 0 && afresh.peak_node >= 0));
  CHECK(mesh.nodes[kept.peak_node](0) == doctest::Approx(mesh.nodes[afresh.peak_node](0)).epsilon(1e-12));
  REQUIRE(kept.cell.size() == afresh.cell.size());
  const double largest = *std::max_element(afresh.cell.begin(), afresh.cell.end());
  REQUIRE(largest > 0);
  double worst = 0;
  for (std::size_t e = 0; e < kept.cell.size(); ++e)
    worst = std::max(worst, std::abs(kept.cell[e] - afresh.cell[e]) / largest);
  CHECK(worst < 1e-10);
}

/// Three estimates through one kept fit, with the centroid stresses a run takes from the same pass: the first
/// fits its own stresses and notes the mesh (builds the weights, when `several`), the second builds the
/// weights, the third reuses them; each the estimate fitted afresh. `skips`: the left-out materials to try in
/// turn (a new skip starts again).
template <class Fe>
void check_kept_fit(const Fe& fe, RecoveryWeights& kept, std::initializer_list<std::vector<int>> skips) {
  for (const std::vector<int>& skip : skips) {
    const ErrorEstimate afresh              = fe.error_estimate(skip);
    const std::vector<PointValues> expected = fe.centroid_values(Recovered::stress);
    for (int call = 0; call < 3; ++call) {
      std::vector<PointValues> centroids;
      check_same_estimate(fe.error_estimate(skip, &centroids, &kept), afresh, fe.problem().mesh);
      check_same_values(centroids, expected);
      CHECK(kept.built == (call > 0 || kept.several));
    }
  }
}

}  // namespace

TEST_CASE_TEMPLATE("[estimate] the patch fit kept across a run's increments gives the estimate fitted afresh",
                   M, Model<Axisym2, LegacyQuad, Isotropic>, Model<Axisym2, Quad4, Isotropic>,
                   Model<Axisym3, Quad4BBar, Isotropic>) {
  // Two materials, a triangle among the quadrilaterals, and the second material left out (its cells then
  // give their centroids and take no weights).
  LinearStatic<M> fe(mixed_tube<M>());
  fe.solve();
  RecoveryWeights kept;
  check_kept_fit(fe, kept, {{}, {1}, {}});
  // A mesh changed in place is another mesh: a node moved, then a cell given the other material.
  fe.problem().mesh.nodes[8] += Vec2(1e-3, 5e-4);
  check_kept_fit(fe, kept, {{}});
  int& material = fe.problem().mesh.cell_tags[2].material;
  material      = 1 - material;
  check_kept_fit(fe, kept, {{}, {1}});
  // A run of several load steps builds the weights at its first estimate, and on each new mesh.
  RecoveryWeights at_once;
  at_once.several = true;
  check_kept_fit(fe, at_once, {{}, {1}});
  fe.problem().mesh.nodes[9] += Vec2(-1e-3, 5e-4);
  check_kept_fit(fe, at_once, {{}});
  CHECK(at_once.several);
}

TEST_CASE("[estimate] the kept fit of quadratic patches (Quad8), and of a law's stored stresses") {
  using M      = Model<Axisym2, Quad8, Isotropic>;
  Problem<M> p = tube_problem<M>(4, 2, 0.04, 2.0);
  p.materials.push_back(p.materials.front());
  p.mesh.cell_tags.resize(p.mesh.cells.size());
  for (std::size_t e = 0; e < p.mesh.cells.size(); ++e)
    if (p.mesh.nodes[p.mesh.cells[e][0]](0) > 0.15) p.mesh.cell_tags[e].material = 1;
  LinearStatic<M> fe(std::move(p));
  fe.solve();
  RecoveryWeights kept;
  check_kept_fit(fe, kept, {{}, {1}});

  using Plastic                   = Model<Axisym2, Quad4BBar, Hill<ReturnMapping>>;
  Problem<Plastic> plastic        = tube_problem<Plastic>(6, 2, 0.04, 2.0);
  plastic.materials.front().yield = HillYield::mises(250e6);  // yields at the bore (as the next case)
  plastic.edge_loads              = bore_pressure(plastic.mesh, 6, 2, 160e6);
  NonlinearStatic<Plastic> flowing(std::move(plastic));
  flowing.solve();
  RecoveryWeights other;
  check_kept_fit(flowing, other, {{}});
}

TEST_CASE("[estimate] the centroid stresses of the estimate's pass with stored stresses, bit for bit") {
  using Plastic      = Model<Axisym2, Quad4BBar, Hill<ReturnMapping>>;
  Problem<Plastic> p = tube_problem<Plastic>(6, 2, 0.04, 2.0);
  // The bore yields at 160 MPa (its Mises stress 369 MPa elastic); the limit pressure is 200 MPa.
  p.materials.front().yield = HillYield::mises(250e6);
  p.edge_loads              = bore_pressure(p.mesh, 6, 2, 160e6);
  NonlinearStatic<Plastic> fe(std::move(p));
  fe.solve();
  std::vector<PointValues> centroids;
  (void)fe.error_estimate({}, &centroids);
  check_same_values(centroids, fe.centroid_values(Recovered::stress));
  double eqps = 0;
  for (const PointValues& v : centroids) eqps = std::max(eqps, v.eqps);
  CHECK(eqps > 0);  // the values compared hold plastic flow
}

TEST_CASE("[estimate] a twisted shaft, which quad4 solves exactly: an estimate at round-off") {
  using M             = Model<Axisym3, Quad4, Isotropic>;
  const double radius = 0.05, length = 0.2, twist = 0.01;  // u_theta = twist r z [rad / m]
  Problem<M> p;
  p.mesh      = rectangle_mesh<4>(0.0, radius, 0.0, length, 6, 10);
  p.materials = {M::Material::constant(kModulus, kPoisson)};
  fix_plane(p.conditions, p.mesh, 0.0, 7, zero3);
  fix_plane(p.conditions, p.mesh, length, 4,
            [&](const Vec2& x) { return Vec3(0, 0, twist * x(0) * length); });
  LinearStatic<M> fe(std::move(p));
  fe.solve();
  const ErrorEstimate est = fe.error_estimate();
  CHECK(est.energy_squared > 0);
  CHECK(est.relative() < 1e-9);
}

namespace {

/// The true energy-norm error of a solved isoparametric model against a closed-form stress (rr, zz, hoop)
/// of r, integrated on 4 x 4 Gauss points per cell with the element's own strain there (B-bar's too), and
/// the solution's norm |u|^2 from the closed form on the same points. Returns |u - u_h| / |u|.
template <class M, class Exact>
double integrated_relative_error(const LinearStatic<M>& fe, const Exact& exact) {
  using Elem          = typename M::Element;
  using Kernel        = ElementKernel<typename M::Kinematics, Elem>;
  const auto& m       = fe.problem().mesh;
  const auto& u       = fe.solution().displacement;
  const Mat66 d       = fe.problem().materials[0].localize({}, 0.0, 0.0).stiffness;
  constexpr auto rule = gauss::square<4>();
  double error2 = 0, norm2 = 0;
  for (const auto& cell : m.cells) {
    Mat<Elem::kNodes, 2> x;
    typename Kernel::Vector ue;
    for (int a = 0; a < Elem::kNodes; ++a) {
      x.row(a) = m.nodes[cell[a]].transpose();
      for (int c = 0; c < Kernel::kDofsPerNode; ++c) ue(a * Kernel::kDofsPerNode + c) = u(cell[a], c);
    }
    const auto dilation = Kernel::dilatation(x);
    for (int q = 0; q < static_cast<int>(rule.weight.size()); ++q) {
      double det     = 0;
      const auto g   = Elem::at(x, rule.point[q][0], rule.point[q][1], rule.weight[q], det);
      const Vec6 h   = d * Kernel::strain(g, dilation, ue);
      const Vec<3> s = exact(g.r);
      const Vec<4> e = Vec<4>(s(0) - h(voigt::rr), s(1) - h(voigt::zz), s(2) - h(voigt::hoop), -h(voigt::rz));
      error2 += g.weight * complementary(e, kPoisson);
      norm2 += g.weight * complementary(Vec<4>(s(0), s(1), s(2), 0.0), kPoisson);
    }
  }
  return std::sqrt(error2 / norm2);
}

}  // namespace

TEST_CASE_TEMPLATE("[estimate] a spinning solid cylinder: effectivity within [0.7, 1.5], B-bar's too", M,
                   Model<Axisym2, Quad4, Isotropic>, Model<Axisym2, Quad4BBar, Isotropic>) {
  const double radius = 0.1, omega = 1000, density = 7850;
  const SpinningCylinder cylinder{radius, omega, density, kModulus, kPoisson};
  const auto exact = [&](double r) { return cylinder.stress(r); };
  for (const int nr : {8, 16, 32}) {
    Problem<M> p;
    const double height        = 2 * radius / nr;
    p.mesh                     = rectangle_mesh<4>(0.0, radius, 0.0, height, nr, 2);
    p.materials                = {M::Material::constant(kModulus, kPoisson, 0.0, density)};
    p.inertia.angular_velocity = omega;
    fix_plane(p.conditions, p.mesh, 0.0, 2, zero3);
    fix_plane(p.conditions, p.mesh, height, 2, zero3);
    LinearStatic<M> fe(std::move(p));
    fe.solve();
    const double estimate = fe.error_estimate().relative(), truth = integrated_relative_error(fe, exact);
    INFO("nr " << nr << ": estimate " << estimate << ", true " << truth);
    CHECK(estimate / truth >= 0.7);
    CHECK(estimate / truth <= 1.5);
    if (nr == 32) CHECK(std::abs(estimate / truth - 1) < 0.01);  // measured 0.999 for both
  }
}

TEST_CASE(
    "[estimate] Quad8 on the Lame tube: quadratic patches, effectivity within [0.7, 1.5] from 4 cells "
    "through "
    "the wall, [0.6, 1.5] at 2") {
  // From below towards 1 (measured 0.79, 0.88, 0.94, 0.97 at 4 to 32 cells uniform; 0.83 to 0.99 graded):
  // the recovery samples the 3 x 3 points, not Quad8's superconvergent 2 x 2. Two cells through the wall
  // lie before the asymptotic range: 0.65 uniform, 0.74 graded (0.76 and 0.80 before the element's
  // linear pressure, whose smaller true error there the estimate follows less closely).
  check_tube_effectivities<Model<Axisym2, Quad8, Isotropic>>({4, 8, 16, 32}, 0.05);
  for (const double grading : {1.0, 3.0}) {  // two cells: held to the looser bound they measure at
    using M = Model<Axisym2, Quad8, Isotropic>;
    LinearStatic<M> fe(tube_problem<M>(2, 2, 0.1, grading));
    fe.solve();
    const double ratio = fe.error_estimate().relative() / true_relative_error(fe, 0.1);
    INFO("2 cells, grading " << grading << ": effectivity " << ratio);
    CHECK(ratio >= 0.6);
    CHECK(ratio <= 1.5);
  }
}

TEST_CASE(
    "[estimate] a quadratic patch on a skewed cell reproduces a quadratic field; a plane patch a plane") {
  // One Quad8-like cell's 3 x 3 Gauss points on a parallelogram skewed 18 degrees (its scaled normal
  // matrix's determinant is about 5e-11, yet the fit is as well determined as on a square), about a corner.
  const double skew = 3, a = std::sqrt(0.6);
  const auto field = [](const Vec2& p) { return 1 + 2 * p(0) - 3 * p(1) + 0.5 * p(0) * p(0) - p(0) * p(1); };
  const Vec2 corner(10, 0);
  detail::PatchSums<1, 6> quadratic;
  detail::PatchSums<1, 3> plane;
  for (const double s : {-a, 0.0, a})
    for (const double t : {-a, 0.0, a}) {
      const Vec2 p = corner + Vec2(1 + s + skew * (1 + t), 1 + t) * 0.5;  // (xi, eta) -> the parallelogram
      quadratic.add(p - corner, Vec<1>(field(p)));
      plane.add(p - corner, Vec<1>(2 * p(0) - 3 * p(1)));
    }
  CHECK(quadratic.at_node()(0) == doctest::Approx(field(corner)).epsilon(1e-9));
  CHECK(plane.at_node()(0) == doctest::Approx(2 * corner(0) - 3 * corner(1)).epsilon(1e-12));
}

TEST_CASE_TEMPLATE("[estimate] the recovered peak stress on the Lame tube: at the bore, second order", M,
                   Model<Axisym2, Quad4, Isotropic>, Model<Axisym2, LegacyQuad, Isotropic>,
                   Model<Axisym2, Quad4BBar, Isotropic>) {
  // The bore's von Mises stress is the largest; the largest centroid's sits half a cell from it and
  // converges at first order, the nodes' recovered from the centroids (post/peak_stress.hpp) at second
  // (measured 1.6, 1.8, 1.9 over the halvings; triangles through the command: tests/check_error_bars.py).
  const Lame exact{0.1, 0.2, 100e6, kModulus, kPoisson};
  const Vec6 bore =
      (Vec6() << exact.radial_stress(0.1), exact.axial_stress(), exact.hoop_stress(0.1), 0, 0, 0).finished();
  const double truth = voigt::von_mises(bore);
  std::vector<double> recovered, centroid;
  for (const int nr : {4, 8, 16, 32}) {
    const double height = 0.1 / nr;  // square cells, two rows
    LinearStatic<M> fe(tube_problem<M>(nr, 2, 2 * height));
    fe.solve();
    const auto centroids    = fe.centroid_values(Recovered::stress);
    const PeakStress peak   = recovered_peak(fe.problem().mesh, centroids, -1);
    double largest_centroid = 0;
    for (const PointValues& v : centroids)
      largest_centroid = std::max(largest_centroid, voigt::von_mises(v.stress));
    REQUIRE(peak.node >= 0);
    CHECK(fe.problem().mesh.nodes[static_cast<std::size_t>(peak.node)](0) == doctest::Approx(0.1));
    recovered.push_back(std::abs(peak.mises - truth) / truth);
    centroid.push_back(std::abs(largest_centroid - truth) / truth);
  }
  for (std::size_t k = 1; k < recovered.size(); ++k) {
    const double order = std::log2(recovered[k - 1] / recovered[k]);
    MESSAGE("recovered peak error " << recovered[k] << " (order " << order << "), centroid's "
                                    << centroid[k]);
    CHECK(order > (k == 1 ? 1.5 : 1.75));                   // towards 2 as the mesh is refined
    CHECK(std::log2(centroid[k - 1] / centroid[k]) < 1.3);  // the centroid's: first order
  }
  CHECK(recovered.back() < 2e-3);
  CHECK(recovered.back() < centroid.back() / 5);
}

TEST_CASE("[estimate] the recovered peak at a boundary node reads its interior neighbours' planes") {
  // A field linear in r and z sampled at the centroids of a 3 x 2 grid of unit squares is recovered exactly
  // at every node, the boundary's too (each read of a neighbour's plane, or a corner's own), and a skipped
  // material's cells are no part of it.
  Mesh<4> mesh = rectangle_mesh<4>(1, 4, 0, 2, 3, 2);
  mesh.cell_tags.assign(mesh.cells.size(), CellTag{});
  std::vector<PointValues> centroids;
  const auto field = [](double r, double z) { return Vec6(1 + 2 * r - z, 0, 0, 0, 0, 0); };  // von Mises: |.|
  for (const auto& cell : mesh.cells) {
    Vec2 c = Vec2::Zero();
    for (const int n : cell) c += mesh.nodes[static_cast<std::size_t>(n)] / 4;
    PointValues v;
    v.r = c(0), v.z = c(1), v.stress = field(c(0), c(1));
    centroids.push_back(v);
  }
  PeakStress peak = recovered_peak(mesh, centroids, -1);
  REQUIRE(peak.node >= 0);
  const Vec2 at = mesh.nodes[static_cast<std::size_t>(peak.node)];
  CHECK(at(0) == doctest::Approx(4));  // the largest at r = 4, z = 0: 1 + 8 - 0 = 9
  CHECK(at(1) == doctest::Approx(0));
  CHECK(peak.mises == doctest::Approx(9).epsilon(1e-12));
  // The outer column another material, skipped: the largest is then on r = 3, still exact.
  for (std::size_t e = 0; e < mesh.cells.size(); ++e)
    if (centroids[e].r > 3) mesh.cell_tags[e].material = 1;
  peak = recovered_peak(mesh, centroids, 1);
  REQUIRE(peak.node >= 0);
  CHECK(mesh.nodes[static_cast<std::size_t>(peak.node)](0) == doctest::Approx(3));
  CHECK(peak.mises == doctest::Approx(7).epsilon(1e-12));
}

namespace {

/// One cell's stresses as the estimate takes them (CellPoints::stresses(): plain Quad4 with 2 DOF through its
/// bilinear fields, the others through the law restricted to the kinematics' strains) against the recovery's
/// (points(): the strain at each point into the law's full 6 x 6 update), on a distorted cell of a helically
/// wound orthotropic law with a thermal strain that has shear parts in the global axes.
template <class Kin, class E>
void check_estimate_stresses() {
  using Kernel = ElementKernel<Kin, E>;
  ElasticConstants c;
  c.E_N = 140e9, c.E_S = 10e9, c.E_T = 9e9, c.nu_NS = 0.3, c.nu_NT = 0.28, c.nu_ST = 0.4;
  c.G_NS = 5e9, c.G_ST = 3.5e9, c.G_TN = 4.5e9, c.alpha_N = -1e-6, c.alpha_S = 3e-5, c.alpha_T = 2e-5;
  const ElasticPoint lp = Orthotropic::constant(c).localize({0.3, 0.5}, 120, 20);
  REQUIRE(lp.thermal_strain.tail<2>().norm() > 1e-5);  // shear in the global axes, which Axisym2 leaves out
  Mat<E::kNodes, 2> x;  // a distorted cell, with a quadratic cell's middle nodes off the chords
  if constexpr (E::kNodes >= 4) x.template topRows<4>() << 0.50, 0.10, 0.82, 0.05, 0.90, 0.41, 0.47, 0.36;
  if constexpr (E::kNodes == 8) x.template bottomRows<4>() << 0.66, 0.09, 0.86, 0.22, 0.69, 0.40, 0.49, 0.22;
  if constexpr (E::kNodes == 3 || E::kNodes == 6)
    x.template topRows<3>() << 0.50, 0.10, 0.82, 0.05, 0.70, 0.41;
  if constexpr (E::kNodes == 6) x.template bottomRows<3>() << 0.66, 0.09, 0.75, 0.22, 0.61, 0.24;
  typename Kernel::Vector ue;
  for (int i = 0; i < ue.size(); ++i) ue(i) = 1e-4 * std::sin(1.0 + 0.7 * i);
  const ElasticStress<Orthotropic> source;
  const CellPoints<Kin, E, ElasticPoint, ElasticStress<Orthotropic>> values(x, lp, InertiaLoad{}, ue, source,
                                                                            0, false, 0, Recovered::stress);
  const auto fast = values.stresses();
  const auto all  = values.points();
  for (int q = 0; q < E::kStiffnessPoints; ++q) {
    const Vec<Kin::kStrain> reference = Kernel::restrict(all.value[q].stress);
    CHECK((fast.stress[q] - reference).norm() <= 1e-12 * reference.norm());
    CHECK(std::abs(fast.position[q](0) - all.value[q].r) <= 1e-14);
    CHECK(std::abs(fast.position[q](1) - all.value[q].z) <= 1e-14);
    CHECK(std::abs(fast.weight[q] - all.weight[q]) <= 1e-13 * all.weight[q]);
  }
}

}  // namespace

TEST_CASE("[estimate] the estimate's point stresses are the recovery's, to round-off (1e-12)") {
  check_estimate_stresses<Axisym2, Quad4>();  // the bilinear fields
  check_estimate_stresses<Axisym3, Quad4>();  // the restricted law from here on
  check_estimate_stresses<Axisym2, Quad4BBar>();
  check_estimate_stresses<Axisym2, Quad8>();
  check_estimate_stresses<Axisym3, Quad8>();
  check_estimate_stresses<Axisym2, Tri3>();
  check_estimate_stresses<Axisym3, Tri6>();
}

TEST_CASE_TEMPLATE(
    "[threads] a linear run on 1 or 3 threads: stiffness, displacements, stresses and estimate "
    "the same bit for bit",
    M, Model<Axisym2, LegacyQuad, Isotropic>, Model<Axisym2, Quad4, Isotropic>) {
  // 100 x 84 cells, two materials and a pair of triangles: several tasks and two rounds of the cell loops
  // (assembly/cell_blocks.hpp). A stiffness entry or a patch sum added in another order than the cells'
  // would differ in its last bits between the runs (cells of one node fall in different tasks along
  // every task's edge), and so would everything solved from it.
  const Problem<M> p = mixed_tube<M>(100, 84, 0.4);
  REQUIRE(p.mesh.cells.size() * 576 > kRoundBytes);  // two rounds of 576 B slots (8 x 8 and 8 doubles)
  struct Run {
    std::vector<double> stiffness;
    Eigen::MatrixX3d u;
    std::vector<PointValues> centroids, estimate_centroids;
    ErrorEstimate fresh, kept;
  };
  const auto run = [&](int threads) {
    set_worker_threads(threads);
    LinearStatic<M> fe(p);
    Run r;
    r.u            = fe.solve().displacement;
    const SpMat& k = fe.stiffness();
    r.stiffness    = std::vector<double>(k.valuePtr(), k.valuePtr() + k.nonZeros());
    r.centroids    = fe.centroid_values();
    r.fresh        = fe.error_estimate();
    RecoveryWeights kept;
    kept.several = true;  // the weighted sums too
    r.kept       = fe.error_estimate({}, &r.estimate_centroids, &kept);
    return r;
  };
  const Run one = run(1), three = run(3);
  set_worker_threads(1);
  CHECK(one.stiffness == three.stiffness);
  CHECK(one.u == three.u);
  check_same_values(one.centroids, three.centroids);
  check_same_values(one.estimate_centroids, three.estimate_centroids);
  for (const auto& [a, b] : {std::pair(one.fresh, three.fresh), std::pair(one.kept, three.kept)}) {
    CHECK(a.error_squared == b.error_squared);
    CHECK(a.energy_squared == b.energy_squared);
    CHECK(a.cell == b.cell);
    CHECK(a.peak_node == b.peak_node);
  }
  CHECK(one.fresh.relative() > 0);
}

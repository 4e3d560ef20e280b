// Material laws: rotations (docs/theory.md 3.2-3.3), orthotropic compliance, temperature tables, thermal
// strain, validation. References are closed forms written out here, not the code's own output.
#include "support.hpp"

using namespace gapfe;
using test::rel;

namespace {
ElasticConstants fibre() {  // a carbon-epoxy-like ply: N = fibre
  ElasticConstants c;
  c.E_N = 140e9, c.E_S = 10e9, c.E_T = 9e9;
  c.nu_NS = 0.3, c.nu_NT = 0.28, c.nu_ST = 0.4;
  c.G_NS = 5e9, c.G_ST = 3.5e9, c.G_TN = 4.5e9;
  c.alpha_N = -0.5e-6, c.alpha_S = 30e-6, c.alpha_T = 28e-6;
  return c;
}
}  // namespace

TEST_CASE("[material] T_eps = T_sigma^-T and both are orthogonal-like for any BETA, ALPHA") {
  for (double beta : {0.0, 0.3, 1.1, -2.0})
    for (double alpha : {0.0, 0.5, -0.9}) {
      const Mat33 q = material_axes({beta, alpha});
      CHECK((q * q.transpose() - Mat33::Identity()).norm() < 1e-14);
      const Mat66 ts = stress_rotation(q), te = strain_rotation(ts);
      CHECK((te.transpose() * ts - Mat66::Identity()).norm() < 1e-13);
    }
}

TEST_CASE("[material] explicit ALPHA = 0 strain rotation (docs/theory.md 3.3)") {
  const double beta = 0.37, s = std::sin(beta), c = std::cos(beta);
  const Mat66 te = strain_rotation(stress_rotation(material_axes({beta, 0.0})));
  Vec6 e;
  e << 1e-3, -2e-3, 0.5e-3, 0.7e-3, -0.3e-3, 0.9e-3;  // [rr, zz, tt, rz, z-theta, theta-r]
  const Vec6 m = te * e;                              // [NN, SS, TT, NS, ST, TN]
  CHECK(m(0) == doctest::Approx(s * s * e(0) + c * c * e(1) + s * c * e(3)).epsilon(1e-13));
  CHECK(m(2) == doctest::Approx(c * c * e(0) + s * s * e(1) - s * c * e(3)).epsilon(1e-13));
  CHECK(m(1) == doctest::Approx(e(2)).epsilon(1e-13));
  CHECK(m(3) == doctest::Approx(s * e(5) + c * e(4)).epsilon(1e-13));
  CHECK(m(4) == doctest::Approx(-c * e(5) + s * e(4)).epsilon(1e-13));
  CHECK(m(5) == doctest::Approx(2 * s * c * (e(1) - e(0)) + (s * s - c * c) * e(3)).epsilon(1e-13));
}

TEST_CASE(
    "[material] orthotropic: compliance inverse, reciprocity, no in-plane/torsion coupling at ALPHA = 0") {
  const Orthotropic m = Orthotropic::constant(fibre());
  const auto p0       = m.localize({0.4, 0.0}, 0, 0);
  CHECK(p0.stiffness.topRightCorner<4, 2>().norm() < 1e-13 * p0.stiffness.norm());
  const auto p1 = m.localize({0.4, 0.5}, 0, 0);
  CHECK(p1.stiffness.topRightCorner<4, 2>().norm() > 1e-3 * p1.stiffness.norm());  // helical: coupled
  CHECK((p1.stiffness - p1.stiffness.transpose()).norm() < 1e-12 * p1.stiffness.norm());
  // Uniaxial sigma_N in material axes gives eps_S = -nu_NS sigma / E_N (Jones' convention).
  const Mat66 s = fibre().compliance();
  Vec6 sig      = Vec6::Zero();
  sig(0)        = 1e8;
  const Vec6 e  = s * sig;
  CHECK(rel(e(0), 1e8 / 140e9) < 1e-14);
  CHECK(rel(e(1), -0.3 * 1e8 / 140e9) < 1e-14);
  CHECK(rel(e(2), -0.28 * 1e8 / 140e9) < 1e-14);
  // Rotating the fibre into the hoop direction (BETA = 90 deg, ALPHA = 90 deg: N = theta) puts E_N in C(tt).
  const auto ph  = m.localize({std::numbers::pi / 2, std::numbers::pi / 2}, 0, 0);
  const Mat66 sh = ph.stiffness.inverse();
  CHECK(rel(1 / sh(voigt::hoop, voigt::hoop), 140e9) < 1e-10);
}

TEST_CASE("[material] isotropic equals orthotropic with equal constants, in any frame") {
  const auto iso = Isotropic::constant(200e9, 0.3, 12e-6).localize({}, 150, 50);
  const auto ortho =
      Orthotropic::constant(ElasticConstants::isotropic(200e9, 0.3, 12e-6)).localize({0.7, 0.4}, 150, 50);
  CHECK((iso.stiffness - ortho.stiffness).norm() < 1e-12 * iso.stiffness.norm());
  CHECK((iso.thermal_strain - ortho.thermal_strain).norm() < 1e-15);
  CHECK(rel(iso.thermal_strain(voigt::hoop), 12e-6 * 100) < 1e-14);
}

TEST_CASE("[material] temperature table: linear interpolation, constant outside, free-strain input") {
  Isotropic m;
  m.table.rows             = {ElasticConstants::isotropic(200e9, 0.30, 11e-6, 20),
                              ElasticConstants::isotropic(180e9, 0.32, 13e-6, 220),
                              ElasticConstants::isotropic(150e9, 0.34, 14e-6, 420)};
  const ElasticConstants c = m.table.at(120);
  CHECK(rel(c.E_N, 190e9) < 1e-14);
  CHECK(rel(c.nu_NS, 0.31) < 1e-14);
  CHECK(rel(m.table.at(320).E_N, 165e9) < 1e-14);
  CHECK(m.table.at(-100).E_N == 200e9);
  CHECK(m.table.at(1000).E_N == 150e9);
  // Coefficients: eps = alpha(T) (T - T_ref).
  CHECK(rel(m.localize({}, 120, 20).thermal_strain(0), 12e-6 * 100) < 1e-13);
  // Free strain: eps = e(T) - e(T_ref).
  m.table.thermal         = ThermalInput::free_strain;
  m.table.rows[0].alpha_N = m.table.rows[0].alpha_S = m.table.rows[0].alpha_T = 0.0;
  m.table.rows[1].alpha_N = m.table.rows[1].alpha_S = m.table.rows[1].alpha_T = 2e-3;
  CHECK(rel(m.localize({}, 120, 20).thermal_strain(voigt::zz), 1e-3) < 1e-13);
  CHECK(m.localize({}, 120, 20).thermal_strain(voigt::rz) == 0.0);
}

TEST_CASE("[material] orthotropic thermal strain maps to global axes with shear parts (docs/theory.md 3.4)") {
  const double beta = 0.5, s = std::sin(beta), c = std::cos(beta), dT = 100;
  const auto p    = Orthotropic::constant(fibre()).localize({beta, 0.0}, dT, 0);
  const double aN = -0.5e-6 * dT, aT = 28e-6 * dT, aS = 30e-6 * dT;
  // N = (s, c) and T = (-c, s) in (r, z): eps_g = aN N N^T + aT T T^T, engineering rz shear doubled.
  CHECK(rel(p.thermal_strain(voigt::rr), aN * s * s + aT * c * c) < 1e-12);
  CHECK(rel(p.thermal_strain(voigt::zz), aN * c * c + aT * s * s) < 1e-12);
  CHECK(rel(p.thermal_strain(voigt::hoop), aS) < 1e-12);
  CHECK(rel(p.thermal_strain(voigt::rz), 2 * s * c * (aN - aT)) < 1e-12);
}

TEST_CASE("[material] validation names the material and the problem") {
  ElasticConstants bad = fibre();
  bad.nu_NS            = 5.0;  // |nu_NS| >= sqrt(E_N / E_S) = 3.74
  CHECK_THROWS_WITH_AS(Orthotropic::constant(bad).validate("material 2"), doctest::Contains("material 2"),
                       InputError);
  CHECK_THROWS_AS(Isotropic::constant(200e9, 0.5).validate("m"), InputError);
  CHECK_THROWS_AS(Isotropic::constant(-1, 0.3).validate("m"), InputError);
  CHECK_NOTHROW(Isotropic::constant(200e9, 0.4999).validate("m"));
  Isotropic unsorted;
  unsorted.table.rows = {ElasticConstants::isotropic(2e11, 0.3, 0, 100),
                         ElasticConstants::isotropic(2e11, 0.3, 0, 50)};
  CHECK_THROWS_WITH_AS(unsorted.validate("m"), doctest::Contains("increase"), InputError);
}

TEST_CASE(
    "[material] validation refuses exactly the Poisson's ratios whose compliance is not positive definite") {
  // The reference: the normal block's smallest eigenvalue, from Eigen's eigen-solver, against validate()'s
  // closed-form condition, over ratios of either sign up to 3.8 (past the pairwise bounds), on moduli that
  // tell every ratio and every modulus apart (E_S > E_T and E_S < E_T) and on equal moduli (isotropic: nu in
  // (-1, 0.5) is admissible, 0.5 itself is not).
  const std::array<Vec3, 3> moduli = {Vec3(140e9, 10e9, 9e9), Vec3(140e9, 9e9, 10e9), Vec3(70e9, 70e9, 70e9)};
  int refused = 0, accepted = 0, on_boundary = 0;
  for (const Vec3& e : moduli)
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 20; ++j)
        for (int k = 0; k < 20; ++k) {
          ElasticConstants m = fibre();
          m.E_N = e(0), m.E_S = e(1), m.E_T = e(2);
          m.nu_NS = -3.8 + 0.4 * i, m.nu_NT = -3.8 + 0.4 * j, m.nu_ST = -3.8 + 0.4 * k;
          const Mat33 normal    = m.compliance().topLeftCorner<3, 3>();
          const double smallest = Eigen::SelfAdjointEigenSolver<Mat33>(normal).eigenvalues().minCoeff();
          if (std::abs(smallest) < 1e-9 * normal.norm()) {  // on the boundary: round-off decides
            ++on_boundary;
            continue;
          }
          bool threw = false;
          try {
            m.validate("m");
          } catch (const InputError&) {
            threw = true;
          }
          CHECK_MESSAGE(threw == (smallest < 0), "nu = ", m.nu_NS, ", ", m.nu_NT, ", ", m.nu_ST,
                        ", E = ", e.transpose());
          (threw ? refused : accepted) += 1;
        }
  CHECK(refused > 1000);
  CHECK(accepted > 100);
  CHECK(on_boundary < 100);  // 28: equal moduli with a ratio of -1 or 1 (a singular 2 x 2 block)
  CHECK_THROWS_AS(Isotropic::constant(200e9, 0.5).validate("m"), InputError);  // the limit itself
  CHECK_NOTHROW(Isotropic::constant(200e9, -0.9).validate("m"));
  ElasticConstants infinite = fibre();
  infinite.E_S              = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(Orthotropic::constant(infinite).validate("m"), InputError);
  // The stiffness is the compliance's inverse.
  CHECK((fibre().stiffness() * fibre().compliance() - Mat66::Identity()).norm() < 1e-13);
}

TEST_CASE("[material] temperature field from (r, z, T) points: exact at nodes, bounded, constant") {
  const auto m = rectangle_mesh<4>(0.1, 0.2, 0, 0.1, 2, 2);
  std::vector<TemperaturePoint> at_nodes;
  for (const auto& x : m.nodes) at_nodes.push_back({x(0), x(1), 100 + 1000 * x(0) - 500 * x(1)});
  const VecX t = nodal_temperatures(m, at_nodes);
  for (int n = 0; n < m.node_count(); ++n)
    CHECK(t(n) == doctest::Approx(100 + 1000 * m.nodes[n](0) - 500 * m.nodes[n](1)).epsilon(1e-14));
  const VecX two = nodal_temperatures(m, {{0.1, 0.0, 20}, {0.2, 0.1, 220}});
  CHECK(two.minCoeff() >= 20);
  CHECK(two.maxCoeff() <= 220);
  CHECK(two(0) == 20.0);
  CHECK(constant_temperature(m, 75).isConstant(75));
  CHECK_THROWS_AS(nodal_temperatures(m, {}), InputError);
  CHECK_THROWS_AS(nodal_temperatures(m, {{0.1, 0.0, std::nan("")}}), InputError);
}

TEST_CASE("[material] card 6 IANG/NANG: ALPHA alternates in sign every NANG cells along I") {
  const double a = 0.5;
  for (int i = 0; i < 6; ++i) CHECK(helical_frame(0.1, a, 0, 0, i).alpha == a);  // IANG = 0: constant
  const std::array<double, 6> every2{a, a, -a, -a, a, a};
  for (int i = 0; i < 6; ++i) {
    CHECK(helical_frame(0.1, a, 1, 2, i).alpha == every2[i]);
    CHECK(helical_frame(0.1, a, 1, 2, i).beta == 0.1);
    CHECK(helical_frame(0.1, a, 1, 1, i).alpha == (i % 2 ? -a : a));
  }
  CHECK_THROWS_WITH_AS(helical_frame(0, a, 1, 0, 0), doctest::Contains("NANG"), InputError);
  CHECK_THROWS_AS(helical_frame(0, a, 2, 1, 0), InputError);
}

// Hill plasticity (material/hill.hpp) and the Newton driver (driver/nonlinear_static.hpp), against
// closed forms: uniaxial and shear yield, von Mises equivalence, the Bauschinger shift, the thick tube
// (first yield, elastic-plastic radius, limit pressure, THEORY.md V6), the fully plastic shaft, and
// Newton's quadratic rate.
#include <cmath>
#include <sstream>

#include "gapfe/driver/nonlinear_static.hpp"
#include "gapfe/material/hill.hpp"

#include "support.hpp"

namespace gapfe::test {
namespace {

constexpr double kE = 200e3, kNu = 0.3;  // MPa; stresses in MPa, lengths in m below

/// One material point driven in strain along global Voigt slot `k`, every other stress held at zero
/// (a uniaxial-stress or pure-shear test), by Newton on the free strains with the law's tangent.
template <class Law>
struct PointDriver {
  typename Law::Local local;
  typename Law::State state{};
  int k       = 0;
  Vec6 stress = Vec6::Zero();

  /// Move the controlled strain to `target` in `steps` equal increments; returns the stress history.
  std::vector<double> to(double target, int steps) {
    std::vector<double> out;
    const double start = state.strain(k);
    for (int s = 1; s <= steps; ++s) {
      Vec6 eps = state.strain;
      eps(k)   = start + (target - start) * s / steps;
      PointResponse<typename Law::State> r;
      for (int it = 0; it < 50; ++it) {
        r       = Law::update(local, eps, state, {});
        Vec6 rs = r.stress;
        rs(k)   = 0;
        if (rs.norm() <= 1e-12 * (1 + r.stress.norm())) break;
        // Free strains: D_ff d_eps_f = -sigma_f.
        Mat<5, 5> d;
        Vec<5> f;
        for (int i = 0, ii = 0; i < 6; ++i) {
          if (i == k) continue;
          f(ii) = -rs(i);
          for (int j = 0, jj = 0; j < 6; ++j)
            if (j != k) d(ii, jj++) = r.tangent(i, j);
          ++ii;
        }
        const Vec<5> de = d.fullPivLu().solve(f);
        for (int i = 0, ii = 0; i < 6; ++i)
          if (i != k) eps(i) += de(ii++);
      }
      state  = r.state;
      stress = r.stress;
      out.push_back(stress(k));
    }
    return out;
  }
};

/// Distinct yield stresses so that a mix-up of directions cannot pass.
HillYield anisotropic_yield() {
  return {300.0, 400.0, 500.0, 150.0, 200.0, 250.0, 0.0, PragerShear::legacy};
}

template <class Integration>
Hill<Integration> hill(const HillYield& y, double E = kE, double nu = kNu) {
  return {Orthotropic::constant(ElasticConstants::isotropic(E, nu)), y};
}

TEST_CASE_TEMPLATE("Hill: uniaxial and shear stress yield at the card's yield stresses, by axis pair",
                   Integration, ReturnMapping, Tangent) {
  // beta = alpha = 0: N = +z, S = +theta, T = -r (material/orientation.hpp). So global zz, hoop and rr
  // test X, Y, Z; the shears z-theta (NS), theta-r (ST = TS) and rz (TN = NT) test R_NS, R_TS, R_NT.
  const HillYield y = anisotropic_yield();
  const auto law    = hill<Integration>(y);
  const auto local  = law.localize({}, 0.0, 0.0);
  struct Case {
    int slot;
    double yield;
    const char* what;
  };
  for (const Case c : {Case{voigt::zz, y.X, "N (zz)"}, Case{voigt::hoop, y.Y, "S (hoop)"},
                       Case{voigt::rr, y.Z, "T (rr)"}, Case{voigt::z_theta, y.R_NS, "NS (z-theta)"},
                       Case{voigt::theta_r, y.R_TS, "TS (theta-r)"}, Case{voigt::rz, y.R_NT, "NT (rz)"}}) {
    CAPTURE(c.what);
    const bool shear     = c.slot >= 3;
    const double modulus = shear ? kE / (2 * (1 + kNu)) : kE;
    for (double sign : {1.0, -1.0}) {
      PointDriver<Hill<Integration>> d{local, {}, c.slot};
      // Elastic up to 0.9 of the yield strain, exactly.
      d.to(sign * 0.9 * c.yield / modulus, 9);
      CHECK(rel(d.stress(c.slot), sign * 0.9 * c.yield) < 1e-12);
      CHECK_FALSE(d.state.plastic);
      // Past yield (perfectly plastic): the stress stays at the yield stress.
      d.to(sign * 5 * c.yield / modulus, 40);
      CHECK(d.state.plastic);
      const double tolerance = std::is_same_v<Integration, ReturnMapping> ? 1e-10 : 2e-2;  // Tangent drifts
      CHECK(rel(d.stress(c.slot), sign * c.yield) < tolerance);
      CHECK(d.state.eqps > 0);
    }
  }
}

TEST_CASE("Hill: the elastic-plastic transition inside one Tangent step is found exactly") {
  // One step from zero to twice the yield strain: the elastic fraction r = 1/2 is solved for, then the
  // forward-Euler part; with c = 0 and uniaxial N the stress after the step must be on the surface
  // within the first-order error of one step, and the first yield point exactly where the card says.
  const auto law = hill<Tangent>(anisotropic_yield());
  const Mat66 p  = anisotropic_yield().yield_matrix();
  Vec6 xi0       = Vec6::Zero();
  Vec6 d         = Vec6::Zero();
  d(0)           = 2.0 * 300.0;  // material NN, twice the yield stress
  CHECK(detail::elastic_fraction(p, xi0, d) == doctest::Approx(0.5).epsilon(1e-14));
  xi0(0) = 150.0;
  CHECK(detail::elastic_fraction(p, xi0, d) == doctest::Approx(0.25).epsilon(1e-14));
  (void)law;
}

TEST_CASE("Hill with equal yield stresses and sigma_y / sqrt(3) in shear is von Mises") {
  const double sy = 400;
  const auto law  = hill<ReturnMapping>(HillYield::mises(sy));
  // Any frame: the criterion is isotropic, so a rotated frame must not change it.
  const auto local = law.localize({0.4, 0.3}, 0.0, 0.0);
  std::srand(7);
  for (int t = 0; t < 100; ++t) {
    const Vec6 s       = 300 * Vec6::Random();
    const double mises = std::sqrt(0.5 * ((s(0) - s(1)) * (s(0) - s(1)) + (s(1) - s(2)) * (s(1) - s(2)) +
                                          (s(2) - s(0)) * (s(2) - s(0))) +
                                   3 * (s(3) * s(3) + s(4) * s(4) + s(5) * s(5)));
    CHECK(Hill<ReturnMapping>::yield_ratio(local, s, {}) == doctest::Approx(mises / sy).epsilon(1e-12));
  }
}

TEST_CASE_TEMPLATE("Kinematic hardening: a tension-compression cycle shows the closed-form Bauschinger shift",
                   Integration, ReturnMapping, Tangent) {
  // Mises (equal yields), Prager c: uniaxial back stress beta = (3/2) c eps_p, so the plastic slope is
  // H' = 3c/2, the tangent modulus E_t = E H' / (E + H'), and reverse yield comes at sigma_max - 2 sigma_y
  // (the elastic range along the loading line stays 2 sigma_y wide).
  const double sy = 400, c = 20e3, h = 1.5 * c, et = kE * h / (kE + h);
  const auto law = hill<Integration>(HillYield::mises(sy, c));
  PointDriver<Hill<Integration>> d{law.localize({}, 0.0, 0.0), {}, voigt::zz};
  const double eps_y = sy / kE, eps_1 = 5 * eps_y;
  d.to(eps_1, 200);
  const double s_max = sy + et * (eps_1 - eps_y);
  const double tol   = std::is_same_v<Integration, ReturnMapping> ? 1e-10 : 1e-3;
  CHECK(rel(d.stress(voigt::zz), s_max) < tol);
  // Unload: elastic until sigma_max - 2 sigma_y, at eps_r = eps_1 - 2 sigma_y / E.
  const double eps_r = eps_1 - 2 * sy / kE;
  d.to(eps_r + 0.05 * eps_y, 100);
  CHECK_FALSE(d.state.plastic);
  CHECK(rel(d.stress(voigt::zz), s_max - 2 * sy + 0.05 * sy) < 1e-9);
  d.to(-4 * eps_y, 300);
  CHECK(d.state.plastic);
  const double s_rev = s_max - 2 * sy + et * (-4 * eps_y - eps_r);
  CHECK(rel(d.stress(voigt::zz), s_rev) < tol);
  MESSAGE(Integration::kName << ": reverse stress " << d.stress(voigt::zz) << " MPa, closed form " << s_rev);
}

TEST_CASE_TEMPLATE(
    "Reverse yielding inside one step: a big unloading step crosses the elastic range and yields",
    Integration, ReturnMapping, Tangent) {
  // Mises, perfectly plastic, uniaxial along N: at +sigma_y (plastic), one step of -3 sigma_y / E strain.
  // Elastic over 2 sigma_y / E, then reverse plastic flow: the stress ends at -sigma_y, not at -2 sigma_y
  // outside the surface.
  const double sy = 400;
  const auto law  = hill<Integration>(HillYield::mises(sy));
  PointDriver<Hill<Integration>> d{law.localize({}, 0.0, 0.0), {}, voigt::zz};
  d.to(2 * sy / kE, 20);
  REQUIRE(d.state.plastic);
  d.to(2 * sy / kE - 3 * sy / kE, 1);
  CHECK(d.state.plastic);
  CHECK(rel(d.stress(voigt::zz), -sy) < 1e-9);
}

TEST_CASE("ReturnMapping's consistent tangent matches finite differences") {
  HillYield y  = anisotropic_yield();
  y.hardening  = 5e3;
  const auto p = hill<ReturnMapping>(y).localize({0.3, 0.2}, 0.0, 0.0);
  HillState old;
  old.plastic_strain << 1e-3, -4e-4, -6e-4, 2e-4, -1e-4, 3e-4;
  old.back_stress = p.hardening_matrix * old.plastic_strain;
  old.strain      = old.plastic_strain;
  Vec6 eps        = old.strain;
  eps << 4e-3, -1e-3, -2e-3, 1e-3, 5e-4, -8e-4;
  const auto r = Hill<ReturnMapping>::update(p, eps, old, {});
  REQUIRE(r.yielded);
  CHECK(std::abs(Hill<ReturnMapping>::yield_ratio(p, r.stress, r.state) - 1) < 1e-12);
  Mat66 fd;
  for (int j = 0; j < 6; ++j) {
    const double hstep = 1e-8;
    Vec6 e1 = eps, e2 = eps;
    e1(j) += hstep, e2(j) -= hstep;
    fd.col(j) = (Hill<ReturnMapping>::update(p, e1, old, {}).stress -
                 Hill<ReturnMapping>::update(p, e2, old, {}).stress) /
                (2 * hstep);
  }
  CHECK((fd - r.tangent).norm() / r.tangent.norm() < 1e-6);
}

// ------------------------------------------------------------------------------ thick tube (V6)

/// Plane-strain thick tube a..b, Mises, elastic-perfectly plastic: Quad4-family mesh, one cell high,
/// u_z = 0 everywhere, bore pressure or bore displacement.
template <class M>
struct PlasticTube {
  double a = 0.1, b = 0.2, sy = 400, nu = 0.49;
  int nr       = 40;
  double ratio = 1.03;  // radial grading, small cells at the bore where yield starts

  Problem<M> problem() const {
    Problem<M> p;
    p.mesh      = rectangle_mesh<M::Element::kNodes>(a, b, 0, 0.005, nr, 1, ratio);
    p.materials = {{Orthotropic::constant(ElasticConstants::isotropic(kE, nu)), HillYield::mises(sy)}};
    for (int n = 0; n < p.mesh.node_count(); ++n) p.conditions.push_back({n, 2, {}});
    return p;
  }
  void set_pressure(Problem<M>& p, double pressure) const {
    p.edge_loads = bore_pressure(p.mesh, nr, 1, pressure);
  }
  /// Bore displacement control: u_r = value on the bore nodes (code 3: r and z fixed).
  void set_bore_displacement(Problem<M>& p, double u) const {
    p.conditions.clear();
    for (int n = 0; n < p.mesh.node_count(); ++n) {
      const bool bore = std::abs(p.mesh.nodes[n](0) - a) < 1e-12;
      p.conditions.push_back({n, bore ? 3 : 2, {bore ? u : 0.0, 0, 0}});
    }
  }
  /// Bore pressure from the radial reactions: p = sum R_r / (2 pi a h) (the rig pushes the bore out).
  double bore_pressure_from(const NonlinearStatic<M>& fe) const {
    double f = 0;
    for (int n = 0; n < fe.problem().mesh.node_count(); ++n)
      if (std::abs(fe.problem().mesh.nodes[n](0) - a) < 1e-12) f += fe.solution().reaction(n, 0);
    return f / (kTwoPi * a * 0.005);
  }

  /// Mises first-yield pressure with sigma_z = 2 nu A (elastic plane strain; V1): Mises stress at r = a
  /// is linear in p.
  double first_yield() const {
    const Lame l{a, b, 1.0, kE, nu};
    const double sr = l.radial_stress(a), st = l.hoop_stress(a), sz = l.axial_stress();
    return sy / std::sqrt(0.5 * ((sr - st) * (sr - st) + (st - sz) * (st - sz) + (sz - sr) * (sz - sr)));
  }
  /// Pressure with the plastic zone out to rho, assuming sigma_z = (sigma_r + sigma_theta) / 2 in both
  /// zones (exact for nu = 1/2; Hill 1950): Tresca's formula with sigma_y -> 2 sigma_y / sqrt(3).
  double pressure_at(double rho) const {
    return 2 / std::sqrt(3.0) * sy * (std::log(rho / a) + (b * b - rho * rho) / (2 * b * b));
  }
  double limit() const { return 2 / std::sqrt(3.0) * sy * std::log(b / a); }
};

/// The elastic-plastic boundary: where the yield ratio of the elastic points, extrapolated linearly
/// from the two innermost ones, reaches 1.
template <class M>
double plastic_radius(const NonlinearStatic<M>& fe) {
  std::vector<std::pair<double, double>> elastic;  // (r, yield ratio)
  const auto values = fe.point_values();
  const auto& law   = fe.problem().materials[0];
  const auto local  = law.localize({}, 0.0, 0.0);
  for (std::size_t q = 0; q < values.size(); ++q)
    if (!fe.states()[q].plastic)
      elastic.emplace_back(values[q].r, M::Material::yield_ratio(local, values[q].stress, fe.states()[q]));
  std::sort(elastic.begin(), elastic.end());
  // Points come in pairs at equal r (2 x 2 Gauss); take two distinct radii.
  const auto first = elastic.front();
  auto second      = elastic.front();
  for (const auto& e : elastic)
    if (e.first > first.first + 1e-9) {
      second = e;
      break;
    }
  const double slope = (second.second - first.second) / (second.first - first.first);
  return first.first + (1 - first.second) / slope;
}

TEST_CASE("Thick tube, plane strain, ReturnMapping: first yield, plastic radius and limit pressure") {
  using M = Model<Axisym2, Quad4BBar, Hill<ReturnMapping>>;
  const PlasticTube<M> tube;
  NonlinearStatic<M> fe(tube.problem());
  auto& p = fe.problem();

  // First yield: the elastic response is linear, so the pressure at which the bore reaches f = 1
  // follows from one elastic step: the yield ratio sqrt(f) of the two innermost Gauss radii, extrapolated
  // linearly to r = a (the closed form is a bore value; the nearest point sits 0.3 mm inside the wall).
  const double p_probe = 0.5 * tube.first_yield();
  tube.set_pressure(p, p_probe);
  fe.solve();
  CHECK(fe.report().plastic_points == 0);
  const auto local = p.materials[0].localize({}, 0.0, 0.0);
  std::vector<std::pair<double, double>> ratio;  // (r, sqrt f)
  for (const auto& v : fe.point_values())
    ratio.emplace_back(v.r, M::Material::yield_ratio(local, v.stress, {}));
  std::sort(ratio.begin(), ratio.end());
  const auto inner = ratio.front();
  const auto next =
      *std::find_if(ratio.begin(), ratio.end(), [&](auto& x) { return x.first > inner.first + 1e-9; });
  const double at_bore =
      inner.second + (tube.a - inner.first) * (next.second - inner.second) / (next.first - inner.first);
  const double p_y_fe = p_probe / at_bore;
  MESSAGE("first yield " << p_y_fe << " MPa, closed form " << tube.first_yield());
  CHECK(rel(p_y_fe, tube.first_yield()) < 0.01);
  fe.reject();

  // Plastic radius against pressure, 2%.
  double applied = 0;
  for (const double rho : {0.12, 0.15, 0.18}) {
    const double target = tube.pressure_at(rho);
    const int steps     = 8;
    const double from   = applied;
    for (int s = 1; s <= steps; ++s) {
      tube.set_pressure(p, from + (target - from) * s / steps);
      fe.solve();
      REQUIRE(fe.report().converged);
      fe.commit();
    }
    applied           = target;
    const double r_fe = plastic_radius(fe);
    MESSAGE("p = " << target << " MPa: plastic radius " << r_fe << " m, closed form " << rho);
    CHECK(rel(r_fe, rho) < 0.02);
  }
}

TEST_CASE(
    "Thick tube: the pressure approaches the limit (2/sqrt 3) sigma_y ln(b/a) under bore displacement") {
  using M = Model<Axisym2, Quad4BBar, Hill<ReturnMapping>>;
  const PlasticTube<M> tube;
  Problem<M> problem = tube.problem();
  tube.set_bore_displacement(problem, 0.0);
  NonlinearStatic<M> fe(problem);
  const double u_y = tube.first_yield() / kE * tube.a * 1.5;  // about the first-yield bore displacement
  double pressure  = 0;
  for (int s = 1; s <= 40; ++s) {
    tube.set_bore_displacement(fe.problem(), 20 * u_y * s / 40);
    fe.solve();
    REQUIRE(fe.report().converged);
    fe.commit();
    pressure = tube.bore_pressure_from(fe);
  }
  MESSAGE("bore pressure at 20 x u_y: " << pressure << " MPa; limit " << tube.limit());
  CHECK(pressure < tube.limit() * 1.02);
  CHECK(rel(pressure, tube.limit()) < 0.02);
}

TEST_CASE(
    "Locking: the plane-strain limit pressure with Quad4, Quad4BBar and Quad8 (which element plastic decks "
    "need)") {
  // Fully plastic flow is isochoric: plain Quad4 locks and overshoots the limit pressure; B-bar and Quad8
  // do not. The measured errors decide the default element of plastic decks (quad4bbar).
  std::ostringstream table;
  const auto limit_error = [&](auto element, const char* name) {
    using M = Model<Axisym2, decltype(element), Hill<ReturnMapping>>;
    PlasticTube<M> tube;
    tube.nr            = 20;
    Problem<M> problem = tube.problem();
    tube.set_bore_displacement(problem, 0.0);
    NonlinearStatic<M> fe(problem);
    const double u_y = tube.first_yield() / kE * tube.a * 1.5;
    for (int s = 1; s <= 20; ++s) {
      tube.set_bore_displacement(fe.problem(), 20 * u_y * s / 20);
      fe.solve();
      fe.commit();
    }
    const double error = (tube.bore_pressure_from(fe) - tube.limit()) / tube.limit();
    table << "\n  " << name << ": limit pressure error " << error;
    return error;
  };
  const double quad4 = limit_error(Quad4{}, "Quad4"), bbar = limit_error(Quad4BBar{}, "Quad4BBar"),
               quad8 = limit_error(Quad8{}, "Quad8");
  MESSAGE("20 cells across the thick tube, nu = 0.49:" << table.str());
  CHECK(std::abs(bbar) < 0.02);
  CHECK(std::abs(quad8) < 0.02);
  CHECK(quad4 > 2 * std::abs(bbar));  // locking: plain Quad4 is stiffer and farther off
}

TEST_CASE("ReturnMapping: Newton converges quadratically (the residuals of a plastic step)") {
  using M = Model<Axisym2, Quad4BBar, Hill<ReturnMapping>>;
  const PlasticTube<M> tube;
  NewtonOptions o;
  o.tolerance = 1e-12;  // the round-off floor of this nu = 0.49 system is about 3e-13
  NonlinearStatic<M> fe(tube.problem(), {}, o);
  tube.set_pressure(fe.problem(), 0.9 * tube.first_yield());
  fe.solve();
  fe.commit();
  tube.set_pressure(fe.problem(), tube.pressure_at(0.15));  // one big plastic step
  fe.solve();
  const auto& r = fe.report().residuals;
  std::ostringstream s;
  for (double x : r) s << " " << x;
  MESSAGE("residuals:" << s.str());
  // Quadratic: r_k+1 <= K r_k^2 once r_k <= 5e-2, with K = 10 (relative residuals, dimensionless). A
  // linearly converging iteration (factor q) fails it as soon as r_k < q / K. At least two such pairs.
  int checked = 0;
  for (std::size_t k = 1; k < r.size(); ++k) {
    if (r[k - 1] > 5e-2) continue;
    CAPTURE(k);
    CHECK(r[k] <= 10 * r[k - 1] * r[k - 1]);
    ++checked;
  }
  CHECK(checked >= 2);
}

TEST_CASE("Thick tube with the seed's Tangent scheme at 10, 50 and 200 steps: error against step count") {
  // Pressure ramped to p(rho = 0.15) = 288.3 MPa. Errors of the bore displacement against ReturnMapping
  // (Newton, 1e-10) on the same mesh, and of the plastic radius against the closed form. The tangent
  // scheme is first order: the error must fall with the step count, roughly in proportion.
  const auto run = [](auto integration, int steps, double& radius) {
    using M = Model<Axisym2, Quad4BBar, Hill<decltype(integration)>>;
    const PlasticTube<M> tube;
    NonlinearStatic<M> fe(tube.problem());
    for (int s = 1; s <= steps; ++s) {
      tube.set_pressure(fe.problem(), tube.pressure_at(0.15) * s / steps);
      fe.solve();
      fe.commit();
    }
    radius = plastic_radius(fe);
    return fe.solution().displacement(0, 0);
  };
  double radius          = 0;
  const double reference = run(ReturnMapping{}, 50, radius);
  std::vector<double> errors;
  std::ostringstream table;
  for (const int steps : {10, 50, 200}) {
    const double u = run(Tangent{}, steps, radius);
    errors.push_back(rel(u, reference));
    table << "\n  Tangent " << steps << " steps: bore u error " << errors.back() << ", plastic radius "
          << radius << " (closed form 0.15)";
  }
  MESSAGE("thick tube, Tangent against ReturnMapping:" << table.str());
  CHECK(errors[1] < errors[0]);
  CHECK(errors[2] < errors[1]);
  CHECK(errors[2] < 0.01);
}

// ------------------------------------------------------------------------------ shaft in torsion

TEST_CASE_TEMPLATE("Solid shaft in torsion past yield (SAGA): the torque approaches (2 pi / 3) tau_y R^3",
                   Integration, ReturnMapping, Tangent) {
  using M        = Model<Axisym3, Quad4, Hill<Integration>>;
  const double R = 0.05, L = 0.02, sy = 400, tau_y = sy / std::sqrt(3.0), G = kE / (2 * (1 + kNu));
  const int nr = 20;
  Problem<M> p;
  p.mesh      = rectangle_mesh<4>(0, R, 0, L, nr, 1);
  p.materials = {{Orthotropic::constant(ElasticConstants::isotropic(kE, kNu)), HillYield::mises(sy)}};
  const double twist_y = tau_y / (G * R) * L;  // end rotation at first yield [rad]
  const auto set_twist = [&](Problem<M>& q, double phi) {
    q.conditions.clear();
    fix_plane(q.conditions, q.mesh, 0, 7, zero3);  // base: all fixed
    fix_plane(q.conditions, q.mesh, L, 6, [&](const Vec2& x) { return Vec3(0, 0, phi * x(0)); });
  };
  set_twist(p, 0);
  NonlinearStatic<M> fe(p);
  const int steps = std::is_same_v<Integration, ReturnMapping> ? 20 : 200;
  double torque   = 0;
  for (int s = 1; s <= steps; ++s) {
    set_twist(fe.problem(), 10 * twist_y * s / steps);
    fe.solve();
    fe.commit();
  }
  for (int n = 0; n < fe.problem().mesh.node_count(); ++n)
    if (std::abs(fe.problem().mesh.nodes[n](1) - L) < 1e-12)
      torque += fe.solution().reaction(n, dof::theta) * fe.problem().mesh.nodes[n](0);
  // Elastic-perfectly plastic shaft: T = T_p (1 - (phi_y / phi)^3 / 4), at 10 phi_y 0.99975 T_p.
  const double t_p = 2 * std::numbers::pi / 3 * tau_y * R * R * R * 1e6;  // MPa m^3 -> N m
  const double t   = t_p * (1 - 0.25e-3);
  MESSAGE(Integration::kName << ": torque " << torque * 1e6 << " N m at 10 x first-yield twist; closed form "
                             << t << " (fully plastic " << t_p << ")");
  CHECK(rel(torque * 1e6, t) < 0.02);
}

}  // namespace
}  // namespace gapfe::test

namespace gapfe::test {
namespace {

TEST_CASE("SAAC = SAGAEP + gaps: a plastic tube pressed across a gap onto an elastic one, in equilibrium") {
  // Inner tube a..b (Mises sigma_y = 250 MPa) inside an elastic outer tube b + delta..c across a column of
  // soft gap elements, plane strain, bore pressure ramped past closure and past first yield of the inner
  // tube. Checked: the gap closes and the inner tube yields in the same run; every increment is in
  // equilibrium to 1e-8 (Newton's residual over all DOFs, contact links included); the outer tube, elastic
  // and loaded only through the closed pairs, has the bore displacement Lame gives for the contact pressure
  // those pairs carry (1%).
  using M        = Model<Axisym2, Quad4BBar, Hill<ReturnMapping>>;
  const double a = 0.05, b = 0.075, c = 0.1, delta = 20e-6, E = 200e3, nu = 0.3, h = 0.001;
  const int n_in = 30, n_out = 30;
  std::vector<double> r;
  for (int i = 0; i <= n_in; ++i) r.push_back(a + (b - a) * i / n_in);
  for (int i = 0; i <= n_out; ++i) r.push_back(b + delta + (c - b - delta) * i / n_out);
  const int ni = static_cast<int>(r.size());
  Problem<M> p;
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i < ni; ++i) p.mesh.nodes.push_back({r[i], j * h});
  std::vector<GapPair> pairs;
  for (int i = 0; i + 1 < ni; ++i) {
    const std::array<int, 4> ix{i, i + 1, ni + i + 1, ni + i};
    p.mesh.cells.push_back(ix);
    const int material = i < n_in ? 0 : i == n_in ? 1 : 2;
    p.mesh.cell_tags.push_back({material, {}});
    if (i == n_in)
      for (const auto& g : gap_element_pairs(static_cast<int>(p.mesh.cells.size() - 1), ix, 1, p.mesh.nodes))
        pairs.push_back(g);
  }
  const auto elastic = [](double modulus, double poisson) {
    return Orthotropic::constant(ElasticConstants::isotropic(modulus, poisson));
  };
  p.materials = {{elastic(E, nu), HillYield::mises(250)}, {elastic(1e-9 * E, 0.0), {}}, {elastic(E, nu), {}}};
  for (int n = 0; n < p.mesh.node_count(); ++n) p.conditions.push_back({n, 2, {}});
  ContactOptions options;
  options.gap_materials = {1};
  ContactStatic<M, Saac> contact(std::move(p), pairs, options);
  const double p_max                             = 200;  // MPa: closure near 36.6, inner yield near 80
  const ContactStatic<M, Saac>::LoadsAt loads_at = [&](Problem<M>& q, double t) {
    q.edge_loads = {{ni, 0, p_max * t / 20, 0, 0}};
  };
  double worst_residual                            = 0;
  const ContactStatic<M, Saac>::OnIncrement record = [&](double, const ContactStatic<M, Saac>& s) {
    worst_residual = std::max(worst_residual, s.fe().solution().residual);
  };
  for (int step = 1; step <= 20; ++step) contact.advance(step, loads_at, record);
  const auto& fe = contact.fe();
  CHECK(fe.report().plastic_points > 0);
  double closed = 0, force = 0;
  for (std::size_t q = 0; q < pairs.size(); ++q)
    closed += contact.states()[q].closed, force += contact.states()[q].normal_force;
  CHECK(closed == pairs.size());
  MESSAGE("plastic points " << fe.report().plastic_points << ", worst residual " << worst_residual);
  CHECK(worst_residual <= 1e-8);
  const double q_contact = force / (kTwoPi * b * h);  // pairs carry total ring forces
  const double u_outer   = fe.solution().displacement(n_in + 1, 0);
  const double u_lame    = Lame{b + delta, c, q_contact, E, nu}.displacement(b + delta);
  MESSAGE("contact pressure " << q_contact << " MPa; outer bore u " << u_outer << ", Lame " << u_lame);
  CHECK(rel(u_outer, u_lame) < 0.01);
}

}  // namespace
}  // namespace gapfe::test

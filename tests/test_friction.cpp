// Friction at gap pairs (contact/friction.hpp, docs/theory.md 6): the push-out and the slip torque of
// a press fit against their closed forms, no spurious friction, the seed's two models, Newton's
// convergence with the unsymmetric tangent, the tangential penalty sweep and friction with plasticity.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "gapfe/solver/eigen_lu.hpp"

#include "contact_support.hpp"

namespace gapfe::test {
namespace {

using Lu2   = Model<Axisym2, Quad4, Isotropic, EigenLu>;
using Lu3   = Model<Axisym3, Quad4, Isotropic, EigenLu>;
using Ldlt2 = Model<Axisym2, Quad4, Isotropic, EigenLdlt>;
using Ldlt3 = Model<Axisym3, Quad4, Isotropic, EigenLdlt>;

ContactOptions fit_options(const PressFit& fit) {
  ContactOptions o;
  o.gap_materials = {1};
  o.friction      = fit.mu;
  return o;
}

/// One accepted point of a path: load factor, push force and torque on the ring, worst slip-cone error.
struct PathPoint {
  double t = 0, force = 0, torque = 0;
};

/// The fit's standard path: the pressure ramps over t in [0, 1] (one step), then `motion(t)` (push or
/// twist) over `steps` equal steps up to t_end. Returns every accepted point after the pressure.
template <class CS>
std::vector<PathPoint> run_path(CS& cs, const PressFit& fit, const std::function<double(double)>& push,
                                const std::function<double(double)>& twist, double t_end, int steps) {
  using P          = std::decay_t<decltype(cs.fe().problem())>;
  const auto loads = [&](P& p, double t) { fit.set(p, std::min(t, 1.0), push(t), twist(t)); };
  std::vector<PathPoint> out;
  cs.advance(1.0, loads);
  for (int k = 1; k <= steps; ++k) {
    const double t = 1 + (t_end - 1) * k / steps;
    cs.advance(t, loads);
    const auto& s = cs.fe().solution();
    out.push_back({t, fit.push_force(s), fit.torque(cs.fe().problem(), s)});
  }
  return out;
}

double none(double) {
  return 0;
}

}  // namespace

TEST_CASE_TEMPLATE("friction: a press fit pushed out slides at mu p 2 pi b L, flat, and back at minus it",
                   Policy, ActiveSet, AugmentedLagrangian) {
  const PressFit fit;
  std::vector<GapPair> pairs;
  auto problem = fit.problem<Lu2>(pairs);
  ContactStatic<Lu2, Policy, Coulomb> cs(std::move(problem), pairs, fit_options(fit));
  const double d  = 2e-6;  // push amplitude [m]: up to +d, then down to -d (a hysteresis loop)
  const auto push = [&](double t) { return t <= 1 ? 0.0 : t <= 2 ? d * (t - 1) : d * (3 - t); };
  const auto path = run_path(cs, fit, push, none, 4.0, 30);
  const double f  = fit.slip_force();
  MESSAGE(Policy::kName, ": closed-form slip force ", f, " N, push-out force at the first push step ",
          path.front().force, ", at the top ", path[7].force, ", at the bottom ", path.back().force);
  double lo = 1e300, hi = -1e300;
  for (const auto& pt : path) {
    if (pt.t > 1.2 && pt.t <= 2) {  // sliding up: the plateau
      CHECK(rel(pt.force, f) < 0.01);
      lo = std::min(lo, pt.force), hi = std::max(hi, pt.force);
    }
    if (pt.t > 2.5) CHECK(rel(pt.force, -f) < 0.01);  // sliding back
  }
  CHECK(hi - lo < 1e-6 * f);  // flat after slip
  // Every closed pair slips at the end, with its force on the cone: |t| = mu P.
  for (const auto& s : cs.states()) {
    REQUIRE(s.closed);
    CHECK(s.slipping);
    CHECK(std::abs(s.tangential_force.norm() - fit.mu * s.normal_force) <= 1e-9 * fit.mu * s.normal_force);
  }
}

TEST_CASE("friction: a press fit twisted (SAGA) slips at the torque mu p 2 pi b^2 L") {
  const PressFit fit;
  std::vector<GapPair> pairs;
  auto problem = fit.problem<Lu3>(pairs);
  ContactStatic<Lu3, ActiveSet, Coulomb> cs(std::move(problem), pairs, fit_options(fit));
  const double phi = 1e-4;  // rotation of the ring [rad]
  const auto path  = run_path(
       cs, fit, none, [&](double t) { return t <= 1 ? 0.0 : phi * (t - 1); }, 2.0, 10);
  MESSAGE("closed-form slip torque ", fit.slip_torque(), " N m, computed ", path.back().torque);
  for (const auto& pt : path)
    if (pt.t > 1.2) CHECK(rel(pt.torque, fit.slip_torque()) < 0.01);
  CHECK(std::abs(path.back().force) < 1e-9 * fit.slip_force());  // a twist pushes nothing along z
}

TEST_CASE("friction: nothing loads the gap tangentially, so friction changes nothing") {
  // Shaft held at its bottom, ring at its top, nu = 0: the pressure closes the fit without any slide.
  PressFit fit;
  fit.drive      = PressFit::Drive::ends;
  const auto run = [&]<class Friction>(std::type_identity<Friction>, double mu) {
    std::vector<GapPair> pairs;
    auto problem       = fit.problem<Lu2>(pairs);
    ContactOptions opt = fit_options(fit);
    opt.friction       = mu;
    // The augmented Lagrangian's moderate penalty: with 1e4 x the adjacent stiffness (active-set), the
    // round-off of the radial solve alone gives tangential forces of ~5e-6 of the normal ones.
    ContactStatic<Lu2, AugmentedLagrangian, Friction> cs(std::move(problem), pairs, opt);
    cs.advance(1.0, [&](Problem<Lu2>& p, double t) { fit.set(p, t, 0); });
    double tangential = 0, normal = 0, closed_at = 2;
    for (const auto& s : cs.states()) {
      tangential = std::max(tangential, s.tangential_force.norm()), normal = std::max(normal, s.normal_force);
      closed_at = std::min(closed_at, s.closed_at);
    }
    return std::tuple{Eigen::MatrixXd(cs.fe().solution().displacement), closed_at, tangential, normal};
  };
  const auto [u0, closed0, t0, n0] = run(std::type_identity<NoFriction>{}, 0.0);
  const auto [u1, closed1, t1, n1] = run(std::type_identity<Coulomb>{}, 0.3);
  const auto [u2, closed2, t2, n2] = run(std::type_identity<Coulomb>{}, 0.0);
  REQUIRE(n0 > 0);
  MESSAGE("closure at load factor ", closed0, " (frictionless), ", closed1,
          " (mu = 0.3); max |t| / max P = ", t1 / n1);
  CHECK(t1 < 1e-6 * n1);
  CHECK(std::abs(closed1 - closed0) < 1e-9);
  CHECK((u1 - u0).cwiseAbs().maxCoeff() < 1e-8 * u0.cwiseAbs().maxCoeff());
  CHECK((u2 - u0).cwiseAbs().maxCoeff() < 1e-10 * u0.cwiseAbs().maxCoeff());  // mu = 0: frictionless
  CHECK(std::abs(closed2 - closed0) < 1e-12);
}

TEST_CASE("friction: proportional (SAACFR) puts mu k along T and S of every closed pair, with no limit") {
  PressFit fit;
  fit.tilt = 0.5;  // a conical fit: N and T are not along r and z
  std::vector<GapPair> pairs;
  auto problem = fit.problem<Ldlt3>(pairs);
  ContactStatic<Ldlt3, Saac, Proportional> cs(std::move(problem), pairs, fit_options(fit));
  const double d = 5e-6;
  // Pushed along -z, which presses the conical fit closed (N has a +z part).
  const auto path = run_path(
      cs, fit, [&](double t) { return t <= 1 ? 0.0 : -d * (t - 1); }, none, 2.0, 4);
  int closed = 0;
  for (int p = 0; p < cs.pair_count(); ++p) {
    if (!cs.states()[p].closed) continue;
    ++closed;
    const Vec2 n = pairs[p].normal;
    Mat33 rotation;  // rows N, T, S (seed Eq. 5)
    rotation << n(0), n(1), 0, -n(1), n(0), 0, 0, 0, 1;
    const Mat33 local = rotation * cs.link(p).stiffness * rotation.transpose();
    const double k    = cs.penalty(p);
    Mat33 expected    = Mat33::Zero();
    expected.diagonal() << k, fit.mu * k, fit.mu * k;
    CHECK((local - expected).cwiseAbs().maxCoeff() < 1e-12 * k);
    // No slip limit: the tangential force is mu k times the slide since closure, far beyond mu P.
    const PairState& s = cs.states()[p];
    CHECK(s.tangential_force.norm() > fit.mu * s.normal_force);
  }
  CHECK(closed == cs.pair_count());
  MESSAGE("push force with proportional springs after a push of ", d, " m: ", path.back().force, " N");
}

TEST_CASE(
    "friction: extended (seed 3.2) switches pairs from stick to slip; its overshoot against the step count") {
  // The ring pushed at its top face along an elastic shaft held at its bottom: the element stresses
  // around the pairs carry the shear the seed's check reads.
  // One row of elements (nz = 1): both pairs have the same two real elements around them, whose mean
  // shear is the interface's friction, so the check compares the fit's own shear with mu p.
  PressFit fit;
  fit.drive      = PressFit::Drive::ends;
  fit.nz         = 1;
  const double d = 5e-5;
  std::vector<double> errors;
  for (const int steps : {10, 20, 40, 80}) {
    std::vector<GapPair> pairs;
    auto problem = fit.problem<Ldlt2>(pairs);
    ContactStatic<Ldlt2, Saac, Extended> cs(std::move(problem), pairs, fit_options(fit));
    bool stuck_after_closure = true;
    const auto loads         = [&](Problem<Ldlt2>& p, double t) {
      fit.set(p, std::min(t, 1.0), t <= 1 ? 0 : -d * (t - 1));
    };
    cs.advance(1.0, loads);
    for (const auto& s : cs.states()) stuck_after_closure = stuck_after_closure && s.closed;
    double peak = 0, sum_normal = 0;
    int switched = 0;
    for (int k = 1; k <= steps; ++k) {
      cs.advance(1.0 + static_cast<double>(k) / steps, loads);
      peak = std::max(peak, std::abs(fit.push_force(cs.fe().solution())));
    }
    for (const auto& s : cs.states()) switched += s.slipping, sum_normal += s.normal_force;
    CHECK(stuck_after_closure);
    CHECK(switched > 0);
    const double error = (peak - fit.mu * sum_normal) / (fit.mu * sum_normal);
    errors.push_back(error);
    MESSAGE("extended, ", steps, " push steps: ", switched, " of ", cs.pair_count(),
            " pairs slipping; peak push force ", peak, " N against mu sum P = ", fit.mu * sum_normal,
            " N (closed form ", fit.slip_force(), "): overshoot ", 100 * error, " %");
  }
}

namespace {

/// Whether a Newton record shows quadratic convergence: the contraction q_k = r_{k+1} / r_k itself
/// contracts quadratically somewhere, q_{k+1} <= 10 q_k^2 with q_k < 0.1. Linear convergence at a
/// constant rate c fails both ways (c <= 10 c^2 needs c >= 0.1).
bool quadratic(const std::vector<double>& r) {
  for (std::size_t k = 0; k + 2 < r.size(); ++k) {
    const double q0 = r[k + 1] / r[k], q1 = r[k + 2] / r[k + 1];
    if (q0 < 0.1 && r[k + 2] > 1e-15 && q1 <= 10 * q0 * q0) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("friction: Newton with the unsymmetric Coulomb tangent converges quadratically on a slip step") {
  // SAGA, nu = 0.3 (slip changes the normal forces: the dt/dP coupling): the ring pushed at its top
  // and twisted, the twist growing faster than the push, so the slip direction turns in every step and
  // Newton has work to do (a fit sliding straight on is linear from one step to the next, one solve).
  PressFit fit;
  fit.drive      = PressFit::Drive::ring;
  const auto run = [&](bool symmetric, double nu) {
    fit.nu = nu;
    std::vector<GapPair> pairs;
    auto problem                = fit.problem<Lu3>(pairs);
    ContactOptions opt          = fit_options(fit);
    opt.symmetric_tangent       = symmetric;
    opt.max_friction_iterations = 200;
    ContactStatic<Lu3, ActiveSet, Coulomb> cs(std::move(problem), pairs, opt);
    const auto loads = [&](Problem<Lu3>& p, double t) {
      const double x = std::max(t - 1, 0.0);
      fit.set(p, std::min(t, 1.0), -1e-5 * x, 4e-4 * x * x);
    };
    cs.advance(1.0, loads);
    std::vector<double> longest;
    int iterations = 0;
    for (int k = 1; k <= 8; ++k) {
      cs.reset_counters();
      cs.advance(1.0 + k / 8.0, loads);
      iterations += cs.counters().friction_iterations;
      if (cs.friction_residuals().size() > longest.size()) longest = cs.friction_residuals();
    }
    int slipping = 0;
    for (const auto& s : cs.states()) slipping += s.slipping;
    return std::tuple{longest, iterations, slipping};
  };
  const auto record = [](const std::vector<double>& r) {
    std::string text;
    char x[32];
    for (double v : r) std::snprintf(x, sizeof x, " %.2e", v), text += x;
    return text;
  };
  const auto [lu, lu_iterations, lu_slipping] = run(false, 0.3);
  MESSAGE("unsymmetric tangent, nu = 0.3: ", lu_iterations,
          " extra solves in 8 push-and-twist steps; longest record:", record(lu));
  CHECK(lu_slipping > 0);
  CHECK(quadratic(lu));
  CHECK(lu.back() <= 1e-10);
  // The tangent without the slip's unsymmetric coupling (what a symmetric solver gets): linear
  // convergence, more solves, the same answer.
  const auto [sym, sym_iterations, sym_slipping] = run(true, 0.3);
  MESSAGE("symmetrized tangent, nu = 0.3: ", sym_iterations,
          " extra solves in 8 push-and-twist steps; longest record:", record(sym));
  CHECK(sym_slipping == lu_slipping);
  CHECK(sym_iterations > lu_iterations);
  CHECK_FALSE(quadratic(sym));
}

TEST_CASE_TEMPLATE("friction: pressed and pushed in the same step, then pushed off (the example deck's path)",
                   Policy, ActiveSet, AugmentedLagrangian) {
  // examples/decks/press_fit.deck: the pressure and the first push increment ramp together, so pairs
  // close one by one while the fit already slides. Newton must get through the closures (each pair
  // linearized on the branch of the return mapping it is predicted to end on) and reach the plateau
  // mu sum P. tests/check_friction_family.py runs this path and its variants (pressure and push in every
  // order, other elements, 1 to 200 steps) through the command. With events = step-end the step is not
  // split at the closures: the statuses settle at its end.
  PressFit fit;
  fit.drive = PressFit::Drive::ends;
  std::vector<GapPair> pairs;
  auto problem           = fit.problem<Lu2>(pairs);
  ContactOptions options = fit_options(fit);
  std::string events     = "locate";
  SUBCASE("events = locate") {}
  SUBCASE("events = step-end") {
    events = "step-end", options.locate_events = false;
  }
  ContactStatic<Lu2, Policy, Coulomb> cs(std::move(problem), pairs, options);
  const double step = 1e-6;  // push per step [m]
  const auto loads  = [&](Problem<Lu2>& p, double t) { fit.set(p, std::min(t, 1.0), -step * t); };
  double force      = 0;
  for (int k = 1; k <= 40; ++k) {
    cs.advance(k, loads);
    force = -fit.push_force(cs.fe().solution());
  }
  double sum = 0;
  for (const auto& s : cs.states()) sum += s.normal_force;
  MESSAGE(Policy::kName, ", events = ", events, ": push-out force after 40 um ", force, " N; mu sum P ",
          fit.mu * sum, "; closed form ", fit.slip_force(), "; linear solves ", cs.counters().solves,
          " (friction re-solves ", cs.counters().friction_iterations, ", stalls ",
          cs.counters().friction_stalls, ", halved ", cs.counters().cuts, ")");
  CHECK(rel(force, fit.mu * sum) < 1e-3);
  CHECK(rel(force, fit.slip_force()) < 0.01);
}

TEST_CASE_TEMPLATE("contact events = step-end: a tapered fit closing row by row ends where locate ends",
                   Policy, ActiveSet, AugmentedLagrangian) {
  // Frictionless and elastic, the end state does not depend on the path: settling the statuses at the
  // step's end must reach the split-at-every-closure answer (to the penalty solution's round-off), in
  // fewer solves. The ring's bore is tapered (the gap grows from w at z = 0 to 11 w at z = L, all below
  // the gap the pressure closes), so the pairs close row by row, at distinct loads.
  PressFit fit;
  fit.drive      = PressFit::Drive::ends;
  const auto run = [&](bool locate) {
    std::vector<GapPair> pairs;
    auto problem = fit.problem<Ldlt2>(pairs);
    auto& mesh   = problem.mesh;
    for (int n = 0; n < mesh.node_count(); ++n)
      if (fit.ring_node(n)) mesh.nodes[n](0) += 10 * fit.w * (n / fit.columns()) / fit.nz;
    pairs.clear();
    for (std::size_t e = 0; e < mesh.cells.size(); ++e)
      if (mesh.cell_tags[e].material == 1)
        for (const GapPair& g : gap_element_pairs(static_cast<int>(e), mesh.cells[e], 1, mesh.nodes))
          pairs.push_back(g);
    ContactOptions options = fit_options(fit);
    options.friction       = 0;
    options.locate_events  = locate;
    ContactStatic<Ldlt2, Policy> cs(std::move(problem), pairs, options);
    for (int k = 1; k <= 2; ++k) cs.advance(k, [&](Problem<Ldlt2>& p, double t) { fit.set(p, t / 2, 0); });
    int closed = 0;
    for (const auto& s : cs.states()) closed += s.closed;
    return std::tuple{Eigen::MatrixXd(cs.fe().solution().displacement), cs.counters().solves,
                      cs.counters().splits, closed, static_cast<int>(pairs.size())};
  };
  const auto [u_locate, solves_locate, splits, closed_locate, pairs] = run(true);
  const auto [u_end, solves_end, no_splits, closed_end, pairs_end]   = run(false);
  MESSAGE(Policy::kName, ": locate ", solves_locate, " solves (", splits, " split points), step-end ",
          solves_end, " solves; ", closed_end, " of ", pairs, " pairs closed");
  REQUIRE(splits > 5);  // the pairs do close row by row
  CHECK(no_splits == 0);
  CHECK(closed_end == pairs);
  CHECK(closed_locate == pairs);
  CHECK((u_end - u_locate).cwiseAbs().maxCoeff() < 1e-9 * u_locate.cwiseAbs().maxCoeff());
  CHECK(solves_end < solves_locate);
}

TEST_CASE_TEMPLATE("friction: tangential penalty sweep 1e1 to 1e12 x the adjacent stiffness", Policy,
                   ActiveSet, AugmentedLagrangian) {
  PressFit fit;
  std::string table = std::string(Policy::kName) +
                      ": factor, stick slide / ring displacement, slip force error, "
                      "friction solves\n";
  for (double factor = 1e1; factor <= 1e12; factor *= 10) {
    // Stick: the ring pushed at its top by about a tenth of what would slide it; exact stick slides nothing.
    fit.drive = PressFit::Drive::ends;
    std::vector<GapPair> pairs;
    auto problem                  = fit.problem<Lu2>(pairs);
    ContactOptions opt            = fit_options(fit);
    opt.tangential_penalty_factor = factor;
    ContactStatic<Lu2, Policy, Coulomb> stick(std::move(problem), pairs, opt);
    const double push = 3e-7;
    std::vector<Vec2> pressed;  // slides after the pressure
    try {
      stick.advance(1.0, [&](Problem<Lu2>& p, double t) { fit.set(p, t, 0); });
      for (const auto& s : stick.states()) pressed.push_back(s.slide);
      stick.advance(2.0, [&](Problem<Lu2>& p, double t) { fit.set(p, 1.0, -push * (t - 1)); });
    } catch (const SolveError& e) {
      // A penalty this large makes the stiffness numerically singular: refused, never a wrong answer.
      CHECK(std::is_same_v<Policy, ActiveSet>);
      CHECK(factor >= 1e9);
      table += "   factor " + std::to_string(factor) + ": refused (" + e.what() + ")\n";
      continue;
    }
    double slide = 0;
    for (int p = 0; p < stick.pair_count(); ++p) {
      CHECK_FALSE(stick.states()[p].slipping);
      slide = std::max(slide, (stick.states()[p].slide - pressed[p]).norm());
    }
    const double stick_error = slide / push;
    // Slip: the closed-form push-out.
    fit.drive = PressFit::Drive::all;
    pairs.clear();
    auto problem2 = fit.problem<Lu2>(pairs);
    ContactStatic<Lu2, Policy, Coulomb> slip(std::move(problem2), pairs, opt);
    const auto path = run_path(
        slip, fit, [&](double t) { return t <= 1 ? 0.0 : 2e-6 * (t - 1); }, none, 2.0, 5);
    const double force_error = rel(path.back().force, fit.slip_force());
    char row[160];
    std::snprintf(row, sizeof row, "%8.0e  %10.3e  %10.3e  %d\n", factor, stick_error, force_error,
                  stick.counters().friction_iterations + slip.counters().friction_iterations);
    table += row;
    CHECK(force_error < 0.01);
    if (std::is_same_v<Policy, AugmentedLagrangian>) CHECK(stick_error < 1e-5);
  }
  MESSAGE(table);
}

// Extremes: the seed's two friction models under SAAC across the normal penalty, whose factor
// sets their tangential springs too (Proportional mu k, Extended k in stick). Each factor gives the law's
// springs exactly, every pair closed and finite displacements, or a SolveError (a penalty so large the
// stiffness is numerically singular: refused, never a wrong answer) and only at 1e9 and above.
TEST_CASE("friction: SAACFR's and the extended model's penalty sweep 1e1 to 1e12 x the adjacent stiffness") {
  std::string table =
      "factor, proportional: max |K u - f| / |f|; extended: slipping pairs, max |K u - f| / |f|\n";
  std::vector<double> adjacent;  // k / factor per pair at the first factor: the adjacent stiffness
  for (double factor = 1e1; factor <= 1e12; factor *= 10) {
    char row[160];
    std::string proportional = "refused", extended = "refused";
    {  // SAACFR on a conical fit pushed closed (the existing proportional test's path)
      PressFit fit;
      fit.tilt = 0.5;
      std::vector<GapPair> pairs;
      auto problem       = fit.problem<Ldlt3>(pairs);
      ContactOptions opt = fit_options(fit);
      opt.penalty_factor = factor;
      try {
        ContactStatic<Ldlt3, Saac, Proportional> cs(std::move(problem), pairs, opt);
        const auto path = run_path(
            cs, fit, [&](double t) { return t <= 1 ? 0.0 : -5e-6 * (t - 1); }, none, 2.0, 4);
        CHECK(std::isfinite(path.back().force));
        CHECK(cs.fe().solution().displacement.allFinite());
        if (adjacent.empty())
          for (int p = 0; p < cs.pair_count(); ++p) adjacent.push_back(cs.penalty(p) / factor);
        for (int p = 0; p < cs.pair_count(); ++p) {
          CHECK(cs.states()[p].closed);
          const double k = cs.penalty(p);
          CHECK(rel(k / factor, adjacent[static_cast<std::size_t>(p)]) < 1e-12);  // k scales with the factor
          CHECK(rel(cs.tangential_penalty(p), fit.mu * k) < 1e-12);               // Eq. 12-13: mu k
        }
        const double residual = cs.fe().solution().residual;
        if (factor <= 1e8) CHECK(residual < 1e-6);  // the linear solves hold equilibrium
        std::snprintf(row, sizeof row, "%9.2e", residual);
        proportional = row;
      } catch (const SolveError& e) {
        CHECK(factor >= 1e9);
        proportional += std::string(" (") + e.what() + ")";
      }
    }
    {  // the extended model on the one-row fit pushed at its top (the existing extended test's path)
      PressFit fit;
      fit.drive = PressFit::Drive::ends;
      fit.nz    = 1;
      std::vector<GapPair> pairs;
      auto problem       = fit.problem<Ldlt2>(pairs);
      ContactOptions opt = fit_options(fit);
      opt.penalty_factor = factor;
      try {
        ContactStatic<Ldlt2, Saac, Extended> cs(std::move(problem), pairs, opt);
        const auto loads = [&](Problem<Ldlt2>& p, double t) {
          fit.set(p, std::min(t, 1.0), t <= 1 ? 0 : -5e-5 * (t - 1));
        };
        cs.advance(1.0, loads);
        for (int p = 0; p < cs.pair_count(); ++p) {
          CHECK(cs.states()[p].closed);
          CHECK(rel(cs.tangential_penalty(p), cs.penalty(p)) < 1e-12);  // stick spring k (Eq. 14)
        }
        for (int k = 1; k <= 20; ++k) cs.advance(1.0 + k / 20.0, loads);
        int slipping = 0;
        for (const auto& st : cs.states()) slipping += st.slipping;
        CHECK(slipping > 0);  // the push slides the ring
        CHECK(cs.fe().solution().displacement.allFinite());
        // Equilibrium with the springs the step ran with (a switch refactorizes: it once reused the
        // stick factorization, 0.44 here).
        const double residual = cs.fe().solution().residual;
        if (factor <= 1e8) CHECK(residual < 1e-6);
        std::snprintf(row, sizeof row, "%d of %d, %9.2e", slipping, cs.pair_count(), residual);
        extended = row;
      } catch (const SolveError& e) {
        CHECK(factor >= 1e9);
        extended += std::string(" (") + e.what() + ")";
      }
    }
    std::snprintf(row, sizeof row, "%8.0e  ", factor);
    table += row + proportional + "; " + extended + "\n";
  }
  MESSAGE(table);
}

TEST_CASE(
    "friction: a plastic ring pushed along an elastic shaft: equilibrium and every slipping pair on the "
    "cone") {
  using M = Model<Axisym2, Quad4BBar, Hill<ReturnMapping>, EigenLu>;
  PressFit fit;
  fit.drive = PressFit::Drive::ends;
  fit.nu    = 0.3;
  std::vector<GapPair> pairs;
  auto problem   = fit.problem<M>(pairs);
  const auto law = [&](double e, double sy, double hardening = 0.0) {
    return Hill<ReturnMapping>{Orthotropic::constant(ElasticConstants::isotropic(e, fit.nu)),
                               HillYield::mises(sy, hardening)};
  };
  problem.materials = {law(fit.E, 1e12), law(fit.gap_modulus_ratio * fit.E, 1e12), law(fit.E, 70e6, 2e9)};
  ContactStatic<M, ActiveSet, Coulomb> cs(std::move(problem), pairs, fit_options(fit));
  const auto loads = [&](Problem<M>& p, double t) {
    fit.set(p, std::min(t, 1.0), t <= 1 ? 0 : -2e-5 * (t - 1));
  };
  double worst_residual = 0, worst_cone = 0;
  int slipping = 0, plastic = 0;
  const auto check = [&](double, const auto& c) {
    worst_residual = std::max(worst_residual, c.fe().report().residuals.back());
    for (const auto& s : c.states())
      if (s.closed && s.slipping)
        worst_cone = std::max(worst_cone, std::abs(s.tangential_force.norm() - fit.mu * s.normal_force) /
                                              (fit.mu * s.normal_force));
  };
  for (int k = 1; k <= 10; ++k) cs.advance(0.2 * k, loads, check);
  for (const auto& s : cs.states()) slipping += s.slipping;
  for (const auto& s : cs.fe().states()) plastic += s.plastic;
  MESSAGE("plastic ring: ", plastic, " plastic points, ", slipping, " slipping pairs; worst residual ",
          worst_residual, ", worst |t| / (mu P) - 1 ", worst_cone);
  CHECK(plastic > 0);
  CHECK(slipping > 0);
  CHECK(worst_residual <= 1e-8);
  CHECK(worst_cone <= 1e-8);
}

}  // namespace gapfe::test

namespace gapfe::test {

TEST_CASE_TEMPLATE("exact contact policies over the plastic driver: V5's closure and contact pressure",
                   Policy, ActiveSet, AugmentedLagrangian) {
  // Two tubes, plane strain, a Hill law whose yield stress is never reached: the plastic driver with
  // Newton and the event search must give the frictionless elastic closed form (docs/theory.md V5).
  using M = Model<Axisym2, Quad4BBar, Hill<ReturnMapping>, EigenLdlt>;
  TwoTubes tubes;
  std::vector<GapPair> pairs;
  auto problem   = tubes.problem<M>(pairs);
  const auto law = [&](double e, double nu) {
    return Hill<ReturnMapping>{Orthotropic::constant(ElasticConstants::isotropic(e, nu)),
                               HillYield::mises(1e12)};
  };
  problem.materials = {law(tubes.E, tubes.nu), law(tubes.gap_modulus_ratio * tubes.E, 0.0)};
  ContactOptions opt;
  opt.gap_materials = {1};
  ContactStatic<M, Policy> cs(std::move(problem), pairs, opt);
  const double p = 100e6;
  cs.advance(1.0, [&](Problem<M>& pr, double t) { tubes.set_pressure(pr, t * p); });
  double closed_at = 2, force = 0;
  for (const auto& s : cs.states()) closed_at = std::min(closed_at, s.closed_at), force += s.normal_force;
  const double q = force / (kTwoPi * tubes.b * tubes.height);  // the pairs share the ring force
  MESSAGE(Policy::kName, ": closure at ", closed_at * p, " Pa (closed form ", tubes.closure_pressure(),
          "), contact pressure ", q, " (", tubes.contact_pressure(p), ")");
  CHECK(rel(closed_at * p, tubes.closure_pressure()) < 2e-3);
  CHECK(rel(q, tubes.contact_pressure(p)) < 5e-3);
  CHECK(cs.fe().report().residuals.back() <= 1e-10);
}

}  // namespace gapfe::test

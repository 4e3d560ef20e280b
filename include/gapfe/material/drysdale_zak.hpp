#pragma once
// Rate-dependent plasticity of Drysdale and Zak (1983): SAAC3's law (seed section 4, Eq. 16-18;
// docs/theory.md 8), on the Hill machinery of material/hill.hpp. The yield surface grows with the effective
// plastic strain rate r [1/time]:
//
//     sqrt(f(sigma - alpha)) = level(r) = 1 + b ln(1 + r / rate_0)        (seed Eq. 17)
//
// with f Hill's function of card 11 scaled so that f = 1 is the static surface (its yield stresses are
// the static sigma_0 per direction), Prager kinematic hardening d alpha = c H d eps_p (card 11's C) and b,
// rate_0 from card 0. Convention (docs/theory.md 8.1, fixed here): a tensile test along a card axis yields at
// sigma_0 level(r), the rate-dependent yield stress; its uniaxial plastic modulus is 3c/2 (Mises). The
// effective plastic strain rate is work-conjugate, r = (sigma - alpha) : eps_p' / (X sqrt f) (= the Mises
// equivalent plastic strain rate sqrt(2/3 eps_p' : eps_p') for Mises; hill.hpp's eqps is its integral).
// b = 0 is the rate-independent Hill law exactly: level = 1 whatever r.
//
// The step's dt comes from the StepContext [model time unit]. Integration, the existing policy names:
//   * `Tangent`: the seed's SAAC3 scheme (Eq. 18). While a point yields, r relaxes toward A, the plastic
//     rate the rate-independent law would give, as r' = lambda (A - r) (docs/theory.md 8.2), integrated
//     exactly over the step with A and lambda frozen at its start: r_1 = r_0 + (A - r_0)(1 - exp(-lambda
//     dt)). So r never overshoots A, for any lambda dt. The surface then moves to level(r_1)^2, from
//     where the point is (the secant form of docs/theory.md 8.4, and no drift carried over: dK = level(r_1)^2
//     - f(xi_0)), and the flow that takes it there is added to EPLSS's: d lambda = a . C d eps / H + x, x the
//     root of f(xi_0 - x E a) = f(xi_0) + dK nearest 0 (-dK / H to first order: Eq. 18's second term; solved
//     exactly along the flow, as a tensile test's surface grows radially and the linear term would leave it
//     off by dK^2). The stress changes by C_ep d eps - x C a: EPLSS's continuum tangent, which the assembler
//     gets, plus the surface's term, which the driver's equilibrium correction applies as the equivalent body
//     force of section 4.2 (at the assembler's query, d eps = 0, it is the surface's relaxation) and the next
//     step's residual carries the rest of. One solve per step. A comes from the step's own strain increment,
//     where SAAC3 took the last step's rates: with stress-controlled components (SAAC3X's held torque) that
//     lag feeds back through the strain rate and the stress oscillates about the steady state at lambda dt ~
//     1 (measured: +-3% of sigma, r between 1.27 and 1.69 / s against 1.47), which is what the seed rewrote
//     EPLSS to avoid.
//   * `ReturnMapping`: the fully implicit consistency return (docs/theory.md 8.6): backward Euler with the
//     yield condition f(xi_1) = level(r)^2, r = d eqps / dt, and its consistent tangent, for Newton.
// r is monotone in both for every lambda dt (docs/theory.md 8.4): exponential, and backward Euler. The
// tangent scheme's flow direction is the step's start's: where a step turns the loading away from it
// (SAAC3X's first axial step from pure shear, a . C d eps = 0) one large step would go elastic and
// overshoot (30 times the steady stress at lambda dt = 1e3). So a step whose end is off the surface by
// more than kCutAbove is cut into pieces (halved until each piece's end is on it to kDrift, doubled
// again after), each a step of the same scheme over its share of dt. That keeps SAAC3X's stress within
// 1e-4 of the steady value at lambda dt = 1e3 (tests/test_plasticity.cpp measures it; first order in
// the pieces). Ordinary steps drift less than kCutAbove and stay whole: cutting every step to kDrift
// made a thick-tube step 10 times dearer (BENCHMARKS.md).
// Units: rates [1/time] in the deck's time unit (card 0's delta t); stresses as the moduli.
#include <cmath>
#include <limits>
#include <string>

#include "gapfe/material/hill.hpp"

namespace gapfe {

/// Seed Data 0 (SAAC3): the rate law's parameters.
struct RateLaw {
  double b      = 0;  ///< strain-rate hardening parameter of Eq. 17 [-]
  double rate_0 = 1;  ///< transition strain rate eps_0' of Eq. 17 (card 0's "eps_p dot") [1/time]

  void validate(const std::string& where) const {
    if (!(b >= 0 && std::isfinite(b))) throw InputError(where + ": rate parameter b must be >= 0 (card 0)");
    if (!(rate_0 > 0 && std::isfinite(rate_0)))
      throw InputError(where + ": the transition strain rate must be > 0 (card 0)");
  }
};

/// History of a rate-dependent point: Hill's, plus the rates the next step needs.
struct RateState : HillState {
  double plastic_rate = 0;  ///< r over the last step [1/time] (0 when it did not yield)
  double relaxation   = 0;  ///< lambda dt of the last step (0: did not yield, or b = 0) [-]
  bool operator==(const RateState&) const = default;
};

struct RatePoint : HillPoint {
  double b = 0, rate_0 = 1;
};

template <class Integration>
struct DrysdaleZak {
  /// The seed's scheme in pieces (seed_scheme): how far a piece may leave the surface, relative; how far
  /// a whole step's end must be off it to be cut; the smallest piece (a fraction of the step) and the
  /// most pieces in one step.
  static constexpr double kDrift         = 1e-7;
  static constexpr double kCutAbove      = 1e-3;
  static constexpr double kSmallestPiece = 1.0 / (1 << 20);
  static constexpr int kMaxPieces        = 100000;

  Orthotropic elastic;
  HillYield yield;
  RateLaw rate;

  using State                    = RateState;
  using Local                    = RatePoint;
  using Integrator               = Integration;
  static constexpr bool kLinear  = false;
  static constexpr bool kIterate = Integration::kEquilibriumIterations;
  static constexpr bool kRate    = true;

  Local localize(const MaterialFrame& frame, double T, double T_ref) const {
    Local p;
    static_cast<HillPoint&>(p) = Hill<Integration>{elastic, yield}.localize(frame, T, T_ref);
    p.b = rate.b, p.rate_0 = rate.rate_0;
    return p;
  }
  void validate(const std::string& where) const {
    Hill<Integration>{elastic, yield}.validate(where);
    rate.validate(where);
  }
  static double yield_ratio(const Local& p, const Vec6& stress, const State& s) {
    return Hill<Integration>::yield_ratio(p, stress, s) /
           detail::RateTerm{p.b, p.rate_0, 0}.level(s.plastic_rate);
  }

  static PointResponse<State> update(const Local& p, const Vec6& strain, const State& old,
                                     const StepContext& ctx) {
    const detail::RateTerm term{p.b, p.rate_0, ctx.dt};
    PointResponse<State> r;
    if (term.active() && !(ctx.dt > 0)) {
      // No time passes: any plastic strain would be infinitely fast, so the step is elastic.
      r               = detail::hill_elastic_trial(p, strain, old);
      r.state.plastic = false;
    } else if constexpr (std::is_same_v<Integration, ReturnMapping>) {
      r = detail::hill_return_map(p, strain, old, term, ctx.tangent);
    } else {
      r = seed_scheme(p, strain, old, term);
    }
    if (!r.state.plastic) r.state.plastic_rate = 0, r.state.relaxation = 0;
    if constexpr (std::is_same_v<Integration, ReturnMapping>)
      if (r.state.plastic && ctx.dt > 0) {
        r.state.plastic_rate = (r.state.eqps - old.eqps) / ctx.dt;
        r.state.relaxation   = relaxation(p, r.stress - r.state.back_stress, r.state.plastic_rate, term);
      }
    return r;
  }

  /// The error of a step's time integration at a point. Both schemes are first order in time: the
  /// increment's rate r_1 = d eqps / dt is the step's mean, and its plastic strain is off by about half
  /// the change of the rate over the step, |r_1 - r_0| dt / 2 (r_0 the last accepted increment's mean, 0
  /// when that did not yield), where the rate law sets the flow. Where the step is long against the
  /// relaxation time 1 / lambda (docs/plasticity.md), consistency with the surface sets it instead and the
  /// rate's error hardly moves it (the rate-independent limit, which needs no small steps), so the strain is
  /// divided by 1 + lambda dt. Returned as the stress it stands for relative to the yield stress,
  ///     C_11 |r_1 - r_0| dt / (2 X (1 + lambda dt))
  /// (C_11: the stiffness of a uniaxial strain, a scale only) [-]; 0 at a point that does not yield now.
  /// The drivers cut a load step until it meets the deck's time_tolerance (docs/plasticity.md, "Time
  /// steps").
  static double time_error(const Local& p, const State& old, const State& now, double dt) {
    if (!now.plastic || !(dt > 0) || !(p.b > 0)) return 0.0;  // b = 0: the rate-independent law exactly
    return 0.5 * std::abs(now.plastic_rate - old.plastic_rate) * dt * p.stiffness(0, 0) /
           (p.reference_yield * (1 + now.relaxation));
  }

  /// lambda dt at a yielding point (docs/theory.md 8.2): lambda = H / (m K'), H = a.(C + cH) a, m = 2 s / X
  /// (r = lambda' m), K' = d level^2 / d r. Reported as 0 when b = 0 (lambda is infinite there: the
  /// rate-independent limit).
  static double relaxation(const Local& p, const Vec6& xi, double r, const detail::RateTerm& term) {
    if (!term.active()) return 0.0;
    const Vec6 a       = 2.0 * (p.yield_matrix * xi);
    const double s     = std::sqrt(std::max(xi.dot(p.yield_matrix * xi), 1e-300));
    const double slope = 2 * term.level(r) * term.slope(r);
    return detail::plastic_modulus(p.stiffness, p.hardening_matrix, a) / (2 * s / p.reference_yield * slope) *
           term.dt;
  }

 private:
  /// How far a piece of the seed's scheme ended from where the model keeps a point (docs/theory.md 8.1: F =
  /// 0 while yielding): a yielding point off its surface sqrt f = level(r), relative; an elastic one
  /// pushed further above the static surface than it started (it would have flowed).
  static double off_surface(const Local& p, const State& start, const PointResponse<State>& end,
                            const detail::RateTerm& term) {
    const auto ratio = [&](const Vec6& stress, const State& s) {
      return Hill<Tangent>::yield_ratio(p, stress, s);
    };
    if (end.state.plastic)
      return std::abs(ratio(end.stress, end.state) / term.level(end.state.plastic_rate) - 1);
    const double before =
        ratio(p.stiffness * (start.strain - start.thermal_strain - start.plastic_strain), start);
    return std::max(0.0, ratio(end.stress, end.state) - std::max(1.0, before));
  }

  /// The seed's SAAC3 update (see the header comment), in pieces where one step would leave the point off
  /// its surface: the forward-Euler flow direction is the start's, so a step that turns the loading
  /// (SAAC3X's first axial step from pure shear) is cut until each piece ends on the surface to kDrift.
  /// The assembler's tangent and the reported lambda dt are the whole step's.
  static PointResponse<State> seed_scheme(const Local& p, const Vec6& strain, const State& old,
                                          const detail::RateTerm& term) {
    PointResponse<State> whole = seed_piece(p, strain, old, term);
    if (!term.active() || off_surface(p, old, whole, term) <= kCutAbove) return whole;
    Local at    = p;  // the point at a piece's end: its thermal strain interpolated like the strain
    State s     = old;
    double done = 0, part = 0.5;
    bool yielded = false;
    int pieces   = 0;
    PointResponse<State> r;
    while (done < 1) {
      part              = std::min(part, 1 - done);
      const double to   = done + part >= 1 ? 1.0 : done + part;
      at.thermal_strain = old.thermal_strain + to * (p.thermal_strain - old.thermal_strain);
      r                 = seed_piece(at, to == 1 ? strain : Vec6(old.strain + to * (strain - old.strain)), s,
                                     {term.b, term.rate_0, part * term.dt});
      if (off_surface(at, s, r, term) > kDrift && part > kSmallestPiece) {
        part *= 0.5;
        continue;
      }
      if (++pieces > kMaxPieces)
        throw SolveError("Drysdale-Zak (tangent): more than " + std::to_string(kMaxPieces) +
                         " pieces in one step at a material point; the driver cuts the load step");
      yielded = yielded || r.yielded;
      s = r.state, done = to, part *= 2;
    }
    r.tangent          = whole.tangent;
    r.yielded          = yielded;
    r.state.relaxation = r.state.plastic ? whole.state.relaxation : 0.0;
    return r;
  }

  /// One forward-Euler step of the seed's scheme: Hill's step plus the plastic multiplier of the surface's
  /// change over the step (see the header comment).
  static PointResponse<State> seed_piece(const Local& p, const Vec6& strain, const State& old,
                                         const detail::RateTerm& term) {
    double rate_end = 0, lambda_dt = 0;
    const auto growth = [&](const Vec6& xi, const Vec6& a, double modulus, const Vec6& d_eps_rest,
                            double time_left, bool continuing) {
      const double tau = time_left * term.dt;
      if (!term.active() || !(tau > 0)) return detail::SurfaceChange{};
      // r_0: the last step's rate, or, for a point that starts yielding, the rate its stress flows at (0
      // from the static surface; above it after a step the point unloaded in, faster than it relaxed).
      const double f  = std::max(xi.dot(p.yield_matrix * xi), 1e-300);
      const double r0 = continuing ? old.plastic_rate : term.rate_at(std::sqrt(f));
      const double m  = 2 * std::sqrt(f) / p.reference_yield;
      // A: the rate-independent plastic rate for this step's strain rate, m a.C eps' / H, not negative
      // (SAAC3 took the last step's rates; see the header comment).
      const Vec6 strain_rate = d_eps_rest / tau;
      const double target    = std::max(0.0, m * a.dot(p.stiffness * strain_rate) / modulus);
      const double slope     = 2 * term.level(r0) * term.slope(r0);  // K'(r_0)
      lambda_dt              = modulus / (m * slope) * tau;
      rate_end               = target + (r0 - target) * std::exp(-lambda_dt);
      // The surface moves to level(r_1)^2 from where the point is, f (secant, and no drift kept:
      // docs/theory.md 8.4): dK = level(r_1)^2 - f. Flow along E a = (C + cH) a changes f by -H x + q x^2, q
      // = (E a)^T P (E a), so the multiplier is the root of q x^2 - H x - dK = 0 nearest 0 (-dK / H to first
      // order, the seed's linear term), or where f is least along the flow when the surface shrinks out of
      // reach.
      const double level = term.level(rate_end), dk = level * level - f;
      const Vec6 flow   = (p.stiffness + p.hardening_matrix) * a;
      const double q    = flow.dot(p.yield_matrix * flow);
      const double root = -2 * dk / (modulus + std::sqrt(std::max(modulus * modulus + 4 * q * dk, 0.0)));
      // The tangent: A grows with the strain increment, and r_1 with A by 1 - exp(-lambda dt), which
      // takes back the share (1 - exp(-lambda dt)) / (lambda dt) of EPLSS's plastic flow: elastic for
      // lambda dt -> 0 (no time to flow), C_ep for lambda dt -> infinity.
      const double share = lambda_dt > 1e-8 ? 1 + std::expm1(-lambda_dt) / lambda_dt : lambda_dt / 2;
      return detail::SurfaceChange{dk < 0 ? std::min(root, 0.5 * modulus / q) : root, share};
    };
    PointResponse<State> r = detail::hill_forward_euler(p, strain, old, growth);
    if (r.state.plastic) r.state.plastic_rate = rate_end, r.state.relaxation = lambda_dt;
    return r;
  }
};

}  // namespace gapfe

namespace gapfe {
static_assert(MaterialLaw<DrysdaleZak<Tangent>>);
static_assert(MaterialLaw<DrysdaleZak<ReturnMapping>>);
}  // namespace gapfe

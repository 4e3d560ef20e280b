#pragma once
// The plastic flow of the Hill laws (material/hill.hpp, material/drysdale_zak.hpp): the plastic modulus and
// continuum tangent (docs/theory.md 7.2), the elastic fraction of an increment that crosses the surface, and
// the return mapping onto the yield surface with its consistent tangent (backward Euler), shared by the
// rate-independent and the rate-dependent law.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "gapfe/core/concepts.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/material/elastic.hpp"
#include "gapfe/material/hill_yield.hpp"

namespace gapfe {

namespace detail {

/// 1 / D of EPLSS: a^T C a + a^T cH a, the denominator of d lambda and of C_ep (docs/theory.md 7.2).
inline double plastic_modulus(const Mat66& c, const Mat66& ch, const Vec6& a) {
  return a.dot(c * a) + a.dot(ch * a);
}

/// EPLSS's continuum elastic-plastic tangent C - (C a)(C a)^T / (a^T C a + a^T cH a) (docs/theory.md 7.2).
inline Mat66 continuum_tangent(const Mat66& c, const Mat66& ch, const Vec6& a) {
  const Vec6 ca = c * a;
  return c - ca * ca.transpose() / plastic_modulus(c, ch, a);
}

/// The larger root r in [0, 1] of f(xi0 + r d) = 1 when f(xi0 + d) > 1: where a step leaves the yield
/// surface. From inside (f(xi0) < 1) it is the elastic fraction of a step that crosses the surface; from a
/// point on the surface moving inward (unloading, d.P xi0 < 0) it is where the step crosses the elastic
/// region and leaves on the far side (reverse yielding). The quadratic is solved without cancellation:
/// (-qb + disc) / qa written as -qc / (qb + disc) when qb >= 0.
inline double elastic_fraction(const Mat66& p, const Vec6& xi0, const Vec6& d) {
  const double qa = d.dot(p * d), qb = xi0.dot(p * d), qc = xi0.dot(p * xi0) - 1.0;
  if (!(qa > 0)) return 1.0;
  const double disc = std::sqrt(std::max(0.0, qb * qb - qa * qc));
  return std::clamp(qb >= 0 ? -qc / (qb + disc) : (disc - qb) / qa, 0.0, 1.0);
}

/// How fast the yield level grows with the effective plastic strain rate r [1/time] (Drysdale-Zak, seed
/// Eq. 17; material/drysdale_zak.hpp): the surface is f = level(r)^2 with level(r) = 1 + b ln(1 + r /
/// rate_0), over a step of dt. b = 0, the default, is Hill's rate-independent surface f = 1.
struct RateTerm {
  double b = 0, rate_0 = 1, dt = 0;
  bool active() const { return b > 0; }
  double level(double r) const { return 1 + b * std::log1p(r / rate_0); }
  double slope(double r) const { return b / (rate_0 + r); }  ///< d level / d r [time]
  /// The inverse: the plastic rate at which a stress at `level` flows (0 on or inside the static
  /// surface; the exponent capped so that a tiny b gives a huge rate, not an overflow).
  double rate_at(double level) const {
    return level > 1 ? rate_0 * std::expm1(std::min((level - 1) / b, 690.0)) : 0.0;
  }
};

inline Vec6 hill_stress(const HillPoint& p, const Vec6& strain, const Vec6& plastic) {
  return p.stiffness * (strain - p.thermal_strain - plastic);
}

/// Plastic strain increment d eps_p = dl a into the state (strain, back stress, eqps).
inline void add_plastic_flow(const HillPoint& p, HillState& s, const Vec6& xi, double dl, const Vec6& a) {
  const Vec6 d_eps_p = dl * a;
  s.plastic_strain += d_eps_p;
  s.back_stress += p.hardening_matrix * d_eps_p;
  const double ratio = std::sqrt(std::max(xi.dot(p.yield_matrix * xi), 1e-300));
  s.eqps += xi.dot(d_eps_p) / (p.reference_yield * ratio);  // plastic work / (X sqrt f)
}

/// Both updates start from the elastic trial: stress with the old plastic strain, elastic tangent, the
/// old history with this strain and thermal strain recorded.
template <class State>
PointResponse<State> hill_elastic_trial(const HillPoint& p, const Vec6& strain, const State& old) {
  PointResponse<State> r{hill_stress(p, strain, old.plastic_strain), p.stiffness, old, false};
  r.state.strain         = strain;
  r.state.thermal_strain = p.thermal_strain;
  return r;
}

/// What the yield surface's own change over a step asks of the forward-Euler step (material/
/// drysdale_zak.hpp): an extra plastic multiplier, and the share of EPLSS's plastic correction the
/// tangent keeps (C - share (C a)(C a)^T / H; 1: the continuum tangent, 0: elastic). The
/// rate-independent law's surface does not change: {0, 1}.
struct SurfaceChange {
  double multiplier = 0, plastic_share = 1;
};

/// The seed's forward-Euler step (Hill<Tangent>, see the header comment). `growth(xi, a, H, d_eps, part,
/// continuing)` gives the SurfaceChange over the plastic part of the step: at the yield point xi
/// (gradient a, 1/D = H), with the mechanical strain increment d_eps left over the fraction `part` of the
/// step's time, `continuing` when the point was already yielding at the start. Its multiplier adds to
/// EPLSS's a . C d_eps / H.
template <class State, class Growth>
PointResponse<State> hill_forward_euler(const HillPoint& p, const Vec6& strain, const State& old,
                                        Growth&& growth) {
  const Mat66& c         = p.stiffness;
  const Mat66& P         = p.yield_matrix;
  PointResponse<State> r = hill_elastic_trial(p, strain, old);
  // The mechanical strain increment: a temperature change within the step is part of it.
  const Vec6 d_eps = (strain - p.thermal_strain) - (old.strain - old.thermal_strain);
  const Vec6 xi0   = c * (old.strain - old.thermal_strain - old.plastic_strain) - old.back_stress;
  const Vec6 d_xi  = c * d_eps;
  // The seed's IFGPL flag: a point that ended the last step plastic and is loaded further gets C_ep of
  // the start state, for the assembler too; otherwise the step starts elastic. Loading: d lambda >= 0
  // (a rate-dependent point relaxes, its surface shrinking, even at d_eps = 0).
  const Vec6 a0              = 2.0 * (P * xi0);
  const double modulus0      = old.plastic ? plastic_modulus(c, p.hardening_matrix, a0) : 1.0;
  const SurfaceChange grown0 = old.plastic ? growth(xi0, a0, modulus0, d_eps, 1.0, true) : SurfaceChange{};
  const bool loading =
      old.plastic && a0.dot(d_xi) / modulus0 + grown0.multiplier >= 0;  // d_eps = 0: the query
  if (loading) {
    const Vec6 ca = c * a0;
    r.tangent     = grown0.plastic_share == 1 ? continuum_tangent(c, p.hardening_matrix, a0)
                                              : Mat66(c - grown0.plastic_share * ca * ca.transpose() / modulus0);
  }
  const Vec6 xi_trial = xi0 + d_xi;
  if (!loading && xi_trial.dot(P * xi_trial) <= 1.0) {
    r.state.plastic = false;  // elastic step, unloading, or reloading below the surface
    return r;
  }
  // Elastic part up to where the step leaves the surface: none when it starts on it and loads; through
  // the elastic region to the far side when it starts on it and unloads (reverse yielding); up to the
  // surface from inside. Then one forward-Euler step.
  const double f0      = xi0.dot(P * xi0);
  const double e       = loading || (!old.plastic && f0 >= 1.0) ? 0.0 : elastic_fraction(P, xi0, d_xi);
  const Vec6 xi_y      = xi0 + e * d_xi;
  const Vec6 a         = loading ? a0 : Vec6(2.0 * (P * xi_y));
  const double modulus = loading ? modulus0 : plastic_modulus(c, p.hardening_matrix, a);
  const double grown   = loading ? grown0.multiplier
                                 : growth(xi_y, a, modulus, Vec6((1.0 - e) * d_eps), 1.0 - e, false).multiplier;
  const double dl      = a.dot(c * ((1.0 - e) * d_eps)) / modulus + grown;
  if (!(dl > 0)) {
    r.state.plastic = false;
    return r;
  }
  add_plastic_flow(p, r.state, xi_y, dl, a);
  r.stress        = hill_stress(p, strain, r.state.plastic_strain);
  r.state.plastic = true;
  r.yielded       = true;
  return r;
}

/// Backward-Euler closest-point projection (Hill<ReturnMapping>, docs/theory.md 7.3), onto the surface
/// f = level(r)^2 of `rate` with r = d eqps / dt = 2 dl sqrt(f) / (X dt) (docs/theory.md 8.6; level 1 for
/// the rate-independent law), with its consistent tangent. A(dl) is inverted in E P's modes (HillModes):
/// one scalar equation in dl, no matrix factorization per iteration. Without `tangent` (a residual pass,
/// StepContext::tangent) the consistent tangent, about half the work at a yielding point, is skipped.
template <class State>
PointResponse<State> hill_return_map(const HillPoint& p, const Vec6& strain, const State& old,
                                     const RateTerm& rate, bool tangent) {
  const Mat66& c         = p.stiffness;
  const Mat66& P         = p.yield_matrix;
  PointResponse<State> r = hill_elastic_trial(p, strain, old);
  const Vec6 xi_trial    = r.stress - old.back_stress;
  if (xi_trial.dot(P * xi_trial) <= 1.0) {
    r.state.plastic = false;
    // A point that ended the last step on the surface, asked for its tangent at the same strain (the
    // first Newton iteration of the next step, NonlinearStatic): the continuum tangent C_ep, the
    // consistent tangent's limit as dl -> 0+, on the expectation that the loading goes on. The stress
    // is the same either way; with the elastic tangent the first solve ignored the plastic zone (the
    // 1e4-equation tube: 49 solves instead of 45, BENCHMARKS.md, "Levers measured on the second machine").
    if (tangent && old.plastic && strain == old.strain && p.thermal_strain == old.thermal_strain)
      r.tangent = continuum_tangent(c, p.hardening_matrix, Vec6(2.0 * (P * xi_trial)));
    return r;
  }
  // phi(dl) = f(dl) - level(r)^2 with f(dl) = sum lambda_i y_i^2 d_i^2, d_i = 1 / (1 + 2 dl lambda_i),
  // y = W xi_trial (HillModes). f is convex and decreasing from phi(0) > 0; the level grows with dl.
  // Newton from 0, kept inside the bracket [lo, hi] of the root (bisection when it would leave it): for
  // the rate-independent law it approaches the root from below, monotonically, and never bisects.
  const HillModes& m = p.modes();
  const Vec6 y       = m.inverse * xi_trial;
  const Vec6 y2      = y.cwiseAbs2();
  const double to_r  = rate.active() ? 2.0 / (p.reference_yield * rate.dt) : 0.0;  // r = to_r dl s
  const auto damping = [&](double dl) {
    return (1.0 + 2.0 * dl * m.lambda.array()).inverse().matrix().eval();
  };
  double dl = 0.0, lo = 0.0, hi = std::numeric_limits<double>::infinity();
  double level = 1.0, level_slope = 0.0, s = 1.0;  // at the last iterate: level(r), d level / d r, sqrt f
  for (int it = 0;; ++it) {
    const Vec6 d   = damping(dl);
    const double f = (m.lambda.array() * y2.array() * d.array().square()).sum();
    s              = std::sqrt(f);
    if (rate.active()) level = rate.level(to_r * dl * s), level_slope = rate.slope(to_r * dl * s);
    const double phi = f - level * level;
    if (std::abs(phi) <= ReturnMapping::kTolerance * level * level) break;
    if (it == ReturnMapping::kMaxIterations || !std::isfinite(phi))
      throw SolveError("Hill return mapping: no convergence at a material point (|f - level^2| = " +
                       std::to_string(std::abs(phi)) + "); the driver cuts the load step");
    (phi > 0 ? lo : hi) = dl;
    // d phi / d dl = f' - 2 level level' dr/d dl, f' = -4 sum lambda_i^2 y_i^2 d_i^3 (= -2 xi . P A^-1
    // (2 E P) xi), dr/d dl = to_r (s + dl f' / (2 s)).
    const double d_f   = -4.0 * (m.lambda.array().square() * y2.array() * d.array().cube()).sum();
    const double d_phi = d_f - 2 * level * level_slope * to_r * (s + dl * d_f / (2 * s));
    const double step  = phi / d_phi;
    const double next  = dl - step;
    dl                 = next > lo && next < hi ? next : std::isfinite(hi) ? 0.5 * (lo + hi) : 2 * lo;
    // Converged to round-off in dl, or the bracket closed (never while hi is still unbounded).
    if (std::abs(step) <= 1e-15 * std::abs(dl) || (std::isfinite(hi) && hi - lo <= 1e-15 * hi)) break;
  }
  const Vec6 d  = damping(dl);
  const Vec6 dy = d.cwiseProduct(y);
  const Vec6 xi = m.modes * dy;  // A^-1 xi_trial
  const Vec6 a  = 2.0 * (P * xi);
  add_plastic_flow(p, r.state, xi, dl, a);
  r.stress        = hill_stress(p, strain, r.state.plastic_strain);
  r.state.plastic = true;
  r.yielded       = true;
  if (!tangent) return r;
  // Consistent tangent (docs/theory.md 7.3, with the rate term of 8.6): d dl = g^T d eps,
  // g = kappa C A^-T a / (kappa a^T A^-1 E a + h), kappa = 1 - 2 level' dl / (X dt),
  // h = 4 s^2 level' / (X dt) (kappa = 1, h = 0 without rate dependence);
  // d xi / d eps = A^-1 (C - E a g^T), d eps_p / d eps = a g^T + 2 dl P d xi / d eps, D = C (I - ...).
  // In the modes: V^T a = 2 lambda d y and W E = V^T, so with z = lambda d^2 y, A^-T a = 2 W^T z,
  // A^-1 E a = 2 V z and a^T A^-1 E a = 4 sum lambda_i^2 d_i^3 y_i^2 = 2 z . (V^T a).
  const Vec6 z        = m.lambda.cwiseProduct(d).cwiseProduct(dy);
  const double kappa  = 1 - level_slope * to_r * dl;
  const double h      = 2 * s * s * level_slope * to_r;
  const Vec6 ai_t     = 2.0 * (m.inverse.transpose() * z);       // A^-T a
  const double a_ea   = 4.0 * z.dot(m.lambda.cwiseProduct(dy));  // a^T A^-1 E a
  const Vec6 g        = kappa * (c * ai_t) / (kappa * a_ea + h);
  const Mat66 dxi     = m.modes * (d.asDiagonal() * m.inverse_c) - 2.0 * (m.modes * z) * g.transpose();
  const Mat66 d_eps_p = a * g.transpose() + 2.0 * dl * (P * dxi);
  r.tangent           = c - c * d_eps_p;
  r.tangent           = 0.5 * (r.tangent + r.tangent.transpose());  // symmetric up to round-off
  return r;
}

}  // namespace detail

}  // namespace gapfe

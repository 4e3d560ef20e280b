#pragma once
// Closed-form references for the Drysdale-Zak law (seed Eq. 17; docs/theory.md 8), shared by the point and
// structure tests (test_plasticity.cpp) and the SAAC3X deck test (test_deck_run.cpp).
#include <cmath>

namespace gapfe::test {

/// Seed Eq. 17 with yield stress sigma_0, parameter b and transition rate rate_0 [1/time].
struct RateReference {
  double sigma_0 = 400, b = 0.05, rate_0 = 1e-3;

  /// The yield stress ratio sigma_y / sigma_0 at the plastic rate r.
  double level(double r) const { return 1 + b * std::log1p(r / rate_0); }
  /// Its inverse phi: the plastic rate at the equivalent stress ratio s (0 below the static surface).
  double plastic_rate_at(double s) const { return s <= 1 ? 0.0 : rate_0 * std::expm1((s - 1) / b); }

  /// SAAC3X's steady state (docs/theory.md 8.7): shear stress tau held, axial strain rate `rate`. sigma
  /// solves phi(sigma_bar) sigma / sigma_bar = rate (bisection to round-off), sigma_bar = sqrt(sigma^2 +
  /// 3 tau^2); then the plastic rate phi(sigma_bar) and the (engineering) twist rate 3 tau phi / sigma_bar.
  struct Saac3x {
    double sigma = 0, plastic_rate = 0, twist_rate = 0;
  };
  Saac3x saac3x_steady(double tau, double rate) const {
    double lo = 0, hi = 2 * sigma_0 * level(rate);
    const auto excess = [&](double s) {
      const double bar = std::hypot(s, std::sqrt(3.0) * tau);
      return plastic_rate_at(bar / sigma_0) * s / bar - rate;
    };
    for (int i = 0; i < 200; ++i) (excess(0.5 * (lo + hi)) > 0 ? hi : lo) = 0.5 * (lo + hi);
    const double sigma = 0.5 * (lo + hi), bar = std::hypot(sigma, std::sqrt(3.0) * tau);
    const double r = plastic_rate_at(bar / sigma_0);
    return {sigma, r, 3 * tau * r / bar};
  }
};

}  // namespace gapfe::test

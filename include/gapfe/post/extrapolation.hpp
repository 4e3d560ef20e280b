#pragma once
// A quantity's error from its values on meshes each twice as fine as the last (h, h/2, h/4): Richardson's
// extrapolation (docs/accuracy.md "Error bars"). With an error C h^p, the differences d1 = q(h/2) - q(h) and
// d2 = q(h/4) - q(h/2) shrink by 2^p, so three values give the observed order p = log2(d1 / d2) and the limit
// q(h/4) + d2 / (2^p - 1); two values give the limit with the element's order assumed. The error bar of the
// first mesh's value is its distance to the limit. Differences that do not shrink (a stress at a re-entrant
// corner grows without bound) give no limit: the quantity does not converge, and no number is claimed for it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

namespace gapfe {

/// What the values of a quantity on successively halved meshes say about its value on the first.
struct ErrorBar {
  enum class Status {
    exact,           ///< the values agree to the solvers' noise (kRoundOff): error 0
    observed,        ///< three values, converging at the observed order
    assumed,         ///< two values, the order assumed
    not_converging,  ///< the differences do not shrink (or shrink slower than order kSlowest): no error bar
    /// (`gapfe run --accuracy`) not converging, but moving by less than a tenth of the target: the last
    /// difference is the error (app/accuracy.hpp)
    settled,
  };
  Status status = Status::not_converging;
  double value  = 0;                                         ///< on the first mesh
  double limit  = std::numeric_limits<double>::quiet_NaN();  ///< extrapolated to h -> 0
  double error  = std::numeric_limits<double>::quiet_NaN();  ///< |value - limit|
  double order  = std::numeric_limits<double>::quiet_NaN();  ///< observed or assumed p

  bool converges() const { return status != Status::not_converging; }
  /// Orders below this are taken as not converging: the differences shrink by less than 2^0.5 a level, and
  /// the limit extrapolated would be further than 2.4 times the last difference, a guess.
  static constexpr double kSlowest = 0.5;
  /// Differences below this fraction of the values (or of their scale) are the solvers' noise, not the mesh's
  /// error: a linear solve leaves about 1e-13 relative, but Newton's tolerance (1e-10 of the residual) and a
  /// rate-dependent law's time steps leave up to about 1e-8 in a displacement
  /// (examples/decks/saac3x_tube.deck: 3e-8 between meshes on a uniform state the mesh cannot change).
  static constexpr double kRoundOff = 1e-7;
};

/// The error bar of `values[0]` from the values on meshes each twice as fine (two or three of them; more are
/// not read), with `assumed_order` used when there are two. Differences below kRoundOff times the larger of
/// `scale` and the values are round-off (a sum whose terms cancel has a scale far above its value).
inline ErrorBar error_bar(std::span<const double> values, double assumed_order, double scale = 0) {
  ErrorBar b;
  b.value = values.empty() ? std::numeric_limits<double>::quiet_NaN() : values[0];
  if (values.size() < 2) return b;
  for (const double v : values.first(std::min<std::size_t>(values.size(), 3)))
    scale = std::max(scale, std::abs(v));
  const double d1 = values[1] - values[0];
  const double d2 = values.size() >= 3 ? values[2] - values[1] : 0.0;
  if (!std::isfinite(d1) || !std::isfinite(d2)) return b;
  if (std::abs(d1) <= ErrorBar::kRoundOff * scale && std::abs(d2) <= ErrorBar::kRoundOff * scale) {
    b.status = ErrorBar::Status::exact, b.limit = values.back(), b.error = 0;
    return b;
  }
  double last        = d1;  // the last difference, and the level it ends on
  double p           = assumed_order;
  std::size_t finest = 1;
  if (values.size() >= 3 && std::abs(d2) <= ErrorBar::kRoundOff * scale) {  // exact from the second mesh on
    b.status = ErrorBar::Status::observed, b.order = std::numeric_limits<double>::infinity();
    b.limit = values[2], b.error = std::abs(b.value - b.limit);
    return b;
  }
  if (values.size() >= 3) {
    // Not shrinking, or shrinking slower than order kSlowest, or changing sign: no limit to extrapolate to.
    if (!(d1 * d2 > 0) || !(std::abs(d2) * std::exp2(ErrorBar::kSlowest) <= std::abs(d1))) return b;
    p = std::log2(d1 / d2), last = d2, finest = 2;
    b.status = ErrorBar::Status::observed;
  } else {
    b.status = ErrorBar::Status::assumed;
  }
  b.order = p;
  b.limit = values[finest] + last / (std::exp2(p) - 1);
  b.error = std::abs(b.value - b.limit);
  return b;
}

}  // namespace gapfe

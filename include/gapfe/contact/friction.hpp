#pragma once
// Friction models at closed gap pairs (seed section 3, Eq. 12-15; docs/theory.md 6): a compile-time policy of
// ContactStatic next to the contact policy, so a scene without friction instantiates none of it.
//
// Every model is a tangential spring on the pair's slide s = (T . d, S . d) [length], d = u_b - u_a in
// (r, z, theta), T = (-cos beta, sin beta, 0) along the gap and S = e_theta. Its force on node b in the
// tangent plane is t [force, total ring], on node a -t:
//
//     t_trial = t_base - k_t (s - s_n),     s_n the slide the increment starts from (PairState::
//                                           slide_start: the accepted slide, or where a pair closing
//                                           inside a step settled at its end closed),
//
// with t_base the accepted tangential force (augmented-Lagrangian runs replace it by the tangential
// multiplier, which Uzawa updates drive to exact stick). The models differ in k_t and in the limit:
//
//   NoFriction    no tangential spring: the frictionless gap of SAAC.
//   Proportional  SAACFR (Eq. 12-13): k_t = mu k_n, no limit. Partial bonding, not Coulomb: mu is only a
//                 stiffness ratio. Faithful, for legacy comparisons.
//   Extended      the seed's stick/slip model (section 3.2, Eq. 14-15): k_t = k_n (stick, "large") or 0
//                 (slip: only the soft gap element's own stiffness resists, the seed's "low value of S").
//                 The status is decided at every accepted increment from the stresses of the real
//                 elements around the pair (ContactStatic::decide_stick_slip) and used in the next step:
//                 a one-step lag, and the force a slipping pair carries is kept, not returned to mu P.
//   Coulomb       the exact law |t| <= mu P with a return mapping (docs/theory.md 6, third item): stick
//                 t = t_trial; slip t = mu P t_trial / |t_trial|. P, the pair's normal force, is taken at
//                 the current iterate, so slip couples t to the normal gap: the consistent tangent is
//                 unsymmetric, and the driver iterates (Newton) within every solve.
//
// Units: k_t [force/length]; mu [-]. Sign: P compressive positive; t is the force on b, so a stuck pair
// pulled along +T by b's motion carries t along -T.
#include <cmath>
#include <concepts>
#include <string_view>

#include "gapfe/contact/policies.hpp"
#include "gapfe/core/combinations.hpp"
#include "gapfe/core/types.hpp"

namespace gapfe {

/// The tangential answer of a closed pair at one slide: force on b and its derivatives.
struct TangentialResponse {
  Vec2 force              = Vec2::Zero();       ///< t in (T, S) [force]
  Mat<2, 2> stiffness     = Mat<2, 2>::Zero();  ///< -dt/ds [force/length]
  Vec2 normal_force_slope = Vec2::Zero();       ///< dt/dP [-] (mu nu while slipping, else 0)
  bool slipping           = false;
  double excess           = 0;  ///< |t_trial| - mu P while slipping [force], 0 in stick
  /// The force on the stick branch [force]: Coulomb's t_trial, what the pair would carry stuck (= force
  /// in stick); the spring models' own force.
  Vec2 stick_force = Vec2::Zero();
};

/// What a model needs of a closed pair: the trial slide measured from s_n, the normal force
/// at the iterate, the base force, the spring and mu.
struct TangentialInput {
  Vec2 slide_increment = Vec2::Zero();  ///< s - s_n [length]
  Vec2 base_force      = Vec2::Zero();  ///< t_base [force]
  double normal_force  = 0;             ///< P [force], compressive positive
  double spring        = 0;             ///< k_t [force/length]
  double mu            = 0;             ///< [-]
  bool slipping        = false;         ///< Extended: the status fixed for this step; Coulomb: the last one
};

template <class F>
concept FrictionModel = requires(const TangentialInput& in) {
  { F::kName } -> std::convertible_to<std::string_view>;
  { F::kFriction } -> std::convertible_to<bool>;     ///< false: the pairs carry no tangential spring
  { F::kIterative } -> std::convertible_to<bool>;    ///< the pair force is nonlinear in the slide: Newton
  { F::kStressCheck } -> std::convertible_to<bool>;  ///< stick/slip from element stresses at each accept
  { F::respond(in) } -> std::same_as<TangentialResponse>;
  /// Whether this model runs under contact policy P (a compile-time table, documented per model).
  { F::template accepts<NoContact>() } -> std::convertible_to<bool>;
};

struct NoFriction {
  static constexpr std::string_view kName = "none";
  static constexpr bool kFriction = false, kIterative = false, kStressCheck = false;
  static TangentialResponse respond(const TangentialInput&) { return {}; }
  template <class P>
  static constexpr bool accepts() {
    return unsupported({.contact = P::kName, .friction = kName}).empty();  // core/combinations.hpp
  }
};

/// SAACFR (Eq. 12-13); with the seed's step-splitting policy only, as the seed ran it.
struct Proportional {
  static constexpr std::string_view kName = "proportional";
  static constexpr bool kFriction = true, kIterative = false, kStressCheck = false;
  static TangentialResponse respond(const TangentialInput& in) {
    TangentialResponse out;
    out.force       = in.base_force - in.spring * in.slide_increment;
    out.stiffness   = in.spring * Mat<2, 2>::Identity();
    out.stick_force = out.force;
    return out;
  }
  template <class P>
  static constexpr bool accepts() {
    return unsupported({.contact = P::kName, .friction = kName}).empty();  // core/combinations.hpp
  }
};

/// The seed's extended stick/slip model (section 3.2, Eq. 14-15); with the seed's policy only.
struct Extended {
  static constexpr std::string_view kName = "extended";
  static constexpr bool kFriction = true, kIterative = false, kStressCheck = true;
  /// Proportional's linear spring with S = k_t in stick and 0 in slip (the seed's Eq. 14-15).
  static TangentialResponse respond(const TangentialInput& in) {
    TangentialInput spring = in;
    spring.spring          = in.slipping ? 0.0 : in.spring;
    TangentialResponse out = Proportional::respond(spring);
    out.slipping           = in.slipping;
    return out;
  }
  template <class P>
  static constexpr bool accepts() {
    return unsupported({.contact = P::kName, .friction = kName}).empty();  // core/combinations.hpp
  }
};

/// Penalty-regularised Coulomb friction with a return mapping; with the exact contact policies (the
/// seed's policy freezes the gap at closure and splits only once, so the normal force it would give the
/// cone is not the converged one).
struct Coulomb {
  static constexpr std::string_view kName = "coulomb";
  static constexpr bool kFriction = true, kIterative = true, kStressCheck = false;
  static TangentialResponse respond(const TangentialInput& in) {
    TangentialResponse out;
    const Vec2 trial   = in.base_force - in.spring * in.slide_increment;
    out.stick_force    = trial;
    const double limit = in.mu * std::max(in.normal_force, 0.0);
    const double size  = trial.norm();
    // Stick inside the cone (a pair without normal force carries nothing: limit 0, trial 0). On its
    // boundary, to 1e-12, the pair keeps the status it had: a step starts from the accepted force, on
    // the cone when the pair slipped, and its first linearization is then the slip tangent (one solve
    // per step while a fit slides on) instead of the stick spring.
    if (size < limit * (1 - 1e-12) || (size <= limit && !in.slipping)) {
      out.force     = trial;
      out.stiffness = in.spring * Mat<2, 2>::Identity();
      return out;
    }
    // Slip: back to the cone along the trial direction nu. dt/ds = (mu P / |t_trial|) (I - nu nu^T)
    // (-k_t), dt/dP = mu nu (docs/theory.md 6). With P <= 0 the pair carries nothing and stiffens nothing.
    out.slipping = true;
    out.excess   = std::max(size - limit, 0.0);
    if (limit <= 0) return out;
    const Vec2 nu          = trial / size;
    out.force              = limit * nu;
    out.stiffness          = (in.spring * limit / size) * (Mat<2, 2>::Identity() - nu * nu.transpose());
    out.normal_force_slope = in.mu * nu;
    return out;
  }
  template <class P>
  static constexpr bool accepts() {
    return unsupported({.contact = P::kName, .friction = kName}).empty();  // core/combinations.hpp
  }
};

static_assert(FrictionModel<NoFriction> && FrictionModel<Proportional> && FrictionModel<Extended> &&
              FrictionModel<Coulomb>);

}  // namespace gapfe

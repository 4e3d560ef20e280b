#pragma once
// Contact policies: how a load step treats the gap pairs (docs/theory.md 5.3-5.5). A policy is a type with
// a name, whether it acts on the pairs at all, its default penalty factor, and a step function that
// drives a Stepper (driver/contact_stepper.hpp) from the accepted load factor to the step's end:
//
//   NoContact            gap elements keep their soft stiffness; no links, so a scene pays nothing.
//   Saac                 the seed (section 2.2): solve the step, split it once at the smallest closure
//                        factor (a step that only unloads: where the first closed pair goes into tension),
//                        declare every overlapping pair closed, apply the rest; a closed pair that pulls
//                        where an increment is accepted opens and that point is solved again. Penalty
//                        100 x the adjacent stiffness.
//   ActiveSet            re-solve until no open pair overlaps and no closed pair pulls, splitting the
//                        step at every status change, so closure loads are exact to round-off; the
//                        closed pairs are penalty springs (constraint error ~ 1 / penalty factor).
//                        With events = step-end (ContactOptions::locate_events false) the step is not
//                        split: the statuses settle at its end by active-set rounds (every overlapping
//                        pair closed, every pulling one opened, re-solved), as CalculiX and most codes do.
//                        The end state of an elastic frictionless step is the same; a path-dependent one
//                        (friction, plasticity) sees each closure at the step's end instead of where it
//                        happened, an O(step) error that the friction benchmarks measure.
//   AugmentedLagrangian  ActiveSet with Uzawa multiplier updates at every solve, to a penetration
//                        tolerance, with the moderate penalty 100 (capped at 1e6): exact without
//                        ill-conditioning.
//
// A closed pair pushes its nodes apart along N with  P = lambda - k (g - g_ref)  [force, total ring,
// compressive positive]: Saac has lambda = 0 and g_ref = the gap when the pair was declared closed (the
// seed's penalty acts on displacement increments from then on, which freezes any gap or overlap left at
// closure); the exact policies have g_ref = 0 (total gap form), and lambda is the Uzawa multiplier.
#include <algorithm>
#include <concepts>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "gapfe/core/error.hpp"

namespace gapfe {

namespace detail {

/// What a policy may ask of the driver: the contract behind the ContactPolicy concept (declared only).
struct StepperArchetype {
  double load_factor() const;
  int pair_count() const;
  bool closed(int pair) const;
  double gap(int pair) const;          ///< at the accepted state [length]
  double force(int pair) const;        ///< at the accepted state [force]
  double trial_gap(int pair) const;    ///< after the last solve
  double trial_force(int pair) const;  ///< after the last solve
  double gap_tolerance() const;        ///< below -this an open pair overlaps [length]
  double force_tolerance(int pair) const;
  static constexpr bool linear_response() { return true; }  ///< linear in the load between status changes
  bool locate_events() const;  ///< true: split at every status change; false: settle at the step's end
  void solve_at(double load_factor);
  void settle_multipliers();
  void close(int pair, double reference_gap);
  void open(int pair);
  void accept(double load_factor);
  void flip(int pair);  ///< change a pair's status in the trial only (settling at the end; restart undoes it)
  void restart();       ///< back to the accepted statuses and state
  void count_split();
  void count_round();  ///< a re-solve after status changes at the same load factor (step-end, saac's pulls)
  void count_cut();    ///< a solve that did not converge, retried over half the interval
  [[noreturn]] void fail(const std::string& why) const;
};

}  // namespace detail

template <class P>
concept ContactPolicy = requires {
  { P::kName } -> std::convertible_to<std::string_view>;
  { P::kContact } -> std::convertible_to<bool>;
  { P::kDefaultPenalty } -> std::convertible_to<double>;
  { P::kMaxPenalty } -> std::convertible_to<double>;
}
&&requires(detail::StepperArchetype& s, double t) {
  P::step(s, t);
};

namespace detail {

/// Fraction of the interval from the accepted state to the last solve at which open pair p closes:
/// f = g_start / (g_start - g_end), exact while the response is linear (docs/theory.md 5.4); 0 when it
/// already touched at the start.
template <class S>
double closure_fraction(const S& s, int p) {
  const double g0 = std::max(s.gap(p), 0.0), g1 = s.trial_gap(p);
  return g0 / (g0 - g1);
}

/// The same for the change the last solve asks of pair p: closure_fraction of an open pair, and for a
/// closed one the fraction at which its force reaches zero, f = P_start / (P_start - P_end).
template <class S>
double change_fraction(const S& s, int p) {
  if (!s.closed(p)) return closure_fraction(s, p);
  const double p0 = std::max(s.force(p), 0.0), p1 = s.trial_force(p);
  return p0 / (p0 - p1);
}

/// Whether the last solve contradicts pair p's status: an open pair that overlaps, a closed one that pulls.
template <class S>
bool contradicted(const S& s, int p) {
  return s.closed(p) ? s.trial_force(p) < -s.force_tolerance(p) : s.trial_gap(p) < -s.gap_tolerance();
}

}  // namespace detail

struct NoContact {
  static constexpr std::string_view kName = "none";
  static constexpr bool kContact          = false;
  static constexpr double kDefaultPenalty = 0;
  static constexpr double kMaxPenalty     = 0;
  template <class S>
  static void step(S& s, double t_end) {
    s.solve_at(t_end);
    s.accept(t_end);
  }
};

struct Saac {
  static constexpr std::string_view kName = "saac";
  static constexpr bool kContact          = true;
  static constexpr double kDefaultPenalty = 100;    // "about two orders of magnitude" (seed 2.2)
  static constexpr double kMaxPenalty     = 1e300;  // the user's choice, however ill-conditioned
  template <class S>
  static void step(S& s, double t_end) {
    const double t0 = s.load_factor();
    s.solve_at(t_end);
    // The seed (docs/theory.md 5.4) splits the step once, at the first closure: an open pair that overlaps
    // closes at f = g_start / (g_start - g_end). A step that only unloads is split likewise where its
    // first closed pair goes into tension, f = P_start / (P_start - P_end) ("unloading could separate the
    // gap"). Whatever load moves them (pressure, temperature, inertia, a prescribed displacement), the
    // step's loads all move linearly with the load factor, so f is that of the whole load.
    std::vector<int> closing, opening;
    double f_close = 1, f_open = 1;
    for (int p = 0; p < s.pair_count(); ++p)
      if (detail::contradicted(s, p)) {
        (s.closed(p) ? opening : closing).push_back(p);
        (s.closed(p) ? f_open : f_close) =
            std::min(s.closed(p) ? f_open : f_close, detail::change_fraction(s, p));
      }
    if (!closing.empty() || !opening.empty()) {
      s.count_split();
      const double f       = closing.empty() ? f_open : f_close;
      const double t_split = t0 + f * (t_end - t0);
      if (f > 0) {  // the step again at the reduced load (same stiffness), accepted as an increment
        s.solve_at(t_split);
        open_pulling(s, t_split, opening);
        s.accept(t_split);
      }
      // The one-split assumption: every pair that overlapped at the full step closes now, at its gap of
      // the reduced step (which the penalty then freezes).
      for (const int p : closing) s.close(p, f > 0 ? s.trial_gap(p) : s.gap(p));
      s.solve_at(t_end);  // the rest of the step, no further test of closure
    }
    open_pulling(s, t_end, {});
    s.accept(t_end);
  }

 private:
  /// Before an increment at load factor t is accepted: the pairs of `at_zero` whose force has fallen to
  /// zero there (the change the step was split at) open, and then any closed pair still pulling opens and
  /// t is solved again, until none pulls: no accepted increment has a closed pair in tension.
  template <class S>
  static void open_pulling(S& s, double t, const std::vector<int>& at_zero) {
    for (const int p : at_zero)
      if (s.closed(p) && s.trial_force(p) <= s.force_tolerance(p)) s.open(p);
    for (int round = 0;; ++round) {
      std::vector<int> pulling;
      for (int p = 0; p < s.pair_count(); ++p)
        if (s.closed(p) && s.trial_force(p) < -s.force_tolerance(p)) pulling.push_back(p);
      if (pulling.empty()) return;
      if (round > s.pair_count()) s.fail("closed pairs kept pulling after every one was opened");
      for (const int p : pulling) s.open(p);
      s.count_round();
      s.solve_at(t);
    }
  }
};

namespace detail {

/// events = step-end: solve to the target, flip every contradicted pair (in the trial only) and re-solve
/// at the same target until none is left, then accept. Rounds that do not settle within `max_rounds`,
/// or a solve that fails, restart from the accepted state over half the interval (down to 1/1024 of
/// the step), growing back to the step's end after every accepted piece.
template <bool kMultipliers, class S>
void settle_at_end(S& s, double t_end, int max_rounds) {
  const double step = t_end - s.load_factor();
  double target     = t_end;
  for (;;) {
    const double t0 = s.load_factor();
    bool settled    = false;
    try {
      for (int round = 0; round <= max_rounds && !settled; ++round) {
        if (round > 0) s.count_round();
        s.solve_at(target);
        if constexpr (kMultipliers) s.settle_multipliers();
        std::vector<int> flips;
        for (int p = 0; p < s.pair_count(); ++p)
          if (contradicted(s, p)) flips.push_back(p);
        for (const int p : flips) s.flip(p);
        settled = flips.empty();
      }
    } catch (const SolveError&) {
      if (target - t0 < step / 1024) throw;
    }
    if (settled) {
      s.accept(target);
      if (target >= t_end) return;
      target = t_end;
      continue;
    }
    s.restart();
    if (target - t0 < step / 1024)
      s.fail("the contact status did not settle in " + std::to_string(max_rounds) +
             " rounds at the end of 1/1024 of the step to load factor " + std::to_string(t_end));
    target = t0 + 0.5 * (target - t0);
    s.count_cut();
  }
}

/// ActiveSet and AugmentedLagrangian: event-driven. Solve to the step's end with the current statuses;
/// if a pair would change status, interpolate (the response is linear while statuses hold) to the first
/// change, accept that point, flip every pair changing there, and continue from it. With events =
/// step-end, settle_at_end instead.
template <bool kMultipliers, class S>
void event_step(S& s, double t_end, int max_events) {
  // Settling rounds close or open every contradicted pair at once, so a few suffice unless they cycle.
  if (!s.locate_events()) return settle_at_end<kMultipliers>(s, t_end, std::min(max_events, 25));
  const auto solve = [&](double t) {
    s.solve_at(t);
    if constexpr (kMultipliers) s.settle_multipliers();
  };
  // A nonlinear response (plasticity, Coulomb slip) may not converge over the whole interval at once
  // (a step that presses a fit shut and slides it): the target is then halved, down to 1/1024 of the
  // step, and grows back to the step's end after every accepted piece. A linear response never fails.
  const double step = t_end - s.load_factor();
  double target     = t_end;
  for (int event = 0; event <= max_events;) {
    const double t0 = s.load_factor();
    if constexpr (S::linear_response()) {
      solve(target);
    } else {
      try {
        solve(target);
      } catch (const SolveError&) {
        if (target - t0 < step / 1024) throw;
        target = t0 + 0.5 * (target - t0);
        s.count_cut();
        continue;
      }
    }
    double first = 2;
    std::vector<std::tuple<double, int, bool>> change;  // (fraction of the interval, pair, opening)
    for (int p = 0; p < s.pair_count(); ++p)
      if (contradicted(s, p)) {
        const double f = change_fraction(s, p);
        change.emplace_back(f, p, s.closed(p)), first = std::min(first, f);
      }
    if (change.empty()) {
      s.accept(target);
      if (target >= t_end) return;
      target = t_end;
      continue;
    }
    ++event;
    s.count_split();
    double t_event = t0 + first * (target - t0);
    if (first > 0) {
      // The first pair to change, its gap (closing) or force (opening) at the start and at the target.
      const int q        = std::get<1>(*std::min_element(change.begin(), change.end()));
      const auto value   = [&] { return s.closed(q) ? s.trial_force(q) : s.trial_gap(q); };
      const double start = s.closed(q) ? std::max(s.force(q), 0.0) : std::max(s.gap(q), 0.0);
      double h_hi        = value();
      solve(t_event);
      if constexpr (!S::linear_response()) {
        // Plasticity or Coulomb slip: the interpolated point is only close. Regula falsi (Illinois)
        // between the start and the target until the value is zero to 1e-9 of its start value.
        const double tol = std::max(1e-9 * start, s.closed(q) ? s.force_tolerance(q) : s.gap_tolerance());
        double lo = t0, h_lo = start, hi = target, h = value();
        for (int k = 0, side = 0; k < 30 && std::abs(h) > tol; ++k) {
          if (h > 0) {
            lo = t_event, h_lo = h;
            if (side == 1) h_hi *= 0.5;
            side = 1;
          } else {
            hi = t_event, h_hi = h;
            if (side == -1) h_lo *= 0.5;
            side = -1;
          }
          t_event = lo + h_lo / (h_lo - h_hi) * (hi - lo);
          solve(t_event);
          h = value();
        }
      }
    }
    // Pairs whose change falls within 1e-9 of the first go together (a uniform gap closes at once). At the
    // located point a pair that opens carries no force: it is open there, and the accepted increment (its
    // row in gaps.csv) says so; a nonlinear search that stopped short leaves one with force, which opens
    // after the accept. One that closes has no gap there: it closes from that point on.
    const auto changes = [&](auto&& act) {
      for (const auto& [f, p, opens] : change)
        if (f <= first + 1e-9) act(p, opens);
    };
    changes([&](int p, bool opens) {
      if (opens && s.closed(p) && s.trial_force(p) <= s.force_tolerance(p)) s.open(p);
    });
    if (first > 0) s.accept(t_event);
    changes([&](int p, bool opens) {
      if (opens && s.closed(p))
        s.open(p);
      else if (!opens && !s.closed(p))
        s.close(p, 0.0);
    });
    target = t_end;
  }
  s.fail("the contact status did not settle after " + std::to_string(max_events) +
         " changes in the step to load factor " + std::to_string(t_end));
}

}  // namespace detail

struct ActiveSet {
  static constexpr std::string_view kName = "active-set";
  static constexpr bool kContact          = true;
  static constexpr double kDefaultPenalty = 1e4;  // constraint error ~1e-4 of the adjacent deformation
  static constexpr double kMaxPenalty     = 1e300;
  template <class S>
  static void step(S& s, double t_end) {
    detail::event_step<false>(s, t_end, 20 + 4 * s.pair_count());
  }
};

struct AugmentedLagrangian {
  static constexpr std::string_view kName = "augmented-lagrangian";
  static constexpr bool kContact          = true;
  static constexpr double kDefaultPenalty = 100;
  // The multipliers make the constraint exact, so the penalty is only a convergence rate: above 1e6 it
  // gains nothing and costs digits (the penalty sweep test: residuals grow ~kappa, LDL^T fails at 1e12).
  static constexpr double kMaxPenalty = 1e6;
  template <class S>
  static void step(S& s, double t_end) {
    detail::event_step<true>(s, t_end, 20 + 4 * s.pair_count());
  }
};

static_assert(ContactPolicy<NoContact> && ContactPolicy<Saac> && ContactPolicy<ActiveSet> &&
              ContactPolicy<AugmentedLagrangian>);

}  // namespace gapfe

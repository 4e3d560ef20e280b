#pragma once
// ContactStepper: what a contact policy (contact/policies.hpp) may ask of the analysis it steps, as an
// object the policy receives: ContactStatic::advance() makes one and hands it to Policy::step. It meets the
// policies' contract (detail::StepperArchetype: accepted and trial gaps and forces, solve at a load
// factor, close, open, flip, accept, restart), and it is the only way to those calls: they are private to
// ContactStatic (driver/contact_static.hpp), whose own API is advance() and the results.
#include <algorithm>
#include <string>

#include "gapfe/contact/pair_state.hpp"
#include "gapfe/contact/policies.hpp"

namespace gapfe {

template <class Contact>
class ContactStepper {
 public:
  explicit ContactStepper(Contact& c) : c_(c) {}

  double load_factor() const { return c_.t_; }
  int pair_count() const { return c_.pair_count(); }
  bool closed(int p) const { return trial(p).closed; }
  double gap(int p) const { return accepted(p).gap; }             ///< at the accepted state [length]
  double force(int p) const { return accepted(p).normal_force; }  ///< at the accepted state [force]
  double trial_gap(int p) const { return trial(p).gap; }          ///< after the last solve [length]
  double trial_force(int p) const { return trial(p).normal_force; }
  /// An open pair overlaps when its gap is below minus this [length]: 1e-12 of the model size, or 1e-6
  /// of the smallest initial clearance where that is smaller (contact/penalty.hpp, gap_tolerance_of).
  double gap_tolerance() const { return c_.gap_tolerance_; }
  double force_tolerance(int p) const { return c_.force_tolerance(p); }
  /// Between two status changes the response is linear in the load factor (elastic, no Coulomb slip): the
  /// policies then find an event by one interpolation, otherwise by a few more solves.
  static constexpr bool linear_response() { return Contact::kLinearResponse; }
  bool locate_events() const { return c_.opt_.locate_events; }

  void solve_at(double t) { c_.solve_at(t); }
  void settle_multipliers() { c_.settle_multipliers(); }
  void close(int p, double reference_gap) { c_.close(p, reference_gap); }
  void open(int p) { c_.open(p); }
  /// Pair p changes status in the trial only (settling at the step's end; restart() undoes it). A pair
  /// that closes does so at the interpolated point of its gap (detail::closure_fraction, exact for a
  /// linear response): that is its closure load, and its tangential spring starts from its slide there.
  void flip(int p) {
    c_.flip(p, accepted(p).closed ? 0.0 : std::clamp(detail::closure_fraction(*this, p), 0.0, 1.0));
  }
  void restart() { c_.restart(); }
  void accept(double t) { c_.accept(t); }
  void count_split() { ++c_.count_.splits; }
  void count_cut() { ++c_.count_.cuts; }
  void count_round() { ++c_.count_.status_rounds; }
  [[noreturn]] void fail(const std::string& why) const { c_.fail(why); }

 private:
  const PairState& accepted(int p) const { return c_.set_.history().committed(static_cast<std::size_t>(p)); }
  const PairState& trial(int p) const { return c_.set_.history().trial(static_cast<std::size_t>(p)); }
  Contact& c_;
};

}  // namespace gapfe

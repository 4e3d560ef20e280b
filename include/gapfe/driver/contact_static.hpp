#pragma once
// ContactStatic: an analysis with gap pairs, stepped in load factor under a contact policy
// (contact/policies.hpp), over LinearStatic or, for laws with history, NonlinearStatic (SAAC = SAGAEP +
// gaps). The pairs and their states are a GapPairSet (contact/pair_set.hpp), whose History is committed
// with the driver's material history at every accepted increment. Each closed pair is a node link k n n^T
// (assembly/node_links.hpp) whose coupling is in the stiffness pattern from the start, so the symbolic
// factorization is done once; a solve refactorizes only after a pair changed status, and
// augmented-Lagrangian updates (contact/uzawa.hpp) and repeated (split) steps reuse the factorization.
//
// The policy steps the analysis through a ContactStepper (driver/contact_stepper.hpp), the object it
// receives in advance(): solve at a load factor, close, open or flip a pair, accept, restart. Those calls
// are this class's private business; its public face is advance() and the results.
//
// Loads are given as a function loads_at(Problem&, t) that puts the loads at load factor t into the
// problem; the response between two solves is linear in t while no pair changes status, which is what
// step splitting relies on. The penalty of a pair is k = kappa max(n^T K_aa n, n^T K_bb n), K_aa the
// node's diagonal block of the structural (non-gap) elements (docs/theory.md 5.4).
//
// Friction (contact/friction.hpp) is the third parameter; the pair force and its tangent are
// GapPairSet's. The Coulomb slip term of the tangent is unsymmetric: a solver with full storage (EigenLu,
// UMFPACK) takes it as it is; a symmetric solver gets the tangent without it, and Newton converges
// linearly instead of quadratically (tests/test_friction.cpp and BENCHMARKS.md measure both; averaging it
// into (K + K^T) / 2 instead was tried: it cycles, and makes LDL^T indefinite). Coulomb is nonlinear in d,
// so a solve becomes Newton iterations: over LinearStatic, re-linearize and re-solve the links until the
// pair forces balance (contact/pair_newton.hpp); over NonlinearStatic, the pair forces are re-linearized
// at every Newton iterate of the material loop, so plastic history and friction converge together.
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "gapfe/contact/friction.hpp"
#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/contact/pair_newton.hpp"
#include "gapfe/contact/pair_set.hpp"
#include "gapfe/contact/pair_state.hpp"
#include "gapfe/contact/penalty.hpp"
#include "gapfe/contact/policies.hpp"
#include "gapfe/contact/stick_check.hpp"
#include "gapfe/contact/uzawa.hpp"
#include "gapfe/driver/contact_options.hpp"
#include "gapfe/driver/contact_stepper.hpp"
#include "gapfe/driver/linear_static.hpp"
#include "gapfe/driver/nonlinear_static.hpp"

namespace gapfe {

template <class M, ContactPolicy Policy, FrictionModel Friction = NoFriction>
class ContactStatic {
  static_assert(kSupported<typename M::Material, typename M::Element, Policy, Friction>,
                "ContactStatic: the library does not run this combination (core/combinations.hpp says why)");
  static constexpr int kNd = M::kDofsPerNode;
  /// A symmetric solver reads the lower triangle: links get the tangent without the slip coupling.
  static constexpr bool kSymmetrize = storage_of<typename M::LinearSolver>() == MatrixStorage::lower;
  friend class ContactStepper<ContactStatic>;
  /// Linear in the load factor between two status changes (elastic, no Coulomb slip): the policies then
  /// find an event by one interpolation, otherwise by a few more solves.
  static constexpr bool kLinearResponse = M::Material::kLinear && !Friction::kIterative;

 public:
  /// LinearStatic for elastic laws; NonlinearStatic (Newton, history) for laws with history: SAAC is
  /// SAGAEP plus gaps. Every trial solve starts from the committed history; an accepted increment commits it.
  using Fe          = std::conditional_t<M::Material::kLinear, LinearStatic<M>, NonlinearStatic<M>>;
  using LoadsAt     = std::function<void(Problem<M>&, double)>;
  using OnIncrement = std::function<void(double, const ContactStatic&)>;

  // Not copyable: Coulomb over NonlinearStatic hands the driver a callback into this object.
  ContactStatic(const ContactStatic&)            = delete;
  ContactStatic& operator=(const ContactStatic&) = delete;

  /// `solver`: the linear solver of the driver underneath (empty: a default-constructed M::LinearSolver).
  ContactStatic(Problem<M> problem, std::vector<GapPair> pairs, ContactOptions options = {},
                std::unique_ptr<typename M::LinearSolver> solver = nullptr)
      : opt_(std::move(options)),
        set_(std::move(pairs), opt_.friction),
        fe_(make_fe(std::move(problem), links_of(set_.pairs()), std::move(solver))) {
    fe_.defer_reactions(true);  // trial solves need displacements only; reactions when an increment is read
    check_options(opt_);
    kappa_ = std::min(opt_.penalty_factor > 0 ? opt_.penalty_factor : Policy::kDefaultPenalty,
                      Policy::kMaxPenalty);
    gap_tolerance_ = gap_tolerance_of(set_.pairs(), fe_.problem().mesh.size());
    if constexpr (Policy::kContact) set_penalties();
    if constexpr (Friction::kStressCheck)
      around_ = structural_cells_around(set_.pairs(), fe_.problem().mesh, opt_.gap_materials);
    evaluate_pairs();
    set_.commit();
    if constexpr (Friction::kIterative && !M::Material::kLinear)
      fe_.set_link_update([this](const VecX& u, bool start) {
        set_.set_predicting(start);  // the start of a Newton pass is a prediction (GapPairSet::evaluate_at)
        set_.evaluate([&](int n) {
          Vec3 v                 = Vec3::Zero();
          v.template head<kNd>() = u.template segment<kNd>(kNd * n);
          return v;
        });
        set_.set_predicting(false);
        set_links();
      });
  }

  /// Advance to load factor t_end under the policy, which steps through a ContactStepper;
  /// `on_increment(t, *this)` sees every accepted increment (a split step gives more than one).
  void advance(double t_end, const LoadsAt& loads_at, const OnIncrement& on_increment = {}) {
    struct Forget {  // the caller's callbacks, also when the policy throws (TimeErrorExceeded, SolveError)
      ContactStatic& c;
      ~Forget() { c.loads_at_ = nullptr, c.on_increment_ = nullptr; }
    } forget{*this};
    loads_at_ = &loads_at, on_increment_ = &on_increment, step_end_ = t_end;
    ContactStepper<ContactStatic> stepper(*this);
    Policy::step(stepper, t_end);
  }
  /// Back to the accepted statuses and pair states (a settling that did not settle; an interval its caller
  /// repeats in pieces after TimeErrorExceeded).
  void restart() {
    set_.history().reject();
    status_changed_ = true, warm_start_ = false;
  }
  /// The accepted load factor.
  double load_factor() const { return t_; }

  const Fe& fe() const { return fe_; }
  Fe& fe() { return fe_; }
  const std::vector<GapPair>& pairs() const { return set_.pairs(); }
  const std::vector<PairState>& states() const { return set_.history().committed(); }
  int pair_count() const { return static_cast<int>(set_.size()); }
  double penalty(int p) const { return set_.penalty(static_cast<std::size_t>(p)); }
  /// k_t of pair p [force/length] (0 without friction).
  double tangential_penalty(int p) const { return set_.tangential_penalty(static_cast<std::size_t>(p)); }
  /// The link of pair p as the last solve used it: stiffness on u_b - u_a and force (node_links.hpp).
  const NodeLink& link(int p) const { return fe_.link_values()[static_cast<std::size_t>(p)]; }
  /// Coulomb: the relative pair-force imbalance after each linear solve of the last solve (the
  /// quadratic-convergence test reads it); over NonlinearStatic, its Newton residuals.
  const std::vector<double>& friction_residuals() const { return friction_residuals_; }
  /// kappa in use: the option or the policy's default, capped by the policy's kMaxPenalty.
  double penalty_factor() const { return kappa_; }
  const ContactCounters& counters() const { return count_; }
  void reset_counters() { count_ = {}, factorizations_at_reset_ = fe_.factorizations(); }
  /// Largest overlap of a closed pair at the accepted state [length] (0 when none overlaps).
  double max_penetration() const {
    double m = 0;
    for (const auto& s : states())
      if (s.closed) m = std::max(m, -s.gap);
    return m;
  }

 private:
  // ---- the stepping the policies ask for (through ContactStepper)
  void solve_at(double t);
  void settle_multipliers();
  void accept(double t);
  void close(int p, double reference_gap) {
    set_.close(static_cast<std::size_t>(p), reference_gap, t_);
    status_changed_ = true;
    evaluate_pairs();
  }
  void open(int p) {
    set_.open(static_cast<std::size_t>(p));
    status_changed_ = true;
    evaluate_pairs();
  }
  /// Settling at the step's end: pair p changes status in the trial only, a closing pair at fraction f of
  /// the interval from the accepted state to the last solve (ContactStepper::flip).
  void flip(int p, double f) {
    set_.flip(static_cast<std::size_t>(p), f, t_, t_trial_);
    status_changed_ = warm_start_ = true;
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw SolveError("contact (" + std::string(Policy::kName) + "): " + why);
  }
  double force_tolerance(int p) const { return penalty(p) * gap_tolerance_; }

  static Fe make_fe(Problem<M> problem, Connectivity<2> links,
                    std::unique_ptr<typename M::LinearSolver> solver) {
    if constexpr (M::Material::kLinear)
      return Fe(std::move(problem), std::move(links), std::move(solver));
    else
      return Fe(std::move(problem), std::move(links), NewtonOptions{}, std::move(solver));
  }
  static Connectivity<2> links_of(const std::vector<GapPair>& pairs) {
    Connectivity<2> l;
    if constexpr (Policy::kContact)
      for (const auto& p : pairs) l.push_back({p.node_a, p.node_b});
    return l;
  }
  /// The pairs' penalties k = kappa x the adjacent structure's stiffness along n, and k_t with friction;
  /// InputError for a pair with no structure next to it or an open gap element too stiff to be soft.
  void set_penalties() {
    if (!(kappa_ > 0) || !std::isfinite(kappa_))
      throw InputError("contact: the penalty factor must be a positive number");
    const auto& gaps      = opt_.gap_materials;
    const auto structural = [&](const CellTag& t) {
      return std::find(gaps.begin(), gaps.end(), t.material) == gaps.end();
    };
    const std::vector<double> adjacent = adjacent_stiffness(fe_.nodal_stiffness(structural), set_.pairs());
    std::vector<double> k, k_t;
    for (const double a : adjacent) k.push_back(kappa_ * a);
    if (!gaps.empty())
      check_soft_gaps(set_.pairs(), fe_.nodal_stiffness([&](const CellTag& t) { return !structural(t); }),
                      kappa_, k, opt_.max_soft_share);
    if constexpr (Friction::kFriction) {
      const double kappa_t = std::min(
          opt_.tangential_penalty_factor > 0 ? opt_.tangential_penalty_factor : kappa_, Policy::kMaxPenalty);
      if (!(kappa_t > 0) || !std::isfinite(kappa_t))
        throw InputError("friction: the tangential penalty factor must be a positive number");
      for (std::size_t p = 0; p < k.size(); ++p)
        k_t.push_back(std::is_same_v<Friction, Proportional> ? opt_.friction * k[p]
                      : std::is_same_v<Friction, Extended>   ? k[p]
                                                             : kappa_t * adjacent[p]);
    }
    set_.set_penalties(std::move(k), std::move(k_t));
  }
  /// The links of the trial states into the driver's node links (GapPairSet::update_links).
  void set_links() {
    if constexpr (Policy::kContact) {
      const auto& pairs = set_.update_links(kSymmetrize || opt_.symmetric_tangent, M::Material::kLinear);
      auto& links       = fe_.link_values();
      for (std::size_t p = 0; p < pairs.size(); ++p)
        links[p].stiffness = pairs[p].stiffness, links[p].force = pairs[p].force;
    }
  }
  void equilibrium(bool assemble);
  /// The pairs at the last solve's displacement (zero before the first).
  void evaluate_pairs() {
    const auto& u = fe_.displacement();
    set_.evaluate(
        [&](int node) -> Vec3 { return u.rows() > 0 ? Vec3(u.row(node).transpose()) : Vec3::Zero(); });
  }

  ContactOptions opt_;
  GapPairSet<Friction, kNd> set_;
  Fe fe_;
  std::vector<std::vector<int>> around_;  ///< Extended: structural cells around each pair
  std::vector<double> friction_residuals_;
  double t_ = 0, t_trial_ = 0, kappa_ = 0;  ///< accepted and last solved load factors; kappa
  double gap_tolerance_ = 1e-12;            ///< an open pair overlaps below minus this [length]
  bool status_changed_  = true;
  bool warm_start_      = false;  ///< Coulomb: the next solve's Newton starts from the last solve
  double step_end_      = 0;      ///< the load factor the current advance() goes to
  ContactCounters count_;
  int factorizations_at_reset_     = 0;
  const LoadsAt* loads_at_         = nullptr;
  const OnIncrement* on_increment_ = nullptr;
};

template <class M, ContactPolicy Policy, FrictionModel Friction>
void ContactStatic<M, Policy, Friction>::solve_at(double t) {
  t_trial_ = t;
  (*loads_at_)(fe_.problem(), t);
  if constexpr (!M::Material::kLinear) fe_.context() = {t * opt_.step_time, (t - t_) * opt_.step_time};
  // Coulomb's Newton starts from the accepted state, whatever a failed or rejected solve left; after flips
  // at the same target (settling at the step's end) from the last solve instead, where the pairs just
  // closed overlap and have slid: their normal force and slip direction are about right there (from the
  // accepted state they are open, and Newton cycles between stuck and slipping linearizations on the
  // press-fit path). Without Coulomb, a status flipped or restored since the last evaluation re-evaluates
  // the links at the last displacement. The tangential base of a pair whose status the trial did not change
  // is the accepted one: the return mapping measures from the accepted force, and an augmented-Lagrangian
  // update of another solve (at the step's end, before an event point inside it was located) belongs to
  // another load.
  set_.keep_accepted_bases();
  if constexpr (Friction::kIterative) {
    // Over an elastic structure this evaluation is the solve's first linearization, a prediction; over a
    // plastic one the material Newton's first link update is. A cold start has no last linearization to
    // reverse against.
    set_.set_predicting(M::Material::kLinear);
    if (warm_start_)
      evaluate_pairs();
    else
      set_.evaluate_accepted();
    set_.set_predicting(false);
  } else if (status_changed_) {
    evaluate_pairs();
  }
  warm_start_ = false;
  try {
    equilibrium(true);
  } catch (const SolveError& e) {
    if (!set_.any_closed_trial()) throw;
    throw SolveError(std::string(e.what()) + " (closed gap pairs at penalty " + detail::number_text(kappa_) +
                     " x the adjacent stiffness: a penalty this large can make the stiffness numerically "
                     "singular; lower gap_penalty or use the augmented-lagrangian policy)");
  }
}

/// Set the links, solve (assembling the element system when `assemble`, else re-using it) and, for Coulomb
/// over an elastic structure, Newton on the pair forces (contact/pair_newton.hpp).
template <class M, ContactPolicy Policy, FrictionModel Friction>
void ContactStatic<M, Policy, Friction>::equilibrium(bool assemble) {
  set_links();
  // The factorization is reused while no pair changed status and, for Coulomb, no link stiffness changed: a
  // fit slipping on in 2D keeps its slip tangent from one push step to the next.
  const bool same_links = Friction::kIterative ? !set_.links_changed() : true;
  if (assemble)
    fe_.solve(!status_changed_ && same_links);
  else
    fe_.resolve_links(same_links);
  status_changed_ = false;
  ++count_.solves;
  evaluate_pairs();
  if constexpr (Friction::kIterative && M::Material::kLinear) {
    const bool stalled = pair_newton(
        set_, {opt_.friction_tolerance, opt_.max_friction_iterations}, t_trial_, friction_residuals_,
        [&] {
          set_links();
          fe_.resolve_links(!set_.links_changed());
          ++count_.solves, ++count_.friction_iterations;
          evaluate_pairs();
        },
        [&](const std::string& why) { fail(why); });
    count_.friction_stalls += stalled;
  } else if constexpr (Friction::kIterative) {
    friction_residuals_ = fe_.report().residuals;
    count_.friction_iterations += fe_.report().iterations;
  }
}

/// Uzawa (contact/uzawa.hpp) to penetration_tolerance x max |u| over the whole model.
template <class M, ContactPolicy Policy, FrictionModel Friction>
void ContactStatic<M, Policy, Friction>::settle_multipliers() {
  const auto tolerance = [&] {
    double scale = std::max(fe_.displacement().cwiseAbs().maxCoeff(), gap_tolerance_);
    if (const Subdomain* part = fe_.problem().subdomain.get()) scale = part->max(scale);  // the whole's
    return opt_.penetration_tolerance * scale;
  };
  uzawa_updates(
      set_, Friction::kFriction, opt_.max_multiplier_updates, tolerance,
      [&] {
        evaluate_pairs();
        equilibrium(false);
        ++count_.multiplier_updates;
      },
      [&](const std::string& why) { fail(why); });
}

template <class M, ContactPolicy Policy, FrictionModel Friction>
void ContactStatic<M, Policy, Friction>::accept(double t) {
  if constexpr (!M::Material::kLinear)
    if (opt_.time_tolerance > 0 && fe_.report().time_error > opt_.time_tolerance &&
        t - t_ > 1.5 * kSmallestTimePiece)  // a piece of the smallest size, whatever the round-off of t
      throw TimeErrorExceeded("time error " + detail::number_text(fe_.report().time_error));
  if constexpr (!M::Material::kLinear) fe_.commit();
  t_ = t;
  set_.set_slip_on(t >= step_end_);
  if (set_.prepare_accept([&](std::size_t p) { return force_tolerance(static_cast<int>(p)); }))
    status_changed_ = true;
  set_.commit();
  count_.factorizations = fe_.factorizations() - factorizations_at_reset_;
  // The increment as it was solved (the extended model's status the step ran with), then the next step's
  // status from its stresses and the next step's first linearization.
  if (on_increment_ && *on_increment_) (*on_increment_)(t, *this);
  if constexpr (Friction::kStressCheck) {
    const auto& accepted = set_.history().committed();
    if (std::any_of(accepted.begin(), accepted.end(), [](const PairState& s) { return s.closed; }) &&
        decide_stick_slip(set_.pairs(), set_.history(), around_, fe_.centroid_values(Recovered::stress),
                          fe_.problem().subdomain.get(), opt_.friction))
      status_changed_ = true;
  }
  if constexpr (Friction::kFriction) evaluate_pairs();
}

}  // namespace gapfe

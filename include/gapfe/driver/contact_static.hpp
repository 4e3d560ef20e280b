#pragma once
// ContactStatic: an analysis with gap pairs, stepped in load factor under a contact policy
// (contact/policies.hpp), over LinearStatic or, for laws with history, NonlinearStatic (SAAC = SAGAEP +
// gaps). The pairs' states are a History (core/history.hpp): every trial solve writes the trial records,
// an accepted increment commits them together with the driver's material history. Each closed pair is a node
// link k n n^T (assembly/node_links.hpp) whose coupling is in the stiffness pattern from the start, so the
// symbolic factorization is done once; a solve refactorizes only after a pair changed status, and
// augmented-Lagrangian updates and repeated (split) steps reuse the factorization.
//
// Loads are given as a function loads_at(Problem&, t) that puts the loads at load factor t into the
// problem; the response between two solves is linear in t while no pair changes status, which is what
// step splitting relies on. The penalty of a pair is k = kappa max(n^T K_aa n, n^T K_bb n), K_aa the
// node's diagonal block of the structural (non-gap) elements (THEORY.md 5.4).
//
// Friction (contact/friction.hpp) is the third parameter. A closed pair's link then carries the normal
// spring and the tangential model's force and tangent, linearized at the current displacement:
//   f_b = P n + E t,   K = -df_b/dd = k n n^T + E K_tt E^T + k E (dt/dP) n^T,   E = [T, S] (3 x 2),
// with d = u_b - u_a. The last term (Coulomb slip) is unsymmetric: a solver with full storage
// (EigenLu, UMFPACK) takes it as it is; a symmetric solver gets the tangent without it, and Newton
// converges linearly instead of quadratically (tests/test_friction.cpp and BENCHMARKS.md measure both;
// averaging it into (K + K^T) / 2 instead was tried: it cycles, and makes LDL^T indefinite). Coulomb is
// nonlinear in d, so a solve becomes Newton iterations: over LinearStatic, re-linearize and re-solve the
// links until the pair forces balance; over NonlinearStatic, the pair forces are re-linearized at every
// Newton iterate of the material loop, so plastic history and friction converge together.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "gapfe/contact/friction.hpp"
#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/contact/pair_state.hpp"
#include "gapfe/contact/policies.hpp"
#include "gapfe/core/history.hpp"
#include "gapfe/driver/linear_static.hpp"
#include "gapfe/driver/nonlinear_static.hpp"

namespace gapfe {

struct ContactOptions {
  double penalty_factor = 0;            ///< kappa; 0: the policy's kDefaultPenalty
  std::vector<int> gap_materials;       ///< material indices of gap elements, left out of the penalty scale
  double penetration_tolerance = 1e-8;  ///< augmented Lagrangian: |g| of closed pairs <= this x max |u|
  int max_multiplier_updates   = 200;   ///< per solve, before the run fails
  double max_soft_share        = 1e-2;  ///< open gap element stiffness / adjacent stiffness allowed
  double friction              = 0;     ///< mu >= 0 (models other than NoFriction)
  /// Laws that estimate a time error (StepReport::time_error): an increment longer than the smallest piece
  /// (kSmallestTimePiece of a load step) whose estimate exceeds this is not accepted: accept() throws
  /// TimeErrorExceeded (run_deck_contact restarts and repeats the piece in halves). 0: off.
  double time_tolerance = 0;
  /// Coulomb: k_t / adjacent stiffness; 0: the normal penalty factor (k_t = k). Proportional and
  /// Extended take theirs from the seed (mu k and k).
  double tangential_penalty_factor = 0;
  double friction_tolerance        = 1e-10;  ///< Coulomb: pair force imbalance / pair force to stop at
  int max_friction_iterations      = 40;     ///< Coulomb: Newton iterations per solve, then a SolveError
  /// Coulomb: leave the slip's unsymmetric coupling out of the pair tangents even when the solver reads
  /// every entry (always so for a symmetric solver). Newton then converges linearly; the tests measure it.
  bool symmetric_tangent = false;
  /// Exact policies: split the step at every status change, so closure loads are exact (true, the
  /// default), or let the statuses settle at the step's end by active-set rounds, without splitting
  /// (false; deck key `events = step-end`): far fewer solves on a path with many closures, at an O(step)
  /// error of a path-dependent response (friction, plasticity) that the friction benchmarks measure.
  bool locate_events = true;
  /// Time one unit of load factor lasts [model time unit], for rate-dependent laws: the deck's card 0
  /// delta t. A split or cut piece of a step lasts its fraction, so the rate stays what the load asks.
  double step_time = 1;
};

template <class M, ContactPolicy Policy, FrictionModel Friction = NoFriction>
class ContactStatic {
  static_assert(kSupported<typename M::Material, typename M::Element, Policy, Friction>,
                "ContactStatic: the library does not run this combination (core/combinations.hpp says why)");
  static constexpr int kNd = M::kDofsPerNode;
  /// A symmetric solver reads the lower triangle: links get the tangent without the slip coupling.
  static constexpr bool kSymmetrize = storage_of<typename M::LinearSolver>() == MatrixStorage::lower;

 public:
  /// LinearStatic for elastic laws; NonlinearStatic (Newton, history) for laws with history: SAAC is
  /// SAGAEP plus gaps. Every trial solve starts from the committed history; accept() commits it.
  using Fe          = std::conditional_t<M::Material::kLinear, LinearStatic<M>, NonlinearStatic<M>>;
  using LoadsAt     = std::function<void(Problem<M>&, double)>;
  using OnIncrement = std::function<void(double, const ContactStatic&)>;

  // Not copyable: Coulomb over NonlinearStatic hands the driver a callback into this object.
  ContactStatic(const ContactStatic&)            = delete;
  ContactStatic& operator=(const ContactStatic&) = delete;

  /// `solver`: the linear solver of the driver underneath (empty: a default-constructed M::LinearSolver).
  ContactStatic(Problem<M> problem, std::vector<GapPair> pairs, ContactOptions options = {},
                std::unique_ptr<typename M::LinearSolver> solver = nullptr)
      : pairs_(std::move(pairs)),
        opt_(std::move(options)),
        fe_(make_fe(std::move(problem), links_of(pairs_), std::move(solver))),
        history_(pairs_.size()) {
    fe_.defer_reactions(true);  // trial solves need displacements only; reactions when an increment is read
    const double kappa = std::min(opt_.penalty_factor > 0 ? opt_.penalty_factor : Policy::kDefaultPenalty,
                                  Policy::kMaxPenalty);
    size_  = fe_.problem().mesh.size();
    kappa_ = kappa;
    // An open pair overlaps when its gap is below -gap_tolerance_: 1e-12 of the model size, or 1e-6 of the
    // smallest initial clearance where that is smaller. Without the second a 1e-13 m gap in a 0.1 m body
    // was crossed by its own size before it counted as closed (closure load 29-50% late; tests/
    // test_contact.cpp, gaps to 1e-12 of the body). A gap's round-off, ~1e-16 of the displacements
    // across it, stays far below either.
    gap_tolerance_ = 1e-12 * size_;
    for (const auto& g : pairs_)
      if (g.initial_gap > 0) gap_tolerance_ = std::min(gap_tolerance_, 1e-6 * g.initial_gap);
    if constexpr (Policy::kContact) {
      if (!(kappa > 0) || !std::isfinite(kappa))
        throw InputError("contact: the penalty factor must be a positive number");
      const auto& gaps = opt_.gap_materials;
      const auto k     = fe_.nodal_stiffness(
          [&](const CellTag& t) { return std::find(gaps.begin(), gaps.end(), t.material) == gaps.end(); });
      for (const GapPair& p : pairs_) {
        const Vec3 n(p.normal(0), p.normal(1), 0.0);
        const double adjacent = std::max(n.dot(k[p.node_a] * n), n.dot(k[p.node_b] * n));
        if (!(adjacent > 0))
          throw InputError("gap element " + std::to_string(p.element + 1) + ": neither node " +
                           std::to_string(p.node_a + 1) + " nor " + std::to_string(p.node_b + 1) +
                           " belongs to a structural element, so there is nothing to scale its penalty by");
        stiffness_.push_back(kappa * adjacent);
        adjacent_.push_back(adjacent);
      }
      // An open gap element must be soft: its own stiffness along N resists closure and shifts the
      // closure load by about its share (seed 2.2: "small relative to the adjacent structure").
      if (!gaps.empty()) {
        const auto soft = fe_.nodal_stiffness(
            [&](const CellTag& t) { return std::find(gaps.begin(), gaps.end(), t.material) != gaps.end(); });
        for (std::size_t q = 0; q < pairs_.size(); ++q) {
          const GapPair& p = pairs_[q];
          const Vec3 n(p.normal(0), p.normal(1), 0.0);
          const double share =
              std::max(n.dot(soft[p.node_a] * n), n.dot(soft[p.node_b] * n)) * kappa / stiffness_[q];
          if (share > opt_.max_soft_share) {
            char text[48];
            std::snprintf(text, sizeof text, "%.3g", share);
            throw InputError("gap element " + std::to_string(p.element + 1) + ": while open it is " + text +
                             " times as stiff along its closure direction as the structure next to it, so it "
                             "would carry load across the gap; lower the gap material's moduli");
          }
        }
      }
    }
    if (!(opt_.step_time > 0) || !std::isfinite(opt_.step_time))
      throw InputError("contact: the time a load step lasts must be a positive number");
    if (!(opt_.friction >= 0) || !std::isfinite(opt_.friction))
      throw InputError("friction: the coefficient mu must be a number >= 0");
    if constexpr (Friction::kFriction) {
      const double kappa_t = std::min(
          opt_.tangential_penalty_factor > 0 ? opt_.tangential_penalty_factor : kappa, Policy::kMaxPenalty);
      if (!(kappa_t > 0) || !std::isfinite(kappa_t))
        throw InputError("friction: the tangential penalty factor must be a positive number");
      for (std::size_t p = 0; p < pairs_.size(); ++p)
        tangential_.push_back(std::is_same_v<Friction, Proportional> ? opt_.friction * stiffness_[p]
                              : std::is_same_v<Friction, Extended>   ? stiffness_[p]
                                                                     : kappa_t * adjacent_[p]);
      if constexpr (Friction::kStressCheck) around_ = structural_cells_around();
    }
    response_.resize(pairs_.size());
    linearized_branch_.assign(pairs_.size(), Vec2::Zero());
    accepted_relative_.assign(pairs_.size(), Vec3::Zero());
    evaluate_pairs();
    history_.commit();
    if constexpr (Friction::kIterative && !M::Material::kLinear)
      fe_.set_link_update([this](const VecX& u, bool start) {
        predicting_ = start;  // the start of a Newton pass is a prediction (evaluate_pairs_at)
        evaluate_pairs([&](int n) {
          Vec3 v                 = Vec3::Zero();
          v.template head<kNd>() = u.template segment<kNd>(kNd * n);
          return v;
        });
        predicting_ = false;
        set_links();
      });
  }

  /// Advance to load factor t_end under the policy; `on_increment(t, *this)` sees every accepted
  /// increment (a split step gives more than one).
  void advance(double t_end, const LoadsAt& loads_at, const OnIncrement& on_increment = {}) {
    struct Forget {  // the caller's callbacks, also when the policy throws (TimeErrorExceeded, SolveError)
      ContactStatic& c;
      ~Forget() { c.loads_at_ = nullptr, c.on_increment_ = nullptr; }
    } forget{*this};
    loads_at_ = &loads_at, on_increment_ = &on_increment, step_end_ = t_end;
    Policy::step(*this, t_end);
  }

  const Fe& fe() const { return fe_; }
  Fe& fe() { return fe_; }
  const std::vector<GapPair>& pairs() const { return pairs_; }
  const std::vector<PairState>& states() const { return history_.committed(); }
  double penalty(int p) const { return stiffness_[p]; }
  /// k_t of pair p [force/length] (0 without friction).
  double tangential_penalty(int p) const { return tangential_.empty() ? 0.0 : tangential_[p]; }
  /// The link of pair p as the last solve used it: stiffness on u_b - u_a and force (node_links.hpp).
  const NodeLink& link(int p) const { return fe_.link_values()[p]; }
  /// Coulomb: the relative pair-force imbalance after each linear solve of the last solve_at (the
  /// quadratic-convergence test reads it); over NonlinearStatic, its Newton residuals.
  const std::vector<double>& friction_residuals() const { return friction_residuals_; }
  /// kappa in use: the option or the policy's default, capped by the policy's kMaxPenalty.
  double penalty_factor() const { return kappa_; }
  const ContactCounters& counters() const { return count_; }
  void reset_counters() { count_ = {}, factorizations_at_reset_ = fe_.factorizations(); }
  /// Largest overlap of a closed pair at the accepted state [length] (0 when none overlaps).
  double max_penetration() const {
    double m = 0;
    for (const auto& s : history_.committed())
      if (s.closed) m = std::max(m, -s.gap);
    return m;
  }

  // ---- the Stepper contract (contact/policies.hpp)
  double load_factor() const { return t_; }
  int pair_count() const { return static_cast<int>(pairs_.size()); }
  bool closed(int p) const { return history_.trial(p).closed; }
  double gap(int p) const { return history_.committed(p).gap; }
  double force(int p) const { return history_.committed(p).normal_force; }
  double trial_gap(int p) const { return history_.trial(p).gap; }
  double trial_force(int p) const { return history_.trial(p).normal_force; }
  /// An open pair overlaps when its gap is below minus this (see the constructor) [length].
  double gap_tolerance() const { return gap_tolerance_; }
  double force_tolerance(int p) const { return stiffness_.empty() ? 0.0 : stiffness_[p] * gap_tolerance(); }
  /// Between two status changes the response is linear in the load factor (elastic, no Coulomb slip):
  /// the policies then find an event by one interpolation, otherwise by a few more solves.
  static constexpr bool linear_response() { return M::Material::kLinear && !Friction::kIterative; }
  bool locate_events() const { return opt_.locate_events; }

  void solve_at(double t) {
    t_trial_ = t;
    (*loads_at_)(fe_.problem(), t);
    if constexpr (!M::Material::kLinear) fe_.context() = {t * opt_.step_time, (t - t_) * opt_.step_time};
    // Coulomb's Newton starts from the accepted state, whatever a failed or rejected solve left; after
    // flips at the same target (settling at the step's end) from the last solve instead, where the pairs
    // just closed overlap and have slid: their normal force and slip direction are about right there
    // (from the accepted state they are open, and Newton cycles between stuck and slipping
    // linearizations on the press-fit path). Without Coulomb, a status flipped or restored since the
    // last evaluation re-evaluates the links at the last displacement. The tangential base t_base of a
    // pair whose status the trial did not change is the accepted one: the return mapping measures from
    // the accepted force, and an augmented-Lagrangian update of another solve (at the step's end, before
    // an event point inside it was located) belongs to another load.
    if constexpr (Friction::kFriction)
      for (std::size_t p = 0; p < pairs_.size(); ++p)
        if (PairState& s = history_.trial(p); s.closed == history_.committed(p).closed)
          s.tangential_base = history_.committed(p).tangential_base;
    if constexpr (Friction::kIterative) {
      // Over an elastic structure this evaluation is the solve's first linearization, a prediction
      // (evaluate_pairs_at); over a plastic one the material Newton's first link update is. A cold start
      // has no last linearization to reverse against.
      predicting_ = M::Material::kLinear;
      if (warm_start_) {
        evaluate_pairs();
      } else {
        std::fill(linearized_branch_.begin(), linearized_branch_.end(), Vec2::Zero());
        evaluate_pairs_at([&](std::size_t p) { return accepted_relative_[p]; });
      }
      predicting_ = false;
    } else if (status_changed_) {
      evaluate_pairs();
    }
    warm_start_ = false;
    try {
      equilibrium(true);
    } catch (const SolveError& e) {
      const auto& trial = history_.trial();
      if (std::none_of(trial.begin(), trial.end(), [](const PairState& s) { return s.closed; })) throw;
      char kappa[32];
      std::snprintf(kappa, sizeof kappa, "%g", penalty_factor());
      throw SolveError(std::string(e.what()) + " (closed gap pairs at penalty " + kappa +
                       " x the adjacent stiffness: a penalty this large can make the stiffness numerically "
                       "singular; lower gap_penalty or use the augmented-lagrangian policy)");
    }
  }
  /// Uzawa: lambda <- lambda - k g on closed pairs, re-solved with the same factorization, until every
  /// closed pair's |g| <= penetration_tolerance x max |u| (THEORY.md 5.5 item 2). With friction the
  /// tangential force gets its own multiplier: t_base <- t, until every sticking pair's slide in the
  /// step is within the same tolerance (exact stick without a huge k_t).
  void settle_multipliers() {
    for (int it = 0;; ++it) {
      double scale = std::max(fe_.displacement().cwiseAbs().maxCoeff(), gap_tolerance());
      if (const Subdomain* part = fe_.problem().subdomain.get()) scale = part->max(scale);  // the whole's
      double worst = 0;
      for (std::size_t p = 0; p < pairs_.size(); ++p) {
        const PairState& s = history_.trial(p);
        if (!s.closed) continue;
        worst = std::max(worst, std::abs(s.gap));
        if (Friction::kFriction && !s.slipping) worst = std::max(worst, (s.slide - s.slide_start).norm());
      }
      if (worst <= opt_.penetration_tolerance * scale) return;
      if (it == opt_.max_multiplier_updates)
        fail("the augmented-Lagrangian updates did not reach the penetration tolerance (" +
             std::to_string(worst) + " after " + std::to_string(it) + " updates)");
      for (std::size_t p = 0; p < pairs_.size(); ++p)
        if (PairState& s = history_.trial(p); s.closed) {
          s.multiplier = s.normal_force;
          // Stick: the tangential multiplier takes the force. Slip: the cone sets the force, and the
          // base stays the accepted force (re-basing a slipping pair on mu P nu made Newton flip its slip
          // direction back and forth on the example's path).
          if (!s.slipping) rebase(s);
        }
      evaluate_pairs();
      equilibrium(false);
      ++count_.multiplier_updates;
    }
  }
  void close(int p, double reference_gap) {
    history_.amend(p, [&](PairState& s) {
      s.closed = true, s.reference_gap = reference_gap, s.multiplier = 0, s.closed_at = t_;
      clear_friction(s);
    });
    status_changed_ = true;
    evaluate_pairs();
  }
  void open(int p) {
    history_.amend(p, [](PairState& s) {
      s.closed = false, s.multiplier = 0, s.reference_gap = 0;
      clear_friction(s);
    });
    status_changed_ = true;
    evaluate_pairs();
  }
  /// Settling at the step's end: pair p changes status in the trial only. A pair that closes does so
  /// at the interpolated point of its gap, f = g_start / (g_start - g_end) of the interval (exact for a
  /// linear response): that is its closure load, and its tangential spring starts from its slide there,
  /// so the slide before closure does not load it.
  void flip(int p) {
    PairState& s             = history_.trial(p);
    const PairState& start   = history_.committed(p);
    const bool was_closed    = s.closed;
    const double f           = start.closed ? 0.0 : std::clamp(detail::closure_fraction(*this, p), 0.0, 1.0);
    const Vec2 slide_closure = start.slide + f * (s.slide - start.slide);
    s.closed = !was_closed, s.multiplier = 0, s.reference_gap = 0;
    clear_friction(s);
    if (!was_closed) s.closed_at = t_ + f * (t_trial_ - t_), s.slide_start = slide_closure;
    status_changed_ = warm_start_ = true;
  }
  /// Back to the accepted statuses and pair states (a settling that did not settle).
  void restart() {
    history_.reject();
    status_changed_ = true, warm_start_ = false;
  }
  void accept(double t) {
    if constexpr (!M::Material::kLinear)
      if (opt_.time_tolerance > 0 && fe_.report().time_error > opt_.time_tolerance &&
          t - t_ > 1.5 * kSmallestTimePiece)  // a piece of the smallest size, whatever the round-off of t
        throw TimeErrorExceeded("time error " + detail::number_text(fe_.report().time_error));
    if constexpr (!M::Material::kLinear) fe_.commit();
    t_       = t;
    slip_on_ = t >= step_end_;
    if constexpr (Friction::kFriction)
      for (std::size_t p = 0; p < pairs_.size(); ++p) {
        PairState& s = history_.trial(p);
        if (s.closed && s.slipping) s.slip += (s.slide - s.slide_start).norm();
        rebase(s);
        s.slide_start = s.slide;
      }
    // A closed pair that pulls by less than the opening tolerance (the policies split or re-solve at a
    // larger pull) is open: P < 0 means its gap is open by as much. It is recorded open, so that no
    // accepted state, and no row of gaps.csv, has a closed pair in tension.
    for (std::size_t p = 0; p < pairs_.size(); ++p)
      if (PairState& s = history_.trial(p);
          s.closed && s.normal_force < 0 && s.normal_force >= -force_tolerance(static_cast<int>(p))) {
        s.closed = false, s.multiplier = 0, s.reference_gap = 0, s.normal_force = 0;
        clear_friction(s);
        status_changed_ = true;
      }
    history_.commit();
    if constexpr (Friction::kIterative)
      for (std::size_t p = 0; p < pairs_.size(); ++p) accepted_relative_[p] = response_[p].relative;
    count_.factorizations = fe_.factorizations() - factorizations_at_reset_;
    // The increment as it was solved (the extended model's status the step ran with), then the next
    // step's status from its stresses and the next step's first linearization.
    if (on_increment_ && *on_increment_) (*on_increment_)(t, *this);
    if constexpr (Friction::kStressCheck) decide_stick_slip();
    if constexpr (Friction::kFriction) evaluate_pairs();
  }
  void count_split() { ++count_.splits; }
  void count_cut() { ++count_.cuts; }
  void count_round() { ++count_.status_rounds; }
  [[noreturn]] void fail(const std::string& why) const {
    throw SolveError("contact (" + std::string(Policy::kName) + "): " + why);
  }

 private:
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
  /// The pair forces of the trial states, linearized at the displacement d the pairs were last evaluated
  /// at: stiffness K (its symmetric part for a symmetric solver) and force f_b + K d (node_links.hpp).
  /// The normal part is written in closed form, (lambda - k (g0 - g_ref)) n, so that a large penalty
  /// adds no round-off through k d.
  void set_links() {
    if constexpr (Policy::kContact) {
      auto& links = fe_.link_values();
      for (std::size_t p = 0; p < pairs_.size(); ++p) {
        const PairState& s    = history_.trial(p);
        linearized_branch_[p] = response_[p].branch;
        if (!s.closed) {
          links[p] = {};
          continue;
        }
        const PairResponse& r = response_[p];
        const Vec3 n(pairs_[p].normal(0), pairs_[p].normal(1), 0.0);
        const Mat33 normal = stiffness_[p] * n * n.transpose();
        links[p].stiffness =
            kSymmetrize || opt_.symmetric_tangent ? r.stiffness : Mat33(r.stiffness + r.coupling);
        links[p].force = (s.multiplier - stiffness_[p] * (pairs_[p].initial_gap - s.reference_gap)) * n;
        // Over an elastic structure the link carries the branch's force, so that a solve lands on the
        // branch's solution (pair_newton measures the imbalance against the pair's true force). Over a
        // plastic one the link's force is the material Newton's residual, which must be the pair's true
        // force: there the branch sets the tangent only.
        if constexpr (Friction::kFriction)
          links[p].force += (M::Material::kLinear ? r.branch_force : r.tangential) +
                            (links[p].stiffness - normal) * r.relative;
      }
    }
  }
  /// Set the links, solve (assembling the element system when `assemble`, else re-using it) and, for
  /// Coulomb over an elastic structure, Newton on the pair forces: the element system is linear, so a
  /// solve with the links linearized at the last iterate is a full Newton step.
  void equilibrium(bool assemble) {
    set_links();
    // The factorization is reused while no pair changed status and, for Coulomb, no link stiffness
    // changed: a fit slipping on in 2D keeps its slip tangent from one push step to the next.
    const bool same_links = Friction::kIterative ? !links_changed() : true;
    if (assemble)
      fe_.solve(!status_changed_ && same_links);
    else
      fe_.resolve_links(same_links);
    status_changed_ = false;
    ++count_.solves;
    evaluate_pairs();
    if constexpr (Friction::kIterative && M::Material::kLinear) {
      pair_newton();
    } else if constexpr (Friction::kIterative) {
      friction_residuals_ = fe_.report().residuals;
      count_.friction_iterations += fe_.report().iterations;
    }
  }
  /// Whether the link stiffnesses now set differ from those of the last call (their kNd x kNd blocks,
  /// what the assembler reads); the solve that follows refactorizes when they do.
  bool links_changed() {
    const auto& links = fe_.link_values();
    bool changed      = factorized_links_.size() != links.size();
    factorized_links_.resize(links.size());
    for (std::size_t p = 0; p < links.size(); ++p) {
      const Mat<kNd, kNd> k = links[p].stiffness.template topLeftCorner<kNd, kNd>();
      if (changed || (k.array() != factorized_links_[p].array()).any())
        changed = true, factorized_links_[p] = k;
    }
    return changed;
  }
  /// Coulomb over an elastic structure: Newton on the pair forces after a solve. The element system is
  /// linear, so a solve with the links linearized at the last iterate is a full Newton step, and the
  /// residual of the whole system lives at the pairs: the structure balances the linearized pair forces
  /// L(d) = F - K d of the links it was solved with, so R = L(d) - f(d) pair by pair (pair_residuals).
  /// Each pair is linearized on the branch of the return mapping it is predicted to end on
  /// (evaluate_pairs_at), which keeps Newton from cycling between slip directions.
  void pair_newton() {
    friction_residuals_.clear();
    std::vector<Vec3> residual(pairs_.size());
    for (int it = 0;; ++it) {
      pair_residuals(residual);
      const double r = residual_norm(residual);
      friction_residuals_.push_back(r);
      if (r <= opt_.friction_tolerance) break;
      // Stalled below 1e-4 for four solves: pairs that have just closed carry forces so small that
      // their stick/slip status and slip direction are decided at round-off. Their force is then right
      // to that fraction of the pair forces; counted in friction_stalls and logged by the command.
      if (it >= 4 && r <= 1e-4 &&
          r >= 0.5 * *std::min_element(friction_residuals_.end() - 5, friction_residuals_.end() - 1)) {
        ++count_.friction_stalls;
        break;
      }
      if (it + 1 >= opt_.max_friction_iterations) {
        std::ostringstream text;
        text << "the friction iterations did not converge in " << opt_.max_friction_iterations
             << " solves at load factor " << t_trial_ << " (relative pair force imbalances";
        for (const double x : friction_residuals_) text << ' ' << x;
        text << "; tolerance " << opt_.friction_tolerance << "): cut the load step";
        fail(text.str());
      }
      set_links();
      fe_.resolve_links(!links_changed());
      ++count_.solves, ++count_.friction_iterations;
      evaluate_pairs();
    }
  }
  /// Per pair, L(d) - f(d) at the pairs' last evaluation d: L the links the last solve balanced, f =
  /// P n + E t the pair force (at every DOF: at a prescribed one the difference would go into the
  /// reaction); zero for open pairs. Only the in-plane components count where the model has no u_theta.
  void pair_residuals(std::vector<Vec3>& out) const {
    const auto& links = fe_.link_values();
    for (std::size_t p = 0; p < pairs_.size(); ++p) {
      const PairState& s = history_.trial(p);
      out[p]             = Vec3::Zero();
      if (!s.closed) continue;
      const PairResponse& r = response_[p];
      const Vec3 n(pairs_[p].normal(0), pairs_[p].normal(1), 0.0);
      out[p] = links[p].force - links[p].stiffness * r.relative - (s.normal_force * n + r.tangential);
      if constexpr (kNd == 2) out[p](2) = 0;
    }
  }
  /// |R| relative to the pair forces |f|, or, when larger, to their round-off (ten ulps of
  /// k (|g0| + |n.d|): P = -k g is a difference of large terms, which matters when a pair has just
  /// closed and P is tiny), so that Newton stops at round-off instead of failing.
  double residual_norm(const std::vector<Vec3>& residual) const {
    double diff = 0, size = 0, noise = 0;
    for (std::size_t p = 0; p < pairs_.size(); ++p) {
      const PairState& s = history_.trial(p);
      if (!s.closed) continue;
      const PairResponse& r = response_[p];
      const Vec3 n(pairs_[p].normal(0), pairs_[p].normal(1), 0.0);
      noise += stiffness_[p] * (std::abs(pairs_[p].initial_gap) + std::abs(n.dot(r.relative)));
      diff += residual[p].squaredNorm();
      size += (s.normal_force * n + r.tangential).template head<kNd>().squaredNorm();
    }
    const double floor = 10 * std::numeric_limits<double>::epsilon() * noise / opt_.friction_tolerance;
    return std::sqrt(diff) / std::max({std::sqrt(size), floor, std::numeric_limits<double>::min()});
  }
  /// Gap, normal force, slide and the friction model's answer of every pair at the displacement
  /// `node(n)` (r, z, theta of node n), into the trial records and response_.
  template <class NodeDisplacement>
  void evaluate_pairs(NodeDisplacement&& node) {
    evaluate_pairs_at([&](std::size_t p) -> Vec3 { return node(pairs_[p].node_b) - node(pairs_[p].node_a); });
  }
  /// The same with each pair's u_b - u_a given directly, `relative(p)`.
  template <class Relative>
  void evaluate_pairs_at(Relative&& relative) {
    for (std::size_t p = 0; p < pairs_.size(); ++p) {
      const GapPair& g = pairs_[p];
      PairState& s     = history_.trial(p);
      PairResponse& r  = response_[p];
      const Vec3 n(g.normal(0), g.normal(1), 0.0);
      r.relative     = relative(p);
      s.gap          = g.gap(r.relative.template head<2>());
      s.normal_force = s.closed ? s.multiplier - stiffness_[p] * (s.gap - s.reference_gap) : 0.0;
      r.tangential = r.branch_force = Vec3::Zero();
      r.branch                      = Vec2::Zero();
      r.coupling                    = Mat33::Zero();
      r.stiffness                   = s.closed ? Mat33(stiffness_[p] * n * n.transpose()) : Mat33::Zero();
      if constexpr (Friction::kFriction) {
        Mat<3, 2> e;  // E = [T, S]: along the gap and theta
        e << g.tangent()(0), 0, g.tangent()(1), 0, 0, 1;
        s.slide = e.transpose() * r.relative;
        if (!s.closed) continue;
        TangentialResponse t =
            Friction::respond({s.slide - s.slide_start, s.tangential_base, s.normal_force, tangential_[p],
                               opt_.friction, s.slipping && (!Friction::kIterative || slip_on_)});
        // The branch of the return mapping the pair is linearized on (PairResponse::branch). Newton
        // linearizes each pair on the branch its evaluation lands on, except where that branch is known
        // to be wrong; the pair is then predicted to stick and linearized on the stick branch itself,
        // t = t_trial - k_t (s - s_now) (not the stick slope through the returned force, whose offset
        // mu P nu - t_trial would keep the next iterate off the stick solution):
        //  - a pair whose slip direction reversed against the branch of the last linearization: its
        //    slide crossed the cone's width mu P / k_t within one iterate, so neither slip direction is
        //    consistent and the stick solution lies between (with k_t ~ 1e9 x mu P that width is below
        //    the iterates' error, and linearizing on the opposite slip branch makes Newton cycle);
        //  - at a solve's first linearization (a prediction from the accepted state), a closed pair
        //    without compression (its cone is empty): it is predicted to carry the stiffness it will
        //    have once pressed, instead of none. Past the prediction such a pair is linearized as it is
        //    (no tangential force, no stiffness): at a converged state a closed pair may be in tension
        //    within the opening tolerance, and a stick linearization of a pair that carries nothing
        //    would leave Newton converging to the stick spring's force, a non-zero imbalance.
        bool stick_branch = !t.slipping;
        if constexpr (Friction::kIterative)
          stick_branch = stick_branch || (predicting_ && !(s.normal_force > 0)) ||
                         t.force.dot(linearized_branch_[p]) < 0;
        s.tangential_force = t.force;
        s.slipping         = t.slipping;
        r.tangential       = e * t.force;
        r.branch           = stick_branch ? Vec2::Zero() : Vec2(t.force.normalized());
        if (stick_branch && t.slipping) {
          t.force              = t.stick_force;
          t.stiffness          = tangential_[p] * Mat<2, 2>::Identity();
          t.normal_force_slope = Vec2::Zero();
        }
        r.branch_force = e * t.force;
        r.stiffness += e * t.stiffness * e.transpose();
        r.coupling = stiffness_[p] * e * t.normal_force_slope * n.transpose();
      }
    }
  }
  /// The same at the last solve's displacement (zero before the first).
  void evaluate_pairs() {
    const auto& u = fe_.displacement();
    evaluate_pairs(
        [&](int node) -> Vec3 { return u.rows() > 0 ? Vec3(u.row(node).transpose()) : Vec3::Zero(); });
  }
  /// The tangential force becomes the base of the next trial (an accepted increment; an Uzawa update).
  static void rebase(PairState& s) { s.tangential_base = s.tangential_force; }
  static void clear_friction(PairState& s) {
    s.tangential_force = s.tangential_base = Vec2::Zero();
    s.slipping                             = false;
  }
  /// Extended (seed 3.2): the real elements around each pair: every non-gap cell with node a or b,
  /// as indices into centroid_values() (cells, then triangles).
  std::vector<std::vector<int>> structural_cells_around() const {
    const auto& mesh = fe_.problem().mesh;
    const auto& gaps = opt_.gap_materials;
    const auto real  = [&](const CellTag& t) {
      return std::find(gaps.begin(), gaps.end(), t.material) == gaps.end();
    };
    std::vector<std::vector<int>> around(pairs_.size());
    const auto add = [&](int index, const auto& nodes) {
      for (std::size_t p = 0; p < pairs_.size(); ++p)
        for (const int v : nodes)
          if (v == pairs_[p].node_a || v == pairs_[p].node_b) {
            around[p].push_back(index);
            break;
          }
    };
    for (std::size_t e = 0; e < mesh.cells.size(); ++e)
      if (real(mesh.cell_tag(e))) add(static_cast<int>(e), mesh.cells[e]);
    for (std::size_t e = 0; e < mesh.triangles.size(); ++e)
      if (real(mesh.triangle_tag(e))) add(static_cast<int>(mesh.cells.size() + e), mesh.triangles[e]);
    return around;
  }
  /// Extended (seed 3.2): at an accepted increment, every closed pair's status for the next step from
  /// the mean stress of the real elements around it, rotated to (N, T, S): stick while the resultant
  /// shear sqrt(tau_NT^2 + tau_NS^2) < mu |sigma_NN| with sigma_NN < 0, else slip. The one-step lag of
  /// the seed's model is here: the status a step runs with was decided by the stresses before it.
  void decide_stick_slip() {
    if (std::none_of(history_.committed().begin(), history_.committed().end(),
                     [](const PairState& s) { return s.closed; }))
      return;
    const std::vector<PointValues> values = fe_.centroid_values(Recovered::stress);
    // Per pair, the sum of the stress tensors around it (9) and their count; a part of a partitioned
    // problem holds only its own cells around a pair, so the parts' sums are added.
    std::vector<double> around(10 * pairs_.size(), 0.0);
    for (std::size_t p = 0; p < pairs_.size(); ++p) {
      if (!history_.committed(p).closed) continue;
      Eigen::Map<Mat33> sum(around.data() + 10 * p);
      for (const int c : around_[p]) sum += voigt::stress_tensor(values[static_cast<std::size_t>(c)].stress);
      around[10 * p + 9] = static_cast<double>(around_[p].size());
    }
    if (const Subdomain* part = fe_.problem().subdomain.get())
      part->sum(around.data(), static_cast<int>(around.size()));
    for (std::size_t p = 0; p < pairs_.size(); ++p) {
      const double count = around[10 * p + 9];
      if (!history_.committed(p).closed || count == 0) continue;
      const Mat33 sigma  = Eigen::Map<const Mat33>(around.data() + 10 * p) / count;
      const Vec2 tangent = pairs_[p].tangent();
      const Vec3 n(pairs_[p].normal(0), pairs_[p].normal(1), 0.0), t(tangent(0), tangent(1), 0.0),
          theta(0, 0, 1);
      const double normal = n.dot(sigma * n);
      const double shear  = std::hypot(t.dot(sigma * n), theta.dot(sigma * n));
      const bool stick    = normal < 0 && shear < opt_.friction * -normal;
      // A pair that switches changes its tangential spring (k in stick, 0 in slip), so the next solve
      // must factorize again: reusing the factor left the extended model's steps after a switch solved
      // with the old springs (relative residual 0.44-0.66 on the press fit; issue 15's penalty sweep).
      if (history_.committed(p).slipping == stick) status_changed_ = true;
      history_.amend(p, [&](PairState& s) { s.slipping = !stick; });
    }
  }

  /// At the displacement a pair was evaluated at: u_b - u_a, the tangential force E t on b, and the
  /// tangent K = -df_b/dd of the pair force f_b = P n + E t on the branch it is linearized on (the stick
  /// branch for a pair predicted to stick, evaluate_pairs_at), as its symmetric part k n n^T +
  /// E K_tt E^T and the slip's unsymmetric coupling k E (dt/dP) n^T.
  struct PairResponse {
    Vec3 relative = Vec3::Zero(), tangential = Vec3::Zero();
    /// The tangential force on the branch the pair is linearized on (E t_trial where it is predicted to
    /// stick while its evaluation slips, else E t) and that branch's slip direction (zero: stick).
    Vec3 branch_force = Vec3::Zero();
    Vec2 branch       = Vec2::Zero();
    Mat33 stiffness = Mat33::Zero(), coupling = Mat33::Zero();
  };

  std::vector<GapPair> pairs_;
  ContactOptions opt_;
  Fe fe_;
  std::vector<double> stiffness_, adjacent_, tangential_;  ///< k, adjacent stiffness, k_t per pair
  std::vector<PairResponse> response_;
  std::vector<Vec3> accepted_relative_;   ///< Coulomb: u_b - u_a per pair at the accepted state
  std::vector<Vec2> linearized_branch_;   ///< Coulomb: PairResponse::branch of the links last set
  std::vector<std::vector<int>> around_;  ///< Extended: real cells around each pair
  std::vector<double> friction_residuals_;
  std::vector<Mat<kNd, kNd>> factorized_links_;  ///< Coulomb: link stiffnesses of the last solve
  History<PairState> history_;                   ///< committed: the accepted increment; trial: the last solve
  double t_ = 0, t_trial_ = 0, size_ = 1, kappa_ = 0;  ///< accepted and last solved load factors
  double gap_tolerance_ = 1e-12;                       ///< see gap_tolerance() [length]
  bool status_changed_  = true;
  bool warm_start_      = false;  ///< Coulomb: the next solve's Newton starts from the last solve
  bool predicting_      = false;  ///< Coulomb: the evaluation is a solve's first linearization
  /// Coulomb: the accepted state ends a whole step (not a split point inside one), so a pair that
  /// slipped there is predicted to slip on: on the cone's boundary it keeps the slip linearization.
  bool slip_on_    = false;
  double step_end_ = 0;  ///< the load factor the current advance() goes to
  ContactCounters count_;
  int factorizations_at_reset_     = 0;
  const LoadsAt* loads_at_         = nullptr;
  const OnIncrement* on_increment_ = nullptr;
};

}  // namespace gapfe

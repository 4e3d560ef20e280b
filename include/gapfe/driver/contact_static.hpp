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
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

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
};

template <class M, ContactPolicy Policy>
class ContactStatic {
 public:
  /// LinearStatic for elastic laws; NonlinearStatic (Newton, history) for laws with history: SAAC is
  /// SAGAEP plus gaps. Every trial solve starts from the committed history; accept() commits it.
  using Fe          = std::conditional_t<M::Material::kLinear, LinearStatic<M>, NonlinearStatic<M>>;
  using LoadsAt     = std::function<void(Problem<M>&, double)>;
  using OnIncrement = std::function<void(double, const ContactStatic&)>;

  ContactStatic(Problem<M> problem, std::vector<GapPair> pairs, ContactOptions options = {})
      : pairs_(std::move(pairs)),
        opt_(std::move(options)),
        fe_(std::move(problem), links_of(pairs_)),
        history_(pairs_.size()) {
    fe_.defer_reactions(true);  // trial solves need displacements only; reactions when an increment is read
    const double kappa = std::min(opt_.penalty_factor > 0 ? opt_.penalty_factor : Policy::kDefaultPenalty,
                                  Policy::kMaxPenalty);
    size_  = fe_.problem().mesh.size();
    kappa_ = kappa;
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
    for (std::size_t p = 0; p < pairs_.size(); ++p)
      history_.amend(p, [&](PairState& s) { s.gap = pairs_[p].initial_gap; });
  }

  /// Advance to load factor t_end under the policy; `on_increment(t, *this)` sees every accepted
  /// increment (a split step gives more than one).
  void advance(double t_end, const LoadsAt& loads_at, const OnIncrement& on_increment = {}) {
    loads_at_ = &loads_at, on_increment_ = &on_increment;
    Policy::step(*this, t_end);
    loads_at_ = nullptr, on_increment_ = nullptr;
  }

  const Fe& fe() const { return fe_; }
  Fe& fe() { return fe_; }
  const std::vector<GapPair>& pairs() const { return pairs_; }
  const std::vector<PairState>& states() const { return history_.committed(); }
  double penalty(int p) const { return stiffness_[p]; }
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
  /// An open pair overlaps when its gap is below -1e-12 of the model size.
  double gap_tolerance() const { return 1e-12 * size_; }
  double force_tolerance(int p) const { return stiffness_.empty() ? 0.0 : stiffness_[p] * gap_tolerance(); }

  void solve_at(double t) {
    (*loads_at_)(fe_.problem(), t);
    if constexpr (!M::Material::kLinear) fe_.context() = {t, t - t_};  // time = load factor
    try {
      fe_.solve(!status_changed_);
    } catch (const SolveError& e) {
      const auto& trial = history_.trial();
      if (std::none_of(trial.begin(), trial.end(), [](const PairState& s) { return s.closed; })) throw;
      char kappa[32];
      std::snprintf(kappa, sizeof kappa, "%g", penalty_factor());
      throw SolveError(std::string(e.what()) + " (closed gap pairs at penalty " + kappa +
                       " x the adjacent stiffness: a penalty this large can make the stiffness numerically "
                       "singular; lower gap_penalty or use the augmented-lagrangian policy)");
    }
    status_changed_ = false;
    ++count_.solves;
    update_trial();
  }
  /// Uzawa: lambda <- lambda - k g on closed pairs, re-solved with the same factorization, until every
  /// closed pair's |g| <= penetration_tolerance x max |u| (THEORY.md 5.5 item 2).
  void settle_multipliers() {
    for (int it = 0;; ++it) {
      const double scale = std::max(fe_.displacement().cwiseAbs().maxCoeff(), gap_tolerance());
      double worst       = 0;
      for (std::size_t p = 0; p < pairs_.size(); ++p)
        if (history_.trial(p).closed) worst = std::max(worst, std::abs(history_.trial(p).gap));
      if (worst <= opt_.penetration_tolerance * scale) return;
      if (it == opt_.max_multiplier_updates)
        fail("the augmented-Lagrangian updates did not reach the penetration tolerance (" +
             std::to_string(worst) + " after " + std::to_string(it) + " updates)");
      for (std::size_t p = 0; p < pairs_.size(); ++p)
        if (PairState& s = history_.trial(p); s.closed) s.multiplier = s.normal_force;
      set_links();
      fe_.resolve_links(true);
      ++count_.solves, ++count_.multiplier_updates;
      update_trial();
    }
  }
  void close(int p, double reference_gap) {
    history_.amend(p, [&](PairState& s) {
      s.closed = true, s.reference_gap = reference_gap, s.multiplier = 0, s.closed_at = t_;
    });
    status_changed_ = true;
    set_links();
  }
  void open(int p) {
    history_.amend(p, [](PairState& s) { s.closed = false, s.multiplier = 0, s.reference_gap = 0; });
    status_changed_ = true;
    set_links();
  }
  void accept(double t) {
    if constexpr (!M::Material::kLinear) fe_.commit();
    t_ = t;
    history_.commit();
    count_.factorizations = fe_.factorizations() - factorizations_at_reset_;
    if (on_increment_ && *on_increment_) (*on_increment_)(t, *this);
  }
  void count_split() { ++count_.splits; }
  [[noreturn]] void fail(const std::string& why) const {
    throw SolveError("contact (" + std::string(Policy::kName) + "): " + why);
  }

 private:
  static Connectivity<2> links_of(const std::vector<GapPair>& pairs) {
    Connectivity<2> l;
    if constexpr (Policy::kContact)
      for (const auto& p : pairs) l.push_back({p.node_a, p.node_b});
    return l;
  }
  /// Link of every pair: closed ones push b along +N with P = lambda - k (g0 + N.(u_b - u_a) - g_ref).
  void set_links() {
    if constexpr (Policy::kContact) {
      auto& links = fe_.link_values();
      for (std::size_t p = 0; p < pairs_.size(); ++p) {
        const PairState& s = history_.trial(p);
        if (!s.closed) {
          links[p] = {};
          continue;
        }
        const Vec3 n(pairs_[p].normal(0), pairs_[p].normal(1), 0.0);
        const double k     = stiffness_[p];
        links[p].stiffness = k * n * n.transpose();
        links[p].force     = (s.multiplier - k * (pairs_[p].initial_gap - s.reference_gap)) * n;
      }
    }
  }
  void update_trial() {
    const auto& u = fe_.displacement();
    for (std::size_t p = 0; p < pairs_.size(); ++p) {
      const GapPair& g = pairs_[p];
      PairState& s     = history_.trial(p);
      s.gap            = g.gap(u.row(g.node_a).template head<2>().transpose(),
                               u.row(g.node_b).template head<2>().transpose());
      s.normal_force   = s.closed ? s.multiplier - stiffness_[p] * (s.gap - s.reference_gap) : 0.0;
    }
  }

  std::vector<GapPair> pairs_;
  ContactOptions opt_;
  Fe fe_;
  std::vector<double> stiffness_;
  History<PairState> history_;  ///< committed: the accepted increment; trial: the last solve
  double t_ = 0, size_ = 1, kappa_ = 0;
  bool status_changed_ = true;
  ContactCounters count_;
  int factorizations_at_reset_     = 0;
  const LoadsAt* loads_at_         = nullptr;
  const OnIncrement* on_increment_ = nullptr;
};

}  // namespace gapfe

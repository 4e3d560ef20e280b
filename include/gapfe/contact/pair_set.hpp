#pragma once
// GapPairSet: the gap pairs of a contact analysis, their states (a History, core/history.hpp: trial records
// from the last solve, committed ones from the accepted increment) and what a pair asks of the structure:
// a link k n n^T plus the friction model's force and tangent, linearized at the pair's last evaluation.
// The driver (driver/contact_static.hpp) solves the structure with these links and hands the
// displacements back; the pair Newton (contact/pair_newton.hpp) and the Uzawa updates (contact/uzawa.hpp)
// work on this set. Forces are ring totals, compressive positive; gaps positive open (core/types.hpp).
//
// Friction (contact/friction.hpp): a closed pair's force on node b and its tangent, with d = u_b - u_a,
//   f_b = P n + E t,   K = -df_b/dd = k n n^T + E K_tt E^T + k E (dt/dP) n^T,   E = [T, S] (3 x 2).
// The last term (Coulomb slip) is unsymmetric; `symmetric` links leave it out (docs and tests in
// driver/contact_static.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "gapfe/contact/friction.hpp"
#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/contact/pair_state.hpp"
#include "gapfe/core/history.hpp"
#include "gapfe/core/types.hpp"

namespace gapfe {

/// What a closed pair asks the structure to carry: a node link's stiffness on u_b - u_a and its force
/// (f_b + K d, so that K (u_b - u_a) - force is the link's internal force; assembly/node_links.hpp).
struct PairLink {
  Mat33 stiffness = Mat33::Zero();
  Vec3 force      = Vec3::Zero();
};

template <FrictionModel Friction, int kNd>
class GapPairSet {
 public:
  /// `mu`: the friction coefficient (models other than NoFriction).
  GapPairSet(std::vector<GapPair> pairs, double mu)
      : pairs_(std::move(pairs)),
        mu_(mu),
        history_(pairs_.size()),
        response_(pairs_.size()),
        accepted_relative_(pairs_.size(), Vec3::Zero()),
        linearized_branch_(pairs_.size(), Vec2::Zero()),
        links_(pairs_.size()) {}

  /// k per pair [force/length] (closure penalty), and k_t (friction; empty without).
  void set_penalties(std::vector<double> normal, std::vector<double> tangential) {
    stiffness_ = std::move(normal), tangential_ = std::move(tangential);
  }

  std::size_t size() const { return pairs_.size(); }
  const std::vector<GapPair>& pairs() const { return pairs_; }
  History<PairState>& history() { return history_; }
  const History<PairState>& history() const { return history_; }
  double penalty(std::size_t p) const { return stiffness_.empty() ? 0.0 : stiffness_[p]; }
  double tangential_penalty(std::size_t p) const { return tangential_.empty() ? 0.0 : tangential_[p]; }
  double mu() const { return mu_; }
  const std::vector<PairLink>& links() const { return links_; }
  bool any_closed_trial() const {
    const auto& t = history_.trial();
    return std::any_of(t.begin(), t.end(), [](const PairState& s) { return s.closed; });
  }

  /// Coulomb: the evaluation is a solve's first linearization (a prediction), and whether the accepted
  /// state ends an advance, a whole step or a piece of one (a pair that slipped there is predicted to slip
  /// on).
  void set_predicting(bool on) { predicting_ = on; }
  void set_slip_on(bool on) { slip_on_ = on; }

  /// Gap, normal force, slide and the friction model's answer of every pair with u_b - u_a given by
  /// `relative(p)`, into the trial records and the pair responses.
  template <class Relative>
  void evaluate_at(Relative&& relative) {
    for (std::size_t p = 0; p < pairs_.size(); ++p) evaluate_pair(p, relative(p));
  }
  /// The same at node displacements `node(n)` (r, z, theta of node n).
  template <class NodeDisplacement>
  void evaluate(NodeDisplacement&& node) {
    evaluate_at([&](std::size_t p) -> Vec3 { return node(pairs_[p].node_b) - node(pairs_[p].node_a); });
  }
  /// Coulomb's cold start: every pair at its accepted u_b - u_a, no branch of a last linearization.
  void evaluate_accepted() {
    std::fill(linearized_branch_.begin(), linearized_branch_.end(), Vec2::Zero());
    evaluate_at([&](std::size_t p) { return accepted_relative_[p]; });
  }

  /// The links of the trial states, linearized at the displacement the pairs were last evaluated at:
  /// stiffness K (without the slip's unsymmetric coupling when `symmetric`) and force f_b + K d. The normal
  /// part is written in closed form, (lambda - k (g0 - g_ref)) n, so that a large penalty adds no
  /// round-off through k d. `linear_structure`: over an elastic structure the link carries the branch's
  /// force, so that a solve lands on the branch's solution (the pair Newton measures the imbalance against
  /// the pair's true force); over a plastic one the link's force is the material Newton's residual, which
  /// must be the pair's true force: there the branch sets the tangent only.
  const std::vector<PairLink>& update_links(bool symmetric, bool linear_structure) {
    for (std::size_t p = 0; p < pairs_.size(); ++p) {
      const PairState& s    = history_.trial(p);
      linearized_branch_[p] = response_[p].branch;
      if (!s.closed) {
        links_[p] = {};
        continue;
      }
      const Response& r   = response_[p];
      const Vec3 n        = normal(p);
      const Mat33 normal  = stiffness_[p] * n * n.transpose();
      links_[p].stiffness = symmetric ? r.stiffness : Mat33(r.stiffness + r.coupling);
      links_[p].force     = (s.multiplier - stiffness_[p] * (pairs_[p].initial_gap - s.reference_gap)) * n;
      if constexpr (Friction::kFriction)
        links_[p].force +=
            (linear_structure ? r.branch_force : r.tangential) + (links_[p].stiffness - normal) * r.relative;
    }
    return links_;
  }
  /// Whether the link stiffnesses now set differ from those of the last call (their kNd x kNd blocks,
  /// what the assembler reads); the solve that follows refactorizes when they do.
  bool links_changed() {
    bool changed = factorized_links_.size() != links_.size();
    factorized_links_.resize(links_.size());
    for (std::size_t p = 0; p < links_.size(); ++p) {
      const Mat<kNd, kNd> k = links_[p].stiffness.template topLeftCorner<kNd, kNd>();
      if (changed || (k.array() != factorized_links_[p].array()).any())
        changed = true, factorized_links_[p] = k;
    }
    return changed;
  }

  /// The pair force imbalance after a solve with the links last set: per pair R = L(d) - f(d), L the link
  /// the solve balanced, f = P n + E t the pair force (only the in-plane components without u_theta), as
  /// |R| relative to |f| or, when larger, to their round-off (ten ulps of k (|g0| + |n.d|): P = -k g is a
  /// difference of large terms, which matters when a pair has just closed and P is tiny), so that the pair
  /// Newton stops at round-off instead of failing (`tolerance`: the one it stops at).
  double imbalance(double tolerance) const {
    double diff = 0, size = 0, noise = 0;
    for (std::size_t p = 0; p < pairs_.size(); ++p) {
      const PairState& s = history_.trial(p);
      if (!s.closed) continue;
      const Response& r = response_[p];
      const Vec3 n      = normal(p);
      const Vec3 f      = s.normal_force * n + r.tangential;
      Vec3 residual     = links_[p].force - links_[p].stiffness * r.relative - f;
      if constexpr (kNd == 2) residual(2) = 0;
      noise += stiffness_[p] * (std::abs(pairs_[p].initial_gap) + std::abs(n.dot(r.relative)));
      diff += residual.squaredNorm();
      size += f.template head<kNd>().squaredNorm();
    }
    const double floor = 10 * std::numeric_limits<double>::epsilon() * noise / tolerance;
    return std::sqrt(diff) / std::max({std::sqrt(size), floor, std::numeric_limits<double>::min()});
  }

  /// Statuses: pair p closes (its penalty acting on g - reference_gap) at load factor t, or opens.
  void close(std::size_t p, double reference_gap, double t) {
    history_.amend(p, [&](PairState& s) {
      s.closed = true, s.reference_gap = reference_gap, s.multiplier = 0, s.closed_at = t;
      clear_friction(s);
    });
  }
  void open(std::size_t p) {
    history_.amend(p, [](PairState& s) {
      s.closed = false, s.multiplier = 0, s.reference_gap = 0;
      clear_friction(s);
    });
  }
  /// Pair p changes status in the trial only, a closing pair at fraction f of the interval from load
  /// factor t_start to t_end: its closure load, and its tangential spring starts from its slide there.
  void flip(std::size_t p, double f, double t_start, double t_end) {
    PairState& s             = history_.trial(p);
    const PairState& start   = history_.committed(p);
    const bool was_closed    = s.closed;
    const Vec2 slide_closure = start.slide + f * (s.slide - start.slide);
    s.closed = !was_closed, s.multiplier = 0, s.reference_gap = 0;
    clear_friction(s);
    if (!was_closed) s.closed_at = t_start + f * (t_end - t_start), s.slide_start = slide_closure;
  }
  /// Before an accepted increment is committed: friction's travel and bases move on; a closed pair that
  /// pulls by less than the opening tolerance `force_tolerance(p)` is recorded open (P < 0 means its gap
  /// is open by as much), so that no accepted state has a closed pair in tension. Returns whether one was.
  template <class ForceTolerance>
  bool prepare_accept(ForceTolerance&& force_tolerance) {
    if constexpr (Friction::kFriction)
      for (std::size_t p = 0; p < pairs_.size(); ++p) {
        PairState& s = history_.trial(p);
        if (s.closed && s.slipping) s.slip += (s.slide - s.slide_start).norm();
        rebase(s);
        s.slide_start = s.slide;
      }
    bool released = false;
    for (std::size_t p = 0; p < pairs_.size(); ++p)
      if (PairState& s = history_.trial(p);
          s.closed && s.normal_force < 0 && s.normal_force >= -force_tolerance(p)) {
        s.closed = false, s.multiplier = 0, s.reference_gap = 0, s.normal_force = 0;
        clear_friction(s);
        released = true;
      }
    return released;
  }
  /// Commit the trial records (an accepted increment); Coulomb keeps each pair's u_b - u_a for a cold start.
  void commit() {
    history_.commit();
    if constexpr (Friction::kIterative)
      for (std::size_t p = 0; p < pairs_.size(); ++p) accepted_relative_[p] = response_[p].relative;
  }
  /// Each trial pair that keeps its committed status starts from the committed tangential base: the return
  /// mapping measures from the accepted force.
  void keep_accepted_bases() {
    if constexpr (Friction::kFriction)
      for (std::size_t p = 0; p < pairs_.size(); ++p)
        if (PairState& s = history_.trial(p); s.closed == history_.committed(p).closed)
          s.tangential_base = history_.committed(p).tangential_base;
  }

  /// The tangential force becomes the base of the next trial (an accepted increment; an Uzawa update).
  static void rebase(PairState& s) { s.tangential_base = s.tangential_force; }
  static void clear_friction(PairState& s) {
    s.tangential_force = s.tangential_base = Vec2::Zero();
    s.slipping                             = false;
  }
  /// The pair's closure direction in (r, z, theta).
  Vec3 normal(std::size_t p) const { return Vec3(pairs_[p].normal(0), pairs_[p].normal(1), 0.0); }

 private:
  /// At the displacement a pair was evaluated at: u_b - u_a, the tangential force E t on b, and the
  /// tangent K = -df_b/dd of the pair force on the branch it is linearized on, as its symmetric part
  /// k n n^T + E K_tt E^T and the slip's unsymmetric coupling k E (dt/dP) n^T.
  struct Response {
    Vec3 relative = Vec3::Zero(), tangential = Vec3::Zero();
    /// The tangential force on the branch the pair is linearized on (E t_trial where it is predicted to
    /// stick while its evaluation slips, else E t) and that branch's slip direction (zero: stick).
    Vec3 branch_force = Vec3::Zero();
    Vec2 branch       = Vec2::Zero();
    Mat33 stiffness = Mat33::Zero(), coupling = Mat33::Zero();
  };

  void evaluate_pair(std::size_t p, const Vec3& relative) {
    const GapPair& g = pairs_[p];
    PairState& s     = history_.trial(p);
    Response& r      = response_[p];
    const Vec3 n     = normal(p);
    r.relative       = relative;
    s.gap            = g.gap(r.relative.template head<2>());
    s.normal_force   = s.closed ? s.multiplier - stiffness_[p] * (s.gap - s.reference_gap) : 0.0;
    r.tangential = r.branch_force = Vec3::Zero();
    r.branch                      = Vec2::Zero();
    r.coupling                    = Mat33::Zero();
    r.stiffness                   = s.closed ? Mat33(stiffness_[p] * n * n.transpose()) : Mat33::Zero();
    if constexpr (Friction::kFriction) {
      Mat<3, 2> e;  // E = [T, S]: along the gap and theta
      e << g.tangent()(0), 0, g.tangent()(1), 0, 0, 1;
      s.slide = e.transpose() * r.relative;
      if (!s.closed) return;
      TangentialResponse t =
          Friction::respond({s.slide - s.slide_start, s.tangential_base, s.normal_force, tangential_[p], mu_,
                             s.slipping && (!Friction::kIterative || slip_on_)});
      // The branch of the return mapping the pair is linearized on (Response::branch). Newton linearizes
      // each pair on the branch its evaluation lands on, except where that branch is known to be wrong; the
      // pair is then predicted to stick and linearized on the stick branch itself, t = t_trial - k_t (s -
      // s_now) (not the stick slope through the returned force, whose offset mu P nu - t_trial would keep
      // the next iterate off the stick solution):
      //  - a pair whose slip direction reversed against the branch of the last linearization: its slide
      //    crossed the cone's width mu P / k_t within one iterate, so neither slip direction is consistent
      //    and the stick solution lies between (with k_t ~ 1e9 x mu P that width is below the iterates'
      //    error, and linearizing on the opposite slip branch makes Newton cycle);
      //  - at a solve's first linearization (a prediction from the accepted state), a closed pair without
      //    compression (its cone is empty): it is predicted to carry the stiffness it will have once
      //    pressed, instead of none. Past the prediction such a pair is linearized as it is (no tangential
      //    force, no stiffness): at a converged state a closed pair may be in tension within the opening
      //    tolerance, and a stick linearization of a pair that carries nothing would leave Newton
      //    converging to the stick spring's force, a non-zero imbalance.
      bool stick_branch = !t.slipping;
      if constexpr (Friction::kIterative)
        stick_branch =
            stick_branch || (predicting_ && !(s.normal_force > 0)) || t.force.dot(linearized_branch_[p]) < 0;
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

  std::vector<GapPair> pairs_;
  double mu_ = 0;
  History<PairState> history_;
  std::vector<double> stiffness_, tangential_;  ///< k and k_t per pair
  std::vector<Response> response_;
  std::vector<Vec3> accepted_relative_;          ///< Coulomb: u_b - u_a per pair at the accepted state
  std::vector<Vec2> linearized_branch_;          ///< Coulomb: Response::branch of the links last set
  std::vector<PairLink> links_;                  ///< the links last set (update_links)
  std::vector<Mat<kNd, kNd>> factorized_links_;  ///< Coulomb: link stiffnesses of the last solve
  bool predicting_ = false;
  bool slip_on_    = false;
};

}  // namespace gapfe

#pragma once
// A run's plan: what a deck or a scene asks for, decided once into types (docs/architecture.md). The
// compiled variant it needs (kinematics, element, law and its integration, contact policy, friction
// model; app/variant_table.hpp holds one row per key the library runs), the solver, and the reasons. The
// command and a C++ user make the same plan (make_plan), meet the same checks (check_plan) and run it the
// same way (app/run.hpp); explain() says it in words (what `gapfe info` prints).
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

#include "gapfe/core/choices.hpp"
#include "gapfe/core/combinations.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/input/scene.hpp"

namespace gapfe::app {

/// The kind of material law: elastic (orthotropic), plastic (Hill, SAGAEP) or rate-dependent plastic
/// (Drysdale-Zak, SAAC3).
enum class LawKind { elastic, plastic, rate_dependent };

/// The compiled variant a run needs: one row of the variant table (app/variant_table.hpp).
struct VariantKey {
  VariantChoice kinematics     = VariantChoice::saas;
  ElementChoice element        = ElementChoice::legacy;  ///< never automatic
  LawKind law                  = LawKind::elastic;
  PlasticityChoice integration = PlasticityChoice::return_mapping;  ///< return_mapping for an elastic law
  ContactChoice contact        = ContactChoice::none;               ///< none without gap elements
  FrictionChoice friction      = FrictionChoice::none;
  bool operator==(const VariantKey&) const = default;
};

/// What a run will do, decided from the model and the options before anything is solved or written.
struct Plan {
  VariantKey key;
  std::string variant_reason;                 ///< why this kinematics (the log's "variant:" line)
  SolverChoice solver = SolverChoice::eigen;  ///< never automatic: the fastest one built for auto
  bool gaps = false, plastic = false, rate = false;
  /// The Coulomb rows' tangent is unsymmetric: their solver is an LU (app/run_solver.hpp).
  bool unsymmetric() const { return key.friction == FrictionChoice::coulomb; }
};

/// Whether this build has CHOLMOD, UMFPACK and PETSc (the optional solvers; docs/library.md "Solvers").
#ifdef GAPFE_HAS_CHOLMOD
inline constexpr bool kHasCholmod = true;
#else
inline constexpr bool kHasCholmod = false;
#endif
#ifdef GAPFE_HAS_UMFPACK
inline constexpr bool kHasUmfpack = true;
#else
inline constexpr bool kHasUmfpack = false;
#endif
#ifdef GAPFE_HAS_PETSC
inline constexpr bool kHasPetsc = true;
#else
inline constexpr bool kHasPetsc   = false;
#endif

/// The kinematics the model needs, and why: SAGA when anything needs u_theta, else SAAS unless `forced`
/// asks for SAGA (then u_theta = 0 everywhere). InputError when SAAS is forced on a model that needs
/// u_theta.
inline VariantChoice pick_variant(const ModelNeeds& needs, std::optional<VariantChoice> forced,
                                  std::string& why) {
  if (needs.needs_theta()) {
    why = "3 DOF per node: " + needs.theta.front() +
          (needs.theta.size() > 1 ? " (and " + std::to_string(needs.theta.size() - 1) + " more)" : "");
    if (forced == VariantChoice::saas)
      throw InputError("--variant saas cannot represent this deck: it needs u_theta (" + needs.theta.front() +
                       ")");
    return VariantChoice::saga;
  }
  why =
      "no theta loads, theta displacements, transverse shear, angular acceleration or ALPHA: 2 DOF per node";
  if (forced == VariantChoice::saga) {
    why += "; saga forced by --variant, with u_theta = 0 at every node (its value by symmetry)";
    return VariantChoice::saga;
  }
  return VariantChoice::saas;
}

/// The plan of a model: its variant (`forced` from --variant, or the smallest it needs), the element
/// (auto: quad8 for a scene of quadratic cells, quad4bbar for plastic models, legacy otherwise), the law, the
/// contact policy and friction model, the solver (auto: CHOLMOD when built, else Eigen). Checks only what the
/// variant needs; check_plan the rest.
inline Plan make_plan(const ModelDescription& d, const Scene& s, std::optional<VariantChoice> forced = {}) {
  const ModelOptions& o = d.options;
  Plan p;
  p.gaps            = !s.needs.gaps.empty();
  p.plastic         = !s.needs.plasticity.empty();
  p.rate            = p.plastic && d.rate_dependent();
  p.key.kinematics  = pick_variant(s.needs, forced, p.variant_reason);
  p.key.element     = o.element != ElementChoice::automatic ? o.element
                      : s.is_quadratic()                    ? ElementChoice::quad8
                      : p.plastic                           ? ElementChoice::quad4bbar
                                                            : ElementChoice::legacy;
  p.key.law         = !p.plastic ? LawKind::elastic : p.rate ? LawKind::rate_dependent : LawKind::plastic;
  p.key.integration = p.plastic ? o.plasticity : PlasticityChoice::return_mapping;
  p.key.contact     = p.gaps ? o.contact : ContactChoice::none;
  p.key.friction    = o.friction_model();
  p.solver          = o.solver != SolverChoice::automatic ? o.solver
                      : kHasCholmod                       ? SolverChoice::cholmod
                                                          : SolverChoice::eigen;
  return p;
}

/// The solver this build lacks, as an InputError; nothing when it has it.
inline void check_solver_built(SolverChoice solver) {
  if (solver == SolverChoice::cholmod && !kHasCholmod)
    throw InputError("solver = cholmod: this gapfe was built without CHOLMOD (SuiteSparse)");
  if (solver == SolverChoice::petsc && !kHasPetsc)
    throw InputError(
        "solver = petsc: this gapfe was built without PETSc (cmake -DGAPFE_WITH_PETSC=ON; docs/cluster.md "
        "\"Past one machine\")");
}

/// The checks a plan must pass before it runs on the model (`d`, `s`): a solver this build has; the plan
/// made for this model (its kinematics, gaps and plasticity); the library's rule of what combines
/// (core/combinations.hpp), friction without gaps, events without an exact policy, and a rate card that
/// cannot integrate. InputError naming the options and the reason.
inline void check_plan(const Plan& p, const ModelDescription& d, const Scene& s) {
  const ModelOptions& o = d.options;
  if (p.solver == SolverChoice::automatic)
    throw InputError("the plan's solver is not chosen (make_plan chooses it)");
  check_solver_built(p.solver);
  if (p.key.kinematics == VariantChoice::saas && s.needs.needs_theta())
    throw InputError("--variant saas cannot represent this deck: it needs u_theta (" + s.needs.theta.front() +
                     ")");
  if (p.gaps != !s.needs.gaps.empty() || p.plastic != !s.needs.plasticity.empty())
    throw InputError(
        "the plan was made for another model (its gaps or plasticity differ): make_plan for this one");
  if ((p.key.element == ElementChoice::quad8) != s.is_quadratic())
    throw InputError(s.is_quadratic()
                         ? "the scene has quadratic cells (middle nodes), which element = quad8 runs"
                         : "element = quad8: the scene has no middle nodes; read the model with "
                           "element = quad8 (input/scene_quadratic.hpp)");
  if (p.key.element == ElementChoice::quad8 && p.solver == SolverChoice::petsc)
    throw InputError("element = quad8 runs on one process: not with solver = petsc");
  const std::string friction(name_of(p.key.friction));
  if (p.key.friction != FrictionChoice::none && !p.gaps)
    throw InputError("friction = " + detail::number_text(o.friction) + ", slip = " + friction +
                     ": the deck has no gap elements (material 2) to carry friction; remove the friction "
                     "option or add a gap layer");
  Combination combination;
  combination.history   = p.plastic;
  combination.iterates  = p.key.integration == PlasticityChoice::return_mapping;
  combination.condensed = p.key.element == ElementChoice::legacy;
  combination.quadratic = p.key.element == ElementChoice::quad8;
  combination.contact   = p.key.contact;
  combination.friction  = p.key.friction;
  if (const std::string_view why = unsupported(combination); !why.empty())
    throw InputError("element = " + std::string(name_of(p.key.element)) +
                     (p.plastic ? ", plasticity = " + std::string(name_of(o.plasticity)) : "") +
                     (p.gaps ? ", contact = " + std::string(name_of(o.contact)) : "") +
                     (p.key.friction != FrictionChoice::none ? ", slip = " + friction : "") + ": " +
                     std::string(why));
  if (o.events == EventChoice::step_end && o.contact != ContactChoice::active_set &&
      o.contact != ContactChoice::augmented_lagrangian)
    throw InputError("events = step-end: contact = " + std::string(name_of(o.contact)) +
                     " does not locate status changes to begin with; it applies to contact = active-set "
                     "and augmented-lagrangian");
  if (p.rate) {
    const RateCard& c = *d.rate;
    if (!(c.time_step > 0) || !std::isfinite(c.time_step))
      throw InputError(
          "DATA NO. 0 (rate property card): delta t must be > 0 when b != 0 (each load step lasts it)");
    if (!(c.rate_b > 0) || !std::isfinite(c.rate_b))
      throw InputError("DATA NO. 0 (rate property card): rate parameter b must be > 0");
    if (!(c.rate_plastic_strain > 0) || !std::isfinite(c.rate_plastic_strain))
      throw InputError(
          "DATA NO. 0 (rate property card): the transition strain rate (columns 25-36) must be > 0");
  }
}

}  // namespace gapfe::app

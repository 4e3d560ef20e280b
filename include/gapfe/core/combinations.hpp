#pragma once
// Which combinations of law, element, contact policy and friction model the library runs: one rule, by
// the names the deck options use, so that the drivers' static_asserts (contact/friction.hpp,
// driver/nonlinear_static.hpp, driver/contact_static.hpp) and the command's refusals of a deck are the
// same function, and the command's table of compiled variants is every combination it admits.
//
// What is refused, and why:
//   * a law with history on an element with condensed interior nodes (the legacy quad's centre): those
//     displacements would have to be history too, and NonlinearStatic does not keep them;
//   * friction without a contact policy (contact = none: every gap stays open);
//   * the seed's slip models (proportional, extended) under another policy than the seed's stepping
//     (saac): they decide stick and slip once per step, as the seed did;
//   * Coulomb friction under saac: saac freezes the gap at closure, so the normal force the cone needs
//     never converges;
//   * Coulomb friction with the seed's one-solve plasticity (tangent): slip converges in the Newton
//     iterations of the plastic driver, which that scheme does not make;
//   * contact on quadratic cells (Quad8, Tri6): gap pairs join two nodes, and a quadratic side's consistent
//     forces (1/6, 2/3, 1/6 of a uniform pressure) do not make node-to-node contact a fair pressure.
#include <string_view>

#include "gapfe/core/choices.hpp"

namespace gapfe {

/// A run's combination: the law's kind, the element's, the contact policy and the friction model.
struct Combination {
  bool history   = false;  ///< the law has history (plasticity, rate-dependent or not)
  bool iterates  = false;  ///< its scheme iterates to equilibrium (return-mapping), not the seed's one solve
  bool condensed = false;  ///< the element condenses interior nodes (the legacy quad's centre)
  bool quadratic = false;  ///< the element's sides are quadratic (Quad8, Tri6: 3 nodes a side)
  ContactChoice contact   = ContactChoice::none;
  FrictionChoice friction = FrictionChoice::none;
};

/// Why the library does not run `c`, or empty when it does.
constexpr std::string_view unsupported(const Combination& c) {
  const bool seed_slip = c.friction == FrictionChoice::proportional || c.friction == FrictionChoice::extended;
  if (c.history && c.condensed)
    return "a law with history on the legacy quad: its condensed centre node is not in the plastic driver; "
           "use element = quad4bbar (the default for plastic decks) or quad4";
  if (c.friction != FrictionChoice::none && c.contact == ContactChoice::none)
    return "friction with contact = none: every gap stays open; choose contact = saac, active-set or "
           "augmented-lagrangian";
  if (seed_slip && c.contact != ContactChoice::saac)
    return "the seed's slip models (proportional, extended) run under the seed's stepping, contact = saac; "
           "under the exact policies use slip = coulomb";
  if (c.friction == FrictionChoice::coulomb && c.contact == ContactChoice::saac)
    return "Coulomb friction needs an exact contact policy (contact = active-set or augmented-lagrangian): "
           "saac freezes the gap at closure, so the normal force of the friction cone never converges";
  if (c.friction == FrictionChoice::coulomb && c.history && !c.iterates)
    return "Coulomb friction with plasticity needs plasticity = return-mapping: slip and plastic flow "
           "converge together in its Newton iterations, and tangent solves once per increment";
  if (c.quadratic && c.contact != ContactChoice::none)
    return "contact on quadratic cells (element = quad8): gap pairs join two nodes, which a quadratic "
           "side's middle node does not fit; use a 4-corner element (quad4bbar, quad4 or legacy)";
  return {};
}

/// Whether element `Elem` condenses interior nodes (more shape nodes than mesh nodes: the legacy quad).
template <class Elem>
constexpr bool condensed() {
  return Elem::kShapeNodes > Elem::kNodes;
}

/// The combination of a compiled variant: law `Law` (kLinear, and kIterate for laws with history),
/// element `Elem` (kNodes, kShapeNodes), contact policy `Policy` and friction model `Friction` (their kName
/// is their option's word).
template <class Law, class Elem, class Policy, class Friction>
constexpr Combination combination_of() {
  Combination c;
  c.history = !Law::kLinear;
  if constexpr (!Law::kLinear) c.iterates = Law::kIterate;
  c.condensed = condensed<Elem>();
  c.quadratic = Elem::kEdgeNodes == 3;
  // A policy or model of one's own, under a name the deck options do not have, counts as an exact policy
  // (one that contacts: Policy::kContact) and as Coulomb-like friction (a friction model: kFriction).
  const auto contact  = choice_named<ContactChoice>(Policy::kName);
  const auto friction = choice_named<FrictionChoice>(Friction::kName);
  c.contact  = contact ? *contact : Policy::kContact ? ContactChoice::active_set : ContactChoice::none;
  c.friction = friction ? *friction : Friction::kFriction ? FrictionChoice::coulomb : FrictionChoice::none;
  return c;
}

/// Whether the library runs that variant (the drivers assert it; the command compiles every such one).
template <class Law, class Elem, class Policy, class Friction>
inline constexpr bool kSupported = unsupported(combination_of<Law, Elem, Policy, Friction>()).empty();

}  // namespace gapfe

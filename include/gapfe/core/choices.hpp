#pragma once
// The run's choices as types. Every deck option with a fixed set of values (docs/decks.md "Deck options") is
// an enum here, and its words are one table per enum (ChoiceWords): the deck reader, the scene reader and the
// command line parse through it (choice_named), the log and `gapfe info` print through it (name_of), so the
// words cannot drift apart and no code compares an option against a string literal.
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace gapfe {

/// The compiled variant's kinematics: SAAS (u_r, u_z) or SAGA (u_r, u_z, u_theta). The seed's code names,
/// mirrored on purpose (BRL-CR-670 section 2.1).
enum class VariantChoice { saas, saga };
/// element = auto | legacy (the seed's four-CST quad) | quad4 | quad4bbar | quad8 (8-node quadrilaterals,
/// 6-node triangles).
enum class ElementChoice { automatic, legacy, quad4, quad4bbar, quad8 };
/// solver = auto (the fastest built) | eigen | cholmod | petsc.
enum class SolverChoice { automatic, eigen, cholmod, petsc };
/// contact = saac | active-set | augmented-lagrangian | none (contact/policies.hpp).
enum class ContactChoice { saac, active_set, augmented_lagrangian, none };
/// slip = auto | proportional | extended | coulomb: the friction model asked for (auto: by the policy).
enum class SlipChoice { automatic, proportional, extended, coulomb };
/// The friction model a run uses (contact/friction.hpp): none without friction.
enum class FrictionChoice { none, proportional, extended, coulomb };
/// events = locate | step-end: where the exact contact policies take gap status changes.
enum class EventChoice { locate, step_end };
/// plasticity = return-mapping | tangent: how a law with history is integrated (docs/plasticity.md).
enum class PlasticityChoice { return_mapping, tangent };
/// output_csv, output_vtu = all | last | none: which accepted increments a kind of result file gets.
enum class Increments { all, last, none };

/// The words of each choice, in the enum's order.
template <class E>
struct ChoiceWords;
template <>
struct ChoiceWords<VariantChoice> {
  static constexpr std::array<std::string_view, 2> kWords{"saas", "saga"};
};
template <>
struct ChoiceWords<ElementChoice> {
  static constexpr std::array<std::string_view, 5> kWords{"auto", "legacy", "quad4", "quad4bbar", "quad8"};
};
template <>
struct ChoiceWords<SolverChoice> {
  static constexpr std::array<std::string_view, 4> kWords{"auto", "eigen", "cholmod", "petsc"};
};
template <>
struct ChoiceWords<ContactChoice> {
  static constexpr std::array<std::string_view, 4> kWords{"saac", "active-set", "augmented-lagrangian",
                                                          "none"};
};
template <>
struct ChoiceWords<SlipChoice> {
  static constexpr std::array<std::string_view, 4> kWords{"auto", "proportional", "extended", "coulomb"};
};
template <>
struct ChoiceWords<FrictionChoice> {
  static constexpr std::array<std::string_view, 4> kWords{"none", "proportional", "extended", "coulomb"};
};
template <>
struct ChoiceWords<EventChoice> {
  static constexpr std::array<std::string_view, 2> kWords{"locate", "step-end"};
};
template <>
struct ChoiceWords<PlasticityChoice> {
  static constexpr std::array<std::string_view, 2> kWords{"return-mapping", "tangent"};
};
template <>
struct ChoiceWords<Increments> {
  static constexpr std::array<std::string_view, 3> kWords{"all", "last", "none"};
};

/// A choice's word, as the deck options write it.
template <class E>
constexpr std::string_view name_of(E choice) {
  return ChoiceWords<E>::kWords[static_cast<std::size_t>(choice)];
}

/// The choice whose word is `word`; empty when none is.
template <class E>
constexpr std::optional<E> choice_named(std::string_view word) {
  for (std::size_t k = 0; k < ChoiceWords<E>::kWords.size(); ++k)
    if (ChoiceWords<E>::kWords[k] == word) return static_cast<E>(k);
  return std::nullopt;
}

/// Every word of a choice, comma-separated (for messages and help).
template <class E>
std::string choice_list() {
  std::string list;
  for (const std::string_view w : ChoiceWords<E>::kWords) list += (list.empty() ? "" : ", ") + std::string(w);
  return list;
}

}  // namespace gapfe

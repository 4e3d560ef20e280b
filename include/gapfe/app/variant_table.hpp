#pragma once
// The compiled variants a run chooses from: one table, one row per (kinematics, element, law, contact
// policy, friction model) that the library runs (core/combinations.hpp), keyed by the plan's VariantKey.
// Every row is instantiated exactly once, explicitly, in one of GAPFE_APP_SHARDS translation units
// (app/variant_shards.hpp; the gapfe::app target generates them, cmake/app.cmake; a model's rows share one
// shard, kShardOfRow), so the compile time is the table's size spread over the cores, and offering a new
// law, element or contact policy is one more entry on an axis. The solver is not a column: RunSolver picks
// it at run time, except that the Coulomb rows use RunLuSolver (their tangent is unsymmetric).
#include <algorithm>
#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "gapfe/app/plan.hpp"
#include "gapfe/app/run_output.hpp"
#include "gapfe/contact/friction.hpp"
#include "gapfe/contact/policies.hpp"
#include "gapfe/core/combinations.hpp"
#include "gapfe/material/drysdale_zak.hpp"
#include "gapfe/material/elastic.hpp"
#include "gapfe/material/hill.hpp"
#include "gapfe/problem/model.hpp"

/// The number of translation units the table's rows are instantiated in (the gapfe::app target defines it;
/// one by default, for a program that includes app/variant_shards.hpp in one file itself).
#ifndef GAPFE_APP_SHARDS
#define GAPFE_APP_SHARDS 1
#endif
/// Whether the table holds every supported row (1, the default) or only those the default options reach
/// (0: the gapfe::app target of a GAPFE_VARIANTS=defaults build).
#ifndef GAPFE_APP_ALL_VARIANTS
#define GAPFE_APP_ALL_VARIANTS 1
#endif

namespace gapfe::app {

template <class Kin, class Elem, class Law, class Policy, class Friction = NoFriction>
struct Variant {};

/// The table's axes: every kinematics, element, law, contact policy and friction model the command knows.
template <class... T>
struct Axis {};
using Kinematics = Axis<Axisym2, Axisym3>;
using Elements   = Axis<LegacyQuad, Quad4, Quad4BBar, Quad8>;
using Laws =
    Axis<Orthotropic, Hill<Tangent>, Hill<ReturnMapping>, DrysdaleZak<Tangent>, DrysdaleZak<ReturnMapping>>;
using Policies  = Axis<NoContact, Saac, ActiveSet, AugmentedLagrangian>;
using Frictions = Axis<NoFriction, Proportional, Extended, Coulomb>;

/// The rows the default options reach: the element `auto` picks on decks and order-1 meshes (the legacy quad
/// for elastic models, quad4bbar for plastic ones; an order-2 mesh's quad8 is not among them), plasticity =
/// return-mapping, and contact = saac with the seed's slip models or none; so every deck of the seed's codes
/// (SAAS to SAAC3X) runs. A build with GAPFE_VARIANTS=defaults (GAPFE_APP_ALL_VARIANTS 0) compiles only
/// these, 24 rows of the 170, for a first build in a fraction of the time; options past them are refused
/// before the run, naming the cmake setting that compiles them.
template <class Elem, class Law, class Policy, class Friction>
constexpr bool default_options_row() {
  const Combination c = combination_of<Law, Elem, Policy, Friction>();
  const bool element  = c.history ? std::is_same_v<Elem, Quad4BBar> : std::is_same_v<Elem, LegacyQuad>;
  return element && (!c.history || c.iterates) &&
         (c.contact == ContactChoice::none || c.contact == ContactChoice::saac);
}

/// The rows: every point of the axes' product the library runs (kSupported, core/combinations.hpp), so the
/// command offers every combination the library supports and refuses the rest with the library's reason;
/// in a GAPFE_VARIANTS=defaults build, those the default options reach.
template <class Kin, class Elem, class Law, class Policy, class Friction>
using RowIf =
    std::conditional_t<kSupported<Law, Elem, Policy, Friction> &&
                           (GAPFE_APP_ALL_VARIANTS || default_options_row<Elem, Law, Policy, Friction>()),
                       std::tuple<Variant<Kin, Elem, Law, Policy, Friction>>, std::tuple<>>;
template <class... T>
using Joined = decltype(std::tuple_cat(std::declval<T>()...));
template <class Kin, class Elem, class Law, class Policy, class... F>
auto friction_rows(Axis<F...>) -> Joined<RowIf<Kin, Elem, Law, Policy, F>...>;
template <class Kin, class Elem, class Law, class... P>
auto policy_rows(Axis<P...>) -> Joined<decltype(friction_rows<Kin, Elem, Law, P>(Frictions{}))...>;
template <class Kin, class Elem, class... L>
auto law_rows(Axis<L...>) -> Joined<decltype(policy_rows<Kin, Elem, L>(Policies{}))...>;
template <class Kin, class... E>
auto element_rows(Axis<E...>) -> Joined<decltype(law_rows<Kin, E>(Laws{}))...>;
template <class... K>
auto all_rows(Axis<K...>) -> Joined<decltype(element_rows<K>(Elements{}))...>;
using VariantTable = decltype(all_rows(Kinematics{}));

inline constexpr std::size_t kVariantCount = std::tuple_size_v<VariantTable>;

/// A row's key: what each of its types is in the plan's words. A type on an axis without its word here is
/// a compile error (not a silent alias of another row's key); kKeysUnique checks the table as a whole.
template <class>
inline constexpr bool kNoWord = false;
template <class Elem>
constexpr ElementChoice element_choice() {
  if constexpr (std::is_same_v<Elem, LegacyQuad>)
    return ElementChoice::legacy;
  else if constexpr (std::is_same_v<Elem, Quad4>)
    return ElementChoice::quad4;
  else if constexpr (std::is_same_v<Elem, Quad4BBar>)
    return ElementChoice::quad4bbar;
  else if constexpr (std::is_same_v<Elem, Quad8>)
    return ElementChoice::quad8;
  else
    static_assert(kNoWord<Elem>, "element_choice: an element on the Elements axis without an ElementChoice");
}
template <class Law>
constexpr LawKind law_kind() {
  if constexpr (Law::kLinear)
    return LawKind::elastic;
  else if constexpr (std::is_same_v<Law, DrysdaleZak<Tangent>> ||
                     std::is_same_v<Law, DrysdaleZak<ReturnMapping>>)
    return LawKind::rate_dependent;
  else if constexpr (std::is_same_v<Law, Hill<Tangent>> || std::is_same_v<Law, Hill<ReturnMapping>>)
    return LawKind::plastic;
  else
    static_assert(kNoWord<Law>, "law_kind: a law on the Laws axis without a LawKind");
}
template <class Law>
constexpr PlasticityChoice integration_of() {
  if constexpr (Law::kLinear)
    return PlasticityChoice::return_mapping;
  else
    return Law::kIterate ? PlasticityChoice::return_mapping : PlasticityChoice::tangent;
}
template <class Kin, class Elem, class Law, class Policy, class Friction>
constexpr VariantKey key_of(Variant<Kin, Elem, Law, Policy, Friction>) {
  return {Kin::kDofsPerNode == 2 ? VariantChoice::saas : VariantChoice::saga,
          element_choice<Elem>(),
          law_kind<Law>(),
          integration_of<Law>(),
          *choice_named<ContactChoice>(Policy::kName),
          *choice_named<FrictionChoice>(Friction::kName)};
}

/// Every row's key, in the table's order.
inline constexpr std::array<VariantKey, kVariantCount> kVariantKeys =
    []<std::size_t... I>(std::index_sequence<I...>) {
  return std::array<VariantKey, kVariantCount>{key_of(std::tuple_element_t<I, VariantTable>{})...};
}
(std::make_index_sequence<kVariantCount>{});

/// Whether every row has its own key: a plan names one row or none.
inline constexpr bool kKeysUnique = [] {
  for (std::size_t a = 0; a < kVariantKeys.size(); ++a)
    for (std::size_t b = a + 1; b < kVariantKeys.size(); ++b)
      if (kVariantKeys[a] == kVariantKeys[b]) return false;
  return true;
}();
static_assert(kKeysUnique, "two rows of the variant table have one key");

/// Whether the table has a row for `key`.
inline bool compiled(const VariantKey& key) {
  return std::find(kVariantKeys.begin(), kVariantKeys.end(), key) != kVariantKeys.end();
}

/// The plan's row compiled into this build, or an InputError naming the options and the cmake setting
/// that compiles it (a GAPFE_VARIANTS=defaults build lacks the rows past the default options).
inline void check_compiled(const Plan& p) {
  if (compiled(p.key)) return;
  const VariantKey& k = p.key;
  throw InputError(
      std::string(name_of(k.kinematics)) + ", element = " + std::string(name_of(k.element)) +
      ", plasticity = " + std::string(name_of(k.integration)) +
      ", contact = " + std::string(name_of(k.contact)) + ", slip = " + std::string(name_of(k.friction)) +
      (GAPFE_APP_ALL_VARIANTS ? std::string(": not compiled into this gapfe")
                              : std::string(": this gapfe was built with the default options' rows only "
                                            "(cmake -DGAPFE_VARIANTS=defaults); configure with "
                                            "-DGAPFE_VARIANTS=all and build again for every "
                                            "combination")));
}

/// Runs the request when this shard holds the row of its plan's key; false otherwise. Defined in
/// app/variant_shards.hpp, instantiated for Shard in [0, GAPFE_APP_SHARDS) once each (cmake/app.cmake).
template <std::size_t Shard>
bool run_shard(const RunRequest& r, RunResult& result);

}  // namespace gapfe::app

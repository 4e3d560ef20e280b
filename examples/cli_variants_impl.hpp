#pragma once
// The body of run_shard (cli_variants.hpp), included only by the generated shard translation units.
#include "cli_families.hpp"
#include "cli_variants.hpp"

namespace gapfe::cli {

template <class Kin, class Elem, class Law, class Policy, class Friction>
void run_variant(const RunRequest& r, RunTimes& times) {
  using Solver = std::conditional_t<std::is_same_v<Friction, Coulomb>, CliLuSolver, CliSolver>;
  using M      = Model<Kin, Elem, Law, Solver>;
  if constexpr (std::is_same_v<Policy, NoContact>) {
    if (r.scene.needs.gaps.empty()) {
      if constexpr (Law::kLinear)
        run_linear<M>(r, times);
      else
        run_plastic<M>(r, times);
      return;
    }
  }
  if constexpr (Law::kLinear || !std::is_same_v<Policy, NoContact>)
    run_contact<M, Policy, Friction>(r, times);
  else
    throw std::logic_error("run_variant: a law with history and gaps needs a contact policy");
}

template <std::size_t Row, class Kin, class Elem, class Law, class Policy, class Friction>
bool try_row(Variant<Kin, Elem, Law, Policy, Friction>, const VariantKey& k, const RunRequest& r,
             RunTimes& times) {
  if (k.kinematics != kinematics_name<Kin>() || k.element != CliName<Elem>::value ||
      k.law != law_name<Law>() || k.contact != Policy::kName || k.friction != Friction::kName)
    return false;
  run_variant<Kin, Elem, Law, Policy, Friction>(r, times);
  return true;
}

template <std::size_t Shard>
bool run_shard(const VariantKey& key, const RunRequest& r, RunTimes& times) {
  return [&]<std::size_t... Row>(std::index_sequence<Row...>) {
    bool done      = false;
    const auto row = [&]<std::size_t I>(std::integral_constant<std::size_t, I>) {
      if constexpr (I % GAPFE_CLI_SHARDS == Shard)
        done = done || try_row<I>(std::tuple_element_t<I, VariantTable>{}, key, r, times);
    };
    (row(std::integral_constant<std::size_t, Row>{}), ...);
    return done;
  }
  (std::make_index_sequence<kVariantCount>{});
}

}  // namespace gapfe::cli

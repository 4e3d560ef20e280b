#pragma once
// The body of run_shard (app/variant_table.hpp). Included only by the translation units that instantiate
// the shards (cmake/app.cmake generates GAPFE_APP_SHARDS of them): a file that calls run_shard<K> and sees
// this definition would instantiate every row.
#include <array>
#include <type_traits>

#include "gapfe/app/run_loops.hpp"
#include "gapfe/app/variant_table.hpp"

namespace gapfe::app {

/// The shards run the plastic laws: naming the Hill modes' computation here (outside any template) has the
/// shards' precompiled header instantiate its 6 x 6 decompositions once for all of them (cmake/app.cmake),
/// which the laws' headers leave to the units that use them (material/hill_yield.hpp).
inline constexpr auto kShardsHillModes = &HillPoint::modes<0>;

/// Run the request on one variant: the NoContact rows run models without gap elements (LinearStatic, or
/// NonlinearStatic for laws with history) and models whose gap elements stay soft (contact = none, through
/// ContactStatic's NoContact stepping); the other rows run ContactStatic under their policy.
template <class Kin, class Elem, class Law, class Policy, class Friction>
void run_variant(const RunRequest& r, RunResult& times) {
  using Solver = std::conditional_t<std::is_same_v<Friction, Coulomb>, RunLuSolver, RunSolver>;
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
  run_contact<M, Policy, Friction>(r, times);
}

template <class Kin, class Elem, class Law, class Policy, class Friction>
bool try_row(Variant<Kin, Elem, Law, Policy, Friction> row, const RunRequest& r, RunResult& times) {
  if (!(key_of(row) == r.plan.key)) return false;
  run_variant<Kin, Elem, Law, Policy, Friction>(r, times);
  return true;
}

/// The row's compiled model, (kinematics, element, law, solver): rows that share it share its element
/// kernels and assembly, most of a shard's compile time (clang's trace: 84% in the fixed-size Eigen
/// expressions of the kernels).
template <class Kin, class Elem, class Law, class Policy, class Friction>
constexpr auto model_of(Variant<Kin, Elem, Law, Policy, Friction>) {
  return std::type_identity<
      std::tuple<Kin, Elem, Law, std::bool_constant<std::is_same_v<Friction, Coulomb>>>>{};
}
template <std::size_t I>
using RowModel = decltype(model_of(std::tuple_element_t<I, VariantTable>{}));

/// Each row's shard: a model's rows go to one shard together (each model is instantiated once), the
/// models placed largest first on the shard with the fewest rows so far (longest-processing-time
/// first). Row k % shards, as before, spread a model over up to every shard.
inline constexpr auto kShardOfRow = [] {
  std::array<std::size_t, kVariantCount> first{};  // the first row with the same model
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    const auto first_of = [&]<std::size_t J>(std::integral_constant<std::size_t, J>) {
      std::size_t f = J;
      [&]<std::size_t... K>(std::index_sequence<K...>) {
        ((f = (f == J && std::is_same_v<RowModel<K>, RowModel<J>>) ? K : f), ...);
      }
      (std::make_index_sequence<J>{});
      return f;
    };
    ((first[I] = first_of(std::integral_constant<std::size_t, I>{})), ...);
  }
  (std::make_index_sequence<kVariantCount>{});

  std::array<std::size_t, kVariantCount> size{}, shard{};
  for (std::size_t i = 0; i < kVariantCount; ++i) ++size[first[i]];
  std::array<std::size_t, GAPFE_APP_SHARDS> load{};
  std::array<bool, kVariantCount> placed{};
  for (;;) {  // the largest model not yet placed, then the least loaded shard
    std::size_t model = kVariantCount;
    for (std::size_t i = 0; i < kVariantCount; ++i)
      if (first[i] == i && !placed[i] && (model == kVariantCount || size[i] > size[model])) model = i;
    if (model == kVariantCount) break;
    std::size_t s = 0;
    for (std::size_t k = 1; k < load.size(); ++k)
      if (load[k] < load[s]) s = k;
    placed[model] = true, load[s] += size[model], shard[model] = s;
  }
  for (std::size_t i = 0; i < kVariantCount; ++i) shard[i] = shard[first[i]];
  return shard;
}();

template <std::size_t Shard>
bool run_shard(const RunRequest& r, RunResult& times) {
  return [&]<std::size_t... Row>(std::index_sequence<Row...>) {
    bool done      = false;
    const auto row = [&]<std::size_t I>(std::integral_constant<std::size_t, I>) {
      if constexpr (kShardOfRow[I] == Shard)
        done = done || try_row(std::tuple_element_t<I, VariantTable>{}, r, times);
    };
    (row(std::integral_constant<std::size_t, Row>{}), ...);
    return done;
  }
  (std::make_index_sequence<kVariantCount>{});
}

}  // namespace gapfe::app

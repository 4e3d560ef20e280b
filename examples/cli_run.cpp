// `gapfe run`'s choice of a compiled variant (cli_variants.hpp) for a deck, after the checks of the deck's
// input and the library's rule of what combines (core/combinations.hpp), which the table mirrors.
#include "cli_run.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string_view>
#include <utility>

#include "cli_variants.hpp"

namespace gapfe::cli {

void run_deck_request(const RunRequest& r, RunTimes& times) {
  const bool plastic         = !r.scene.needs.plasticity.empty();
  const bool gaps            = !r.scene.needs.gaps.empty();
  const DeckOptions& o       = r.deck.options;
  const std::string friction = o.friction_model();
  if (friction != "none" && !gaps) {
    char mu[32];
    std::snprintf(mu, sizeof mu, "%g", o.friction);
    throw InputError("friction = " + std::string(mu) + ", slip = " + friction +
                     ": the deck has no gap elements (material 2) to carry friction; remove the friction "
                     "option or add a gap layer");
  }
  // The library's one rule of what combines (core/combinations.hpp); the table holds every other variant.
  Combination combination;
  combination.history   = plastic;
  combination.iterates  = o.plasticity == "return-mapping";
  combination.condensed = r.element == "legacy";
  combination.contact   = gaps ? std::string_view(o.contact) : std::string_view("none");
  combination.friction  = friction;
  if (const std::string_view why = unsupported(combination); !why.empty())
    throw InputError("element = " + r.element + (plastic ? ", plasticity = " + o.plasticity : "") +
                     (gaps ? ", contact = " + o.contact : "") +
                     (friction != "none" ? ", slip = " + friction : "") + ": " + std::string(why));
  if (o.events == "step-end" && o.contact != "active-set" && o.contact != "augmented-lagrangian")
    throw InputError("events = step-end: contact = " + o.contact +
                     " does not locate status changes to begin with; it applies to contact = active-set "
                     "and augmented-lagrangian");
  const bool rate = plastic && r.deck.rate_dependent();
  if (rate) {
    const RateCard& c = *r.deck.rate;
    if (!(c.time_step > 0) || !std::isfinite(c.time_step))
      throw InputError(
          "DATA NO. 0 (rate property card): delta t must be > 0 when b != 0 (each load step lasts it)");
    if (!(c.rate_b > 0) || !std::isfinite(c.rate_b))
      throw InputError("DATA NO. 0 (rate property card): rate parameter b must be > 0");
    if (!(c.rate_plastic_strain > 0) || !std::isfinite(c.rate_plastic_strain))
      throw InputError(
          "DATA NO. 0 (rate property card): the transition strain rate (columns 25-36) must be > 0");
  }
  const VariantKey key{r.variant, r.element,
                       plastic ? (rate ? "rate-dependent " : "") + o.plasticity : std::string("elastic"),
                       gaps ? o.contact : "none", friction};
  CliSolver::select<EigenLdlt>();
  CliLuSolver::select<EigenLu>();
#ifdef GAPFE_HAS_CHOLMOD
  if (r.solver == "cholmod") CliSolver::select<CholmodLlt>();
#endif
#ifdef GAPFE_HAS_UMFPACK
  if (r.solver != "eigen")
    CliLuSolver::select<UmfpackLu>();  // SuiteSparse in the build: UMFPACK unless told eigen
#endif
#ifdef GAPFE_HAS_PETSC
  if (r.solver == "petsc")
    CliSolver::select<PetscSolver<>>(), CliLuSolver::select<PetscSolver<MatrixStorage::full>>();
#endif
  const bool done = [&]<std::size_t... Shard>(std::index_sequence<Shard...>) {
    return (run_shard<Shard>(key, r, times) || ...);
  }
  (std::make_index_sequence<GAPFE_CLI_SHARDS>{});
  if (!done)
    throw InputError("no compiled variant for " + key.kinematics + ", element = " + key.element + ", law " +
                     key.law + ", contact " + key.contact + ", friction " + key.friction +
                     " (examples/cli_variants.hpp lists them)");
}

}  // namespace gapfe::cli

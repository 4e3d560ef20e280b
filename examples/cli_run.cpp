// `gapfe run`'s choice of a compiled variant (cli_variants.hpp) for a deck, after the checks that give a
// combination the table does not hold a clear message.
#include "cli_run.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <utility>

#include "cli_variants.hpp"

namespace gapfe::cli {

void run_deck_request(const RunRequest& r, RunTimes& times) {
  const bool plastic         = !r.scene.needs.plasticity.empty();
  const bool gaps            = !r.scene.needs.gaps.empty();
  const DeckOptions& o       = r.deck.options;
  const std::string friction = o.friction_model();
  if (friction != "none") {
    char mu[32];
    std::snprintf(mu, sizeof mu, "%g", o.friction);
    const std::string head = "friction = " + std::string(mu) + ", slip = " + friction + ": ";
    if (!gaps)
      throw InputError(head +
                       "the deck has no gap elements (material 2) to carry friction; remove the "
                       "friction option or add a gap layer");
    if (o.contact == "none")
      throw InputError(head +
                       "contact = none leaves every gap open; choose contact = saac, active-set or "
                       "augmented-lagrangian");
    if (friction != "coulomb" && o.contact != "saac")
      throw InputError(head +
                       "the seed's slip models run under the seed's stepping (contact = saac); with "
                       "contact = " +
                       o.contact + " use slip = coulomb");
    if (friction == "coulomb" && o.contact == "saac")
      throw InputError(head +
                       "Coulomb friction needs an exact contact policy (contact = active-set or "
                       "augmented-lagrangian): saac freezes the gap at closure, so the normal force of "
                       "the friction cone never converges");
    if (friction == "coulomb" && plastic && o.plasticity != "return-mapping")
      throw InputError(head +
                       "with yield cards Coulomb friction needs plasticity = return-mapping (slip and "
                       "plastic flow converge together in its Newton iterations; tangent solves once "
                       "per step)");
  }
  if (o.events == "step-end" && o.contact != "active-set" && o.contact != "augmented-lagrangian")
    throw InputError("events = step-end: contact = " + o.contact +
                     " does not locate status changes to begin with; it applies to contact = active-set "
                     "and augmented-lagrangian");
  if (plastic && r.element == "legacy")
    throw InputError(
        "element = legacy with yield cards: the legacy quad's condensed centre node is not in the "
        "plastic driver yet; use element = quad4bbar (the default for plastic decks) or quad4");
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
    if (gaps && o.contact != "saac" && o.contact != "none")
      throw InputError(
          "contact = " + o.contact +
          " with rate-dependent plasticity (card 0, b != 0): the command offers it with contact = "
          "saac (SAAC3 = SAAC2 + the rate law); the library's ContactStatic takes any policy");
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

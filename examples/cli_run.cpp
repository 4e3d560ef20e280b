// `gapfe run`'s choice of a compiled variant (cli_variants.hpp) for a deck, after the checks that give a
// combination the table does not hold a clear message; and the progress line.
#include "cli_run.hpp"

#include <iostream>
#include <utility>

#include "cli_variants.hpp"

namespace gapfe::cli {

void progress_line(const RunRequest& r, int step) {
  if (r.progress) r.err << "\rstep " << step << "/" << r.deck.steps() << std::flush;
}
void progress_done(const RunRequest& r) {
  if (r.progress) r.err << "\r" << std::string(32, ' ') << "\r" << std::flush;
}

void run_deck_request(const RunRequest& r, RunTimes& times) {
  const bool plastic = !r.scene.needs.plasticity.empty();
  const bool gaps    = !r.scene.needs.gaps.empty();
  if (plastic && gaps && r.deck.options.contact != "saac")
    throw InputError(
        "gap elements and yield cards: contact = " + r.deck.options.contact +
        " is for elastic decks; a plastic run with gaps uses the seed's policy (contact = saac)");
  if (plastic && r.element == "legacy")
    throw InputError(
        "element = legacy with yield cards: the legacy quad's condensed centre node is not in the "
        "plastic driver yet; use element = quad4bbar (the default for plastic decks) or quad4");
  const VariantKey key{r.variant, r.element, plastic ? r.deck.options.plasticity : "elastic",
                       gaps ? r.deck.options.contact : "none"};
  CliSolver::select(r.solver == "cholmod" ? 1 : 0);
  const bool done = [&]<std::size_t... Shard>(std::index_sequence<Shard...>) {
    return (run_shard<Shard>(key, r, times) || ...);
  }
  (std::make_index_sequence<GAPFE_CLI_SHARDS>{});
  if (!done)
    throw InputError("no compiled variant for " + key.kinematics + ", element = " + key.element + ", law " +
                     key.law + ", contact " + key.contact + " (examples/cli_variants.hpp lists them)");
}

}  // namespace gapfe::cli

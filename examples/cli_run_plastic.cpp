// `gapfe run` with yield cards (cli_run_plastic.hpp): the checks, and the return-mapping variants.
#include "cli_run_plastic.hpp"

namespace gapfe::cli {

void run_plastic(const RunRequest& r, RunTimes& times) {
  if (!r.scene.needs.gaps.empty() && r.deck.options.contact != "saac")
    throw InputError(
        "gap elements and yield cards: contact = " + r.deck.options.contact +
        " is for elastic decks; a plastic run with gaps uses the seed's policy (contact = saac)");
  if (r.element == "legacy")
    throw InputError(
        "element = legacy with yield cards: the legacy quad's condensed centre node is not in the "
        "plastic driver yet; use element = quad4bbar (the default for plastic decks) or quad4");
  if (r.deck.options.plasticity == "tangent") return run_plastic_tangent(r, times);
  plastic::run_integration<ReturnMapping>(r, times);
}

}  // namespace gapfe::cli

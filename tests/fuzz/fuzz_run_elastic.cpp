// fuzz_run.hpp: the elastic model's runs.
#include <sstream>

#include "gapfe/material/elastic.hpp"
#include "gapfe/model.hpp"

#include "cli_families.hpp"
#include "fuzz_run.hpp"

void gapfe::fuzz::run_elastic(const Deck& deck, const DeckScene& scene, const std::string& dir, bool gaps) {
  using M = Model<Axisym3, Quad4BBar, Orthotropic, EigenLdlt>;
  std::ostringstream err;  // the warnings a run would print
  const cli::RunRequest r{deck, scene, dir, "saga", "quad4bbar", "eigen", err, false, {"mises"}, {}};
  cli::RunTimes times;
  gaps ? cli::run_contact<M, Saac>(r, times) : cli::run_linear<M>(r, times);
}

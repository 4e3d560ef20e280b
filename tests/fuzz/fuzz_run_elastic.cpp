// fuzz_run.hpp: the elastic model's runs, and the run files' definitions (compiled in the gapfe::app target,
// which the fuzzer does not link: it compiles its own two models' runs).
#include <sstream>

#include "gapfe/app/run_loops.hpp"
#include "gapfe/app/run_output_impl.hpp"
#include "gapfe/material/elastic.hpp"
#include "gapfe/problem/model.hpp"

#include "fuzz_run.hpp"

void gapfe::fuzz::run_elastic(const ModelDescription& model, const Scene& scene, const std::string& dir,
                              bool gaps) {
  using M = Model<Axisym3, Quad4BBar, Orthotropic, EigenLdlt>;
  std::ostringstream err;  // the warnings a run would print
  const app::Plan plan = fuzz_plan(model, scene);
  const app::RunRequest r{model, scene, plan, dir, err, false, {"mises"}, {}};
  app::RunResult times;
  gaps ? app::run_contact<M, Saac>(r, times) : app::run_linear<M>(r, times);
}

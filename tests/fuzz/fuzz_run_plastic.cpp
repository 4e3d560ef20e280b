// fuzz_run.hpp: the plastic model's runs.
#include <sstream>

#include "gapfe/app/run_loops.hpp"
#include "gapfe/material/hill.hpp"
#include "gapfe/problem/model.hpp"

#include "fuzz_run.hpp"

void gapfe::fuzz::run_plastic(const ModelDescription& model, const Scene& scene, const std::string& dir,
                              bool gaps) {
  using M = Model<Axisym3, Quad4BBar, Hill<ReturnMapping>, EigenLdlt>;
  std::ostringstream err;  // the warnings a run would print
  const app::Plan plan = fuzz_plan(model, scene);
  const app::RunRequest r{model, scene, plan, dir, err, false, {"mises"}, {}};
  app::RunResult times;
  gaps ? app::run_contact<M, Saac>(r, times) : app::run_plastic<M>(r, times);
}

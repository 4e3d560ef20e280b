#pragma once
// The run half of fuzz_deck.cpp: a small deck or scene run as `gapfe run` runs it (app/run_loops.hpp:
// the step loop, the files, the pictures) into `dir`, on the 3-DOF quad4bbar, without gaps or with SAAC's.
// The elastic and the plastic model are instantiated in a translation unit each (fuzz_run_elastic.cpp,
// fuzz_run_plastic.cpp) so that the sanitizer build compiles them side by side, and this header stays light.
#include <string>

#include "gapfe/app/plan.hpp"
#include "gapfe/input/scene.hpp"

namespace gapfe::fuzz {

/// The plan both runs take: the library's for the model (make_plan, forced to SAGA), on the one model per
/// law compiled here (quad4bbar, Eigen) and frictionless, as the runs are.
inline app::Plan fuzz_plan(const ModelDescription& model, const Scene& scene) {
  app::Plan plan    = app::make_plan(model, scene, VariantChoice::saga);
  plan.key.element  = ElementChoice::quad4bbar;
  plan.key.friction = FrictionChoice::none;
  plan.solver       = SolverChoice::eigen;
  return plan;
}

void run_elastic(const ModelDescription& model, const Scene& scene, const std::string& dir, bool gaps);
void run_plastic(const ModelDescription& model, const Scene& scene, const std::string& dir, bool gaps);

}  // namespace gapfe::fuzz

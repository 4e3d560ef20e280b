#pragma once
// The definitions of app/run_output.hpp's RunFiles, for exactly one translation unit of a program (the
// gapfe::app target's command.cpp, through app/command_impl.hpp): the writers and the pictures are
// compiled there once.
#include "gapfe/app/run_output.hpp"

namespace gapfe::app {

RunFiles::RunFiles(const RunRequest& r) {
  if (!r.writes) return;
  files_ = std::make_unique<StepFiles>(r.dir, r.scene, r.model.step_time(), r.model.options.output_csv,
                                       r.model.options.output_vtu);
  files_->draw_fields(r.pictures, r.units);
  files_->keep_history(r.model.steps(), {r.plan.key.friction != FrictionChoice::none,
                                         r.plan.key.kinematics == VariantChoice::saga});
}
RunFiles::~RunFiles() = default;

void RunFiles::write(int step, double inc, const Solution& solution, const std::vector<PointValues>& values,
                     std::vector<VtuField> extra_cells, const IncrementSummary& summary) {
  files_->write(step, inc, solution, values, std::move(extra_cells), summary);
}

void RunFiles::finish(const std::string& title, RunResult& times) {
  files_->finish(title);
  times.pictures = files_->pictures_written(), times.pictures_skipped = files_->pictures_skipped();
}

}  // namespace gapfe::app

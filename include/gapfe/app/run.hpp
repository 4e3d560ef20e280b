#pragma once
// A plan run on its compiled variant: the call the command and a C++ user make after make_plan
// (app/plan.hpp). The rows are compiled elsewhere: link the gapfe::app target (cmake/app.cmake), or
// include app/variant_shards.hpp, app/run_output_impl.hpp and app/run_solver_impl.hpp in one translation unit
// and instantiate run_shard<0>.
#include <cstddef>
#include <stdexcept>
#include <utility>

#include "gapfe/app/plan.hpp"
#include "gapfe/app/report.hpp"
#include "gapfe/app/run_output.hpp"
#include "gapfe/app/run_result.hpp"
#include "gapfe/app/variant_table.hpp"

namespace gapfe::app {

/// Run the request on the variant its plan's key names, after the plan's checks (check_plan) and the
/// warning of a locking element (warn_locking). Writes the files into r.dir (which must exist) and returns
/// what the run did; InputError when the plan fails its checks, SolveError when a step cannot be solved
/// (the files then hold the increments accepted).
inline RunResult run(const RunRequest& r) {
  check_plan(r.plan, r.model, r.scene);
  check_compiled(r.plan);
  if (r.plan.solver == SolverChoice::petsc && !r.part)
    throw InputError(
        "solver = petsc runs a partitioned model: each process's part (RunRequest::part) on PETSc and MPI, "
        "which "
        "the program starts (the gapfe command does)");
  warn_locking(r.plan, r.model, r.scene, r.err);
  RunResult result;
  const bool done = [&]<std::size_t... Shard>(std::index_sequence<Shard...>) {
    return (run_shard<Shard>(r, result) || ...);
  }
  (std::make_index_sequence<GAPFE_APP_SHARDS>{});
  if (!done) throw std::logic_error("app::run: the plan's row is compiled but no shard ran it");
  return result;
}

}  // namespace gapfe::app

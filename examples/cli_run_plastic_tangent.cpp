// `gapfe run` with yield cards, the seed's tangent scheme (cli_run_plastic.hpp).
#include "cli_run_plastic.hpp"

namespace gapfe::cli {

void run_plastic_tangent(const RunRequest& r, RunTimes& times) {
  plastic::run_integration<Tangent>(r, times);
}

}  // namespace gapfe::cli

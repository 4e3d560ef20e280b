// The 3-DOF (SAGA) contact variants of `gapfe run` (cli_run_contact.hpp).
#include "cli_run_contact.hpp"

namespace gapfe::cli {

void run_contact_saga(const RunRequest& r, RunTimes& times) {
  contact::run_contact_with<Axisym3>(r, times);
}

}  // namespace gapfe::cli

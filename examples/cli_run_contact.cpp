// The 2-DOF (SAAS) contact variants of `gapfe run` (cli_run_contact.hpp); SAGA's are in
// cli_run_contact_saga.cpp.
#include "cli_run_contact.hpp"

namespace gapfe::cli {

void run_contact(const RunRequest& r, RunTimes& times) {
  if (r.variant == "saga") return run_contact_saga(r, times);
  contact::run_contact_with<Axisym2>(r, times);
}

}  // namespace gapfe::cli

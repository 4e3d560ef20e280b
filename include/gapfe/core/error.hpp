#pragma once
// Errors: InputError for a model that cannot be built (says what and where), SolveError for a
// system that cannot be solved (singular, not positive definite). Nothing returns NaN silently.
#include <stdexcept>
#include <string>

namespace gapfe {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct SolveError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace gapfe

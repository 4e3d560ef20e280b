#pragma once
// Errors: InputError for a model that cannot be built (says what and where), SolveError for a
// system that cannot be solved (singular, not positive definite), FileError for a file that cannot be
// read or written. Nothing returns NaN silently.
#include <cstdio>
#include <stdexcept>
#include <string>

namespace gapfe {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct SolveError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// An increment of a rate-dependent law whose estimated time error exceeds the caller's tolerance
/// (ContactOptions::time_tolerance): not a failure, the caller repeats the piece in halves. Not SolveError,
/// so that the contact policies, which cut a step on a SolveError, pass it to the caller that sized it.
struct TimeErrorExceeded : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A file that cannot be read or written (a result file, an output folder): names the path and the
/// system's reason. Not InputError: the model may be fine.
struct FileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What a singular stiffness most often means, as the factorization (solver/system.hpp) and the model's
/// check for bodies nothing holds (assembly/problem_check.hpp) say it.
inline constexpr const char* kRigidBodyHint =
    "check that the constraints remove every rigid-body motion (axial translation; in 3-DOF also rotation "
    "about the axis)";

namespace detail {

/// A number as error messages print it (%g: 6 significant digits).
inline std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace detail

}  // namespace gapfe

#pragma once
// The `gapfe run` families, one translation unit each (elastic, contact, plastic), so that the model
// variants they instantiate compile in parallel. Internal to the command.
#include <iosfwd>
#include <string>

#include "gapfe/driver/contact_static.hpp"
#include "gapfe/element/legacy_quad.hpp"
#include "gapfe/element/quad4.hpp"
#include "gapfe/io/deck.hpp"
#include "gapfe/io/deck_scene.hpp"
#include "gapfe/kinematics/axisym2.hpp"
#include "gapfe/kinematics/axisym3.hpp"
#include "gapfe/solver/eigen_ldlt.hpp"
#ifdef GAPFE_HAS_CHOLMOD
#include "gapfe/solver/cholmod.hpp"
#endif

namespace gapfe::cli {

/// Wall-clock seconds of a run's phases after meshing, and the work of contact and plasticity.
struct RunTimes {
  double assemble = 0, factorize = 0, solve = 0, write = 0;
  ContactCounters contact;
  int increments = 0, closed = 0, pairs = 0;
  double penalty        = 0;
  int newton_iterations = 0, cut_steps = 0, plastic_points = 0;
  double drift = 0, worst_residual = 0;
};

/// What a run needs: the deck, its scene, where to write, and the resolved variant choices.
struct RunRequest {
  const Deck& deck;
  const DeckScene& scene;
  std::string dir;
  std::string variant;  ///< saas | saga
  std::string element;  ///< legacy | quad4 | quad4bbar (resolved, never auto)
  std::string solver;   ///< eigen | cholmod (resolved)
  std::ostream& err;
  bool progress;
};

void run_elastic(const RunRequest& r, RunTimes& times);  // cli_run_elastic.cpp
void run_contact(const RunRequest& r, RunTimes& times);  // cli_run_contact.cpp
void run_plastic(const RunRequest& r, RunTimes& times);  // cli_run_plastic.cpp

/// The deck option value (element = ...) of each element type.
template <class E>
struct CliName;
template <>
struct CliName<LegacyQuad> {
  static constexpr const char* value = "legacy";
};
template <>
struct CliName<Quad4> {
  static constexpr const char* value = "quad4";
};
template <>
struct CliName<Quad4BBar> {
  static constexpr const char* value = "quad4bbar";
};

/// f.template operator()<Kin, Elem, Solver>() for the request's variant, element (one of Elems) and solver.
template <class... Elems, class F>
void dispatch(const RunRequest& r, F&& f) {
  const auto with_solver = [&]<class Solver>() {
    bool done              = false;
    const auto try_element = [&]<class Elem>() {
      if (done || r.element != CliName<Elem>::value) return;
      done = true;
      if (r.variant == "saga")
        f.template operator()<Axisym3, Elem, Solver>();
      else
        f.template operator()<Axisym2, Elem, Solver>();
    };
    (try_element.template operator()<Elems>(), ...);
    if (!done) throw InputError("element = " + r.element + " is not available for this kind of deck");
  };
#ifdef GAPFE_HAS_CHOLMOD
  if (r.solver == "cholmod") return with_solver.template operator()<CholmodLlt>();
#endif
  with_solver.template operator()<EigenLdlt>();
}

/// The log's progress line.
void progress_line(const RunRequest& r, int step);
void progress_done(const RunRequest& r);

}  // namespace gapfe::cli

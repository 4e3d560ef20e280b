#pragma once
// Deck extensions: the options the seed's input lacks, set by lines `$ key = value` before the first card
// or from the command line (gapfe --set key=value), so legacy decks stay untouched. Each key's values and
// default are documented at its field; input/deck_reader.hpp reads them.
#include <array>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <string>

#include "gapfe/core/choices.hpp"
#include "gapfe/core/error.hpp"

namespace gapfe {

enum class DeckFormat { saac, saac3, elastic };

/// The three names of a `units` value "LENGTH,FORCE,STRESS" (e.g. mm,N,MPa); InputError otherwise.
inline std::array<std::string, 3> unit_names(const std::string& text) {
  std::array<std::string, 3> names;
  std::size_t k = 0;
  for (const char c : text) {
    if (c != ',')
      names[k] += c;
    else if (++k == 3)
      break;
  }
  if (k != 2 || names[0].empty() || names[1].empty() || names[2].empty())
    throw InputError("units '" + text + "': expected LENGTH,FORCE,STRESS, e.g. mm,N,MPa");
  return names;
}

/// Options a deck sets with `$ key = value` lines or the command line sets with --set key=value.
struct ModelOptions {
  DeckFormat format = DeckFormat::saac;  ///< format = saac | saac3 | elastic
  /// element = auto | legacy (the seed's four-CST quad) | quad4 | quad4bbar (Quad4 with B-bar). auto:
  /// legacy for elastic and gap decks, quad4bbar for decks with yield cards (plain Quad4 locks in
  /// plastic flow, tests/test_plasticity.cpp; the legacy quad's condensed centre is not in the plastic
  /// driver yet).
  ElementChoice element = ElementChoice::automatic;
  SolverChoice solver = SolverChoice::automatic;  ///< solver = auto (fastest built) | eigen | cholmod | petsc
  bool loads_per_radian = false;                  ///< bc_loads = total (default) | per-radian (legacy decks)
  ContactChoice contact = ContactChoice::saac;  ///< contact = saac | active-set | augmented-lagrangian | none
  /// friction = mu >= 0 at closed gap pairs (0: frictionless, no friction model compiled in).
  double friction = 0.0;
  /// slip = auto | proportional | extended | coulomb: the friction model (contact/friction.hpp). auto:
  /// extended (the seed's section 3.2) under contact = saac, coulomb under the exact policies.
  /// proportional and extended run under saac only, coulomb under active-set and augmented-lagrangian.
  SlipChoice slip    = SlipChoice::automatic;
  double gap_penalty = 0.0;  ///< gap_penalty = closed-gap / adjacent stiffness (0: the policy's default)
  /// events = locate | step-end: under the exact contact policies, split each step at every gap status
  /// change (locate: closure loads exact) or let the statuses settle at the step's end without
  /// splitting (step-end: fewer solves; a path-dependent response sees closures late by up to a step).
  EventChoice events = EventChoice::locate;
  int gap_direction  = 0;  ///< gap_direction = 0 (IJDIR per block, SAAC2) | 1 | 2 (SAAC's one LGAP)
  /// plasticity = return-mapping (the default: backward Euler onto the yield surface, Newton to
  /// newton_tolerance in every increment) | tangent (the seed's one solve per increment, SAGAEP's and
  /// SAAC3's schemes: for reproducing legacy results; docs/plasticity.md).
  PlasticityChoice plasticity = PlasticityChoice::return_mapping;
  /// Which accepted increments the result files get, per kind: output_csv for the tables nodes.csv,
  /// elements.csv and reactions.csv, output_vtu for the VTU files and result.pvd; each all (every
  /// increment, the default) | last (only the run's last: a many-step run read at its end does not spend
  /// its time writing text) | none. `output = X` sets both. plasticity.csv and gaps.csv, the run's
  /// record, and deformed.svg (the last increment) are always written.
  Increments output_csv = Increments::all;
  Increments output_vtu = Increments::all;
  /// output_parts = pieces (the default) | gathered: how a partitioned run (solver = petsc on several
  /// processes) writes the tables and VTU files: each process its own part (nodes_pK.csv, ...,
  /// step_NNNN_pK.vtu with a step_NNNN.pvtu; output/step_files.hpp), or rank 0 the whole mesh's, as one
  /// process would, after gathering every result (memory and time on rank 0 that grow with the model).
  bool output_gathered = false;
  /// error_estimate = energy (the default: the recovery estimate of the energy-norm error at every accepted
  /// increment, post/error_estimate.hpp, docs/accuracy.md) | none (no estimate: a run timed against a code
  /// that makes none).
  bool error_estimate = true;
  /// newton_tolerance = |R_free| / |F_int| that ends a plastic step's Newton iterations (default 1e-10);
  /// newton_iterations = the iterations before a step is cut in halves (default 30). NewtonOptions.
  double newton_tolerance = 1e-10;
  int newton_iterations   = 30;
  /// load_pieces = N: a law with history, or contact, takes each load step in N equal increments or more
  /// (default 1: a step whole, cut only when Newton, the time control or a contact status change asks).
  /// `--estimate` runs a path-dependent model (plasticity, friction) with 2 and 4 to measure the load-step
  /// error (docs/accuracy.md "Error bars").
  int load_pieces = 1;
  /// time_tolerance = the largest estimated local error of a rate-dependent law's time integration an
  /// increment may keep (DrysdaleZak::time_error: the stress its plastic-strain error stands for, relative
  /// to yield); a load step is cut into halves until its pieces meet it (plasticity = return-mapping; the
  /// seed's tangent scheme keeps one increment per step). 0: off. docs/plasticity.md, "Time steps".
  double time_tolerance = 1e-3;
  /// fields = legacy | wide: wide widens the two fields that cap a deck's size, the line
  /// segment cards' grid indices (I3, at most 999) and the edge load cards' node numbers (I5, at most
  /// 99,999); every other card keeps its columns (CardLayout, input/deck_lines.hpp).
  bool wide_fields = false;
  /// units = LENGTH,FORCE,STRESS (e.g. mm,N,MPa): names for the pictures' labels; gapfe never
  /// converts units, so this only says which consistent set the deck uses. Empty: generic names.
  std::string units;

  /// The friction model a run uses: none without friction, else the slip option with auto resolved.
  FrictionChoice friction_model() const {
    if (!(friction > 0)) return FrictionChoice::none;
    switch (slip) {
      case SlipChoice::proportional:
        return FrictionChoice::proportional;
      case SlipChoice::extended:
        return FrictionChoice::extended;
      case SlipChoice::coulomb:
        return FrictionChoice::coulomb;
      case SlipChoice::automatic:
        break;
    }
    return contact == ContactChoice::saac ? FrictionChoice::extended : FrictionChoice::coulomb;
  }

  /// Set one option from its text form; throws InputError naming the key and the accepted values.
  void set(const std::string& key, const std::string& value) {
    const auto choice = [&]<class E>(E) {
      if (const auto c = choice_named<E>(value)) return *c;
      throw InputError("option " + key + " = '" + value + "': expected one of " + choice_list<E>());
    };
    const auto one_of = [&](std::initializer_list<const char*> allowed) {
      std::string list;
      for (const char* a : allowed) {
        if (value == a) return value;
        list += (list.empty() ? "" : ", ") + std::string(a);
      }
      throw InputError("option " + key + " = '" + value + "': expected one of " + list);
    };
    const auto number = [&](double lo) {
      char* end      = nullptr;
      const double v = std::strtod(value.c_str(), &end);
      if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(v) || v < lo)
        throw InputError("option " + key + " = '" + value + "': expected a number >= " + std::to_string(lo));
      return v;
    };
    if (key == "format") {
      const std::string f = one_of({"saac", "saac2", "saac3", "saac3x", "elastic", "saas", "saga"});
      format              = (f == "saac3" || f == "saac3x")                  ? DeckFormat::saac3
                            : (f == "elastic" || f == "saas" || f == "saga") ? DeckFormat::elastic
                                                                             : DeckFormat::saac;
    } else if (key == "element") {
      element = choice(ElementChoice{});
    } else if (key == "solver") {
      solver = choice(SolverChoice{});
    } else if (key == "bc_loads") {
      loads_per_radian = one_of({"total", "per-radian"}) == "per-radian";
    } else if (key == "contact") {
      contact = choice(ContactChoice{});
    } else if (key == "friction") {
      friction = number(0.0);
    } else if (key == "slip") {
      slip = choice(SlipChoice{});
    } else if (key == "events") {
      events = choice(EventChoice{});
    } else if (key == "gap_penalty") {
      gap_penalty = number(0.0);
    } else if (key == "gap_direction") {
      gap_direction = std::stoi(one_of({"0", "1", "2"}));
    } else if (key == "plasticity") {
      plasticity = choice(PlasticityChoice{});
    } else if (key == "output") {
      output_csv = output_vtu = choice(Increments{});
    } else if (key == "output_csv") {
      output_csv = choice(Increments{});
    } else if (key == "output_vtu") {
      output_vtu = choice(Increments{});
    } else if (key == "output_parts") {
      output_gathered = one_of({"pieces", "gathered"}) == "gathered";
    } else if (key == "error_estimate") {
      error_estimate = one_of({"energy", "none"}) == "energy";
    } else if (key == "newton_tolerance") {
      newton_tolerance = number(0.0);
      if (!(newton_tolerance > 0 && newton_tolerance < 1))
        throw InputError("option newton_tolerance = '" + value + "': expected a number in (0, 1)");
    } else if (key == "time_tolerance") {
      time_tolerance = number(0.0);
    } else if (key == "fields") {
      wide_fields = one_of({"legacy", "wide"}) == "wide";
    } else if (key == "units") {
      (void)unit_names(value);  // checked here, used by the pictures
      units = value;
    } else if (key == "load_pieces") {
      const double n = number(1.0);
      if (n != std::floor(n) || n > 1024)
        throw InputError("option load_pieces = '" + value + "': expected a whole number 1 to 1024");
      load_pieces = static_cast<int>(n);
    } else if (key == "newton_iterations") {
      const double n = number(1.0);
      if (n != std::floor(n) || n > 10000)
        throw InputError("option newton_iterations = '" + value + "': expected a whole number 1 to 10000");
      newton_iterations = static_cast<int>(n);
    } else {
      throw InputError(
          "unknown option '" + key +
          "' (known: format, element, solver, bc_loads, contact, friction, slip, gap_penalty, "
          "events, gap_direction, plasticity, output, output_csv, output_vtu, output_parts, error_estimate, "
          "newton_tolerance, newton_iterations, load_pieces, time_tolerance, fields, units)");
    }
  }
};

}  // namespace gapfe

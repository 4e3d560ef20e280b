#pragma once
// The neutral description of a model that both readers fill: options, materials, temperatures and the load
// program, in the seed's terms (the card each field mirrors is named, BRL-CR-670 Appendix A). A card deck
// (input/deck_reader.hpp) and a scene file (input/scene_file.hpp) each become one.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gapfe/input/deck_options.hpp"
#include "gapfe/material/elastic.hpp"
#include "gapfe/mesh/temperature.hpp"
#include "gapfe/problem/loads.hpp"

namespace gapfe {

/// Where a card came from, for messages about values that need the mesh to check.
struct CardRef {
  std::string card;  ///< "DATA NO. 13 (boundary pressure card 2 of load step 1)"
  int line = 0;
  std::string where() const { return card + ", line " + std::to_string(line); }
};

struct RateCard {  // Data 0 (SAAC3, SAAC3X)
  double time_step = 0, rate_b = 0, rate_plastic_strain = 0, strain_rate = 0, shear_stress_step = 0;
};

struct YieldCard {                // Data 11, in material axes
  std::array<double, 6> yield{};  ///< tension N, S, T; shear NS, NT, TS [stress]
  double hardening = 0;           ///< C
  bool blank       = true;        ///< all-blank card: the material stays elastic
};

struct MaterialInput {  // Data 10 (+ 11)
  int id = 0;
  ElasticTable table;
  std::optional<YieldCard> yield;  ///< absent in elastic decks
  CardRef ref;
};

/// A load history, which a scene file can give and a deck cannot: the factor on a load's value at
/// the end of each load step, linear between (step, factor) points at whole steps, 0 at step 0 unless a
/// point says otherwise, and the last point's factor after it. Within a step the load moves linearly, as
/// every load does (run/step_loads.hpp, interpolate).
struct Amplitude {
  std::vector<std::pair<int, double>> points;  ///< (step, factor), steps increasing, from 0

  double at(int step) const {
    std::pair<int, double> before{0, 0.0};
    for (const auto& p : points) {
      if (p.first >= step)
        return p.first == before.first ? p.second
                                       : before.second + (p.second - before.second) * (step - before.first) /
                                                             static_cast<double>(p.first - before.first);
      before = p;
    }
    return before.second;
  }
};

struct EdgeCard {              // Data 13-15
  int node_m = 0, node_n = 0;  ///< 1-based, as on the card
  double value = 0;            ///< the increment of each step; with an amplitude, the value it multiplies
  CardRef ref;
  int amplitude = -1;  ///< index into LoadProgram::amplitudes (scene files); -1: a deck's card
};

struct LoadBlock {  // Data 12-15 of one load step
  std::optional<InertiaLoad> inertia;
  int inertia_amplitude = -1;  ///< as EdgeCard::amplitude, for the inertia card
  std::vector<EdgeCard> pressure, shear, transverse_shear;
};

/// The load program of a model, as both readers give it (a deck from its control card and load blocks, a
/// scene file from its [steps], loads and histories): what run/step_loads.hpp sums. In a deck's terms:
/// NLINC steps, INERT, INCI = 0 (inertia_repeats), INCF = 0 (surface_repeats), TREF.
struct LoadProgram {
  int steps            = 1;       ///< load steps
  bool inertia         = false;   ///< an inertia card in the blocks (a deck's INERT != 0)
  bool inertia_repeats = true;    ///< the first block's inertia card repeats every step (INCI = 0)
  bool surface_repeats = true;    ///< the first block's edge load cards repeat every step (INCF = 0)
  std::vector<LoadBlock> blocks;  ///< as given: one per step, or the first only
  /// Load histories (EdgeCard::amplitude, LoadBlock::inertia_amplitude, Scene::condition_amplitude,
  /// temperature_amplitude): a scene file's; a deck has none. They act only in a block that repeats, which is
  /// how a scene gives its loads.
  std::vector<Amplitude> amplitudes;
  /// The temperature field's history (an index into amplitudes); -1: the deck's, the whole field from the
  /// end of the first load step on (StepTotals::thermal_fraction).
  int temperature_amplitude    = -1;
  double reference_temperature = 0;  ///< T_ref, from which thermal strains count (a deck's TREF)

  /// Inertia increment of load step s (1-based): its own card, the first block's when it repeats.
  InertiaLoad inertia_at(int s) const {
    if (!inertia) return {};
    return blocks[inertia_repeats ? 0 : static_cast<std::size_t>(s - 1)].inertia.value_or(InertiaLoad{});
  }
  /// Surface-load cards of load step s (1-based): its own, the first block's when they repeat.
  const LoadBlock& surface(int s) const {
    return blocks[surface_repeats ? 0 : static_cast<std::size_t>(s - 1)];
  }
};

/// A model as both readers give it, before its mesh is built: what a card deck and a scene file alike
/// become (a deck adds the cards that describe its grid, input/deck_cards.hpp; a scene file gives its mesh
/// its own way). The mesh, conditions and checked loads are the Scene's (input/scene.hpp).
struct ModelDescription {
  ModelOptions options;
  std::optional<RateCard> rate;  ///< SAAC3's rate card (Data 0), or a scene's [rate] table
  std::string title;
  std::vector<TemperaturePoint> temperature_points;
  std::string temperature_where =
      "DATA NO. 9, temperature card";  ///< how errors name a point (and its number)
  std::optional<double> constant_temperature;
  std::vector<MaterialInput> materials;
  LoadProgram program;  ///< the load steps, blocks and histories

  int steps() const { return program.steps; }
  /// Whether a temperature field is given (points, or one value everywhere).
  bool has_temperature() const { return !temperature_points.empty() || constant_temperature.has_value(); }
  /// Whether the law is rate dependent (SAAC3): a rate card (Data 0) with b != 0.
  bool rate_dependent() const { return rate && rate->rate_b != 0; }
  /// The time one load step lasts [model time unit]: card 0's delta t for a rate-dependent model, else 1
  /// (time is the load factor). A cut or split piece of a step lasts its fraction of it.
  double step_time() const { return rate_dependent() ? rate->time_step : 1.0; }
  InertiaLoad inertia(int s) const { return program.inertia_at(s); }
  const LoadBlock& surface(int s) const { return program.surface(s); }
  const MaterialInput* material(int id) const {
    for (const auto& m : materials)
      if (m.id == id) return &m;
    return nullptr;
  }
};

/// Limits that keep a hostile input file from exhausting memory; the seed's own limits are lifted.
struct InputLimits {
  long long max_grid_points = 200'000'000;  ///< MAXI x MAXJ, or a scene's grid
  int max_load_steps        = 1'000'000;
};

}  // namespace gapfe

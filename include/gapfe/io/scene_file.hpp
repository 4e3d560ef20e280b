#pragma once
// The scene file (issue 16): a model in TOML, by name instead of by card column, on a Gmsh mesh or on the
// seed's I-J grid. It says what a deck says (io/deck.hpp): materials by surface, conditions and loads by
// curve or surface, load steps and their histories, temperatures, inertia, the rate card, contact between
// two facing curves, and the deck options. read_scene turns it into the Deck and DeckScene a deck becomes,
// so everything after it (run/deck_run.hpp, the command, io/deck_output.hpp) is one path for decks and
// scenes, and one model given both ways gives the same answers.
//
// Needs toml++ (Debian's libtomlplusplus-dev; CMake target gapfe::scene), so gapfe.hpp does not include
// it. The keys, their units and defaults are in README "Scene files" and examples/scenes/; in short:
//
//   title = "..."
//   [mesh]        file = "part.msh" (relative to the scene file; physical groups name its parts), or
//                 grid = [MAXI, MAXJ] with [[mesh.segments]] type, points = [[I, J, r, z], ...], centre and
//                 [mesh.groups] NAME = {i = [I1, I2], j = [J1, J2]} (io/scene_mesh.hpp)
//   [options]     any deck option (io/deck_options.hpp) except format, which the scene implies
//   [steps]       count = N (load steps, default 1); time = dt (a step's duration, with [rate])
//   [materials.NAME]  surfaces = [...] (default [NAME]); number = k (its number in the output, default
//                 its place in the file's sorted names); E, nu, G, alpha as one number (isotropic) or
//                 three (orthotropic N, S, T: E_N E_S E_T, nu_NS nu_NT nu_ST, G_NS G_ST G_TN, alpha_N
//                 alpha_S alpha_T); or [[materials.NAME.rows]] with `temperature` for a table; density,
//                 thermal = "coefficients" | "free-strain", beta, helix (the seed's BETA, ALPHA [deg]),
//                 yield = Y (Mises) or yield = [N, S, T, NS, NT, TS], hardening = C
//   [[boundary]]  groups = [...]; fix = ["r", "z", "theta"]; displacement = {z = ...}; force = {r = ...}
//   [[load]]      curves = [...]; pressure, shear, transverse_shear
//   [inertia]     axial_acceleration, angular_velocity, angular_acceleration
//   [temperature] reference = T_ref; value = T or points = [[r, z, T], ...]
//   [rate]        b, transition_rate, strain_rate, shear_step (the seed's card 0)
//   [[contact]]   faces = ["A", "B"] (face A's side first: the gap closes from A towards B); soft = "S";
//                 policy, friction, slip, penalty, events (the deck options contact, friction, slip,
//                 gap_penalty, events: one value per run)
//
// Loads, displacements and angular velocities are the totals at the end of the last step, reached in
// equal increments (a deck with INCI = INCF = 0), unless the table has `amplitude = [[step, factor], ...]`:
// then the value times the factor at each step's end (Amplitude: linear between whole steps, 0 at step 0
// unless given, held after the last point), which says what a deck's per-step load blocks say and also
// lets prescribed displacements follow a history.
//
// Gap pairs (contact): every node of face A pairs with the node of face B nearest to it, which must be
// closer than half of each face's shortest edge at those nodes and face no other node of A; each edge of
// face A with its two partners is one gap element (corners in the seed's order IX1..IX4 = a, A(a), A(b), b,
// gap direction 1: seed Eq. 1-3 unchanged), numbered after the mesh's cells unless the soft surface S has a
// cell with those four corners (then it is that cell, soft while open, as a deck's material-2 element).
// Unequal node counts or a node without a partner is an error naming the node, its position and the
// nearest candidate (contact/facing_faces.hpp).
//
// Errors are InputErrors naming the key, its line in the scene file and what was expected.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "gapfe/contact/facing_faces.hpp"
#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/io/deck.hpp"
#include "gapfe/io/deck_scene.hpp"
#include "gapfe/io/input_file.hpp"
#include "gapfe/io/scene_mesh.hpp"
#include "gapfe/io/scene_table.hpp"
#include "gapfe/material/orientation.hpp"
#include "gapfe/mesh/gmsh_reader.hpp"

namespace gapfe {

/// Gives the text of the mesh a scene's [mesh] file names (throws InputError when it cannot).
using SceneMeshLoader = std::function<std::string(const std::string& name)>;

namespace detail {

/// One elastic row from a table holding E, nu and optionally G and alpha, each one number (isotropic) or
/// three (N, S, T).
inline ElasticConstants scene_elastic_row(const SceneTable& t, double temperature) {
  const char* three = "a number or three (N, S, T)";
  const auto E      = t.numbers("E", 3, three);
  const auto nu     = t.numbers("nu", 3, three);
  ElasticConstants c;
  c.temperature = temperature;
  c.E_N = E[0], c.E_S = E[1], c.E_T = E[2];
  c.nu_NS = nu[0], c.nu_NT = nu[1], c.nu_ST = nu[2];
  if (t.has("G")) {
    const auto G = t.numbers("G", 3, three);
    c.G_NS = G[0], c.G_ST = G[1], c.G_TN = G[2];
  } else if (E[0] == E[1] && E[1] == E[2] && nu[0] == nu[1] && nu[1] == nu[2]) {
    c.G_NS = c.G_ST = c.G_TN = ElasticConstants::isotropic(E[0], nu[0]).G_NS;
  } else {
    throw InputError("scene: " + t.where() + " needs " + t.where("G") +
                     ": an orthotropic material (three E or nu) gives its shear moduli");
  }
  if (t.has("alpha")) {
    const auto a = t.numbers("alpha", 3, three);
    c.alpha_N = a[0], c.alpha_S = a[1], c.alpha_T = a[2];
  }
  try {
    c.validate("");
  } catch (const InputError& e) {
    throw InputError("scene: " + t.where() + e.what());
  }
  return c;
}

/// [materials.NAME]: the deck material (its table and yield card) and its surfaces and orientation.
struct SceneMaterial {
  std::string name;
  DeckMaterial deck;
  std::vector<std::string> surfaces;
  double beta_deg = 0, helix_deg = 0;
  bool has_number = false;
};

inline SceneMaterial scene_material(const std::string& name, const SceneTable& t) {
  SceneMaterial m;
  m.name     = name;
  m.surfaces = t.names("surfaces", std::vector<std::string>{name});
  if (t.has("number")) {
    const double k = t.number("number");
    if (!(k >= 1 && k <= 1e6 && k == std::floor(k))) t.fail("number", "a whole number from 1 to 1000000");
    m.deck.id = static_cast<int>(k), m.has_number = true;
  }
  m.deck.ref           = {"[materials." + name + "]", SceneTable::line(t.raw())};
  m.deck.table.density = t.number("density", 0.0);
  if (m.deck.table.density < 0) t.fail("density", "a number >= 0");
  const std::string thermal = t.text("thermal", std::string("coefficients"));
  if (thermal != "coefficients" && thermal != "free-strain")
    t.fail("thermal", "\"coefficients\" or \"free-strain\"");
  m.deck.table.thermal = thermal == "free-strain" ? ThermalInput::free_strain : ThermalInput::coefficients;
  m.beta_deg           = t.number("beta", 0.0);
  m.helix_deg          = t.number("helix", 0.0);
  if (t.has("rows")) {
    if (t.has("E") || t.has("nu") || t.has("G") || t.has("alpha"))
      throw InputError("scene: " + t.where() + ": give the constants either in [[" + t.path() +
                       ".rows]] (a temperature table) or directly, not both");
    for (const SceneTable& row : t.tables("rows", {"temperature", "E", "nu", "G", "alpha"})) {
      const double T = row.number("temperature");
      if (!m.deck.table.rows.empty() && !(T > m.deck.table.rows.back().temperature))
        row.fail("temperature", "a temperature above the row before's (rows in increasing temperature)");
      m.deck.table.rows.push_back(scene_elastic_row(row, T));
    }
  } else {
    m.deck.table.rows.push_back(scene_elastic_row(t, 0.0));
  }
  if (t.has("yield") || t.has("hardening")) {
    YieldCard card;
    if (const toml::node* y = t.get("yield"); y && SceneTable::as_number(*y)) {
      const double Y = t.positive("yield");  // Mises: shear yield Y / sqrt(3)
      card.yield     = {Y, Y, Y, Y / std::sqrt(3.0), Y / std::sqrt(3.0), Y / std::sqrt(3.0)};
    } else {
      const auto v = t.numbers("yield", 6, "one yield stress (Mises) or six [N, S, T, NS, NT, TS], all > 0");
      for (int k = 0; k < 6; ++k) {
        if (!(v[k] > 0)) t.fail("yield", "one yield stress (Mises) or six [N, S, T, NS, NT, TS], all > 0");
        card.yield[k] = v[k];
      }
    }
    card.hardening = t.number("hardening", 0.0);
    card.blank     = false;
    m.deck.yield   = card;
  } else {
    m.deck.yield = YieldCard{};  // blank: elastic (a scene is read in a format with yield cards)
  }
  return m;
}

/// Builds a SceneModel from a scene's tables, one member per table, in the order their data depend on each
/// other: options and steps, the mesh and its cells, materials, conditions, loads, temperature, contact.
class SceneBuilder {
 public:
  SceneBuilder(const SceneTable& top, const DeckLimits& limits) : top_(top), limits_(limits) {}

  SceneModel build(const SceneMeshLoader& load_mesh,
                   const std::vector<std::pair<std::string, std::string>>& overrides) {
    model_.deck.title = top_.text("title", std::string("untitled scene"));
    options(overrides);
    steps();
    mesh(load_mesh);
    materials();
    boundary();
    loads();
    temperature();
    contact();
    finish_scene(model_.deck, model_.scene);
    return std::move(model_);
  }

 private:
  using Overrides = std::vector<std::pair<std::string, std::string>>;

  /// The [[contact]] keys that set a deck option: (key, option).
  static constexpr std::array<std::pair<const char*, const char*>, 5> kContactOptions{
      {{"policy", "contact"},
       {"friction", "friction"},
       {"slip", "slip"},
       {"penalty", "gap_penalty"},
       {"events", "events"}}};
  std::vector<SceneTable> contact_tables() const {
    return top_.tables("contact", {"faces", "soft", "policy", "friction", "slip", "penalty", "events"});
  }

  /// One deck option from a scene value (a string or a number) at `where`; an option the scene set before
  /// ([options] and [[contact]] tables alike) must not get another value.
  void set_option(const std::string& name, const toml::node& node, const std::string& where) {
    std::ostringstream value;
    if (node.is_string())
      value << *node.value<std::string_view>();
    else if (const auto* i = node.as_integer())
      value << i->get();
    else if (const auto v = SceneTable::as_number(node))
      value << std::setprecision(17) << *v;
    else
      throw InputError("scene: " + where + ": expected a string or a number");
    const auto [before, fresh] = options_set_.emplace(name, std::pair{value.str(), where});
    if (!fresh && before->second.first != value.str())
      throw InputError("scene: " + where + ": " + name + " = '" + value.str() + "', but " +
                       before->second.second + " set it to '" + before->second.first + "'; a run has one " +
                       name);
    try {
      model_.deck.options.set(name, value.str());
    } catch (const InputError& e) {
      throw InputError("scene: " + where + ": " + e.what());
    }
  }

  /// [options] through DeckOptions::set, [[contact]]'s options, then [rate] (card 0: SAAC3's format), then
  /// the command line's.
  void options(const Overrides& overrides) {
    Deck& d = model_.deck;
    if (const toml::node* o = top_.get("options")) {
      if (!o->is_table()) top_.fail("options", "a table of deck options");
      for (auto&& [key, node] : *o->as_table()) {
        const std::string name(key.str()),
            where = "key 'options." + name + "' (line " + std::to_string(SceneTable::line(node)) + ")";
        if (name == "format")
          throw InputError("scene: " + where +
                           ": a scene's format follows from what it holds (a [rate] table makes it saac3); "
                           "remove the key");
        set_option(name, node, where);
      }
    }
    // [[contact]]'s policy, friction, slip, penalty and events are deck options too; one value per run.
    for (const SceneTable& c : contact_tables())
      for (const auto& [key, option] : kContactOptions)
        if (const toml::node* node = c.get(key)) set_option(option, *node, c.where(key));
    d.options.format = DeckFormat::saac;
    if (const auto r = top_.table("rate", {"b", "transition_rate", "strain_rate", "shear_step"})) {
      d.options.format = DeckFormat::saac3;
      d.rate           = RateCard{0, r->number("b", 0.0), r->number("transition_rate", 0.0),
                        r->number("strain_rate", 0.0), r->number("shear_step", 0.0)};
    }
    for (const auto& [key, value] : overrides) d.options.set(key, value);
    if (d.options.format == DeckFormat::elastic)
      throw InputError(
          "scene: format = elastic given on the command line: a scene's format follows from what "
          "it holds");
  }

  void steps() {
    Deck& d         = model_.deck;
    d.control.nlinc = 1;
    if (const auto s = top_.table("steps", {"count", "time"})) {
      const int most = limits_.max_load_steps;
      const double n = s->number("count", 1.0);
      if (!(n >= 1 && n <= most && n == std::floor(n)))
        s->fail("count", "a whole number of load steps from 1 to " + std::to_string(most));
      d.control.nlinc = static_cast<int>(n);
      if (s->has("time")) {
        if (!d.rate) s->fail("time", "no step duration without a [rate] table (time is the load factor)");
        d.rate->time_step = s->positive("time");
      }
    }
    if (d.rate && d.rate->rate_b != 0 && !(d.rate->time_step > 0))
      throw InputError("scene: [rate] has b != 0, so a load step's duration matters: give key 'steps.time'");
  }

  /// [mesh]: a Gmsh file, or the I-J generator's grid, segments and groups (io/scene_mesh.hpp).
  void mesh(const SceneMeshLoader& load_mesh) {
    const auto table = top_.table("mesh", {"file", "grid", "segments", "groups"});
    if (!table)
      throw InputError(
          "scene: no [mesh] table: give [mesh] file = \"part.msh\" (a Gmsh mesh) or grid = [MAXI, MAXJ] "
          "with [[mesh.segments]] (the I-J generator)");
    if (table->has("file") == table->has("grid"))
      throw InputError("scene: " + table->where() +
                       ": give either file (a Gmsh mesh) or grid with segments (the I-J generator)");
    if (!table->has("file")) {
      mesh_name_ = "the I-J grid";
      mesh_      = std::make_unique<GridSceneMesh>(*table, model_.scene, limits_);
      return;
    }
    for (const char* key : {"segments", "groups"})
      if (table->has(key))
        table->fail(key, std::string("no ") + key + " with a Gmsh file (its physical groups name it)");
    mesh_name_       = table->text("file");
    model_.mesh_file = mesh_name_;
    std::string text;
    try {
      text = load_mesh(mesh_name_);
    } catch (const InputError& e) {
      throw InputError("scene: " + table->where("file") + ": " + e.what());
    } catch (const FileError& e) {  // still a file problem (exit 3), now naming the key that named the file
      throw FileError("scene: " + table->where("file") + ": " + e.what());
    }
    mesh_ = std::make_unique<GmshSceneMesh>(mesh_name_, text, model_.scene);
  }

  CellTag& tag(int cell) {
    const GridCell& c = model_.scene.grid.cells[cell];
    return (c.corners == 4 ? model_.scene.mesh.cell_tags : model_.scene.mesh.triangle_tags)[c.group_index];
  }

  /// A group's cells, edges or nodes, its errors prefixed with the key that named it.
  template <class Lookup>
  auto in_group(const SceneTable& t, const char* key, Lookup&& lookup) const {
    try {
      return lookup(*mesh_);
    } catch (const InputError& e) {
      throw InputError("scene: " + t.where(key) + ": " + e.what() + " (mesh " + mesh_name_ + ")");
    }
  }

  /// A load history (`amplitude = [[step, factor], ...]`, Amplitude) as an index into Deck::amplitudes, -1
  /// without one.
  int amplitude(const SceneTable& t) {
    const toml::node* node = t.get("amplitude");
    if (!node) return -1;
    const int steps            = model_.deck.steps();
    const std::string expected = "[[step, factor], ...]: whole steps from 0 to the last, " +
                                 std::to_string(steps) + ", increasing, with finite factors";
    const toml::array* a = node->as_array();
    if (!a || a->empty()) t.fail("amplitude", expected);
    Amplitude amp;
    for (const toml::node& e : *a) {
      const toml::array* q = e.as_array();
      const auto step      = q && q->size() == 2 ? SceneTable::as_number(*q->get(0)) : std::nullopt;
      const auto factor    = q && q->size() == 2 ? SceneTable::as_number(*q->get(1)) : std::nullopt;
      if (!step || !factor || !std::isfinite(*factor) || !(*step >= 0 && *step <= steps) ||
          *step != std::floor(*step) || (!amp.points.empty() && !(*step > amp.points.back().first)))
        t.fail("amplitude", expected);
      amp.points.emplace_back(static_cast<int>(*step), *factor);
    }
    model_.deck.amplitudes.push_back(std::move(amp));
    return static_cast<int>(model_.deck.amplitudes.size()) - 1;
  }

  /// [materials.NAME] on their surfaces: material numbers (given, or the next free in name order), the
  /// deck's materials, each cell's tag; every cell must get one.
  void materials() {
    Deck& d                 = model_.deck;
    DeckScene& s            = model_.scene;
    const toml::node* table = top_.get("materials");
    if (!table || !table->is_table() || table->as_table()->empty())
      throw InputError("scene: no [materials.NAME] table: each physical surface needs a material");
    std::vector<std::pair<SceneMaterial, SceneTable>> read;
    std::set<int> numbers;
    for (auto&& [key, node] : *table->as_table()) {
      const std::string name(key.str());
      if (!node.is_table()) top_.fail("materials", "[materials." + name + "] tables");
      SceneTable t(*node.as_table(), "materials." + name,
                   {"surfaces", "number", "E", "nu", "G", "alpha", "rows", "density", "thermal", "beta",
                    "helix", "yield", "hardening"});
      SceneMaterial m = scene_material(name, t);
      if (m.has_number && !numbers.insert(m.deck.id).second)
        t.fail("number", "a number no other material has");
      read.emplace_back(std::move(m), std::move(t));
    }
    int next = 1;
    for (auto& [m, t] : read) {
      if (!m.has_number) {
        while (numbers.count(next)) ++next;
        numbers.insert(m.deck.id = next);
      }
      d.materials.push_back(m.deck);
    }
    d.control.nummat = static_cast<int>(d.materials.size());
    // Per cell, the material (index into read) and surface that gave it one: a cell in two surface groups
    // (a surface in "steel" and in "all") may be named by both, for one material only.
    std::vector<std::pair<int, const std::string*>> given(s.material_id.size(), {-1, nullptr});
    for (std::size_t k = 0; k < read.size(); ++k) {
      const auto& [m, t] = read[k];
      const double deg   = kTwoPi / 360.0;
      const CellTag cell_tag{static_cast<int>(k),
                             helical_frame(m.beta_deg * deg, m.helix_deg * deg, 0, 0, 0)};
      for (const std::string& surface : m.surfaces)
        for (const int e :
             in_group(t, "surfaces", [&](const SceneMesh& g) { return g.surface_cells(surface); })) {
          auto& [first, first_surface] = given[static_cast<std::size_t>(e)];
          if (first >= 0 && first != static_cast<int>(k))
            throw InputError("scene: " + t.where("surfaces") + ": " + mesh_->cell_where(e) + ", in \"" +
                             surface + "\", is also in \"" + *first_surface + "\" of [materials." +
                             read[static_cast<std::size_t>(first)].first.name +
                             "]: a cell takes one material, so two materials may not name it");
          first = static_cast<int>(k), first_surface = &surface;
          s.material_id[e] = m.deck.id;
          tag(e)           = cell_tag;
        }
      if (m.helix_deg != 0)
        s.needs.theta.push_back("helix = " + number_text(m.helix_deg) + " in " + m.deck.ref.where());
    }
    for (std::size_t e = 0; e < s.material_id.size(); ++e)
      if (s.material_id[e] == 0)
        throw InputError("scene: " + mesh_->cell_where(static_cast<int>(e)) +
                         " has no material: name its surface in some [materials.NAME] surfaces");
    scene_materials(d, s);
  }

  /// [[boundary]]: a condition on every node of the groups; values are totals, so each step adds 1 / N,
  /// unless an amplitude gives their history.
  void boundary() {
    DeckScene& s                          = model_.scene;
    const std::array<const char*, 3> dirs = {"r", "z", "theta"};
    for (const SceneTable& b :
         top_.tables("boundary", {"groups", "fix", "displacement", "force", "amplitude"})) {
      const int history  = amplitude(b);
      const double steps = history < 0 ? model_.deck.control.nlinc : 1.0;
      int code = 0, given = 0;  // prescribed displacements (seed Data 5's code bits); directions given
      std::array<double, 3> value{};
      if (b.has("fix"))
        for (const std::string& c : b.names("fix")) {
          const auto k = std::find(dirs.begin(), dirs.end(), c) - dirs.begin();
          if (k == 3) b.fail("fix", "directions among \"r\", \"z\", \"theta\"");
          code |= 1 << k, given |= 1 << k;
        }
      for (const char* kind : {"displacement", "force"})
        if (const auto v = b.table(kind, {"r", "z", "theta"}))
          for (int k = 0; k < 3; ++k)
            if (v->has(dirs[k])) {
              if ((given >> k) & 1)
                v->fail(dirs[k], std::string("one condition per direction (") + dirs[k] + " is given twice)");
              given |= 1 << k;
              code |= std::string_view(kind) == "displacement" ? 1 << k : 0;
              value[k] = v->number(dirs[k]) / steps;
            }
      if (given == 0)
        throw InputError("scene: " + b.where() + ": a [[boundary]] needs fix, displacement or force");
      const std::vector<std::string> groups = b.names("groups");
      const int card                        = static_cast<int>(s.condition_cards.size());
      s.condition_cards.emplace_back();
      for (const std::string& name : groups) {
        s.condition_cards.back() += (s.condition_cards.back().empty() ? "" : "+") + name;
        for (const int n : in_group(b, "groups", [&](const SceneMesh& g) { return g.nodes(name); })) {
          s.conditions.push_back({n, code, value, given});
          s.condition_amplitude.push_back(history);
          s.condition_card.push_back(card);
        }
      }
      if (value[2] != 0)
        s.needs.theta.push_back(std::string("a theta ") + ((code & 4) ? "displacement" : "force") + " in " +
                                b.where());
    }
  }

  /// [[load]] on curves as the deck's edge cards (Data 13-15), each edge from M to N with its cell on the
  /// left; [inertia] as the first block's inertia card. Both repeat every step (INCI = INCF = 0), or follow
  /// their amplitude.
  void loads() {
    Deck& d         = model_.deck;
    const IJGrid& g = model_.scene.grid;
    std::set<std::pair<int, int>> ccw;  // every cell side, counterclockwise
    for (const auto& c : g.cells)
      for (int k = 0; k < c.corners; ++k) ccw.insert({c.node[k], c.node[(k + 1) % c.corners]});
    LoadBlock block;
    const std::array<const char*, 3> kinds = {"pressure", "shear", "transverse_shear"};
    for (const SceneTable& l :
         top_.tables("load", {"curves", "pressure", "shear", "transverse_shear", "amplitude"})) {
      const int history  = amplitude(l);
      const double steps = history < 0 ? d.control.nlinc : 1.0;
      std::array<std::optional<double>, 3> value;
      for (int k = 0; k < 3; ++k)
        if (l.has(kinds[k])) value[k] = l.number(kinds[k]) / steps;
      if (!value[0] && !value[1] && !value[2])
        throw InputError("scene: " + l.where() + ": a [[load]] needs pressure, shear or transverse_shear");
      const CardRef ref{"scene key '" + l.path() + ".curves'",
                        l.has("curves") ? SceneTable::line(*l.get("curves")) : 0};
      // Each edge once per [[load]]: a curve named twice, or two curves that share an edge, would load it
      // twice.
      std::map<std::pair<int, int>, std::string> loaded;  // edge (sorted nodes) -> the curve that loads it
      const std::vector<std::string> curves = l.names("curves");
      for (std::size_t k = 0; k < curves.size(); ++k)
        if (std::find(curves.begin(), curves.begin() + static_cast<std::ptrdiff_t>(k), curves[k]) !=
            curves.begin() + static_cast<std::ptrdiff_t>(k))
          throw InputError("scene: " + l.where("curves") + ": the curve \"" + curves[k] +
                           "\" is listed twice (its edges would be loaded twice)");
      for (const std::string& name : curves)
        for (const SceneEdge& e :
             in_group(l, "curves", [&](const SceneMesh& groups) { return groups.curve_edges(name); })) {
          int m = e.m, n = e.n;
          const std::string& edge = e.where;
          if (const auto [at, fresh] = loaded.emplace(std::minmax(m, n), name); !fresh)
            throw InputError("scene: " + l.where("curves") + ": the curves \"" + at->second + "\" and \"" +
                             name + "\" share " + edge +
                             ": a [[load]] loads each edge once (name it in one curve, or "
                             "give the two their own [[load]] tables to load it twice)");
          const bool forward  = m >= 0 && n >= 0 && ccw.count({m, n}),
                     backward = m >= 0 && n >= 0 && ccw.count({n, m});
          if (!forward && !backward)
            throw InputError("scene: " + l.where("curves") + ": " + edge + " is not a side of a cell");
          if (forward && backward)
            throw InputError("scene: " + l.where("curves") + ": " + edge +
                             " lies between two cells; a surface load acts on the boundary");
          if (backward) std::swap(m, n);
          for (int k = 0; k < 3; ++k)
            if (value[k])
              (k == 0   ? block.pressure
               : k == 1 ? block.shear
                        : block.transverse_shear)
                  .push_back({m + 1, n + 1, *value[k], ref, history});
        }
    }
    d.control.numpc = static_cast<int>(block.pressure.size());
    d.control.numsc = static_cast<int>(block.shear.size());
    d.control.numst = static_cast<int>(block.transverse_shear.size());
    if (const auto in = top_.table(
            "inertia", {"axial_acceleration", "angular_velocity", "angular_acceleration", "amplitude"})) {
      block.inertia_amplitude = amplitude(*in);
      const double steps      = block.inertia_amplitude < 0 ? d.control.nlinc : 1.0;
      block.inertia           = InertiaLoad{in->number("axial_acceleration", 0.0) / steps,
                                  in->number("angular_velocity", 0.0) / steps,
                                  in->number("angular_acceleration", 0.0) / steps};
      d.control.inert         = 1;
    }
    d.control.inci = d.control.incf = 0;
    d.blocks_read.push_back(std::move(block));
  }

  /// [temperature]: the reference, and one value (card 9's constant form) or (r, z, T) points; the field
  /// acts from the end of the first step on (a deck's reading) unless an amplitude gives its history.
  void temperature() {
    Deck& d      = model_.deck;
    const auto t = top_.table("temperature", {"reference", "value", "points", "amplitude"});
    if (!t) return;
    d.control.tref          = t->number("reference", 0.0);
    d.temperature_amplitude = amplitude(*t);
    if (t->has("value") && t->has("points"))
      throw InputError("scene: " + t->where() + ": give value (one temperature) or points, not both");
    if (t->has("value")) {
      d.constant_temperature = t->number("value"), d.control.numtc = -2;
      return;
    }
    const toml::node* p = t->get("points");
    if (!p) return;
    d.temperature_where  = "scene: " + t->where("points") + ", point";
    const toml::array* a = p->as_array();
    if (!a || a->empty()) t->fail("points", "an array of [r, z, T] points");
    for (const toml::node& e : *a) {
      const toml::array* q = e.as_array();
      std::array<double, 3> v{};
      for (int k = 0; k < 3; ++k) {
        const auto x = q && q->size() == 3 ? SceneTable::as_number(*q->get(k)) : std::nullopt;
        if (!x || !std::isfinite(*x)) t->fail("points", "an array of [r, z, T] points");
        v[k] = *x;
      }
      d.temperature_points.push_back({v[0], v[1], v[2]});
    }
    d.control.numtc = static_cast<int>(d.temperature_points.size());
  }

  /// [[contact]]: gap elements between facing curves (contact/facing_faces.hpp); a soft surface's cells
  /// are the gap elements they bridge, soft while open (a deck's material 2), or soft throughout.
  void contact() {
    DeckScene& s            = model_.scene;
    const std::size_t cells = s.grid.cells.size();
    std::vector<char> soft(cells, 0);  // 1: a soft cell, 2: one that bridges the faces
    for (const SceneTable& c : contact_tables()) {
      const std::vector<std::string> faces = c.names("faces");
      if (faces.size() != 2 || faces[0] == faces[1])
        c.fail("faces", "two different curve groups [\"A\", \"B\"]");
      std::array<std::vector<std::array<int, 2>>, 2> edges;
      for (int f = 0; f < 2; ++f)
        for (const SceneEdge& e :
             in_group(c, "faces", [&](const SceneMesh& g) { return g.curve_edges(faces[f]); })) {
          const int m = e.m, n = e.n;
          if (m < 0 || n < 0)
            throw InputError("scene: " + c.where("faces") + ": curve \"" + faces[f] +
                             "\" has a node no cell uses");
          edges[f].push_back({m, n});
        }
      std::map<std::array<int, 4>, int> soft_by_corners;  // sorted corners -> cell
      if (c.has("soft")) {
        const std::string name = c.text("soft");
        for (const int e : in_group(c, "soft", [&](const SceneMesh& g) { return g.surface_cells(name); })) {
          if (s.gap_material >= 0 && s.gap_material != tag(e).material)
            c.fail("soft", "the soft cells of every contact in one material");
          s.gap_material             = tag(e).material;
          soft[e]                    = std::max<char>(soft[e], 1);
          std::array<int, 4> corners = s.grid.cells[e].node;
          if (s.grid.cells[e].corners == 4)
            std::sort(corners.begin(), corners.end()), soft_by_corners[corners] = e;
        }
      }
      std::vector<std::array<int, 4>> elements;
      try {
        elements = facing_gap_elements(s.grid.nodes, edges[0], edges[1], faces[0], faces[1], mesh_->labels());
      } catch (const InputError& e) {
        throw InputError("scene: " + c.where("faces") + ": " + e.what());
      }
      for (const auto& ix : elements) {
        std::array<int, 4> corners = ix;
        std::sort(corners.begin(), corners.end());
        const auto cell = soft_by_corners.find(corners);
        const int element =
            cell != soft_by_corners.end() ? cell->second : static_cast<int>(cells + s.gaps.pairs.size() / 2);
        if (cell != soft_by_corners.end()) soft[cell->second] = 2;
        const auto pairs = gap_element_pairs(element, ix, 1, s.grid.nodes);
        s.gaps.pairs.insert(s.gaps.pairs.end(), pairs.begin(), pairs.end());
      }
      s.needs.gaps.push_back("contact between \"" + faces[0] + "\" and \"" + faces[1] + "\" (" +
                             c.where("faces") + ")");
    }
    for (std::size_t e = 0; e < cells; ++e)
      if (soft[e] == 1) s.gaps.soft.push_back(static_cast<int>(e));
  }

  const SceneTable& top_;
  DeckLimits limits_;
  SceneModel model_;
  std::string mesh_name_;
  std::unique_ptr<SceneMesh> mesh_;
  /// Deck options the scene set, with the value and the key that set it (one value per run).
  std::map<std::string, std::pair<std::string, std::string>> options_set_;
};

}  // namespace detail

/// Read a scene file's text; `load_mesh` reads the mesh it names (read_scene_file: a file beside the
/// scene). `overrides` are option settings (the command's --set) applied after the scene's [options];
/// `limits` bound the grid and the load steps as a deck's (io/deck_cards.hpp).
inline SceneModel read_scene(std::string_view text, const SceneMeshLoader& load_mesh,
                             const std::vector<std::pair<std::string, std::string>>& overrides = {},
                             const DeckLimits& limits                                          = {}) {
  toml::table root;
  try {
    root = toml::parse(text);
  } catch (const toml::parse_error& e) {
    throw InputError("scene: line " + std::to_string(e.source().begin.line) + ", column " +
                     std::to_string(e.source().begin.column) + ": " + std::string(e.description()));
  }
  const detail::SceneTable top(root, "",
                               {"title", "mesh", "options", "steps", "materials", "boundary", "load",
                                "inertia", "temperature", "rate", "contact"});
  return detail::SceneBuilder(top, limits).build(load_mesh, overrides);
}

/// Read a scene file from disk, its mesh path relative to the file's directory.
inline SceneModel read_scene_file(const std::string& path,
                                  const std::vector<std::pair<std::string, std::string>>& overrides = {}) {
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  SceneModel m                     = read_scene(
                          read_input(path, "scene file"),
                          [&](const std::string& name) { return read_input((base / name).string(), "mesh"); }, overrides);
  if (!m.mesh_file.empty()) m.mesh_file = (base / m.mesh_file).string();
  return m;
}

}  // namespace gapfe

#pragma once
// The scene file: a model in TOML, by name instead of by card column, on a Gmsh mesh or on the
// seed's I-J grid. It says what a deck says (input/deck.hpp): materials by surface, conditions and loads by
// curve or surface, load steps and their histories, temperatures, inertia, the rate card, contact between
// two facing curves, and the deck options. read_scene turns it into the ModelDescription and Scene a deck
// also becomes, so everything after it (run/scene_run.hpp, the command, output/step_files.hpp) is one path
// for decks and scenes, and one model given both ways gives the same answers.
//
// Needs toml++ (Debian's libtomlplusplus-dev; CMake target gapfe::scene), so gapfe.hpp does not include
// it. The keys, their units and defaults are in docs/scenes.md "Scene files" and examples/scenes/; in short:
//
//   title = "..."
//   [mesh]        file = "part.msh" (relative to the scene file; physical groups name its parts), or
//                 grid = [MAXI, MAXJ] with [[mesh.segments]] type, points = [[I, J, r, z], ...], centre and
//                 [mesh.groups] NAME = {i = [I1, I2], j = [J1, J2]} (input/scene_grid.hpp)
//   [options]     any deck option (input/deck_options.hpp) except format, which the scene implies
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
#include "gapfe/input/gmsh_reader.hpp"
#include "gapfe/input/input_file.hpp"
#include "gapfe/input/model_description.hpp"
#include "gapfe/input/scene.hpp"
#include "gapfe/input/scene_grid.hpp"
#include "gapfe/input/scene_materials.hpp"
#include "gapfe/input/scene_mesh.hpp"
#include "gapfe/input/scene_table.hpp"
#include "gapfe/material/orientation.hpp"

namespace gapfe {

/// Gives the text of the mesh a scene's [mesh] file names (throws InputError when it cannot).
using SceneMeshLoader = std::function<std::string(const std::string& name)>;

namespace detail {

/// Builds a SceneModel from a scene's tables, one member per table, in the order their data depend on each
/// other: options and steps, the mesh and its cells, materials, conditions, loads, temperature, contact.
class SceneBuilder {
 public:
  /// `refine`: the mesh refined that many times (SceneRefinement), for `gapfe run --estimate`.
  SceneBuilder(const SceneTable& top, const InputLimits& limits, int refine = 0)
      : top_(top), limits_(limits), refine_(refine) {}

  SceneModel build(const SceneMeshLoader& load_mesh,
                   const std::vector<std::pair<std::string, std::string>>& overrides) {
    model_.description.title = top_.text("title", std::string("untitled scene"));
    options(overrides);
    steps();
    mesh(load_mesh);
    materials();
    boundary();
    loads();
    temperature();
    contact();
    finish_scene(model_.description, model_.scene);
    quadratic_cells(model_.description, model_.scene);
    model_.refined = mesh_->refined();
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
      model_.description.options.set(name, value.str());
    } catch (const InputError& e) {
      throw InputError("scene: " + where + ": " + e.what());
    }
  }

  /// [options] through ModelOptions::set, [[contact]]'s options, then [rate] (card 0: SAAC3's format), then
  /// the command line's.
  void options(const Overrides& overrides) {
    ModelDescription& d = model_.description;
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
    ModelDescription& d = model_.description;
    d.program.steps     = 1;
    if (const auto s = top_.table("steps", {"count", "time"})) {
      const int most = limits_.max_load_steps;
      const double n = s->number("count", 1.0);
      if (!(n >= 1 && n <= most && n == std::floor(n)))
        s->fail("count", "a whole number of load steps from 1 to " + std::to_string(most));
      d.program.steps = static_cast<int>(n);
      if (s->has("time")) {
        if (!d.rate) s->fail("time", "no step duration without a [rate] table (time is the load factor)");
        d.rate->time_step = s->positive("time");
      }
    }
    if (d.rate && d.rate->rate_b != 0 && !(d.rate->time_step > 0))
      throw InputError("scene: [rate] has b != 0, so a load step's duration matters: give key 'steps.time'");
  }

  /// [mesh]: a Gmsh file, or the I-J generator's grid, segments and groups (input/scene_mesh.hpp,
  /// scene_grid.hpp).
  void mesh(const SceneMeshLoader& load_mesh) {
    const auto table = top_.table("mesh", {"file", "grid", "segments", "groups"});
    if (!table)
      throw InputError(
          "scene: no [mesh] table: give [mesh] file = \"part.msh\" (a Gmsh mesh) or grid = [MAXI, MAXJ] "
          "with [[mesh.segments]] (the I-J generator)");
    if (table->has("file") == table->has("grid"))
      throw InputError("scene: " + table->where() +
                       ": give either file (a Gmsh mesh) or grid with segments (the I-J generator)");
    SceneRefinement refine{refine_, {}, {}};
    if (refine_ > 0)  // the layers between contact faces stay one cell (their names are checked later)
      for (const SceneTable& c : contact_tables()) {
        const std::vector<std::string> faces = c.names("faces");
        if (faces.size() == 2) refine.faces.push_back({faces[0], faces[1]});
        if (c.has("soft")) refine.soft.push_back(c.text("soft"));
      }
    if (!table->has("file")) {
      mesh_name_ = "the I-J grid";
      mesh_      = std::make_unique<GridSceneMesh>(*table, model_.scene, limits_, refine);
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
    mesh_ = std::make_unique<GmshSceneMesh>(mesh_name_, text, model_.scene, refine);
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

  /// A load history (`amplitude = [[step, factor], ...]`, Amplitude) as an index into
  /// LoadProgram::amplitudes, -1 without one.
  int amplitude(const SceneTable& t) {
    const toml::node* node = t.get("amplitude");
    if (!node) return -1;
    const int steps            = model_.description.steps();
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
    model_.description.program.amplitudes.push_back(std::move(amp));
    return static_cast<int>(model_.description.program.amplitudes.size()) - 1;
  }

  /// [materials.NAME] on their surfaces: material numbers (given, or the next free in name order), the
  /// deck's materials, each cell's tag; every cell must get one.
  void materials() {
    ModelDescription& d     = model_.description;
    Scene& s                = model_.scene;
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
      if (m.has_number && !numbers.insert(m.input.id).second)
        t.fail("number", "a number no other material has");
      read.emplace_back(std::move(m), std::move(t));
    }
    int next = 1;
    for (auto& [m, t] : read) {
      if (!m.has_number) {
        while (numbers.count(next)) ++next;
        numbers.insert(m.input.id = next);
      }
      d.materials.push_back(m.input);
    }
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
          s.material_id[e] = m.input.id;
          tag(e)           = cell_tag;
        }
      if (m.helix_deg != 0)
        s.needs.theta.push_back("helix = " + number_text(m.helix_deg) + " in " + m.input.ref.where());
    }
    for (std::size_t e = 0; e < s.material_id.size(); ++e)
      if (s.material_id[e] == 0)
        throw InputError("scene: " + mesh_->cell_where(static_cast<int>(e)) +
                         " has no material: name its surface in some [materials.NAME] surfaces");
    scene_materials(d, s);
  }

  /// [[boundary]]: a condition on every node of the groups; values are totals, so each step adds 1 / N,
  /// unless an amplitude gives their history.
  void boundary();

  /// [[load]] on curves as the deck's edge cards (Data 13-15), each edge from M to N with its cell on the
  /// left; [inertia] as the first block's inertia card. Both repeat every step (INCI = INCF = 0), or follow
  /// their amplitude.
  void loads();

  /// [temperature]: the reference, and one value (card 9's constant form) or (r, z, T) points; the field
  /// acts from the end of the first step on (a deck's reading) unless an amplitude gives its history.
  void temperature();

  /// [[contact]]: gap elements between facing curves (contact/facing_faces.hpp); a soft surface's cells
  /// are the gap elements they bridge, soft while open (a deck's material 2), or soft throughout.
  void contact();

  const SceneTable& top_;
  InputLimits limits_;
  int refine_ = 0;
  SceneModel model_;
  std::string mesh_name_;
  std::unique_ptr<SceneMesh> mesh_;
  /// Deck options the scene set, with the value and the key that set it (one value per run).
  std::map<std::string, std::pair<std::string, std::string>> options_set_;
};

}  // namespace detail

/// Read a scene file's text; `load_mesh` reads the mesh it names (read_scene_file: a file beside the
/// scene). `overrides` are option settings (the command's --set) applied after the scene's [options];
/// `limits` bound the grid and the load steps as a deck's (InputLimits, input/model_description.hpp).
/// `refine` > 0: the model on its mesh refined that many times (SceneRefinement), for `gapfe run --estimate`.
inline SceneModel read_scene(std::string_view text, const SceneMeshLoader& load_mesh,
                             const std::vector<std::pair<std::string, std::string>>& overrides = {},
                             const InputLimits& limits = {}, int refine = 0) {
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
  return detail::SceneBuilder(top, limits, refine).build(load_mesh, overrides);
}

/// Read a scene file from disk, its mesh path relative to the file's directory; `refine` as read_scene's.
inline SceneModel read_scene_file(const std::string& path,
                                  const std::vector<std::pair<std::string, std::string>>& overrides = {},
                                  int refine                                                        = 0) {
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  const auto mesh = [&](const std::string& name) { return read_input((base / name).string(), "mesh"); };
  SceneModel m    = read_scene(read_input(path, "scene file"), mesh, overrides, {}, refine);
  if (!m.mesh_file.empty()) m.mesh_file = (base / m.mesh_file).string();
  return m;
}

}  // namespace gapfe

// Out-of-class members of SceneBuilder.
#include "gapfe/input/scene_loads.hpp"  // IWYU pragma: export

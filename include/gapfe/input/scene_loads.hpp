#pragma once
// The scene file's loads, SceneBuilder's members defined out of its class (included at the end of
// input/scene_file.hpp): [[boundary]] conditions, [[load]] and [inertia], [temperature] and [[contact]].
#include "gapfe/input/scene_file.hpp"

namespace gapfe::detail {

inline void SceneBuilder::boundary() {
  Scene& s                              = model_.scene;
  const std::array<const char*, 3> dirs = {"r", "z", "theta"};
  for (const SceneTable& b :
       top_.tables("boundary", {"groups", "fix", "displacement", "force", "amplitude"})) {
    const int history  = amplitude(b);
    const double steps = history < 0 ? model_.description.program.steps : 1.0;
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
        // A refined mesh's new nodes take the displacements (an edge held stays held all along) but not
        // the ring forces, which stay on the mesh's own nodes: the same total load.
        const bool own = mesh_->own(n);
        if (!own && (code & given) == 0) continue;
        std::array<double, 3> v = value;
        for (int k = 0; k < 3; ++k)
          if (!own && !((code >> k) & 1)) v[k] = 0;
        s.conditions.push_back({n, code, v, own ? given : (code & given)});
        s.condition_amplitude.push_back(history);
        s.condition_card.push_back(card);
      }
    }
    if (value[2] != 0)
      s.needs.theta.push_back(std::string("a theta ") + ((code & 4) ? "displacement" : "force") + " in " +
                              b.where());
  }
}

inline void SceneBuilder::loads() {
  ModelDescription& d = model_.description;
  const IJGrid& g     = model_.scene.grid;
  std::set<std::pair<int, int>> ccw;  // every cell side, counterclockwise
  for (const auto& c : g.cells)
    for (int k = 0; k < c.corners; ++k) ccw.insert({c.node[k], c.node[(k + 1) % c.corners]});
  LoadBlock block;
  const std::array<const char*, 3> kinds = {"pressure", "shear", "transverse_shear"};
  for (const SceneTable& l :
       top_.tables("load", {"curves", "pressure", "shear", "transverse_shear", "amplitude"})) {
    const int history  = amplitude(l);
    const double steps = history < 0 ? d.program.steps : 1.0;
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
  if (const auto in = top_.table(
          "inertia", {"axial_acceleration", "angular_velocity", "angular_acceleration", "amplitude"})) {
    block.inertia_amplitude = amplitude(*in);
    const double steps      = block.inertia_amplitude < 0 ? d.program.steps : 1.0;
    block.inertia           = InertiaLoad{in->number("axial_acceleration", 0.0) / steps,
                                in->number("angular_velocity", 0.0) / steps,
                                in->number("angular_acceleration", 0.0) / steps};
    d.program.inertia       = true;
  }
  d.program.inertia_repeats = d.program.surface_repeats = true;
  d.program.blocks.push_back(std::move(block));
}

inline void SceneBuilder::temperature() {
  ModelDescription& d = model_.description;
  const auto t        = top_.table("temperature", {"reference", "value", "points", "amplitude"});
  if (!t) return;
  d.program.reference_temperature = t->number("reference", 0.0);
  d.program.temperature_amplitude = amplitude(*t);
  if (t->has("value") && t->has("points"))
    throw InputError("scene: " + t->where() + ": give value (one temperature) or points, not both");
  if (t->has("value")) {
    d.constant_temperature = t->number("value");
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
}

inline void SceneBuilder::contact() {
  Scene& s                = model_.scene;
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

}  // namespace gapfe::detail

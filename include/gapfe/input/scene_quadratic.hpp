#pragma once
// Quadratic cells for a scene (element = quad8; docs/settings.md "Quadratic cells"): a middle node on every
// side of the scene's cells, so that a deck's I-J grid, a grid scene or an order-1 Gmsh mesh runs as 8-node
// quadrilaterals and 6-node triangles (Quad8, Tri6), and an order-2 Gmsh mesh runs on its own middle nodes.
// The middle nodes are numbered after the corners, so every corner keeps its number, its I and J and its
// conditions; each is half-way along its side (its straight chord) unless the mesh file gives it
// (Scene::given_mid_sides: a curved side of an order-2 mesh).
//
// What the scene says on corners, the middle nodes get:
//   * each component that the conditions in force at both ends of the side prescribe (the last card or
//     [[boundary]] setting it there: NodalCondition::sets): the mean of the two ends' values (the side's
//     linear interpolation, what 4-corner cells saw), under their load history (detail::middle_value for
//     two), its reaction counted for the card that holds both ends (else the later one); a side held node
//     by node, one card a node, is held along its length too. A component a later card frees at one end
//     (a force, or another card's free component) is free in the middle. Forces stay on the nodes they name:
//     a nodal force is a ring load there, not a load spread along a side;
//   * the temperature: the field's points evaluated at the node, or the mean of the side's ends;
//   * SAAC3X's faces: a side with both ends on a face has its middle on it.
// Edge loads name their side by its corners, as before. Gap elements and contact are refused: a gap pair
// joins two nodes, which a quadratic side's middle node does not fit (core/combinations.hpp).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/pair_key.hpp"
#include "gapfe/input/scene.hpp"

namespace gapfe {

namespace detail {

/// Per corner node and component, the condition in force there (the last that sets it, NodalCondition::sets):
/// its index into Scene::conditions, or -1 where none does.
inline std::vector<std::array<int, 3>> conditions_in_force(const Scene& s, int corners) {
  std::vector<std::array<int, 3>> in_force(static_cast<std::size_t>(corners), {-1, -1, -1});
  for (std::size_t k = 0; k < s.conditions.size(); ++k) {
    const NodalCondition& c = s.conditions[k];
    for (int comp = 0; comp < 3; ++comp)
      if ((c.sets >> comp) & 1) in_force[static_cast<std::size_t>(c.node)][comp] = static_cast<int>(k);
  }
  return in_force;
}

/// What a middle node takes from a side's ends for one component: its value, the load history it follows
/// (an index into LoadProgram::amplitudes, -1: the step count) and the card its reaction counts for.
struct MiddleValue {
  double value  = 0;
  int amplitude = -1, card = 0;
};

/// Component `comp` of the middle node of side (a, b), when the conditions in force at both ends prescribe it
/// (`in_force`, conditions_in_force): the mean of their values. Its load history is theirs; where they
/// differ, the one of the end whose value is not zero (a side from a held point to a moved one), and
/// InputError when both are (a mean of two histories is neither). Its reactions count for a card with a
/// condition prescribing it at both ends (the one that holds the side, when a later card overrides it at a
/// corner), else the later condition's card. `by_node[n]`: node n's conditions, in order.
inline std::optional<MiddleValue> middle_value(const Scene& s,
                                               const std::vector<std::array<int, 3>>& in_force,
                                               const std::vector<std::vector<int>>& by_node, int a, int b,
                                               int comp) {
  const int ka = in_force[static_cast<std::size_t>(a)][comp],
            kb = in_force[static_cast<std::size_t>(b)][comp];
  if (ka < 0 || kb < 0 || !s.conditions[ka].prescribed(comp) || !s.conditions[kb].prescribed(comp)) return {};
  const auto card      = [&](int k) { return s.condition_card.empty() ? 0 : s.condition_card[k]; };
  const auto amplitude = [&](int k) { return s.condition_amplitude.empty() ? -1 : s.condition_amplitude[k]; };
  const double va = s.conditions[ka].value[comp], vb = s.conditions[kb].value[comp];
  MiddleValue m{0.5 * (va + vb), amplitude(std::max(ka, kb)), card(std::max(ka, kb))};
  if (amplitude(ka) != amplitude(kb)) {
    if (va != 0 && vb != 0)
      throw InputError("element = quad8: the side from (r, z) = (" + number_text(s.mesh.nodes[a](0)) + ", " +
                       number_text(s.mesh.nodes[a](1)) + ") to (" + number_text(s.mesh.nodes[b](0)) + ", " +
                       number_text(s.mesh.nodes[b](1)) +
                       ") has a displacement prescribed at both ends under two different load histories, "
                       "which its middle node cannot follow; give both ends one history");
    m.amplitude = amplitude(va != 0 ? ka : kb);
  }
  for (const int k : by_node[static_cast<std::size_t>(a)])  // the latest card holding both ends
    if (s.conditions[k].prescribed(comp))
      for (const int l : by_node[static_cast<std::size_t>(b)])
        if (card(l) == card(k) && s.conditions[l].prescribed(comp)) m.card = card(k);
  return m;
}

/// The conditions the middle node `mid` of side (a, b) gets, one per (card, load history), appended to `made`
/// with their card and load history.
inline void side_conditions(const Scene& s, const std::vector<std::array<int, 3>>& in_force,
                            const std::vector<std::vector<int>>& by_node, int a, int b, int mid,
                            std::vector<std::pair<NodalCondition, MiddleValue>>& made) {
  const std::size_t first = made.size();
  for (int comp = 0; comp < 3; ++comp) {
    const std::optional<MiddleValue> m = middle_value(s, in_force, by_node, a, b, comp);
    if (!m) continue;
    auto it = made.begin() + static_cast<std::ptrdiff_t>(first);
    while (it != made.end() && (it->second.card != m->card || it->second.amplitude != m->amplitude)) ++it;
    if (it == made.end()) it = made.insert(it, {NodalCondition{mid, 0, {}, 0}, *m});
    it->first.code |= 1 << comp, it->first.sets |= 1 << comp, it->first.value[comp] = m->value;
  }
}

}  // namespace detail

/// Give scene `s` of the model `d` its quadratic cells: a middle node on every side (Scene::quadratic,
/// GridCell::mid), with the conditions, temperatures and faces above. InputError for a model with gap
/// elements.
inline void make_quadratic(const ModelDescription& d, Scene& s) {
  if (!s.needs.gaps.empty())
    throw InputError(
        std::string(s.given_mid_sides.empty() ? "element = quad8"
                                              : "the mesh is of order 2 (its cells have middle nodes), which "
                                                "runs as element = quad8 (mesh with Mesh.ElementOrder = 1)") +
        ": the model has gap elements (" + s.needs.gaps.front() +
        "), and contact runs on 4-corner cells (element = quad4bbar, quad4 or legacy): a gap pair joins two "
        "nodes, which a quadratic side's middle node does not fit");
  const int corners = s.mesh.node_count();
  std::unordered_map<std::uint64_t, int> middle_of;  // side (lesser corner, greater) -> its middle node
  std::vector<std::array<int, 3>> sides;             // (a, b, middle)
  const auto middle = [&](int a, int b) {
    const std::array<int, 2> side{std::min(a, b), std::max(a, b)};
    const std::uint64_t key = side_key(a, b);
    if (const auto it = middle_of.find(key); it != middle_of.end()) return it->second;
    const auto given = s.given_mid_sides.find(side);
    const Vec2 at =
        given != s.given_mid_sides.end() ? given->second : 0.5 * (s.mesh.nodes[a] + s.mesh.nodes[b]);
    const int n = s.mesh.node_count();
    s.mesh.nodes.push_back(at), s.grid.nodes.push_back(at);
    s.grid.node_ij.push_back({0, 0}), s.grid.placed.push_back(0);  // no card placed it
    middle_of.emplace(key, n), sides.push_back({a, b, n});
    return n;
  };
  Mesh<8>& q = s.quadratic;
  q          = {};
  q.cells.resize(s.mesh.cells.size());
  q.triangles.resize(s.mesh.triangles.size());
  q.cell_tags = s.mesh.cell_tags, q.triangle_tags = s.mesh.triangle_tags;
  for (GridCell& c : s.grid.cells) {
    for (int k = 0; k < c.corners; ++k) c.mid[k] = middle(c.node[k], c.node[(k + 1) % c.corners]);
    const auto g = static_cast<std::size_t>(c.group_index);
    if (c.corners == 4)
      q.cells[g] = {c.node[0], c.node[1], c.node[2], c.node[3], c.mid[0], c.mid[1], c.mid[2], c.mid[3]};
    else
      q.triangles[g] = {c.node[0], c.node[1], c.node[2], c.mid[0], c.mid[1], c.mid[2]};
  }
  q.nodes = s.mesh.nodes;
  s.given_mid_sides.clear();

  // Conditions: after every corner's; a middle node's never overlap (one per component at most).
  const std::vector<std::array<int, 3>> in_force = detail::conditions_in_force(s, corners);
  std::vector<std::vector<int>> by_node(static_cast<std::size_t>(corners));
  for (std::size_t k = 0; k < s.conditions.size(); ++k)
    by_node[static_cast<std::size_t>(s.conditions[k].node)].push_back(static_cast<int>(k));
  std::vector<std::pair<NodalCondition, detail::MiddleValue>> made;
  for (const auto& [a, b, m] : sides) detail::side_conditions(s, in_force, by_node, a, b, m, made);
  const bool cards = !s.condition_card.empty(), amplitudes = !s.condition_amplitude.empty();
  for (const auto& [c, m] : made) {
    s.conditions.push_back(c);
    if (cards) s.condition_card.push_back(m.card);
    if (amplitudes) s.condition_amplitude.push_back(m.amplitude);
  }

  // Temperatures: the field at the node, or the side's mean.
  if (s.temperature.size() > 0) {
    VecX t(s.mesh.node_count());
    t.head(corners) = s.temperature;
    for (const auto& [a, b, m] : sides) t(m) = 0.5 * (s.temperature(a) + s.temperature(b));
    if (!d.temperature_points.empty())
      t = nodal_temperatures(s.mesh, d.temperature_points, d.temperature_where);
    s.temperature = std::move(t);
  }

  // SAAC3X's faces.
  StrainRateTest& x = s.strain_rate_test;
  for (std::vector<int>* face : {&x.bottom, &x.top}) {
    std::vector<char> on(static_cast<std::size_t>(corners), 0);
    for (const int n : *face) on[static_cast<std::size_t>(n)] = 1;
    for (const auto& [a, b, m] : sides)
      if (on[static_cast<std::size_t>(a)] && on[static_cast<std::size_t>(b)]) face->push_back(m);
  }
}

/// The last step of reading a model's scene: quadratic cells when the model asks for them (element = quad8)
/// or its mesh file is of order 2 (element auto then means quad8; any other element is an InputError).
inline void quadratic_cells(const ModelDescription& d, Scene& s) {
  const ElementChoice element = d.options.element;
  const bool order2           = !s.given_mid_sides.empty();
  if (order2 && element != ElementChoice::automatic && element != ElementChoice::quad8)
    throw InputError(
        "element = " + std::string(name_of(element)) +
        ": the mesh is of order 2 (its cells have middle nodes), which element = quad8 runs; set "
        "element = quad8 (or leave it auto), or mesh with Mesh.ElementOrder = 1");
  if (order2 || element == ElementChoice::quad8) make_quadratic(d, s);
}

}  // namespace gapfe

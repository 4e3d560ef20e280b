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
//     linear interpolation, what 4-corner cells saw), with the later of the two conditions' card (its
//     reactions) and amplitude; a side held node by node, one card a node, is held along its length too.
//     A component a later card frees at one end (a force, or another card's free component) is free in the
//     middle. Forces stay on the nodes they name: a nodal force is a ring load there, not a load spread
//     along a side;
//   * the temperature: the field's points evaluated at the node, or the mean of the side's ends;
//   * SAAC3X's faces: a side with both ends on a face has its middle on it.
// Edge loads name their side by its corners, as before. Gap elements and contact are refused: a gap pair
// joins two nodes, which a quadratic side's middle node does not fit (core/combinations.hpp).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "gapfe/core/error.hpp"
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

/// The middle node `mid` of side (a, b) gets component k where the conditions in force at both ends prescribe
/// it: the mean of their values, with the later condition's card and amplitude (the same condition's, for a
/// side inside one card's nodes). One condition per card, appended to `made` with the corner condition whose
/// card and amplitude it takes.
inline void side_conditions(const Scene& s, const std::vector<std::array<int, 3>>& in_force, int a, int b,
                            int mid, std::vector<std::pair<NodalCondition, int>>& made) {
  const std::size_t first = made.size();
  for (int comp = 0; comp < 3; ++comp) {
    const int ka = in_force[static_cast<std::size_t>(a)][comp],
              kb = in_force[static_cast<std::size_t>(b)][comp];
    if (ka < 0 || kb < 0 || !s.conditions[ka].prescribed(comp) || !s.conditions[kb].prescribed(comp))
      continue;
    const int from    = std::max(ka, kb);
    const auto card   = [&](int k) { return s.condition_card.empty() ? 0 : s.condition_card[k]; };
    const double mean = 0.5 * (s.conditions[ka].value[comp] + s.conditions[kb].value[comp]);
    auto it           = made.begin() + static_cast<std::ptrdiff_t>(first);
    while (it != made.end() && card(it->second) != card(from)) ++it;
    if (it == made.end()) it = made.insert(it, {NodalCondition{mid, 0, {}, 0}, from});
    it->first.code |= 1 << comp, it->first.sets |= 1 << comp, it->first.value[comp] = mean;
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
    const std::uint64_t key =
        (static_cast<std::uint64_t>(side[0]) << 32) | static_cast<std::uint32_t>(side[1]);
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
  std::vector<std::pair<NodalCondition, int>> made;  // (condition, the corner condition whose card it takes)
  for (const auto& [a, b, m] : sides) detail::side_conditions(s, in_force, a, b, m, made);
  const bool cards = !s.condition_card.empty(), amplitudes = !s.condition_amplitude.empty();
  for (const auto& [c, from] : made) {
    s.conditions.push_back(c);
    if (cards) s.condition_card.push_back(s.condition_card[static_cast<std::size_t>(from)]);
    if (amplitudes) s.condition_amplitude.push_back(s.condition_amplitude[static_cast<std::size_t>(from)]);
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

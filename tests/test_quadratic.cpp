// Quadratic cells for a scene (input/scene_quadratic.hpp): the middle nodes a deck's grid and a Gmsh mesh
// get, what the conditions give them, and the refusals. Their answers through the command, against closed
// forms: tests/check_quadratic.py.
#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <doctest/doctest.h>

#include "gapfe/input/deck_reader.hpp"
#include "gapfe/input/deck_scene.hpp"
#include "gapfe/input/gmsh_mesh.hpp"
#include "gapfe/input/input_file.hpp"
#ifdef GAPFE_HAS_SCENE
#include "gapfe/input/scene_file.hpp"
#endif

using namespace gapfe;

namespace {

const std::filesystem::path kSource = GAPFE_SOURCE_DIR;

/// examples/decks/thick_tube.deck (9 x 3 grid, 100 <= r <= 200, 0 <= z <= 10; bc1 holds u_z on J = 1, bc2 on
/// J = 3) with a third card: u_r = 0.001 on the column I = 9, which meets bc1 at the corner (9, 1).
std::string tube_with_outer_card() {
  std::string text   = read_input((kSource / "examples/decks/thick_tube.deck").string(), "deck");
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
  };
  replace("    9    3    4    2    1", "    9    3    4    3    1");
  replace("    1    9    3    3         2       0.0       0.0       0.0\n",
          "    1    9    3    3         2       0.0       0.0       0.0\n"
          "    9    9    1    3         1     0.001       0.0       0.0\n");
  return text;
}

/// The conditions of node n: (card, code, value) in order.
std::vector<std::tuple<int, int, std::array<double, 3>>> conditions_of(const Scene& s, int n) {
  std::vector<std::tuple<int, int, std::array<double, 3>>> out;
  for (std::size_t k = 0; k < s.conditions.size(); ++k)
    if (s.conditions[k].node == n)
      out.emplace_back(s.condition_card[k], s.conditions[k].code, s.conditions[k].value);
  return out;
}

}  // namespace

TEST_CASE(
    "[quadratic] element = quad8 on a deck: a middle node per side, after the corners, with its cards") {
  const Deck deck = read_deck(tube_with_outer_card(), {{"element", "quad8"}});
  const Scene s   = build_scene(deck);
  REQUIRE(s.is_quadratic());
  // 8 x 2 cells: 27 corners, 8 x 3 + 9 x 2 = 42 sides.
  CHECK(s.mesh.node_count() == 27 + 42);
  CHECK(s.grid.node_count() == 27 + 42);
  CHECK(s.quadratic.cells.size() == 16);
  CHECK(s.quadratic.triangles.empty());
  CHECK(s.quadratic.nodes.size() == s.mesh.nodes.size());
  std::map<std::pair<int, int>, int> middle;  // (corner, corner) -> the middle node, from the cells
  for (const auto& c : s.quadratic.cells)
    for (int k = 0; k < 4; ++k) {
      const int a = c[k], b = c[(k + 1) % 4], m = c[4 + k];
      CHECK(a < 27);
      CHECK(m >= 27);
      CHECK((s.mesh.nodes[m] - 0.5 * (s.mesh.nodes[a] + s.mesh.nodes[b])).norm() < 1e-12);
      CHECK(s.grid.node_ij[m] == std::array<int, 2>{0, 0});
      middle[{std::min(a, b), std::max(a, b)}] = m;
    }
  CHECK(middle.size() == 42);
  const auto at = [&](int i1, int j1, int i2, int j2) {  // the middle node of grid side (I1, J1)-(I2, J2)
    const int a = s.grid.node(i1, j1), b = s.grid.node(i2, j2);
    return middle.at({std::min(a, b), std::max(a, b)});
  };
  using Conditions = std::vector<std::tuple<int, int, std::array<double, 3>>>;
  // Along J = 1: bc1's u_z at both ends; the side ending at (9, 1) has bc3 at that end only, so no u_r.
  CHECK(conditions_of(s, at(1, 1, 2, 1)) == Conditions{{0, 2, {0, 0, 0}}});
  CHECK(conditions_of(s, at(8, 1, 9, 1)) == Conditions{{0, 2, {0, 0, 0}}});
  // Along I = 9: bc3's u_r = 0.001 at both ends; the lower side's end (9, 1) is bc1's too, the other not.
  CHECK(conditions_of(s, at(9, 1, 9, 2)) == Conditions{{2, 1, {0.001, 0, 0}}});
  CHECK(conditions_of(s, at(9, 2, 9, 3)) == Conditions{{2, 1, {0.001, 0, 0}}});
  CHECK(conditions_of(s, at(9, 3, 8, 3)) == Conditions{{1, 2, {0, 0, 0}}});
  // Inside and along the bore: none.
  CHECK(conditions_of(s, at(1, 1, 1, 2)).empty());
  CHECK(conditions_of(s, at(4, 2, 5, 2)).empty());
  CHECK(conditions_of(s, at(4, 1, 4, 2)).empty());
}

TEST_CASE(
    "[quadratic] Gmsh order 2: the file's middle nodes, 9-node quadrangles as 8-node, 6-node triangles") {
  const auto read = [](const std::string& name) {
    return read_gmsh(read_input((kSource / "tests/data/scenes" / name).string(), "mesh"));
  };
  GmshMesh quad9 = read("lame_quad9_h25.msh"), quad8 = read("lame_quad8_h25.msh");
  REQUIRE(quad9.cells.size() == quad8.cells.size());
  for (std::size_t e = 0; e < quad9.cells.size(); ++e) {
    CHECK(quad9.cells[e].type == 16);
    CHECK(quad9.cells[e].node_count == 8);
    for (int k = 0; k < 8; ++k)
      CHECK((quad9.nodes[quad9.cells[e].nodes[k]] - quad8.nodes[quad8.cells[e].nodes[k]]).norm() < 1e-12);
  }
  // take_mid_sides: every side of every cell, its middle node half-way along it (the tube's sides are
  // straight); the cells reduced to their corners.
  const auto sides = take_mid_sides(quad8);
  CHECK(sides.size() == 4 * quad8.cells.size());
  for (const auto& [a, b, m] : sides)
    CHECK((quad8.nodes[m] - 0.5 * (quad8.nodes[a] + quad8.nodes[b])).norm() < 1e-9);
  for (const GmshElement& c : quad8.cells) CHECK(c.node_count == 4);
  for (const GmshElement& e : quad8.edges) CHECK(e.node_count == 2);
  // Triangles of 6 nodes as a Quad8 mesh's 3-corner cells.
  const GmshFeMesh<8> tri6 = gmsh_fe_mesh<8>(read("lame_tri6_h25.msh"));
  CHECK(tri6.mesh.cells.empty());
  CHECK(tri6.mesh.triangles.size() == 22);
}

TEST_CASE("[quadratic] refusals: quadratic cells with gap elements; a 4-corner element on an order-2 mesh") {
  const std::string gaps = read_input((kSource / "examples/decks/two_tubes.deck").string(), "deck");
  CHECK_THROWS_WITH_AS(build_scene(read_deck(gaps, {{"element", "quad8"}})),
                       doctest::Contains("gap elements"), InputError);
#ifdef GAPFE_HAS_SCENE
  const std::string scene = R"(title = "order 2"
[mesh]
file = "lame_quad8_h25.msh"
[options]
element = "quad4"
[materials.steel]
E = 200000.0
nu = 0.3
[[boundary]]
groups = ["bottom"]
fix = ["z"]
)";
  const auto mesh         = [](const std::string& name) {
    return read_input((kSource / "tests/data/scenes" / name).string(), "mesh");
  };
  CHECK_THROWS_WITH_AS(read_scene(scene, mesh), doctest::Contains("order 2"), InputError);
  const SceneModel order2 = read_scene(scene, mesh, {{"element", "auto"}});
  CHECK(order2.scene.is_quadratic());
#endif
}

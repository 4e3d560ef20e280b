// Quadratic cells for a scene (input/scene_quadratic.hpp): the middle nodes a deck's grid and a Gmsh mesh
// get, what the conditions give them, and the refusals. Their answers through the command, against closed
// forms: tests/check_quadratic.py.
#include <algorithm>
#include <array>
#include <cmath>
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
std::string tube_with_outer_card(int code = 1) {
  std::string text   = read_input((kSource / "examples/decks/thick_tube.deck").string(), "deck");
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
  };
  replace("    9    3    4    2    1", "    9    3    4    3    1");
  replace("    1    9    3    3         2       0.0       0.0       0.0\n",
          "    1    9    3    3         2       0.0       0.0       0.0\n"
          "    9    9    1    3         " +
              std::to_string(code) + "     0.001       0.0       0.0\n");
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
  // Along J = 1: bc1's u_z at both ends. At (9, 1) bc3, the later card, sets every component (a deck card
  // does): u_r = 0.001 and u_z free, so the side ending there is free in z and, held in r at one end only,
  // free in r.
  CHECK(conditions_of(s, at(1, 1, 2, 1)) == Conditions{{0, 2, {0, 0, 0}}});
  CHECK(conditions_of(s, at(7, 1, 8, 1)) == Conditions{{0, 2, {0, 0, 0}}});
  CHECK(conditions_of(s, at(8, 1, 9, 1)).empty());
  CHECK(conditions_of(s, at(9, 3, 8, 3)).empty());
  // Along I = 9: bc3's u_r = 0.001 at both ends.
  CHECK(conditions_of(s, at(9, 1, 9, 2)) == Conditions{{2, 1, {0.001, 0, 0}}});
  CHECK(conditions_of(s, at(9, 2, 9, 3)) == Conditions{{2, 1, {0.001, 0, 0}}});
  // bc3 holding z as well (code 3): the side (8, 1)-(9, 1) is held in z, its reaction bc1's, whose nodes both
  // ends are (bc3 overrides bc1 only at the corner).
  const Scene held = build_scene(read_deck(tube_with_outer_card(3), {{"element", "quad8"}}));
  CHECK(conditions_of(held, middle.at({held.grid.node(8, 1), held.grid.node(9, 1)})) ==
        Conditions{{0, 2, {0, 0, 0}}});
  // Inside and along the bore: none.
  CHECK(conditions_of(s, at(1, 1, 1, 2)).empty());
  CHECK(conditions_of(s, at(4, 2, 5, 2)).empty());
  CHECK(conditions_of(s, at(4, 1, 4, 2)).empty());
}

TEST_CASE("[quadratic] a side held node by node, one card a node, is held along its length") {
  // bc1 of the thick tube (u_z = 0 on J = 1) as nine cards, one per grid point.
  std::string text      = tube_with_outer_card();
  const std::string row = "    1    9    1    1         2       0.0       0.0       0.0\n";
  std::string cards;
  for (int i = 1; i <= 9; ++i)
    cards += "    " + std::to_string(i) + "    " + std::to_string(i) +
             "    1    1         2       0.0       0.0       0.0\n";
  text.replace(text.find(row), row.size(), cards);
  text.replace(text.find("    9    3    4    3    1"), 25, "    9    3    4   11    1");
  const Scene s = build_scene(read_deck(text, {{"element", "quad8"}}));
  REQUIRE(s.is_quadratic());
  for (int i = 1; i < 8; ++i) {  // the side (i, 1)-(i + 1, 1): the later card is point i + 1's, number i
    const int a = s.grid.node(i, 1), b = s.grid.node(i + 1, 1);
    int middle = -1;
    for (const auto& c : s.quadratic.cells)
      for (int k = 0; k < 4; ++k)
        if (std::minmax(c[k], c[(k + 1) % 4]) == std::minmax(a, b)) middle = c[4 + k];
    REQUIRE(middle >= 0);
    using Conditions = std::vector<std::tuple<int, int, std::array<double, 3>>>;
    CHECK(conditions_of(s, middle) == Conditions{{i, 2, {0, 0, 0}}});
  }
}

#ifdef GAPFE_HAS_SCENE
TEST_CASE("[quadratic] a side between two load histories: the moving end's, and refused when both move") {
  // lame_quad8_h25.msh (order 2): "top" (z = 50) moved along z under a history, "outer" (r = 200) held in z
  // by a later table without one, so at their corner (200, 50) "outer" is in force.
  const auto mesh = [](const std::string& name) {
    return read_input((kSource / "tests/data/scenes" / name).string(), "mesh");
  };
  const auto scene = [](const std::string& outer) {
    return "title = \"histories\"\n[mesh]\nfile = \"lame_quad8_h25.msh\"\n[steps]\ncount = 2\n"
           "[materials.steel]\nE = 200000.0\nnu = 0.3\n[[boundary]]\ngroups = \"bottom\"\nfix = [\"z\"]\n"
           "[[boundary]]\ngroups = \"top\"\ndisplacement = {z = 0.1}\namplitude = [[1, 0.25], [2, 1.0]]\n"
           "[[boundary]]\ngroups = \"outer\"\n" +
           outer;
  };
  const SceneModel m = read_scene(scene("fix = [\"z\"]\n"), mesh);
  const Scene& s     = m.scene;
  REQUIRE(s.is_quadratic());
  // The middle node of the top's last side: z = 50, the greatest r below 200.
  int middle = -1;
  for (int n = s.quadratic.node_count() - 1; n >= 0; --n)
    if (std::abs(s.mesh.nodes[n](1) - 50) < 1e-9 && s.mesh.nodes[n](0) < 200 - 1e-9 &&
        (middle < 0 || s.mesh.nodes[n](0) > s.mesh.nodes[middle](0)))
      middle = n;
  bool is_middle = false;  // a cell's middle node, not a corner
  for (const auto& c : s.quadratic.cells)
    for (int k = 4; k < 8; ++k) is_middle = is_middle || c[k] == middle;
  REQUIRE(is_middle);
  int found = 0, top_history = -1;
  for (std::size_t k = 0; k < s.conditions.size(); ++k)
    if (s.conditions[k].node != middle && s.condition_amplitude[k] >= 0)
      top_history = s.condition_amplitude[k];
  for (std::size_t k = 0; k < s.conditions.size(); ++k)
    if (s.conditions[k].node == middle) {
      ++found;
      CHECK(s.conditions[k].code == 2);
      CHECK(s.conditions[k].value[1] == doctest::Approx(0.05));  // (0.1 + 0) / 2, under the top's history
      CHECK(s.condition_amplitude[k] == top_history);
    }
  CHECK(found == 1);
  CHECK(top_history >= 0);
  CHECK_THROWS_WITH_AS(read_scene(scene("displacement = {z = 0.2}\n"), mesh),
                       doctest::Contains("two different load histories"), InputError);
}
#endif

TEST_CASE("[quadratic] clockwise order-2 cells are turned with their middle nodes") {
  // A 6-node triangle and an 8-node quadrangle, both clockwise, in MSH 2.2.
  const GmshMesh g = read_gmsh(
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n14\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0.5 0 0\n5 0.5 0.5 0\n"
      "6 0 0.5 0\n7 2 0 0\n8 2 1 0\n9 3 1 0\n10 3 0 0\n11 2 0.5 0\n12 2.5 1 0\n13 3 0.5 0\n14 2.5 0 0\n"
      "$EndNodes\n$Elements\n2\n1 9 2 1 1 1 3 2 6 5 4\n2 16 2 1 1 7 8 9 10 11 12 13 14\n$EndElements\n");
  REQUIRE(g.cells.size() == 2);
  CHECK(g.flipped == 2);
  for (const GmshElement& c : g.cells) {
    const int corners = c.type == 9 ? 3 : 4;
    double area       = 0;
    for (int k = 0; k < corners; ++k) {
      const Vec2 &p = g.nodes[c.nodes[k]], &q = g.nodes[c.nodes[(k + 1) % corners]];
      area += p(0) * q(1) - q(0) * p(1);
      CHECK((g.nodes[c.nodes[corners + k]] - 0.5 * (p + q)).norm() < 1e-15);
    }
    CHECK(area > 0);
  }
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

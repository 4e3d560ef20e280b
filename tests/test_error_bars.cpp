// What `gapfe run --estimate` is made of: Richardson's extrapolation with the observed order
// (post/extrapolation.hpp) on sequences whose limit is known, and a deck's grid refined from its own cards
// (input/deck_refine.hpp), which must describe the same model: the same points, loads and supports.
// The error bars through the command, against closed forms: tests/check_error_bars.py.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include "gapfe/app/accuracy.hpp"
#include "gapfe/input/deck.hpp"
#include "gapfe/input/deck_refine.hpp"
#include "gapfe/input/gmsh_refine.hpp"
#include "gapfe/input/input_file.hpp"
#include "gapfe/post/extrapolation.hpp"

#include "deck_support.hpp"

using namespace gapfe;
namespace fs = std::filesystem;

namespace {

/// q(h) on h = 1, 1/2, 1/4 (as many as `levels`).
template <class Q>
std::vector<double> sequence(const Q& q, int levels) {
  std::vector<double> v;
  for (int k = 0; k < levels; ++k) v.push_back(q(std::exp2(-k)));
  return v;
}

}  // namespace

TEST_CASE(
    "[error bars] Richardson's extrapolation: the observed order, the limit and the first value's error") {
  // q = 3 + 0.2 h^2 - 0.05 h^3: the observed order near 2, the limit near 3.
  const auto smooth = [](double h) { return 3 + 0.2 * h * h - 0.05 * h * h * h; };
  const ErrorBar b  = error_bar(sequence(smooth, 3), 1.0);
  CHECK(b.status == ErrorBar::Status::observed);
  CHECK(b.order == doctest::Approx(2).epsilon(0.15));
  CHECK(b.limit == doctest::Approx(3).epsilon(2e-3));
  const double truth = smooth(1) - 3;  // the first value's true error
  CHECK(b.error / truth >= 0.9);
  CHECK(b.error / truth <= 1.1);
  // Exactly first order: its limit exactly.
  const ErrorBar linear = error_bar(sequence([](double h) { return 1 - 2 * h; }, 3), 2.0);
  CHECK(linear.order == doctest::Approx(1).epsilon(1e-12));
  CHECK(linear.limit == doctest::Approx(1).epsilon(1e-12));
  CHECK(linear.error == doctest::Approx(2).epsilon(1e-12));
  // Two values: the order assumed.
  const ErrorBar two = error_bar(sequence([](double h) { return 5 + h * h; }, 2), 2.0);
  CHECK(two.status == ErrorBar::Status::assumed);
  CHECK(two.limit == doctest::Approx(5).epsilon(1e-12));
  CHECK(two.error == doctest::Approx(1).epsilon(1e-12));
}

TEST_CASE("[error bars] values that do not converge get no error bar") {
  // A stress at a re-entrant corner of 270 degrees grows as h^(lambda - 1), lambda = 0.5445.
  const ErrorBar corner = error_bar(sequence([](double h) { return 100 * std::pow(h, -0.4555); }, 3), 1.0);
  CHECK(corner.status == ErrorBar::Status::not_converging);
  CHECK_FALSE(corner.converges());
  CHECK(std::isnan(corner.error));
  // A displacement under a ring load grows as log(1 / h): differences that do not shrink.
  CHECK_FALSE(error_bar(sequence([](double h) { return std::log(1 / h); }, 3), 2.0).converges());
  // Differences changing sign: no order to extrapolate with.
  CHECK_FALSE(error_bar(std::vector<double>{1.0, 1.1, 1.05}, 2.0).converges());
  // Shrinking slower than order 0.5 (by 1.2 a level): too slow to extrapolate.
  CHECK_FALSE(error_bar(std::vector<double>{1.0, 2.0, 2.0 + 1 / 1.2}, 2.0).converges());
  // Not a number on some mesh.
  CHECK_FALSE(error_bar(std::vector<double>{1.0, std::nan(""), 1.0}, 2.0).converges());
}

TEST_CASE("[error bars] values that agree to the solvers' noise, or exact from the second mesh on") {
  const ErrorBar same = error_bar(std::vector<double>{2.5, 2.5 * (1 + 3e-8), 2.5 * (1 - 2e-8)}, 2.0);
  CHECK(same.status == ErrorBar::Status::exact);
  CHECK(same.error == 0.0);
  const ErrorBar settled = error_bar(std::vector<double>{2.0, 2.5, 2.5}, 2.0);
  CHECK(settled.converges());
  CHECK(settled.error == doctest::Approx(0.5).epsilon(1e-12));
}

namespace {

/// The total ring force of a deck's pressure cards on a scene's nodes: value x edge length x 2 pi r_mid.
double pressure_force(const Deck& d, const Scene& s) {
  double total = 0;
  for (const EdgeCard& c : d.program.blocks.front().pressure) {
    const Vec2 m = s.mesh.nodes[static_cast<std::size_t>(c.node_m - 1)],
               n = s.mesh.nodes[static_cast<std::size_t>(c.node_n - 1)];
    total += c.value * (m - n).norm() * std::numbers::pi * (m(0) + n(0));
  }
  return total;
}

}  // namespace

TEST_CASE("[error bars] a deck's grid refined from its cards: the same points, loads and supports") {
  const Deck d       = read_deck(gapfe::test::lame_tube_deck(5, 3, false));
  const Scene coarse = build_scene(d);
  for (const int times : {1, 2}) {
    const RefinedDeck f = refine_deck(d, coarse, times);
    const IJGrid& g     = f.scene.grid;
    const int k         = 1 << times;
    CHECK(g.max_i == 4 * k + 1);
    CHECK(g.max_j == 2 * k + 1);
    CHECK(f.scene.mesh.cells.size() == coarse.mesh.cells.size() * static_cast<std::size_t>(k * k));
    // Every point of the deck's grid is a point of the finer one, where it was.
    double moved = 0;
    for (int n = 0; n < coarse.grid.node_count(); ++n) {
      const auto ij = coarse.grid.node_ij[static_cast<std::size_t>(n)];
      const int fine =
          g.node(f.index.i[static_cast<std::size_t>(ij[0])], f.index.j[static_cast<std::size_t>(ij[1])]);
      REQUIRE(fine >= 0);
      moved = std::max(moved, (g.nodes[static_cast<std::size_t>(fine)] - coarse.grid.nodes[n]).norm());
    }
    CHECK(moved < 1e-9);
    // The bore's pressure: each card's edge split in k, the same total force.
    CHECK(f.deck.program.blocks.front().pressure.size() == d.program.blocks.front().pressure.size() * k);
    CHECK(pressure_force(f.deck, f.scene) == doctest::Approx(pressure_force(d, coarse)).epsilon(1e-12));
    // Both ends held along z at every point of the finer grid's ends.
    CHECK(f.scene.conditions.size() == static_cast<std::size_t>(2 * g.max_i));
  }
}

TEST_CASE("[error bars] a refined deck's ring loads stay at the deck's points, its arcs on their circles") {
  // The quarter annulus 100 < rho < 200 between 10 and 80 degrees (arcs about the origin, seed type 4), held
  // along z on its lower edge, with ring loads along r on its outer arc's other points.
  const double deg = std::numbers::pi / 180;
  const auto at    = [&](double rho, double angle) {
    char text[16];
    std::snprintf(text, sizeof text, "%.3f", rho * std::cos(angle * deg));
    std::string r = text;
    std::snprintf(text, sizeof text, "%.3f", rho * std::sin(angle * deg));
    return std::pair<std::string, std::string>{r, text};
  };
  const auto [r1, z1] = at(100, 10);
  const auto [r2, z2] = at(200, 10);
  const auto [r3, z3] = at(200, 80);
  const auto [r4, z4] = at(100, 80);
  using gapfe::test::Card;
  using gapfe::test::segment;
  std::string text = "$ format = elastic\nQUARTER ANNULUS\n";
  text += Card().i(1, 5, 1).i(11, 15, 1).i(41, 45, 1).str() + "\n";
  text += Card().i(1, 5, 5).i(6, 10, 7).i(11, 15, 4).i(16, 20, 2).i(21, 25, 1).str() + "\n";
  text += segment(1, 1, r1.c_str(), z1.c_str(), 5, 1, r2.c_str(), z2.c_str()) + "\n";
  text += segment(5, 1, r2.c_str(), z2.c_str(), 5, 7, r3.c_str(), z3.c_str(), 4) + "\n";  // centre: blank, 0
  text += segment(5, 7, r3.c_str(), z3.c_str(), 1, 7, r4.c_str(), z4.c_str()) + "\n";
  text += segment(1, 1, r1.c_str(), z1.c_str(), 1, 7, r4.c_str(), z4.c_str(), 4) + "\n";
  text += Card().i(1, 5, 1).i(6, 10, 5).i(11, 15, 1).i(16, 20, 1).i(21, 30, 2).str() + "\n";
  text +=
      Card().i(1, 5, 5).i(6, 10, 5).i(11, 15, 2).i(16, 20, 7).i(21, 30, 0).f(31, 40, "1000.").str() + "\n";
  text += Card().i(1, 5, 1).i(6, 10, 1).i(11, 15, 5).i(16, 20, 1).i(21, 25, 7).str() + "\n";
  text += Card().i(1, 5, 1).i(6, 10, 1).str() + "\n" + gapfe::test::steel_first_property_card() + "\n";
  text += Card().f(1, 10, "76923.0769").f(11, 20, "76923.0769").f(21, 30, "76923.0769").str() + "\n";
  const Deck d          = read_deck(text);
  const Scene coarse    = build_scene(d);
  const auto ring_loads = [](const Scene& s) {
    double total = 0;
    int loaded   = 0;
    for (const NodalCondition& c : s.conditions)
      if (c.value[0] != 0) total += c.value[0], ++loaded;
    return std::pair<double, int>{total, loaded};
  };
  const RefinedDeck f = refine_deck(d, coarse, 1);
  CHECK(ring_loads(f.scene).first == doctest::Approx(ring_loads(coarse).first).epsilon(1e-15));
  CHECK(ring_loads(f.scene).second == ring_loads(coarse).second);  // 6 points, not the 11 of the finer arc
  double off_circle = 0;  // the finer grid's points on either arc, from its circle
  for (int j = 1; j <= f.scene.grid.max_j; ++j)
    for (const auto& [i, rho] : {std::pair<int, double>{1, 100.0}, {9, 200.0}}) {
      const int n = f.scene.grid.node(i, j);
      REQUIRE(n >= 0);
      off_circle =
          std::max(off_circle, std::abs(f.scene.grid.nodes[static_cast<std::size_t>(n)].norm() - rho));
    }
  // The cards' coordinates have three decimals, so the arcs' ends are off their circles by up to 7e-4; a
  // point put on the chord between two of the deck's points instead would be 200 (1 - cos(70 / 12 degrees))
  // = 1.0 off.
  CHECK(off_circle < 2e-3);
}

TEST_CASE("[error bars] a gap layer stays one cell thick: its gap elements are split along it, not across") {
  // examples/decks/two_tubes.deck: tubes on I 1-21 and 22-42, the gap elements between I = 21 and 22
  // (IJDIR = 1), 2 rows of cells.
  const fs::path deck = fs::path(GAPFE_SOURCE_DIR) / "examples" / "decks" / "two_tubes.deck";
  const Deck d        = read_deck(read_input(deck.string(), "deck"));
  const Scene coarse  = build_scene(d);
  const RefinedDeck f = refine_deck(d, coarse, 2);
  const int gap_line  = f.index.i[21];
  CHECK(f.index.i[22] == gap_line + 1);  // the layer: one cell
  CHECK(gap_line == 1 + 20 * 4);         // the tubes: four times the cells
  CHECK(f.index.i[42] == gap_line + 1 + 20 * 4);
  int gap_cells = 0;
  for (std::size_t e = 0; e < f.scene.grid.cells.size(); ++e)
    if (f.scene.material_id[e] == 2) {
      ++gap_cells;
      CHECK(f.scene.grid.cells[e].i == gap_line);
    }
  CHECK(gap_cells == 2 * 4);  // each split in four along z
  REQUIRE_FALSE(f.scene.gaps.pairs.empty());
  for (const GapPair& p : f.scene.gaps.pairs) {  // across the layer, from one tube to the other
    CHECK(f.scene.grid.node_ij[static_cast<std::size_t>(p.node_a)][0] == gap_line);
    CHECK(f.scene.grid.node_ij[static_cast<std::size_t>(p.node_b)][0] == gap_line + 1);
    CHECK(p.initial_gap == doctest::Approx(0.02).epsilon(1e-9));
  }
}

namespace {

/// A saac deck of one row of 10 x 10 cells between r = 10 and 10 ni, 0 < z < 10 rows, a column of vertical
/// line cards at every I (each placing its column's points), a bottom and a top line across the whole row,
/// held along z at the bottom, material 2 (gap elements closing along I, IJDIR 1) in the columns [gap_from,
/// gap_to].
std::string column_deck(int ni, int rows, int gap_from, int gap_to) {
  using gapfe::test::Card;
  const auto number = [](double v) { return std::to_string(static_cast<int>(v)) + "."; };
  std::string t     = "COLUMNS\n" + Card().i(1, 5, 1).i(11, 15, 2).i(41, 45, 1).str() + "\n";
  t += Card().i(1, 5, ni).i(6, 10, rows + 1).i(11, 15, ni + 2).i(16, 20, 1).i(21, 25, 3).str() + "\n";
  const auto line = [&](int i1, int j1, int i2, int j2) {
    return gapfe::test::segment(i1, j1, number(10.0 * i1).c_str(), number(10.0 * (j1 - 1)).c_str(), i2, j2,
                                number(10.0 * i2).c_str(), number(10.0 * (j2 - 1)).c_str()) +
           "\n";
  };
  t += line(1, 1, ni, 1) + line(1, rows + 1, ni, rows + 1);
  for (int i = 1; i <= ni; ++i) t += line(i, 1, i, rows + 1);
  t += Card().i(1, 5, 1).i(6, 10, ni).i(11, 15, 1).i(16, 20, 1).i(21, 30, 2).str() + "\n";
  t += Card().i(1, 5, 1).i(6, 10, 1).i(11, 15, gap_from).i(16, 20, 1).i(21, 25, rows + 1).str() + "\n";
  t += Card()
           .i(1, 5, 2)
           .i(6, 10, gap_from)
           .i(11, 15, gap_to)
           .i(16, 20, 1)
           .i(21, 25, rows + 1)
           .i(56, 60, 1)
           .str() +
       "\n";
  t += Card().i(1, 5, 1).i(6, 10, gap_to).i(11, 15, ni).i(16, 20, 1).i(21, 25, rows + 1).str() + "\n";
  for (const char* e : {"200000.", "0.0002"}) {
    t += Card().i(1, 5, e[0] == '2' ? 1 : 2).i(6, 10, 1).str() + "\n";
    t += Card().f(1, 10, "0.").f(11, 20, e).f(21, 30, e).f(31, 40, e).str() + "\n";
    t += Card()
             .f(1, 10, e[0] == '2' ? "76923." : "0.0001")
             .f(11, 20, e[0] == '2' ? "76923." : "0.0001")
             .f(21, 30, e[0] == '2' ? "76923." : "0.0001")
             .str() +
         "\n\n";
  }
  return t;
}

}  // namespace

TEST_CASE("[error bars] a line across a gap layer is split there: its points stay where the deck put them") {
  // Columns of 10 from r = 10 to 50; the gap elements between r = 30 and 40 (one cell, as thick as the
  // others); the bottom and top lines run across all of it, the gap layer too.
  const Deck d       = read_deck(column_deck(5, 1, 3, 4));
  const Scene coarse = build_scene(d);
  REQUIRE_FALSE(coarse.gaps.pairs.empty());
  const RefinedDeck f = refine_deck(d, coarse, 2);
  CHECK(f.index.i[4] == f.index.i[3] + 1);  // the layer: one cell
  const IJGrid& g = f.scene.grid;
  for (const int i : {1, 3, 4, 5}) {  // the deck's points, exactly where they were
    const Vec2 x = g.nodes[static_cast<std::size_t>(g.node(f.index.i[static_cast<std::size_t>(i)], 1))];
    CHECK(x(0) == 10.0 * i);
    CHECK(x(1) == 0.0);
  }
  REQUIRE_FALSE(f.scene.gaps.pairs.empty());
  for (const GapPair& p : f.scene.gaps.pairs) CHECK(p.initial_gap == doctest::Approx(10.0).epsilon(1e-12));
  // A diagonal line across the layer could not keep equal steps in I and J: refused.
  Deck diagonal = d;
  diagonal.segments.push_back(
      {{GridPoint{2, 1, Vec2(20.0, 0.0)}, GridPoint{5, 4, Vec2(50.0, 30.0)}}, SegmentType::line});
  diagonal.segment_refs.push_back(diagonal.segment_refs.back());
  CHECK_THROWS_WITH_AS(refine_deck(diagonal, coarse, 1), doctest::Contains("crosses a gap layer"),
                       InputError);
}

TEST_CASE(
    "[error bars] gap elements in series along their row: their pieces would be soft corners, refused") {
  // Two gap elements side by side along I, in a deck of one row: each closes along I (no gap neighbour along
  // J). On a finer grid each piece has gap neighbours both ways, a corner, soft: another model.
  const Deck d       = read_deck(column_deck(6, 1, 3, 5));
  const Scene coarse = build_scene(d);
  REQUIRE_FALSE(coarse.gaps.pairs.empty());
  CHECK_THROWS_WITH_AS(refine_deck(d, coarse, 1), doctest::Contains("pieces on a finer grid would be soft"),
                       InputError);
}

TEST_CASE("[error bars] finer points no card places, where the deck's had them placed: refused, named") {
  Deck d = read_deck(column_deck(5, 1, 3, 4));
  // Only the bottom and top lines: the finer rows between them have no ends (the deck's one row had them),
  // and the generator finds no cell (with some rows placed, refine_deck names the first element short of
  // points: examples/decks/projectile.deck through the command).
  Deck rows = d;
  rows.segments.resize(2), rows.segment_refs.resize(2);
  const Scene rows_scene = build_scene(rows);
  CHECK_THROWS_WITH_AS(
      refine_deck(rows, rows_scene, 1),
      doctest::Contains("on the finer grid, do the deck's cards place the ends of every row"), InputError);
  // The outer columns back, not the gap's faces: the fill would place the faces' finer points, and move them.
  Deck faces = rows;
  faces.segments.push_back(
      {{GridPoint{1, 1, Vec2(10.0, 0.0)}, GridPoint{1, 2, Vec2(10.0, 10.0)}}, SegmentType::line});
  faces.segments.push_back(
      {{GridPoint{5, 1, Vec2(50.0, 0.0)}, GridPoint{5, 2, Vec2(50.0, 10.0)}}, SegmentType::line});
  faces.segment_refs.resize(4, faces.segment_refs.front());
  const Scene faces_scene = build_scene(faces);
  CHECK_THROWS_WITH_AS(refine_deck(faces, faces_scene, 1), doctest::Contains("gap element 3 (I = 3, J = 1)"),
                       InputError);
}

TEST_CASE("[error bars] what a finer grid could not keep is refused, naming the card or the gap element") {
  const fs::path deck = fs::path(GAPFE_SOURCE_DIR) / "examples" / "decks" / "two_tubes.deck";
  const Deck d        = read_deck(read_input(deck.string(), "deck"));
  const Scene coarse  = build_scene(d);
  // The lower boundary as one arc from the first tube's bore to the second's outside: across the gap layer
  // its points could not stay evenly spaced.
  Deck arc        = d;
  arc.segments[0] = {{GridPoint{1, 1, Vec2(50.0, 0.0)}, GridPoint{42, 1, Vec2(100.0, 0.0)}},
                     SegmentType::arc_centre};
  CHECK_THROWS_WITH_AS(refine_deck(arc, coarse, 1), doctest::Contains("crosses a gap layer"), InputError);
  // The gap's faces without their segment cards (I = 21 and 22): the Laplace fill places their middle points,
  // and would place them elsewhere on a finer grid.
  Deck filled = d;
  filled.segments.erase(filled.segments.begin() + 5, filled.segments.begin() + 7);
  filled.segment_refs.erase(filled.segment_refs.begin() + 5, filled.segment_refs.begin() + 7);
  const Scene filled_scene = build_scene(filled);
  CHECK_THROWS_WITH_AS(refine_deck(filled, filled_scene, 1), doctest::Contains("placed by no segment card"),
                       InputError);
}

// ---- a Gmsh mesh split in four (input/gmsh_refine.hpp)

namespace {

const std::filesystem::path kGmshData = std::filesystem::path(GAPFE_SOURCE_DIR) / "tests" / "data";

gapfe::GmshMesh gmsh_file(const std::filesystem::path& path) {
  return gapfe::read_gmsh(gapfe::read_input(path.string(), "mesh"));
}

/// The area of the mesh's cells (shoelace), and of those in physical group `tag` when >= 0.
double cell_area(const gapfe::GmshMesh& g, int tag = -1) {
  double area = 0;
  for (const gapfe::GmshElement& c : g.cells) {
    if (tag >= 0 && !c.in(tag)) continue;
    for (int k = 0; k < c.node_count; ++k) {
      const gapfe::Vec2 &a = g.nodes[c.nodes[k]], &b = g.nodes[c.nodes[(k + 1) % c.node_count]];
      area += 0.5 * (a(0) * b(1) - b(0) * a(1));
    }
  }
  return area;
}

}  // namespace

TEST_CASE(
    "a Gmsh mesh split in four keeps its area, its nodes and its groups, and its straight sides straight") {
  const gapfe::GmshMesh coarse = gmsh_file(kGmshData / "tube_quad4_v41.msh");
  const gapfe::GmshSplit split = gapfe::split_gmsh(coarse, 1);
  const gapfe::GmshMesh& fine  = split.mesh;
  // Euler on a quadrangle mesh: V' = V + sides + cells
  std::set<std::pair<int, int>> sides;
  for (const auto& c : coarse.cells)
    for (int k = 0; k < c.node_count; ++k) {
      const int a = c.nodes[k], b = c.nodes[(k + 1) % c.node_count];
      sides.insert({std::min(a, b), std::max(a, b)});
    }
  CHECK(fine.cells.size() == 4 * coarse.cells.size());
  CHECK(fine.edges.size() == 2 * coarse.edges.size());
  CHECK(split.coarse_nodes == coarse.nodes.size());
  CHECK(fine.nodes.size() == coarse.nodes.size() + sides.size() + coarse.cells.size());
  CHECK(split.arc_points == 0);  // a rectangle's corners are not an arc
  for (std::size_t n = 0; n < coarse.nodes.size(); ++n) CHECK(fine.nodes[n] == coarse.nodes[n]);
  CHECK(cell_area(fine) == doctest::Approx(cell_area(coarse)).epsilon(1e-13));
  for (const auto& [key, name] : coarse.physical_names)
    if (key.first == 2) CHECK(cell_area(fine, key.second) == doctest::Approx(cell_area(coarse, key.second)));
  for (const auto& c : fine.cells) {  // counterclockwise, every one
    gapfe::GmshMesh one = fine;
    one.cells           = {c};
    CHECK(cell_area(one) > 0);
  }
}

TEST_CASE("a Gmsh mesh split in four puts the new points of its arcs on their circles") {
  for (const char* file : {"sphere_quad.msh", "sphere_tri.msh"}) {
    CAPTURE(file);
    const gapfe::GmshMesh coarse = gmsh_file(kGmshData / "scenes" / file);
    const double a = 100, b = 200, exact = std::numbers::pi / 4 * (b * b - a * a);
    double error = std::abs(cell_area(coarse) - exact);
    for (int times = 1; times <= 2; ++times) {
      const gapfe::GmshSplit split = gapfe::split_gmsh(coarse, times);
      CHECK(split.arc_points > 0);
      for (const auto& [radius, name] : {std::pair{a, "bore"}, std::pair{b, "outer"}}) {
        const int tag = split.mesh.physical(1, name);
        for (const auto& e : split.mesh.edges)
          if (e.in(tag))
            for (int k = 0; k < 2; ++k)
              CHECK(split.mesh.nodes[e.nodes[k]].norm() == doctest::Approx(radius).epsilon(1e-13));
      }
      // The polygon's area error, the chords' segments, falls 4 times a split (16 times in two).
      const double finer = std::abs(cell_area(split.mesh) - exact);
      CHECK(finer < error / (times == 1 ? 3.5 : 12.0));
      CHECK(cell_area(split.mesh) < exact);  // inscribed
    }
  }
}

TEST_CASE("a Gmsh mesh split in four keeps a soft layer one cell thick, and refuses one it cannot") {
  const gapfe::GmshMesh coarse = gmsh_file(kGmshData / "matrix" / "fit.msh");
  const gapfe::GmshSplit split = gapfe::split_gmsh(coarse, 2, {"gap"}, {"shaft_face", "hub_face"});
  const int soft               = coarse.physical(2, "gap");
  std::size_t before = 0, after = 0;
  for (const auto& c : coarse.cells) before += c.in(soft);
  for (const auto& c : split.mesh.cells) {
    if (!c.in(soft)) continue;
    ++after;
    int inner = 0, outer = 0;  // corners on r = 15 and on r = 15.001
    for (int k = 0; k < 4; ++k) {
      const double r = split.mesh.nodes[c.nodes[k]](0);
      inner += std::abs(r - 15.0) < 1e-9, outer += std::abs(r - 15.001) < 1e-9;
    }
    CHECK((inner == 2 && outer == 2));
  }
  CHECK(after == 4 * before);  // 2 x 2 along the faces, none across
  CHECK(cell_area(split.mesh, soft) == doctest::Approx(cell_area(coarse, soft)).epsilon(1e-12));

  // A 2 x 2 block whose lower-left cell is soft between its left and right sides: the cell above it shares
  // the soft cell's top, a side across the layer, which the split keeps whole.
  gapfe::GmshMesh block;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      block.nodes.push_back(gapfe::Vec2(1 + i, j)), block.node_tags.push_back(3 * j + i + 1);
  block.physical_names = {{{2, 1}, "soft"}, {{2, 2}, "body"}, {{1, 3}, "left"}, {{1, 4}, "right"}};
  const auto element   = [](int type, std::vector<int> nodes, int group) {
    gapfe::GmshElement e;
    e.type = type, e.node_count = static_cast<int>(nodes.size()), e.physical = {group}, e.line = 10 + group;
    std::copy(nodes.begin(), nodes.end(), e.nodes.begin());
    return e;
  };
  block.cells = {element(3, {0, 1, 4, 3}, 1), element(3, {1, 2, 5, 4}, 2), element(3, {3, 4, 7, 6}, 2),
                 element(3, {4, 5, 8, 7}, 2)};
  block.edges = {element(1, {0, 3}, 3), element(1, {1, 4}, 4)};
  CHECK_THROWS_WITH_AS(gapfe::split_gmsh(block, 1, {"soft"}, {"left", "right"}),
                       doctest::Contains("shares a side with a soft layer's cell across the layer"),
                       gapfe::InputError);
  CHECK_THROWS_WITH_AS(gapfe::split_gmsh(block, 1, {"soft"}, {"left"}),
                       doctest::Contains("whose two opposite sides are not on the contact's faces"),
                       gapfe::InputError);
  CHECK_NOTHROW(gapfe::split_gmsh(block, 1));  // without the soft layer: every cell in four
}

// ---- --accuracy's ladder (app/accuracy.hpp), on made-up runs: no model is solved

namespace {

/// Rung k of a made-up ladder: 100 x 4^k nodes, 1 ms x 4^k; the largest stress 1 + 0.1 h (h = 2^-k),
/// exactly first order, unless `wobble` (then 1 + 0.1 (-1)^k: no limit); a support's reaction 1e5; one on
/// the axis, 1e-3 (-1)^k (tending to nothing against the loads, changing sign).
gapfe::app::LevelRun made_up_rung(int k, bool wobble = false) {
  gapfe::app::LevelRun r{k, 100L << (2 * k), 1e-3 * std::exp2(2 * k), {}};
  const double h = std::exp2(-k);
  r.quantities   = {{"reaction bottom R_z", 1e5, gapfe::Vec2::Zero(), false, 2, 1e5},
                    {"reaction axis R_r", 1e-3 * (k % 2 ? -1 : 1), gapfe::Vec2::Zero(), false, 2, 0},
                    {"largest von Mises", wobble ? 1 + 0.1 * (k % 2 ? -1 : 1) : 1 + 0.1 * h,
                     gapfe::Vec2::Zero(), true, 1, 0}};
  return r;
}

struct MadeUpLadder {
  bool wobble  = false;
  int fails_at = 0;         ///< the rung whose run throws (0: none)
  std::vector<bool> files;  ///< whether each rung solved wrote its files
  int climb(const gapfe::app::AccuracyTarget& target, long max_nodes, std::string& written) {
    std::vector<gapfe::app::LevelRun> rungs{made_up_rung(0, wobble)};
    std::ostringstream log;
    int solved      = 0;
    const auto make = [](int) { return gapfe::SceneModel{}; };
    const auto run  = [&](gapfe::SceneModel&, bool write, bool& cleared) {
      files.push_back(write);
      cleared = write;
      if (solved + 1 == fails_at) throw gapfe::SolveError("load step 3: Newton did not converge");
      return made_up_rung(++solved, wobble);
    };
    const double start =
        std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    return gapfe::app::climb(rungs, make, run, target, max_nodes, 4.0, 0.0, "mesh", start, written, log);
  }
};

}  // namespace

TEST_CASE(
    "--accuracy's ladder ends on the rung whose estimated error is within the target, its files written") {
  MadeUpLadder ladder;
  std::string written = "mesh 0";
  // The stress's error on rung k is 0.1 / 2^k, estimated exactly at first order: within 1e-2 from k = 4 on
  // (0.00625 over 1.00625), and never on two rungs (an assumed order is not enough).
  CHECK(ladder.climb({1e-2, 0, 3600}, 1'000'000, written) == 4);
  CHECK(ladder.files == std::vector<bool>{false, true, true, true});
  CHECK(written == "mesh 4");
  // The axis reaction changes sign at 1e-8 of the loads: settled, not a failure.
  std::vector<gapfe::app::LevelRun> rungs;
  for (int k = 2; k <= 4; ++k) rungs.push_back(made_up_rung(k));
  const gapfe::app::RungVerdict v = gapfe::app::judge(rungs, 1e-3, 0);  // the stress still outside: its rate
  CHECK(v.failed.empty());
  CHECK(v.which == "largest von Mises");
  CHECK(v.worst == doctest::Approx(0.1 / 16 / (1 + 0.1 / 16)).epsilon(1e-9));
  CHECK(v.rate == doctest::Approx(1.0).epsilon(1e-9));
}

/// The message of the SolveError `f` throws ("" when it throws none).
template <class F>
std::string solve_error(F&& f) {
  try {
    f();
  } catch (const gapfe::SolveError& e) {
    return e.what();
  }
  return "";
}

TEST_CASE(
    "--accuracy's ladder stops before a rung past the memory or the time, and at a quantity that wobbles") {
  const auto has = [](const std::string& text, const char* part) {
    return text.find(part) != std::string::npos;
  };
  std::string written = "mesh 0";
  MadeUpLadder small;  // rung 3 would have 6,400 nodes
  const std::string memory = solve_error([&] { small.climb({1e-2, 0, 3600}, 5'000, written); });
  CAPTURE(memory);
  CHECK(has(memory, "would have about 6400 nodes, past the 5000"));
  CHECK(has(memory, "about 2 more halvings needed"));  // 0.025 at first order to 0.01
  CHECK(has(memory, "the files are those of mesh 2"));
  MadeUpLadder slow;  // rung 2 ends at 16 ms, past 10 ms
  written                = "mesh 0";
  const std::string time = solve_error([&] { slow.climb({1e-2, 0, 0.010}, 1'000'000, written); });
  CAPTURE(time);
  CHECK(has(time, "past the time left"));
  CHECK(has(time, "--time-limit"));
  MadeUpLadder wobbly;
  wobbly.wobble             = true;
  written                   = "mesh 0";
  const std::string wobbles = solve_error([&] { wobbly.climb({1e-2, 0, 3600}, 1'000'000, written); });
  CAPTURE(wobbles);
  CHECK(has(wobbles, "largest von Mises does not converge as the mesh is refined"));
  CHECK(wobbly.files.size() == 3);  // two verdicts in a row: rungs 2 and 3
  for (const int rung : {1, 3}) {   // a run that fails: named, and whose files the folder holds
    MadeUpLadder failing;
    failing.fails_at        = rung;
    written                 = "mesh 0";
    const std::string stops = solve_error([&] { failing.climb({1e-2, 0, 3600}, 1'000'000, written); });
    CAPTURE(stops);
    CHECK(has(stops, ("mesh " + std::to_string(rung) + ": load step 3: Newton did not converge").c_str()));
    CHECK(
        has(stops, rung == 1 ? "the files are those of mesh 0" : "the files are those of mesh 3 (stopped)"));
  }
}

// The card-deck reader (seed Appendix A): Fortran field semantics, one test per card type reading its
// exact columns, and malformed decks that must each give one clear message and a non-zero exit from
// the `gapfe` command (run in-process; CI runs this file under ASan + UBSan too).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include <doctest/doctest.h>

#include "gapfe/app/command.hpp"
#include "gapfe/input/deck.hpp"
#include "gapfe/input/deck_scene.hpp"
#include "gapfe/input/gmsh_reader.hpp"
#include "gapfe/output/step_files.hpp"

#include "deck_support.hpp"

using namespace gapfe;
using gapfe::test::Card;

TEST_CASE("Fortran fields: blanks, implied decimal points, exponents") {
  const std::string text = Card()
                               .f(1, 5, "  1 0")
                               .f(6, 10, "-12")
                               .f(11, 16, "1.5-3")
                               .f(17, 22, "1.5D2")
                               .f(23, 30, "1500")
                               .f(31, 34, "+5")
                               .f(35, 42, "1.2E+1")
                               .str();
  const CardImage c(text, 7, "DATA NO. 99 (test card)");
  CHECK(c.integer(1, 5, "a") == 10);  // embedded blank ignored (BN)
  CHECK(c.integer(6, 10, "b") == -12);
  CHECK(c.real(6, 10, 3, "b") == doctest::Approx(-0.012).epsilon(1e-15));   // implied point: d = 3
  CHECK(c.real(11, 16, 0, "c") == doctest::Approx(1.5e-3).epsilon(1e-15));  // exponent without E
  CHECK(c.real(17, 22, 0, "d") == doctest::Approx(150.0).epsilon(1e-15));   // D exponent
  CHECK(c.real(23, 30, 3, "e") == doctest::Approx(1.5).epsilon(1e-15));     // "    1500" in F8.3
  CHECK(c.integer(31, 34, "f") == 5);
  CHECK(c.real(35, 42, 0, "g") == doctest::Approx(12.0).epsilon(1e-15));
  CHECK(c.real(43, 60, 2, "blank") == 0.0);  // past the end of the line: blank
  CHECK(c.integer(70, 80, "blank") == 0);

  const auto error = [](const std::string& t, bool integer, int decimals = 0) {
    try {
      const CardImage k(t, 3, "DATA NO. 5 (boundary condition card 1)");
      if (integer)
        (void)k.integer(1, 10, "XR");
      else
        (void)k.real(1, 10, decimals, "XR");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string letters = error("     1.2a", false);
  CHECK(
      letters.find("DATA NO. 5 (boundary condition card 1), line 3, columns 1-10 (XR): expected a number") !=
      std::string::npos);
  CHECK(letters.find("'     1.2a '") != std::string::npos);
  CHECK(error("  1.2.3", false).find("expected a number") != std::string::npos);
  CHECK(error("      1.5", true).find("expected an integer") != std::string::npos);
  CHECK(error("9999999999", true).find("within") != std::string::npos);
  CHECK(error("   1.0E", false).find("exponent") != std::string::npos);
  CHECK(error("   1.0E999", false).find("finite") != std::string::npos);
  CHECK(error("   -", false).find("expected a number") != std::string::npos);
  CHECK(error("\t1.0", false).find("tab") != std::string::npos);
  CHECK(error("   .", false).find("expected a number") != std::string::npos);
}

TEST_CASE("Deck cards 1-6 and 10-13 read from their exact columns") {
  const Deck d = read_deck(gapfe::test::tube_deck());
  CHECK(d.title == "TUBE");
  CHECK(d.options.format == DeckFormat::elastic);
  // Card 2: NUMTC blank, TREF with an implied point ("   70" in F5.0 is 70).
  CHECK(d.control.nnla == 1);
  CHECK(d.control.numtc == 0);
  CHECK(d.control.nummat == 1);
  CHECK(d.control.numpc == 2);
  CHECK(d.control.tref == 70.0);
  CHECK(d.control.nlinc == 1);
  // Card 3.
  CHECK(d.mesh.max_i == 5);
  CHECK(d.mesh.max_j == 3);
  CHECK(d.mesh.nseg == 4);
  CHECK(d.mesh.nbc == 2);
  CHECK(d.mesh.nmtl == 1);
  // Card 4: "    1000" in F8.3 is 1.000; the type in columns 67-71.
  REQUIRE(d.segments.size() == 4);
  CHECK(d.segments[0].p[0].x(0) == 1.0);
  CHECK(d.segments[0].p[1].i == 5);
  CHECK(d.segments[0].p[1].x(0) == 2.0);
  CHECK(d.segments[1].p[1].x(1) == 0.25);
  CHECK(d.segments[0].type == SegmentType::line);
  // Card 5: code in columns 21-30.
  CHECK(d.boundary[0].code == 2);
  CHECK(d.boundary[1].j1 == 3);
  // Card 6: IANG, NANG, IJDIR in columns 46-60.
  CHECK(d.blocks[0].beta_deg == 90.0);
  CHECK(d.blocks[0].iang == 1);
  CHECK(d.blocks[0].nang == 2);
  CHECK(d.blocks[0].ijdir == 1);
  // Cards 10a/10b.
  REQUIRE(d.materials.size() == 1);
  CHECK(d.materials[0].table.density == 7.85e-9);
  CHECK(d.materials[0].table.rows[0].E_N == 200000.0);
  CHECK(d.materials[0].table.rows[0].nu_ST == 0.3);
  CHECK(d.materials[0].table.rows[0].G_TN == 80000.0);
  CHECK(d.materials[0].table.rows[0].alpha_T == 1.2e-5);
  CHECK(d.materials[0].table.thermal == ThermalInput::coefficients);
  CHECK_FALSE(d.materials[0].yield.has_value());  // elastic format: no card 11
  // Card 13: M, N, pressure.
  REQUIRE(d.program.blocks.size() == 1);
  REQUIRE(d.program.blocks[0].pressure.size() == 2);
  CHECK(d.program.blocks[0].pressure[0].node_m == 6);
  CHECK(d.program.blocks[0].pressure[0].node_n == 1);
  CHECK(d.program.blocks[0].pressure[0].value == 100.0);
  CHECK(d.program.blocks[0].pressure[0].ref.line == 15);
}

TEST_CASE("Deck card 0 (SAAC3 rate card) in E12.6 fields, and cards 7-9, 11, 12, 14, 15") {
  using gapfe::test::lines_of;
  std::vector<std::string> deck = lines_of(gapfe::test::tube_deck());
  deck.erase(deck.begin());  // drop `$ format = elastic`: read as saac3 below
  // Card 0 first: "     1500000" in E12.6 is 1.5; b explicit; eps_p dot with an exponent.
  deck.insert(deck.begin(),
              Card().f(1, 12, "     1500000").f(13, 24, "2.5").f(25, 36, "1.0E-3").f(37, 48, "").str());
  // Control card: NUMTC = 2, NUMSC = 1, NUMST = 1, INERT = 1, NLINC = 2, INCI = 1, INCF = 0, IPLLOT = 1.
  deck[2] = Card()
                .i(1, 5, 1)
                .i(6, 10, 2)
                .i(11, 15, 1)
                .i(16, 20, 2)
                .i(21, 25, 1)
                .i(26, 30, 1)
                .f(31, 35, "0.")
                .i(36, 40, 1)
                .i(41, 45, 2)
                .i(46, 50, 1)
                .i(51, 55, 0)
                .i(56, 60, 1)
                .str();
  // After the material block card (line index 11): plot title, plot limits, two temperature cards.
  const auto after_blocks = deck.begin() + 11;
  deck.insert(after_blocks, {"PLOT OF THE TUBE", Card().f(1, 10, "2.5").f(11, 20, "       1").str(),
                             Card().f(1, 10, "1.").f(11, 20, "0.").f(21, 30, "100.").str(),
                             Card().f(1, 10, "2.").f(11, 20, "0.").f(21, 30, "  50").str()});
  // Yield card after the material's property cards (index 18 now).
  deck.insert(deck.begin() + 18, Card()
                                     .f(1, 10, "500.")
                                     .f(11, 20, "510.")
                                     .f(21, 30, "520.")
                                     .f(31, 40, "300.")
                                     .f(41, 50, "310.")
                                     .f(51, 60, "320.")
                                     .f(61, 70, "1000.")
                                     .str());
  // Load step 1: inertia, 2 pressure (already there), 1 shear, 1 transverse shear; step 2: inertia only.
  deck.insert(deck.begin() + 19, Card().f(1, 10, "9.81").f(11, 20, "100.").f(21, 30, "0.5").str());
  deck.push_back(Card().i(1, 5, 2).i(6, 10, 3).f(11, 20, "7.").str());
  deck.push_back(Card().i(1, 5, 3).i(6, 10, 4).f(11, 20, "-3.").str());
  deck.push_back(Card().f(1, 10, "1.").str());
  const Deck d = read_deck(gapfe::test::join(deck), {{"format", "saac3"}});
  REQUIRE(d.rate.has_value());
  CHECK(d.rate->time_step == 1.5);
  CHECK(d.rate->rate_b == 2.5);
  CHECK(d.rate->rate_plastic_strain == 1e-3);
  CHECK(d.rate->strain_rate == 0.0);
  CHECK(d.plot_title == "PLOT OF THE TUBE");
  CHECK(d.plot_rmax == 2.5);
  CHECK(d.plot_zmax == 1.0);
  REQUIRE(d.temperature_points.size() == 2);
  CHECK(d.temperature_points[1].r == 2.0);
  CHECK(d.temperature_points[1].temperature == 50.0);
  REQUIRE(d.materials[0].yield.has_value());
  CHECK_FALSE(d.materials[0].yield->blank);
  CHECK(d.materials[0].yield->yield[5] == 320.0);
  CHECK(d.materials[0].yield->hardening == 1000.0);
  REQUIRE(d.program.blocks.size() == 2);
  CHECK(d.inertia(1).axial_acceleration == 9.81);
  CHECK(d.inertia(1).angular_velocity == 100.0);
  CHECK(d.inertia(2).axial_acceleration == 1.0);  // step 2 has its own inertia card (INCI = 1)
  CHECK(d.inertia(2).angular_velocity == 0.0);
  CHECK(d.surface(2).shear.size() == 1);  // INCF = 0: block 1's surface cards repeat
  CHECK(d.surface(1).shear[0].value == 7.0);
  CHECK(d.surface(1).transverse_shear[0].node_n == 4);
  CHECK(d.surface(1).transverse_shear[0].value == -3.0);

  // NUMTC = -2: one constant-temperature card; an all-blank yield card keeps the material elastic.
  std::vector<std::string> c = lines_of(gapfe::test::tube_deck());
  c.erase(c.begin());
  c[1] = Card().i(1, 5, 1).i(6, 10, -2).i(11, 15, 1).i(16, 20, 2).f(31, 35, "20.").i(41, 45, 1).str();
  c.insert(c.begin() + 10, Card().f(1, 10, "  120").str());
  c.insert(c.begin() + 14, "");
  const Deck e = read_deck(gapfe::test::join(c));
  REQUIRE(e.constant_temperature.has_value());
  CHECK(*e.constant_temperature == 120.0);
  CHECK(e.materials[0].yield->blank);
}

TEST_CASE("Deck options: `$ key = value` lines before the title, overridden by the command line") {
  std::string text =
      "$ a comment line\n$ element = quad4\n$ bc_loads = per-radian\n" + gapfe::test::tube_deck();
  const Deck d = read_deck(text, {{"solver", "eigen"}});
  CHECK(d.options.element == gapfe::ElementChoice::quad4);
  CHECK(d.options.solver == gapfe::SolverChoice::eigen);
  CHECK(d.options.format == DeckFormat::elastic);
  CHECK(d.options.loads_per_radian);
  const Deck o = read_deck(text, {{"element", "legacy"}});
  CHECK(o.options.element == gapfe::ElementChoice::legacy);
}

namespace {

struct Outcome {
  int exit = 0;
  std::string err;
};

Outcome run_text(const std::string& text, const std::string& command = "run") {
  namespace fs       = std::filesystem;
  static int serial  = 0;
  const fs::path dir = fs::temp_directory_path() / ("gapfe_deck_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path deck = dir / ("deck" + std::to_string(++serial) + ".deck");
  std::ofstream(deck) << text;
  std::ostringstream out, err;
  const int code = gapfe::app::command({command, deck.string(), "--out", (dir / "out").string()}, out, err);
  return {code, err.str()};
}

}  // namespace

TEST_CASE("The valid test deck runs") {
  const Outcome o = run_text(gapfe::test::tube_deck());
  CHECK(o.err == "");
  CHECK(o.exit == 0);
}

TEST_CASE("Malformed decks: each gives one clear message and a non-zero exit") {
  using gapfe::test::tube_deck;
  struct Case {
    const char* name;
    std::string deck;
    int exit;
    std::vector<std::string> says;
  };
  const std::string base = tube_deck();
  auto lines             = gapfe::test::lines_of(base);
  const auto with        = [&](std::initializer_list<std::pair<int, std::string>> changes) {
    auto l = lines;
    for (const auto& [k, t] : changes) l[k] = t;
    return gapfe::test::join(l);
  };
  const auto head = [&](int n) { return gapfe::test::join({lines.begin(), lines.begin() + n}); };
  // Line indices in tube_deck(): 0 `$`, 1 title, 2 control, 3 mesh control, 4-7 segments, 8-9 BC, 10 block,
  // 11 material id, 12-13 properties, 14-15 pressure cards.
  std::vector<Case> cases = {
      {"empty deck", "", 1, {"DATA NO. 1 (title card)", "deck ends"}},
      {"truncated after the mesh control card",
       head(4),
       1,
       {"DATA NO. 4 (line segment card 1)", "deck ends"}},
      {"letters in an integer field",
       with({{2, Card().i(1, 5, 1).f(11, 15, "   ab").str()}}),
       1,
       {"DATA NO. 2 (control card), line 3, columns 11-15 (NUMMAT): expected an integer"}},
      {"two decimal points in a coordinate",
       with({{4, lines[4].substr(0, 6) + "  1.0.0" + lines[4].substr(13)}}),
       1,
       {"DATA NO. 4 (line segment card 1), line 5, columns 7-14 (R): expected a number"}},
      {"more pressure cards announced than given",
       with({{2, Card().i(1, 5, 1).i(11, 15, 1).i(16, 20, 3).f(31, 35, "70").i(41, 45, 1).str()}}),
       1,
       {"DATA NO. 13 (boundary pressure card 3 of load step 1)", "deck ends"}},
      {"fewer pressure cards announced than given",
       with({{2, Card().i(1, 5, 1).i(11, 15, 1).i(16, 20, 1).f(31, 35, "70").i(41, 45, 1).str()}}),
       1,
       {"line 16: unexpected card after the last load block"}},
      {"segment index beyond MAXI",
       with({{4, gapfe::test::segment(1, 1, "1.", "0.", 6, 1, "2.", "0.")}}),
       1,
       {"DATA NO. 4 (line segment card 1), line 5, columns 23-25 (I): must be within 1..MAXI = 5"}},
      {"segment type 9",
       with({{4, lines[4].substr(0, 66) + "    9"}}),
       1,
       {"columns 67-71 (line segment type): must be 0-6"}},
      {"boundary condition code 8",
       with({{8, Card().i(1, 5, 1).i(6, 10, 5).i(11, 15, 1).i(16, 20, 1).i(21, 30, 8).str()}}),
       1,
       {"DATA NO. 5 (boundary condition card 1), line 9, columns 21-30 (boundary condition code)"}},
      {"boundary condition rectangle inverted",
       with({{8, Card().i(1, 5, 5).i(6, 10, 1).i(11, 15, 1).i(16, 20, 1).i(21, 30, 2).str()}}),
       1,
       {"DATA NO. 5 (boundary condition card 1), line 9, columns 1-10 (I range)"}},
      {"undefined material number",
       with({{10, Card().i(1, 5, 4).i(6, 10, 1).i(11, 15, 5).i(16, 20, 1).i(21, 25, 3).str()}}),
       1,
       {"DATA NO. 6 (material block card 1), line 11", "material 4 is not defined"}},
      {"IJDIR 3",
       with({{10, Card().i(1, 5, 1).i(6, 10, 1).i(11, 15, 5).i(16, 20, 1).i(21, 25, 3).i(56, 60, 3).str()}}),
       1,
       {"columns 56-60 (IJDIR): must be 0, 1 or 2"}},
      {"pressure on a node that does not exist",
       with({{14, Card().i(1, 5, 999).i(6, 10, 1).f(11, 20, "100.").str()}}),
       1,
       {"DATA NO. 13 (boundary pressure card 1 of load step 1), line 15, columns 1-5: node 999 does not "
        "exist"}},
      {"pressure on two nodes that are not an edge",
       with({{14, Card().i(1, 5, 1).i(6, 10, 7).f(11, 20, "100.").str()}}),
       1,
       {"line 15", "are not the ends of an element edge"}},
      {"pressure with the element on the right",
       with({{14, Card().i(1, 5, 1).i(6, 10, 6).f(11, 20, "100.").str()}}),
       1,
       {"line 15", "swap M and N"}},
      {"zero-area elements",
       with({{5, gapfe::test::segment(5, 1, "2.", "0.", 5, 3, "2.", "0.")},
             {6, gapfe::test::segment(5, 3, "2.", "0.", 1, 3, "1.", "0.")},
             {7, gapfe::test::segment(1, 3, "1.", "0.", 1, 1, "1.", "0.")}}),
       1,
       {"zero or negative area"}},
      {"negative Young's modulus",
       with({{12, lines[12].substr(0, 10) + "   -200000" + lines[12].substr(20)}}),
       1,
       {"DATA NO. 10b (first property cards of material 1, temperature 1), line 13", "Young's moduli"}},
      {"NLINC 0",
       with({{2, Card().i(1, 5, 1).i(11, 15, 1).i(16, 20, 2).f(31, 35, "70").str()}}),
       1,
       {"columns 41-45 (NLINC): must be >= 1"}},
      {"tab in a card", with({{8, "    1\t5"}}), 1, {"line 9, column 6: tab character"}},
      {"unknown extension option",
       "$ colour = red\n" + base,
       1,
       {"extension line 1", "unknown option 'colour'"}},
      {"NUMTC -1",
       with({{2,
              Card().i(1, 5, 1).i(6, 10, -1).i(11, 15, 1).i(16, 20, 2).f(31, 35, "70").i(41, 45, 1).str()}}),
       1,
       {"columns 6-10 (NUMTC): must be >= 0, or -2"}},
      {"material blocks leave an element without material",
       with({{10, Card().i(1, 5, 1).i(6, 10, 1).i(11, 15, 4).i(16, 20, 1).i(21, 25, 3).str()}}),
       1,
       {"element 4 (I = 4, J = 1) is in no material block"}},
      {"segment that is not a row, column or diagonal",
       with({{7, gapfe::test::segment(1, 3, "1.", ".25", 2, 1, "1.", "0.")}}),
       1,
       {"DATA NO. 4 (line segment card 4", "line 8", "neither a row, a column nor a 45-degree diagonal"}},
      {"MAXI x MAXJ beyond the limit",
       with({{3, Card().i(1, 5, 99999).i(6, 10, 99999).i(11, 15, 4).i(16, 20, 2).i(21, 25, 1).str()}}),
       1,
       {"DATA NO. 3 (mesh generation control card), line 4, columns 1-10 (MAXI x MAXJ)"}},
      {"temperatures of a material not increasing", "", 1, {"must increase strictly"}},
  };
  // A second temperature row at a lower temperature: rebuild the material with two rows.
  {
    auto l = lines;
    l[11]  = Card().i(1, 5, 1).i(6, 10, 2).f(11, 20, "7.85e-9").str();
    l.insert(l.begin() + 14, {gapfe::test::steel_first_property_card("-10."), lines[13]});
    cases.back().deck = gapfe::test::join(l);
  }
  // Unconstrained: no boundary cards at all -> singular stiffness (exit 2), named by node.
  {
    auto l = lines;
    l[3]   = Card().i(1, 5, 5).i(6, 10, 3).i(11, 15, 4).i(16, 20, 0).i(21, 25, 1).str();
    l.erase(l.begin() + 8, l.begin() + 10);
    cases.push_back(
        {"unconstrained model (singular)", gapfe::test::join(l), 2, {"cannot solve", "constraints"}});
  }
  // A deck in the default (saac) format lacks its yield card.
  cases.push_back({"elastic deck read as saac",
                   gapfe::test::join({lines.begin() + 1, lines.end()}),
                   1,
                   {"DATA NO. 11 (yield stress card of material 1), line 14"}});
  CHECK(cases.size() >= 20);
  for (const auto& c : cases) {
    CAPTURE(c.name);
    const Outcome o = run_text(c.deck);
    CAPTURE(o.err);
    CHECK(o.exit == c.exit);
    for (const auto& s : c.says) CHECK(o.err.find(s) != std::string::npos);
    // One message, one line (plus nothing else): no crash output, no NaN.
    CHECK(std::count(o.err.begin(), o.err.end(), '\n') == 1);
    CHECK(o.err.find("nan") == std::string::npos);
  }
}

TEST_CASE("The gapfe command: usage errors and unreadable decks") {
  std::ostringstream out, err;
  CHECK(gapfe::app::command({}, out, err) == gapfe::app::usage);
  CHECK(gapfe::app::command({"run", "x.deck"}, out, err) == gapfe::app::usage);  // no --out
  CHECK(gapfe::app::command({"explode", "x.deck"}, out, err) == gapfe::app::usage);
  CHECK(gapfe::app::command({"run", "x.deck", "--out", "/tmp", "--variant", "big"}, out, err) ==
        gapfe::app::usage);
  std::ostringstream e2;
  CHECK(gapfe::app::command({"info", "/nonexistent/deck"}, out, e2) == gapfe::app::system);
  CHECK(e2.str().find("cannot open the deck '/nonexistent/deck'") != std::string::npos);
  for (const char* bad : {"0", "two", "2x", "-1"}) {
    std::ostringstream e3;
    CHECK(gapfe::app::command({"run", "x.deck", "--out", "/tmp", "--threads", bad}, out, e3) ==
          gapfe::app::usage);
    CHECK(e3.str().find("--threads: '" + std::string(bad) + "' is not a thread count") != std::string::npos);
  }
  std::ostringstream e4;
  CHECK(gapfe::app::command({"run", "x.deck", "--out", "/tmp", "--threads"}, out, e4) == gapfe::app::usage);
  std::ostringstream help;
  CHECK(gapfe::app::command({"--help"}, help, err) == gapfe::app::ok);
  CHECK(help.str().find("gapfe run DECK --out DIR") != std::string::npos);
}

TEST_CASE("deformed.svg of a large mesh: the outline keeps the boundary and the material interfaces") {
  // tube_deck(): a 5 x 3 grid, 4 x 2 cells. Its boundary has 2 (4 + 2) = 12 cell sides; a second material
  // in the cells of I >= 3 adds the 2 sides between I = 2 and I = 3.
  const gapfe::Scene s = gapfe::build_scene(gapfe::read_deck(gapfe::test::tube_deck()));
  REQUIRE(s.grid.cells.size() == 8);
  std::vector<int> material(8, 1);
  CHECK(gapfe::detail::outline_edges(s.grid, material).size() == 12);
  for (std::size_t e = 0; e < 8; ++e) material[e] = s.grid.cells[e].i >= 3 ? 2 : 1;
  const auto edges = gapfe::detail::outline_edges(s.grid, material);
  CHECK(edges.size() == 14);
  for (const auto& [a, b] : edges) CHECK(a < b);
}

// ---- Gmsh meshes (input/gmsh_reader.hpp). The files in tests/data were written by meshio
// (a writer independent of the reader) or, for MSH 4.1 with curve groups, by tests/data/make_meshes.py and
// read back there with meshio; each holds the tube 100 <= r <= 200, 0 <= z <= 25.
namespace {

const std::filesystem::path kMeshData = std::filesystem::path(GAPFE_SOURCE_DIR) / "tests" / "data";

gapfe::GmshMesh read_mesh_file(const std::string& name) {
  std::ifstream in(kMeshData / name);
  REQUIRE(in);
  std::stringstream s;
  s << in.rdbuf();
  return gapfe::read_gmsh(s.str());
}

/// Twice the signed area of a cell's corners in (r, z): positive counterclockwise.
double corner_area(const gapfe::GmshMesh& m, const gapfe::GmshElement& e) {
  const int corners = gapfe::detail::gmsh_corners(e.type);
  double area       = 0;
  for (int a = 0; a < corners; ++a) {
    const gapfe::Vec2& p = m.nodes[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(a)])];
    const gapfe::Vec2& q =
        m.nodes[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>((a + 1) % corners)])];
    area += p(0) * q(1) - q(0) * p(1);
  }
  return area;
}

/// The edges of physical group `tag`.
int edges_in(const gapfe::GmshMesh& m, int tag) {
  return static_cast<int>(
      std::count_if(m.edges.begin(), m.edges.end(), [&](const auto& e) { return e.in(tag); }));
}

}  // namespace

TEST_CASE("[gmsh] the tube in MSH 4.1 and 2.2: nodes, counterclockwise cells, physical groups") {
  for (const char* file : {"tube_quad4_v41.msh", "tube_quad4_v22.msh"}) {
    CAPTURE(file);
    const gapfe::GmshMesh m = read_mesh_file(file);
    REQUIRE(m.nodes.size() == 15);
    REQUIRE(m.cells.size() == 8);
    CHECK(m.flipped == 4);           // the second row is written clockwise
    for (const auto& x : m.nodes) {  // on the 4 x 2 grid r = 100 + 25 i, z = 12.5 j
      const double i = (x(0) - 100) / 25, j = x(1) / 12.5;
      CHECK(i == std::round(i));
      CHECK(j == std::round(j));
    }
    for (const auto& c : m.cells) {
      CHECK(c.type == 3);
      CHECK(c.physical == std::vector<int>{m.physical(2, "steel")});
      CHECK(corner_area(m, c) == doctest::Approx(2 * 25 * 12.5).epsilon(1e-12));  // counterclockwise
    }
    CHECK(edges_in(m, m.physical(1, "bore")) == 2);
    CHECK(edges_in(m, m.physical(1, "bottom")) == 4);
    CHECK(edges_in(m, m.physical(1, "top")) == 4);
    for (const auto& e : m.edges)
      if (e.in(m.physical(1, "bore")))
        for (int a = 0; a < 2; ++a)
          CHECK(m.nodes[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(a)])](0) == 100);
  }
  // Node tags with gaps (1000 + 10 j + i) in the 4.1 file.
  const gapfe::GmshMesh m = read_mesh_file("tube_quad4_v41.msh");
  for (std::size_t k = 0; k < m.nodes.size(); ++k)
    CHECK(m.node_tags[k] ==
          1000 + 10 * std::lround(m.nodes[k](1) / 12.5) + std::lround((m.nodes[k](0) - 100) / 25));
}

TEST_CASE("[gmsh] 8-node quadrangles: mid-side nodes halfway along their edges, in gapfe's order") {
  const gapfe::GmshMesh m = read_mesh_file("tube_quad8_v41.msh");
  REQUIRE(m.nodes.size() == 23);
  REQUIRE(m.cells.size() == 4);
  CHECK(m.flipped == 0);
  for (const auto& c : m.cells) {
    CHECK(c.type == 16);
    CHECK(corner_area(m, c) == doctest::Approx(2 * 25 * 25).epsilon(1e-12));
    for (int a = 0; a < 4; ++a) {  // mid-side 4 + a on edge (a, a + 1): element/quad8.hpp
      const auto node = [&](int k) {
        return m.nodes[static_cast<std::size_t>(c.nodes[static_cast<std::size_t>(k)])];
      };
      CHECK((node(4 + a) - 0.5 * (node(a) + node((a + 1) % 4))).norm() < 1e-12);
    }
  }
  CHECK(m.edges.size() == 9);  // 3-node lines; meshio's 4.1 writer gives them no physical group
  for (const auto& e : m.edges) CHECK(e.physical.empty());
}

TEST_CASE("[gmsh] malformed meshes: each a clear InputError naming the line and what is wrong") {
  const std::string head  = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  const std::string nodes = "$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n";
  const std::string quad  = "$Elements\n1 1 1 1\n2 1 3 1\n1 1 2 3 4\n$EndElements\n";
  REQUIRE_NOTHROW(gapfe::read_gmsh(head + nodes + quad));
  const auto replaced = [](std::string s, const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"hello\n", "expected a section"},
      {"", "empty file"},
      {replaced(head, "4.1 0 8", "4.1 1 8") + nodes + quad, "binary MSH file"},
      {replaced(head, "4.1 0 8", "3 0 8") + nodes + quad, "gapfe reads 4.1 and 2.2"},
      {head + replaced(nodes, "0 0 0\n1 0 0", "-1 0 0\n1 0 0") + quad, "< 0: an axisymmetric section"},
      {head + replaced(nodes, "1 1 0\n", "1 1 0.5\n") + quad, "plane z = 0"},
      {head + nodes + replaced(quad, "2 1 3 1\n1 1 2 3 4", "3 1 4 1\n1 1 2 3 4"), "element type 4"},
      {head + nodes + replaced(quad, "1 1 2 3 4", "1 1 2 3 9"), "node 9 is not in $Nodes"},
      {head + replaced(nodes, "1\n2\n3\n4\n", "1\n2\n2\n4\n") + quad, "node 2 is given twice"},
      {head + nodes + replaced(quad, "1 1 2 3 4", "1 1 2 2 1"),
       "line 19 ($Elements): the element names node 1 twice"},
      {head + nodes + replaced(quad, "1 1 2 3 4", "1 1 2 3 3"),
       "line 19 ($Elements): the element names node 3 twice"},
      {head + nodes + replaced(quad, "1 1 2 3 4", "1 1 3 2 4"), "zero area"},  // a bow tie: signed area 0
      // the same cell twice in a 4.1 file (each element is given once there)
      {head + nodes + "$Elements\n1 2 1 2\n2 1 3 2\n1 1 2 3 4\n2 2 3 4 1\n$EndElements\n",
       "line 20 ($Elements): the element repeats the one of line 19 (the same nodes)"},
      // two groups of one dimension with one name; an empty name; a quoted number
      {head + "$PhysicalNames\n2\n2 1 \"steel\"\n2 2 \"steel\"\n$EndPhysicalNames\n" + nodes + quad,
       "line 7 ($PhysicalNames): physical groups 1 and 2 of dimension 2 are both named \"steel\""},
      {head + "$PhysicalNames\n1\n2 1 \"\"\n$EndPhysicalNames\n" + nodes + quad,
       "line 6 ($PhysicalNames): an empty name"},
      {head + nodes + replaced(quad, "1 1 2 3 4", "1 \"\" 2 3 4"), "a quoted word where an element's node"},
      {head + nodes + replaced(quad, "2 1 3 1", "2 \"\" 3 1"), "a quoted word where a block's entity tag"},
      {head + nodes + "$Elements\n1 1 1 1\n1 1 1 1\n1 1 2\n$EndElements\n", "no triangles or quadrangles"},
      {head + nodes + quad.substr(0, quad.size() / 2), "the file ends in $Elements"},
      {head + quad + nodes, "$Elements before $Nodes"},
      {nodes + quad, "does not start with $MeshFormat"},
      {head + "$PhysicalNames\n1\n2 1 \"steel\n$EndPhysicalNames\n" + nodes + quad,
       "unterminated quoted name"},
      {head + replaced(nodes, "1 4 1 4", "1 5 1 4") + quad, "the header says 5 nodes"},
      {head + replaced(nodes, "0 0 0\n", "0 zero 0\n") + quad, "expected a finite number, found 'zero'"},
      // a header claiming a billion nodes in a short file: found short, nothing allocated for the claim
      {head + "$Nodes\n1 1000000000 1 1000000000\n2 1 0 1000000000\n1\n", "the file ends in $Nodes"},
  };
  for (const auto& c : cases) {
    const std::string& text     = c.first;  // named: CAPTURE's lambda cannot take a structured binding
    const std::string& expected = c.second;
    CAPTURE(text);
    try {
      (void)gapfe::read_gmsh(text);
      FAIL("no error; expected: " << expected);
    } catch (const gapfe::InputError& e) {
      CAPTURE(e.what());
      CHECK(std::string(e.what()).find(expected) != std::string::npos);
    }
  }
  const gapfe::GmshMesh m = read_mesh_file("tube_quad4_v22.msh");
  CHECK_THROWS_WITH_AS(m.physical(1, "outer"), doctest::Contains("has no curve physical group \"outer\""),
                       gapfe::InputError);
}

TEST_CASE("[gmsh] sections gapfe does not use are skipped, their quoted strings included") {
  // meshio and Gmsh write point data as $NodeData with a quoted field name (and spaces in it).
  const std::string mesh =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"steel\"\n"
      "$EndPhysicalNames\n$Nodes\n4\n1 1 0 0\n2 2 0 0\n3 2 1 0\n4 1 1 0\n$EndNodes\n"
      "$Elements\n1\n1 3 2 1 7 1 2 3 4\n$EndElements\n";
  const std::string data =
      "$NodeData\n1\n\"temperature rise\"\n1\n0.0\n3\n0\n1\n4\n1 1.0\n2 2.0\n3 3.0\n"
      "4 4.0\n$EndNodeData\n";
  const gapfe::GmshMesh m = gapfe::read_gmsh(mesh + data);
  CHECK(m.cells.size() == 1);
  CHECK(m.nodes.size() == 4);
  CHECK_THROWS_WITH_AS(gapfe::read_gmsh(mesh + "$NodeData\n1\n\"temperature\n"),
                       doctest::Contains("unterminated quoted string before $EndNodeData"),
                       gapfe::InputError);
  // A node tag below 1: refused with its line.
  std::string zero = mesh;
  zero.replace(zero.find("1 1 0 0"), 7, "0 1 0 0");
  CHECK_THROWS_WITH_AS(gapfe::read_gmsh(zero), doctest::Contains("node tag 0"), gapfe::InputError);
}

TEST_CASE(
    "[gmsh] MSH 2.2 writes a cell once per physical group: read once, in both; a true repeat is refused") {
  // Gmsh -format msh22 with the surface in "steel" and in "all": element 2 is element 1 again (same nodes,
  // type and elementary entity 7), in the other group. The curve "bore" is given once.
  const std::string head =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n1 3 \"bore\"\n2 1 "
      "\"steel\"\n2 2 \"all\"\n$EndPhysicalNames\n$Nodes\n4\n1 1 0 0\n2 2 0 0\n3 2 1 0\n"
      "4 1 1 0\n$EndNodes\n";
  const std::string cells =
      "$Elements\n3\n1 3 2 1 7 1 2 3 4\n2 3 2 2 7 1 2 3 4\n3 1 2 3 5 4 1\n$EndElements\n";
  const gapfe::GmshMesh m = gapfe::read_gmsh(head + cells);
  REQUIRE(m.cells.size() == 1);
  CHECK(m.cells[0].in(m.physical(2, "steel")));
  CHECK(m.cells[0].in(m.physical(2, "all")));
  CHECK(m.edges.size() == 1);
  // The same cell again in the same group, or in another entity (an overlapping mesh): refused.
  for (const auto& [repeat, expected] : std::vector<std::pair<std::string, std::string>>{
           {"2 3 2 1 7 1 2 3 4",
            "line 20 ($Elements): the element repeats the one of line 19 (the same nodes, "
            "in the same physical group)"},
           {"2 3 2 2 8 1 2 3 4",
            "line 20 ($Elements): the element repeats the one of line 19 (the same nodes)"},
           {"2 3 2 0 7 1 2 3 4",
            "line 20 ($Elements): the element repeats the one of line 19 (the same nodes)"}}) {
    std::string text = head + cells;
    text.replace(text.find("2 3 2 2 7 1 2 3 4"), 17, repeat);
    const std::string line = repeat;  // a structured binding cannot be captured (C++20 before P1091 in clang)
    CAPTURE(line);
    CHECK_THROWS_WITH_AS(gapfe::read_gmsh(text), doctest::Contains(expected.c_str()), gapfe::InputError);
  }
  // A physical tag past 2^31 - 1 (it wrapped into another group): refused.
  std::string wide = head + cells;
  wide.replace(wide.find("1 3 2 1 7"), 9, "1 3 2 4294967297 7");
  CHECK_THROWS_WITH_AS(gapfe::read_gmsh(wide),
                       doctest::Contains("line 19 ($Elements): an element's physical tag"),
                       gapfe::InputError);
}

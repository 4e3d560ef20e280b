// Decks run end to end through the `gapfe` command: the thick-tube example deck against the library
// API and the Lame closed form, the same deck in the smallest and a richer variant, load-step ramps,
// the constant-temperature card and the per-radian load option.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <doctest/doctest.h>

#include "gapfe/app/command.hpp"
#include "gapfe/app/plan.hpp"
#include "gapfe/app/run.hpp"
#include "gapfe/gapfe.hpp"
#include "gapfe/input/deck_scene.hpp"
#include "gapfe/input/input_file.hpp"
#include "gapfe/output/csv_rows.hpp"
#include "gapfe/output/svg_canvas.hpp"
#include "gapfe/output/vtu_writer.hpp"
#include "gapfe/solver/threads.hpp"

#include "deck_support.hpp"
#include "rate_reference.hpp"
#include "support.hpp"

using namespace gapfe;
namespace fs = std::filesystem;

namespace {

/// Rows of a CSV file as maps column name -> value.
std::vector<std::map<std::string, double>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  REQUIRE(in);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream h(line);
  for (std::string n; std::getline(h, n, ',');) names.push_back(n);
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::map<std::string, double> row;
    std::string v;
    for (const auto& n : names) {
      std::getline(s, v, ',');
      // gaps.csv status: 0 open, 1 closed, 2 stick, 3 slip
      row[n] = v == "closed"  ? 1.0
               : v == "open"  ? 0.0
               : v == "stick" ? 2.0
               : v == "slip"  ? 3.0
                              : std::stod(v);
    }
    rows.push_back(row);
  }
  return rows;
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("gapfe_run_test_" + std::to_string(::getpid())) / name;
  fs::create_directories(dir);
  return dir;
}

/// Run `gapfe run` on a deck file; returns the output directory.
fs::path run_deck_file(const fs::path& deck, const std::string& name, std::vector<std::string> extra = {}) {
  const fs::path out            = scratch(name);
  std::vector<std::string> args = {"run", deck.string(), "--out", out.string(), "--quiet"};
  args.insert(args.end(), extra.begin(), extra.end());
  std::ostringstream o, e;
  const int code = gapfe::app::command(args, o, e);
  CAPTURE(e.str());
  REQUIRE(code == 0);
  return out;
}

fs::path write_deck(const std::string& text, const std::string& name) {
  const fs::path p = scratch("decks") / (name + ".deck");
  std::ofstream(p) << text;
  return p;
}

const fs::path kExamples = fs::path(GAPFE_SOURCE_DIR) / "examples" / "decks";

/// The whole file as a string.
std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  REQUIRE(in);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// examples/decks/`example` with its first `from` replaced by `to` (which must be there), written as
/// the scratch deck `name`.
fs::path edited_example(const std::string& example, const std::string& from, const std::string& to,
                        const std::string& name) {
  std::string text = read_text(kExamples / example);
  const auto at    = text.find(from);
  REQUIRE(at != std::string::npos);
  text.replace(at, from.size(), to);
  return write_deck(text, name);
}

}  // namespace

TEST_CASE("Thick-tube example deck: equals the library-API solution to 1e-12 and Lame within 0.5%") {
  const fs::path out = run_deck_file(kExamples / "thick_tube.deck", "thick_tube");
  const auto nodes   = read_csv(out / "nodes.csv");
  REQUIRE(nodes.size() == 27);

  // The same problem through the API: a = 100, b = 200, h = 10, 8 x 2 cells, u_z = 0 on both ends,
  // pressure 100 on the bore, the card's constants (G from the card, not from E and nu).
  using M = Saas;
  Problem<M> p;
  p.mesh = rectangle_mesh<4>(100, 200, 0, 10, 8, 2);
  ElasticConstants c{0,         200000,    200000,    200000, 0.3,    0.3,   0.3,
                     76923.077, 76923.077, 76923.077, 1.2e-5, 1.2e-5, 1.2e-5};
  p.materials = {Orthotropic::constant(c, 7.85e-9)};
  test::fix_plane(p.conditions, p.mesh, 0.0, 2, test::zero3);
  test::fix_plane(p.conditions, p.mesh, 10.0, 2, test::zero3);
  p.edge_loads = test::bore_pressure(p.mesh, 8, 2, 100.0);
  LinearStatic<M> fe(p);
  const auto& u      = fe.solve().displacement;
  const double scale = u.cwiseAbs().maxCoeff();
  const test::Lame lame{100, 200, 100, 200000, 0.3};
  double api = 0, closed = 0;
  for (const auto& row : nodes) {
    const int n = static_cast<int>(row.at("node")) - 1;
    CHECK(row.at("r") == doctest::Approx(p.mesh.nodes[n](0)).epsilon(1e-13));
    CHECK(row.at("z") == doctest::Approx(p.mesh.nodes[n](1)).epsilon(1e-13));
    api    = std::max({api, std::abs(row.at("u_r") - u(n, 0)), std::abs(row.at("u_z") - u(n, 1))});
    closed = std::max(closed, test::rel(row.at("u_r"), lame.displacement(row.at("r"))));
    CHECK(row.at("u_t") == 0.0);
  }
  MESSAGE("deck vs API: " << api / scale << " (relative to max |u|); deck vs Lame u_r: " << closed);
  CHECK(api / scale < 1e-12);
  CHECK(closed < 5e-3);

  // Hoop stress at the element centroids, also within 0.5% of Lame.
  const auto elements = read_csv(out / "elements.csv");
  REQUIRE(elements.size() == 16);
  for (const auto& row : elements) CHECK(test::rel(row.at("s_tt"), lame.hoop_stress(row.at("r"))) < 5e-3);
  CHECK(fs::exists(out / "result.pvd"));
  CHECK(fs::exists(out / "step_0001.vtu"));
}

TEST_CASE("[library] a C++ user's run is the command's: make_plan, check_plan, run; one solver per run") {
  // The thick tube through the library's three calls, as the command makes them (app/command_impl.hpp).
  // A deck becomes a description and its scene, as a scene file does (input/scene.hpp).
  const Deck tube = read_deck(read_input((kExamples / "thick_tube.deck").string(), "deck"));
  const SceneModel model{tube, build_scene(tube), {}, {}};
  const app::Plan plan = app::make_plan(model.description, model.scene);
  CHECK(plan.key == app::VariantKey{VariantChoice::saas, ElementChoice::legacy, app::LawKind::elastic,
                                    PlasticityChoice::return_mapping, ContactChoice::none,
                                    FrictionChoice::none});
  CHECK(plan.solver != SolverChoice::automatic);
  const test::Lame lame{100, 200, 100, 200000, 0.3};
  std::vector<std::map<std::string, double>> by_solver;
  for (const SolverChoice solver : {SolverChoice::eigen, SolverChoice::cholmod}) {
    if (solver == SolverChoice::cholmod && !app::kHasCholmod) continue;
    app::Plan p        = plan;
    p.solver           = solver;  // two solvers in one process: the choice is the run's, not a global
    const fs::path out = scratch(std::string("library_") + std::string(name_of(solver)));
    std::ostringstream err;
    const app::RunRequest request{model.description, model.scene, p, out.string(), err, false, {}, {}};
    const app::RunResult result = app::run(request);
    CHECK(result.equilibrium < 1e-12);
    CHECK(result.step_residual.size() == 1);
    const auto nodes = read_csv(out / "nodes.csv");
    REQUIRE(nodes.size() == 27);
    for (const auto& row : nodes) CHECK(test::rel(row.at("u_r"), lame.displacement(row.at("r"))) < 5e-3);
    by_solver.push_back(nodes.back());
  }
  if (by_solver.size() == 2)
    CHECK(by_solver[0].at("u_r") == doctest::Approx(by_solver[1].at("u_r")).epsilon(1e-10));
  // The command's answer is the library's.
  const auto command_nodes =
      read_csv(run_deck_file(kExamples / "thick_tube.deck", "library_command") / "nodes.csv");
  CHECK(command_nodes.back().at("u_r") == doctest::Approx(by_solver[0].at("u_r")).epsilon(1e-12));

  // A refusal is the same from either side: the plastic tube on the legacy quad.
  const Deck plastic_deck =
      read_deck(read_input((kExamples / "plastic_tube.deck").string(), "deck"), {{"element", "legacy"}});
  const SceneModel plastic{plastic_deck, build_scene(plastic_deck), {}, {}};
  const app::Plan refused = app::make_plan(plastic.description, plastic.scene);
  CHECK(refused.key.law == app::LawKind::plastic);
  CHECK_THROWS_WITH_AS(app::check_plan(refused, plastic.description, plastic.scene),
                       doctest::Contains("a law with history on the legacy quad"), InputError);
  std::ostringstream err;
  const app::RunRequest request{
      plastic.description, plastic.scene, refused, scratch("library_refused").string(), err, false, {}, {}};
  CHECK_THROWS_AS(app::run(request), InputError);
  // The checks a C++ user meets that the command's process set-up made before: a plan made for another
  // model, PETSc without a partitioned run.
  const app::RunRequest other{
      model.description, model.scene, refused, scratch("library_other").string(), err, false, {}, {}};
  CHECK_THROWS_WITH_AS(app::run(other), doctest::Contains("made for another model"), InputError);
  app::Plan petsc = plan;
  petsc.solver    = SolverChoice::petsc;
  if (app::kHasPetsc) {
    const app::RunRequest whole{
        model.description, model.scene, petsc, scratch("library_petsc").string(), err, false, {}, {}};
    CHECK_THROWS_WITH_AS(app::run(whole), doctest::Contains("partitioned"), InputError);
  } else {
    CHECK_THROWS_WITH_AS(app::check_plan(petsc, model.description, model.scene),
                         doctest::Contains("without PETSc"), InputError);
  }
  std::ostringstream o, e;
  CHECK(app::command({"run", (kExamples / "plastic_tube.deck").string(), "--element", "legacy", "--out",
                      scratch("library_refused_command").string()},
                     o, e) == app::input);
  CHECK(e.str().find("a law with history on the legacy quad") != std::string::npos);
}

TEST_CASE(
    "gapfe run warns when element = quad4 meets a Poisson's ratio above 0.49 (locking), and only then") {
  const fs::path nearly_incompressible =
      edited_example("thick_tube.deck", "       0.3       0.3       0.3", "    0.4999    0.4999    0.4999",
                     "nearly_incompressible");
  const std::string warning =
      "warning: element = quad4 with Poisson's ratio 0.4999 (material 1): the bilinear quad locks";
  for (const std::string element : {"quad4", "quad4bbar", "legacy"}) {
    std::ostringstream o, e;
    REQUIRE(gapfe::app::command({"run", nearly_incompressible.string(), "--out",
                                 scratch("locking_" + element).string(), "--quiet", "--element", element},
                                o, e) == 0);
    CAPTURE(e.str());
    CHECK((e.str().find(warning) != std::string::npos) == (element == "quad4"));
  }
  std::ostringstream o, e;  // the example as it is (nu = 0.3): no warning
  REQUIRE(gapfe::app::command({"run", (kExamples / "thick_tube.deck").string(), "--out",
                               scratch("locking_none").string(), "--quiet", "--element", "quad4"},
                              o, e) == 0);
  CHECK(e.str().find("warning") == std::string::npos);
}

TEST_CASE("gapfe run reports each step's relative residual and warns of ill-conditioning above 1e-4") {
  // The two-tube example under the active-set penalty: the residual |K u - f| / |f| grows about like the
  // penalty (tests/test_contact.cpp); at 1e11 x the adjacent stiffness it is about 4e-3.
  const auto run = [](const std::string& penalty, const std::string& name) {
    std::ostringstream o, e;
    REQUIRE(
        gapfe::app::command({"run", (kExamples / "two_tubes.deck").string(), "--out", scratch(name).string(),
                             "--contact", "active-set", "--set", "gap_penalty=" + penalty},
                            o, e) == 0);
    const std::string log = o.str(), key = "equilibrium: largest relative residual |K u - f| / |f| ";
    const auto at = log.find(key);
    REQUIRE(at != std::string::npos);
    const double largest = std::stod(log.substr(at + key.size()));
    // The per-step list: one value for each of the deck's 20 load steps, the largest equal to the above.
    const std::string list = "residual per load step (|K u - f| / |f|, the largest of its increments):";
    const auto from        = log.find(list);
    REQUIRE(from != std::string::npos);
    std::istringstream values(log.substr(from + list.size(), at - from - list.size()));
    std::vector<double> per_step;
    for (double v; values >> v;) per_step.push_back(v);
    CHECK(per_step.size() == 20);
    for (const double v : per_step) CHECK((std::isfinite(v) && v >= 0));
    CHECK(*std::max_element(per_step.begin(), per_step.end()) == largest);
    return std::pair{largest, e.str()};
  };
  const auto [fine, fine_err] = run("100", "residual_fine");
  CHECK(fine < 1e-8);
  CHECK(fine_err.find("warning") == std::string::npos);
  const auto ill_run        = run("1e11", "residual_ill");
  const std::string ill_err = ill_run.second;  // a named variable: CAPTURE's lambda cannot take a binding
  CHECK(ill_run.first > 1e-4);
  CAPTURE(ill_err);
  CHECK(ill_err.find("was solved to a relative residual") != std::string::npos);
  CHECK(ill_err.find("ill-conditioned") != std::string::npos);
}

TEST_CASE("A deck in the smallest (saas) and a richer (saga) variant gives the same displacements to 1e-10") {
  for (const char* element : {"legacy", "quad4"}) {
    CAPTURE(element);
    const auto small = read_csv(
        run_deck_file(kExamples / "thick_tube.deck", std::string("saas_") + element, {"--element", element}) /
        "nodes.csv");
    const auto rich = read_csv(run_deck_file(kExamples / "thick_tube.deck", std::string("saga_") + element,
                                             {"--element", element, "--variant", "saga"}) /
                               "nodes.csv");
    REQUIRE(small.size() == rich.size());
    double scale = 0, diff = 0;
    for (std::size_t k = 0; k < small.size(); ++k)
      for (const char* c : {"u_r", "u_z", "u_t"}) {
        scale = std::max(scale, std::abs(small[k].at(c)));
        diff  = std::max(diff, std::abs(small[k].at(c) - rich[k].at(c)));
      }
    CHECK(diff <= 1e-10 * scale);
  }
}

TEST_CASE("The runner picks the smallest variant and says why; a forced smaller variant is refused") {
  std::ostringstream out, err;
  REQUIRE(gapfe::app::command({"info", (kExamples / "helical_sleeve.deck").string()}, out, err) == 0);
  CHECK(out.str().find("variant: saga (3 DOF per node: ALPHA") != std::string::npos);
  std::ostringstream out2, err2;
  REQUIRE(gapfe::app::command({"info", (kExamples / "thick_tube.deck").string()}, out2, err2) == 0);
  CHECK(out2.str().find("variant: saas") != std::string::npos);
  std::ostringstream out3, err3;
  CHECK(gapfe::app::command({"run", (kExamples / "helical_sleeve.deck").string(), "--out",
                             scratch("refuse").string(), "--variant", "saas"},
                            out3, err3) == gapfe::app::input);
  CHECK(err3.str().find("--variant saas cannot represent this deck") != std::string::npos);
  // Gap decks say what they need: pairs, the soft corner, the policy.
  std::ostringstream out4, err4;
  CHECK(gapfe::app::command(
            {"mesh", (kExamples / "projectile.deck").string(), "--out", scratch("gap_mesh").string()}, out4,
            err4) == 0);
  CHECK(fs::exists(scratch("gap_mesh") / "mesh.svg"));
  CHECK(out4.str().find("gaps: material 2") != std::string::npos);
  CHECK(out4.str().find("32 node pairs, 1 gap element(s) soft throughout") != std::string::npos);
}

TEST_CASE(
    "Two-tube gap deck: closure pressure from gaps.csv; SAAC (one LGAP) equals SAAC2 (IJDIR per block)") {
  // examples/decks/two_tubes.deck: a = 50, b = 75, gap 0.02, c = 100, E = 200000, nu = 0.3, plane strain,
  // bore pressure 100 in 20 steps. Closure (docs/theory.md V5, plane strain): 36.63.
  const double a = 50, b = 75, delta = 0.02, E = 200000, nu = 0.3;
  const double pc = delta * E * (b * b - a * a) / (2 * a * a * b * (1 - nu * nu));
  for (const char* policy : {"saac", "active-set", "augmented-lagrangian"}) {
    CAPTURE(policy);
    const fs::path out =
        run_deck_file(kExamples / "two_tubes.deck", std::string("tubes_") + policy, {"--contact", policy});
    std::ifstream in(out / "gaps.csv");
    std::string header, line;
    std::getline(in, header);
    CHECK(header == "step,inc,t,element,pair,node_a,node_b,status,gap,f_n,f_t");
    // The closure load: the last increment with every pair open, just before the first closed row.
    double last_open = 0, closed_at = -1;
    while (std::getline(in, line) && closed_at < 0) {
      std::stringstream s(line);
      std::vector<std::string> f;
      for (std::string v; std::getline(s, v, ',');) f.push_back(v);
      REQUIRE(f.size() == 11);
      if (f[7] == "closed")
        closed_at = last_open;
      else
        last_open = std::stod(f[1]);
    }
    const double p_closure = closed_at / 20 * 100;
    CHECK(std::abs(p_closure - pc) / pc < 5e-3);  // 20 legacy elements across each tube
    // deformed.svg shows the last increment: at 100 > p_c every gap element is closed (red), none open.
    const std::string svg = read_text(out / "deformed.svg");
    CHECK(svg.find("fill=\"#d62728\"") != std::string::npos);
    CHECK(svg.find("fill=\"#1f77b4\"") == std::string::npos);
    if (std::string(policy) == "active-set") {
      const fs::path saac  = run_deck_file(kExamples / "two_tubes.deck", "tubes_lgap",
                                           {"--contact", policy, "--set", "gap_direction=1"});
      const auto per_block = read_csv(out / "nodes.csv"), global = read_csv(saac / "nodes.csv");
      REQUIRE(per_block.size() == global.size());
      double worst = 0, largest = 0;
      for (std::size_t k = 0; k < global.size(); ++k)
        worst   = std::max(worst, std::abs(per_block[k].at("u_r") - global[k].at("u_r"))),
        largest = std::max(largest, std::abs(global[k].at("u_r")));
      CHECK(worst <= 1e-12 * largest);
    }
  }
}

TEST_CASE("Load steps: a block given once (INCF = 0) ramps uniformly; per-step blocks add up") {
  using gapfe::test::Card;
  auto lines = gapfe::test::lines_of(gapfe::test::tube_deck());
  // NLINC = 4, INCF = 0: the pressure cards of block 1 repeat in every step.
  lines[2] = Card().i(1, 5, 1).i(11, 15, 1).i(16, 20, 2).f(31, 35, "70").i(41, 45, 4).str();
  const auto ramp =
      read_csv(run_deck_file(write_deck(gapfe::test::join(lines), "ramp"), "ramp") / "nodes.csv");
  const auto one = read_csv(run_deck_file(write_deck(gapfe::test::tube_deck(), "one"), "one") / "nodes.csv");
  REQUIRE(ramp.size() == 4 * one.size());
  for (std::size_t k = 0; k < ramp.size(); ++k) {
    const auto& base = one[k % one.size()];
    const double s   = ramp[k].at("step");
    CHECK(ramp[k].at("inc") == s);
    CHECK(ramp[k].at("u_r") == doctest::Approx(s * base.at("u_r")).epsilon(1e-12));
  }
  // INCF = 1, NLINC = 2: step 2 gives its own cards (pressure 50): totals 100, then 150.
  lines[2] = Card().i(1, 5, 1).i(11, 15, 1).i(16, 20, 2).f(31, 35, "70").i(41, 45, 2).i(51, 55, 1).str();
  lines.push_back(Card().i(1, 5, 6).i(6, 10, 1).f(11, 20, "50.").str());
  lines.push_back(Card().i(1, 5, 11).i(6, 10, 6).f(11, 20, "50.").str());
  const auto blocks =
      read_csv(run_deck_file(write_deck(gapfe::test::join(lines), "blocks"), "blocks") / "nodes.csv");
  REQUIRE(blocks.size() == 2 * one.size());
  for (std::size_t k = 0; k < one.size(); ++k) {
    CHECK(blocks[k].at("u_r") == doctest::Approx(one[k].at("u_r")).epsilon(1e-12));
    CHECK(blocks[one.size() + k].at("u_r") == doctest::Approx(1.5 * one[k].at("u_r")).epsilon(1e-12));
  }
}

TEST_CASE("NUMTC = -2: a constant temperature expands a free tube by alpha dT r") {
  using gapfe::test::Card;
  auto lines = gapfe::test::lines_of(gapfe::test::tube_deck());
  // TREF 20, T 120, no pressure, u_z = 0 only at J = 1: free expansion u_r = alpha dT r, u_z = alpha dT z.
  lines[2] = Card().i(1, 5, 1).i(6, 10, -2).i(11, 15, 1).f(31, 35, "20.").i(41, 45, 1).str();
  lines[3] = Card().i(1, 5, 5).i(6, 10, 3).i(11, 15, 4).i(16, 20, 1).i(21, 25, 1).str();
  lines.erase(lines.begin() + 14, lines.end());  // no pressure cards
  lines.erase(lines.begin() + 9);                // one BC card
  lines.insert(lines.begin() + 10, Card().f(1, 10, "120.").str());
  const auto rows =
      read_csv(run_deck_file(write_deck(gapfe::test::join(lines), "thermal"), "thermal") / "nodes.csv");
  const double strain = 1.2e-5 * 100.0;
  for (const auto& row : rows) {
    CHECK(row.at("u_r") == doctest::Approx(strain * row.at("r")).epsilon(1e-9));
    CHECK(std::abs(row.at("u_z") - strain * row.at("z")) < 1e-9 * strain);
  }
}

TEST_CASE("bc_loads = per-radian multiplies BC-card loads by 2 pi; prescribed values are unchanged") {
  using gapfe::test::Card;
  auto lines = gapfe::test::lines_of(gapfe::test::tube_deck());
  // Replace the pressure by a BC-card radial load on the bore nodes (I = 1): XR = 10 per node.
  lines[2] = Card().i(1, 5, 1).i(11, 15, 1).f(31, 35, "70").i(41, 45, 1).str();
  lines[3] = Card().i(1, 5, 5).i(6, 10, 3).i(11, 15, 4).i(16, 20, 3).i(21, 25, 1).str();
  lines.erase(lines.begin() + 14, lines.end());
  lines.insert(lines.begin() + 10,
               Card().i(1, 5, 1).i(6, 10, 1).i(11, 15, 1).i(16, 20, 3).i(21, 30, 2).f(31, 40, "10.").str());
  const std::string total = gapfe::test::join(lines);
  const auto a            = read_csv(run_deck_file(write_deck(total, "total"), "total") / "nodes.csv");
  const auto b            = read_csv(
                 run_deck_file(write_deck(total, "radian"), "radian", {"--set", "bc_loads=per-radian"}) / "nodes.csv");
  for (std::size_t k = 0; k < a.size(); ++k) {
    CHECK(b[k].at("u_r") == doctest::Approx(kTwoPi * a[k].at("u_r")).epsilon(1e-12));
    CHECK(b[k].at("u_z") == doctest::Approx(kTwoPi * a[k].at("u_z")).epsilon(1e-12));
  }
}

TEST_CASE("Deck needs: theta loads, transverse shear, angular acceleration and ALPHA each ask for 3 DOF") {
  using gapfe::test::Card;
  const auto needs = [](const std::string& text) { return build_scene(read_deck(text)).needs; };
  auto lines       = gapfe::test::lines_of(gapfe::test::tube_deck());
  CHECK_FALSE(needs(gapfe::test::join(lines)).needs_theta());
  auto alpha = lines;
  alpha[10]  = Card().i(1, 5, 1).i(6, 10, 1).i(11, 15, 5).i(16, 20, 1).i(21, 25, 3).f(36, 45, "15.").str();
  CHECK(needs(gapfe::test::join(alpha)).theta.front().find("ALPHA") != std::string::npos);
  auto theta = lines;
  theta[8]   = Card().i(1, 5, 1).i(6, 10, 5).i(11, 15, 1).i(16, 20, 1).i(21, 30, 6).f(51, 60, "1.").str();
  CHECK(needs(gapfe::test::join(theta)).theta.front().find("theta displacement") != std::string::npos);
  auto fixed = lines;  // u_theta = 0 prescribed is not a theta load
  fixed[8]   = Card().i(1, 5, 1).i(6, 10, 5).i(11, 15, 1).i(16, 20, 1).i(21, 30, 6).str();
  CHECK_FALSE(needs(gapfe::test::join(fixed)).needs_theta());
  auto shear = lines;  // NUMST = 1 with a transverse shear card
  shear[2]   = Card().i(1, 5, 1).i(11, 15, 1).i(16, 20, 2).i(26, 30, 1).f(31, 35, "70").i(41, 45, 1).str();
  shear.push_back(Card().i(1, 5, 6).i(6, 10, 1).f(11, 20, "5.").str());
  CHECK(needs(gapfe::test::join(shear)).theta.front().find("transverse shear") != std::string::npos);
  auto spin = lines;  // INERT = 1: inertia card before the pressure cards, ANGACC != 0
  spin[2]   = Card().i(1, 5, 1).i(11, 15, 1).i(16, 20, 2).f(31, 35, "70").i(36, 40, 1).i(41, 45, 1).str();
  spin.insert(spin.begin() + 14, Card().f(21, 30, "3.").str());
  CHECK(needs(gapfe::test::join(spin)).theta.front().find("ANGACC") != std::string::npos);
}

TEST_CASE("Plastic tube deck: yield cards run Hill plasticity; eqps in elements.csv; both integrations") {
  // examples/decks/plastic_tube.deck: a = 100, b = 200, Mises sigma_y = 400 (card 11), nu = 0.3, plane
  // strain, bore pressure to 300 in 15 steps. Closed forms (docs/theory.md V6): no yield before p ~ 173 (step
  // 8 at 20 per step is 160: all elastic), and 300 < p_L = 320.15, so the outer wall stays elastic.
  std::map<std::string, std::vector<std::map<std::string, double>>> bore;
  for (const char* integration : {"return-mapping", "tangent"}) {
    CAPTURE(integration);
    const fs::path out = run_deck_file(kExamples / "plastic_tube.deck", std::string("plastic_") + integration,
                                       {"--plasticity", integration});
    const auto elements = read_csv(out / "elements.csv");
    REQUIRE(elements.size() == 15 * 40);
    for (const auto& row : elements) {
      if (row.at("step") <= 8) CHECK(row.at("eqps") == 0);
      if (row.at("step") == 15 && row.at("element") == 1) CHECK(row.at("eqps") > 0);
      if (row.at("step") == 15 && row.at("element") == 40) CHECK(row.at("eqps") == 0);
    }
    bore[integration] = read_csv(out / "nodes.csv");
    // plasticity.csv: one row per increment; return-mapping converges to its tolerance, tangent solves once.
    std::ifstream record(out / "plasticity.csv");
    std::string line;
    std::getline(record, line);
    CHECK(line == "step,inc,t,iterations,plastic_points,drift,time_error,residuals");
    int rows = 0;
    while (std::getline(record, line)) {
      ++rows;
      std::stringstream fields(line);
      std::vector<std::string> f;
      for (std::string v; std::getline(fields, v, ',');) f.push_back(v);
      REQUIRE(f.size() == 8);
      CHECK(std::stod(f[2]) == std::stod(f[1]));  // t = inc: no rate card, a step lasts 1
      CHECK(std::stod(f[6]) == 0);                // time_error: no rate law, no estimate
      const double last = std::stod(
          f[7].substr(f[7].find_last_of(' ') == std::string::npos ? 0 : f[7].find_last_of(' ') + 1));
      if (std::string(integration) == "return-mapping")
        CHECK(last <= 1e-10);
      else
        CHECK(std::stoi(f[3]) == 1);
    }
    CHECK(rows == 15);
  }
  // The seed's tangent scheme against Newton. Tangent is forward Euler in the load with equilibrium
  // correction (docs/theory.md 7.2), so its difference to the return mapping must fall at least linearly with
  // the step size: the same deck in 15, 30 and 60 steps of 300 / n, the ratio of successive differences
  // >= 1.8 (2 for exactly first order, less a margin for the higher-order terms). An earlier version of
  // this test asked for 5% at 15 steps; the difference there is 5.2%, and that check never ran (ctest
  // skipped case names with ';', tests/CMakeLists.txt).
  const auto& rm = bore["return-mapping"].back();
  std::ifstream deck_file(kExamples / "plastic_tube.deck");
  std::vector<std::string> deck_lines;
  for (std::string line; std::getline(deck_file, line);) deck_lines.push_back(line);
  REQUIRE(deck_lines.size() > 14);
  std::vector<double> difference;
  for (const int steps : {15, 30, 60}) {
    CAPTURE(steps);
    std::vector<std::string> lines = deck_lines;
    REQUIRE(lines[2].substr(40, 5) == "   15");  // control card: NLINC in columns 41-45
    char field[16];
    std::snprintf(field, sizeof field, "%5d", steps);
    lines[2].replace(40, 5, field);
    REQUIRE(lines[14].substr(0, 10) == "   42    1");  // the load card: 20 per step in columns 11-20
    char value[16];
    std::snprintf(value, sizeof value, "%10.4f", 300.0 / steps);
    lines[14] = lines[14].substr(0, 10) + value;
    const fs::path out =
        run_deck_file(write_deck(gapfe::test::join(lines), "tangent_" + std::to_string(steps)),
                      "tangent_" + std::to_string(steps), {"--plasticity", "tangent"});
    const auto tg = read_csv(out / "nodes.csv").back();
    REQUIRE(tg.at("step") == steps);
    difference.push_back(std::abs(tg.at("u_r") - rm.at("u_r")) / std::abs(rm.at("u_r")));
    MESSAGE("outer u_r: return-mapping (15 steps) " << rm.at("u_r") << ", tangent (" << steps << " steps) "
                                                    << tg.at("u_r") << ", difference " << difference.back());
  }
  CHECK(difference[1] <= difference[0] / 1.8);
  CHECK(difference[2] <= difference[1] / 1.8);

  // output = last: the result files hold the last increment only, the same rows the full run wrote for it;
  // plasticity.csv still has every increment.
  {
    const fs::path all  = scratch("plastic_return-mapping");
    const fs::path last = run_deck_file(kExamples / "plastic_tube.deck", "plastic_last",
                                        {"--plasticity", "return-mapping", "--output", "last"});
    for (const char* file : {"nodes.csv", "elements.csv", "reactions.csv"}) {
      CAPTURE(file);
      const auto every = read_csv(all / file), only = read_csv(last / file);
      std::vector<std::map<std::string, double>> final_rows;
      for (const auto& row : every)
        if (row.at("step") == 15) final_rows.push_back(row);
      REQUIRE(!final_rows.empty());
      CHECK(only == final_rows);
    }
    CHECK(fs::exists(last / "step_0015.vtu"));
    CHECK(!fs::exists(last / "step_0014.vtu"));
    std::ifstream record(last / "plasticity.csv");
    int rows = -1;
    for (std::string line; std::getline(record, line);) ++rows;
    CHECK(rows == 15);
  }
  // Per kind: the tables of the last increment with the VTU series of every one; none writes neither,
  // and the run's record and picture stay.
  {
    const fs::path mixed = run_deck_file(kExamples / "plastic_tube.deck", "plastic_mixed",
                                         {"--plasticity", "return-mapping", "--set", "output_csv=last"});
    CHECK(read_csv(mixed / "nodes.csv").front().at("step") == 15);
    CHECK(fs::exists(mixed / "step_0014.vtu"));
    CHECK(fs::exists(mixed / "step_0015.vtu"));
    const fs::path none = run_deck_file(kExamples / "plastic_tube.deck", "plastic_none",
                                        {"--plasticity", "return-mapping", "--output", "none"});
    for (const char* file : {"nodes.csv", "elements.csv", "reactions.csv", "result.pvd", "step_0015.vtu"}) {
      CAPTURE(file);
      CHECK(!fs::exists(none / file));
    }
    CHECK(fs::exists(none / "plasticity.csv"));
    CHECK(fs::exists(none / "deformed.svg"));
  }

  std::ostringstream o, e;
  CHECK(gapfe::app::command({"run", (kExamples / "plastic_tube.deck").string(), "--out",
                             scratch("plastic_legacy").string(), "--element", "legacy"},
                            o, e) == gapfe::app::input);
  CHECK(e.str().find("element = legacy") != std::string::npos);
  CHECK(e.str().find("condensed centre node is not in the plastic driver") != std::string::npos);
}

TEST_CASE(
    "A plastic deck loaded past its limit load: a clear error naming the step, exit 2, and every "
    "accepted increment on disk") {
  // examples/decks/plastic_tube.deck with 30 instead of 20 per step: 15 steps to 450 against the limit
  // p_L = (2 / sqrt 3) 400 ln 2 = 320.15 of the perfectly plastic tube (docs/theory.md V6; Mises at nu = 0.3
  // is within ~1% of it). Steps 1-10 (to 300) must be accepted; step 11 (330) has no equilibrium: the
  // cut-back halves it down to 1/64 and then gives up past load factor 10 + k / 64, p < p_L.
  // With two threads each increment's files are written while the next computes (app/run_output_impl.hpp):
  // the failing step's work then meets a write under way, which must still end whole.
  const gapfe::test::OneThreadAfter restore;
  const fs::path deck =
      edited_example("plastic_tube.deck", "   42    1      20.0", "   42    1      30.0", "past_the_limit");
  for (const char* threads : {"1", "2"}) {
    CAPTURE(threads);
    const fs::path out = scratch(std::string("past_the_limit_") + threads);
    std::ostringstream o, e;
    const int code = gapfe::app::command(
        {"run", deck.string(), "--out", out.string(), "--quiet", "--threads", threads}, o, e);
    CAPTURE(e.str());
    CHECK(code == gapfe::app::Exit::solve);
    CHECK(e.str().find("load step 11 fails even when cut to 1/64, past load factor 10") != std::string::npos);
    CHECK(e.str().find("limit (collapse) load") != std::string::npos);
    // The accepted increments: all 10 whole steps, then pieces of step 11 below the limit.
    const auto nodes = read_csv(out / "nodes.csv");
    std::map<double, int> rows_per_increment;
    for (const auto& row : nodes) ++rows_per_increment[row.at("inc")];
    REQUIRE(rows_per_increment.size() > 10);
    for (const auto& [inc, rows] : rows_per_increment) CHECK(rows == 82);  // 41 x 2 nodes, no torn increment
    const double last = rows_per_increment.rbegin()->first;
    CHECK(last >= 10);
    CHECK(last < 11);
    CHECK(20.0 * 1.5 * last <= 320.15 * 1.01);  // the pressure reached stays below the limit load
    // The ParaView collection is closed and names only files that exist.
    const std::string collection = read_text(out / "result.pvd");
    CHECK(collection.rfind("</VTKFile>") != std::string::npos);
    int listed = 0;
    for (std::size_t at = collection.find("file=\""); at != std::string::npos;
         at             = collection.find("file=\"", at + 1), ++listed) {
      const std::size_t begin = at + 6, end = collection.find('"', begin);
      CHECK(fs::exists(out / collection.substr(begin, end - begin)));
    }
    CHECK(listed == static_cast<int>(rows_per_increment.size()));
  }
}

TEST_CASE(
    "SAAC3X deck: card 0's STRSTEP then STRRATE drive a thin tube to docs/theory.md 8.7's steady state") {
  // examples/decks/saac3x_tube.deck (bench/deckgen.py saac3x_deck): a tube 999..1000 mm, 1 mm long, one
  // cell, Mises sigma_0 = 400 MPa, b = 0.05, rate_0 = 1e-3 / s; STRSTEP = 230.94 MPa on the top face in
  // step 1, then STRRATE = 1 / s through u_z of the top face, 150 steps of 5e-5 s (lambda dt 0.85 at the
  // steady state). No BC or load card: the command drives the faces. Reference: the steady state of the
  // ODE (tests/rate_reference.hpp): axial stress and twist rate within 1%, no increment's axial stress
  // above it by more than 1e-6, and never falling (the exact response rises monotonically).
  const auto exact = gapfe::test::RateReference{400, 0.05, 1e-3}.saac3x_steady(230.94, 1.0);
  const double dt = 5e-5, r_mid = 999.5, length = 1.0;
  for (const char* integration : {"return-mapping", "tangent"}) {
    CAPTURE(integration);
    std::ostringstream o, e;
    const fs::path out = scratch(std::string("saac3x_") + integration);
    REQUIRE(gapfe::app::command({"run", (kExamples / "saac3x_tube.deck").string(), "--out", out.string(),
                                 "--plasticity", integration},
                                o, e) == 0);
    CHECK(o.str().find("saac3x: constant strain rate 1 over L = 1: u_z = rate L (t - delta t) on the 2 nodes "
                       "at z = 1 from step 2 on") != std::string::npos);
    const auto elements = read_csv(out / "elements.csv");
    const auto nodes    = read_csv(out / "nodes.csv");
    // One row per increment: the 150 steps, and under return-mapping the pieces time_tolerance cut some into.
    REQUIRE(std::count_if(elements.begin(), elements.end(),
                          [](const auto& row) { return row.at("inc") == std::floor(row.at("inc")); }) == 150);
    REQUIRE(elements.back().at("inc") == 150);
    double overshoot = 0, fall = 0, previous = 0;
    for (const auto& row : elements) {
      const double s = row.at("s_zz");
      overshoot      = std::max(overshoot, (s - exact.sigma) / exact.sigma);
      fall           = std::max(fall, (previous - s) / exact.sigma);
      previous       = s;
    }
    // The top face's u_z is the imposed one, and its mean rotation u_theta / r gives the twist rate.
    std::map<double, double> twist;  // inc -> mean u_theta / r on the top face
    for (const auto& row : nodes) CHECK(row.at("t") == doctest::Approx(row.at("inc") * dt).epsilon(1e-12));
    // The faces SAAC3X drives have reactions: the top's axial force is the axial stress times the area.
    double axial_force = 0;
    for (const auto& row : read_csv(out / "reactions.csv"))
      if (row.at("inc") == 150 && row.at("z") == length) axial_force += row.at("R_z");
    const double area = 0.5 * kTwoPi * (1000.0 * 1000.0 - 999.0 * 999.0);
    CHECK(axial_force == doctest::Approx(elements.back().at("s_zz") * area).epsilon(1e-3));
    for (const auto& row : nodes)
      if (row.at("z") == length) {
        CHECK(row.at("u_z") == doctest::Approx(1.0 * length * dt * (row.at("inc") - 1)).epsilon(1e-12));
        twist[row.at("inc")] += 0.5 * row.at("u_t") / row.at("r");
      }
    const double twist_rate = (twist[150] - twist[149]) * r_mid / length / dt;
    const double sigma      = elements.back().at("s_zz");
    MESSAGE(std::string(integration) << ": axial stress " << sigma << " MPa against " << exact.sigma
                                     << ", twist rate " << twist_rate << " / s against " << exact.twist_rate
                                     << "; overshoot " << overshoot << ", largest fall " << fall);
    CHECK(overshoot <= 1e-6);
    if (std::string(integration) == "return-mapping") {
      CHECK(std::abs(sigma - exact.sigma) <= 0.01 * exact.sigma);
      CHECK(std::abs(twist_rate - exact.twist_rate) <= 0.01 * exact.twist_rate);
      CHECK(fall <= 1e-9);
    }
  }
  // Blank STRRATE and STRSTEP: nothing is driven (an ordinary SAAC3 deck; this one has no BC cards).
  std::ifstream file(kExamples / "saac3x_tube.deck");
  std::vector<std::string> lines;
  for (std::string line; std::getline(file, line);) lines.push_back(line);
  REQUIRE(lines.size() > 3);
  REQUIRE(lines[2].size() >= 60);
  lines[2].replace(36, 24, std::string(24, ' '));
  std::ostringstream o, e;
  CHECK(gapfe::app::command({"info", write_deck(gapfe::test::join(lines), "saac3x_blank").string()}, o, e) ==
        0);
  CHECK(o.str().find("saac3x:") == std::string::npos);
  CHECK(o.str().find("variant: saas") != std::string::npos);
}

TEST_CASE("Rate-dependent tube deck (SAAC3): card 0 with b != 0 runs Drysdale-Zak in the deck's time") {
  // examples/decks/rate_tube.deck is plastic_tube.deck with card 0: each step lasts 1 ms, b = 0.05,
  // rate_0 = 1e-3 / s. The bore then strains at about 1 / s, where the yield stress is about 1.35 sigma_0
  // (seed Eq. 17), so the tube yields later and less than the rate-independent one. The same deck with b =
  // 1e-9 is the rate-independent tube (the rate term is then below 1e-8 of the yield stress).
  std::ifstream file(kExamples / "rate_tube.deck");
  std::vector<std::string> lines;
  for (std::string line; std::getline(file, line);) lines.push_back(line);
  REQUIRE(lines.size() > 3);
  REQUIRE(lines[2].substr(12, 12) == " 5.00000E-02");  // card 0: b in columns 13-24
  const auto plastic =
      read_csv(run_deck_file(kExamples / "plastic_tube.deck", "rate_reference") / "nodes.csv");
  for (const char* integration : {"return-mapping", "tangent"}) {
    CAPTURE(integration);
    std::ostringstream o, e;
    const fs::path out = scratch(std::string("rate_tube_") + integration);
    REQUIRE(gapfe::app::command({"run", (kExamples / "rate_tube.deck").string(), "--out", out.string(),
                                 "--plasticity", integration},
                                o, e) == 0);
    const std::string log = o.str();
    CHECK(log.find("rate: rate-dependent " + std::string(integration)) != std::string::npos);
    CHECK(log.find("card 0 has b = 0.05 != 0") != std::string::npos);
    CHECK(log.find("step 15, inc 15 (t = 0.015): lambda dt") != std::string::npos);
    const auto rate = read_csv(out / "nodes.csv");
    // return-mapping cuts the steps to time_tolerance: more increments, the same last one.
    REQUIRE(rate.back().at("inc") == plastic.back().at("inc"));
    REQUIRE(rate.back().at("node") == plastic.back().at("node"));
    // Outer wall u_r at the end: elastic there, so it measures the load the plastic zone passes on.
    const double u_rate = rate.back().at("u_r"), u_plain = plastic.back().at("u_r");
    MESSAGE(std::string(integration) << ": outer u_r " << u_rate << " (rate-independent " << u_plain << ")");
    if (std::string(integration) == "return-mapping") CHECK(u_rate < u_plain);
    // b -> 0: the rate-independent answer.
    std::vector<std::string> tiny = lines;
    tiny[2].replace(12, 12, " 1.00000E-09");
    const fs::path limit =
        run_deck_file(write_deck(gapfe::test::join(tiny), std::string("rate_limit_") + integration),
                      std::string("rate_limit_") + integration, {"--plasticity", integration});
    const double u_limit = read_csv(limit / "nodes.csv").back().at("u_r");
    const double u_ref   = std::string(integration) == "return-mapping"
                               ? u_plain
                               : read_csv(run_deck_file(kExamples / "plastic_tube.deck",
                                                        "rate_reference_tangent", {"--plasticity", "tangent"}) /
                                          "nodes.csv")
                                   .back()
                                   .at("u_r");
    MESSAGE(std::string(integration) << ": b = 1e-9 gives " << u_limit << " against " << u_ref);
    // The seed's scheme with any b > 0 puts each step back on the surface (dK = level^2 - f) where
    // SAGAEP's keeps its drift, so its limit differs by that drift; the implicit return has none.
    if (std::string(integration) == "return-mapping")
      CHECK(std::abs(u_limit - u_ref) <= 1e-6 * std::abs(u_ref));
  }
  // Card 0 errors name the card.
  std::vector<std::string> bad = lines;
  bad[2].replace(0, 12, " 0.00000E+00");
  std::ostringstream o, e;
  CHECK(gapfe::app::command({"run", write_deck(gapfe::test::join(bad), "rate_bad").string(), "--out",
                             scratch("rate_bad").string()},
                            o, e) == gapfe::app::input);
  CHECK(e.str().find("DATA NO. 0 (rate property card), line 3, columns 1-12") != std::string::npos);
}

TEST_CASE("Plastic tube in a tube deck: SAAC = SAGAEP + gaps, closure and yield in one run") {
  // examples/decks/plastic_two_tubes.deck: the two-tube deck with a Mises inner tube (sigma_y = 250) and
  // bore pressure to 200: the gap closes near 36.6 (elastic, V5), the inner bore yields later.
  const fs::path out  = run_deck_file(kExamples / "plastic_two_tubes.deck", "plastic_two_tubes");
  const auto gaps     = read_csv(out / "gaps.csv");
  const auto elements = read_csv(out / "elements.csv");
  REQUIRE(!gaps.empty());
  const double last_inc = gaps.back().at("inc");
  int closed = 0, rows = 0;
  for (const auto& g : gaps)
    if (g.at("inc") == last_inc) ++rows, closed += g.at("status") == 1 && g.at("f_n") > 0;
  CHECK(rows > 0);
  CHECK(closed == rows);
  double inner_eqps = 0, outer_eqps = 0;
  for (const auto& e : elements) {
    if (e.at("inc") != last_inc) continue;
    (e.at("material") == 1 ? inner_eqps : outer_eqps) =
        std::max(e.at("material") == 1 ? inner_eqps : outer_eqps, e.at("eqps"));
  }
  CHECK(inner_eqps > 0);
  CHECK(outer_eqps == 0);
}

TEST_CASE("Press-fit example deck: Coulomb push-out at mu p 2 pi b L, stick then slip, reactions.csv") {
  // examples/decks/press_fit.deck (mm, N, MPa; nu = 0): hub 25.001-50 on a shaft 12.5-25, 50 long, 75 on
  // its outer surface, pushed 40 x 1 um. Closed form: q_c = w E (c^2 - b^2) / (2 b c^2), p = (q - q_c)
  // c^2 (b^2 - a^2) / (b^2 (c^2 - a^2)), F = mu p 2 pi b L = 67858 N.
  const double a = 12.5, b = 25, w = 0.001, c = 50, L = 50, E = 200000, q = 75, mu = 0.15;
  const double qc      = w * E * (c * c - b * b) / (2 * b * c * c);
  const double F       = mu * (q - qc) * c * c * (b * b - a * a) / (b * b * (c * c - a * a)) * kTwoPi * b * L;
  const fs::path out   = run_deck_file(kExamples / "press_fit.deck", "press_fit");
  const auto reactions = read_csv(out / "reactions.csv");
  const auto gaps      = read_csv(out / "gaps.csv");
  const double last    = reactions.back().at("inc");
  double push = 0, shaft = 0;
  for (const auto& r : reactions) {
    if (r.at("inc") != last) continue;
    CHECK(r.at("R_r") == 0);  // only u_z is prescribed: free components are written as 0
    (r.at("r") > b + w / 2 ? push : shaft) += r.at("R_z");
  }
  double friction = 0;
  for (const auto& g : gaps)
    if (g.at("inc") == last) friction += mu * g.at("f_n");
  MESSAGE("push-out force ", -push, " N, mu sum f_n ", friction, ", closed form ", F);
  CHECK(std::abs(-push - F) < 0.01 * F);
  CHECK(std::abs(-push - friction) < 1e-3 * friction);
  CHECK(std::abs(push + shaft) < 1e-6 * F);  // the shaft's support takes what the hub is pushed with
  // Statuses: the closed pairs stick first (a slip front starts at the pushed end), all slip at the end.
  bool stuck_once     = false;
  int slipping_at_end = 0, rows_at_end = 0;
  for (const auto& g : gaps) {  // status: 2 stick, 3 slip
    stuck_once = stuck_once || g.at("status") == 2;
    if (g.at("inc") == last) ++rows_at_end, slipping_at_end += g.at("status") == 3;
  }
  CHECK(stuck_once);
  CHECK(rows_at_end > 0);
  CHECK(slipping_at_end == rows_at_end);
  // The seed's two models run on it too.
  for (const char* slip : {"extended", "proportional"})
    run_deck_file(kExamples / "press_fit.deck", std::string("press_fit_") + slip,
                  {"--set", "contact=saac", "--set", std::string("slip=") + slip});
}

TEST_CASE("Friction input errors: one line naming the key, a non-zero exit, no result files") {
  const auto refused = [&](const fs::path& deck, std::vector<std::string> set, const std::string& expect) {
    const fs::path out            = scratch("refused_" + std::to_string(std::hash<std::string>{}(expect)));
    std::vector<std::string> args = {"run", deck.string(), "--out", out.string(), "--quiet"};
    for (const auto& s : set) args.push_back("--set"), args.push_back(s);
    std::ostringstream o, e;
    const int code            = gapfe::app::command(args, o, e);
    const std::string message = e.str();
    CAPTURE(message);
    CHECK(code == 1);
    CHECK(message.find(expect) != std::string::npos);
    CHECK(std::count(message.begin(), message.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(out / "nodes.csv"));
  };
  const fs::path fit = kExamples / "press_fit.deck";
  refused(fit, {"friction=-0.1"}, "friction");
  refused(fit, {"slip=sticky"}, "slip");
  refused(kExamples / "thick_tube.deck", {"friction=0.2"}, "no gap elements");
  refused(fit, {"contact=saac", "slip=coulomb"}, "exact contact policy");
  refused(fit, {"contact=augmented-lagrangian", "slip=extended"}, "contact = saac");
  refused(fit, {"contact=none"}, "contact = none");
  refused(kExamples / "plastic_two_tubes.deck",
          {"friction=0.2", "contact=active-set", "slip=coulomb", "plasticity=tangent"}, "return-mapping");
}

// ------------------------------------------------------------------ Newton and load-step extremes

namespace {
/// `text` with its first `from` replaced by `to` (which must be there).
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}
const std::string kPlasticControl = "    1    0    1    1    0    0  0.0    0   15    0    0    0";
const std::string kPlasticLoad    = "   42    1      20.0";
}  // namespace

TEST_CASE(
    "Newton at round-off: a nearly singular tangent (hardening E / 2e5 at 3 p_L in one step) is accepted "
    "once its residual stops falling below 100 x the tolerance, with a warning") {
  // Before NewtonOptions::stall_factor the residuals wandered between 1.5e-10 and 2.6e-10 against 1e-10
  // for 30 iterations and the step failed even when cut to 1/64.
  std::string text = read_text(kExamples / "plastic_tube.deck");
  text = replaced(text, kPlasticControl, "    1    0    1    1    0    0  0.0    0    1    0    0    0");
  text = replaced(text, kPlasticLoad, "   42    1     960.0");          // 3 p_L at once
  text = replaced(text, "230.94011       0.0", "230.94011       1.0");  // c = 1 MPa
  const fs::path deck = write_deck(text, "round_off"), out = scratch("round_off");
  std::ostringstream o, e;
  const int code = gapfe::app::command({"run", deck.string(), "--out", out.string(), "--quiet"}, o, e);
  CAPTURE(e.str());
  REQUIRE(code == 0);
  CHECK(e.str().find("stopped where the residual stopped falling") != std::string::npos);
  const auto record = read_csv(out / "plasticity.csv");
  REQUIRE(record.size() == 1);  // one increment: no cut was needed
  CHECK(record[0].at("iterations") <= 30);
  for (const auto& row : read_csv(out / "nodes.csv")) REQUIRE(std::isfinite(row.at("u_r")));
  // The last residual of the record (space-separated) is within the stall bound.
  const std::string residuals = gapfe::test::lines_of(read_text(out / "plasticity.csv")).at(1);
  const double last           = std::stod(residuals.substr(residuals.find_last_of(" ,") + 1));
  CHECK(last <= 100 * 1e-10);
}

TEST_CASE(
    "Cut-back rescues a step Newton cannot take whole: the example's pressure 300 in one step with "
    "newton_iterations = 3 is cut in halves, and the halves equal a deck of two steps of 150") {
  std::string text = read_text(kExamples / "plastic_tube.deck");
  text = replaced(text, kPlasticControl, "    1    0    1    1    0    0  0.0    0    1    0    0    0");
  const fs::path whole = write_deck(replaced(text, kPlasticLoad, "   42    1     300.0"), "cut_whole");
  const fs::path two =
      write_deck(replaced(replaced(read_text(kExamples / "plastic_tube.deck"), kPlasticControl,
                                   "    1    0    1    1    0    0  0.0    0    2    0    0    0"),
                          kPlasticLoad, "   42    1     150.0"),
                 "cut_two");
  const fs::path cut = run_deck_file(whole, "cut_whole", {"--set", "newton_iterations=3"});
  const fs::path ref = run_deck_file(two, "cut_two", {"--set", "newton_iterations=3"});
  // The whole step needs more than 3 iterations: without the cut the run fails.
  {
    std::ostringstream o, e;
    const fs::path out = scratch("cut_fails");
    CHECK(gapfe::app::command(
              {"run", whole.string(), "--out", out.string(), "--quiet", "--set", "newton_iterations=1"}, o,
              e) == gapfe::app::Exit::solve);
    CHECK(e.str().find("fails even when cut to 1/64") != std::string::npos);
  }
  const auto record = read_csv(cut / "plasticity.csv");
  CHECK(record.size() >= 2);  // accepted in pieces
  CHECK(record.back().at("inc") == 1.0);
  const auto a = read_csv(cut / "nodes.csv"), b = read_csv(ref / "nodes.csv");
  std::map<int, double> u_cut, u_ref;
  for (const auto& row : a)
    if (row.at("inc") == 1.0) u_cut[static_cast<int>(row.at("node"))] = row.at("u_r");
  for (const auto& row : b)
    if (row.at("inc") == 2.0) u_ref[static_cast<int>(row.at("node"))] = row.at("u_r");
  REQUIRE(u_cut.size() == 82);
  REQUIRE(u_ref.size() == 82);
  const double scale = std::abs(u_ref.at(1));
  for (const auto& [n, u] : u_ref) CHECK(std::abs(u_cut.at(n) - u) <= 1e-9 * scale);
  // Bad Newton options are refused by name.
  for (const std::string bad :
       {"newton_iterations=0", "newton_iterations=2.5", "newton_tolerance=0", "newton_tolerance=2"}) {
    std::ostringstream o, e;
    CHECK(gapfe::app::command({"run", whole.string(), "--out", scratch("bad_newton").string(), "--set", bad},
                              o, e) != 0);
    CHECK(e.str().find(bad.substr(0, bad.find('='))) != std::string::npos);
  }
}

TEST_CASE("10,000 load steps in one run: the thick tube ramped to 1e4 x its pressure ends on Lame") {
  // The example deck's one step of 100 repeated 10,000 times (INCF = 0): linear, so u = 1e4 u(100);
  // one factorization, 10,000 back-substitutions; only the last increment written.
  const fs::path deck = edited_example("thick_tube.deck", "    0    1    0    0    0\n",
                                       "    010000    0    0    0\n", "ten_thousand_steps");
  const fs::path out  = run_deck_file(deck, "ten_thousand_steps", {"--output", "last"});
  const auto nodes    = read_csv(out / "nodes.csv");
  REQUIRE(nodes.size() == 27);
  const test::Lame lame{100, 200, 1e6, 200000, 0.3};
  for (const auto& row : nodes) {
    CHECK(row.at("step") == 10000);
    CHECK(row.at("t") == 10000);
    CHECK(test::rel(row.at("u_r"), lame.displacement(row.at("r"))) < 5e-3);
  }
}

namespace {
/// The deck `text` with every boundary-condition card's code (columns 21-30) set to 0: no constraint
/// left, the model is free to translate along z (and, in SAGA, to spin about the axis).
std::string unconstrained(const std::string& text) {
  auto lines    = gapfe::test::lines_of(text);
  std::size_t k = 0;
  while (k < lines.size() && lines[k].starts_with("$")) ++k;
  const std::size_t mesh_control = k + 2;  // title, control card, mesh control card
  REQUIRE(mesh_control < lines.size());
  const int segments = std::stoi(lines[mesh_control].substr(10, 5));
  const int bcs      = std::stoi(lines[mesh_control].substr(15, 5));
  REQUIRE(bcs > 0);
  for (int b = 0; b < bcs; ++b) {
    std::string& card = lines[mesh_control + 1 + static_cast<std::size_t>(segments + b)];
    card.resize(std::max<std::size_t>(card.size(), 30), ' ');
    card.replace(20, 10, "         0");
  }
  return gapfe::test::join(lines);
}
}  // namespace

TEST_CASE(
    "A model with a missing constraint, in every family the command runs (elastic SAAS and SAGA, plastic, "
    "gaps, friction) and with every solver: a clear error naming a free node and its direction, exit 2") {
  for (const std::string example :
       {"thick_tube.deck", "helical_sleeve.deck", "plastic_tube.deck", "two_tubes.deck", "press_fit.deck"}) {
    const fs::path deck = write_deck(unconstrained(read_text(kExamples / example)), "free_" + example);
    for (const std::string solver : {"auto", "eigen"}) {
      CAPTURE(example);
      CAPTURE(solver);
      std::ostringstream o, e;
      const int code = gapfe::app::command(
          {"run", deck.string(), "--out", scratch("free").string(), "--quiet", "--solver", solver}, o, e);
      CAPTURE(e.str());
      CHECK(code == gapfe::app::Exit::solve);
      CHECK(e.str().find("singular") != std::string::npos);
      // "near node N u_z" (or u_theta in SAGA: the spin about the axis), N a node of the deck.
      const auto at = e.str().find("near node ");
      REQUIRE(at != std::string::npos);
      const int node = std::stoi(e.str().substr(at + 10));
      CHECK(node >= 1);
      const std::string direction = e.str().substr(e.str().find(' ', at + 10) + 1, 7);
      CHECK((direction.starts_with("u_z") || direction.starts_with("u_theta")));
      CHECK(e.str().find("constraints") != std::string::npos);
    }
  }
}

TEST_CASE(
    "Rate-dependent deck at the dt extremes through the command: 1e-12 s steps stay elastic (Lame), 1e4 s "
    "steps give the rate-independent tube") {
  // examples/decks/rate_tube.deck (sigma_0 = 400, b = 0.05, rate_0 = 1e-3 / s, bore pressure to 300 in 15
  // steps) with card 0's dt (columns 1-12) changed. At dt = 1e-12 s the bore strains at ~1e9 / s, where
  // the yield stress is 400 (1 + 0.05 ln(1 + 1e12)) = 952 MPa (seed Eq. 17), above Lame's bore Mises
  // stress sqrt 3 p b^2 / (b^2 - a^2) = 693: the tube stays elastic. At dt = 1e4 s the strain rate is
  // ~1e-7 / s and the overstress 400 x 0.05 ln(1 + 1e-4) = 2e-3 MPa: the rate-independent tube.
  const std::string deck = read_text(kExamples / "rate_tube.deck");
  const auto plastic = read_csv(run_deck_file(kExamples / "plastic_tube.deck", "dt_reference") / "nodes.csv");
  const test::Lame lame{100, 200, 300, 200000, 0.3};
  for (const auto& [dt, label] :
       {std::pair{" 1.00000E-12", "dt_tiny"}, std::pair{" 1.00000E+04", "dt_huge"}}) {
    const std::string name = label;
    CAPTURE(name);
    const fs::path out = run_deck_file(
        write_deck(replaced(deck, " 1.00000E-03 5.00000E-02", std::string(dt) + " 5.00000E-02"), name), name);
    const auto nodes = read_csv(out / "nodes.csv");
    REQUIRE(nodes.size() == plastic.size());
    for (const auto& row : nodes) REQUIRE(std::isfinite(row.at("u_r")));
    const auto &bore = nodes[nodes.size() - 82], &outer = nodes.back();  // last increment: nodes 1 and 82
    REQUIRE(bore.at("node") == 1);
    if (name == "dt_tiny") {
      CHECK(test::rel(bore.at("u_r"), lame.displacement(100)) < 5e-3);
      CHECK(test::rel(outer.at("u_r"), lame.displacement(200)) < 5e-3);
      // Above sigma_0 the Drysdale-Zak law always flows, at no more than rate_0 (exp((sigma / sigma_0 -
      // 1) / b) - 1) = 2.3e3 / s at the bore's 693 MPa, so for at most 15 x 1e-12 s: eqps <= 3.5e-8
      // (measured up to 1.2e-9), against elastic strains of 1e-3.
      for (const auto& row : read_csv(out / "elements.csv")) CHECK(row.at("eqps") < 3.5e-8);
    } else {
      CHECK(test::rel(outer.at("u_r"), plastic.back().at("u_r")) < 1e-4);
      CHECK(test::rel(bore.at("u_r"), plastic[plastic.size() - 82].at("u_r")) < 1e-4);
    }
  }
}

// Wide decks: the seed's fields cap a deck at grid index 999 (line segment cards, I3) and node
// 99,999 (edge load cards, I5); `$ fields = wide` widens those two and nothing else.
TEST_CASE("fields = wide: the same tube as a legacy and as a wide deck gives identical files") {
  const std::string legacy = test::lame_tube_deck(9, 3, false), wide = test::lame_tube_deck(9, 3, true);
  REQUIRE(legacy != wide);
  const fs::path a = run_deck_file(write_deck(legacy, "tube_legacy"), "tube_legacy");
  const fs::path b = run_deck_file(write_deck(wide, "tube_wide"), "tube_wide");
  for (const char* file : {"nodes.csv", "elements.csv", "reactions.csv"}) {
    CAPTURE(file);
    CHECK(read_text(a / file) == read_text(b / file));
  }
  const test::Lame lame{100, 200, 100, 200000, 0.3};
  for (const auto& row : read_csv(b / "nodes.csv"))
    CHECK(test::rel(row.at("u_r"), lame.displacement(row.at("r"))) < 5e-3);
}

TEST_CASE("fields = wide: a 1000 x 500 grid with its bore pressure meshes; the legacy fields refuse it") {
  struct Info {
    int code;
    std::string log, err;
  };
  const auto info = [](const std::string& text, const std::string& name) {
    std::ostringstream o, e;
    const int code = gapfe::app::command({"info", write_deck(text, name).string()}, o, e);
    return Info{code, o.str(), e.str()};
  };
  // The reported fault: index 1000 in I3 reads as 100, so the grid's corners go missing.
  const Info legacy = info(test::lame_tube_deck(1000, 500, false), "grid_legacy");
  CHECK(legacy.code != 0);
  CHECK(legacy.err.find("error in") != std::string::npos);
  const Info wide = info(test::lame_tube_deck(1000, 500, true), "grid_wide");
  CAPTURE(wide.err);
  REQUIRE(wide.code == 0);
  CHECK(wide.log.find("mesh 1000 x 500 index grid: 500000 nodes, 498501 quadrilaterals") !=
        std::string::npos);
}

TEST_CASE("fields = wide: a 1e6-equation tube with its bore pressure as a wide deck runs and ends on Lame") {
  // 707 x 707 grid points, u_z held on both ends: 2 x 499,849 - 2 x 707 = 998,284 equations; the pressure
  // cards name nodes up to 499,143, past I5's 99,999.
  const int n        = 707;
  const fs::path out = run_deck_file(write_deck(test::lame_tube_deck(n, n, true), "tube_1e6"), "tube_1e6",
                                     {"--set", "output_vtu=none"});
  const test::Lame lame{100, 200, 100, 200000, 0.3};
  std::ifstream in(out / "nodes.csv");  // step,inc,t,node,i,j,r,z,u_r,u_z,u_t; only the bore's rows read
  std::string line;
  std::getline(in, line);
  int bore = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> v;
    std::stringstream s(line);
    for (std::string x; std::getline(s, x, ',');) v.push_back(x);
    REQUIRE(v.size() == 11);
    if (v[4] != "1") continue;
    ++bore;
    CHECK(test::rel(std::stod(v[8]), lame.displacement(std::stod(v[6]))) < 1e-3);
  }
  CHECK(bore == n);
}

// ---- Scene files: a Gmsh mesh with a TOML scene, through the same command and the same path as a
// deck. tests/data/scenes/*.msh are the example decks' meshes node for node (make_scenes.py).

#ifdef GAPFE_HAS_SCENE
namespace {

const fs::path kScenes = fs::path(GAPFE_SOURCE_DIR) / "tests" / "data" / "scenes";

/// The largest difference between two runs' tables over every column but the grid indices i, j (0 for a Gmsh
/// mesh), relative to that column's largest magnitude (a column of zeros compares absolutely), and the worst
/// column's name.
std::pair<double, std::string> table_difference(const fs::path& a, const fs::path& b) {
  const auto x = read_csv(a), y = read_csv(b);
  REQUIRE(x.size() == y.size());
  REQUIRE(!x.empty());
  std::pair<double, std::string> worst{0.0, ""};
  for (const auto& [column, unused] : x.front()) {
    if (column == "i" || column == "j") continue;
    double scale = 0, diff = 0;
    for (std::size_t k = 0; k < x.size(); ++k) {
      REQUIRE(y[k].count(column) == 1);
      scale = std::max(scale, std::abs(x[k].at(column)));
      diff  = std::max(diff, std::abs(x[k].at(column) - y[k].at(column)));
    }
    const double rel = scale > 0 ? diff / scale : diff;
    if (rel >= worst.first) worst = {rel, column};
  }
  return worst;
}

}  // namespace

TEST_CASE(
    "[scene] The thick tube, the two tubes and the plastic tube as Gmsh mesh + scene equal their decks to "
    "1e-10 and meet the decks' closed forms") {
  struct Pair {
    const char *deck, *scene;
    std::vector<const char*> tables;
  };
  for (const Pair& p :
       {Pair{"thick_tube.deck", "thick_tube.toml", {"nodes.csv", "elements.csv", "reactions.csv"}},
        Pair{"two_tubes.deck", "two_tubes.toml", {"nodes.csv", "elements.csv", "gaps.csv"}},
        Pair{"plastic_tube.deck", "plastic_tube.toml", {"nodes.csv", "elements.csv", "reactions.csv"}}}) {
    const std::string name = p.scene;
    CAPTURE(name);
    const fs::path deck  = run_deck_file(kExamples / p.deck, "scene_deck_" + name);
    const fs::path scene = run_deck_file(kScenes / p.scene, "scene_toml_" + name);
    for (const char* table : p.tables) {
      CAPTURE(table);
      const auto worst = table_difference(deck / table, scene / table);
      CAPTURE(worst.second);  // the column
      CHECK(worst.first <= 1e-10);
    }
  }

  // The closed forms of the deck tests, read from the scenes' own output.
  const test::Lame lame{100, 200, 100, 200000, 0.3};  // thick tube: Lame within 0.5%
  for (const auto& row : read_csv(scratch("scene_toml_thick_tube.toml") / "nodes.csv"))
    CHECK(test::rel(row.at("u_r"), lame.displacement(row.at("r"))) < 5e-3);
  {  // two tubes: the closure pressure within 0.5% (docs/theory.md V5, plane strain)
    const double a = 50, b = 75, delta = 0.02, E = 200000, nu = 0.3;
    const double pc  = delta * E * (b * b - a * a) / (2 * a * a * b * (1 - nu * nu));
    double last_open = 0, closed_at = -1;
    for (const auto& row : read_csv(scratch("scene_toml_two_tubes.toml") / "gaps.csv")) {
      if (row.at("status") == 1 && closed_at < 0) closed_at = last_open;
      if (row.at("status") == 0) last_open = row.at("inc");
    }
    CHECK(std::abs(closed_at / 20 * 100 - pc) / pc < 5e-3);
  }
  // plastic tube (docs/theory.md V6): elastic through step 8 (160 < 173), the bore yielded and the outer wall
  // elastic at 300 < p_L = 320.15.
  for (const auto& row : read_csv(scratch("scene_toml_plastic_tube.toml") / "elements.csv")) {
    if (row.at("step") <= 8) CHECK(row.at("eqps") == 0);
    if (row.at("step") == 15 && row.at("element") == 1) CHECK(row.at("eqps") > 0);
    if (row.at("step") == 15 && row.at("element") == 40) CHECK(row.at("eqps") == 0);
  }
}
TEST_CASE(
    "[scene] On the I-J generator: the thick tube and the press fit (held pressure, pushed top, Coulomb "
    "contact "
    "keys) write the same files as their decks, byte for byte") {
  // The same generator, cards and loads in the same order: nothing may differ, not even the last bit.
  struct Pair {
    fs::path deck, scene;
    std::vector<const char*> tables;
  };
  for (const Pair& p : {Pair{kExamples / "thick_tube.deck",
                             kScenes / "thick_tube_grid.toml",
                             {"nodes.csv", "elements.csv", "reactions.csv"}},
                        Pair{kExamples / "press_fit.deck",
                             fs::path(GAPFE_SOURCE_DIR) / "examples" / "scenes" / "press_fit.toml",
                             {"nodes.csv", "elements.csv", "reactions.csv", "gaps.csv"}}}) {
    const std::string name = p.scene.filename().string();
    CAPTURE(name);
    const fs::path deck  = run_deck_file(p.deck, "grid_deck_" + name);
    const fs::path scene = run_deck_file(p.scene, "grid_scene_" + name);
    for (const char* table : p.tables) {
      CAPTURE(table);
      CHECK(read_text(deck / table) == read_text(scene / table));
    }
  }
  // The scene's own reactions against Coulomb's push-out force F = mu p 2 pi b L (the press-fit deck's test:
  // p from the shrink fit of the hub under q, q_c the pressure that closes the radial clearance w): the
  // shaft's support carries F once every pair slips.
  const double a = 12.5, b = 25, w = 0.001, c = 50, L = 50, E = 200000, q = 75, mu = 0.15;
  const double qc      = w * E * (c * c - b * b) / (2 * b * c * c);
  const double F       = mu * (q - qc) * c * c * (b * b - a * a) / (b * b * (c * c - a * a)) * kTwoPi * b * L;
  const auto reactions = read_csv(scratch("grid_scene_press_fit.toml") / "reactions.csv");
  double shaft         = 0;
  for (const auto& row : reactions)
    if (row.at("inc") == reactions.back().at("inc") && row.at("r") < b + w / 2) shaft += row.at("R_z");
  MESSAGE("press fit scene: the shaft's support carries " << shaft << " N, closed form " << F);
  CHECK(std::abs(shaft - F) < 0.01 * F);
}

TEST_CASE(
    "[scene] Load histories (amplitude): pressure, a prescribed displacement and spin follow their factors") {
  const std::string tube = read_text(kScenes / "thick_tube_grid.toml");
  const auto with        = [&](const std::string& name, const std::string& from, const std::string& to,
                        const std::string& extra) {
    std::string s = tube;
    const auto at = s.find(from);
    REQUIRE(at != std::string::npos);
    const fs::path scene = scratch("amplitude") / (name + ".toml");
    std::ofstream(scene) << s.replace(at, from.size(), to) << extra;
    return read_csv(run_deck_file(scene, "amplitude_" + name) / "nodes.csv");
  };
  // u_r at (r, z = 0) after each step.
  const auto at_step = [](const std::vector<std::map<std::string, double>>& rows, double r) {
    std::map<int, double> u;
    for (const auto& row : rows)
      if (row.at("r") == r && row.at("z") == 0) u[static_cast<int>(row.at("step"))] = row.at("u_r");
    return u;
  };
  const test::Lame lame{100, 200, 100, 200000, 0.3};
  {  // pressure: factors 0.5, 1, 0.25, -0.5 (linear to 1 at step 2, then to -0.5 at step 4)
    const auto u =
        at_step(with("pressure", "pressure = 100.0", "pressure = 100.0\namplitude = [[2, 1.0], [4, -0.5]]",
                     "[steps]\ncount = 4\n"),
                100);
    const std::array<double, 4> factor{0.5, 1.0, 0.25, -0.5};
    REQUIRE(u.size() == 4);
    for (int k = 1; k <= 4; ++k) {
      CAPTURE(k);
      CHECK(test::rel(u.at(k), factor[k - 1] * lame.displacement(100)) < 5e-3);  // Lame, as the deck's test
      CHECK(std::abs(u.at(k) - factor[k - 1] * u.at(2)) <= 1e-12 * std::abs(u.at(2)));  // linear: exact
    }
  }
  {  // a prescribed bore displacement 0.05 with factors 1, 0, -1: the bore follows exactly, the rim in ratio
    const auto rows = with("displacement", "[[load]]\ncurves = \"bore\"\npressure = 100.0\n",
                           "[[boundary]]\ngroups = \"bore\"\ndisplacement = { r = 0.05 }\n"
                           "amplitude = [[1, 1.0], [3, -1.0]]\n",
                           "[steps]\ncount = 3\n");
    const auto bore = at_step(rows, 100), rim = at_step(rows, 200);
    const std::array<double, 3> factor{1.0, 0.0, -1.0};
    REQUIRE(bore.size() == 3);
    for (int k = 1; k <= 3; ++k) {
      CAPTURE(k);
      CHECK(std::abs(bore.at(k) - 0.05 * factor[k - 1]) <= 1e-15);
      CHECK(std::abs(rim.at(k) - factor[k - 1] * rim.at(1)) <= 1e-12 * std::abs(rim.at(1)));
    }
    CHECK(rim.at(1) > 0);
    CHECK(rim.at(1) < 0.05);  // a tube opened at its bore opens less at its rim (u ~ A r + B / r)
  }
  {  // spin: omega 1000 then 500: the centrifugal load goes with omega^2, so a quarter
    const auto u = at_step(with("spin", "[[load]]\ncurves = \"bore\"\npressure = 100.0\n",
                                "[inertia]\nangular_velocity = 1000.0\namplitude = [[1, 1.0], [2, 0.5]]\n",
                                "[steps]\ncount = 2\n"),
                           200);
    REQUIRE(u.size() == 2);
    CHECK(u.at(1) > 0);
    CHECK(std::abs(u.at(2) - 0.25 * u.at(1)) <= 1e-12 * u.at(1));
  }
}

TEST_CASE("[scene] Malformed scene and mesh files: a clear error naming the key or line, a non-zero exit") {
  const std::string tubes = (kScenes / "two_tubes.msh").string();
  const std::string thick = (kScenes / "thick_tube.msh").string();
  // A valid two-tube scene; each case edits it (or its mesh) once.
  const std::string good =
      "title = \"t\"\n"
      "[mesh]\nfile = \"" +
      tubes +
      "\"\n"
      "[materials.steel]\nsurfaces = [\"inner\", \"outer\"]\nE = 200000.0\nnu = 0.3\n"
      "[materials.gap]\nE = 0.0002\nnu = 0.0\n"
      "[[boundary]]\ngroups = [\"inner\", \"gap\", \"outer\"]\nfix = \"z\"\n"
      "[[load]]\ncurves = \"bore\"\npressure = 100.0\n"
      "[[contact]]\nfaces = [\"inner_face\", \"outer_face\"]\nsoft = \"gap\"\n";
  const auto edit = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const auto at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
  };
  const std::string mesh_text = read_text(kScenes / "thick_tube.msh");
  const auto bad_mesh         = [&](const std::string& from, const std::string& to, const std::string& name) {
    std::string s = mesh_text;
    const auto at = s.find(from);
    REQUIRE(at != std::string::npos);
    const fs::path file = scratch("scene_bad") / (name + ".msh");
    std::ofstream(file) << s.replace(at, from.size(), to);
    return "title = \"t\"\n[mesh]\nfile = \"" + file.string() +
           "\"\n[materials.steel]\nE = 1.0\nnu = 0.3\n[[boundary]]\ngroups = \"bottom\"\nfix = \"z\"\n";
  };
  struct Case {
    std::string name, scene, expected;
  };
  std::vector<Case> cases{
      {"unknown top-level key", "titel = \"x\"\n" + good, "unknown key 'titel' (line 1)"},
      {"unknown material key", edit("E = 200000.0", "Ee = 200000.0"),
       "unknown key 'materials.steel.Ee' (line 6)"},
      {"no mesh table", edit("[mesh]\nfile = \"" + tubes + "\"\n", ""), "no [mesh] table"},
      {"missing mesh file", edit(tubes, tubes + ".missing"),
       "key 'mesh.file' (line 3): cannot open the mesh"},
      {"unknown surface", edit("[\"inner\", \"outer\"]", "[\"inner\", \"outr\"]"),
       "no surface physical group \"outr\""},
      {"cell without material", edit("[materials.gap]\nE = 0.0002\nnu = 0.0\n", ""),
       "(surface group \"gap\") has no material"},
      {"negative modulus", edit("E = 200000.0", "E = -1.0"), "Young's moduli"},
      {"modulus of the wrong type", edit("E = 200000.0", "E = \"big\""),
       "key 'materials.steel.E' (line 6): expected a number or three (N, S, T), got \"big\""},
      {"bad direction", edit("fix = \"z\"", "fix = \"x\""),
       "key 'boundary[1].fix' (line 13): expected directions among"},
      {"unknown boundary group", edit("[\"inner\", \"gap\", \"outer\"]", "\"ends\""),
       "no curve or surface group \"ends\""},
      {"pressure on an interface", edit("curves = \"bore\"", "curves = \"inner_face\""),
       "lies between two cells"},
      {"mismatched gap faces", edit("[\"inner_face\", \"outer_face\"]", "[\"bore\", \"outer_face\"]"),
       "has no node of face \"outer_face\" within half its shortest edge"},
      {"one face twice", edit("[\"inner_face\", \"outer_face\"]", "[\"bore\", \"bore\"]"),
       "two different curve groups"},
      {"TOML syntax", edit("nu = 0.3", "nu = = 0.3"), "scene: line 7, column"},
      {"no load steps", good + "[steps]\ncount = 0\n",
       "key 'steps.count' (line 21): expected a whole number of load steps"},
      {"format in options", good + "[options]\nformat = \"saac\"\n", "key 'options.format' (line 21)"},
      {"unknown option value", good + "[options]\ncontact = \"magic\"\n",
       "option contact = 'magic': expected one of"},
      {"five yield stresses", edit("nu = 0.3", "nu = 0.3\nyield = [1.0, 2.0, 3.0, 4.0, 5.0]"),
       "key 'materials.steel.yield' (line 8): expected one yield stress"},
      {"rate without step time", good + "[rate]\nb = 0.05\n", "give key 'steps.time'"},
      {"boundary without a condition", edit("fix = \"z\"\n", ""), "needs fix, displacement or force"},
      {"a direction twice", edit("fix = \"z\"", "fix = \"z\"\ndisplacement = {z = 1.0}"), "z is given twice"},
      {"temperature value and points", good + "[temperature]\nvalue = 1.0\npoints = [[0.0, 0.0, 1.0]]\n",
       "not both"},
      {"a surface in two materials",
       edit("surfaces = [\"inner\", \"outer\"]", "surfaces = [\"inner\", \"outer\", \"gap\"]"),
       "two materials"},
      {"a cubic cell", bad_mesh("\n1 3 2 1 1 1 2 11 10", "\n1 21 2 1 1 1 2 11 10 3 4 5 6 7 8", "cubic"),
       "element type 21: gapfe reads lines (1, 8), triangles (2, 9) and quadrangles (3, 16, 10)"},
      {"negative r in the mesh",
       bad_mesh("\n2 1.1250000000000000e+02", "\n2 -1.1250000000000000e+02", "negative_r"),
       "< 0: an axisymmetric section lies at r >= 0"},
      {"truncated mesh", bad_mesh("$EndElements", "", "truncated"),
       "truncated.msh: the file ends in $Elements"},
      {"mesh without the named group", bad_mesh("\"bottom\"", "\"base\"", "renamed"),
       "no curve or surface group \"bottom\""},
      // Load histories and the contact keys.
      {"amplitude past the last step", edit("pressure = 100.0", "pressure = 100.0\namplitude = [[2, 1.0]]"),
       "key 'load[1].amplitude' (line 17): expected [[step, factor], ...]: whole steps from 0 to the last, "
       "1"},
      {"amplitude steps not increasing",
       good + "[steps]\ncount = 4\n" +
           "[inertia]\nangular_velocity = 1.0\namplitude = [[2, 1.0], [1, 0.0]]\n",
       "key 'inertia.amplitude' (line 24): expected [[step, factor]"},
      {"contact policy against [options]",
       edit("soft = \"gap\"", "soft = \"gap\"\npolicy = \"active-set\"") + "[options]\ncontact = \"saac\"\n",
       "key 'contact[1].policy' (line 20): contact = 'active-set', but key 'options.contact' (line 22) set "
       "it to "
       "'saac'; a run has one contact"},
      {"unknown friction model", edit("soft = \"gap\"", "soft = \"gap\"\nslip = \"sticky\""),
       "key 'contact[1].slip' (line 20): option slip = 'sticky': expected one of"},
  };
  // The I-J generator's scenes: a valid one (the thick tube of tests/data/scenes), each case edits it once.
  const std::string grid = read_text(kScenes / "thick_tube_grid.toml");
  const auto edit_grid   = [&](const std::string& from, const std::string& to) {
    std::string s = grid;
    const auto at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
  };
  const std::vector<Case> grid_cases{
      {"grid and file", edit_grid("grid = [9, 3]", "grid = [9, 3]\nfile = \"x.msh\""),
       "give either file (a Gmsh mesh) or grid with segments"},
      {"grid of zero rows", edit_grid("grid = [9, 3]", "grid = [9, 0]"),
       "key 'mesh.grid' (line 5): expected [MAXI, MAXJ], whole numbers >= 1"},
      {"segment type", edit_grid("[[mesh.segments]]", "[[mesh.segments]]\ntype = \"spline\""),
       "key 'mesh.segments[1].type' (line 8): expected \"point\", \"line\""},
      {"segment point outside the grid", edit_grid("[9, 1, 200.0, 0.0]]", "[10, 1, 200.0, 0.0]]"),
       "key 'mesh.segments[1].points' (line 8): expected 2 point(s) [I, J, r, z] (a line) with I within "
       "1..9"},
      {"arc without its three points", edit_grid("[[mesh.segments]]", "[[mesh.segments]]\ntype = \"arc\""),
       "expected 3 point(s) [I, J, r, z] (a arc)"},
      {"segment the generator refuses", edit_grid("[9, 1, 200.0, 0.0]]", "[8, 3, 200.0, 0.0]]"),
       "[mesh.segments[1]] (line 7): line segment card 1: from (1, 1) to (8, 3) is neither a row"},
      {"a curve used as a surface", edit_grid("[materials.steel]", "[materials.steel]\nsurfaces = \"bore\""),
       "key 'materials.steel.surfaces' (line 23): the group \"bore\" is one grid line (I = 1, J = 1-3), a "
       "curve"},
      {"unknown group", edit_grid("curves = \"bore\"", "curves = \"bores\""),
       "the grid has no group \"bores\" (its [mesh.groups] are \"bore\", \"bottom\", \"steel\", \"top\")"},
      {"a surface used as a curve", edit_grid("curves = \"bore\"", "curves = \"steel\""),
       "the group \"steel\" (I = 1-9, J = 1-3) spans a range of both I and J, a surface"},
      {"group index outside the grid",
       edit_grid("bore = { i = 1, j = [1, 3] }", "bore = { i = 1, j = [1, 4] }"),
       "key 'mesh.groups.bore.j' (line 20): expected one index or [first, last] within 1..MAXJ = 3"},
      {"group with an unknown key", edit_grid("bore = { i = 1, j = [1, 3] }", "bore = { i = 1, k = [1, 3] }"),
       "unknown key 'mesh.groups.bore.k' (line 20)"},
      {"segments with a Gmsh file", edit(tubes + "\"", tubes + "\"\nsegments = []"),
       "key 'mesh.segments' (line 4): expected no segments with a Gmsh file"},
  };
  cases.insert(cases.end(), grid_cases.begin(), grid_cases.end());
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const fs::path file = scratch("scene_bad") / "scene.toml";
    std::ofstream(file) << c.scene;
    std::ostringstream out, err;
    const int code = gapfe::app::command({"info", file.string()}, out, err);
    CAPTURE(err.str());
    CHECK(code != 0);
    CHECK(err.str().find(c.expected) != std::string::npos);
  }
}
#endif

#ifdef GAPFE_HAS_SCENE
TEST_CASE(
    "[scene] A notched tube (triangles and quadrangles from Gmsh) converges to its Richardson extrapolate, "
    "between the Lame tubes of its two outer radii") {
  // tests/data/make_notched.py: 100 <= r <= 200, 0 <= z <= 100, a groove of radius 20 at z = 50 (root at
  // r = 180); u_z = 0 at both ends, bore pressure 100, E = 200000, nu = 0.3. Quantity: u_r at (100, 50),
  // under the groove, on meshes of size 8, 4, 2 (not nested: Gmsh remeshes each).
  std::vector<double> u;
  for (const int h : {8, 4, 2}) {
    const fs::path scene = scratch("notched") / ("notched_h" + std::to_string(h) + ".toml");
    std::ofstream(scene) << "title = \"notched tube\"\n[mesh]\nfile = \""
                         << (kScenes / ("notched_tube_h" + std::to_string(h) + ".msh")).string()
                         << "\"\n[options]\nelement = \"quad4\"\n[materials.steel]\nE = 200000.0\nnu = 0.3\n"
                            "[[boundary]]\ngroups = [\"bottom\", \"top\"]\nfix = \"z\"\n"
                            "[[load]]\ncurves = \"bore\"\npressure = 100.0\n";
    const fs::path out = run_deck_file(scene, "notched_h" + std::to_string(h));
    double found       = std::nan("");
    for (const auto& row : read_csv(out / "nodes.csv"))
      if (row.at("r") == 100 && row.at("z") == 50) found = row.at("u_r");
    REQUIRE(std::isfinite(found));
    u.push_back(found);
  }
  const double order  = std::log((u[0] - u[1]) / (u[1] - u[2])) / std::log(2.0);
  const double limit  = u[2] + (u[2] - u[1]) / (std::pow(2.0, order) - 1);
  const double intact = test::Lame{100, 200, 100, 200000, 0.3}.displacement(100);
  const double thin   = test::Lame{100, 180, 100, 200000, 0.3}.displacement(100);
  MESSAGE("u_r(100, 50) at h = 8, 4, 2: " << u[0] << ", " << u[1] << ", " << u[2] << "; observed order "
                                          << order << ", extrapolate " << limit
                                          << "; Lame b = 200: " << intact << ", b = 180: " << thin);
  CHECK(order > 1.5);  // linear elements: displacements converge at second order
  CHECK(order < 2.6);
  CHECK(std::abs(u[2] - limit) / limit < 1e-3);  // the finest mesh's estimated error
  CHECK(limit > intact);                         // the groove weakens the tube...
  CHECK(limit < thin);                           // ...less than turning the whole tube down to its root
}
#endif

// ---- Pictures, history.csv and the command line. tests/check_output.py reads the same kinds of
// files with meshio and Python's XML parser.

TEST_CASE("[history] the plastic tube past its limit: history.csv's load climbs to p_L and flattens there") {
  // examples/decks/plastic_tube.deck at 30 per step to 450 (as the past-the-limit test): the run fails in
  // step 11 and keeps the history of every accepted increment. Closed form (docs/theory.md V6): p_L = (2 /
  // sqrt 3) 400 ln 2 = 320.15 for the perfectly plastic tube, Mises at nu = 0.3 within ~1% of it.
  const fs::path deck =
      edited_example("plastic_tube.deck", "   42    1      20.0", "   42    1      30.0", "history_limit");
  const fs::path out = scratch("history_limit");
  std::ostringstream o, e;
  CHECK(gapfe::app::command({"run", deck.string(), "--out", out.string(), "--quiet"}, o, e) ==
        gapfe::app::solve);
  const auto history = read_csv(out / "history.csv");
  REQUIRE(history.size() > 10);
  const double p_limit = 2 / std::sqrt(3.0) * 400 * std::log(2.0);
  const auto& last     = history.back();
  const double reached = 450 * last.at("load_factor");
  MESSAGE("history.csv: " << history.size() << " increments, pressure reached " << reached << " against p_L "
                          << p_limit << "; u_max " << last.at("u_max"));
  CHECK(std::abs(reached - p_limit) < 0.01 * p_limit);
  CHECK(last.at("inc") == doctest::Approx(reached / 30).epsilon(1e-12));
  CHECK(last.at("plastic_points") > 0);
  // The curve bends: the last increments' stiffness dp/du is under 5% of the first (elastic) one.
  const auto& first    = history.front();
  const auto& prev     = history[history.size() - 2];
  const double elastic = first.at("load_factor") / first.at("u_max"),
               final =
                   (last.at("load_factor") - prev.at("load_factor")) / (last.at("u_max") - prev.at("u_max"));
  CHECK(final < 0.05 * elastic);
  // The pictures of the accepted increments are there although the run failed.
  CHECK(fs::exists(out / "deformed.svg"));
  CHECK(fs::exists(out / "plot_mises.svg"));
}

TEST_CASE(
    "[history] columns: each BC card's reaction where it prescribes, pairs, iterations; one step: none") {
  // The press fit (grid scene): the shaft's support and the pushed hub top carry equal and opposite axial
  // forces (nothing else holds the model along z), closed and slipping pairs counted from gaps.csv.
  const fs::path out = run_deck_file(fs::path(GAPFE_SOURCE_DIR) / "examples" / "scenes" / "press_fit.toml",
                                     "history_press_fit");
  const auto history = read_csv(out / "history.csv");
  const auto gaps    = read_csv(out / "gaps.csv");
  REQUIRE(!history.empty());
  for (const auto& row : history) {
    CHECK(std::abs(row.at("R_z_shaft_bottom") + row.at("R_z_hub_top")) <=
          1e-6 * std::max(1.0, std::abs(row.at("R_z_hub_top"))));
    CHECK(row.at("iterations") >= 1);
    int closed = 0, slipping = 0;
    for (const auto& g : gaps)
      if (g.at("inc") == row.at("inc")) closed += g.at("status") >= 2, slipping += g.at("status") == 3;
    CHECK(row.at("closed") == closed);
    CHECK(row.at("slipping") == slipping);
  }
  CHECK(history.back().at("load_factor") == 1.0);
  CHECK(history.back().at("R_z_shaft_bottom") > 60000);  // pushed out: Coulomb's 67,858 N (the deck test)
  // A history.csv whose row is short, and a group name with a comma (a CSV separator) in a scene: clear
  // errors or a clean header (found by review).
  {
    const fs::path dir = scratch("history_short");
    gapfe::RunFolder::record(dir.string(), "a hand-made run", "complete");  // plot reads a run's folder only
    std::ofstream(dir / "history.csv") << "step,u_max,load_factor\n1,0.5\n";
    std::ostringstream o, e;
    CHECK(gapfe::app::command({"plot", dir.string(), "--x", "u_max", "--y", "load_factor"}, o, e) ==
          gapfe::app::system);  // a malformed result file: a file problem
    CHECK(e.str().find("history.csv, line 2: fewer values than the header's columns") != std::string::npos);
    std::string scene = read_text(kScenes / "thick_tube_grid.toml");
    const auto swap   = [&](const std::string& from, const std::string& to) {
      const auto at = scene.find(from);
      REQUIRE(at != std::string::npos);
      scene.replace(at, from.size(), to);
    };
    swap("bottom = {", "\"bot,tom\" = {");
    swap("groups = [\"bottom\", \"top\"]", "groups = [\"bot,tom\", \"top\"]");
    const fs::path file = scratch("history_comma") / "scene.toml";
    std::ofstream(file) << scene << "[steps]\ncount = 2\n";
    const fs::path comma = run_deck_file(file, "history_comma_out");
    CHECK(read_text(comma / "history.csv").find("R_z_bot_tom+top,") != std::string::npos);
  }
  // One load step: no history.csv.
  CHECK(!fs::exists(run_deck_file(kExamples / "thick_tube.deck", "history_one_step") / "history.csv"));
}

TEST_CASE("[files] result files never write through a link, and a failed write leaves no temporary") {
  const fs::path dir = scratch("output_links");
  std::ofstream(dir / "precious.txt") << "precious";
  fs::create_symlink(dir / "precious.txt", dir / "nodes.csv");
  // A table (appended rows) on a planted link: refused, naming the link (O_NOFOLLOW), the target untouched.
  CHECK_THROWS_WITH_AS(gapfe::OutputFile((dir / "nodes.csv").string()),
                       doctest::Contains("it is a symbolic link"), gapfe::FileError);
  // A file written whole on a planted link: the link is replaced by the file, the target untouched.
  fs::create_symlink(dir / "precious.txt", dir / "step_0001.vtu");
  gapfe::detail::write_file_atomically((dir / "step_0001.vtu").string(), "new");
  CHECK(!fs::is_symlink(dir / "step_0001.vtu"));
  CHECK(read_text(dir / "step_0001.vtu") == "new");
  CHECK(read_text(dir / "precious.txt") == "precious");
  // A name taken by a folder: the rename fails, FileError names the file, and no temporary is left.
  fs::create_directory(dir / "result.pvd");
  std::ofstream(dir / "result.pvd" / "keep") << "x";
  CHECK_THROWS_WITH_AS(gapfe::detail::write_file_atomically((dir / "result.pvd").string(), "new"),
                       doctest::Contains("result.pvd"), gapfe::FileError);
  int temporaries = 0;
  for (const auto& e : fs::directory_iterator(dir))
    temporaries += e.path().filename().string().find(".gapfe-") != std::string::npos;
  CHECK(temporaries == 0);
}

TEST_CASE("[vtu] inline binary: the UInt32 byte count, then the values, in base64 (Python's base64 module)") {
  // Expected strings: base64.b64encode(struct.pack('<I', nbytes) + struct.pack('<Nd', *values)). An empty
  // array (a run with no cell of some kind) is its header alone.
  const auto encoded = [](const auto& values) {
    std::string s;
    gapfe::detail::append_binary(s, values);
    return s;
  };
  CHECK(encoded(std::vector<double>{}) == "AAAAAA==\n");
  CHECK(encoded(std::vector<double>{1.0}) == "CAAAAAAAAAAAAPA/\n");
  CHECK(encoded(std::vector<double>{1.0, -2.5}) == "EAAAAAAAAAAAAPA/AAAAAAAABMA=\n");
  CHECK(encoded(std::vector<std::int32_t>{7}) == "BAAAAAcAAAA=\n");
}

TEST_CASE("[vtu] read_vtu reads back a run's files: every array equals the tables") {
  const fs::path out = run_deck_file(kExamples / "two_tubes.deck", "vtu_reader");
  std::ifstream in(out / "step_0020.vtu");
  REQUIRE(in);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const VtuData d = read_vtu(text, "step_0020.vtu");
  std::vector<std::map<std::string, double>> nodes, elements;
  for (const auto& row : read_csv(out / "nodes.csv"))
    if (row.at("step") == 20 && row.at("inc") == 20) nodes.push_back(row);
  for (const auto& row : read_csv(out / "elements.csv"))
    if (row.at("step") == 20 && row.at("inc") == 20) elements.push_back(row);
  REQUIRE(d.points.size() == nodes.size());
  REQUIRE(d.cells.size() == elements.size());
  const VtuField* u = d.point("displacement");
  const VtuField* s = d.cell("stress");
  REQUIRE(u);
  REQUIRE(s);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    CHECK(d.points[n](0) == nodes[n].at("r"));
    CHECK(u->values[3 * n] == nodes[n].at("u_r"));
    CHECK(u->values[3 * n + 1] == nodes[n].at("u_z"));
  }
  for (std::size_t e = 0; e < elements.size(); ++e) {
    CHECK(s->values[6 * e + voigt::hoop] == elements[e].at("s_tt"));
    CHECK(d.cells[e].size() == 4);
  }
  const PlotField hoop = plot_field(d, "s_tt");
  CHECK(hoop.values.size() == elements.size());
  CHECK_THROWS_WITH_AS(plot_field(d, "s_t"), doctest::Contains("unknown field 's_t' (known: u, u_r"),
                       InputError);
  CHECK_THROWS_WITH_AS(
      read_vtu("<VTKFile type=\"UnstructuredGrid\"><Piece NumberOfPoints=\"1\" NumberOfCells=\"0\">"
               "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">"
               "AAA*</DataArray></Points>",
               "bad.vtu"),
      doctest::Contains("bad.vtu, array '': a character that is not base64"), InputError);
  // Files a run did not write: each an InputError naming what is wrong, never another exception or a read
  // past the data (found by review: a missing Piece, a count that overflows 3 x N, a negative offset).
  const std::string head = "<VTKFile type=\"UnstructuredGrid\">";
  const std::string ascii_point =
      "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 "
      "0</DataArray></Points>";
  for (const auto& bad : std::vector<std::pair<std::string, std::string>>{
           {head + "</VTKFile>", "no Piece tag"},
           {head + "<Piece NumberOfPoints=\"99999999999999999999\" NumberOfCells=\"0\">", "is not a count"},
           {head + "<Piece NumberOfPoints=\"12297829382473034411\" NumberOfCells=\"0\">" + ascii_point,
            "is not a count"},
           {head + "<Piece NumberOfPoints=\"1\" NumberOfCells=\"0\"><Points><DataArray type=\"Float64\" "
                   "NumberOfComponents=\"x\" format=\"ascii\">0 0 0</DataArray></Points>",
            "NumberOfComponents 'x' is not a count"},
           {head + "<Piece NumberOfPoints=\"1\" NumberOfCells=\"1\">" + ascii_point +
                "<Cells><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0</DataArray>"
                "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">-1</DataArray></Cells>",
            "offsets are not increasing whole numbers"},
       }) {
    const std::string& expected = bad.second;  // named: CAPTURE's lambda cannot take a structured binding
    CAPTURE(expected);
    CHECK_THROWS_WITH_AS(read_vtu(bad.first, "x.vtu"), doctest::Contains(expected.c_str()), InputError);
  }
  // A range of a few round-off steps gets its two ends as ticks, not an endless loop.
  CHECK(detail::nice_ticks(1.0, 1.0 + 2.2e-16, 6).size() <= 14);
}

TEST_CASE(
    "[vtu] a partitioned run's .pvtu: its pieces in order, joined into one mesh; its files are a run's") {
  const std::string pvtu =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\">\n<PUnstructuredGrid "
      "GhostLevel=\"0\">\n<Piece Source=\"step_0002_p0.vtu\"/>\n<Piece Source=\"step_0002_p1.vtu\"/>\n"
      "</PUnstructuredGrid>\n</VTKFile>\n";
  CHECK(read_pvtu(pvtu, "s.pvtu") == std::vector<std::string>{"step_0002_p0.vtu", "step_0002_p1.vtu"});
  CHECK_THROWS_WITH_AS(read_pvtu("<VTKFile type=\"PUnstructuredGrid\"></VTKFile>", "s.pvtu"),
                       doctest::Contains("s.pvtu: no Piece"), InputError);
  CHECK_THROWS_WITH_AS(read_pvtu("<VTKFile type=\"PUnstructuredGrid\"><Piece/>", "s.pvtu"),
                       doctest::Contains("s.pvtu: a Piece without a Source"), InputError);
  // Two triangles sharing an edge, one per piece: the shared nodes twice, the second piece's cell renumbered.
  VtuData a, b;
  a.points = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)}, a.cells = {{0, 1, 2}};
  b.points = {Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)}, b.cells = {{0, 1, 2}};
  a.point_data = {{"node", 1, {1, 2, 3}, true}}, b.point_data = {{"node", 1, {2, 4, 3}, true}};
  a.cell_data = {{"element", 1, {1}, true}}, b.cell_data = {{"element", 1, {2}, true}};
  const VtuData whole = join_pieces({a, b}, "s.pvtu");
  CHECK(whole.points.size() == 6);
  CHECK(whole.cells == std::vector<std::vector<int>>{{0, 1, 2}, {3, 4, 5}});
  CHECK(whole.point("node")->values == std::vector<double>{1, 2, 3, 2, 4, 3});
  CHECK(whole.cell("element")->values == std::vector<double>{1, 2});
  b.cell_data[0].name = "material";
  CHECK_THROWS_WITH_AS(join_pieces({a, b}, "s.pvtu"),
                       doctest::Contains("s.pvtu: piece 2 has other cell arrays than the first"), InputError);
  // The parts' files are a run's (the next run into the folder removes them); names like them are not.
  for (const char* name :
       {"step_0001.pvtu", "step_0001_p3.vtu", "nodes_p0.csv", "elements_p12.csv", "reactions_p7.csv"})
    CHECK_MESSAGE(RunFolder::run_file(name), name);
  for (const char* name : {"nodes_p.csv", "nodes_px.csv", "nodes_p1.csv.bak", "my.pvtu", "elements_p1a.csv"})
    CHECK_MESSAGE(!RunFolder::run_file(name), name);
}

TEST_CASE("[cli] --help on every command, --version, suggestions for misspelt commands and options") {
  for (const char* command : {"run", "mesh", "info", "plot"}) {
    CAPTURE(command);
    for (const char* flag : {"--help", "-h"}) {
      std::ostringstream out, err;
      CHECK(gapfe::app::command({command, flag}, out, err) == gapfe::app::ok);
      CHECK(out.str().find(std::string("usage: gapfe ") + command) != std::string::npos);
      CHECK(out.str().find("--quiet") != std::string::npos);
      CHECK(err.str().empty());
    }
  }
  std::ostringstream run_help, e0;
  gapfe::app::command({"run", "--help"}, run_help, e0);
  CHECK(run_help.str().find("--plot FIELD") != std::string::npos);
  CHECK(run_help.str().find("--field") == std::string::npos);  // plot's option, not run's
  std::ostringstream version, e1;
  CHECK(gapfe::app::command({"run", "--version"}, version, e1) == gapfe::app::ok);
  CHECK(version.str().rfind("gapfe ", 0) == 0);
  struct Case {
    std::vector<std::string> args;
    std::string expected;
  };
  for (const Case& c :
       {Case{{"run", "x.deck", "--outt", "d"}, "unknown option '--outt'; did you mean '--out'?"},
        Case{{"plto", "d"}, "unknown command 'plto'; did you mean 'plot'?"},
        Case{{"plot", "d", "--feild", "u"}, "did you mean '--field'?"},
        Case{{"run", "x.deck", "--out", "d", "--field", "u"},
             "--field is not an option of gapfe run (it belongs to: plot)"},
        Case{{"plot", "d", "--x", "u_max"}, "--x and --y go together"},
        Case{{"plot", "d", "--step", "0"}, "--step: '0' is not a load step"}}) {
    CAPTURE(c.expected);
    std::ostringstream out, err;
    CHECK(gapfe::app::command(c.args, out, err) == gapfe::app::usage);
    CHECK(err.str().find(c.expected) != std::string::npos);
  }
}

TEST_CASE("[plot] gapfe plot: any field of any step, a history curve, and clear errors") {
  const fs::path out = run_deck_file(kExamples / "two_tubes.deck", "plot_cli");
  CHECK(fs::exists(out / "plot_mises.svg"));  // gapfe run's default picture
  CHECK(fs::exists(out / "curve_load_factor_u_max.svg"));
  std::ostringstream o, e;
  CHECK(gapfe::app::command(
            {"plot", out.string(), "--field", "s_tt", "--step", "5", "--no-png", "--units", "mm,N,MPa"}, o,
            e) == gapfe::app::ok);
  const std::string svg = read_text(out / "plot_s_tt_step_0005.svg");
  CHECK(svg.find("s_tt [MPa]") != std::string::npos);
  CHECK(svg.find("r [mm]") != std::string::npos);
  CHECK(gapfe::app::command({"plot", out.string(), "--x", "u_max", "--y", "R_z_bc1", "--no-png", "--quiet"},
                            o, e) == gapfe::app::ok);
  CHECK(fs::exists(out / "curve_R_z_bc1_u_max.svg"));
  struct Case {
    std::vector<std::string> args;
    std::string expected;
  };
  for (const Case& c :
       {Case{{"plot", out.string(), "--field", "mieses"}, "unknown field 'mieses' (known: u, u_r"},
        Case{{"plot", out.string(), "--step", "99"}, "load step 99 is not in"},
        Case{{"plot", out.string(), "--x", "u_max", "--y", "load"}, "no column 'load'"},
        Case{{"plot", out.string(), "--units", "mm"}, "units 'mm': expected LENGTH,FORCE,STRESS"}}) {
    CAPTURE(c.expected);
    std::ostringstream out2, err;
    CHECK(gapfe::app::command(c.args, out2, err) == gapfe::app::input);
    CHECK(err.str().find(c.expected) != std::string::npos);
  }
  {  // a folder no run wrote: a file problem (exit 3), not a model one
    std::ostringstream out2, err;
    CHECK(gapfe::app::command({"plot", (out / "missing").string()}, out2, err) == gapfe::app::system);
    CHECK(err.str().find("holds no gapfe-run.txt") != std::string::npos);
  }
  // A deck asking for units, and a field the run cannot draw: the run goes on and says why.
  std::ostringstream o2, e2;
  CHECK(gapfe::app::command({"run", (kExamples / "thick_tube.deck").string(), "--out",
                             scratch("plot_gaps").string(), "--plot", "gap_state", "--set", "units=mm,N,MPa"},
                            o2, e2) == gapfe::app::ok);
  CHECK(o2.str().find("pictures not drawn: field gap_state: the file has no cell array 'gap_state'") !=
        std::string::npos);
  std::ostringstream o3, e3;
  CHECK(gapfe::app::command({"info", (kExamples / "thick_tube.deck").string(), "--set", "units=mm;N;MPa"}, o3,
                            e3) == gapfe::app::input);
  CHECK(e3.str().find("units 'mm;N;MPa': expected LENGTH,FORCE,STRESS") != std::string::npos);
}

TEST_CASE("solver = petsc and PETSc's options: clear refusals where the run cannot be partitioned") {
  const std::string deck = (kExamples / "thick_tube.deck").string(), out = scratch("petsc_refused").string();
  const auto run = [&](std::vector<std::string> args) {
    std::ostringstream o, e;
    const int code = gapfe::app::command(args, o, e);
    return std::make_pair(code, e.str());
  };
  // In-process, no program started MPI (examples/gapfe/main.cpp does, given StartMpi): said, not crashed.
  auto [code, err] = run({"run", deck, "--out", out, "--solver", "petsc"});
  CHECK(code == gapfe::app::input);
#ifdef GAPFE_HAS_PETSC
  CHECK(err.find("MPI and PETSc are started by the program") != std::string::npos);
#else
  CHECK(err.find("built without PETSc") != std::string::npos);
#endif
  // A PETSc option without solver = petsc, and one given to another command.
  std::tie(code, err) = run({"run", deck, "--out", out, "-ksp_type", "cg"});
  CHECK(code == gapfe::app::input);
  CHECK(err.find("the PETSc option -ksp_type needs solver = petsc") != std::string::npos);
  std::tie(code, err) = run({"mesh", deck, "--out", out, "-ksp_type", "cg"});
  CHECK(code == gapfe::app::usage);
  CHECK(err.find("PETSc options belong to gapfe run") != std::string::npos);
  // Launched as 2 processes (mpirun's variables) with a one-process solver: refused, by rank 0 only.
  ::setenv("OMPI_COMM_WORLD_SIZE", "2", 1);
  ::setenv("OMPI_COMM_WORLD_RANK", "0", 1);
  std::tie(code, err) = run({"run", deck, "--out", out, "--solver", "eigen"});
  CHECK(code == gapfe::app::input);
  CHECK(err.find("started as 2 processes") != std::string::npos);
  ::setenv("OMPI_COMM_WORLD_RANK", "1", 1);  // the other rank says nothing (rank 0 speaks for both)
  std::tie(code, err) = run({"run", deck, "--out", out, "--solver", "eigen"});
  CHECK(code == gapfe::app::input);
  CHECK(err.empty());
  ::unsetenv("OMPI_COMM_WORLD_SIZE");
  ::unsetenv("OMPI_COMM_WORLD_RANK");
}

namespace {

/// RFC 4648 base64 of `bytes`, with padding: the reference the VTU writer's encoder is checked against.
std::string base64(const std::vector<unsigned char>& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t k = 0; k < bytes.size(); k += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - k);
    std::uint32_t b     = std::uint32_t(bytes[k]) << 16;
    if (n > 1) b |= std::uint32_t(bytes[k + 1]) << 8;
    if (n > 2) b |= bytes[k + 2];
    for (std::size_t c = 0; c < 4; ++c) out += c <= n ? digits[(b >> (18 - 6 * c)) & 63] : '=';
  }
  return out;
}

}  // namespace

TEST_CASE("[threads] the files' pieces on 3 threads: the rows, base64 and outline of a serial loop") {
  const gapfe::test::OneThreadAfter restore;
  // write_rows: three rounds of 8 tasks of 8,192 rows and a few rows more, every seventh row left out;
  // against the same rows appended one by one (OutputFile lays rows out the same whatever the pieces).
  const std::size_t rows = 2 * 65536 + 5;
  const auto row         = [](std::string& s, std::size_t i) {
    if (i % 7 == 3) return false;
    gapfe::detail::append_number(s, static_cast<long long>(i)), s += ',';
    gapfe::detail::append_number(s, 0.1 * static_cast<double>(i) * static_cast<double>(i));
    return true;
  };
  const auto table = [&](const std::string& name, bool one_by_one) {
    const fs::path path = scratch("threads_pieces") / name;
    gapfe::OutputFile out(path.string());
    out.append("i,value\n");
    if (one_by_one) {
      for (std::size_t i = 0; i < rows; ++i)
        if (std::string s; row(s, i)) out.append(s + "\n");
    } else {
      gapfe::detail::write_rows(out, rows, row);
    }
    out.close();
    return read_text(path);
  };
  const std::string expected = table("one_by_one.csv", true);
  gapfe::set_worker_threads(3);
  CHECK(table("rows.csv", false) == expected);

  // append_binary: the UInt32 byte count and the values, as one base64 stream, for every way the header's
  // four bytes and the data share the groups of three, and for an array of several tasks' pieces.
  std::vector<std::vector<double>> arrays;
  for (std::size_t n = 0; n < 4; ++n) arrays.emplace_back(n, 1.0 / 3.0);
  arrays.emplace_back(2 * 3 * (std::size_t(1) << 18) / 8 + 11);
  for (std::size_t i = 0; i < arrays.back().size(); ++i) arrays.back()[i] = std::sin(static_cast<double>(i));
  for (const auto& values : arrays) {
    CAPTURE(values.size());
    const auto count = static_cast<std::uint32_t>(values.size() * sizeof(double));
    std::vector<unsigned char> stream(sizeof count + count);
    std::memcpy(stream.data(), &count, sizeof count);
    if (count > 0) std::memcpy(stream.data() + sizeof count, values.data(), count);
    std::string encoded = "<";
    gapfe::detail::append_binary(encoded, values);
    CHECK(encoded == "<" + base64(stream) + "\n");
  }
  std::vector<std::uint8_t> bytes;  // 0 to 8 data bytes after the header
  for (int n = 0; n <= 8; ++n, bytes.push_back(static_cast<std::uint8_t>(37 * n + 1))) {
    std::vector<unsigned char> stream = {static_cast<unsigned char>(n), 0, 0, 0};
    stream.insert(stream.end(), bytes.begin(), bytes.end());
    std::string encoded;
    gapfe::detail::append_binary(encoded, bytes);
    CHECK(encoded == base64(stream) + "\n");
  }

  // outline_sides: the sides of one cell or between materials, in node-pair order, as sorting them all
  // gives (a 40 x 30 grid, the cells of i >= 25 another material).
  const int ni = 40, nj = 30;
  std::vector<int> material;
  for (int j = 0; j < nj; ++j)
    for (int i = 0; i < ni; ++i) material.push_back(i >= 25 ? 1 : 0);
  const auto sides_of = [&](std::size_t e, const auto& side) {
    const int i = static_cast<int>(e) % ni, j = static_cast<int>(e) / ni, n = j * (ni + 1) + i;
    const int corner[4] = {n, n + 1, n + ni + 2, n + ni + 1};
    for (int k = 0; k < 4; ++k) side(corner[k], corner[(k + 1) % 4]);
  };
  std::vector<std::pair<std::array<int, 2>, int>> all;
  for (std::size_t e = 0; e < material.size(); ++e)
    sides_of(e, [&](int a, int b) { all.push_back({{std::min(a, b), std::max(a, b)}, material[e]}); });
  std::sort(all.begin(), all.end());
  std::vector<std::array<int, 2>> sorted;
  for (std::size_t k = 0; k < all.size(); ++k) {
    const bool shared = (k > 0 && all[k - 1].first == all[k].first) ||
                        (k + 1 < all.size() && all[k + 1].first == all[k].first);
    const bool between =
        k + 1 < all.size() && all[k + 1].first == all[k].first && all[k + 1].second != all[k].second;
    if (!shared || between) sorted.push_back(all[k].first);
  }
  const auto outline = gapfe::detail::outline_sides(material.size(), sides_of, material);
  CHECK(outline == sorted);
  CHECK(outline.size() == static_cast<std::size_t>(2 * (ni + nj) + nj));  // the boundary and the interface
}

TEST_CASE(
    "[threads][files] an increment's files written beside the next one's work: a failure to write them is "
    "thrown, and the increments before it stay") {
  // RunFiles (app/run_output.hpp) on the plastic tube's scene (15 load steps), its first two increments with
  // made-up values (the last increment, load factor 15, would be written by the caller's thread). A folder
  // planted where step_0002.vtu goes makes its write fail (output_file.hpp: the rename onto a folder). With
  // one thread the second write() throws; with two it returns at once, the files written on a thread of
  // their own, and finish() throws what that thread met. Either way both increments' table rows were
  // written (the tables come before the VTU file) and step_0001.vtu is whole.
  const gapfe::test::OneThreadAfter restore;
  const Deck tube = read_deck(read_input((kExamples / "plastic_tube.deck").string(), "deck"));
  const SceneModel model{tube, build_scene(tube), {}, {}};
  REQUIRE(model.description.steps() == 15);
  const app::Plan plan = app::make_plan(model.description, model.scene);
  const int nodes      = model.scene.grid.node_count();
  Solution solution;
  solution.displacement.setConstant(nodes, 3, 1e-3);
  solution.reaction.setZero(nodes, 3);
  const std::vector<PointValues> values(model.scene.mesh.cells.size());
  for (const int threads : {1, 2}) {
    CAPTURE(threads);
    set_worker_threads(threads);
    const fs::path out = scratch("beside_" + std::to_string(threads));
    fs::create_directories(out / "step_0002.vtu");
    std::ofstream(out / "step_0002.vtu" / "keep") << "x";
    std::ostringstream err;
    const app::RunRequest request{model.description, model.scene, plan, out.string(), err, false, {}, {}};
    app::RunResult result;
    app::RunFiles files(request);
    files.write(1, 1.0, solution, values, {}, {});
    if (threads == 1) {
      CHECK_THROWS_WITH_AS(files.write(2, 2.0, solution, values, {}, {}), doctest::Contains("step_0002.vtu"),
                           FileError);
      CHECK_NOTHROW(files.finish("beside", result));
      CHECK_FALSE(files.writer_failed());
    } else {
      CHECK_NOTHROW(files.write(2, 2.0, solution, values, {}, {}));
      CHECK_THROWS_WITH_AS(files.finish("beside", result), doctest::Contains("step_0002.vtu"), FileError);
      CHECK(files.writer_failed());
    }
    // The run's end came either way: the collection closed, the picture drawn.
    CHECK(read_text(out / "result.pvd").rfind("</VTKFile>") != std::string::npos);
    CHECK(fs::exists(out / "deformed.svg"));
    const auto rows = read_csv(out / "nodes.csv");
    CHECK(rows.size() == 2 * static_cast<std::size_t>(nodes));
    CHECK(read_text(out / "step_0001.vtu").rfind("</VTKFile>") != std::string::npos);
  }
}

TEST_CASE("[threads] gapfe run --threads 3 writes the files of --threads 1, byte for byte") {
  const gapfe::test::OneThreadAfter restore;
  // A plastic tube on a 60 x 20 grid scene: 1,200 cells, several tasks in every cell loop, 10 steps of
  // return mapping (assembly/cell_blocks.hpp), each written as tables and VTU files on the pool's threads.
  // The solver is Eigen's, which runs on one thread (CHOLMOD's factor on several OpenBLAS threads rounds
  // otherwise past 250,000 equations: docs/process.md "Threads").
  const fs::path scene = scratch("threads") / "plastic_grid.toml";
  std::ofstream(scene) << R"(title = "PLASTIC TUBE 100 < r < 200 ON A 60 X 20 GRID, PRESSURE 300 IN 10 STEPS"
[mesh]
grid = [61, 21]
[[mesh.segments]]
points = [[1, 1, 100.0, 0.0], [61, 1, 200.0, 0.0]]
[[mesh.segments]]
points = [[1, 21, 100.0, 20.0], [61, 21, 200.0, 20.0]]
[[mesh.segments]]
points = [[1, 1, 100.0, 0.0], [1, 21, 100.0, 20.0]]
[[mesh.segments]]
points = [[61, 1, 200.0, 0.0], [61, 21, 200.0, 20.0]]
[mesh.groups]
steel = { i = [1, 61], j = [1, 21] }
bore = { i = 1, j = [1, 21] }
[options]
plasticity = "return-mapping"
[steps]
count = 10
[materials.steel]
E = 200000.0
nu = 0.3
yield = 400.0
[[boundary]]
groups = "steel"
fix = "z"
[[load]]
curves = "bore"
pressure = 300.0
)";
  const fs::path one   = run_deck_file(scene, "threads_1", {"--solver", "eigen", "--threads", "1"});
  const fs::path three = run_deck_file(scene, "threads_3", {"--solver", "eigen", "--threads", "3"});
  int files            = 0;
  for (const auto& entry : fs::directory_iterator(one)) {
    const std::string name = entry.path().filename().string();
    CAPTURE(name);
    CHECK(read_text(entry.path()) == read_text(three / name));
    ++files;
  }
  CHECK(files >=
        18);  // the tables, history.csv, plasticity.csv, 10 steps' VTU files, result.pvd, deformed.svg
  CHECK(read_csv(one / "plasticity.csv").size() > 0);
}

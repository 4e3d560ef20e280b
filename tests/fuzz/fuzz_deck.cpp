// libFuzzer target for the input readers: read any bytes as a card deck and build its mesh, scene and
// load steps, as a Gmsh MSH file (input/gmsh_reader.hpp), as a VTU file drawn as gapfe plot would
// (input/vtu_reader.hpp), and as a scene file (input/scene_file.hpp) on the test meshes of tests/data/scenes
// (its [mesh] file names one of them). A deck or scene that reads and is small is then run as `gapfe run`
// runs it (fuzz_run.hpp) with tiny limits (two load steps, eight Newton iterations) into a scratch folder
// made ready by RunFolder. The only acceptable outcomes are a result or an InputError / SolveError; anything
// else (a crash, another exception, a FileError in the scratch folder, a sanitizer or _GLIBCXX_ASSERTIONS
// report, a hang) is a bug. CI runs it for a bounded time over examples/decks, tests/data/*.msh and
// tests/data/scenes/*.toml.
//   cmake -S . -B build/fuzz -DCMAKE_CXX_COMPILER=clang++ -DGAPFE_FUZZ=ON ...;
//   build/fuzz/tests/fuzz/fuzz_deck
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "gapfe/input/deck.hpp"
#include "gapfe/input/deck_scene.hpp"
#include "gapfe/input/gmsh_reader.hpp"
#include "gapfe/input/vtu_reader.hpp"
#include "gapfe/output/field_plot.hpp"
#include "gapfe/output/run_folder.hpp"
#include "gapfe/run/step_loads.hpp"

#include "fuzz_run.hpp"

#ifdef GAPFE_HAS_SCENE
#include "gapfe/input/scene_file.hpp"

#include "fuzz_meshes.hpp"
#endif

namespace {

/// Run a deck and its scene as `gapfe run` would, small: up to two load steps, eight Newton iterations,
/// into a scratch folder (the same one every input: RunFolder clears the last input's files).
void run_small(gapfe::ModelDescription model, const gapfe::Scene& scene) {
  if (scene.mesh.nodes.size() > 300 || scene.gaps.pairs.size() > 100) return;
  model.program.steps             = std::min(model.program.steps, 2);
  model.options.newton_iterations = std::min(model.options.newton_iterations, 8);
  static const std::string dir    = [] {  // a char array: no destructor runs before the exit handler
    static char name[] = "/tmp/gapfe_fuzz_XXXXXX";
    if (!::mkdtemp(name)) __builtin_trap();
    std::atexit([] { std::filesystem::remove_all(name); });  // libFuzzer ends with exit()
    return std::string(name);
  }();
  gapfe::RunFolder::prepare(dir, false, "fuzz");
  const bool gaps = !scene.needs.gaps.empty();
  scene.needs.plasticity.empty() ? gapfe::fuzz::run_elastic(model, scene, dir, gaps)
                                 : gapfe::fuzz::run_plastic(model, scene, dir, gaps);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  gapfe::InputLimits limits;
  limits.max_grid_points = 40'000;  // keep each input fast: the fuzzer explores the reader, not big meshes
  limits.max_load_steps  = 1'000;
  try {
    const gapfe::Deck deck   = gapfe::read_deck(text, {}, limits);
    const gapfe::Scene scene = gapfe::build_scene(deck);
    for (const auto& x : scene.mesh.nodes)
      if (!x.allFinite()) __builtin_trap();  // the generator must reject what it cannot place
    gapfe::StepLoads loads(deck, scene);
    for (int step = 1; step <= deck.steps() && step <= 3; ++step) (void)loads.at(step);
    if (size < (1u << 14)) run_small(deck, scene);
  } catch (const gapfe::InputError&) {
  } catch (const gapfe::SolveError&) {
  }
  if (size < (1u << 16)) {  // a mesh file: every node finite, every cell's nodes in range
    try {
      const gapfe::GmshMesh mesh = gapfe::read_gmsh(text);
      for (const auto& x : mesh.nodes)
        if (!x.allFinite() || x(0) < 0) __builtin_trap();
      for (const auto& c : mesh.cells)
        for (int a = 0; a < c.node_count; ++a)
          if (c.nodes[static_cast<std::size_t>(a)] < 0 ||
              c.nodes[static_cast<std::size_t>(a)] >= static_cast<int>(mesh.nodes.size()))
            __builtin_trap();
    } catch (const gapfe::InputError&) {
    }
  }
  if (size < (1u << 16)) {  // a VTU file as gapfe plot reads it, and its picture: every cell's points exist
    try {
      const gapfe::VtuData d = gapfe::read_vtu(text, "fuzz.vtu");
      for (const auto& cell : d.cells)
        for (const int n : cell)
          if (n < 0 || n >= static_cast<int>(d.points.size())) __builtin_trap();
      if (d.cell("stress") && !d.cells.empty())
        (void)gapfe::field_svg(d, gapfe::plot_field(d, "mises"), "fuzz");
    } catch (const gapfe::InputError&) {
    }
  }
#ifdef GAPFE_HAS_SCENE
  if (size < (1u << 14)) {  // a scene: its description and scene as the command would run them
    try {
      const gapfe::SceneModel m = gapfe::read_scene(text, gapfe::fuzz::scene_mesh, {}, limits);
      gapfe::StepLoads loads(m.description, m.scene);
      for (int step = 1; step <= m.description.steps() && step <= 3; ++step) (void)loads.at(step);
      for (const auto& p : m.scene.gaps.pairs)
        if (!std::isfinite(p.initial_gap) || !p.normal.allFinite()) __builtin_trap();
      run_small(m.description, m.scene);
    } catch (const gapfe::InputError&) {
    } catch (const gapfe::SolveError&) {
    }
  }
#endif
  return 0;
}

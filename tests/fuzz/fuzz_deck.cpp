// libFuzzer target for the input readers: read any bytes as a card deck and build its mesh and scene, as a
// Gmsh MSH file (mesh/gmsh_reader.hpp), as a VTU file drawn as gapfe plot would (io/vtu_reader.hpp), and as a
// scene file (io/scene_file.hpp) on the test meshes of tests/data/scenes (its [mesh] file names one of them).
// The only acceptable outcomes are a result or an InputError / SolveError; anything else (a crash, another
// exception, a sanitizer report, a hang) is a bug. CI runs it for a bounded time over examples/decks,
// tests/data/*.msh and tests/data/scenes/*.toml.
//   cmake -S . -B build/fuzz -DCMAKE_CXX_COMPILER=clang++ -DGAPFE_FUZZ=ON ...;
//   build/fuzz/tests/fuzz/fuzz_deck
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "gapfe/io/deck.hpp"
#include "gapfe/io/deck_scene.hpp"
#include "gapfe/io/field_plot.hpp"
#include "gapfe/io/vtu_reader.hpp"
#include "gapfe/mesh/gmsh_reader.hpp"
#ifdef GAPFE_HAS_SCENE
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "gapfe/io/scene_file.hpp"

namespace {

/// The scene tests' meshes by file name, read once.
std::string scene_mesh(const std::string& name) {
  static const std::map<std::string, std::string> meshes = [] {
    std::map<std::string, std::string> m;
    for (const char* file : {"thick_tube.msh", "two_tubes.msh", "plastic_tube.msh"}) {
      std::ifstream in(std::filesystem::path(GAPFE_SOURCE_DIR) / "tests/data/scenes" / file);
      std::ostringstream s;
      s << in.rdbuf();
      m[file] = s.str();
    }
    return m;
  }();
  const auto it = meshes.find(name);
  if (it == meshes.end()) throw gapfe::InputError("no mesh '" + name + "'");
  return it->second;
}

}  // namespace
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  gapfe::DeckLimits limits;
  limits.max_grid_points = 40'000;  // keep each input fast: the fuzzer explores the reader, not big meshes
  limits.max_load_steps  = 1'000;
  try {
    const gapfe::Deck deck       = gapfe::read_deck(text, {}, limits);
    const gapfe::DeckScene scene = gapfe::build_scene(deck);
    for (const auto& x : scene.mesh.nodes)
      if (!x.allFinite()) __builtin_trap();  // the generator must reject what it cannot place
    for (int step = 1; step <= deck.steps() && step <= 3; ++step) (void)gapfe::step_totals(deck, scene, step);
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
  if (size < (1u << 14)) {  // a scene: its deck and scene as the command would run them
    try {
      const gapfe::SceneModel m = gapfe::read_scene(text, scene_mesh, {}, limits);
      for (int step = 1; step <= m.deck.steps() && step <= 3; ++step)
        (void)gapfe::step_totals(m.deck, m.scene, step);
      for (const auto& p : m.scene.gaps.pairs)
        if (!std::isfinite(p.initial_gap) || !p.normal.allFinite()) __builtin_trap();
    } catch (const gapfe::InputError&) {
    } catch (const gapfe::SolveError&) {
    }
  }
#endif
  return 0;
}

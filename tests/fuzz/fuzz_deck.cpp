// libFuzzer target for the input readers: read any bytes as a card deck and build its mesh and scene, and
// as a Gmsh MSH file (mesh/gmsh_reader.hpp). The only acceptable outcomes are a result or an InputError /
// SolveError; anything else (a crash, another exception, a sanitizer report, a hang) is a bug. CI runs it for
// a bounded time over examples/decks and tests/data/*.msh.
//   cmake -S . -B build/fuzz -DCMAKE_CXX_COMPILER=clang++ -DGAPFE_FUZZ=ON ...;
//   build/fuzz/tests/fuzz/fuzz_deck
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "gapfe/io/deck.hpp"
#include "gapfe/io/deck_scene.hpp"
#include "gapfe/mesh/gmsh_reader.hpp"

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
  return 0;
}

#pragma once
// `gapfe run --accuracy`'s choice of the cells' order (docs/accuracy.md "A target accuracy"): halving the
// size of linear cells cuts the error 4 times for 4 times the nodes, while 8-node cells cut the
// displacements' 8 times and carry a peak stress 7 times closer on the same mesh, at 3 times the nodes. Which
// reaches a tolerance first depends on the model and the tolerance, so the ladder measures it: after the
// mesh's first three rungs in the model's element (their observed orders), the first two in quad8 (the
// probe, at assumed orders), and each ladder's remaining rungs foreseen (every quantity's error shrinking by
// 2^p a rung, each rung's time growing as the last two's did); the cheaper goes on. The probe costs about one
// and a half times the linear ladder's third rung, so it runs only when the linear ladder needs a fifth.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gapfe/app/error_bars.hpp"
#include "gapfe/app/report.hpp"
#include "gapfe/input/deck_refine.hpp"

namespace gapfe::app {

/// Why `--accuracy` keeps the model's cells rather than trying quadratic ones; "" when it may try them.
inline std::string order_kept(const Plan& p, const ModelDescription& d, const Scene& s) {
  if (s.is_quadratic()) return "its cells are quadratic already";
  if (d.options.element != ElementChoice::automatic) return "the model chooses its element";
  if (p.gaps) return "gap elements do not fit quadratic sides";
  if (p.plastic) return "a law with history (the choice is measured on elastic models only)";
  if (largest_poisson(d).second > kLockingPoisson && !s.mesh.triangles.empty())
    return "a Poisson's ratio near 1/2 (its 3-corner cells would become 6-node triangles, which lock)";
  return "";
}

/// A deck's model on quadratic cells (element = quad8) at 1/2^times of its spacing, times >= 0 (0: its own
/// grid); the deck is copied, its quadratic scene built at the first call.
inline Refiner deck_quadratic_refiner(const Deck& deck) {
  auto quadratic             = std::make_shared<Deck>(deck);
  quadratic->options.element = ElementChoice::quad8;
  auto scene                 = std::make_shared<std::optional<Scene>>();
  return [quadratic, scene](int times) {
    if (!*scene) *scene = build_scene(*quadratic);
    if (times == 0) return SceneModel{*quadratic, **scene, "", "the deck's grid, quadratic cells"};
    RefinedDeck r = refine_deck(*quadratic, **scene, times);
    return SceneModel{std::move(r.deck), std::move(r.scene), "",
                      "the grid at 1/" + std::to_string(1 << times) + " of its spacing, quadratic cells"};
  };
}

/// The quadratic cells `--accuracy` may switch to: the model on them at each spacing (deck_quadratic_refiner,
/// or a scene file read with element = quad8), or why it keeps its own (order_kept; `refine` then empty).
struct OrderChoice {
  Refiner refine;
  std::string kept;
};

}  // namespace gapfe::app

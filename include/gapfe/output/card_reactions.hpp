#pragma once
// A scene's boundary cards as the results read them: each card (a deck's BC card, a scene's [[boundary]]
// group; SAAC3X's driven faces) with its nodes, each once, and the directions it prescribes, and the total
// reaction of a card along a direction. history.csv's R_* columns and `--estimate`'s reactions
// (app/read_quantities.hpp) both sum them so.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "gapfe/input/scene.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

struct CardNodes {
  std::string name;        ///< bc1, bc2, ... (a deck's cards in order), a scene's groups, saac3x_bottom/top
  int code = 0;            ///< the directions some condition of the card prescribes, as a code's bits
  std::vector<int> nodes;  ///< 0-based, ascending, each once
};

/// The scene's cards in card order, then SAAC3X's bottom and top faces when it drives them.
inline std::vector<CardNodes> card_nodes(const Scene& scene) {
  std::map<int, CardNodes> by_index;
  for (std::size_t k = 0; k < scene.conditions.size(); ++k) {
    const int card = scene.condition_card.empty() ? 0 : scene.condition_card[k];
    CardNodes& c   = by_index[card];
    c.name         = card < static_cast<int>(scene.condition_cards.size())
                         ? scene.condition_cards[static_cast<std::size_t>(card)]
                         : "bc" + std::to_string(card + 1);
    c.code |= scene.conditions[k].code;
    c.nodes.push_back(scene.conditions[k].node);
  }
  std::vector<CardNodes> cards;
  for (auto& [index, card] : by_index) cards.push_back(std::move(card));
  if (const StrainRateTest& x = scene.strain_rate_test; x.active()) {
    cards.push_back({"saac3x_bottom", 2 | 4, x.bottom});
    cards.push_back({"saac3x_top", 2, x.top});
  }
  for (CardNodes& c : cards) {
    std::sort(c.nodes.begin(), c.nodes.end());
    c.nodes.erase(std::unique(c.nodes.begin(), c.nodes.end()), c.nodes.end());
  }
  return cards;
}

/// The total reaction of card `c` along `direction` (0 r, 1 z, 2 theta) [force, total ring force]; into
/// `size`, when given, the sum of its nodes' reactions' sizes, which a total that cancels to round-off is
/// measured against.
inline double card_reaction(const Solution& s, const CardNodes& c, int direction, double* size = nullptr) {
  double total = 0, sizes = 0;
  for (const int n : c.nodes) total += s.reaction(n, direction), sizes += std::abs(s.reaction(n, direction));
  if (size) *size = sizes;
  return total;
}

}  // namespace gapfe

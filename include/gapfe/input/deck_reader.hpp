#pragma once
// The card-deck reader: the deck's text to a Deck (input/deck_cards.hpp). It only parses: it checks each
// card's columns, counts and value ranges that need no mesh; input/deck_scene.hpp builds the mesh and checks
// what refers to it (node numbers, edges, material numbers). The readings of what the seed leaves open
// are listed in input/deck.hpp.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gapfe/input/deck_card_groups.hpp"
#include "gapfe/input/deck_cards.hpp"
#include "gapfe/input/deck_lines.hpp"

namespace gapfe {

/// Read a deck held in `text` (the string must outlive nothing: all values are copied). `overrides`
/// are applied after the deck's own `$` lines (the command line wins). Throws InputError naming the
/// card, the line, the columns and what was expected.
inline Deck read_deck(std::string_view text,
                      const std::vector<std::pair<std::string, std::string>>& overrides = {},
                      const InputLimits& limits                                         = {}) {
  Deck d;
  detail::DeckLines in(text);
  detail::read_extensions(in, d, overrides);
  detail::read_head_cards(in, d, limits);
  detail::read_mesh_cards(in, d);
  detail::read_temperature_cards(in, d);
  detail::read_material_cards(in, d);
  detail::read_load_cards(in, d);
  in.expect_end();
  return d;
}

}  // namespace gapfe

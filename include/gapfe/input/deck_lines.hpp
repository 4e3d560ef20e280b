#pragma once
// What the card-deck reader (input/deck_reader.hpp) reads with: the deck's lines one card at a time
// (DeckLines), card names for messages, the column layouts of the fields `fields = wide` widens, and the
// index rectangles of Data 5 and 6.
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "gapfe/input/deck_cards.hpp"
#include "gapfe/input/fixed_format.hpp"

namespace gapfe {

namespace detail {

class DeckLines {
 public:
  explicit DeckLines(std::string_view text) {
    std::size_t start = 0;
    while (start < text.size()) {
      std::size_t end = text.find('\n', start);
      if (end == std::string_view::npos) end = text.size();
      lines_.push_back(text.substr(start, end - start));
      start = end + 1;
    }
  }
  bool done() const { return next_ >= lines_.size(); }
  int line_number() const { return static_cast<int>(next_) + 1; }
  std::string_view peek() const { return lines_[next_]; }
  void skip() { ++next_; }
  /// The next card image, or an error that names the card the deck still owed.
  CardImage take(const std::string& card) {
    if (done())
      throw InputError(card + ": the deck ends after line " + std::to_string(lines_.size()) +
                       "; a count on the control cards asks for more cards than the deck has");
    const std::size_t k = next_++;
    return CardImage(lines_[k], static_cast<int>(k) + 1, card);
  }
  /// After the last card: only blank lines may follow.
  void expect_end() const {
    for (std::size_t k = next_; k < lines_.size(); ++k)
      if (lines_[k].find_first_not_of(" \r") != std::string_view::npos)
        throw InputError("line " + std::to_string(k + 1) +
                         ": unexpected card after the last load block; a count on the control cards (NUMPC, "
                         "NUMSC, NUMST, NLINC, INERT, INCI, INCF, NUMTC, IPLLOT) or the deck format (yield "
                         "cards: format = saac or elastic) disagrees with the cards");
  }

 private:
  std::vector<std::string_view> lines_;
  std::size_t next_ = 0;
};

inline std::string numbered(const std::string& data, const std::string& what, int k) {
  return data + " (" + what + " " + std::to_string(k) + ")";
}

/// The columns of the fields that `fields = wide` widens (ModelOptions::wide_fields). Legacy, as the seed:
/// line segment cards 3(2I3, 2F8.3), I5 and edge load cards 2I5, F10.0. Wide: line segment cards
/// 3(2I5, 2F12.3), I5 (grid indices to 99,999 as MAXI and MAXJ on Data 3, coordinates with four more
/// columns) and edge load cards 2I10, F10.0 (node numbers to 2,147,483,647).
struct CardLayout {
  int index_width;       ///< I and J of a segment point
  int coordinate_width;  ///< R and Z of a segment point (F.3)
  int node_width;        ///< M and N of an edge load card
  int point_width() const { return 2 * index_width + 2 * coordinate_width; }
};
inline constexpr CardLayout kLegacyCards{3, 8, 5}, kWideCards{5, 12, 10};

/// Minimum I, maximum I, minimum J, maximum J: four I5 fields from column `first` (Data 5 and 6),
/// within 1..MAXI and 1..MAXJ. A material block must span at least one cell (`spans_cell`: min < max);
/// a BC rectangle may be a line or a point (min <= max).
inline void read_index_rectangle(const CardImage& c, int first, const MeshControlCard& m, bool spans_cell,
                                 int& i1, int& i2, int& j1, int& j2) {
  i1                     = c.integer(first, first + 4, "minimum I");
  i2                     = c.integer(first + 5, first + 9, "maximum I");
  j1                     = c.integer(first + 10, first + 14, "minimum J");
  j2                     = c.integer(first + 15, first + 19, "maximum J");
  const char* order      = spans_cell ? " < " : " <= ";
  const std::string cell = spans_cell ? " (a block spans at least one cell)" : "";
  if (i1 < 1 || i2 < i1 + spans_cell || i2 > m.max_i)
    c.reject(first, first + 9, "I range",
             std::string("needs 1 <= minimum I") + order + "maximum I <= MAXI = " + std::to_string(m.max_i) +
                 cell);
  if (j1 < 1 || j2 < j1 + spans_cell || j2 > m.max_j)
    c.reject(first + 10, first + 19, "J range",
             std::string("needs 1 <= minimum J") + order + "maximum J <= MAXJ = " + std::to_string(m.max_j) +
                 cell);
}

}  // namespace detail

}  // namespace gapfe

#pragma once
// Two indices (nodes, slots; each below 2^32) as one 64-bit key: the hash sets and sorted lists of a mesh's
// edges, sides and pairs.
#include <algorithm>
#include <concepts>
#include <cstdint>

namespace gapfe {

/// The ordered pair (first, second) as one key, first in the high 32 bits.
template <std::integral I>
std::uint64_t pair_key(I first, I second) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(first)) << 32) |
         static_cast<std::uint32_t>(second);
}

/// The side between `a` and `b`, either way round, as one key.
template <std::integral I>
std::uint64_t side_key(I a, I b) {
  return pair_key(std::min(a, b), std::max(a, b));
}

}  // namespace gapfe

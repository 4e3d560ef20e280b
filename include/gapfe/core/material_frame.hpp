#pragma once
// The orientation of an element's material axes: data carried by every cell (mesh/mesh.hpp) and read by
// every law (core/concepts.hpp). The axes and 6x6 rotations built from it are in material/orientation.hpp.
namespace gapfe {

/// Orientation of an element's material axes [rad]. `beta`: in the meridian plane from +z toward +r;
/// `alpha`: helical angle out of it (seed card 6 BETA, ALPHA; the deck reader converts degrees).
struct MaterialFrame {
  double beta                                 = 0.0;  ///< [rad]
  double alpha                                = 0.0;  ///< [rad]
  bool operator==(const MaterialFrame&) const = default;
};

}  // namespace gapfe

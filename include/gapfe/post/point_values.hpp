#pragma once
// Strains and stresses at integration points and element centroids, in global (r, z, theta) Voigt
// order [rr, zz, hoop, rz, z-theta, theta-r] and in material axes [NN, SS, TT, NS, ST, TN].
// Strains carry engineering shears; stresses are tensor components. Units: stress as the moduli.
#include "gapfe/core/types.hpp"

namespace gapfe {

struct PointValues {
  int cell      = 0;      ///< index within its group
  bool triangle = false;  ///< group: false = the model's element, true = 3-corner cells
  int point     = 0;      ///< stiffness-point index; -1 for a centroid
  double r = 0, z = 0;    ///< position [length]
  Vec6 strain;            ///< total strain, global axes
  Vec6 stress;            ///< global axes
  Vec6 strain_material;   ///< material axes (N, S, T)
  Vec6 stress_material;   ///< material axes
  double eqps = 0.0;      ///< equivalent plastic strain (laws with history; 0 when elastic) [-]
};

}  // namespace gapfe

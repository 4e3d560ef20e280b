#pragma once
// Nodal temperatures from the seed's temperature cards (Data 9): NUMTC (r, z, T) points, or one
// constant. The seed does not say how SAAS spread card points to the nodes [I]; gapfe uses Shepard's
// inverse-distance weighting with power 2, which is exact where a point coincides with a node (within
// 1e-9 of the mesh size), bounded by the smallest and largest card temperature, and needs no
// connectivity. Give points at the nodes for an exact field.
#include <cmath>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/mesh/mesh.hpp"

namespace gapfe {

struct TemperaturePoint {
  double r = 0, z = 0;     ///< [length]
  double temperature = 0;  ///< [deg]
};

template <int NPC>
VecX nodal_temperatures(const Mesh<NPC>& mesh, const std::vector<TemperaturePoint>& points) {
  if (points.empty()) throw InputError("temperature field: no (r, z, T) points given");
  for (std::size_t k = 0; k < points.size(); ++k)
    if (!std::isfinite(points[k].r) || !std::isfinite(points[k].z) || !std::isfinite(points[k].temperature))
      throw InputError("temperature point " + std::to_string(k + 1) + ": non-finite value");
  const double tol2 = std::pow(1e-9 * mesh.size(), 2);
  VecX t(mesh.node_count());
  for (int n = 0; n < mesh.node_count(); ++n) {
    double sum_w = 0, sum_wt = 0;
    bool exact = false;
    for (const auto& p : points) {
      const double d2 = (mesh.nodes[n] - Vec2(p.r, p.z)).squaredNorm();
      if (d2 <= tol2) {
        t(n)  = p.temperature;
        exact = true;
        break;
      }
      sum_w += 1.0 / d2;
      sum_wt += p.temperature / d2;
    }
    if (!exact) t(n) = sum_wt / sum_w;
  }
  return t;
}

/// The seed's NUMTC = -2: one temperature everywhere.
template <int NPC>
VecX constant_temperature(const Mesh<NPC>& mesh, double temperature) {
  if (!std::isfinite(temperature)) throw InputError("constant temperature: non-finite value");
  return VecX::Constant(mesh.node_count(), temperature);
}

}  // namespace gapfe

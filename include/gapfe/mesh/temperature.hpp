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

/// `where`: how the input names the points, for errors ("DATA NO. 9, temperature card"): the point's number
/// is appended.
template <int NPC>
VecX nodal_temperatures(const Mesh<NPC>& mesh, const std::vector<TemperaturePoint>& points,
                        const std::string& where = "temperature point") {
  if (points.empty()) throw InputError("temperature field: no (r, z, T) points given");
  const auto point = [&](std::size_t k) {
    return where + " " + std::to_string(k + 1) + " (r = " + detail::number_text(points[k].r) +
           ", z = " + detail::number_text(points[k].z) + ")";
  };
  for (std::size_t k = 0; k < points.size(); ++k)
    if (!std::isfinite(points[k].r) || !std::isfinite(points[k].z) || !std::isfinite(points[k].temperature))
      throw InputError(point(k) + ": non-finite value");
  const double tol2 = std::pow(1e-9 * mesh.size(), 2);
  VecX t(mesh.node_count());
  std::vector<double> d2(points.size());
  for (int n = 0; n < mesh.node_count(); ++n) {
    // Weights relative to the nearest point's, d2_min / d2, in (0, 1]: a far point's underflows to 0 without
    // taking the near ones with it (1 / d2 of every point underflowed alike, and gave 0 / 0).
    std::size_t nearest = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
      d2[k] = (mesh.nodes[n] - Vec2(points[k].r, points[k].z)).squaredNorm();
      if (d2[k] < d2[nearest]) nearest = k;
    }
    if (d2[nearest] <= tol2) {
      t(n) = points[nearest].temperature;
      continue;
    }
    if (!std::isfinite(d2[nearest]))
      throw InputError(point(nearest) + ", the nearest of the temperature points to node " +
                       std::to_string(n + 1) + " (r = " + detail::number_text(mesh.nodes[n](0)) +
                       ", z = " + detail::number_text(mesh.nodes[n](1)) +
                       "), lies too far from it to interpolate: give the points near the mesh");
    double sum_w = 0, sum_wt = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const double w = d2[nearest] / d2[k];
      sum_w += w, sum_wt += w * points[k].temperature;
    }
    t(n) = sum_wt / sum_w;
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

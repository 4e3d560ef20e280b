#pragma once
// The checks of a Problem before anything is assembled, so that bad input gets an InputError naming what
// is wrong and where rather than a singular matrix or a NaN: the model (mesh, materials, temperatures),
// once per analysis, and the loads, before every solve (they may change between solves).
#include <cmath>
#include <string>
#include <type_traits>

#include "gapfe/assembly/cells.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/problem/problem.hpp"

namespace gapfe {

/// Mesh, materials and temperature field of `p`; node links `links` (node pairs) must join two nodes.
template <class M>
void check_model(const Problem<M>& p, const Connectivity<2>& links) {
  using Elem    = typename M::Element;
  const auto& m = p.mesh;
  if (m.nodes.empty()) throw InputError("the mesh has no nodes");
  if (m.cells.empty() && m.triangles.empty()) throw InputError("the mesh has no cells");
  if (p.materials.empty()) throw InputError("no materials given");
  for (std::size_t i = 0; i < p.materials.size(); ++i)
    p.materials[i].validate("material " + std::to_string(i + 1));
  if (!m.cell_tags.empty() && m.cell_tags.size() != m.cells.size())
    throw InputError("mesh: cell_tags must be empty or one per cell");
  if (!m.triangle_tags.empty() && m.triangle_tags.size() != m.triangles.size())
    throw InputError("mesh: triangle_tags must be empty or one per triangle");
  if constexpr (!kHasTriangles<Elem>)
    if (!m.triangles.empty())
      throw InputError("this element type has no 3-node companion: the mesh must not contain triangles");
  for (const auto& x : m.nodes)
    if (!x.allFinite()) throw InputError("mesh: a node has non-finite coordinates");
  for_each_cell<Elem>(m, [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                       const std::array<int, NPC>& cell, const CellTag& tag) {
    const std::string name =
        std::string(std::is_same_v<E, Elem> ? "element " : "triangle ") + std::to_string(e + 1);
    for (int n : cell)
      if (n < 0 || n >= m.node_count()) throw InputError(name + ": node index out of range");
    if (tag.material < 0 || tag.material >= static_cast<int>(p.materials.size()))
      throw InputError(name + ": material " + std::to_string(tag.material + 1) + " is not defined");
    if (!std::isfinite(tag.frame.beta) || !std::isfinite(tag.frame.alpha))
      throw InputError(name + ": non-finite material angle");
    const auto x = cell_coords<E>(m, cell);
    double det   = 0;
    for (int q = 0; q < E::kStiffnessPoints; ++q) {
      const auto g = E::stiffness_point(x, q, det);
      if (!(det > 0) || !(g.r > 0)) {
        std::string nodes;
        for (int n : cell) nodes += " " + std::to_string(n + 1);
        throw InputError(name + " (nodes" + nodes +
                         ") is inverted, degenerate or not counterclockwise (Jacobian " +
                         std::to_string(det) + " at point " + std::to_string(q + 1) + ")");
      }
    }
  });
  if (p.temperature.size() != 0 && p.temperature.size() != m.node_count())
    throw InputError("temperature: one value per node expected, got " + std::to_string(p.temperature.size()));
  for (const auto& l : links)
    if (l[0] < 0 || l[1] < 0 || l[0] >= m.node_count() || l[1] >= m.node_count() || l[0] == l[1])
      throw InputError("node link (" + std::to_string(l[0] + 1) + ", " + std::to_string(l[1] + 1) +
                       "): needs two different nodes of the mesh");
}

/// Edge load number k (0-based) of a list: finite, and within what DofsPerNode components can carry.
template <int DofsPerNode>
void check_edge_load(const EdgeLoad& l, std::size_t k) {
  if (!std::isfinite(l.pressure) || !std::isfinite(l.shear) || !std::isfinite(l.transverse_shear))
    throw InputError("edge load " + std::to_string(k + 1) + ": non-finite value");
  if (DofsPerNode == 2 && l.transverse_shear != 0)
    throw InputError("edge load " + std::to_string(k + 1) +
                     ": a transverse (theta) shear needs the 3-DOF (SAGA) kinematics");
}

/// Temperatures, inertia and edge loads of `p`: finite, and within what the kinematics can carry.
template <class M>
void check_loads(const Problem<M>& p) {
  constexpr int kNd = M::kDofsPerNode;
  if (!p.temperature.allFinite() || !std::isfinite(p.reference_temperature))
    throw InputError("temperature: non-finite value");
  const auto& in = p.inertia;
  if (!std::isfinite(in.axial_acceleration) || !std::isfinite(in.angular_velocity) ||
      !std::isfinite(in.angular_acceleration))
    throw InputError("inertia load: non-finite value");
  for (std::size_t k = 0; k < p.edge_loads.size(); ++k) check_edge_load<kNd>(p.edge_loads[k], k);
  if (kNd == 2 && in.angular_acceleration != 0)
    throw InputError(
        "inertia load: angular acceleration loads u_theta and needs the 3-DOF (SAGA) kinematics");
}

}  // namespace gapfe

#pragma once
// The checks of a Problem before anything is assembled, so that bad input gets an InputError naming what
// is wrong and where rather than a singular matrix or a NaN: the model (mesh, materials, temperatures),
// once per analysis, and the loads, before every solve (they may change between solves).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <type_traits>
#include <vector>

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

/// Every body (nodes joined by cells or node links) held along z, and in 3-DOF about the axis, by at least
/// one prescribed component (`equation` from DofMap: -1 where prescribed). An axisymmetric body translates
/// along the axis, and spins as u_theta = w r, at no strain (docs/theory.md), so a body that nothing holds
/// has a singular stiffness. The factorization sees this only while round-off leaves the zero pivot small:
/// on the thick tube free in z it reported the singular system up to 80 x 40 cells and from 120 x 60 on
/// solved it, with an arbitrary axial shift, without a word. A SolveError worded as the factorization's
/// (System::factorize). Bodies joined by node links (gap pairs, contact) count as one: whether a link
/// holds is the factorization's to find.
template <int DofsPerNode, class Elem, class MeshT>
void check_held(const MeshT& m, const std::vector<int>& equation, const Connectivity<2>& links) {
  const auto nn = static_cast<std::size_t>(m.node_count());
  std::vector<int> parent(nn);
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int a) {
    while (parent[std::size_t(a)] != a)
      a = parent[std::size_t(a)] = parent[std::size_t(parent[std::size_t(a)])];
    return a;
  };
  const auto join = [&](int a, int b) {  // the body's root is its lowest node
    a = root(a), b = root(b);
    if (a != b) parent[std::size_t(std::max(a, b))] = std::min(a, b);
  };
  std::vector<char> in_cell(nn, 0);  // the first node of a cell: its body has a cell
  for_each_cell<Elem>(m, [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                       const std::array<int, NPC>& cell, const CellTag&) {
    in_cell[std::size_t(cell[0])] = 1;
    for (const int n : cell) join(cell[0], n);
  });
  for (const auto& l : links) join(l[0], l[1]);
  // Per root: 1 has a cell, 2 held along z, 4 held about the axis; and its node count.
  std::vector<int> flags(nn, 0), count(nn, 0);
  for (std::size_t n = 0; n < nn; ++n) {
    const auto r = std::size_t(root(int(n)));
    ++count[r];
    if (in_cell[n]) flags[r] |= 1;
    if (equation[n * DofsPerNode + 1] < 0) flags[r] |= 2;
    if (DofsPerNode == 3 && equation[n * DofsPerNode + 2] < 0) flags[r] |= 4;
  }
  const std::string remedy =
      std::string(": ") + kRigidBodyHint + ": prescribe that component at one of its nodes at least";
  for (std::size_t n = 0; n < nn; ++n) {
    if (!(flags[n] & 1)) continue;  // not a root, or a node in no cell (the factorization's to refuse)
    const std::string body = "nothing holds the body of node " + std::to_string(n + 1) + " (" +
                             std::to_string(count[n]) + " nodes) ";
    if (!(flags[n] & 2))
      throw SolveError("the stiffness is singular near node " + std::to_string(n + 1) + " u_z: " + body +
                       "along z, and it moves along the axis at no strain" + remedy);
    if (DofsPerNode == 3 && !(flags[n] & 4))
      throw SolveError("the stiffness is singular near node " + std::to_string(n + 1) + " u_theta: " + body +
                       "about the axis, and it spins (u_theta = w r) at no strain" + remedy);
  }
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

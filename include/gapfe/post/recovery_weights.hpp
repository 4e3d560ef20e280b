#pragma once
// The patch recovery of the error estimate (post/error_estimate.hpp) as weights. The least-squares fit
// through a patch's point stresses is linear in those stresses, so the recovered stress at a node is a
// weighted sum of them, sigma*_n = sum over the patch's points i of w_i sigma_i, with weights that depend on
// where the points lie only (post/patch_recovery.hpp's node_row). A run estimates every accepted increment
// on one mesh: it fits the patches once, here, and each later estimate is one weighted sum per point and node
// (the patches' sums and their small solves were about a third of quad4's estimate: BENCHMARKS.md).
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include "gapfe/assembly/cells.hpp"
#include "gapfe/post/patch_recovery.hpp"

namespace gapfe {

/// The recovery's slots and weights for one mesh, element and set of left-out materials (estimate_error's
/// `weights`): the first estimate given it notes the mesh, the second on the same mesh builds them (the
/// first, when `several`), and later ones reuse them. A different mesh, element or skip list starts it again;
/// the mesh is told by a fingerprint of its node coordinates, cells and materials, so a mesh changed in place
/// is one too.
struct RecoveryWeights {
  const void* element = nullptr;  ///< whose stiffness points (detail::kElementTag)
  std::uint64_t mesh  = 0;        ///< detail::mesh_fingerprint of the mesh
  std::vector<int> skip;          ///< the materials left out (gap elements)
  detail::RecoverySlots slots{0};
  /// For each recovered cell (cells, then triangles, in for_each_cell's order), for each stiffness point q,
  /// for each of its nodes c: the share of point q's stress in the recovered stress of c's slot.
  std::vector<double> weight;
  bool seen  = false;  ///< an estimate ran on this mesh: the next one builds the weights
  bool built = false;
  /// Set by a caller that will estimate on one mesh several times (a run of several load steps): the first
  /// estimate builds the weights, rather than fitting its own stresses first. Kept when the mesh changes.
  bool several = false;

  bool fits(const void* elem, std::uint64_t fingerprint, const std::vector<int>& left_out) const {
    return seen && elem == element && fingerprint == mesh && left_out == skip;
  }
  /// Forget the weights and note the mesh as seen.
  void remember(const void* elem, std::uint64_t fingerprint, const std::vector<int>& left_out) {
    const bool keep = several;
    *this           = RecoveryWeights{};
    element = elem, mesh = fingerprint, skip = left_out, seen = true, several = keep;
  }
};

namespace detail {

/// A distinct address per element type: which element's stiffness points a fit is for.
template <class E>
inline constexpr char kElementTag = 0;

/// A fingerprint of what a patch fit depends on: the node coordinates, the cells' nodes and their materials
/// (word by word, multiply and xor-shift: any change changes it but for a chance of about 2^-64). Four
/// independent lanes (r, z, the cells' nodes, their materials), folded at the end, so that a run, which takes
/// it at every increment, has four short chains of multiplies instead of one long one (the same instructions;
/// the time saved was not measured apart).
template <class MeshT>
std::uint64_t mesh_fingerprint(const MeshT& mesh) {
  std::uint64_t lane[4] = {0xcbf29ce484222325ULL, 0x84222325cbf29ce4ULL, 0x9e3779b97f4a7c15ULL,
                           0xbf58476d1ce4e5b9ULL};
  const auto mix        = [](std::uint64_t& h, std::uint64_t word) {
    h = (h ^ word) * 0x100000001b3ULL;
    h ^= h >> 29;
  };
  const auto index = [](int i) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)); };
  for (const Vec2& x : mesh.nodes)
    mix(lane[0], std::bit_cast<std::uint64_t>(x(0))), mix(lane[1], std::bit_cast<std::uint64_t>(x(1)));
  for (std::size_t e = 0; e < mesh.cells.size(); ++e) {
    for (const int n : mesh.cells[e]) mix(lane[2], index(n));
    mix(lane[3], index(mesh.cell_tag(e).material));
  }
  mix(lane[2], mesh.cells.size());  // where the cells end and the triangles begin
  for (std::size_t e = 0; e < mesh.triangles.size(); ++e) {
    for (const int n : mesh.triangles[e]) mix(lane[2], index(n));
    mix(lane[3], index(mesh.triangle_tag(e).material));
  }
  std::uint64_t h = mesh.nodes.size();
  for (const std::uint64_t l : lane) mix(h, l);
  return h;
}

/// Whether a cell of material `material` is left out of the recovery.
inline bool left_out(const std::vector<int>& skip, int material) {
  return std::find(skip.begin(), skip.end(), material) != skip.end();
}

/// Where a cell's stiffness point q lies (r, z).
template <class E>
Vec2 stiffness_point_position(const Mat<E::kNodes, 2>& x, const Mat<E::kShapeNodes, 2>& xs, int q) {
  double det   = 0;
  const auto g = E::stiffness_point(x, q, det);
  return {g.r, g.N.dot(xs.col(1))};
}

/// Adds one cell's stiffness points to its nodes' patches (`slot`: its nodes' slots): point_at(q) gives
/// point q's position and stress. A plane's sums are taken about the cell's first corner and moved to each
/// corner (one set of point sums per cell); a quadratic's do not move by a cheap shift: each node's own.
/// The estimate's own fit and the kept weights' build both add through here, so their sums are the same and
/// node_row() takes the same branch (quadratic, plane or mean) either way.
template <class E, int S, int P, class MeshT, std::size_t NPC, class PointAt>
void add_to_patches(std::vector<PatchSums<S, P>>& sums, const std::array<std::size_t, E::kNodes>& slot,
                    const MeshT& mesh, const std::array<int, NPC>& cell, PointAt&& point_at) {
  const Vec2& origin = mesh.nodes[cell[0]];
  PatchSums<S, P> own;
  for (int q = 0; q < E::kStiffnessPoints; ++q) {
    const auto [point, stress] = point_at(q);
    if constexpr (P == 3)
      own.add(point - origin, stress);
    else
      for (int c = 0; c < E::kNodes; ++c) sums[slot[c]].add(point - mesh.nodes[cell[c]], stress);
  }
  if constexpr (P == 3)
    for (int c = 0; c < E::kNodes; ++c) sums[slot[c]].add_shifted(own, origin - mesh.nodes[cell[c]]);
}

/// A slot per node and material around it, of the cells not left out.
template <class Elem, class MeshT>
RecoverySlots recovery_slots(const MeshT& mesh, const std::vector<int>& skip) {
  RecoverySlots slots(mesh.node_count());
  for_each_cell<Elem>(mesh,
                      [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                    const std::array<int, NPC>& cell, const CellTag& tag) {
                        if (!left_out(skip, tag.material))
                          for (int c = 0; c < E::kNodes; ++c) slots.add(cell[c], tag.material);
                      });
  slots.finish();
  return slots;
}

}  // namespace detail

/// The weights of the patch recovery with P terms (3: a plane, 6: a quadratic) on `mesh`, leaving out the
/// cells of the `skip` materials.
/// `fingerprint`: the mesh's (detail::mesh_fingerprint), when the caller has it already.
template <class Elem, int P, class MeshT>
RecoveryWeights recovery_weights(const MeshT& mesh, const std::vector<int>& skip,
                                 std::optional<std::uint64_t> fingerprint = std::nullopt) {
  RecoveryWeights w;
  w.remember(&detail::kElementTag<Elem>, fingerprint ? *fingerprint : detail::mesh_fingerprint(mesh), skip);
  w.slots = detail::recovery_slots<Elem>(mesh, skip);
  std::vector<Vec2> position;  // of each recovered cell's stiffness points, in order
  const auto each_cell = [&](auto&& f) {
    for_each_cell<Elem>(mesh,
                        [&]<class E, std::size_t NPC>(std::type_identity<E> tag_type, std::size_t,
                                                      const std::array<int, NPC>& cell, const CellTag& tag) {
                          if (!detail::left_out(skip, tag.material)) f(tag_type, cell, tag.material);
                        });
  };
  position.reserve(mesh.cells.size() * Elem::kStiffnessPoints + mesh.triangles.size() * 6);
  each_cell([&]<class E, std::size_t NPC>(std::type_identity<E>, const std::array<int, NPC>& cell, int) {
    const auto x  = cell_coords<E>(mesh, cell);
    const auto xs = E::shape_coords(x);
    for (int q = 0; q < E::kStiffnessPoints; ++q)
      position.push_back(detail::stiffness_point_position<E>(x, xs, q));
  });
  // Each patch's normal sums (of a stress of one component, left at zero: the right-hand side goes unused),
  // then its row.
  using Sums = detail::PatchSums<1, P>;
  std::vector<Sums> sums(w.slots.size());
  const Vec2* point = position.data();
  each_cell(
      [&]<class E, std::size_t NPC>(std::type_identity<E>, const std::array<int, NPC>& cell, int material) {
        std::array<std::size_t, E::kNodes> slot;
        for (int c = 0; c < E::kNodes; ++c) slot[c] = w.slots(cell[c], material);
        detail::add_to_patches<E>(sums, slot, mesh, cell,
                                  [&](int q) { return std::pair(point[q], Vec<1>::Zero().eval()); });
        point += E::kStiffnessPoints;
      });
  std::vector<Vec<P>> rows(sums.size());
  for (std::size_t k = 0; k < sums.size(); ++k) rows[k] = sums[k].node_row();
  sums = {};
  w.weight.reserve(position.size() * Elem::kNodes);
  point = position.data();
  each_cell(
      [&]<class E, std::size_t NPC>(std::type_identity<E>, const std::array<int, NPC>& cell, int material) {
        std::array<std::size_t, E::kNodes> slot;
        for (int c = 0; c < E::kNodes; ++c) slot[c] = w.slots(cell[c], material);
        for (int q = 0; q < E::kStiffnessPoints; ++q, ++point)
          for (int c = 0; c < E::kNodes; ++c)
            w.weight.push_back(rows[slot[c]].dot(Sums::terms(*point - mesh.nodes[cell[c]])));
      });
  w.built = true;
  return w;
}

}  // namespace gapfe

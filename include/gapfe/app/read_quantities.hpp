#pragma once
// The quantities a user reads off a run, which `gapfe run --estimate` gives error bars (app/error_bars.hpp;
// docs/accuracy.md "Error bars"): each BC card's (a scene's [[boundary]] group's) reaction along each
// direction it holds, the largest displacement and the largest von Mises stress with where they are. The same
// list on any mesh of one model: the cards and groups are the model's, not the mesh's.
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "gapfe/contact/pair_state.hpp"
#include "gapfe/input/scene.hpp"
#include "gapfe/output/card_reactions.hpp"
#include "gapfe/post/peak_stress.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe::app {

/// One quantity of a run's last increment.
struct ReadQuantity {
  std::string name;             ///< "reaction bc1 R_z", "largest |u|", "largest von Mises"
  double value = 0;             ///< [force] total ring force, [length], [stress]
  Vec2 at      = Vec2::Zero();  ///< where, for a largest value (r, z) [length]
  bool located = false;         ///< whether `at` means something
  /// The order of convergence in h of its error, assumed when only two meshes are solved: reactions and
  /// displacements as the energy on linear cells (2), as the displacements in L2 on quadratic ones (3, below
  /// the energy's 4: the bar errs large); the recovered peak stress 2 on either (post/peak_stress.hpp).
  double order = 2;
  /// What round-off in it is relative to: a sum's terms' sizes (a card whose reactions cancel, gap pairs'
  /// forces); 0: the value itself.
  double scale = 0;
};

/// The largest von Mises stress, a nodal recovered one: on quadratic cells the error estimate's `peak`
/// (ErrorEstimate::peak_mises and its node, -1 when the run did not estimate; the estimate's quadratic
/// patches through the 3 x 3 points are second order at a boundary too, 7 times closer on the Lame tube than
/// the centroids'), else recovered from the cells' centroid stresses (post/peak_stress.hpp). A law
/// with history (`plastic`) keeps its stresses on its yield surface, which a recovered field would cross
/// (by 1% on the plastic tube): its largest is the centroids', first order (half a cell from a boundary's
/// peak). A gap element's stress is a device's: left out.
inline ReadQuantity largest_mises(const Scene& scene, const std::vector<PointValues>& centroids,
                                  const PeakStress& peak, bool plastic) {
  ReadQuantity mises{"largest von Mises", 0, Vec2::Zero(), true, plastic ? 1.0 : 2.0};
  if (plastic) {
    const std::size_t quads = scene.mesh.cells.size();
    for (std::size_t e = 0; e < centroids.size(); ++e) {
      const CellTag tag = e < quads ? scene.mesh.cell_tag(e) : scene.mesh.triangle_tag(e - quads);
      if (tag.material == scene.gap_material) continue;
      if (const double s = voigt::von_mises(centroids[e].stress); s > mises.value)
        mises.value = s, mises.at = Vec2(centroids[e].r, centroids[e].z);
    }
    return mises;
  }
  const PeakStress nodal = scene.is_quadratic() && peak.node >= 0
                               ? peak
                               : recovered_peak(scene.mesh, centroids, scene.gap_material);
  mises.value = nodal.mises, mises.located = nodal.node >= 0;
  if (mises.located) mises.at = scene.mesh.nodes[static_cast<std::size_t>(nodal.node)];
  return mises;
}

/// The quantities of a solution on `scene` (whole, not a part's), with the cells' centroid stresses
/// (cells, then triangles, as a driver's centroid_values gives them), the error estimate's nodal peak and
/// whether the law has history (largest_mises).
inline std::vector<ReadQuantity> read_quantities(const Scene& scene, const Solution& solution,
                                                 const std::vector<PointValues>& centroids,
                                                 const PeakStress& peak = {}, bool plastic = false) {
  std::vector<ReadQuantity> out;
  const double order = scene.is_quadratic() ? 3 : 2;
  static constexpr std::array<const char*, 3> kDirection{"R_r", "R_z", "R_t"};
  for (const CardNodes& card : card_nodes(scene))  // each card's total reaction along what it holds
    for (int d = 0; d < 3; ++d)
      if ((card.code >> d) & 1) {
        double size        = 0;
        const double total = card_reaction(solution, card, d, &size);
        out.push_back(
            {"reaction " + card.name + " " + kDirection[d], total, Vec2::Zero(), false, order, size});
      }

  ReadQuantity u{"largest |u|", 0, Vec2::Zero(), true, order};
  for (Eigen::Index n = 0; n < solution.displacement.rows(); ++n)
    if (const double size = solution.displacement.row(n).norm(); size > u.value)
      u.value = size, u.at = scene.mesh.nodes[static_cast<std::size_t>(n)];
  out.push_back(u);
  out.push_back(largest_mises(scene, centroids, peak, plastic));
  return out;
}

/// The gap pairs' sums: the normal force of the closed pairs, and with friction their tangential force along
/// the interface in the (r, z) plane (PairState::tangential_force's T component) [force, total ring forces].
inline void add_contact_quantities(std::vector<ReadQuantity>& out, const std::vector<PairState>& states,
                                   bool friction) {
  double normal = 0, tangential = 0, sizes = 0;
  for (const PairState& s : states)
    if (s.closed)
      normal += s.normal_force, tangential += s.tangential_force(0), sizes += std::abs(s.normal_force);
  out.push_back({"contact normal force", normal, Vec2::Zero(), false, 2, sizes});
  if (friction) out.push_back({"contact friction force", tangential, Vec2::Zero(), false, 2, sizes});
}

}  // namespace gapfe::app

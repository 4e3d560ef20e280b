#pragma once
// The extended slip model's stick check (seed section 3.2; contact/friction.hpp, Extended): at an accepted
// increment, each closed pair's status for the next step from the mean stress of the structural elements
// around it. The one-step lag of the seed's model is here: the status a step runs with was decided by the
// stresses before it.
#include <algorithm>
#include <cmath>
#include <vector>

#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/contact/pair_state.hpp"
#include "gapfe/core/history.hpp"
#include "gapfe/core/subdomain.hpp"
#include "gapfe/core/types.hpp"
#include "gapfe/mesh/mesh.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

/// The structural elements around each pair: every cell of `mesh` not of a `gap_materials` material with
/// node a or b, as indices into centroid values (cells, then triangles).
template <class MeshT>
std::vector<std::vector<int>> structural_cells_around(const std::vector<GapPair>& pairs, const MeshT& mesh,
                                                      const std::vector<int>& gap_materials) {
  const auto real = [&](const CellTag& t) {
    return std::find(gap_materials.begin(), gap_materials.end(), t.material) == gap_materials.end();
  };
  std::vector<std::vector<int>> around(pairs.size());
  const auto add = [&](int index, const auto& nodes) {
    for (std::size_t p = 0; p < pairs.size(); ++p)
      for (const int v : nodes)
        if (v == pairs[p].node_a || v == pairs[p].node_b) {
          around[p].push_back(index);
          break;
        }
  };
  for (std::size_t e = 0; e < mesh.cells.size(); ++e)
    if (real(mesh.cell_tag(e))) add(static_cast<int>(e), mesh.cells[e]);
  for (std::size_t e = 0; e < mesh.triangles.size(); ++e)
    if (real(mesh.triangle_tag(e))) add(static_cast<int>(mesh.cells.size() + e), mesh.triangles[e]);
  return around;
}

/// Every closed pair of the committed states (`pairs`, `states`) sticks for the next step while the mean
/// stress of its cells `around` (from the centroid `values`), rotated to (N, T, S), has sigma_NN < 0 and a
/// resultant shear sqrt(tau_NT^2 + tau_NS^2) < mu |sigma_NN|; it slips otherwise. A part of a partitioned
/// problem (`part`) holds only its own cells around a pair, so the parts' sums are added (collective).
/// Returns whether any pair switched: its tangential spring changes (k in stick, 0 in slip), so the next
/// solve must factorize again (reusing the factor left the steps after a switch solved with the old
/// springs: relative residual 0.44-0.66 on the press fit).
inline bool decide_stick_slip(const std::vector<GapPair>& pairs, History<PairState>& states,
                              const std::vector<std::vector<int>>& around_cells,
                              const std::vector<PointValues>& values, const Subdomain* part, double mu) {
  // Per pair, the sum of the stress tensors around it (9) and their count.
  std::vector<double> around(10 * pairs.size(), 0.0);
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    if (!states.committed(p).closed) continue;
    Eigen::Map<Mat33> sum(around.data() + 10 * p);
    for (const int c : around_cells[p])
      sum += voigt::stress_tensor(values[static_cast<std::size_t>(c)].stress);
    around[10 * p + 9] = static_cast<double>(around_cells[p].size());
  }
  if (part) part->sum(around.data(), static_cast<int>(around.size()));
  bool switched = false;
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const double count = around[10 * p + 9];
    if (!states.committed(p).closed || count == 0) continue;
    const Mat33 sigma  = Eigen::Map<const Mat33>(around.data() + 10 * p) / count;
    const Vec2 tangent = pairs[p].tangent();
    const Vec3 n(pairs[p].normal(0), pairs[p].normal(1), 0.0), t(tangent(0), tangent(1), 0.0), theta(0, 0, 1);
    const double normal = n.dot(sigma * n);
    const double shear  = std::hypot(t.dot(sigma * n), theta.dot(sigma * n));
    const bool stick    = normal < 0 && shear < mu * -normal;
    if (states.committed(p).slipping == stick) switched = true;
    states.amend(p, [&](PairState& s) { s.slipping = !stick; });
  }
  return switched;
}

}  // namespace gapfe

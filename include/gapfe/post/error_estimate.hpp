#pragma once
// The energy-norm error of a solution, estimated cell by cell by stress recovery (Zienkiewicz and Zhu's
// estimator with their superconvergent patch recovery; docs/accuracy.md):
//   1. at every node, for each material around it, a polynomial in (r, z) of the cells' order (a plane; a
//      quadratic for Quad8 and Tri6) is fitted by least squares to the stresses at the stiffness points of
//      the cells of that material around the node (its patch, post/patch_recovery.hpp); its value at the node
//      is the recovered stress sigma* there. A patch too small for it falls back to a plane, then to the
//      mean.
//   2. In each cell sigma* is interpolated from its nodes, and the error is
//        eta_e^2 = integral over the cell of (sigma* - sigma_h)^T C^-1 (sigma* - sigma_h) dV,
//      with C the law's elastic stiffness and sigma_h the stresses kept at the stiffness points, exactly: on
//      quad4 sigma_h is bilinear through its 2 x 2 points' values (at those points alone it is at its most
//      accurate, and the error would read as nothing there), on a constant-strain triangle it is constant;
//      Quad8's biquadratic through its 3 x 3 points is integrated on 4 x 4, Tri6's on its own 6 points.
// The relative error is eta / sqrt(|u_h|^2 + eta^2), |u_h|^2 = sum over the stiffness points of
// w sigma_h^T C^-1 sigma_h: the stiffness's own quadrature, so for a linear law without thermal strain it is
// u^T K u (without body loads on the legacy quad), the discrete energy that Galerkin orthogonality speaks of
// (docs/accuracy.md).
// Each material is recovered on its own: its stresses jump across a bond to another material.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/LU>

#include "gapfe/post/cell_error.hpp"
#include "gapfe/post/patch_recovery.hpp"
#include "gapfe/post/recovery.hpp"
#include "gapfe/post/recovery_weights.hpp"

namespace gapfe {

/// Stresses below this fraction of a model's stress scale (estimate_error) are round-off: a solve leaves
/// relative errors of about 1e-13 in the displacements, and a 1e-9 margin keeps any real stress above it.
inline constexpr double kRoundOff = 1e-9;

/// What estimate_error() finds.
struct ErrorEstimate {
  /// Per cell (cells, then triangles): its energy-norm error relative to the whole solution's norm,
  /// eta_e / sqrt(|u_h|^2 + eta^2) [-]; their squares sum to relative()^2.
  std::vector<double> cell;
  double error_squared  = 0;  ///< eta^2, summed over the cells [force x length]
  double energy_squared = 0;  ///< |u_h|^2: w sigma_h^T C^-1 sigma_h summed at the stiffness points
  /// The largest von Mises stress of the recovered field sigma* over the nodes (a node between materials
  /// has each material's), and that node [stress]; -1: no cell estimated. On quadratic cells it converges
  /// at second order with a small constant, the boundary's nodes included; on linear cells a boundary
  /// node's is first order (post/peak_stress.hpp says why and does better). A part's own when partitioned.
  double peak_mises = 0;
  int peak_node     = -1;
  /// Whether every stress is round-off (a body in free thermal expansion, or moved rigidly): then there is no
  /// error to estimate, and the ratio of two round-offs would mean nothing.
  bool stress_free = false;
  /// The global relative energy-norm error, eta / sqrt(|u_h|^2 + eta^2) [-]; 0 when stress_free, NaN when a
  /// sum is not finite.
  double relative() const {
    const double whole = error_squared + energy_squared;
    if (!std::isfinite(whole)) return std::numeric_limits<double>::quiet_NaN();
    return whole > 0 && !stress_free ? std::sqrt(error_squared / whole) : 0.0;
  }
};

namespace detail {

/// What step 1 of estimate_error() leaves: the stresses at the stiffness points (restricted to the
/// kinematics' components; the assembler's point slots), sigma* per recovery slot, and the largest stress
/// with the round-off a stress of this model carries: about the unit round-off of the stiffness times the
/// strains the displacements and temperatures could make (max |u| over a cell's side, and the thermal
/// strain).
template <int S>
struct PointStresses {
  std::vector<Vec<S>> stress, recovered;
  double peak = 0, noise = 0;
  double energy = 0;  ///< |u_h|^2: sum over the stiffness points of w sigma_h^T C^-1 sigma_h
};

/// One cell's part of step 1, computed on any thread (assembly/cell_blocks.hpp): its stresses with their
/// positions and weights, its energy, largest stress and round-off.
template <int S>
struct CellStressesOf {
  template <class E>
  struct Slot {
    std::array<Vec<S>, E::kStiffnessPoints> stress;
    std::array<Vec2, E::kStiffnessPoints> position;
    std::array<double, E::kStiffnessPoints> weight;
    double energy = 0, peak = 0, noise = 0;
    bool skipped = false;
  };
};

/// Step 1 of estimate_error(): every cell's stiffness-point stresses, and sigma* on `slots` either from
/// `fit`'s weights (`Weighted`) or from this call's patch sums (`P` terms). The cells on every thread of
/// the pool, their sums added in the cells' order (assembly/cell_blocks.hpp).
template <int P, bool Weighted, class M, class Source>
PointStresses<M::Kinematics::kStrain> point_stresses(const Assembler<M>& a, const Problem<M>& p,
                                                     const VecX& u, const Source& source,
                                                     const std::vector<int>& skip,
                                                     std::vector<PointValues>* centroids,
                                                     const RecoverySlots& slots, const RecoveryWeights* fit) {
  using Kin        = typename M::Kinematics;
  using Elem       = typename M::Element;
  constexpr int S  = Kin::kStrain;
  const auto& mesh = p.mesh;
  PointStresses<S> out;
  out.stress.resize(a.point_count());
  out.recovered.assign(slots.size(), Vec<S>::Zero());
  std::vector<PatchSums<S, P>> sums(Weighted ? 0 : slots.size());
  const double largest_u = u.size() > 0 ? u.cwiseAbs().maxCoeff() : 0.0;
  if (centroids) centroids->assign(mesh.cells.size() + mesh.triangles.size(), PointValues{});
  struct TaskCache {  // a task's law, and its last cell's compliance (neighbours mostly share a material)
    typename Assembler<M>::LawCache law;
    Mat<S, S> stiffness = Mat<S, S>::Zero(), compliance = Mat<S, S>::Zero();
  };
  const auto compute = [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                     const std::array<int, NPC>& cell, const CellTag& tag,
                                                     auto& out_cell, TaskCache& cache) {
    static_assert(
        requires { E::kCorners; } || requires { E::kTri; } || requires { E::kTriangles; } ||
            (E::kEdgeNodes == 3 && (E::kStiffnessPoints == 9 || E::kNodes == 6)),
        "cells the recovery knows: Quad4, its B-bar form, the legacy quad, Tri3 (planes), Quad8 and Tri6 "
        "(quadratics)");
    out_cell.skipped = left_out(skip, tag.material);
    if (out_cell.skipped && !centroids) return;
    const auto x          = cell_coords<E>(mesh, cell);
    const auto& lp        = a.local(p, tag, cell, cache.law);
    const auto first      = a.template first_point<E>(e);
    constexpr bool kTri   = !std::is_same_v<E, Elem>;
    PointValues* centroid = centroids ? centroids->data() + (kTri ? mesh.cells.size() + e : e) : nullptr;
    const CellPoints<Kin, E, std::decay_t<decltype(lp)>, Source> values(
        x, lp, p.inertia, a.gather(cell, u), source, e, kTri, first, Recovered::stress);
    if (out_cell.skipped) {
      *centroid = values.centroid();
      return;
    }
    using Values = std::decay_t<decltype(values)>;
    if constexpr (Values::kCentroidPoint && requires { values.stresses(); }) {
      const auto points = values.stresses();
      out_cell.stress = points.stress, out_cell.position = points.position, out_cell.weight = points.weight;
      if (centroid) *centroid = values.centroid();
    } else {  // the centroid is the points' mean: one pass for both
      const auto all = values.points();
      if (centroid) *centroid = values.centroid(all);
      for (int q = 0; q < E::kStiffnessPoints; ++q)
        out_cell.stress[q]   = ElementKernel<Kin, E>::restrict(all.value[q].stress),
        out_cell.position[q] = Vec2(all.value[q].r, all.value[q].z), out_cell.weight[q] = all.weight[q];
    }
    const Mat<S, S> cs = ElementKernel<Kin, E>::restrict(lp.stiffness);
    if (cs != cache.stiffness) cache.stiffness = cs, cache.compliance = cs.inverse();
    const double side = std::min((x.row(E::kEdges.front().back()) - x.row(0)).norm(),
                                 (x.row(E::kEdges.back().front()) - x.row(0)).norm());
    out_cell.noise =
        lp.stiffness.diagonal().maxCoeff() * (largest_u / side + lp.thermal_strain.cwiseAbs().maxCoeff());
    out_cell.peak = 0, out_cell.energy = 0;
    for (int q = 0; q < E::kStiffnessPoints; ++q) {
      const Vec<S>& s                                 = out_cell.stress[q];
      out.stress[first + static_cast<std::size_t>(q)] = s;
      out_cell.peak                                   = std::max(out_cell.peak, s.cwiseAbs().maxCoeff());
      out_cell.energy += out_cell.weight[q] * s.dot(cache.compliance * s);
    }
  };
  const double* weight = Weighted ? fit->weight.data() : nullptr;
  const auto commit    = [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                    const std::array<int, NPC>& cell, const CellTag& tag,
                                                    const auto& c) {
    if (c.skipped) return;
    out.noise = std::max(out.noise, c.noise), out.peak = std::max(out.peak, c.peak), out.energy += c.energy;
    std::array<std::size_t, E::kNodes> slot;
    for (int n = 0; n < E::kNodes; ++n) slot[n] = slots(cell[n], tag.material);
    if constexpr (Weighted) {
      Vec<S>* recovered = out.recovered.data();
      for (int q = 0; q < E::kStiffnessPoints; ++q)
        for (int n = 0; n < E::kNodes; ++n) recovered[slot[n]] += weight[E::kNodes * q + n] * c.stress[q];
      weight += E::kNodes * E::kStiffnessPoints;
    } else {
      add_to_patches<E>(sums, slot, mesh, cell, [&](int q) { return std::pair(c.position[q], c.stress[q]); });
    }
  };
  for_each_cell_ordered<Elem, CellStressesOf<S>::template Slot, TaskCache>(mesh, CellGroups::all, compute,
                                                                           commit);
  for (std::size_t k = 0; k < sums.size(); ++k) out.recovered[k] = sums[k].at_node();
  if (Weighted && weight != fit->weight.data() + fit->weight.size())  // RecoveryWeights::fits() guards this
    throw std::logic_error("estimate_error: the kept recovery weights are another mesh's");
  return out;
}

}  // namespace detail

/// The recovery estimate of the energy-norm error of displacements `u` (all DOFs) on a driver's assembler
/// and problem, with stresses from `source` (post/recovery.hpp); cells of the `skip` materials (gap
/// elements: their stiffness is a device, not a body's) have no estimate and count in no sum. A part of a
/// partitioned problem recovers from its own cells only (a patch stops at the part's edge) and sums the
/// norms over every part (collective). `centroids`, when given, receives what recover() gives for the
/// cells' centroids with Recovered::stress (every cell's, the skipped ones' too), from the same pass: a run
/// that writes them and estimates recovers each cell once (the legacy quad's condensed centre is the costly
/// part). `weights`, when given, keeps the patches' fit from the second call on one mesh on (from the first
/// when `weights->several`, as a run of several load steps sets it; post/recovery_weights.hpp): a single
/// estimate fits the patches to its stresses directly, for less.
template <class M, class Source>
ErrorEstimate estimate_error(const Assembler<M>& a, const Problem<M>& p, const VecX& u, const Source& source,
                             const std::vector<int>& skip = {}, std::vector<PointValues>* centroids = nullptr,
                             RecoveryWeights* weights = nullptr) {
  using Kin        = typename M::Kinematics;
  using Elem       = typename M::Element;
  constexpr int S  = Kin::kStrain;
  constexpr int P  = Elem::kEdgeNodes == 3 ? 6 : 3;  // quadratic cells (Quad8, Tri6): quadratic patches
  const auto& mesh = p.mesh;
  const RecoveryWeights* fit = nullptr;
  if (weights) {
    const void* element       = &detail::kElementTag<Elem>;
    const std::uint64_t print = detail::mesh_fingerprint(mesh);
    const bool several        = weights->several;
    const bool seen           = weights->fits(element, print, skip);
    if (!seen) weights->remember(element, print, skip);
    if (!weights->built && (seen || several))
      *weights = recovery_weights<Elem, P>(mesh, skip, print), weights->several = several;
    if (weights->built) fit = weights;
  }
  const detail::RecoverySlots own_slots =
      fit ? detail::RecoverySlots(0) : detail::recovery_slots<Elem>(mesh, skip);
  const detail::RecoverySlots& slots = fit ? fit->slots : own_slots;

  // 1. The stresses at the stiffness points, kept, and sigma* per slot.
  detail::PointStresses<S> at_points =
      fit ? detail::point_stresses<P, true>(a, p, u, source, skip, centroids, slots, fit)
          : detail::point_stresses<P, false>(a, p, u, source, skip, centroids, slots, fit);
  const std::vector<Vec<S>>&stress = at_points.stress, &recovered = at_points.recovered;
  double peak = at_points.peak, noise = at_points.noise;

  // 2. The error per cell: sigma* from the cell's nodes against the kept sigma_h.
  ErrorEstimate out;
  for (std::size_t k = 0; k < recovered.size(); ++k)
    if (const int node = slots.node(k); node >= 0)
      if (const double s = voigt::von_mises(ElementKernel<Kin, Elem>::extend(recovered[k]));
          s > out.peak_mises)
        out.peak_mises = s, out.peak_node = node;
  out.cell.assign(mesh.cells.size() + (kHasTriangles<Elem> ? mesh.triangles.size() : 0), 0.0);
  struct TaskCache {  // a task's law, and its last cell's compliance (neighbours mostly share a material)
    typename Assembler<M>::LawCache law;
    Mat<S, S> stiffness = Mat<S, S>::Zero(), compliance = Mat<S, S>::Zero();
  };
  // Each cell's error on any thread into its own entry, summed below in the cells' order.
  for_each_cell_parallel<Elem, TaskCache>(mesh, [&]<class E, std::size_t NPC>(
                                                    std::type_identity<E>, std::size_t e,
                                                    const std::array<int, NPC>& cell, const CellTag& tag,
                                                    TaskCache& cache) {
    if (detail::left_out(skip, tag.material)) return;
    const auto x       = cell_coords<E>(mesh, cell);
    const Mat<S, S> cs = ElementKernel<Kin, E>::restrict(a.local(p, tag, cell, cache.law).stiffness);
    if (cs != cache.stiffness) cache.stiffness = cs, cache.compliance = cs.inverse();
    const Mat<S, S>& compliance = cache.compliance;
    const Vec<S>* at            = stress.data() + a.template first_point<E>(e);
    std::array<Vec<S>, E::kShapeNodes> corner;
    Vec<S> centre = Vec<S>::Zero();
    for (int c = 0; c < E::kNodes; ++c)
      corner[c] = recovered[slots(cell[c], tag.material)], centre += corner[c] / E::kNodes;
    for (int c = E::kNodes; c < E::kShapeNodes; ++c) corner[c] = centre;  // a condensed centre: the mean
    double error = 0;
    if constexpr (E::kEdgeNodes == 3 && E::kNodes == 6) {
      error = detail::triangle_cell_error<E, S>(x, corner, at, compliance);
    } else if constexpr (E::kEdgeNodes == 3) {
      error = detail::quadratic_cell_error<E, S>(x, corner, at, compliance);
    } else if constexpr (requires { E::kCorners; }) {
      error = detail::bilinear_cell_error<S>(x, {corner[0], corner[1], corner[2], corner[3]}, at, compliance);
    } else {  // constant-strain triangles: sigma* - sigma_h is linear on each, integrated exactly
      const Mat<E::kShapeNodes, 2> xs = E::shape_coords(x);
      constexpr auto triangles        = detail::cst_triangles<E>();
      for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& n     = triangles[t];
        const double area = 0.5 * std::abs((xs(n[1], 0) - xs(n[0], 0)) * (xs(n[2], 1) - xs(n[0], 1)) -
                                           (xs(n[2], 0) - xs(n[0], 0)) * (xs(n[1], 1) - xs(n[0], 1)));
        const Vec<3> r(xs(n[0], 0), xs(n[1], 0), xs(n[2], 0));
        const std::array<Vec<S>, 3> diff{corner[n[0]] - at[t], corner[n[1]] - at[t], corner[n[2]] - at[t]};
        error += detail::linear_field_energy<S>(diff, compliance, r, area);
      }
    }
    const std::size_t index = std::is_same_v<E, Elem> ? e : mesh.cells.size() + e;
    out.cell[index]         = error;
  });
  for (const double c : out.cell) out.error_squared += c;  // the left-out cells' zeros change no sum
  out.energy_squared = at_points.energy;
  if (const Subdomain* part = p.subdomain.get()) {  // the whole problem's norms
    double both[2] = {out.error_squared, out.energy_squared};
    part->sum(both, 2);
    out.error_squared = both[0], out.energy_squared = both[1];
    peak = part->max(peak), noise = part->max(noise);
  }
  out.stress_free    = !(peak > kRoundOff * noise);
  const double whole = std::sqrt(out.error_squared + out.energy_squared);
  for (double& c : out.cell) c = whole > 0 && !out.stress_free ? std::sqrt(c) / whole : 0.0;
  return out;
}

}  // namespace gapfe

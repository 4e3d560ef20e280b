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
// The relative error is eta / sqrt(|u_h|^2 + eta^2), |u_h|^2 the integral of sigma_h^T C^-1 sigma_h dV.
// Each material is recovered on its own: its stresses jump across a bond to another material.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include <Eigen/LU>

#include "gapfe/post/patch_recovery.hpp"
#include "gapfe/post/recovery.hpp"

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
  double energy_squared = 0;  ///< |u_h|^2 = integral sigma_h^T C^-1 sigma_h dV, twice the strain energy
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

/// eta_e^2 and |u_h|_e^2 of a bilinear quadrilateral (Quad4 and its B-bar form) from sigma* at its corners
/// and sigma_h at its 2 x 2 Gauss points, `at`. Both fields are bilinear in (xi, eta), c0 + c1 xi + c2 eta +
/// c3 xi eta: sigma* through the corners, sigma_h through the Gauss points' values (what a law with history
/// keeps; a linear law's own field but for the hoop strain's 1 / r). Their squares weighed by C^-1 and by
/// 2 pi r det J are then sums of the coefficients' products c_k^T C^-1 c_l times the moments of
/// (1, xi, eta, xi eta) under the weight, which 3 x 3 Gauss points integrate exactly (the weight is bilinear
/// times linear). Returns {eta_e^2, |u_h|_e^2}.
template <class E, int S>
std::array<double, 2> bilinear_cell_energies(const Mat<4, 2>& x, const std::array<Vec<S>, 4>& corner,
                                             const Vec<S>* at, const Mat<S, S>& compliance) {
  struct Point {
    Vec<4> N, monomial;
    Mat<4, 2> dN;
    double weight;
  };
  static const std::array<Point, 9> points = [] {  // the rule's shape values, the same for every cell
    constexpr auto rule = gauss::square<3>();
    std::array<Point, 9> t;
    for (int q = 0; q < 9; ++q) {
      const double xi = rule.point[q][0], eta = rule.point[q][1];
      t[q] = {E::N(xi, eta), Vec<4>(1, xi, eta, xi * eta), E::dN(xi, eta), rule.weight[q]};
    }
    return t;
  }();
  Mat<4, 4> moments = Mat<4, 4>::Zero();  // of (1, xi, eta, xi eta) under 2 pi r det J
  for (const Point& p : points) {
    const Mat<2, 2> J = p.dN.transpose() * x;
    const double w    = kTwoPi * p.N.dot(x.col(0)) * (J(0, 0) * J(1, 1) - J(0, 1) * J(1, 0)) * p.weight;
    moments += w * p.monomial * p.monomial.transpose();
  }
  std::array<Vec<S>, 4> diff, held;  // the coefficients of sigma* - sigma_h and of sigma_h
  for (int k = 0; k < 4; ++k) diff[k].setZero(), held[k].setZero();
  for (int c = 0; c < 4; ++c) {  // N_c = (1 + xi_c xi)(1 + eta_c eta) / 4
    const double a = E::kCorners[c][0], b = E::kCorners[c][1];
    diff[0] += corner[c] / 4, diff[1] += a * corner[c] / 4, diff[2] += b * corner[c] / 4;
    diff[3] += a * b * corner[c] / 4;
  }
  for (int q = 0; q < 4;
       ++q) {  // Lagrange through (+-1/sqrt 3, +-1/sqrt 3): (1 + 3 xi_q xi)(1 + 3 eta_q eta) / 4
    const double a = 3 * E::kRule.point[q][0], b = 3 * E::kRule.point[q][1];
    held[0] += at[q] / 4, held[1] += a * at[q] / 4, held[2] += b * at[q] / 4, held[3] += a * b * at[q] / 4;
  }
  std::array<double, 2> out{0, 0};
  for (int k = 0; k < 4; ++k) diff[k] -= held[k];
  for (int k = 0; k < 4; ++k) {
    const Vec<S> cd = compliance * diff[k], ch = compliance * held[k];
    for (int l = 0; l < 4; ++l)
      out[0] += moments(k, l) * diff[l].dot(cd), out[1] += moments(k, l) * held[l].dot(ch);
  }
  return out;
}

/// eta_e^2 and |u_h|_e^2 of an 8-node quadrilateral from sigma* at its nodes and sigma_h at its 3 x 3 Gauss
/// points, `at`, on 4 x 4 Gauss points: sigma* through the nodes (its shape functions), sigma_h biquadratic
/// through the 3 x 3 points' values (Lagrange through -a, 0, a, a = sqrt(3/5), in each direction).
template <class E, int S>
std::array<double, 2> quadratic_cell_energies(const Mat<8, 2>& x, const std::array<Vec<S>, 8>& node,
                                              const Vec<S>* at, const Mat<S, S>& compliance) {
  constexpr auto rule = gauss::square<4>();
  constexpr double a  = gauss::Line<3>::a;
  const auto lagrange = [&](double t) {
    return Vec<3>(t * (t - a) / (2 * a * a), (a * a - t * t) / (a * a), t * (t + a) / (2 * a * a));
  };
  std::array<double, 2> out{0, 0};
  double det = 0;
  for (int q = 0; q < 16; ++q) {
    const double xi = rule.point[q][0], eta = rule.point[q][1];
    const auto g    = E::at(x, xi, eta, rule.weight[q], det);
    const Vec<3> li = lagrange(xi), lj = lagrange(eta);
    Vec<S> held = Vec<S>::Zero(), diff = Vec<S>::Zero();
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) held += li(i) * lj(j) * at[3 * j + i];  // square<3>: xi fastest
    for (int c = 0; c < 8; ++c) diff += g.N(c) * node[c];
    diff -= held;
    out[0] += g.weight * diff.dot(compliance * diff), out[1] += g.weight * held.dot(compliance * held);
  }
  return out;
}

/// eta_e^2 and |u_h|_e^2 of a 6-node triangle on its own stiffness points: sigma* through the nodes (its
/// shape functions) against sigma_h where it was computed. The degree-4 rule integrates the quadratic sigma*
/// against the linear part of sigma_h exactly but for the weight r; the estimate needs no more.
template <class E, int S>
std::array<double, 2> triangle_cell_energies(const Mat<6, 2>& x, const std::array<Vec<S>, 6>& node,
                                             const Vec<S>* at, const Mat<S, S>& compliance) {
  std::array<double, 2> out{0, 0};
  double det = 0;
  for (int q = 0; q < E::kStiffnessPoints; ++q) {
    const auto g = E::stiffness_point(x, q, det);
    Vec<S> diff  = -at[q];
    for (int c = 0; c < 6; ++c) diff += g.N(c) * node[c];
    out[0] += g.weight * diff.dot(compliance * diff), out[1] += g.weight * at[q].dot(compliance * at[q]);
  }
  return out;
}

/// The constant-strain triangles of a cell, as shape-node indices: the legacy quadrilateral's four, a
/// triangle itself. Stiffness point q is triangle q's centroid.
template <class E>
constexpr auto cst_triangles() {
  if constexpr (requires { E::kTriangles; })
    return E::kTriangles;
  else
    return std::array<std::array<int, 3>, 1>{E::kTri};
}

/// integral over a straight triangle of d^T K d 2 pi r dA, d linear (d_a at its corners), exactly:
/// sum over a, b, c of (d_a^T K d_b) r_c times the integral of L_a L_b L_c, which is A / 10, A / 30 or
/// A / 60 as a, b, c are all equal, two equal or all different (the integral of L1^i L2^j L3^k is
/// 2 A i! j! k! / (i + j + k + 2)!).
template <int S>
double linear_field_energy(const std::array<Vec<S>, 3>& d, const Mat<S, S>& compliance, const Vec<3>& r,
                           double area) {
  const double all = r.sum();
  double sum       = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const double gram = d[a].dot(compliance * d[b]);
      sum += a == b ? gram * (r(a) / 10 + (all - r(a)) / 30)
                    : gram * ((r(a) + r(b)) / 30 + (all - r(a) - r(b)) / 60);
    }
  return kTwoPi * area * sum;
}

}  // namespace detail

/// The recovery estimate of the energy-norm error of displacements `u` (all DOFs) on a driver's assembler
/// and problem, with stresses from `source` (post/recovery.hpp); cells of the `skip` materials (gap
/// elements: their stiffness is a device, not a body's) have no estimate and count in no sum. A part of a
/// partitioned problem recovers from its own cells only (a patch stops at the part's edge) and sums the
/// norms over every part (collective). `centroids`, when given, receives what recover() gives for the
/// cells' centroids with Recovered::stress (every cell's, the skipped ones' too), from the same pass: a run
/// that writes them and estimates recovers each cell once (the legacy quad's condensed centre is the costly
/// part).
template <class M, class Source>
ErrorEstimate estimate_error(const Assembler<M>& a, const Problem<M>& p, const VecX& u, const Source& source,
                             const std::vector<int>& skip        = {},
                             std::vector<PointValues>* centroids = nullptr) {
  using Kin          = typename M::Kinematics;
  using Elem         = typename M::Element;
  constexpr int S    = Kin::kStrain;
  constexpr int P    = Elem::kEdgeNodes == 3 ? 6 : 3;  // quadratic cells (Quad8, Tri6): quadratic patches
  const auto& mesh   = p.mesh;
  const auto skipped = [&](const CellTag& tag) {
    return std::find(skip.begin(), skip.end(), tag.material) != skip.end();
  };
  detail::RecoverySlots slots(mesh.node_count());
  for_each_cell<Elem>(mesh,
                      [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                    const std::array<int, NPC>& cell, const CellTag& tag) {
                        if (!skipped(tag))
                          for (int c = 0; c < E::kNodes; ++c) slots.add(cell[c], tag.material);
                      });
  slots.finish();

  // 1. The stresses at the stiffness points, kept, and the patches' sums; then sigma* per slot.
  std::vector<Vec<S>> stress(a.point_count());
  std::vector<detail::PatchSums<S, P>> sums(slots.size());
  // The largest stress, against the round-off a stress of this model carries: about the unit round-off of
  // the stiffness times the strains the displacements and temperatures could make (max |u| over a cell's
  // side, and the thermal strain).
  double peak = 0, noise = 0;
  const double largest_u = u.size() > 0 ? u.cwiseAbs().maxCoeff() : 0.0;
  if (centroids) centroids->clear(), centroids->reserve(mesh.cells.size() + mesh.triangles.size());
  a.reset_cache();
  for_each_cell<Elem>(mesh, [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                          const std::array<int, NPC>& cell,
                                                          const CellTag& tag) {
    static_assert(
        requires { E::kCorners; } || requires { E::kTri; } || requires { E::kTriangles; } ||
            (E::kEdgeNodes == 3 && (E::kStiffnessPoints == 9 || E::kNodes == 6)),
        "cells the recovery knows: Quad4, its B-bar form, the legacy quad, Tri3 (planes), Quad8 and Tri6 "
        "(quadratics)");
    const bool skip_cell = skipped(tag);
    if (skip_cell && !centroids) return;
    const auto x     = cell_coords<E>(mesh, cell);
    const auto& lp   = a.local(p, tag, cell);
    const auto first = a.template first_point<E>(e);
    const CellPoints<Kin, E, std::decay_t<decltype(lp)>, Source> values(
        x, lp, p.inertia, a.gather(cell, u), source, e, !std::is_same_v<E, Elem>, first, Recovered::stress);
    if (skip_cell) {
      centroids->push_back(values.centroid());
      return;
    }
    const auto points = values.points();
    if (centroids) centroids->push_back(values.centroid(points));
    const Vec2 origin = x.row(0).transpose();
    // Linear cells: the cell's sums about its first corner, moved to each corner's patch.
    detail::PatchSums<S, P> own;
    const double side = std::min((x.row(E::kEdges.front().back()) - x.row(0)).norm(),
                                 (x.row(E::kEdges.back().front()) - x.row(0)).norm());
    noise             = std::max(noise, lp.stiffness.diagonal().maxCoeff() *
                                            (largest_u / side + lp.thermal_strain.cwiseAbs().maxCoeff()));
    for (int q = 0; q < E::kStiffnessPoints; ++q) {
      const PointValues& v = points.value[q];
      const auto slot      = first + static_cast<std::size_t>(q);
      stress[slot]         = ElementKernel<Kin, E>::restrict(v.stress);
      peak                 = std::max(peak, stress[slot].cwiseAbs().maxCoeff());
      const Vec2 point(v.r, v.z);
      if constexpr (P == 3)
        own.add(point - origin, stress[slot]);
      else  // a quadratic's sums do not move by a cheap shift: each node's own
        for (int c = 0; c < E::kNodes; ++c)
          sums[slots(cell[c], tag.material)].add(point - mesh.nodes[cell[c]], stress[slot]);
    }
    if constexpr (P == 3)
      for (int c = 0; c < E::kNodes; ++c)
        sums[slots(cell[c], tag.material)].add_shifted(own, origin - mesh.nodes[cell[c]]);
  });
  std::vector<Vec<S>> recovered(sums.size());
  for (std::size_t k = 0; k < sums.size(); ++k) recovered[k] = sums[k].at_node();
  sums = {};

  // 2. The error per cell: sigma* from the cell's nodes against the kept sigma_h.
  ErrorEstimate out;
  for (std::size_t k = 0; k < recovered.size(); ++k)
    if (const int node = slots.node(k); node >= 0)
      if (const double s = voigt::von_mises(ElementKernel<Kin, Elem>::extend(recovered[k]));
          s > out.peak_mises)
        out.peak_mises = s, out.peak_node = node;
  out.cell.assign(mesh.cells.size() + (kHasTriangles<Elem> ? mesh.triangles.size() : 0), 0.0);
  a.reset_cache();
  Mat<S, S> stiffness = Mat<S, S>::Zero(), compliance = Mat<S, S>::Zero();  // the last cell's
  for_each_cell<Elem>(mesh, [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                          const std::array<int, NPC>& cell,
                                                          const CellTag& tag) {
    if (skipped(tag)) return;
    const auto x       = cell_coords<E>(mesh, cell);
    const Mat<S, S> cs = ElementKernel<Kin, E>::restrict(a.local(p, tag, cell).stiffness);
    if (cs != stiffness) stiffness = cs, compliance = cs.inverse();  // neighbours mostly share a material
    const Vec<S>* at = stress.data() + a.template first_point<E>(e);
    std::array<Vec<S>, E::kShapeNodes> corner;
    Vec<S> centre = Vec<S>::Zero();
    for (int c = 0; c < E::kNodes; ++c)
      corner[c] = recovered[slots(cell[c], tag.material)], centre += corner[c] / E::kNodes;
    for (int c = E::kNodes; c < E::kShapeNodes; ++c) corner[c] = centre;  // a condensed centre: the mean
    double error = 0, energy = 0;
    if constexpr (E::kEdgeNodes == 3 && E::kNodes == 6) {
      const auto both = detail::triangle_cell_energies<E, S>(x, corner, at, compliance);
      error += both[0], energy += both[1];
    } else if constexpr (E::kEdgeNodes == 3) {
      const auto both = detail::quadratic_cell_energies<E, S>(x, corner, at, compliance);
      error += both[0], energy += both[1];
    } else if constexpr (requires { E::kCorners; }) {
      const auto both = detail::bilinear_cell_energies<E, S>(x, {corner[0], corner[1], corner[2], corner[3]},
                                                             at, compliance);
      error += both[0], energy += both[1];
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
        energy += kTwoPi * area * r.sum() / 3 * at[t].dot(compliance * at[t]);
      }
    }
    const std::size_t index = std::is_same_v<E, Elem> ? e : mesh.cells.size() + e;
    out.cell[index]         = error;
    out.error_squared += error, out.energy_squared += energy;
  });
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

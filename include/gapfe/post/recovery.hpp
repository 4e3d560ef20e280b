#pragma once
// Recovery: nodal results and point values from a driver's displacements, one implementation for every
// driver. Strain comes from the displacements (with the element's own B, B-bar included, and the
// condensed centre of the legacy quad expanded back); stress comes from a StressSource:
//   ElasticStress  a linear law: the stress of the strain, at any point (centroids exactly there);
//   StoredStress   a law with history: the stresses the last evaluation left at the stiffness points
//                  (and their eqps); centroids are the volume-weighted mean of the cell's points.
// The LegacyQuad has no centroid point either: its centroid is the r-bar-A weighted mean of its four
// sub-triangles (docs/theory.md 2 item 4).
#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "gapfe/assembly/assembler.hpp"
#include "gapfe/kinematics/axisym2.hpp"
#include "gapfe/material/elastic.hpp"
#include "gapfe/material/orientation.hpp"
#include "gapfe/post/bilinear_fields.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

/// What ElasticStress gives a kernel's strain components when its law is sigma = C (eps - eps_th)
/// (ElasticUpdate): sigma_S = C_SS eps_S - (C eps_th)_S, S the kinematics' components, whose other strains
/// are zero. stress() restricted, with the thermal part once per cell instead of once per point.
template <class Kernel>
struct RestrictedStress {
  typename Kernel::StrainMatrix stiffness;
  typename Kernel::StrainVector thermal;
  typename Kernel::StrainVector operator()(const typename Kernel::StrainVector& strain) const {
    return stiffness * strain - thermal;
  }
};

/// The stress of a linear law at any point: Law::update from the empty state.
template <class Law>
struct ElasticStress {
  static constexpr bool kAnyPoint = true;
  Vec6 stress(const typename Law::Local& lp, const Vec6& strain, std::size_t /*slot*/) const {
    return Law::update(lp, strain, typename Law::State{}, StepContext{}).stress;
  }
  double eqps(std::size_t /*slot*/) const { return 0.0; }
  template <class Kernel>
  RestrictedStress<Kernel> restricted(
      const typename Law::Local& lp) const requires std::is_base_of_v<ElasticUpdate, Law> {
    return {Kernel::restrict(lp.stiffness), Kernel::restrict(Vec6(lp.stiffness * lp.thermal_strain))};
  }
};

/// Stresses and states a driver with history keeps per stiffness point (History slots).
template <class State>
struct StoredStress {
  static constexpr bool kAnyPoint = false;
  const std::vector<Vec6>& stresses;
  const std::vector<State>& states;
  template <class Local>
  Vec6 stress(const Local&, const Vec6&, std::size_t slot) const {
    return stresses[slot];
  }
  double eqps(std::size_t slot) const {
    if constexpr (requires { states[slot].eqps; })
      return states[slot].eqps;
    else
      return 0.0;
  }
};

/// Displacements (rows nodes, columns r, z, theta) from `u` (all DOFs).
template <int DofsPerNode>
void nodal_displacements(const VecX& u, int nodes, Solution& s) {
  s.displacement.setZero(nodes, 3);
  for (int n = 0; n < nodes; ++n)
    for (int c = 0; c < DofsPerNode; ++c) s.displacement(n, c) = u(n * DofsPerNode + c);
}

/// What a solve's out-of-balance and its global balance are measured against, beyond the internal force.
struct SolveLoads {
  /// The whole load the free DOFs were solved for (edge and nodal forces, and the loads of thermal strain,
  /// inertia and prescribed displacements; all DOFs, read at the free ones), or nullptr.
  const VecX* load = nullptr;
  /// A sum of squares the out-of-balance is measured against too: the largest load the run has carried
  /// (LinearStatic), or the loads of the step's start and of the accepted steps (NonlinearStatic).
  double peak = 0;
  /// Totals of body forces that `external` does not hold (a linear law's are element loads): the axial
  /// force and the torque about the axis [force, force x length].
  Vec2 body = Vec2::Zero();
  /// The torque of the node links' internal forces (post/balance.hpp's link_torque) [force x length].
  double link_torque = 0;
};

/// Displacements at the nodes at `positions` (r, z), reactions = internal - external at prescribed DOFs,
/// the relative out-of-balance |internal - external| / |internal| at the free DOFs (all vectors over all
/// DOFs) and the global balance (Solution::balance: applied = external + loads.body, and the links'
/// torque). The out-of-balance is relative to the largest of the internal force, `loads.load` and
/// `loads.peak`: a body in free thermal expansion, or flying on soft gap elements, has no internal force to
/// speak of, a step that unloads to nothing no load, and their round-off would read as a residual of order
/// 1. Returns the size it used (a sum of squares: LinearStatic's next `peak`).
/// For a part of a partitioned problem (`part`) the vectors are the part's partial sums: they are summed over
/// the parts first (the reactions are then totals at every local node) and the norms and sums count each
/// node once, at its owner, over every part (collective; `loads.body` and `loads.link_torque` are every
/// part's totals already).
template <int DofsPerNode>
double nodal_results(const DofMap<DofsPerNode>& dofs, const VecX& u, const VecX& internal,
                     const VecX& external, const std::vector<Vec2>& positions, Solution& s,
                     const Subdomain* part = nullptr, const SolveLoads& loads = {}) {
  const int nodes = static_cast<int>(positions.size());
  nodal_displacements<DofsPerNode>(u, nodes, s);
  s.reaction.setZero(nodes, 3);
  VecX total_internal, total_external, total_load;
  if (part) {
    total_internal = internal, total_external = external;
    part->sum_shared(total_internal.data(), DofsPerNode);
    part->sum_shared(total_external.data(), DofsPerNode);
    if (loads.load) total_load = *loads.load, part->sum_shared(total_load.data(), DofsPerNode);
  }
  const VecX& in    = part ? total_internal : internal;
  const VecX& ex    = part ? total_external : external;
  const VecX* whole = loads.load ? (part ? &total_load : loads.load) : nullptr;
  const int counted = part ? part->owned_nodes() : nodes;
  // Sums over the nodes (one array: a part sums them in one call): squares of the out-of-balance, the
  // internal force and the load at the free DOFs; along the axis and about it (index kAxial or kTorque +)
  // the applied loads, the reactions and their sizes (sums of |.|); and the largest radius.
  constexpr int kUnbalanced = 0, kInternal = 1, kLoad = 2, kAxial = 3, kTorque = 6, kRadius = 9, kSums = 10;
  constexpr int kApplied = 0, kReaction = 1, kSize = 2;
  double sums[kSums] = {};
  for (int n = 0; n < nodes; ++n)
    for (int c = 0; c < DofsPerNode; ++c) {
      const int d             = dofs.dof(n, c);
      const double unbalanced = in(d)-ex(d);
      if (dofs.equation[d] < 0)
        s.reaction(n, c) = unbalanced;
      else if (n < counted)
        sums[kUnbalanced] += unbalanced * unbalanced, sums[kLoad] += whole ? (*whole)(d) * (*whole)(d) : 0.0;
      if (n >= counted) continue;
      sums[kInternal] += in(d)*in(d);
      if (c == 0) continue;  // radial: no global balance (a ring's radial loads are carried by its hoop)
      const double reaction = dofs.equation[d] < 0 ? unbalanced : 0.0;
      const double arm      = c == 1 ? 1.0 : positions[static_cast<std::size_t>(n)](0);  // u_z; u_theta: r
      double* sum           = sums + (c == 1 ? kAxial : kTorque);
      sum[kApplied] += arm * ex(d), sum[kReaction] += arm * reaction;
      sum[kSize] += std::abs(arm * ex(d)) + std::abs(arm * reaction);
      if (c == 2) sums[kRadius] = std::max(sums[kRadius], arm);
    }
  if (part) {
    part->sum(sums, kRadius);
    sums[kRadius] = part->max(sums[kRadius]);
  }
  const double size = std::max({sums[kInternal], sums[kLoad], loads.peak});
  s.residual        = size > 0 ? std::sqrt(sums[kUnbalanced] / size) : 0.0;
  Balance& b        = s.balance;
  b.applied_axial   = sums[kAxial + kApplied] + loads.body(0);
  b.reaction_axial  = sums[kAxial + kReaction];
  b.size_axial      = sums[kAxial + kSize] + std::abs(loads.body(0)) + std::sqrt(size);
  b.applied_torque  = sums[kTorque + kApplied] + loads.body(1);
  b.reaction_torque = sums[kTorque + kReaction];
  b.gap_torque      = loads.link_torque;
  b.size_torque     = DofsPerNode == 3 ? sums[kTorque + kSize] + std::abs(loads.body(1)) +
                                         std::abs(loads.link_torque) + sums[kRadius] * std::sqrt(size)
                                       : 0.0;
  return size;
}

/// The displacements of a cell's shape nodes from its own DOFs `ue`: the same for an isoparametric cell, and
/// a condensed centre's recovered from the corners' and the cell's loads (element/legacy_quad.hpp).
template <class Kernel, class Local, class Inertia>
typename Kernel::ShapeVector shape_displacements(const typename Kernel::Coords& x, const Local& lp,
                                                 const Inertia& inertia, const typename Kernel::Vector& ue) {
  if constexpr (Kernel::kInner > 0) {
    const typename Kernel::StrainMatrix d = Kernel::restrict(lp.stiffness);
    return Kernel::expand(
        Kernel::inner_rows(x, d),
        Kernel::shape_load(x, d, Kernel::restrict(lp.thermal_strain), body_force(inertia, lp.density)), ue);
  } else {
    return ue;
  }
}

/// One cell's values at its points, as a recovery gives them (Recovered says which fields): the strain from
/// the cell's displacements (the legacy quad's condensed centre recovered once, here) where the values need
/// it, the stress from `source`. recover() and the error estimate (post/error_estimate.hpp) both take their
/// values from here, so a run that does both in one pass writes the same numbers as either alone.
template <class Kin, class E, class Local, class Source>
class CellPoints {
 public:
  using Kernel = ElementKernel<Kin, E>;
  /// Whether the centroid is a point of its own (a stress at any point, and an element that has a centroid
  /// point), else the volume-weighted mean of the stiffness points (the legacy quad's r-bar-A weighted mean
  /// of its sub-triangles, docs/theory.md 2 item 4; a law's stored stresses).
  static constexpr bool kCentroidPoint =
      Source::kAnyPoint && requires(const Mat<E::kNodes, 2>& x, double& det) {
    E::centroid_point(x, det);
  };

  /// The values at every stiffness point, and the points' volume weights.
  struct Points {
    std::array<PointValues, E::kStiffnessPoints> value;
    std::array<double, E::kStiffnessPoints> weight;
  };

  template <class Inertia>
  CellPoints(const typename Kernel::Coords& x, const Local& lp, const Inertia& inertia,
             const typename Kernel::Vector& ue, const Source& source, std::size_t e, bool triangle,
             std::size_t first, Recovered what)
      : x_(x),
        lp_(lp),
        source_(source),
        e_(e),
        first_(first),
        triangle_(triangle),
        all_(what == Recovered::all),
        strain_(all_ || Source::kAnyPoint),  // a law's stress from the strain needs it
        xs_(E::shape_coords(x)) {
    if (strain_) us_ = shape_displacements<Kernel>(x, lp, inertia, ue), dilatation_ = Kernel::dilatation(x);
    if (all_) to_strain_material_ = strain_rotation(lp.to_material);
  }

  /// The values at point `g`: stiffness point `point` (its history slot first + point), or -1 the centroid.
  PointValues at(const PointGeometry<E::kShapeNodes>& g, int point) const {
    PointValues v;
    v.cell = static_cast<int>(e_), v.triangle = triangle_, v.point = point;
    v.r = g.r, v.z = g.N.dot(xs_.col(1));
    v.strain = strain_ ? Kernel::strain(g, dilatation_, us_) : Vec6::Zero();
    v.stress = source_.stress(lp_, v.strain, first_ + static_cast<std::size_t>(std::max(point, 0)));
    v.eqps   = source_.eqps(first_ + static_cast<std::size_t>(std::max(point, 0)));
    if (all_) {
      v.strain_material = to_strain_material_ * v.strain;
      v.stress_material = lp_.to_material * v.stress;
    } else {
      v.strain_material.setZero(), v.stress_material.setZero();
    }
    return v;
  }
  Points points() const {
    Points out;
    double det = 0;
    for (int q = 0; q < E::kStiffnessPoints; ++q) {
      const auto g = E::stiffness_point(x_, q, det);
      out.value[q] = at(g, q), out.weight[q] = g.weight;
    }
    return out;
  }
  /// The stresses alone at the stiffness points, in the kinematics' components, where the points lie
  /// (r, z) and their volume weights: what the error estimate reads, without the strains and material-axes
  /// values points() keeps.
  struct Stresses {
    std::array<typename Kernel::StrainVector, E::kStiffnessPoints> stress;
    std::array<Vec2, E::kStiffnessPoints> position;
    std::array<double, E::kStiffnessPoints> weight;
  };
  /// A linear law's only (ElasticStress::restricted): a law's stored stresses come through points().
  Stresses stresses() const requires requires(const Source& s, const Local& lp) {
    s.template restricted<Kernel>(lp);
  }
  {
    const RestrictedStress<Kernel> law = source_.template restricted<Kernel>(lp_);
    if constexpr (std::is_same_v<E, Quad4> && std::is_same_v<Kin, Axisym2>) {  // the commonest cell
      const detail::Quad4Stresses at(x_, us_, law.stiffness, law.thermal);
      return {at.stress, at.position, at.weight};
    } else {
      Stresses out;
      const auto points = Kernel::stiffness_points(x_);
      for (int q = 0; q < E::kStiffnessPoints; ++q) {
        const auto& g   = points[q];
        out.stress[q]   = law(Kernel::point_B(g, dilatation_) * us_);
        out.position[q] = Vec2(g.r, g.N.dot(xs_.col(1)));
        out.weight[q]   = g.weight;
      }
      return out;
    }
  }
  /// The centroid's values; `p` the stiffness points' (points()) when the centroid is their mean.
  PointValues centroid(const Points& p) const {
    if constexpr (kCentroidPoint) {
      (void)p;
      return centroid();
    } else {
      PointValues mean{};
      double w = 0;
      mean.strain.setZero(), mean.stress.setZero(), mean.strain_material.setZero(),
          mean.stress_material.setZero();
      for (int q = 0; q < E::kStiffnessPoints; ++q) {
        const double g       = p.weight[q];
        const PointValues& v = p.value[q];
        w += g;
        mean.r += g * v.r, mean.z += g * v.z, mean.eqps += g * v.eqps;
        mean.strain += g * v.strain, mean.stress += g * v.stress;
        mean.strain_material += g * v.strain_material, mean.stress_material += g * v.stress_material;
      }
      mean.r /= w, mean.z /= w, mean.eqps /= w, mean.strain /= w, mean.stress /= w;
      mean.strain_material /= w, mean.stress_material /= w;
      mean.cell = static_cast<int>(e_), mean.triangle = triangle_, mean.point = -1;
      return mean;
    }
  }
  /// The centroid's values alone.
  PointValues centroid() const {
    if constexpr (kCentroidPoint) {
      double det = 0;
      return at(E::centroid_point(x_, det), -1);
    } else {
      return centroid(points());
    }
  }

 private:
  const typename Kernel::Coords& x_;
  const Local& lp_;
  const Source& source_;
  std::size_t e_, first_;
  bool triangle_, all_, strain_;
  Mat<E::kShapeNodes, 2> xs_;
  typename Kernel::ShapeVector us_{};
  typename Kernel::Dilatation dilatation_{};
  Mat66 to_strain_material_;  // set and read only when all_ (no 36 stores per cell otherwise)
};

/// Strain and stress at every stiffness point of every cell, or (`centroids`) one value per cell; cells
/// first, then triangles. The cells on every thread of the pool (assembly/cell_blocks.hpp), each writing
/// only its own values.
template <class M, class Source>
std::vector<PointValues> recover(const Assembler<M>& a, const Problem<M>& p, const VecX& u,
                                 const Source& source, bool centroids, Recovered what = Recovered::all) {
  using Kin               = typename M::Kinematics;
  using Elem              = typename M::Element;
  using LawCache          = typename Assembler<M>::LawCache;
  const std::size_t cells = p.mesh.cells.size();
  std::vector<PointValues> out(centroids ? cells + p.mesh.triangles.size() : a.point_count());  // 232 B each
  for_each_cell_parallel<Elem, LawCache>(p.mesh, [&]<class E, std::size_t NPC>(
                                                     std::type_identity<E>, std::size_t e,
                                                     const std::array<int, NPC>& cell, const CellTag& tag,
                                                     const LawCache& cache) {
    constexpr bool kTriangle = !std::is_same_v<E, Elem>;
    const auto x             = cell_coords<E>(p.mesh, cell);
    const auto& lp           = a.local(p, tag, cell, cache);
    const std::size_t first  = a.template first_point<E>(e);
    const CellPoints<Kin, E, std::decay_t<decltype(lp)>, Source> values(x, lp, p.inertia, a.gather(cell, u),
                                                                        source, e, kTriangle, first, what);
    if (centroids) {
      out[kTriangle ? cells + e : e] = values.centroid();
    } else {
      const auto points = values.points();
      std::copy(points.value.begin(), points.value.end(), out.begin() + static_cast<std::ptrdiff_t>(first));
    }
  });
  return out;
}

}  // namespace gapfe

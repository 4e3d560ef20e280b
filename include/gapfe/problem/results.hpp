#pragma once
// What an analysis gives back, as plain data that io writes and tests read without knowing the driver:
// nodal displacements and reactions (Solution), strains and stresses at points (PointValues), the cost of
// a solve (SolveTimings) and the Newton record of a step (StepReport).
//
// PointValues: global (r, z, theta) Voigt order [rr, zz, hoop, rz, z-theta, theta-r] and material axes
// [NN, SS, TT, NS, ST, TN]. Strains carry engineering shears; stresses are tensor components. Units:
// stress as the moduli. Forces are total ring forces (core/types.hpp).
#include <algorithm>
#include <cmath>
#include <vector>

#include "gapfe/core/types.hpp"

namespace gapfe {

/// Global equilibrium of the whole body (docs/checks.md): the applied loads (edge tractions, nodal forces,
/// body forces) and the reactions summed over every node, along the axis and, with 3 DOF per node, as a
/// torque about it. These are the two balances axisymmetry has: a rigid axial translation and a rigid
/// rotation strain nothing, so the elements' internal forces sum to zero in both, thermal strain included;
/// a radial force has no such sum (a ring's radial loads are carried by its hoop stress).
/// `size_*` is the load's size the imbalance is measured against: the sum of |applied| and |reaction|
/// over the nodes, and at least the magnitude of the loads the solve carried (thermal loads included,
/// which sum to nothing, and the loads of prescribed displacements), so that a self-equilibrated load reads
/// its round-off as a small number. Forces [force], torques [force x length].
/// The node links (gap pairs) add one term about the axis: a pair across a radial gap carries its theta
/// force at two radii, so the pairs exert a torque `gap_torque` of their own (post/balance.hpp), which the
/// balance counts: applied + reaction = gap_torque.
struct Balance {
  double applied_axial = 0, reaction_axial = 0, size_axial = 0;
  double applied_torque = 0, reaction_torque = 0, gap_torque = 0, size_torque = 0;
  /// The larger of |applied + reaction - gap| / size along the axis and about it (0 where the size is 0;
  /// NaN where any term is: a warning, never a silent 0).
  double relative() const {
    const auto part = [](double off, double size) {
      return std::isnan(off) || std::isnan(size) ? off + size : size > 0 ? std::abs(off) / size : 0.0;
    };
    const double axial = part(applied_axial + reaction_axial, size_axial);
    const double about = part(applied_torque + reaction_torque - gap_torque, size_torque);
    return std::isnan(axial) || axial > about ? axial : about;
  }
};

/// Nodal results. Rows are nodes; columns (r, z, theta); u_theta and its reaction are 0 in 2-DOF.
struct Solution {
  Eigen::Matrix<double, Eigen::Dynamic, 3> displacement;  ///< [length]
  Eigen::Matrix<double, Eigen::Dynamic, 3> reaction;      ///< total ring force at prescribed DOFs [force]
  double residual = 0.0;  ///< |K u - f| / |f| over free DOFs after the solve (equilibrium check)
  Balance balance;        ///< global equilibrium of the applied loads and the reactions
};

/// Strain and stress at one stiffness point or one cell centroid.
struct PointValues {
  int cell      = 0;      ///< index within its group
  bool triangle = false;  ///< group: false = the model's element, true = 3-corner cells
  int point     = 0;      ///< stiffness-point index; -1 for a centroid
  double r = 0, z = 0;    ///< position [length]
  Vec6 strain;            ///< total strain, global axes
  Vec6 stress;            ///< global axes
  Vec6 strain_material;   ///< material axes (N, S, T)
  Vec6 stress_material;   ///< material axes
  double eqps = 0.0;      ///< equivalent plastic strain (laws with history; 0 when elastic) [-]
};

/// What a recovery fills in (deal.II's update flags; post/recovery.hpp): `all` every PointValues field;
/// `stress` the position, the global stress and eqps only (what the deck output writes), leaving strain
/// and the material-axes values zero, so that a law with stored stresses computes no strain at all.
enum class Recovered { all, stress };

/// Wall-clock seconds of the last solve's phases.
struct SolveTimings {
  double assemble = 0, factorize = 0, solve = 0, reactions = 0;
};

/// What the last nonlinear step did.
struct StepReport {
  std::vector<double> residuals;  ///< |R_free| / |F_int| (or the step's loads) after each linear solve (or at
                                  ///< an extrapolated start already in equilibrium, when no solve was needed)
  int iterations     = 0;         ///< linear solves (1 for Tangent)
  int evaluations    = 0;         ///< passes over the elements for F_int (each with the return map)
  int tangents       = 0;         ///< of those, the ones that assembled K_t too
  bool converged     = false;     ///< residual <= tolerance (Tangent: never required)
  bool stalled       = false;     ///< converged by NewtonOptions::stall_factor: at round-off, not tolerance
  int plastic_points = 0;         ///< points on the yield surface at the end of the step
  double drift       = 0.0;       ///< max |sqrt(f) - 1| over those points: off the surface [-]
  /// Rate-dependent laws: the largest estimated error of the step's time integration over the points (the
  /// law's time_error: the stress its plastic-strain error stands for, relative to yield) [-].
  double time_error = 0.0;
};

}  // namespace gapfe

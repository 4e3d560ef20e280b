#pragma once
// The contracts every policy must meet. A wrong plug-in fails where the Model alias names it.
#include <concepts>
#include <cstdint>
#include <string>
#include <vector>

#include "gapfe/core/material_frame.hpp"
#include "gapfe/core/point_geometry.hpp"
#include "gapfe/core/types.hpp"

namespace gapfe {

/// Time and step of an increment, for rate-dependent laws (dt > 0 there).
struct StepContext {
  double time = 0.0;  ///< [model time unit]
  double dt   = 0.0;  ///< [model time unit]
  /// False when the caller needs stress and state only (a residual pass whose tangent nobody
  /// factorizes): a law may then skip its tangent, and PointResponse::tangent is unspecified.
  bool tangent = true;
};

/// A material point's answer: stress and tangent in global Voigt axes, the trial history.
template <class State>
struct PointResponse {
  Vec6 stress;
  Mat66 tangent;
  State state;
  bool yielded = false;
};

/// A reference cell: stateless, integration points produce PointGeometry over its shape nodes.
/// kShapeNodes > kNodes means interior nodes that the kernel condenses out (LegacyQuad's centre).
template <class E>
concept ElementType = requires(const Mat<E::kNodes, 2>& x, int q, double& det) {
  requires E::kNodes >= 3 && E::kShapeNodes >= E::kNodes;
  requires E::kStiffnessPoints >= 1 && E::kLoadPoints >= 1;
  requires E::kEdgeNodes == 2 || E::kEdgeNodes == 3;
  { E::kEdges[0][0] } -> std::convertible_to<int>;
  { E::shape_coords(x) } -> std::convertible_to<Mat<E::kShapeNodes, 2>>;
  { E::stiffness_point(x, q, det) } -> std::same_as<PointGeometry<E::kShapeNodes>>;
  { E::load_point(x, q, det) } -> std::same_as<PointGeometry<E::kShapeNodes>>;
};

/// Axisym2 (2 DOF) or Axisym3 (3 DOF) on element E: a strain-displacement matrix per point and the
/// rows its strains occupy in the global Voigt-6 vector.
template <class K, class E>
concept KinematicsFor = ElementType<E> && requires(const PointGeometry<E::kShapeNodes>& g) {
  requires K::kDofsPerNode == 2 || K::kDofsPerNode == 3;
  { K::kVoigt[0] } -> std::convertible_to<int>;
  requires static_cast<int>(K::kVoigt.size()) == K::kStrain;
  { K::template B<E::kShapeNodes>(g) } -> std::same_as<Mat<K::kStrain, K::kDofsPerNode * E::kShapeNodes>>;
};

/// A constitutive law. `localize` resolves the material frame and temperature once per element
/// (table lookups and 6x6 rotations stay out of the point loop); `update` is pure: old state in,
/// response out, committed history never touched (so a step can be split and redone).
template <class M>
concept MaterialLaw = std::semiregular<typename M::State> &&
    requires(const M& m, const MaterialFrame& f, double T, const typename M::Local& p, const Vec6& strain,
             const typename M::State& s, const StepContext& ctx, const std::string& where) {
  { M::kLinear } -> std::convertible_to<bool>;
  { m.localize(f, T, T) } -> std::same_as<typename M::Local>;
  { p.stiffness } -> std::convertible_to<Mat66>;      // initial (elastic) stiffness, global axes
  { p.thermal_strain } -> std::convertible_to<Vec6>;  // global axes
  { p.density } -> std::convertible_to<double>;
  { p.to_material } -> std::convertible_to<Mat66>;  // T_sigma, for output in material axes
  { M::update(p, strain, s, ctx) } -> std::same_as<PointResponse<typename M::State>>;
  m.validate(where);
};

/// Which entries of the stiffness a solver reads: the lower triangle (symmetric solvers: LDL^T,
/// Cholesky) or every entry (LU, for unsymmetric tangents such as friction's slip).
enum class MatrixStorage { lower, full };

/// A solver's storage: S::kStorage where it declares one, else the lower triangle.
template <class S>
constexpr MatrixStorage storage_of() {
  if constexpr (requires { S::kStorage; })
    return S::kStorage;
  else
    return MatrixStorage::lower;
}

/// A sparse linear solver: symbolic analysis once per pattern, numeric factorization per matrix, then
/// solves. It reads the entries its storage_of() names. factorize() returns false, never NaN; failure()
/// says why, and begins with "the solver failed" when the cause is the solver's, not the matrix's (then the
/// System's SolveError gives no hint about constraints).
template <class S>
concept LinearSolver = std::default_initializable<S> && requires(S s, const SpMat& K, const VecX& b) {
  { S::kName } -> std::convertible_to<const char*>;
  s.analyze(K);
  { s.factorize(K) } -> std::same_as<bool>;
  { s.solve(b) } -> std::convertible_to<VecX>;
  { s.failure() } -> std::convertible_to<std::string>;  // why factorize() returned false
};

/// The size of a factorization and the work it took, from a solver that counts them (CHOLMOD): `flops` of
/// the factor without the explicit zeros a supernodal solver adds (its analysis' count), `entries` of
/// that factor, `stored` the values actually held (those zeros included). 0: not known. `split`: the
/// factorization was split in two halves and a separator of `separator` equations (solver/split_cholmod.hpp).
struct FactorStatistics {
  double flops = 0, entries = 0, stored = 0;
  int separator = 0;
  bool split    = false;
};

/// A LinearSolver that can take the elimination order from the caller: analyze(K, order), order[k] =
/// the equation eliminated k-th (a permutation of 0 .. rows - 1). The assembler knows the mesh, so it can
/// find a better order than a solver that sees only the pattern (solver/coordinate_dissection.hpp).
template <class S>
concept OrderedSolver = LinearSolver<S> && requires(S s, const SpMat& K, const std::vector<int>& order) {
  s.analyze(K, order);
};

/// Where a part's free equations sit in the system of a partitioned problem (core/subdomain.hpp), and what a
/// solver may want to know of them beyond the pattern. The part's local equations are the rows and columns
/// of the pattern it assembles; [0, owned) are the rows it holds of the global system (its owned nodes'
/// free DOFs, numbered contiguously in part order), the rest couple to rows another part holds.
struct EquationLayout {
  bool partitioned = false;          ///< a part of a partitioned problem; false: a whole problem here
  std::vector<std::int64_t> global;  ///< local equation -> global equation
  int owned          = 0;            ///< local equations [0, owned) are this part's rows
  std::int64_t first = 0;            ///< the global number of local equation 0
  std::int64_t total = 0;            ///< equations over every part
  /// The rigid-body (and near-rigid) modes over the owned rows, column-major, `modes` columns of `owned`
  /// values: what an algebraic multigrid builds its coarse spaces from (Assembler::near_null_space).
  std::vector<double> near_null;
  int modes = 0;
};

/// A LinearSolver that solves a partitioned system: given the layout before analyze(), it reads the part's
/// local pattern and values (its cells' sum, in its storage), sums the parts' entries into the global
/// system, and solve(b) takes the part's partial right-hand side (its cells' contributions, local
/// equations) and returns the solution at every local equation, owned or not. Every call is collective.
template <class S>
concept DistributedSolver = LinearSolver<S> && requires(S s, const EquationLayout& layout) {
  s.distribute(layout);
};

}  // namespace gapfe

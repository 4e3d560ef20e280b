#pragma once
// Hill's yield criterion with kinematic hardening (SAGAEP, docs/theory.md 7): the yield stresses and
// hardening (HillYield), a point's state (HillState), the law at a point (HillPoint) and the integration
// schemes' tags (Tangent, ReturnMapping). material/hill.hpp is the law.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "gapfe/core/concepts.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/material/elastic.hpp"

namespace gapfe {

/// How the back stress follows the plastic strain (docs/theory.md 7.2).
enum class PragerShear { legacy, tensor };

/// Seed Data 11: yield stresses in material axes and the kinematic hardening parameter.
struct HillYield {
  double X = 0, Y = 0, Z = 0;           ///< tensile yield stresses along N, S, T [stress]
  double R_NS = 0, R_NT = 0, R_TS = 0;  ///< shear yield stresses, the card's order NS, NT, TS [stress]
  double hardening  = 0;                ///< Prager's c: d alpha = c H d eps_p [stress]
  PragerShear shear = PragerShear::legacy;

  /// Equal yield stresses in every direction and sigma_y / sqrt(3) in shear: f = (sigma_Mises / sigma_y)^2.
  static HillYield mises(double sigma_y, double hardening = 0.0, PragerShear shear = PragerShear::legacy) {
    const double k = sigma_y / std::sqrt(3.0);
    return {sigma_y, sigma_y, sigma_y, k, k, k, hardening, shear};
  }

  /// An all-blank card 11: the material stays elastic (P = 0, so f = 0 < 1 always).
  bool blank() const { return X == 0 && Y == 0 && Z == 0 && R_NS == 0 && R_NT == 0 && R_TS == 0; }

  /// P of f = xi^T P xi in material Voigt order [NN, SS, TT, NS, ST, TN], tensor shear stresses.
  Mat66 yield_matrix() const {
    if (blank()) return Mat66::Zero();
    const double x = 1 / (X * X), y = 1 / (Y * Y), z = 1 / (Z * Z);
    Mat66 p = Mat66::Zero();
    p(0, 0) = x, p(1, 1) = y, p(2, 2) = z;
    p(0, 1) = p(1, 0) = 0.5 * (z - x - y);  // SIGYB(3) / 2
    p(0, 2) = p(2, 0) = 0.5 * (y - x - z);  // SIGYB(2) / 2
    p(1, 2) = p(2, 1) = 0.5 * (x - y - z);  // SIGYB(1) / 2
    p(3, 3)           = 1 / (R_NS * R_NS);
    p(4, 4)           = 1 / (R_TS * R_TS);  // ST = TS
    p(5, 5)           = 1 / (R_NT * R_NT);  // TN = NT
    return p;
  }
  /// H of d alpha = c H d eps_p in material Voigt order (engineering plastic shear strain).
  Mat66 hardening_matrix() const {
    Mat66 h = Mat66::Identity();
    if (shear == PragerShear::tensor) h.diagonal().tail<3>().setConstant(0.5);
    return h;
  }

  /// Throws InputError naming `where` unless every yield stress is positive and finite, c >= 0 and the
  /// normal part of P is positive semi-definite (Hill's F, G, H >= 0 is not required, but a yield
  /// surface open in some deviatoric direction never yields there and is refused).
  void validate(const std::string& where) const {
    const auto fail = [&](const std::string& what) { throw InputError(where + ": " + what); };
    if (blank()) return;
    for (double s : {X, Y, Z, R_NS, R_NT, R_TS})
      if (!(s > 0 && std::isfinite(s))) fail("yield stresses must be positive and finite (card 11)");
    if (!(hardening >= 0 && std::isfinite(hardening))) fail("hardening parameter C must be >= 0 (card 11)");
    // The normal block is singular along (1, 1, 1) (pressure does not yield); it must be positive
    // definite on the deviatoric plane.
    const Mat33 p = yield_matrix().topLeftCorner<3, 3>();
    Eigen::Matrix<double, 3, 2> dev;
    dev << 1, 1, -1, 1, 0, -2;
    const Eigen::Matrix2d pd = dev.transpose() * p * dev;
    if (!(pd(0, 0) > 0 && pd.determinant() > 0))
      fail(
          "the tensile yield stresses X, Y, Z violate the triangle-type condition of Hill's criterion "
          "(the yield surface is open in a deviatoric direction)");
  }
};

/// History of one material point, committed only when a step is accepted (the driver keeps two copies).
struct HillState {
  Vec6 strain         = Vec6::Zero();  ///< total strain at the last commit, global [-]
  Vec6 thermal_strain = Vec6::Zero();  ///< thermal strain at the last commit, global [-]
  Vec6 plastic_strain = Vec6::Zero();  ///< global, engineering shears [-]
  Vec6 back_stress    = Vec6::Zero();  ///< alpha, global, tensor shears [stress]
  double eqps         = 0.0;    ///< equivalent plastic strain: plastic work / X (= Mises' for Mises) [-]
  bool plastic        = false;  ///< on the yield surface at the last commit (the seed's IFGPL flag)
  bool operator==(const HillState&) const = default;
};

/// The return map's matrix A(dl) = I + 2 dl E P (E = C + cH) taken apart once per law and element,
/// so that a yielding point inverts it mode by mode instead of factorizing a 6 x 6 matrix per iteration
/// (docs/theory.md 7.3). With E = L L^T (Cholesky) and L^T P L = Q diag(lambda) Q^T (symmetric, positive
/// semi-definite), the modes V = L Q and W = V^-1 = Q^T L^-1 give
///   E P = V diag(lambda) W,   A(dl)^-1 = V diag(1 / (1 + 2 dl lambda)) W,   V^T P V = diag(lambda),
/// so with y = W xi_trial the yield function along the return is f(dl) = sum lambda_i y_i^2 /
/// (1 + 2 dl lambda_i)^2, a scalar function. lambda is 0 along the hydrostatic mode (P's null space).
struct HillModes {
  Vec6 lambda;      ///< eigenvalues of E P [-]
  Mat66 modes;      ///< V
  Mat66 inverse;    ///< W = V^-1
  Mat66 inverse_c;  ///< W C, for the consistent tangent
};

/// E P's modes from C, cH and P (global axes); E = C + cH must be positive definite (C is).
/// A template, like HillPoint::modes() below, so that Eigen's 6 x 6 Cholesky and eigen-solver are compiled
/// only in the units that run a plastic law, not in every unit that includes the laws (about 4 s each;
/// BENCHMARKS.md "CI time").
template <class Matrix>
HillModes hill_modes(const Matrix& c, const Matrix& ch, const Matrix& p) {
  const Eigen::LLT<Matrix> e(c + ch);
  const Mat66 l = e.matrixL();
  const Eigen::SelfAdjointEigenSolver<Matrix> s(Matrix(l.transpose() * p * l));
  HillModes m;
  m.lambda    = s.eigenvalues().cwiseMax(0.0);  // P is semi-definite: a round-off negative is a zero
  m.modes     = l * s.eigenvectors();
  m.inverse   = s.eigenvectors().transpose() * e.matrixL().solve(Mat66::Identity());
  m.inverse_c = m.inverse * c;
  return m;
}

/// The law resolved for one element: elastic data plus P, c H in global axes.
struct HillPoint : ElasticPoint {
  Mat66 yield_matrix;            ///< P_g [1 / stress^2]
  Mat66 hardening_matrix;        ///< c H_g [stress]
  double reference_yield = 1.0;  ///< X, the stress eqps is measured with [stress]

  /// E P's modes, computed at the first yielding point that asks (most cells of most steps have none,
  /// and a temperature field resolves every cell anew); valid while stiffness, hardening_matrix and
  /// yield_matrix stay as they were then (a point's thermal strain may change).
  template <int = 0>  // instantiated where a plastic law is run (hill_modes)
  const HillModes& modes() const {
    if (!modes_) modes_ = hill_modes(stiffness, hardening_matrix, yield_matrix);
    return *modes_;
  }

 private:
  mutable std::optional<HillModes> modes_;
};

/// The seed's scheme: one forward-Euler step with EPLSS's continuum tangent (see the header comment).
struct Tangent {
  static constexpr const char* kName           = "tangent";
  static constexpr bool kEquilibriumIterations = false;
};
/// Backward-Euler closest-point projection with the consistent tangent, for Newton iterations.
struct ReturnMapping {
  static constexpr const char* kName           = "return-mapping";
  static constexpr bool kEquilibriumIterations = true;
  static constexpr int kMaxIterations          = 200;    ///< scalar Newton (with bisection) on the multiplier
  static constexpr double kTolerance           = 1e-13;  ///< |f - 1|
};

}  // namespace gapfe

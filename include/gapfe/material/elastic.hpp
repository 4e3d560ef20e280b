#pragma once
// Linear elasticity with temperature-dependent constants (seed Data 10; docs/theory.md 3).
//
// Orthotropic: nine engineering constants in (N, S, T) axes, Jones' convention
// nu_ij = -eps_j / eps_i under uniaxial sigma_i, reciprocity nu_ij / E_i = nu_ji / E_j, rotated to the
// element's frame by BETA/ALPHA. Isotropic: E, nu (G = E / 2(1 + nu)), no rotation. Both keep a table
// of up to 12 temperatures (the seed's limit, not enforced), linearly interpolated at the element
// temperature and held constant outside the table (as Abaqus does).
//
// Thermal strain (card 10a "thermal expansion parameter"): `coefficients` means the table holds alpha(T)
// and eps_th = alpha(T) (T - T_ref); `free_strain` means it holds the free expansion e(T) and
// eps_th = e(T) - e(T_ref). In global axes eps_th_g = T_sigma^T eps_th_m (shear parts when BETA is
// not a multiple of 90 degrees).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "gapfe/core/concepts.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/material/orientation.hpp"

namespace gapfe {

/// One row of the property table, in material axes (N, S, T). Stresses and moduli share one unit.
struct ElasticConstants {
  double temperature = 0.0;                ///< table temperature [deg]
  double E_N = 0, E_S = 0, E_T = 0;        ///< Young's moduli [stress]
  double nu_NS = 0, nu_NT = 0, nu_ST = 0;  ///< Poisson's ratios (Jones: -eps_S / eps_N under sigma_N ...)
  double G_NS = 0, G_ST = 0, G_TN = 0;     ///< shear moduli [stress]
  double alpha_N = 0, alpha_S = 0, alpha_T = 0;  ///< expansion coefficients [1/deg] or free strains [-]

  /// An isotropic row.
  static ElasticConstants isotropic(double E, double nu, double alpha = 0.0, double temperature = 0.0) {
    const double G = E / (2.0 * (1.0 + nu));
    return {temperature, E, E, E, nu, nu, nu, G, G, G, alpha, alpha, alpha};
  }

  /// Compliance in material Voigt order [NN, SS, TT, NS, ST, TN] (docs/theory.md 3.1).
  Mat66 compliance() const {
    Mat66 s = Mat66::Zero();
    s(0, 0) = 1 / E_N, s(1, 1) = 1 / E_S, s(2, 2) = 1 / E_T;
    s(0, 1) = s(1, 0) = -nu_NS / E_N;
    s(0, 2) = s(2, 0) = -nu_NT / E_N;
    s(1, 2) = s(2, 1) = -nu_ST / E_S;
    s(3, 3) = 1 / G_NS, s(4, 4) = 1 / G_ST, s(5, 5) = 1 / G_TN;
    return s;
  }
  /// Stiffness, the compliance's inverse: the normal block inverted in closed form, the shears' diagonal.
  Mat66 stiffness() const {
    Mat66 c                 = Mat66::Zero();
    c.topLeftCorner<3, 3>() = compliance().topLeftCorner<3, 3>().inverse();
    c(3, 3) = G_NS, c(4, 4) = G_ST, c(5, 5) = G_TN;
    return c;
  }
  Vec3 expansion() const { return {alpha_N, alpha_S, alpha_T}; }
  bool operator==(const ElasticConstants&) const = default;

  /// Throws InputError naming `where` unless E, G > 0 and finite, |nu_ij| < sqrt(E_i / E_j) and S is positive
  /// definite.
  void validate(const std::string& where) const {
    const auto fail     = [&](const std::string& what) { throw InputError(where + ": " + what); };
    const auto positive = [](double v) { return v > 0 && std::isfinite(v); };
    if (!(positive(E_N) && positive(E_S) && positive(E_T)))
      fail("Young's moduli E_N, E_S, E_T must be positive and finite");
    if (!(positive(G_NS) && positive(G_ST) && positive(G_TN)))
      fail("shear moduli G_NS, G_ST, G_TN must be positive and finite");
    if (!(std::abs(nu_NS) < std::sqrt(E_N / E_S) && std::abs(nu_NT) < std::sqrt(E_N / E_T) &&
          std::abs(nu_ST) < std::sqrt(E_S / E_T)))
      fail("a Poisson's ratio violates |nu_ij| < sqrt(E_i / E_j)");
    // The normal block of S positive definite (the shear block is diagonal and positive above): with the
    // pairwise bounds above, its determinant times E_N E_S E_T, 1 - nu_NS nu_SN - nu_ST nu_TS - nu_NT nu_TN
    // - 2 nu_NS nu_ST nu_TN > 0 (nu_ji = nu_ij E_j / E_i; Lempriere's condition). Dimensionless, so the
    // isotropic limit nu = 0.5 gives 0 exactly; and no Cholesky factorization for every unit that
    // includes this header to compile.
    const double scaled_determinant = 1 - nu_NS * nu_NS * E_S / E_N - nu_ST * nu_ST * E_T / E_S -
                                      nu_NT * nu_NT * E_T / E_N - 2 * nu_NS * nu_ST * nu_NT * E_T / E_N;
    if (!(scaled_determinant > 0))
      fail("the compliance matrix is not positive definite (Poisson's ratios too large)");
    const auto finite = [](double v) { return std::isfinite(v); };
    if (!(finite(alpha_N) && finite(alpha_S) && finite(alpha_T) && finite(temperature)))
      fail("non-finite temperature or expansion value");
  }
};

enum class ThermalInput { coefficients, free_strain };

/// A property table: rows sorted by temperature, interpolated linearly, constant outside.
struct ElasticTable {
  std::vector<ElasticConstants> rows;
  ThermalInput thermal                       = ThermalInput::coefficients;
  double density                             = 0.0;  ///< mass density [mass / length^3], for inertia loads
  bool operator==(const ElasticTable&) const = default;

  ElasticConstants at(double T) const {
    if (T <= rows.front().temperature) return rows.front();
    if (T >= rows.back().temperature) return rows.back();
    const auto hi  = std::upper_bound(rows.begin(), rows.end(), T,
                                      [](double t, const ElasticConstants& c) { return t < c.temperature; });
    const auto& b  = *hi;
    const auto& a  = *(hi - 1);
    const double s = (T - a.temperature) / (b.temperature - a.temperature);
    const auto mix = [s](double x, double y) { return x + s * (y - x); };
    return {T,
            mix(a.E_N, b.E_N),
            mix(a.E_S, b.E_S),
            mix(a.E_T, b.E_T),
            mix(a.nu_NS, b.nu_NS),
            mix(a.nu_NT, b.nu_NT),
            mix(a.nu_ST, b.nu_ST),
            mix(a.G_NS, b.G_NS),
            mix(a.G_ST, b.G_ST),
            mix(a.G_TN, b.G_TN),
            mix(a.alpha_N, b.alpha_N),
            mix(a.alpha_S, b.alpha_S),
            mix(a.alpha_T, b.alpha_T)};
  }

  /// Thermal strain in material axes (N, S, T normal components) at T, relative to T_ref.
  Vec3 thermal_strain(const ElasticConstants& at_T, double T, double T_ref) const {
    if (thermal == ThermalInput::free_strain) return at_T.expansion() - at(T_ref).expansion();
    return at_T.expansion() * (T - T_ref);
  }

  void validate(const std::string& where) const {
    if (rows.empty()) throw InputError(where + ": no property rows");
    if (!(density >= 0 && std::isfinite(density))) throw InputError(where + ": density must be >= 0");
    for (std::size_t i = 0; i < rows.size(); ++i) {
      rows[i].validate(where + ", temperature row " + std::to_string(i + 1));
      if (i > 0 && !(rows[i].temperature > rows[i - 1].temperature))
        throw InputError(where + ": temperatures must increase strictly (row " + std::to_string(i + 1) + ")");
    }
  }
};

/// What an elastic law is for one element once its frame and temperature are known: stiffness and
/// thermal strain in global Voigt axes. This is the hot-path data; the table lookups happen once.
struct ElasticPoint {
  Mat66 stiffness;      ///< C_g = T_eps^T C_m T_eps [stress]
  Vec6 thermal_strain;  ///< eps_th in global Voigt order [-]
  double density = 0.0;
  Mat66 to_material;  ///< T_sigma: sigma_material = to_material * sigma_global
};

/// Per-point history of a law without history: costs nothing.
struct NoHistory {
  bool operator==(const NoHistory&) const = default;
};

/// Elastic stress update shared by both laws: sigma = C (eps - eps_th); the state never changes.
struct ElasticUpdate {
  using State                   = NoHistory;
  static constexpr bool kLinear = true;  ///< tangent independent of strain and history
  /// Laws compare equal when they give the same stiffness and thermal strain: LinearStatic re-assembles
  /// the stiffness only when a law (or a temperature) changed.
  bool operator==(const ElasticUpdate&) const = default;
  static PointResponse<NoHistory> update(const ElasticPoint& p, const Vec6& strain, const NoHistory&,
                                         const StepContext&) {
    return {p.stiffness * (strain - p.thermal_strain), p.stiffness, {}, false};
  }
};

struct Orthotropic : ElasticUpdate {
  ElasticTable table;
  using Local = ElasticPoint;

  static Orthotropic constant(const ElasticConstants& c, double density = 0.0) {
    return {{}, {{c}, ThermalInput::coefficients, density}};
  }
  Local localize(const MaterialFrame& frame, double T, double T_ref) const {
    const ElasticConstants c = table.at(T);
    const Mat66 t_sigma      = stress_rotation(material_axes(frame));
    const Mat66 t_eps        = strain_rotation(t_sigma);
    const Mat66 c_m          = c.stiffness();
    Vec6 eps_m               = Vec6::Zero();
    eps_m.head<3>()          = table.thermal_strain(c, T, T_ref);
    return {t_eps.transpose() * c_m * t_eps, t_sigma.transpose() * eps_m, table.density, t_sigma};
  }
  void validate(const std::string& where) const { table.validate(where); }
  bool operator==(const Orthotropic&) const = default;
};

struct Isotropic : ElasticUpdate {
  ElasticTable table;  ///< rows built with ElasticConstants::isotropic
  using Local = ElasticPoint;

  static Isotropic constant(double E, double nu, double alpha = 0.0, double density = 0.0) {
    return {{}, {{ElasticConstants::isotropic(E, nu, alpha)}, ThermalInput::coefficients, density}};
  }
  Local localize(const MaterialFrame& /*frame: isotropic*/, double T, double T_ref) const {
    const ElasticConstants c = table.at(T);
    const double E = c.E_N, nu = c.nu_NS, lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), G = E / (2 * (1 + nu));
    Local p;
    p.stiffness.setZero();
    p.stiffness.topLeftCorner<3, 3>().setConstant(lambda);
    p.stiffness.topLeftCorner<3, 3>().diagonal().array() += 2 * G;
    p.stiffness.bottomRightCorner<3, 3>().diagonal().setConstant(G);
    p.thermal_strain.setZero();
    p.thermal_strain.head<3>().setConstant(table.thermal_strain(c, T, T_ref)(0));
    p.density     = table.density;
    p.to_material = Mat66::Identity();
    return p;
  }
  void validate(const std::string& where) const {
    table.validate(where);
    for (const auto& c : table.rows)
      if (!(c.E_N == c.E_S && c.E_S == c.E_T && c.nu_NS == c.nu_NT && c.nu_NT == c.nu_ST))
        throw InputError(where + ": an Isotropic table row has direction-dependent constants");
  }
  bool operator==(const Isotropic&) const = default;
};

}  // namespace gapfe

namespace gapfe {
static_assert(MaterialLaw<Orthotropic>);
static_assert(MaterialLaw<Isotropic>);
}  // namespace gapfe

#pragma once
// Hill (1948) anisotropic plasticity with Prager kinematic hardening: SAGAEP's law (seed section 2.1,
// Appendix B subroutine EPLSS; docs/theory.md 7), on top of the orthotropic elastic law.
//
// Yield function in material axes (N, S, T), xi = sigma - alpha (tensor shears), yield at f = 1:
//   f = xi_NN^2/X^2 + xi_SS^2/Y^2 + xi_TT^2/Z^2 + (1/Z^2 - 1/X^2 - 1/Y^2) xi_NN xi_SS
//     + (1/Y^2 - 1/X^2 - 1/Z^2) xi_NN xi_TT + (1/X^2 - 1/Y^2 - 1/Z^2) xi_SS xi_TT
//     + xi_NS^2/R_NS^2 + xi_ST^2/R_TS^2 + xi_TN^2/R_NT^2  =  xi^T P xi,
// exactly the function whose gradient EPLSS computes (DFDSIG = a = 2 P xi, cross coefficients SIGYB).
// The card's shear order (NS, NT, TS) differs from the Voigt order (NS, ST, TN): mapped by axis pair.
// Flow is associated, d eps_p = d lambda a (a is conjugate to engineering shear strain), and Prager's
// rule d alpha = c H d eps_p moves the centre. H = I is EPLSS's choice (`PragerShear::legacy`, which
// doubles the shear back-stress rate of the tensorial rule); H = diag(1, 1, 1, 1/2, 1/2, 1/2) is the
// tensorial rule (`PragerShear::tensor`). Uniaxial answers agree; shear answers do not (docs/theory.md 7.2).
//
// Everything is evaluated in global axes with P_g = T_s^T P T_s and H_g = T_e^T H T_e (T_s, T_e the
// stress and strain rotations): the dual pairings are invariant, so the update formulas keep their form.
//
// Integration is a compile-time policy (the `Integration` parameter):
//   * `Tangent`: SAGAEP's forward-Euler scheme. The elastic part of a step up to the yield surface is
//     found exactly (a quadratic in the step fraction), the rest is integrated with the continuum
//     elastic-plastic tangent C_ep of EPLSS at the yield point, once. The tangent it gives the assembler
//     is C_ep at the start of the step for points that ended the last step plastic (the seed's IFGPL
//     flag), so one linear solve per increment is the seed's method. Stresses drift off the surface.
//   * `ReturnMapping`: backward-Euler closest-point projection onto the surface (docs/theory.md 7.3) with
//     the algorithmically consistent tangent, for Newton equilibrium iterations: no drift.
// Both detect loading, unloading and reloading from the elastic trial state.
//
// Units: stresses as the moduli; C (card 11, `hardening`) in stress units; strains dimensionless.
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
#include "gapfe/material/hill_yield.hpp"
#include "gapfe/material/plastic_flow.hpp"

namespace gapfe {

/// Hill plasticity over the orthotropic elastic law; `Integration` is Tangent or ReturnMapping.
template <class Integration>
struct Hill {
  Orthotropic elastic;
  HillYield yield;

  using State                    = HillState;
  using Local                    = HillPoint;
  using Integrator               = Integration;
  static constexpr bool kLinear  = false;
  static constexpr bool kIterate = Integration::kEquilibriumIterations;

  Local localize(const MaterialFrame& frame, double T, double T_ref) const {
    Local p;
    static_cast<ElasticPoint&>(p) = elastic.localize(frame, T, T_ref);
    const Mat66 t_eps             = strain_rotation(p.to_material);
    p.yield_matrix                = p.to_material.transpose() * yield.yield_matrix() * p.to_material;
    p.hardening_matrix            = yield.hardening * (t_eps.transpose() * yield.hardening_matrix() * t_eps);
    p.reference_yield             = yield.blank() ? 1.0 : yield.X;
    return p;
  }
  void validate(const std::string& where) const {
    elastic.validate(where);
    yield.validate(where);
  }

  /// sqrt(f): the equivalent stress over the yield stress (1 on the surface).
  static double yield_ratio(const Local& p, const Vec6& stress, const State& s) {
    const Vec6 xi = stress - s.back_stress;
    return std::sqrt(std::max(0.0, xi.dot(p.yield_matrix * xi)));
  }

  static PointResponse<State> update(const Local& p, const Vec6& strain, const State& old,
                                     const StepContext& ctx) {
    if constexpr (std::is_same_v<Integration, ReturnMapping>)
      return detail::hill_return_map(p, strain, old, detail::RateTerm{}, ctx.tangent);
    else
      return detail::hill_forward_euler(p, strain, old, [](auto&&...) { return detail::SurfaceChange{}; });
  }
};

}  // namespace gapfe

namespace gapfe {
static_assert(MaterialLaw<Hill<Tangent>>);
static_assert(MaterialLaw<Hill<ReturnMapping>>);
}  // namespace gapfe

#pragma once
// Material axes and the 6x6 Voigt transformations (docs/theory.md 3.2-3.3; seed Data 6 and Fig. 4).
//
// Material axes are indexed (N, S, T) = (0, 1, 2), the card order of E_N, E_S, E_T. BETA turns N in
// the meridian plane, measured from +z toward +r; ALPHA (helical) turns N out of the meridian plane
// toward +theta about T. Components in (r, z, theta):
//   N = (cos a sin b, cos a cos b, sin a),  S = (-sin a sin b, -sin a cos b, cos a),  T = (-cos b, sin b, 0)
// With ALPHA = 0 the N-T plane is the r-z plane and S is the hoop direction. An orthotropic C is
// unchanged when an axis is reversed, so handedness does not matter.
#include <string>

#include "gapfe/core/error.hpp"
#include "gapfe/core/material_frame.hpp"
#include "gapfe/core/types.hpp"

namespace gapfe {

/// The frame of the cell at I-offset `i_offset` (I - IMIN of its material block, from 0) under the seed's
/// card 6 helical option: IANG = 0 keeps ALPHA for the whole block; IANG = 1 flips its sign every NANG
/// cells along I (+ALPHA for the first NANG, -ALPHA for the next NANG, ...), an angle-ply winding.
inline MaterialFrame helical_frame(double beta, double alpha, int iang, int nang, int i_offset) {
  if (iang != 0 && iang != 1) throw InputError("IANG must be 0 or 1, got " + std::to_string(iang));
  if (iang == 1 && nang < 1) throw InputError("IANG = 1 needs NANG >= 1, got " + std::to_string(nang));
  if (i_offset < 0) throw InputError("helical_frame: negative I offset");
  const bool flipped = iang == 1 && (i_offset / nang) % 2 == 1;
  return {beta, flipped ? -alpha : alpha};
}

/// Rows: the material axes N, S, T in global (r, z, theta) components.
inline Mat33 material_axes(const MaterialFrame& f) {
  const double sb = std::sin(f.beta), cb = std::cos(f.beta);
  const double sa = std::sin(f.alpha), ca = std::cos(f.alpha);
  Mat33 q;
  // clang-format off
  q <<  ca * sb,  ca * cb, sa,
       -sa * sb, -sa * cb, ca,
       -cb,       sb,      0.0;
  // clang-format on
  return q;
}

/// Stress transformation, sigma_material = T_sigma sigma_global, built from the Voigt pair table:
/// T_sigma(I, K) = Q_ik Q_jl + (1 - delta_kl) Q_il Q_jk, I <-> (i, j), K <-> (k, l).
inline Mat66 stress_rotation(const Mat33& q) {
  Mat66 t;
  for (int I = 0; I < 6; ++I) {
    const auto [i, j] = voigt::kPairs[I];
    for (int K = 0; K < 6; ++K) {
      const auto [k, l] = voigt::kPairs[K];
      t(I, K)           = q(i, k) * q(j, l) + (k == l ? 0.0 : q(i, l) * q(j, k));
    }
  }
  return t;
}

/// Strain transformation (engineering shears), eps_material = T_eps eps_global:
/// T_eps(I, K) = (w_I / w_K) T_sigma(I, K), w = 1 for normal and 2 for shear slots; T_eps = T_sigma^-T.
inline Mat66 strain_rotation(const Mat66& t_sigma) {
  Mat66 t = t_sigma;
  for (int I = 0; I < 6; ++I)
    for (int K = 0; K < 6; ++K) t(I, K) *= (I < 3 ? 1.0 : 2.0) / (K < 3 ? 1.0 : 2.0);
  return t;
}

}  // namespace gapfe

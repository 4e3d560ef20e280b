#pragma once
// Helpers shared by the test translation units: small meshes and closed forms.
#include <doctest/doctest.h>

#include "gapfe/core/workers.hpp"
#include "gapfe/gapfe.hpp"
#include "gapfe/solver/threads.hpp"

namespace gapfe::test {

/// One thread for gapfe's pool and for OpenBLAS when a test that changed them ends, failed or not.
struct OneThreadAfter {
  OneThreadAfter()                                 = default;
  OneThreadAfter(const OneThreadAfter&)            = delete;
  OneThreadAfter& operator=(const OneThreadAfter&) = delete;
  ~OneThreadAfter() {
    set_worker_threads(1);
    set_solver_threads(1);
  }
};

/// Relative difference |a - b| / |b|.
inline double rel(double a, double b) {
  return std::abs(a - b) / std::abs(b);
}

/// Lame thick cylinder (docs/theory.md V1): inner pressure p, plane strain.
struct Lame {
  double a, b, p, E, nu;
  double A() const { return p * a * a / (b * b - a * a); }
  double B() const { return p * a * a * b * b / (b * b - a * a); }
  double radial_stress(double r) const { return A() - B() / (r * r); }
  double hoop_stress(double r) const { return A() + B() / (r * r); }
  double axial_stress() const { return 2 * nu * A(); }
  double displacement(double r) const {
    return r / E * (hoop_stress(r) - nu * (radial_stress(r) + axial_stress()));
  }
};

/// A solid cylinder of `radius` spinning at omega, plane strain, free surface: u = c r - kappa r^3 / 8 with
/// kappa = rho omega^2 / (lambda + 2 G), and sigma_r(radius) = 0 sets c. Its pressure varies as r^2.
struct SpinningCylinder {
  double radius, omega, density, E, nu;
  double lambda() const { return E * nu / ((1 + nu) * (1 - 2 * nu)); }
  double shear() const { return E / (2 * (1 + nu)); }
  /// The stresses (rr, zz, hoop) at r.
  Vec3 stress(double r) const {
    const double l = lambda(), g = shear(), kappa = density * omega * omega / (l + 2 * g);
    const double c   = (4 * l + 6 * g) * kappa * radius * radius / 8 / (2 * l + 2 * g);
    const double e_r = c - 3 * kappa * r * r / 8, e_t = c - kappa * r * r / 8;
    return {(l + 2 * g) * e_r + l * e_t, l * (e_r + e_t), l * e_r + (l + 2 * g) * e_t};
  }
};

}  // namespace gapfe::test

namespace gapfe::test {

/// Cells of a rectangle_mesh on the bore (i = 0) and on the top (j = nz - 1), and their edges as the
/// seed's pressure cards give them (element on the left from M to N).
template <int NPC>
std::vector<EdgeLoad> bore_pressure(const Mesh<NPC>& m, int nr, int nz, double p) {
  std::vector<EdgeLoad> loads;
  for (int j = 0; j < nz; ++j) loads.push_back({m.cells[j * nr][3], m.cells[j * nr][0], p, 0, 0});
  return loads;
}
template <int NPC>
std::vector<EdgeLoad> top_pressure(const Mesh<NPC>& m, int nr, int nz, double p) {
  std::vector<EdgeLoad> loads;
  for (int i = 0; i < nr; ++i)
    loads.push_back({m.cells[(nz - 1) * nr + i][2], m.cells[(nz - 1) * nr + i][3], p, 0, 0});
  return loads;
}
/// A condition with `code` and value(r, z) on every node with z == z0.
template <int NPC, class F>
void fix_plane(std::vector<NodalCondition>& out, const Mesh<NPC>& m, double z0, int code, F value) {
  for (int n = 0; n < m.node_count(); ++n)
    if (std::abs(m.nodes[n](1) - z0) < 1e-12) {
      const Vec3 v = value(m.nodes[n]);
      out.push_back({n, code, {v(0), v(1), v(2)}});
    }
}
inline Vec3 zero3(const Vec2&) {
  return Vec3::Zero();
}

}  // namespace gapfe::test

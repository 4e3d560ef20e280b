#pragma once
// The press fit of the friction tests and benchmarks (tests/test_friction.cpp, bench/bench_friction.cpp):
// an API scene with closed forms, free of any test framework.
#include <cmath>
#include <vector>

#include "gapfe/gapfe.hpp"

namespace gapfe::test {

/// A ring (hub) pressed on a hollow shaft by an external pressure q, then pushed along it or twisted:
/// the friction tests' fixture. Shaft a..b (n_shaft cells), one gap element layer b..b + w (w tiny, so
/// the fit starts practically touching), ring b + w..c (n_ring cells), nz cells over the length L.
/// Materials: 0 shaft, 1 gap, 2 ring.
///   drive_all (the closed-form case): nu = 0, every shaft node held at u_z = 0 (and u_theta = 0), every
///     ring node driven together by the push along z (and by a rotation: u_theta = twist r), so the
///     radial problem is exact 1-D Lame and the interface slides uniformly.
///   ring: every ring node driven, the shaft held at its bottom row only (the shaft carries the shear).
///   ends (end effects, Poisson coupling): the shaft's bottom row held, the ring's top row driven.
struct PressFit {
  // The gap element's own stiffness acts in shear too: w and its modulus keep that below 1e-8 of the
  // slip force over the pushes of the tests.
  double a = 0.0125, b = 0.025, c = 0.05, w = 1e-6, L = 0.05, E = 200e9, nu = 0, q = 75e6, mu = 0.15;
  double gap_modulus_ratio = 1e-12;
  int n_shaft = 6, n_ring = 8, nz = 10;
  enum class Drive { all, ring, ends } drive = Drive::all;
  double tilt = 0;  ///< > 0: the whole mesh turned by this angle [rad] about (b, L / 2) and moved out by 1 m
                    ///< in r (a conical fit): the gap's N, T are then not along r and z

  /// External pressure that closes the gap w on the ring alone (nu = 0): w E (c^2 - b^2) / (2 b c^2).
  double closure_pressure() const { return w * E * (c * c - b * b) / (2 * b * c * c); }
  /// Contact pressure beyond closure: the compound tube a..c under q - q_c (Lame, nu = 0, one material):
  /// p = (q - q_c) c^2 (b^2 - a^2) / (b^2 (c^2 - a^2)).
  double contact_pressure() const {
    return (q - closure_pressure()) * c * c * (b * b - a * a) / (b * b * (c * c - a * a));
  }
  /// Slip force mu p 2 pi b L [N] and slip torque mu p 2 pi b^2 L [N m] (total ring).
  double slip_force() const { return mu * contact_pressure() * kTwoPi * b * L; }
  double slip_torque() const { return slip_force() * b; }

  int columns() const { return n_shaft + n_ring + 2; }  ///< nodes per row
  bool ring_node(int n) const { return n % columns() > n_shaft; }
  bool driven(int n) const {
    if (drive == Drive::all) return true;
    if (ring_node(n)) return drive == Drive::ring || n / columns() == nz;
    return n / columns() == 0;
  }

  template <class M>
  Problem<M> problem(std::vector<GapPair>& pairs) const {
    std::vector<double> r;
    for (int i = 0; i <= n_shaft; ++i) r.push_back(a + (b - a) * i / n_shaft);
    for (int i = 0; i <= n_ring; ++i) r.push_back(b + w + (c - b - w) * i / n_ring);
    const int ni = columns();
    Problem<M> p;
    for (int j = 0; j <= nz; ++j)
      for (int i = 0; i < ni; ++i) {
        const Vec2 x(r[i] - b, j * L / nz - L / 2);
        p.mesh.nodes.push_back(
            Vec2(std::cos(tilt) * x(0) - std::sin(tilt) * x(1) + b + (tilt != 0 ? 1.0 : 0.0),
                 std::sin(tilt) * x(0) + std::cos(tilt) * x(1) + L / 2));
      }
    for (int j = 0; j < nz; ++j)
      for (int i = 0; i + 1 < ni; ++i) {
        const std::array<int, 4> ix{j * ni + i, j * ni + i + 1, (j + 1) * ni + i + 1, (j + 1) * ni + i};
        p.mesh.cells.push_back(ix);
        p.mesh.cell_tags.push_back({i < n_shaft ? 0 : i == n_shaft ? 1 : 2, {}});
        if (i == n_shaft)
          for (const auto& g :
               gap_element_pairs(static_cast<int>(p.mesh.cells.size() - 1), ix, 1, p.mesh.nodes))
            pairs.push_back(g);
      }
    if constexpr (M::Material::kLinear)
      p.materials = {M::Material::constant(E, nu), M::Material::constant(gap_modulus_ratio * E, 0.0),
                     M::Material::constant(E, nu)};
    for (int n = 0; n < p.mesh.node_count(); ++n)
      if (driven(n)) p.conditions.push_back({n, M::kDofsPerNode == 3 ? 6 : 2, {}});
    return p;
  }
  /// Loads at pressure fraction `pressure` (of q), push [m] and twist [rad].
  template <class M>
  void set(Problem<M>& p, double pressure, double push, double twist = 0) const {
    const int ni = columns();
    p.edge_loads.clear();
    for (int j = 0; j < nz; ++j)
      p.edge_loads.push_back({j * ni + ni - 1, (j + 1) * ni + ni - 1, pressure * q, 0, 0});
    for (auto& cnd : p.conditions)
      if (ring_node(cnd.node)) cnd.value = {0, push, twist * p.mesh.nodes[cnd.node](0)};
  }
  /// Total ring reaction along z and torque about the axis over the ring's (driven) nodes.
  double push_force(const Solution& s) const {
    double f = 0;
    for (int n = 0; n < static_cast<int>(s.reaction.rows()); ++n)
      if (ring_node(n)) f += s.reaction(n, 1);
    return f;
  }
  template <class M>
  double torque(const Problem<M>& p, const Solution& s) const {
    double t = 0;
    for (int n = 0; n < static_cast<int>(s.reaction.rows()); ++n)
      if (ring_node(n)) t += s.reaction(n, 2) * p.mesh.nodes[n](0);
    return t;
  }
};

}  // namespace gapfe::test

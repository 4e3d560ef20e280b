#pragma once
// Two concentric tubes with a radial clearance (docs/theory.md V5), plane strain, as an API scene: the
// fixture of the contact tests and benchmarks.
#include "press_fit.hpp"
#include "support.hpp"

namespace gapfe::test {

/// Inner tube a..b (n_inner cells), one gap element layer b..b + delta, outer tube b + delta..c
/// (n_outer cells), nz cells of height h; u_z = 0 everywhere (plane strain); bore pressure p.
struct TwoTubes {
  double a = 0.05, b = 0.075, c = 0.1, delta = 20e-6, E = 200e9, nu = 0.3, gap_modulus_ratio = 1e-9;
  int n_inner = 40, n_outer = 40, nz = 1;
  double height = 0.001;
  double aspect = 0;  ///< > 0: gap element height / width (sets `height` from delta)

  /// Closure pressure, plane strain: delta E (b^2 - a^2) / (2 a^2 b (1 - nu^2)).
  double closure_pressure() const { return delta * E * (b * b - a * a) / (2 * a * a * b * (1 - nu * nu)); }
  /// Contact pressure at bore pressure p > p_c: (p - p_c) a^2 (c^2 - b^2) / (b^2 (c^2 - a^2)) (V5).
  double contact_pressure(double p) const {
    return std::max(p - closure_pressure(), 0.0) * a * a * (c * c - b * b) / (b * b * (c * c - a * a));
  }
  /// Bore radial displacement and hoop stress at radius r of the inner tube, by superposition: the inner
  /// tube alone up to p_c, then the compound tube a..c as one (same material, frictionless).
  double inner_displacement(double r, double p) const {
    const double pc = std::min(p, closure_pressure());
    return Lame{a, b, pc, E, nu}.displacement(r) + Lame{a, c, p - pc, E, nu}.displacement(r);
  }
  double inner_hoop(double r, double p) const {
    const double pc = std::min(p, closure_pressure());
    return Lame{a, b, pc, E, nu}.hoop_stress(r) + Lame{a, c, p - pc, E, nu}.hoop_stress(r);
  }

  template <class M>
  Problem<M> problem(std::vector<GapPair>& pairs) const {
    std::vector<double> r;
    for (int i = 0; i <= n_inner; ++i) r.push_back(a + (b - a) * i / n_inner);
    for (int i = 0; i <= n_outer; ++i) r.push_back(b + delta + (c - b - delta) * i / n_outer);
    const double h = aspect > 0 ? aspect * delta : height;
    const int ni   = static_cast<int>(r.size());
    Problem<M> p;
    for (int j = 0; j <= nz; ++j)
      for (int i = 0; i < ni; ++i) p.mesh.nodes.push_back({r[i], j * h});
    const int gap_column = n_inner;
    for (int j = 0; j < nz; ++j)
      for (int i = 0; i + 1 < ni; ++i) {
        const std::array<int, 4> ix{j * ni + i, j * ni + i + 1, (j + 1) * ni + i + 1, (j + 1) * ni + i};
        p.mesh.cells.push_back(ix);
        p.mesh.cell_tags.push_back({i == gap_column ? 1 : 0, {}});
        if (i == gap_column)
          for (const auto& g :
               gap_element_pairs(static_cast<int>(p.mesh.cells.size() - 1), ix, 1, p.mesh.nodes))
            pairs.push_back(g);
      }
    if constexpr (M::Material::kLinear)  // laws with history: the caller sets them
      p.materials = {M::Material::constant(E, nu), M::Material::constant(gap_modulus_ratio * E, 0.0)};
    for (int n = 0; n < p.mesh.node_count(); ++n) p.conditions.push_back({n, 2, {}});
    return p;
  }
  /// Bore pressure edges (element on the left going down the bore).
  template <class M>
  void set_pressure(Problem<M>& p, double pressure) const {
    const int ni = n_inner + n_outer + 2;
    p.edge_loads.clear();
    for (int j = 0; j < nz; ++j) p.edge_loads.push_back({(j + 1) * ni, j * ni, pressure, 0, 0});
  }
};

}  // namespace gapfe::test

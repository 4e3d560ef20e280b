// The README's example: a plane-strain thick tube (SAAS-style 2-DOF, Quad4), bore displacement
// against Lame's closed form. Exits 1 if it is off by more than 1%.
#include <cmath>
#include <iostream>

#include "gapfe/gapfe.hpp"

int main() {
  using Tube = gapfe::Model<gapfe::Axisym2, gapfe::Quad4, gapfe::Isotropic>;
  gapfe::Problem<Tube> p;
  p.mesh      = gapfe::rectangle_mesh<4>(0.1, 0.2, 0.0, 0.02, 16, 2);  // r in [0.1, 0.2] m
  p.materials = {gapfe::Isotropic::constant(200e9, 0.3)};              // E [Pa], nu
  for (int j = 0; j < 2; ++j) {                                        // 100 MPa on the bore
    const auto& cell = p.mesh.cells[j * 16];
    p.edge_loads.push_back({cell[3], cell[0], 100e6});  // from M to N, element on the left
  }
  for (int n = 0; n < p.mesh.node_count(); ++n)  // plane strain: u_z = 0 at both ends (code 2)
    if (p.mesh.nodes[n].y() == 0.0 || p.mesh.nodes[n].y() == 0.02) p.conditions.push_back({n, 2});
  gapfe::LinearStatic<Tube> fe(std::move(p));
  const double u = fe.solve().displacement(0, 0);  // node 0 is at (a, 0)
  std::cout << "bore u_r = " << u << " m (Lame: 9.5333e-05 m)\n";
  return std::abs(u / 9.5333e-5 - 1) < 0.01 ? 0 : 1;
}

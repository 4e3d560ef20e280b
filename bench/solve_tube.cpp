// gapfe_solve_tube --nr NR --nz NZ [--solver eigen|eigen-amd|cholmod] [--element quad4|legacy]
// One plane-strain Lame thick-tube solve (a = 0.1, b = 0.2 m, p = 100 MPa, square cells, the same
// problem bench/ccx_compare.py gives CalculiX), printing one line:
//   gapfe nr=.. nz=.. dofs=.. solver=.. setup_s=.. assemble_s=.. factor_s=.. solve_s=.. total_s=.. u_bore=..
// setup is the DOF map, pattern, offsets and symbolic analysis; total is everything from the mesh on.
#include <chrono>
#include <iostream>
#include <string>

#include "gapfe/gapfe.hpp"
#ifdef GAPFE_HAS_CHOLMOD
#include "gapfe/solver/cholmod.hpp"
#endif

namespace {
template <class Elem, class Solver>
int run(int nr, int nz, const std::string& name) {
  using M        = gapfe::Model<gapfe::Axisym2, Elem, gapfe::Isotropic, Solver>;
  using clock    = std::chrono::steady_clock;
  const auto t0  = clock::now();
  const double a = 0.1, b = 0.2, L = nz * (b - a) / nr;
  gapfe::Problem<M> p;
  p.mesh      = gapfe::rectangle_mesh<Elem::kNodes>(a, b, 0, L, nr, nz);
  p.materials = {gapfe::Isotropic::constant(200e9, 0.3)};
  for (int j = 0; j < nz; ++j) {
    const auto& c = p.mesh.cells[static_cast<std::size_t>(j) * nr];
    p.edge_loads.push_back({c[3], c[0], 100e6, 0, 0});
  }
  for (int n = 0; n < p.mesh.node_count(); ++n)
    if (p.mesh.nodes[n](1) == 0 || p.mesh.nodes[n](1) == L) p.conditions.push_back({n, 2, {}});
  gapfe::LinearStatic<M> fe(std::move(p));
  const auto t1 = clock::now();
  const auto& s = fe.solve();
  const auto t2 = clock::now();
  const auto& t = fe.timings();
  std::cout << "gapfe nr=" << nr << " nz=" << nz << " dofs=" << fe.dofs().free_count << " solver=" << name
            << " setup_s=" << std::chrono::duration<double>(t1 - t0).count() << " assemble_s=" << t.assemble
            << " factor_s=" << t.factorize << " solve_s=" << t.solve << " reactions_s=" << t.reactions
            << " total_s=" << std::chrono::duration<double>(t2 - t0).count()
            << " u_bore=" << s.displacement(0, 0) << '\n';
  return 0;
}
}  // namespace

int main(int argc, char** argv) try {
  int nr = 316, nz = 158;
  std::string solver = "eigen", element = "quad4";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--nr")
      nr = std::stoi(v);
    else if (k == "--nz")
      nz = std::stoi(v);
    else if (k == "--solver")
      solver = v;
    else if (k == "--element")
      element = v;
    else
      throw gapfe::InputError("unknown option " + k);
  }
  if (solver == "eigen-amd") {
    if (element == "legacy") return run<gapfe::LegacyQuad, gapfe::EigenLdltAmd>(nr, nz, solver);
    return run<gapfe::Quad4, gapfe::EigenLdltAmd>(nr, nz, solver);
  }
  if (solver == "eigen") {
    if (element == "legacy") return run<gapfe::LegacyQuad, gapfe::EigenLdlt>(nr, nz, solver);
    return run<gapfe::Quad4, gapfe::EigenLdlt>(nr, nz, solver);
  }
#ifdef GAPFE_HAS_CHOLMOD
  if (solver == "cholmod") {
    if (element == "legacy") return run<gapfe::LegacyQuad, gapfe::CholmodLlt>(nr, nz, solver);
    return run<gapfe::Quad4, gapfe::CholmodLlt>(nr, nz, solver);
  }
#endif
  throw gapfe::InputError("solver " + solver + " is not available in this build");
} catch (const std::exception& e) {
  std::cerr << "gapfe_solve_tube: error: " << e.what() << '\n';
  return 1;
}

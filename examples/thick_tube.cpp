// thick_tube: the Lame thick cylinder under internal pressure (plane strain), solved with a chosen
// element and compared with the closed form (docs/theory.md V1). Writes DIR/thick_tube.vtu for ParaView
// and DIR/radial_profile.csv (centroid r, hoop and radial stress, FE and exact) for plots.
//
//   thick_tube [--element quad4|legacy|quad8] [--nr 16] [--nz 4] [--out DIR]
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "gapfe/gapfe.hpp"

namespace {

struct Options {
  std::string element = "quad4", out = "out";
  int nr = 16, nz = 4;
};

template <class Elem>
int run(const Options& o) {
  using M        = gapfe::Model<gapfe::Axisym2, Elem, gapfe::Isotropic>;
  const double a = 0.1, b = 0.2, p = 100e6, E = 200e9, nu = 0.3, height = o.nz * (b - a) / o.nr;
  gapfe::Problem<M> problem;
  problem.mesh      = gapfe::rectangle_mesh<Elem::kNodes>(a, b, 0, height, o.nr, o.nz);
  problem.materials = {gapfe::Isotropic::constant(E, nu)};
  for (int j = 0; j < o.nz; ++j) {  // bore edges, element on the left from M to N (seed Data 13)
    const auto& cell = problem.mesh.cells[static_cast<std::size_t>(j * o.nr)];
    problem.edge_loads.push_back({cell[3], cell[0], p, 0, 0});
  }
  for (int n = 0; n < problem.mesh.node_count(); ++n)  // plane strain: u_z = 0 on both ends
    if (problem.mesh.nodes[n](1) == 0 || problem.mesh.nodes[n](1) == height)
      problem.conditions.push_back({n, 2, {}});

  gapfe::LinearStatic<M> fe(std::move(problem));
  const gapfe::Solution& s = fe.solve();

  const double A = p * a * a / (b * b - a * a), B = p * a * a * b * b / (b * b - a * a);
  const auto hoop      = [&](double r) { return A + B / (r * r); };
  const auto radial    = [&](double r) { return A - B / (r * r); };
  const double u_exact = a / E * (hoop(a) - nu * (radial(a) + 2 * nu * A));
  const double u_bore  = s.displacement(gapfe::nearest_node(fe.problem().mesh, a, 0.0), 0);

  std::filesystem::create_directories(o.out);
  const auto centroids = fe.centroid_values();
  gapfe::write_vtu(o.out + "/thick_tube.vtu", fe.problem().mesh, s, centroids);
  std::ofstream csv(o.out + "/radial_profile.csv");
  csv << "r,hoop_fe,hoop_exact,radial_fe,radial_exact\n";
  for (int i = 0; i < o.nr; ++i) {
    const auto& v = centroids[static_cast<std::size_t>(i)];
    csv << v.r << ',' << v.stress(gapfe::voigt::hoop) << ',' << hoop(v.r) << ',' << v.stress(gapfe::voigt::rr)
        << ',' << radial(v.r) << '\n';
  }
  const auto& inner = centroids.front();
  std::cout << "thick tube, " << o.element << ", " << o.nr << " x " << o.nz << " cells, "
            << fe.dofs().free_count << " equations\n"
            << "  bore u_r      " << u_bore << " m   exact " << u_exact << "   rel. error "
            << std::abs(u_bore / u_exact - 1) << "\n"
            << "  hoop stress   " << inner.stress(gapfe::voigt::hoop) << " Pa at r = " << inner.r
            << "   exact " << hoop(inner.r) << "   rel. error "
            << std::abs(inner.stress(gapfe::voigt::hoop) / hoop(inner.r) - 1) << "\n"
            << "  wrote " << o.out << "/thick_tube.vtu and " << o.out << "/radial_profile.csv\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) try {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (i + 1 >= argc) throw gapfe::InputError("option " + k + " needs a value");
    const std::string v = argv[++i];
    if (k == "--element")
      o.element = v;
    else if (k == "--nr")
      o.nr = std::stoi(v);
    else if (k == "--nz")
      o.nz = std::stoi(v);
    else if (k == "--out")
      o.out = v;
    else
      throw gapfe::InputError("unknown option " + k + " (use --element, --nr, --nz, --out)");
  }
  if (o.element == "quad4") return run<gapfe::Quad4>(o);
  if (o.element == "legacy") return run<gapfe::LegacyQuad>(o);
  if (o.element == "quad8") return run<gapfe::Quad8>(o);
  throw gapfe::InputError("unknown element " + o.element + " (quad4, legacy, quad8)");
} catch (const std::exception& e) {
  std::cerr << "thick_tube: error: " << e.what() << '\n';
  return 1;
}

// The element study of the speed/accuracy atlas (bench/atlas.py): every element on the
// closed-form elastic problems at a range of refinements, through the library call a user makes
// (build the Problem, construct LinearStatic, solve). Benchmarks are named problem/element/n; counters:
//   error  = the larger of the two below, what the atlas plots;
//   u_error = max over the nodes of |u - u_exact| / max |u_exact| (the component the problem loads),
//   stress_error = max over the cell centroids of |s - s_exact| / max |s_exact| (hoop stress; tau_z-theta
//            for the shaft), the values `gapfe run` writes to elements.csv. Nodal values alone can flatter
//            an element: Quad4's are exact on the shaft (a 1-D problem along z), its stresses are not;
//   dofs  = nodes x DOFs per node (constrained ones included).
// Problems (docs/theory.md section 10; SI units):
//   lame        thick tube a = 0.1, b = 0.2 m, bore pressure 100 MPa, plane strain, nu = 0.3 (V1);
//               n cells through the wall, 2 rows of square cells.
//   lame-0.4999 the same with nu = 0.4999 (near-incompressible: volumetric locking shows).
//   spin        solid cylinder 0 <= r <= 0.1 m spinning at 1000 rad/s, plane strain: nodes on the axis;
//               u = C1 r - k r^3, k = rho w^2 / (8 (lambda + 2 G)), sigma_r(b) = 0.
//   shaft       solid shaft r <= 0.05 m, L = 0.5 m, fixed at z = 0, angular acceleration 1e4 rad/s^2
//               (V4, SAGA): u_theta = rho wdot r / G (z^2 / 2 - L z); n cells across, 10 n along.
//   build/bench/bench/bench_atlas --benchmark_filter='lame/' --benchmark_repetitions=3
#include <cmath>
#include <string>

#include <benchmark/benchmark.h>

#include "gapfe/gapfe.hpp"

namespace {
using namespace gapfe;

constexpr double kE = 200e9, kRho = 7850;

template <class M>
void fix_plane(Problem<M>& p, double z, int code) {
  for (int n = 0; n < p.mesh.node_count(); ++n)
    if (p.mesh.nodes[n](1) == z) p.conditions.push_back({n, code, {}});
}

/// Largest |stress(component) - exact(r, z)| over the cell centroids, relative to the largest |exact|.
template <class M, class Exact>
double centroid_error(const LinearStatic<M>& fe, int component, Exact exact) {
  double worst = 0, scale = 0;
  for (const auto& v : fe.centroid_values()) {
    const double e = exact(v.r, v.z);
    worst = std::max(worst, std::abs(v.stress(component) - e)), scale = std::max(scale, std::abs(e));
  }
  return worst / scale;
}

/// Largest |u(n, c) - exact(r, z)| over the nodes, relative to the largest |exact|.
template <class M, class Exact>
double nodal_error(const LinearStatic<M>& fe, const Solution& s, int c, Exact exact) {
  double worst = 0, scale = 0;
  const auto& m = fe.problem().mesh;
  for (int n = 0; n < m.node_count(); ++n) {
    const double e = exact(m.nodes[n](0), m.nodes[n](1));
    worst = std::max(worst, std::abs(s.displacement(n, c) - e)), scale = std::max(scale, std::abs(e));
  }
  return worst / scale;
}

/// The timed loop every problem shares: build the Problem, construct LinearStatic and solve (what a user's
/// program does); then the counters from the last solve: displacement component `c` at the nodes against
/// `exact_u`, centroid stress component `stress` against `exact_stress`.
template <class M, class Build, class ExactU, class ExactS>
void measure(benchmark::State& state, Build build, int c, ExactU exact_u, int stress, ExactS exact_stress) {
  double u_error = 0, stress_error = 0, dofs = 0;
  for (auto _ : state) {
    LinearStatic<M> fe(build());
    const Solution& s = fe.solve();
    u_error           = nodal_error(fe, s, c, exact_u);
    stress_error      = centroid_error(fe, stress, exact_stress);
    dofs              = static_cast<double>(s.displacement.rows() * M::Kinematics::kDofsPerNode);
  }
  state.counters["error"]        = std::max(u_error, stress_error);
  state.counters["u_error"]      = u_error;
  state.counters["stress_error"] = stress_error;
  state.counters["dofs"]         = dofs;
}

template <class M>
void lame(benchmark::State& state, double nu) {
  const int nr   = static_cast<int>(state.range(0));
  const double a = 0.1, b = 0.2, pressure = 100e6, h = (b - a) / nr;
  const double A = pressure * a * a / (b * b - a * a), B = A * b * b;
  const auto exact = [&](double r, double) {  // plane strain, sigma_z = 2 nu A
    return r / kE * ((A + B / (r * r)) - nu * ((A - B / (r * r)) + 2 * nu * A));
  };
  const auto hoop  = [&](double r, double) { return A + B / (r * r); };
  const auto build = [&] {
    Problem<M> p;
    p.mesh      = rectangle_mesh<M::Element::kNodes>(a, b, 0, 2 * h, nr, 2);
    p.materials = {M::Material::constant(kE, nu)};
    // The bore edge of each row's first cell, 3 -> 0 of the quad (Quad8: its corners come first; Tri3:
    // the same nodes as the 4-corner mesh, whose numbers are used).
    for (int j = 0; j < 2; ++j) {
      const std::size_t first = static_cast<std::size_t>(j) * nr;
      if constexpr (M::Element::kNodes == 8) {
        p.edge_loads.push_back({p.mesh.cells[first][3], p.mesh.cells[first][0], pressure, 0, 0});
      } else {
        const auto c = rectangle_mesh<4>(a, b, 0, 2 * h, nr, 2).cells[first];  // a copy
        p.edge_loads.push_back({c[3], c[0], pressure, 0, 0});
      }
    }
    fix_plane(p, 0.0, 2), fix_plane(p, 2 * h, 2);
    return p;
  };
  measure<M>(state, build, 0, exact, voigt::hoop, hoop);
}

template <class M>
void spin(benchmark::State& state) {
  const int nr   = static_cast<int>(state.range(0));
  const double b = 0.1, w = 1000, nu = 0.3, h = b / nr;
  const double lambda = kE * nu / ((1 + nu) * (1 - 2 * nu)), G = kE / (2 * (1 + nu));
  const double k   = kRho * w * w / (8 * (lambda + 2 * G)),
               C1  = (4 * lambda + 6 * G) * k * b * b / (2 * (lambda + G));
  const auto exact = [&](double r, double) { return C1 * r - k * r * r * r; };
  const auto hoop  = [&](double r, double) {
    return 2 * (lambda + G) * C1 - (4 * lambda + 2 * G) * k * r * r;
  };
  const auto build = [&] {
    Problem<M> p;
    p.mesh                     = rectangle_mesh<M::Element::kNodes>(0, b, 0, 2 * h, nr, 2);
    p.materials                = {M::Material::constant(kE, nu, 0, kRho)};
    p.inertia.angular_velocity = w;
    fix_plane(p, 0.0, 2), fix_plane(p, 2 * h, 2);
    return p;
  };
  measure<M>(state, build, 0, exact, voigt::hoop, hoop);
}

template <class M>
void shaft(benchmark::State& state) {
  const int nr   = static_cast<int>(state.range(0));
  const double c = 0.05, L = 0.5, wdot = 1e4, nu = 0.3, G = kE / (2 * (1 + nu));
  const auto exact = [&](double r, double z) { return kRho * wdot * r / G * (z * z / 2 - L * z); };
  const auto shear = [&](double r, double z) { return kRho * wdot * r * (z - L); };  // G du_theta / dz
  const auto build = [&] {
    Problem<M> p;
    p.mesh                         = rectangle_mesh<M::Element::kNodes>(0, c, 0, L, nr, 10 * nr);
    p.materials                    = {M::Material::constant(kE, nu, 0, kRho)};
    p.inertia.angular_acceleration = wdot;
    fix_plane(p, 0.0, 6);  // u_z = u_theta = 0 at the base
    return p;
  };
  measure<M>(state, build, 2, exact, voigt::z_theta, shear);
}

template <class Element>
void register_element(const std::string& name) {
  using M2 = Model<Axisym2, Element, Isotropic>;
  using M3 = Model<Axisym3, Element, Isotropic>;
  for (int n : {2, 4, 8, 16, 32, 64, 128}) {
    const std::string tail = "/" + name;  // Arg(n) appends "/n"
    benchmark::RegisterBenchmark(("lame" + tail).c_str(), [](benchmark::State& s) { lame<M2>(s, 0.3); })
        ->Arg(n)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("lame-0.4999" + tail).c_str(),
                                 [](benchmark::State& s) { lame<M2>(s, 0.4999); })
        ->Arg(n)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("spin" + tail).c_str(), spin<M2>)->Arg(n)->Unit(benchmark::kMillisecond);
    if (n <= 32)
      benchmark::RegisterBenchmark(("shaft" + tail).c_str(), shaft<M3>)
          ->Arg(n)
          ->Unit(benchmark::kMillisecond);
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_element<LegacyQuad>("legacy");
  register_element<Quad4>("quad4");
  register_element<Quad4BBar>("quad4bbar");
  register_element<Quad8>("quad8");
  register_element<Tri3>("tri3");
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

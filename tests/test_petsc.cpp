// Partitioned runs over MPI with the PETSc solver policy (issue 18), run by ctest under mpirun on 1, 2 and 3
// ranks (tests/mpi_main.cpp). Each problem is solved twice: whole, on this process, with the serial solvers
// (Eigen's LDL^T or LU), and cut into one part per rank with PetscSolver; the parts' answers, gathered,
// must equal the whole one to 1e-8 relative (to the largest value of the field), and the whole one meets
// its closed form as in the serial tests. Every value a CHECK reads is the same on every rank.
#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <petscksp.h>

#include <doctest/doctest.h>

#include "gapfe/assembly/partition.hpp"
#include "gapfe/solver/petsc.hpp"
#include "gapfe/solver/petsc_subdomain.hpp"

#include "contact_support.hpp"
#include "press_fit.hpp"

using namespace gapfe;
using namespace gapfe::test;

namespace {

constexpr double kE = 200e9;  // Pa

int rank() {
  int r = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}
int ranks() {
  int s = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &s);
  return s;
}

/// This rank's part of `whole` (one part per rank), keeping the ends of `pairs`.
template <class M>
Problem<M> part_of(const Problem<M>& whole, const std::vector<GapPair>& pairs = {}) {
  auto piece =
      mesh_part(whole.mesh, partition_cells(whole.mesh, ranks()), ranks(), rank(), pair_nodes(pairs));
  auto domain = std::make_shared<const PetscSubdomain>(std::move(piece.layout));
  Connectivity<2> links;
  for (const auto& p : pairs) links.push_back({p.node_a, p.node_b});
  return problem_part(whole, std::move(piece.mesh), std::move(domain), links);
}

/// A per-node table (rows: local nodes, 3 columns) of a part, as the whole mesh's table on every rank.
Eigen::MatrixX3d gathered(const Subdomain& domain, const Eigen::Matrix<double, Eigen::Dynamic, 3>& local) {
  const PartLayout& l                                             = domain.layout();
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> owned = local.topRows(l.owned_nodes);
  std::vector<double> table = domain.gather_rows(owned.data(), l.owned_nodes, 3, l.global_node.data(),
                                                 static_cast<int>(l.local_node.size()));
  table.resize(3 * l.local_node.size());
  MPI_Bcast(table.data(), static_cast<int>(table.size()), MPI_DOUBLE, 0, PETSC_COMM_WORLD);
  return Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      table.data(), static_cast<Eigen::Index>(l.local_node.size()), 3);
}

/// max |a - b| / max |b| (0 when both vanish).
double difference(const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b) {
  const double scale = b.cwiseAbs().maxCoeff();
  return scale > 0 ? (a - b).cwiseAbs().maxCoeff() / scale : (a - b).cwiseAbs().maxCoeff();
}

template <class Fe>
const Subdomain& domain_of(const Fe& fe) {
  return *fe.problem().subdomain;
}

/// The thick tube of the serial tests: a..b, bore pressure p, u_z = 0 at both ends (plane strain).
template <class M>
Problem<M> thick_tube(int nr, int nz, double p) {
  Problem<M> t;
  t.mesh      = rectangle_mesh<M::Element::kNodes>(0.1, 0.2, 0, 0.05, nr, nz);
  t.materials = {M::Material::constant(ElasticConstants::isotropic(kE, 0.3))};
  fix_plane(t.conditions, t.mesh, 0.0, 2, zero3);
  fix_plane(t.conditions, t.mesh, 0.05, 2, zero3);
  t.edge_loads = bore_pressure(t.mesh, nr, nz, p);
  return t;
}

}  // namespace

TEST_CASE("[petsc] partition: every cell in one part, balanced counts, every node owned once") {
  const auto mesh = rectangle_mesh<4>(0.1, 0.2, 0, 1.0, 10, 60);
  for (const int parts : {1, 2, 3, 7}) {
    const auto cells = partition_cells(mesh, parts);
    std::vector<int> count(static_cast<std::size_t>(parts), 0), owners(mesh.nodes.size(), 0);
    for (const int p : cells) ++count[static_cast<std::size_t>(p)];
    CHECK(*std::max_element(count.begin(), count.end()) - *std::min_element(count.begin(), count.end()) <= 1);
    std::size_t local_cells = 0;
    for (int k = 0; k < parts; ++k) {
      const auto piece = mesh_part(mesh, cells, parts, k);
      local_cells += piece.mesh.cells.size();
      for (int n = 0; n < piece.layout.owned_nodes; ++n)
        ++owners[static_cast<std::size_t>(piece.layout.global_node[static_cast<std::size_t>(n)])];
      for (std::size_t g = 0; g < piece.layout.ghost_part.size();
           ++g) {  // the owner's index is its local node
        const auto owner = mesh_part(mesh, cells, parts, piece.layout.ghost_part[g]);
        CHECK(owner.layout.global_node[static_cast<std::size_t>(piece.layout.ghost_index[g])] ==
              piece.layout.global_node[static_cast<std::size_t>(piece.layout.owned_nodes) + g]);
      }
    }
    CHECK(local_cells == mesh.cells.size());
    CHECK(std::all_of(owners.begin(), owners.end(), [](int o) { return o == 1; }));
  }
  // A long tube is cut across its length: 3 parts of a 10 x 60 grid meet on two grid lines of 11 nodes.
  const auto cells  = partition_cells(mesh, 3);
  const auto middle = mesh_part(mesh, cells, 3, 1);
  CHECK(middle.layout.ghost_part.size() <= 11);
  CHECK_THROWS_AS(partition_cells(mesh, 601), InputError);
}

TEST_CASE_TEMPLATE("[petsc] thick tube (Lame): the parts' answer is the whole one to 1e-8", Elem, LegacyQuad,
                   Quad4, Quad4BBar) {
  using Serial   = Model<Axisym2, Elem, Orthotropic>;
  using Parallel = Model<Axisym2, Elem, Orthotropic, PetscSolver<>>;
  const double p = 100;
  const int nr = 12, nz = 9;
  LinearStatic<Serial> whole(thick_tube<Serial>(nr, nz, p));
  whole.solve();
  LinearStatic<Parallel> part(part_of(thick_tube<Parallel>(nr, nz, p)));
  part.solve();
  const double du =
      difference(gathered(domain_of(part), part.solution().displacement), whole.solution().displacement);
  const double dr =
      difference(gathered(domain_of(part), part.solution().reaction), whole.solution().reaction);
  MESSAGE(ranks(), " rank(s): displacements differ by ", du, ", reactions by ", dr);
  CHECK(du < 1e-8);
  CHECK(dr < 1e-8);
  CHECK(part.solution().residual < 1e-10);
  CHECK(rel(whole.solution().displacement(0, 0), Lame{0.1, 0.2, p, kE, 0.3}.displacement(0.1)) < 5e-3);
}

TEST_CASE("[petsc] SAGA shaft twisted by a theta load: the parts' answer is the whole one to 1e-8") {
  using Serial    = Model<Axisym3, Quad4, Orthotropic>;
  using Parallel  = Model<Axisym3, Quad4, Orthotropic, PetscSolver<>>;
  const auto make = [](auto model) {
    using M = typename decltype(model)::type;
    Problem<M> s;
    s.mesh      = rectangle_mesh<4>(0.02, 0.05, 0, 0.4, 4, 24);
    s.materials = {M::Material::constant(ElasticConstants::isotropic(kE, 0.3))};
    fix_plane(s.conditions, s.mesh, 0.0, 7, zero3);
    for (int n = 0; n < s.mesh.node_count(); ++n)  // a torque at the top: theta forces on the top nodes
      if (std::abs(s.mesh.nodes[n](1) - 0.4) < 1e-12) s.conditions.push_back({n, 0, {0, 1e3, 5e3}});
    return s;
  };
  LinearStatic<Serial> whole(make(std::type_identity<Serial>{}));
  whole.solve();
  LinearStatic<Parallel> part(part_of(make(std::type_identity<Parallel>{})));
  part.solve();
  const double du =
      difference(gathered(domain_of(part), part.solution().displacement), whole.solution().displacement);
  const double dr =
      difference(gathered(domain_of(part), part.solution().reaction), whole.solution().reaction);
  MESSAGE(ranks(), " rank(s): displacements differ by ", du, ", reactions by ", dr);
  CHECK(du < 1e-8);
  CHECK(dr < 1e-8);
  CHECK(whole.solution().displacement.col(2).cwiseAbs().maxCoeff() > 0);
}

TEST_CASE_TEMPLATE("[petsc] two tubes across a gap: the parts close the same pairs at the same loads (1e-8)",
                   Policy, Saac, ActiveSet, AugmentedLagrangian) {
  using Serial   = Model<Axisym2, Quad4, Isotropic>;
  using Parallel = Model<Axisym2, Quad4, Isotropic, PetscSolver<>>;
  TwoTubes t;
  t.n_inner = 12, t.n_outer = 12, t.nz = 4;
  const double p_max = 100e6;
  ContactOptions options;
  options.gap_materials = {1};
  std::vector<GapPair> pairs;
  ContactStatic<Serial, Policy> whole(t.problem<Serial>(pairs), pairs, options);
  std::vector<GapPair> whole_pairs;
  auto parallel_whole = t.problem<Parallel>(whole_pairs);
  auto part_problem   = part_of(parallel_whole, whole_pairs);
  auto local_pairs    = part_pairs(part_problem.subdomain->layout(), whole_pairs);
  ContactStatic<Parallel, Policy> part(std::move(part_problem), local_pairs, options);
  // Loads in the whole mesh's numbering, each part keeps its own.
  const auto serial_loads = [&](Problem<Serial>& p, double f) { t.set_pressure(p, f * p_max); };
  const auto part_loads   = [&](Problem<Parallel>& p, double f) {
    Problem<Parallel> w;
    t.set_pressure(w, f * p_max);
    set_part_loads(p, parallel_whole.mesh.nodes, parallel_whole.conditions, w.edge_loads);
  };
  for (int k = 1; k <= 4; ++k) {
    whole.advance(k / 4.0, serial_loads);
    part.advance(k / 4.0, part_loads);
  }
  CHECK(whole.counters().solves == part.counters().solves);
  double force_diff = 0, force_max = 0;
  int closed = 0;
  for (std::size_t q = 0; q < pairs.size(); ++q) {
    CHECK(whole.states()[q].closed == part.states()[q].closed);
    closed += whole.states()[q].closed;
    force_diff =
        std::max(force_diff, std::abs(whole.states()[q].normal_force - part.states()[q].normal_force));
    force_max = std::max(force_max, std::abs(whole.states()[q].normal_force));
  }
  const double du = difference(gathered(domain_of(part.fe()), part.fe().solution().displacement),
                               whole.fe().solution().displacement);
  MESSAGE(Policy::kName, ", ", ranks(), " rank(s): ", closed, " pairs closed, forces differ by ",
          force_diff / force_max, ", displacements by ", du);
  CHECK(closed == static_cast<int>(pairs.size()));
  CHECK(force_diff < 1e-8 * force_max);
  CHECK(du < 1e-8);
}

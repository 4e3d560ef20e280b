// Partitioned runs over MPI with the PETSc solver policy, run by ctest under mpirun on 1, 2 and 3
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

#include "gapfe/assembly/problem_part.hpp"
#include "gapfe/solver/eigen_lu.hpp"
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

/// The parts' displacements and reactions, gathered, against the whole run's: 1e-8 of each field.
template <class Part, class Whole>
void check_same_solution(const Part& part, const Whole& whole) {
  const double du =
      difference(gathered(domain_of(part), part.solution().displacement), whole.solution().displacement);
  const double dr =
      difference(gathered(domain_of(part), part.solution().reaction), whole.solution().reaction);
  MESSAGE(ranks(), " rank(s): displacements differ by ", du, ", reactions by ", dr);
  CHECK(du < 1e-8);
  CHECK(dr < 1e-8);
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
  check_same_solution(part, whole);
  CHECK(part.solution().residual < 1e-10);
  // PetscSolver on a whole problem solves it on this process alone (PETSC_COMM_SELF), whatever the launch.
  LinearStatic<Parallel> alone(thick_tube<Parallel>(nr, nz, p));
  alone.solve();
  CHECK(difference(alone.solution().displacement, whole.solution().displacement) < 1e-8);
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
  check_same_solution(part, whole);
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

namespace {

/// The plane-strain plastic tube of the serial tests (test_plasticity.cpp, docs/theory.md V6): Mises,
/// perfectly plastic, a..b graded towards the bore, four cells high; stresses in MPa.
template <class M>
Problem<M> plastic_tube(double pressure) {
  Problem<M> p;
  p.mesh      = rectangle_mesh<4>(0.1, 0.2, 0, 0.02, 24, 4, 1.03);
  p.materials = {{Orthotropic::constant(ElasticConstants::isotropic(200e3, 0.49)), HillYield::mises(400)}};
  for (int n = 0; n < p.mesh.node_count(); ++n) p.conditions.push_back({n, 2, {}});
  p.edge_loads = bore_pressure(p.mesh, 24, 4, pressure);
  return p;
}

}  // namespace

TEST_CASE_TEMPLATE(
    "[petsc] plastic tube to 0.95 of its limit load: the parts' Newton is the whole one (1e-8)", Integration,
    ReturnMapping, Tangent) {
  using Serial       = Model<Axisym2, Quad4BBar, Hill<Integration>>;
  using Parallel     = Model<Axisym2, Quad4BBar, Hill<Integration>, PetscSolver<>>;
  const double limit = 2 / std::sqrt(3.0) * 400 * std::log(2.0);  // (2 / sqrt 3) sigma_y ln(b / a) [MPa]
  NonlinearStatic<Serial> whole(plastic_tube<Serial>(0));
  const Problem<Parallel> all = plastic_tube<Parallel>(0);
  NonlinearStatic<Parallel> part(part_of(all));
  const int steps = 10;
  double worst    = 0;
  for (int k = 1; k <= steps; ++k) {
    const double pressure      = 0.95 * limit * k / steps;
    whole.problem().edge_loads = bore_pressure(whole.problem().mesh, 24, 4, pressure);
    set_part_loads(part.problem(), all.mesh.nodes, all.conditions, bore_pressure(all.mesh, 24, 4, pressure));
    whole.solve(), part.solve();
    whole.commit(), part.commit();
    CHECK(whole.report().iterations == part.report().iterations);
    CHECK(whole.report().plastic_points == part.report().plastic_points);
    worst = std::max(worst, difference(gathered(domain_of(part), part.solution().displacement),
                                       whole.solution().displacement));
  }
  MESSAGE(ranks(), " rank(s): ", whole.report().plastic_points, " plastic points, displacements differ by ",
          worst, " at most");
  CHECK(whole.report().plastic_points > 0);
  CHECK(worst < 1e-8);
}

namespace {

/// The press fit of the serial friction tests pushed out by 50 um per unit of load factor after its pressure
/// (t in [0, 1]), whole (Serial, this process) and cut into the ranks' parts (Parallel), side by side.
template <class Serial, class Parallel, ContactPolicy Policy, FrictionModel Friction>
struct PushOut {
  PressFit fit;
  std::vector<GapPair> pairs, whole_pairs;
  Problem<Parallel> all;  ///< the whole problem of the parts, whose loads set_part_loads hands out
  std::unique_ptr<ContactStatic<Serial, Policy, Friction>> whole;
  std::unique_ptr<ContactStatic<Parallel, Policy, Friction>> part;

  explicit PushOut(PressFit f) : fit(f), all(fit.problem<Parallel>(whole_pairs)) {
    ContactOptions options;
    options.gap_materials = {1};
    options.friction      = fit.mu;
    whole =
        std::make_unique<ContactStatic<Serial, Policy, Friction>>(fit.problem<Serial>(pairs), pairs, options);
    auto local       = part_of(all, whole_pairs);
    auto local_pairs = part_pairs(local.subdomain->layout(), whole_pairs);
    part =
        std::make_unique<ContactStatic<Parallel, Policy, Friction>>(std::move(local), local_pairs, options);
  }
  void advance(double t) {
    const auto push = [](double s) { return s <= 1 ? 0.0 : -5e-5 * (s - 1); };
    whole->advance(t, [&](Problem<Serial>& p, double s) { fit.set(p, std::min(s, 1.0), push(s)); });
    part->advance(t, [&](Problem<Parallel>& p, double s) {
      fit.set(all, std::min(s, 1.0), push(s));
      set_part_loads(p, all.mesh.nodes, all.conditions, all.edge_loads);
    });
  }
  /// The parts' reactions, gathered, against the whole run's.
  double reaction_difference(Eigen::MatrixX3d* gathered_reactions = nullptr) const {
    const Eigen::MatrixX3d r = gathered(domain_of(part->fe()), part->fe().solution().reaction);
    if (gathered_reactions) *gathered_reactions = r;
    return difference(r, whole->fe().solution().reaction);
  }
  /// Pairs slipping in the whole run, and pairs whose stick/slip state the parts share.
  std::pair<int, int> slipping_and_same() const {
    int slipping = 0, same = 0;
    for (std::size_t q = 0; q < pairs.size(); ++q) {
      same += whole->states()[q].slipping == part->states()[q].slipping;
      slipping += whole->states()[q].slipping;
    }
    return {slipping, same};
  }
};

}  // namespace

// The fit of the serial friction tests in its closed-form setting (every node driven, uniform sliding):
// the partitioned run must slide at mu p 2 pi b L (1%, as the serial test) with every pair's stick/slip state
// the serial run's. Its reactions are compared at 1e-3, not 1e-8: this fit's pair forces carry the condition
// number of its 1-micron gap, and two serial LUs already disagree there (Eigen's SparseLU against UMFPACK
// and SuperLU through PETSc: 1.3e-4 and 6.6e-5 relative; MUMPS 1.9e-4).
TEST_CASE("[petsc] press fit pushed out with Coulomb friction: MUMPS LU on the unsymmetric tangent") {
  PushOut<Model<Axisym2, Quad4, Isotropic, EigenLu>,
          Model<Axisym2, Quad4, Isotropic, PetscSolver<MatrixStorage::full>>, AugmentedLagrangian, Coulomb>
      run(PressFit{});
  double worst = 0, force = 0;
  for (int k = 0; k <= 4; ++k) {
    run.advance(1.0 + k / 4.0);
    Solution gathered_solution;
    worst = std::max(worst, run.reaction_difference(&gathered_solution.reaction));
    force = run.fit.push_force(gathered_solution);
  }
  const auto [slipping, same] = run.slipping_and_same();
  MESSAGE(ranks(), " rank(s): ", slipping, " of ", run.pairs.size(), " pairs slipping; push force ", force,
          " N against mu p 2 pi b L = ", run.fit.slip_force(),
          " N; reactions differ from the serial LU's by ", worst);
  CHECK(same == static_cast<int>(run.pairs.size()));
  CHECK(slipping == static_cast<int>(run.pairs.size()));
  CHECK(rel(std::abs(force), run.fit.slip_force()) < 0.01);
  CHECK(worst < 1e-3);
}

TEST_CASE("[petsc] the seed's extended slip model sums the stresses around each pair over the parts (1e-8)") {
  PressFit fit;
  fit.drive = PressFit::Drive::ends;
  PushOut<Model<Axisym2, Quad4, Isotropic>, Model<Axisym2, Quad4, Isotropic, PetscSolver<>>, Saac, Extended>
      run(fit);
  for (int k = 0; k <= 10; ++k) run.advance(1.0 + k / 10.0);
  const auto [slipping, same] = run.slipping_and_same();
  const double dr             = run.reaction_difference();
  MESSAGE(ranks(), " rank(s): ", slipping, " of ", run.pairs.size(), " pairs slipping; reactions differ by ",
          dr);
  CHECK(same == static_cast<int>(run.pairs.size()));
  CHECK(slipping > 0);
  CHECK(dr < 1e-8);
}

namespace {

/// PETSc options for the life of a scope (the options database is the process's).
struct PetscOptionScope {
  std::vector<std::string> names;
  PetscOptionScope(std::initializer_list<std::pair<const char*, const char*>> options) {
    for (const auto& [name, value] : options)
      PetscOptionsSetValue(nullptr, name, value), names.emplace_back(name);
  }
  ~PetscOptionScope() {
    for (const auto& n : names) PetscOptionsClearValue(nullptr, n.c_str());
  }
};

}  // namespace

TEST_CASE(
    "[petsc] CG with GAMG and the axisymmetric near-null space, chosen at run time from PETSc's options") {
  using Serial   = Model<Axisym2, Quad4, Orthotropic>;
  using Parallel = Model<Axisym2, Quad4, Orthotropic, PetscSolver<>>;
  const int nr = 40, nz = 60;
  LinearStatic<Serial> whole(thick_tube<Serial>(nr, nz, 100));
  whole.solve();
  const PetscOptionScope cg{{"-ksp_type", "cg"}, {"-pc_type", "gamg"}};
  LinearStatic<Parallel> part(part_of(thick_tube<Parallel>(nr, nz, 100)));
  part.solve();
  const double du =
      difference(gathered(domain_of(part), part.solution().displacement), whole.solution().displacement);
  MESSAGE(ranks(), " rank(s): CG + GAMG (rtol 1e-10), displacements differ from the direct solve by ", du);
  CHECK(du < 1e-7);
  CHECK(part.solution().residual < 1e-8);
}

TEST_CASE("[petsc] a missing constraint is refused on every rank, with the reason") {
  using Parallel              = Model<Axisym2, Quad4, Orthotropic, PetscSolver<>>;
  Problem<Parallel> free_tube = thick_tube<Parallel>(8, 6, 100);
  free_tube.conditions.clear();  // nothing holds the axial translation
  std::string message;
  try {
    LinearStatic<Parallel> part(part_of(free_tube));  // every rank checks the whole model (check_held)
    part.solve();
  } catch (const SolveError& e) {
    message = e.what();
  }
  MESSAGE(message);
  CHECK(message.find("singular") != std::string::npos);
  CHECK(message.find("nothing holds the body of node 1") != std::string::npos);
}

TEST_CASE("[petsc] a contact run analyzes the pattern once: MUMPS' symbolic factorization is reused") {
  using Parallel         = Model<Axisym2, Quad4, Isotropic, PetscSolver<>>;
  PetscLogEvent symbolic = 0, numeric = 0;
  PetscLogEventGetId("MatCholFctrSym", &symbolic);
  PetscLogEventGetId("MatCholFctrNum", &numeric);
  const auto count = [](PetscLogEvent e) {
    PetscEventPerfInfo info{};
    PetscLogEventGetPerfInfo(0, e, &info);
    return info.count;
  };
  const int symbolic_before = count(symbolic), numeric_before = count(numeric);
  TwoTubes t;
  t.n_inner = 12, t.n_outer = 12, t.nz = 4;
  ContactOptions options;
  options.gap_materials = {1};
  std::vector<GapPair> pairs;
  Problem<Parallel> all = t.problem<Parallel>(pairs);
  auto local            = part_of(all, pairs);
  auto local_pairs      = part_pairs(local.subdomain->layout(), pairs);
  ContactStatic<Parallel, ActiveSet> part(std::move(local), local_pairs, options);
  for (int k = 1; k <= 4; ++k)
    part.advance(k / 4.0, [&](Problem<Parallel>& p, double f) {
      Problem<Parallel> w;
      t.set_pressure(w, f * 100e6);
      set_part_loads(p, all.mesh.nodes, all.conditions, w.edge_loads);
    });
  const int symbolic_runs = count(symbolic) - symbolic_before, numeric_runs = count(numeric) - numeric_before;
  MESSAGE(part.counters().solves, " solves: ", symbolic_runs, " symbolic and ", numeric_runs,
          " numeric factorizations");
  CHECK(symbolic_runs == 1);
  CHECK(numeric_runs >= 2);
  CHECK(numeric_runs < part.counters().solves);
}

TEST_CASE("[petsc] an error on one part is every part's error, with its message (on_every_part)") {
  const auto mesh = rectangle_mesh<4>(0.1, 0.2, 0, 1.0, 4, 12);
  auto piece      = mesh_part(mesh, partition_cells(mesh, ranks()), ranks(), rank());
  const PetscSubdomain domain(std::move(piece.layout));
  std::string what;
  int kind = 0;  // 1 InputError, 2 SolveError
  try {
    on_every_part(&domain, [] {
      if (rank() == ranks() - 1) throw SolveError("return map failed on part " + std::to_string(rank()));
    });
  } catch (const InputError& e) {
    kind = 1, what = e.what();
  } catch (const SolveError& e) {
    kind = 2, what = e.what();
  }
  CHECK(kind == 2);
  CHECK(what == "return map failed on part " + std::to_string(ranks() - 1));
  CHECK_NOTHROW(on_every_part(&domain, [] {}));
  // A file only rank 0 writes, and memory one part runs out of: the same on every part.
  CHECK_THROWS_WITH_AS(on_every_part(&domain,
                                     [] {
                                       if (rank() == 0) throw FileError("cannot write out/step_0002.vtu");
                                     }),
                       "cannot write out/step_0002.vtu", FileError);
  CHECK_THROWS_AS(on_every_part(&domain,
                                [] {
                                  if (rank() == ranks() - 1) throw std::bad_alloc();
                                }),
                  std::bad_alloc);
  // Two parts fail differently: every part throws the lowest failing part's error.
  if (ranks() > 1)
    CHECK_THROWS_WITH_AS(on_every_part(&domain,
                                       [] {
                                         if (rank() == 1) throw InputError("card on part 1");
                                         if (rank() == ranks() - 1) throw FileError("file on the last part");
                                       }),
                         "card on part 1", InputError);
}

TEST_CASE(
    "[petsc] skip_unchanged: the same values keep the factorization; new values or a failed one do not") {
  // A chain of three springs on this process alone (PETSC_COMM_SELF), lower triangle: grounded at its first
  // node it is positive definite; without the ground it is singular (a rigid move), which MUMPS' null-pivot
  // detection refuses.
  const auto chain = [](double ground) {
    SpMat k(3, 3);
    k.insert(0, 0) = 1 + ground, k.insert(1, 0) = -1, k.insert(1, 1) = 2, k.insert(2, 1) = -1;
    k.insert(2, 2) = 1;
    k.makeCompressed();
    return k;
  };
  PetscSolver<> solver;
  const SpMat held = chain(1), free = chain(0);
  solver.analyze(held);
  PetscLogEvent numeric = 0;  // registered once PETSc's matrices are (analyze made the first here)
  PetscLogEventGetId("MatCholFctrNum", &numeric);
  const auto numeric_runs = [&] {
    PetscEventPerfInfo info{};
    PetscLogEventGetPerfInfo(0, numeric, &info);
    return info.count;
  };
  solver.skip_unchanged(true);
  const int before = numeric_runs();
  CHECK(solver.factorize(held));
  CHECK(numeric_runs() == before + 1);
  CHECK(solver.factorize(held));  // the same values: kept
  CHECK(numeric_runs() == before + 1);
  const VecX u = solver.solve(VecX::Ones(3));
  CHECK(u(0) == doctest::Approx(3.0).epsilon(1e-12));  // the ground carries all three unit loads
  CHECK(u(2) == doctest::Approx(6.0).epsilon(1e-12));
  CHECK_FALSE(solver.factorize(free));  // new values: factorized, and refused
  CHECK(solver.failure().find("singular") != std::string::npos);
  CHECK(numeric_runs() == before + 2);
  CHECK_FALSE(solver.factorize(free));  // a failed factorization is not kept: tried again, refused again
  CHECK(numeric_runs() == before + 3);
  CHECK(solver.factorize(held));  // back to the first values: factorized afresh
  CHECK(numeric_runs() == before + 4);
}

TEST_CASE("[petsc] a factorization MUMPS fails does not stop the next: its instance is set up afresh") {
  // Without null-pivot detection MUMPS refuses the singular chain with an error (INFOG(1) = -10) and then
  // skips every later factorization of the same instance; the solver must start it again.
  const auto chain = [](double ground) {  // as in the skip_unchanged test: singular without the ground
    SpMat k(3, 3);
    k.insert(0, 0) = 1 + ground, k.insert(1, 0) = -1, k.insert(1, 1) = 2, k.insert(2, 1) = -1;
    k.insert(2, 2) = 1;
    k.makeCompressed();
    return k;
  };
  const PetscOptionScope no_detection{{"-mat_mumps_icntl_24", "0"}};
  {
    PetscSolver<> solver;
    const SpMat held = chain(1), free = chain(0);
    solver.analyze(free);
    CHECK_FALSE(solver.factorize(free));
    MESSAGE(solver.failure());
    CHECK(solver.failure().find("INFOG(1) = -") != std::string::npos);
    REQUIRE(solver.factorize(held));
    const VecX u = solver.solve(VecX::Ones(3));
    CHECK(u(0) == doctest::Approx(3.0).epsilon(1e-12));
    CHECK(u(1) == doctest::Approx(5.0).epsilon(1e-12));
    CHECK(u(2) == doctest::Approx(6.0).epsilon(1e-12));
  }
}

TEST_CASE("[petsc] global_rows: a lower triangle's entries as whole rows in global numbers, columns sorted") {
  // Local equations 0..3 are global 2, 0, 3, 1; the lower triangle holds the diagonal and (1, 0), (3, 1),
  // (3, 2), each value its own, so that every entry of the rows names where it came from.
  SpMat k(4, 4);
  k.insert(0, 0) = 1, k.insert(1, 0) = 2, k.insert(1, 1) = 3, k.insert(3, 1) = 4, k.insert(2, 2) = 5;
  k.insert(3, 2) = 6, k.insert(3, 3) = 7;
  k.makeCompressed();
  const std::vector<std::int64_t> global{2, 0, 3, 1};
  Eigen::Matrix4d expected = Eigen::Matrix4d::Zero();  // the whole matrix in global numbers
  for (int j = 0; j < 4; ++j)
    for (SpMat::InnerIterator it(k, j); it; ++it)
      expected(global[it.row()], global[j]) = expected(global[j], global[it.row()]) = it.value();
  const auto rows = global_rows<MatrixStorage::lower, PetscInt>(k, global);
  REQUIRE(rows.rows() == 4);
  CHECK(rows.column.size() == 10);  // 4 diagonal entries, 3 off it twice
  Eigen::Matrix4d got = Eigen::Matrix4d::Zero();
  for (std::size_t r = 0; r < rows.rows(); ++r) {
    CHECK(rows.row[r] == static_cast<PetscInt>(r));  // in global order
    std::vector<double> values;
    rows.values(r, k.valuePtr(), values);
    for (std::size_t c = rows.start[r]; c < rows.start[r + 1]; ++c) {
      if (c > rows.start[r]) CHECK(rows.column[c - 1] < rows.column[c]);
      got(rows.row[r], rows.column[c]) += values[c - rows.start[r]];
    }
  }
  CHECK(got == expected);
  const auto full = global_rows<MatrixStorage::full, PetscInt>(k, global);  // every entry once
  CHECK(full.column.size() == static_cast<std::size_t>(k.nonZeros()));
}

#pragma once
// A run's report: what it did and how far to trust it, in the log and, where a figure passes its limit, as
// a warning on the error stream (docs/checks.md lists them). Reads the RunResult; writes only to the
// streams it is given.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "gapfe/app/plan.hpp"
#include "gapfe/app/run_result.hpp"
#include "gapfe/driver/newton_options.hpp"
#include "gapfe/output/run_folder.hpp"

namespace gapfe::app {

/// Above this Poisson's ratio a run warns that element = quad4, or a mesh's triangles, lock (warn_locking),
/// and `--accuracy` keeps the order of a mesh with 3-corner cells (app/accuracy_order.hpp).
inline constexpr double kLockingPoisson = 0.49;

/// Above this relative residual |K u - f| / |f| of a linear solve a run warns of ill-conditioning. A
/// well-posed model solves to about 1e-14 (machine epsilon times a modest condition number).
/// The example two-tube deck under the active-set penalty reaches 4e-10 at the default 100 x the adjacent
/// stiffness, 5e-6 at 1e8, 4e-4 at 1e10 and 4e-3 at 1e11; tests/test_contact.cpp's penalty sweep keeps its
/// answers to the discretization error up to 1e9 and loses them beyond, which this threshold marks.
inline constexpr double kResidualWarning = 1e-4;

/// Above this Balance::relative() of an accepted increment a run warns that the run is out of global
/// equilibrium (docs/checks.md). Round-off gives 1e-16 (the thick tube) to 6e-11 (the SAAC3X tube) on the
/// examples.
inline constexpr double kBalanceWarning = 1e-8;

/// The largest Poisson's ratio of any material table row, and its material's deck number.
inline std::pair<int, double> largest_poisson(const ModelDescription& d) {
  std::pair<int, double> worst{0, -1.0};
  for (const MaterialInput& m : d.materials)
    for (const ElasticConstants& c : m.table.rows)
      if (const double nu = std::max({c.nu_NS, c.nu_NT, c.nu_ST}); nu > worst.second) worst = {m.id, nu};
  return worst;
}

/// The warning of a plan on the plain bilinear quad (element = quad4), or on a mesh with triangles, with a
/// nearly incompressible material (any material: which cells carry it is not asked): the bilinear quad locks
/// (its volumetric strain is enforced at every Gauss point), so its displacements come out too small. Every
/// element's triangles are plain and lock too (Tri3 beside quad4bbar and legacy: the atlas' centroid stresses
/// 32% to 130% off at nu = 0.4999; quad8's Tri6: measured on the Lame tube, the bore's stresses 1.26 times
/// the pressure off at 32 cells through the wall, the L2 error of u_r 100 times nu = 0.3's), while quad8's
/// and quad4bbar's quadrilaterals and the legacy quad do not; so the cure is a mesh of quadrilaterals. On the
/// error stream, so that --quiet keeps it.
inline void warn_locking(const Plan& p, const ModelDescription& d, const Scene& s, std::ostream& err) {
  const bool quad4            = p.key.element == ElementChoice::quad4;
  const std::size_t triangles = s.mesh.triangles.size();
  if (!quad4 && triangles == 0) return;
  if (const auto [material, nu] = largest_poisson(d); nu > kLockingPoisson) {
    err << "gapfe: warning: element = " << name_of(p.key.element) << " with Poisson's ratio " << nu
        << " (material " << material << "): ";
    if (quad4)
      err << "the bilinear quad locks near incompressibility and its displacements come out too small; use "
             "element = quad4bbar or legacy"
          << (triangles > 0 ? " on a mesh of quadrilaterals only" : "") << "\n";
    else
      err << "the mesh's " << triangles << (p.key.element == ElementChoice::quad8 ? " 6-node" : "")
          << " triangles lock near incompressibility"
          << (s.mesh.cells.empty() ? "" : " (its quadrilaterals do not)")
          << "; mesh with quadrilaterals only\n";
  }
}

/// Up to this many load steps the log lists a per-step figure (the relative residual, the friction cone)
/// for each step; beyond, their median and the largest with its step.
inline constexpr std::size_t kListedSteps = 50;

/// A friction force past this multiple of mu f_n is reported: the seed's models leave Coulomb's cone.
inline constexpr double kConeWarning = 1.1;

/// The warning of a run whose friction forces left Coulomb's cone |f_t| <= mu f_n (slip model `model`):
/// where it was worst, and the likely cause.
inline std::string cone_warning(const RunResult::ConeWorst& w, FrictionChoice model) {
  std::ostringstream m;
  m << "gapfe: warning: gap element " << w.element + 1 << ", pair " << w.pair + 1 << " (nodes "
    << w.node_a + 1 << " and " << w.node_b + 1 << ") carries a friction force " << std::setprecision(3)
    << w.ratio << std::setprecision(6) << " times mu f_n at load step " << w.step << " (inc " << w.inc
    << "), outside Coulomb's cone |f_t| <= mu f_n: ";
  if (model == FrictionChoice::proportional)
    m << "slip = proportional (SAACFR) has no slip limit, mu only scales its tangential springs, so a pair's "
         "force grows with its slide";
  else if (!(w.normal_force > 0))
    m << "the pair carries its friction force in tension (the seed's model keeps a pair's force until it "
         "opens)";
  else if (w.slipping)
    m << "the pair slips but keeps the force it gained while stuck (the seed's slip does not return a pair "
         "to "
         "the cone)";
  else if (w.outline)
    m << "the pair was stuck for the step next to a free surface or an end of the fit, where the averaged "
         "stresses of the elements around it (the seed's stick check) carry little shear, so its force grew "
         "by the stick stiffness times its slide";
  else
    m << "the pair was stuck for the step: the seed's check takes stick or slip from the stresses before the "
         "step, so a step whose slide times the stick stiffness passes mu f_n overshoots (smaller load "
         "steps)";
  m << "; slip = coulomb (with contact = active-set or augmented-lagrangian) keeps every pair on the cone\n";
  return m.str();
}

/// One number per load step, after `what`: each, up to kListedSteps steps, else their median and the
/// largest with its step.
inline void log_per_step(std::ostream& log, const std::string& what, const std::vector<double>& per_step) {
  if (per_step.empty()) return;
  log << what << ":";
  if (per_step.size() <= kListedSteps) {
    for (std::size_t k = 0; k < per_step.size(); ++k)
      log << (k % 10 == 0 ? "\n   " : "") << " " << per_step[k];
    log << "\n";
    return;
  }
  std::vector<double> sorted = per_step;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                   sorted.end());
  const auto worst = std::max_element(per_step.begin(), per_step.end());
  log << " " << per_step.size() << " steps, median " << sorted[sorted.size() / 2] << ", largest " << *worst
      << " (step " << (worst - per_step.begin()) + 1 << ")\n";
}

/// Above this relative residual an accepted increment of the seed's one-solve plasticity (plasticity =
/// tangent, rate-dependent or not) is warned of. Measured on thick tubes against return-mapping: the
/// SAAC3 tube of docs/checks.md at 20 and 200 steps reached 0.19 and 0.15 with bore displacements 3 and 20
/// times the converged one (0.0027 at 2000 steps: 3% off); the rate-independent tube at 0.97 of its limit
/// 0.036 in 20 steps (6.6% low) and 0.0042 in 200 (0.3% low).
inline constexpr double kSeedResidualWarning = 1e-2;

/// The warning of a run of the seed's one-solve plasticity whose out-of-balance passed kSeedResidualWarning;
/// whether it was given.
inline bool warn_seed_residual(std::ostream& err, const RunResult& times) {
  const auto& r    = times.step_residual;
  const auto worst = std::max_element(r.begin(), r.end());
  if (worst == r.end() || !(*worst > kSeedResidualWarning)) return false;
  err << "gapfe: warning: load step " << (worst - r.begin()) + 1 << " was accepted with a relative residual "
      << *worst << " (above " << kSeedResidualWarning
      << "): plasticity = tangent (the seed's one solve per increment) does not iterate, and out-of-balances "
         "this large have put its answers off by 7% to 20 times (docs/plasticity.md); plasticity = "
         "return-mapping (the default) iterates every increment to newton_tolerance\n";
  return true;
}

/// A rate-dependent run under return-mapping: the largest estimated time error of an accepted increment in
/// the log (DrysdaleZak::time_error, docs/plasticity.md "Time steps"), and a warning when it stayed above
/// time_tolerance (a step cut to its smallest pieces, 1/1024, and still above it).
inline void report_time_error(std::ostream& log, std::ostream& err, const RunResult& times,
                              const ModelDescription& d) {
  const double tol = d.options.time_tolerance;
  log << "time steps: largest estimated time error of an increment " << times.time_error
      << (tol > 0 ? " (time_tolerance " + detail::number_text(tol) + ")"
                  : std::string(" (time_tolerance 0: off)"))
      << "\n";
  if (tol > 0 && times.time_error > tol)
    err << "gapfe: warning: an increment kept an estimated time error " << times.time_error
        << " (above time_tolerance " << tol
        << "): load steps cut to 1/1024 did not meet it; more load steps, or a larger time_tolerance to "
           "accept it (docs/plasticity.md)\n";
}

/// The run's global balance (docs/checks.md) in the log, and the warning past its limit: kBalanceWarning, or
/// for runs that iterate (plasticity, contact) at least the residual Newton accepts, newton_tolerance times
/// NewtonOptions::stall_factor (100: a stalled increment). The seed's one-solve plasticity leaves an
/// out-of-balance by design: when its residual was warned of (`seed_warned`), that warning says it.
inline void report_balance(std::ostream& log, std::ostream& err, const RunResult& times,
                           const ModelDescription& d, bool torque, bool gaps, bool plastic,
                           bool seed_warned) {
  log_per_step(log,
               "global balance per load step (the loads against the reactions along the axis and about it)",
               times.step_balance);
  const Balance& b = times.last_balance;
  log << "global balance at the end: axial force of the loads " << b.applied_axial << ", of the reactions "
      << b.reaction_axial;
  if (torque) {
    log << "; torque of the loads " << b.applied_torque << ", of the reactions " << b.reaction_torque;
    if (gaps) log << ", of the gap pairs (theta forces at two radii) " << b.gap_torque;
  }
  log << "\n";
  const double limit =
      plastic || gaps ? std::max(kBalanceWarning, NewtonOptions{}.stall_factor * d.options.newton_tolerance)
                      : kBalanceWarning;
  if (seed_warned || times.balance <= limit) return;
  err << "gapfe: warning: load step " << times.balance_step << " is out of global equilibrium: the applied "
      << "loads and the reactions differ by " << times.balance << " of the load (above " << limit << ")"
      << (plastic && d.options.plasticity == PlasticityChoice::tangent
              ? ": plasticity = tangent (the seed's one solve per increment) leaves an out-of-balance; "
                "plasticity = return-mapping iterates it away\n"
              : ": the solve did not reach equilibrium (see the residual above), so its results may be "
                "inaccurate\n");
}

/// The recovery estimate of the discretization error (post/error_estimate.hpp; docs/accuracy.md) in the log:
/// per load step and at the end, with the element that holds the largest share.
inline void report_error_estimate(std::ostream& log, const ModelDescription& d, const RunResult& r) {
  if (!d.options.error_estimate) {
    log << "error estimate: none (error_estimate = none)\n";
    return;
  }
  log_per_step(log,
               "error estimate per load step (the relative energy-norm error of the recovered stresses, the "
               "largest of its increments)",
               r.step_error);
  if (r.step_error.empty()) return;
  if (r.error_stress_free) {
    log << "error estimate at the end: none, the stresses are round-off (a body moved or expanded freely)\n";
    return;
  }
  if (!std::isfinite(r.error)) {
    log << "error estimate at the end: not finite (a material's stiffness singular?)\n";
    return;
  }
  log << "error estimate at the end: " << 100 * r.error << "% in the energy norm";
  if (r.error_element >= 0)
    log << ", the largest share in element " << r.error_element + 1 << " at r = " << r.error_element_at(0)
        << ", z = " << r.error_element_at(1) << " (the VTU cell array error_estimate)";
  log << "; it measures the mesh, not the load steps or a gap's penalty (docs/accuracy.md)\n";
}

/// How far the run is from this machine's limits (bench/limits.py sets them beside dgemm's rate and a plain
/// write's): the factorization's flops and rate, when the solver counts them, and the bytes of the files in
/// the run's folder with the time spent writing them.
inline void report_throughput(std::ostream& log, const RunResult& r, const std::string& dir, bool writes) {
  if (const FactorStatistics& f = r.factor; f.flops > 0 && r.factorizations > 0) {
    const double flops = f.flops * r.factorizations;
    log << "factorization: " << flops << " flops in " << r.factorize << " s";
    if (r.factorize > 0) log << " (" << flops / r.factorize / 1e9 << " GFLOP/s)";
    log << "; " << r.factorizations << " numeric factorization(s), the factor's " << f.entries << " entries ("
        << f.stored << " stored with the supernodes' zeros: " << f.stored * sizeof(double) / 1e6 << " MB)";
    if (f.split)
      log << "; split in two halves (a thread each with --threads 2 or more) and a separator of "
          << f.separator << " equations";
    log << "\n";
  }
  if (!writes) return;
  std::uintmax_t bytes = 0;  // the run's own files (RunFolder::run_file), not a deck or mesh beside them
  std::error_code failed;  // a file that vanishes while counted is left out, never an error of a finished run
  for (std::filesystem::directory_iterator entry(dir, failed), end; !failed && entry != end;
       entry.increment(failed))
    if (RunFolder::run_file(entry->path().filename().string()) && entry->is_regular_file(failed))
      if (const std::uintmax_t size = entry->file_size(failed); !failed) bytes += size;
  // The writers' own seconds: with two threads or more an increment's files are written while the next
  // increment computes (RunFiles::write), and the time line's `write` is only what the run waited for them.
  const double seconds = r.files_seconds > 0 ? r.files_seconds : r.write;
  log << "files: " << bytes << " bytes in " << seconds << " s";
  if (seconds > 0) log << " (" << static_cast<double>(bytes) / seconds / 1e6 << " MB/s)";
  if (r.files_beside) log << ", each increment's beside the next one's work";
  log << "\n";
}

/// The run's figures after it ends: residuals per step, equilibrium, global balance, the plastic and contact
/// work, the friction cone and the rate-dependent increments in the log; the warnings their limits call for.
inline void report_run(std::ostream& log, std::ostream& err, const Plan& p, const ModelDescription& d,
                       const RunResult& r) {
  const bool plastic = p.plastic;
  // Each load step's worst relative residual: a step the solver could not hold to round-off shows where.
  log_per_step(log,
               std::string("residual per load step (") +
                   (plastic ? "Newton's |R| / (|F_int| or the loads)" : "|K u - f| / |f|") +
                   ", the largest of its increments)",
               r.step_residual);
  if (!plastic) {
    log << "equilibrium: largest relative residual |K u - f| / |f| " << r.equilibrium << " (load step "
        << r.equilibrium_step << ")\n";
    if (r.equilibrium > kResidualWarning)
      err << "gapfe: warning: load step " << r.equilibrium_step << " was solved to a relative residual "
          << r.equilibrium << " (above " << kResidualWarning
          << "): the stiffness is ill-conditioned (a large gap_penalty? a nearly incompressible material? a "
             "body held by little more than its gaps?), so its results may be inaccurate\n";
  }
  const bool seed = plastic && p.key.integration == PlasticityChoice::tangent;
  report_balance(log, err, r, d, p.key.kinematics == VariantChoice::saga, p.gaps, plastic,
                 seed && warn_seed_residual(err, r));
  report_error_estimate(log, d, r);
  if (plastic && !p.gaps)
    log << "plasticity: " << name_of(d.options.plasticity) << "; " << r.increments << " increments ("
        << r.cut_steps << " from cut steps), " << r.newton_iterations << " linear solves ("
        << r.factorizations << " factorizations; " << r.tangents << " tangents in " << r.element_passes
        << " element passes); worst residual " << r.worst_residual << ", largest drift off the yield surface "
        << r.drift << "; " << r.plastic_points << " plastic points at the end\n";
  if (plastic && d.rate_dependent() && !seed) report_time_error(log, err, r, d);
  if (plastic && !p.gaps && r.stalled > 0)
    err << "gapfe: warning: " << r.stalled << " increment(s) stopped where the residual stopped falling, "
        << "at most 100 x newton_tolerance (" << d.options.newton_tolerance  // NewtonOptions::stall_factor
        << "; worst " << r.worst_residual
        << "): the round-off of a nearly singular tangent (loads near a collapse load? very small "
           "hardening?); accepted\n";
  if (p.gaps)
    log << "contact: " << r.increments << " increments ("
        << (d.options.events == EventChoice::step_end
                ? "statuses settled at step ends: " + std::to_string(r.contact.status_rounds) + " re-solves"
                : std::to_string(r.contact.splits) + " split points" +
                      (r.contact.status_rounds > 0 ? ", " + std::to_string(r.contact.status_rounds) +
                                                         " re-solves after pulling pairs opened"
                                                   : std::string()))
        << (r.contact.cuts > 0 ? ", " + std::to_string(r.contact.cuts) + " intervals halved" : "") << "), "
        << r.contact.solves << " linear solves, " << r.contact.factorizations << " factorizations, "
        << r.contact.multiplier_updates << " multiplier updates; penalty " << r.penalty << " x adjacent; "
        << r.closed << " of " << r.pairs << " pairs closed at the end"
        << (p.key.friction == FrictionChoice::coulomb
                ? "; friction: " + std::to_string(r.contact.friction_iterations) + " Newton re-solves, " +
                      std::to_string(r.contact.friction_stalls) + " stalled below 1e-4"
                : std::string())
        << "\n";
  if (p.key.friction != FrictionChoice::none) {
    log_per_step(
        log,
        "friction cone per load step (the largest |f_t| / (mu f_n) of a closed pair; at most 1 under "
        "Coulomb)",
        r.step_cone);
    if (r.cone.ratio > kConeWarning) err << cone_warning(r.cone, p.key.friction);
  }
  if (!r.relaxation.empty()) {
    log << "rate-dependent increments (t = inc x delta t of card 0):\n";
    for (const auto& line : r.relaxation) log << line << "\n";
  }
}

}  // namespace gapfe::app

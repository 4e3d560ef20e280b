#pragma once
// A plan in words: what the model is and what the run will do (the head of the log, and all `gapfe info`
// prints). The figures come from the model and the plan (app/plan.hpp); nothing is decided here.
#include <ostream>
#include <string>

#include "gapfe/app/plan.hpp"
#include "gapfe/core/text.hpp"
#include "gapfe/input/deck_cards.hpp"
#include "gapfe/input/scene.hpp"
#include "gapfe/solver/eigen_ldlt.hpp"
#ifdef GAPFE_HAS_PETSC
#include <petscsys.h>
#endif

namespace gapfe::app {

/// A scene's cells for the log: "40 quadrilaterals, 2 triangles", "8-node" and "6-node" when quadratic.
inline std::string cells_text(const Scene& s) {
  const bool q = s.is_quadratic();
  return std::to_string(s.mesh.cells.size()) + (q ? " 8-node" : "") + " quadrilaterals, " +
         std::to_string(s.mesh.triangles.size()) + (q ? " 6-node" : "") + " triangles";
}

/// The model read from a card deck: its title, format, mesh and cards.
inline void describe_deck(std::ostream& out, const Deck& d, const Scene& s) {
  const char* format = d.options.format == DeckFormat::elastic ? "elastic (SAAS/SAGA, no yield cards)"
                       : d.options.format == DeckFormat::saac3 ? "saac3 (rate card, yield cards)"
                                                               : "saac (yield cards)";
  out << "deck: " << detail::visible_text(d.title) << "\n"
      << "  format " << format << "; element " << name_of(d.options.element) << "; " << d.materials.size()
      << " material(s)\n"
      << "  mesh " << d.mesh.max_i << " x " << d.mesh.max_j << " index grid: " << s.grid.node_count()
      << " nodes, " << cells_text(s) << "\n"
      << "  " << d.boundary.size() << " boundary condition card(s), " << d.blocks.size()
      << " material block(s), " << d.steps() << " load step(s)";
  if (d.has_temperature()) out << ", temperature field";
  if (d.program.inertia) out << ", inertia loads";
  out << "\n";
}

/// The model read from a scene file: its title, mesh (the generator's or a Gmsh file) and loads.
inline void describe_scene(std::ostream& out, const SceneModel& m) {
  const ModelDescription& d = m.description;
  const Scene& s            = m.scene;
  const auto edge_cards     = [&](std::vector<EdgeCard> LoadBlock::*kind) {
    return d.program.blocks.empty() ? std::size_t{0} : (d.program.blocks.front().*kind).size();
  };
  out << "scene: " << detail::visible_text(d.title) << "\n"
      << "  element " << name_of(d.options.element) << "; " << d.materials.size() << " material(s)"
      << (d.rate ? "; rate card (saac3)" : "") << "\n"
      << "  mesh "
      << (m.mesh_file.empty() ? "of the I-J generator (" + std::to_string(s.grid.max_i) + " x " +
                                    std::to_string(s.grid.max_j) + ")"
                              : m.mesh_file)
      << ": " << s.grid.node_count() << " nodes, " << cells_text(s) << "\n"
      << "  " << s.conditions.size() << " node condition(s), " << edge_cards(&LoadBlock::pressure)
      << " pressure, " << edge_cards(&LoadBlock::shear) << " shear and "
      << edge_cards(&LoadBlock::transverse_shear) << " transverse shear edge(s), " << d.steps()
      << " load step(s)";
  if (d.has_temperature()) out << ", temperature field";
  if (d.program.inertia) out << ", inertia loads";
  out << "\n";
}

/// How a law with history is integrated, in words (the log's "integration:" line).
inline std::string integration_text(const Plan& p, const ModelDescription& d) {
  const ModelOptions& o = d.options;
  if (p.key.integration == PlasticityChoice::tangent)
    return std::string(
               "tangent (the seed's one solve per increment, for reproducing legacy results: not iterated, "
               "the log reports its out-of-balance") +
           (d.rate_dependent() ? "; one increment per step, time_tolerance does not apply)" : ")");
  return "return-mapping (backward Euler, Newton to newton_tolerance " +
         detail::number_text(o.newton_tolerance) + " in every increment" +
         (d.rate_dependent() && o.time_tolerance > 0
              ? "; steps cut to time_tolerance " + detail::number_text(o.time_tolerance)
              : std::string()) +
         ")";
}

/// The plan: the variant and why, then what the gaps, the plasticity, the rate card and SAAC3X's test ask.
inline void explain_plan(std::ostream& log, const Plan& p, const ModelDescription& d, const Scene& s) {
  const ModelOptions& o = d.options;
  log << "variant: " << name_of(p.key.kinematics) << " (" << p.variant_reason << ")\n";
  if (p.gaps) {
    log << "  gaps: " << s.needs.gaps.front() << (s.needs.gaps.size() > 1 ? " and more" : "") << "; "
        << s.gaps.pairs.size() << " node pairs, " << s.gaps.soft.size()
        << " gap element(s) soft throughout (without a node pair: corners, IJDIR 0)\n"
        << "  contact: " << name_of(o.contact) << "; friction: "
        << (p.key.friction == FrictionChoice::none
                ? std::string("none")
                : std::string(name_of(p.key.friction)) + ", mu = " + detail::number_text(o.friction))
        << (o.gap_direction
                ? "; one gap direction for all (SAAC's LGAP = " + std::to_string(o.gap_direction) + ")"
                : "")
        << "\n";
  }
  if (p.plastic)
    log << "  plasticity: " << s.needs.plasticity.front() << "\n  integration: " << integration_text(p, d)
        << "\n";
  if (d.rate_dependent())
    log << "  rate: "
        << (p.plastic ? "rate-dependent " + std::string(name_of(o.plasticity))
                      : "ignored, no yield card (elastic)")
        << " (Drysdale-Zak, SAAC3: card 0 has b = " << detail::number_text(d.rate->rate_b)
        << " != 0; transition rate " << detail::number_text(d.rate->rate_plastic_strain)
        << ", each load step lasts " << detail::number_text(d.rate->time_step) << ")\n";
  if (const StrainRateTest& x = s.strain_rate_test; x.active())
    log << "  saac3x: constant strain rate " << detail::number_text(x.strain_rate)
        << " over L = " << detail::number_text(x.length) << ": u_z = rate L (t - delta t) on the "
        << x.top.size() << " nodes at z = " << detail::number_text(x.top_z)
        << " from step 2 on; u_z = u_theta = 0 on the " << x.bottom.size()
        << " nodes at z = " << detail::number_text(x.bottom_z)
        << (x.shear_step != 0 ? "; theta traction " + detail::number_text(x.shear_step) + " on the " +
                                    std::to_string(x.top_edges.size()) + " top edges, ramped over step 1"
                              : std::string())
        << " (card 0's STRRATE, STRSTEP)\n";
}

/// The solver in words (the log's "solver:" line): PETSc's from its options database, else the direct
/// solver the plan's choice picks (an LU for the unsymmetric Coulomb tangent).
inline std::string solver_text(const Plan& p) {
  if (p.solver == SolverChoice::petsc) {
#ifdef GAPFE_HAS_PETSC
    const auto option = [](const char* name, const std::string& otherwise) {
      char value[256] = {};
      PetscBool set   = PETSC_FALSE;
      PetscOptionsGetString(nullptr, nullptr, name, value, sizeof value, &set);
      return set ? std::string(value) : otherwise;
    };
    const std::string ksp = option("-ksp_type", "preonly"),
                      pc  = option("-pc_type", p.unsymmetric() ? "lu" : "cholesky");
    std::string text      = "PETSc -ksp_type " + ksp + " -pc_type " + pc;
    if (pc == "lu" || pc == "cholesky")
      text += " -pc_factor_mat_solver_type " + option("-pc_factor_mat_solver_type", "mumps");
    return text + (p.unsymmetric() ? " (the Coulomb slip tangent is unsymmetric)" : "");
#else
    return "PETSc";
#endif
  }
  if (p.unsymmetric())
    return std::string(p.solver == SolverChoice::eigen || !kHasUmfpack ? "Eigen SparseLU (COLAMD)"
                                                                       : "UMFPACK LU") +
           " (the Coulomb slip tangent is unsymmetric)";
  return p.solver == SolverChoice::eigen
             ? std::string(EigenLdlt::kName)
             : std::string("CHOLMOD supernodal LLT (nested dissection of the mesh)");
}

}  // namespace gapfe::app

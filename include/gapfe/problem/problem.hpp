#pragma once
// Problem<M>: everything an analysis of a compile-time Model needs, as plain data: the mesh, one law per
// material, the nodal conditions, the loads and the temperature field. Drivers own one (and let the
// caller change loads, temperatures and materials between solves); the deck layer builds one from a deck
// (run/scene_run.hpp). Node and material indices are 0-based.
#include <memory>
#include <vector>

#include "gapfe/core/subdomain.hpp"
#include "gapfe/core/types.hpp"
#include "gapfe/mesh/mesh.hpp"
#include "gapfe/problem/loads.hpp"

namespace gapfe {

template <class M>
struct Problem {
  Mesh<M::Element::kNodes> mesh;
  std::vector<typename M::Material> materials;  ///< indexed by CellTag::material
  std::vector<NodalCondition> conditions;       ///< seed Data 5, later entries win
  std::vector<EdgeLoad> edge_loads;             ///< seed Data 13-15
  InertiaLoad inertia;                          ///< seed Data 12
  VecX temperature;                             ///< nodal temperatures [deg]; empty: T_ref everywhere
  double reference_temperature = 0.0;           ///< TREF [deg]
  /// The part of the thermal strain eps_th(T, T_ref) in force [-]: the temperature change is a load, and
  /// a load program ramps it like the others (0 before the first load step, 1 from its end on in a deck),
  /// so that a step split at a gap's closure splits the thermal load too. The material properties stay
  /// those of the full temperature field (the seed's thermal load vector, scaled with the step).
  double thermal_fraction = 1.0;
  /// Set when this is one part of a problem partitioned over several processes (assembly/problem_part.hpp
  /// makes it): the mesh, conditions, loads and temperatures above are then the part's, in its local
  /// numbering, and the drivers sum what the parts share through it. Empty: the problem is whole.
  std::shared_ptr<const Subdomain> subdomain;
};

}  // namespace gapfe

#pragma once
// The cell loop every pass over a mesh shares (assembly, checks, recovery): a mesh holds cells of the
// model's element and, along boundary diagonals, 3-corner cells of its Degenerate companion (Tri3, Tri6);
// for_each_cell visits both groups with the element type as a tag, so one generic lambda serves both.
// Also the per-cell data the passes read: corner coordinates, mean temperature, the material resolved
// for the cell (cached: consecutive cells usually share material, frame and temperature).
#include <array>
#include <type_traits>
#include <vector>

#include "gapfe/assembly/element_kernel.hpp"
#include "gapfe/mesh/mesh.hpp"
#include "gapfe/problem/loads.hpp"

namespace gapfe {

/// Whether element type Elem has a 3-corner companion (Tri3 beside 4-corner cells, Tri6 beside Quad8).
template <class Elem>
inline constexpr bool kHasTriangles = !std::is_void_v<typename Elem::Degenerate>;

/// f(std::type_identity<E>{}, index within the group, cell nodes, cell tag) for the model's cells, then
/// for the triangles.
template <class Elem, class MeshT, class F>
void for_each_cell(const MeshT& m, F&& f) {
  for (std::size_t e = 0; e < m.cells.size(); ++e)
    f(std::type_identity<Elem>{}, e, m.cells[e], m.cell_tag(e));
  if constexpr (kHasTriangles<Elem>)
    for (std::size_t e = 0; e < m.triangles.size(); ++e)
      f(std::type_identity<typename Elem::Degenerate>{}, e, m.triangles[e], m.triangle_tag(e));
}

/// Corner coordinates (kNodes x 2: r, z) of a cell of element type E.
template <class E, class MeshT, std::size_t NPC>
Mat<E::kNodes, 2> cell_coords(const MeshT& m, const std::array<int, NPC>& cell) {
  Mat<E::kNodes, 2> x;
  for (int a = 0; a < E::kNodes; ++a) x.row(a) = m.nodes[cell[a]].transpose();
  return x;
}

/// Mean nodal temperature of a cell; the reference temperature when the problem has no field.
template <std::size_t NPC>
double cell_temperature(const VecX& temperature, double reference, const std::array<int, NPC>& cell) {
  if (temperature.size() == 0) return reference;
  double t = 0;
  for (int n : cell) t += temperature(n);
  return t / static_cast<double>(NPC);
}

/// Body force per unit volume of a material of `density` under the frame's motion (docs/theory.md 4.1).
inline BodyForce body_force(const InertiaLoad& inertia, double density) {
  return {density * inertia.angular_velocity * inertia.angular_velocity,
          -density * inertia.axial_acceleration, -density * inertia.angular_acceleration};
}

/// A law resolved for a cell (Law::localize: frame rotations and temperature tables), with the part
/// `thermal_fraction` of its thermal strain in force (Problem::thermal_fraction), kept while the next
/// cell has the same material, frame and temperature.
template <class Law>
class LocalLawCache {
 public:
  const typename Law::Local& get(const std::vector<Law>& materials, const CellTag& tag, double T,
                                 double reference, double thermal_fraction = 1.0) const {
    if (!valid_ || tag.material != tag_.material || !(tag.frame == tag_.frame) || T != T_ ||
        thermal_fraction != fraction_) {
      local_ = materials[tag.material].localize(tag.frame, T, reference);
      local_.thermal_strain *= thermal_fraction;
      tag_ = tag, T_ = T, fraction_ = thermal_fraction, valid_ = true;
    }
    return local_;
  }
  void reset() const { valid_ = false; }

 private:
  mutable typename Law::Local local_{};
  mutable CellTag tag_{};
  mutable double T_        = 0;
  mutable double fraction_ = 1;
  mutable bool valid_      = false;
};

}  // namespace gapfe

#pragma once
// A Gmsh mesh (input/gmsh_reader.hpp) as a finite-element Mesh<N> for a Problem: 4-node quadrangles with
// 3-node triangles beside them (Quad4, Quad4BBar, LegacyQuad; the triangles as constant-strain triangles),
// or an order-2 mesh: 8-node quadrangles with 6-node triangles beside them (Quad8 and Tri6). Nodes no cell
// uses (Gmsh's geometry points, a curve meshed alone) are dropped, since they would carry no stiffness;
// `node` maps Gmsh's node indices to the mesh's. Cells keep the file's order. A material index per physical
// surface sets each cell's tag (its material, default axes). The scene files (input/scene_mesh.hpp) build
// their meshes with it too.
//
//   const GmshMesh g  = read_gmsh(text);
//   auto fe           = gmsh_fe_mesh<8>(g, {{"steel", 0}});
//   problem.mesh      = fe.mesh;
//   for (int n : fe.group_nodes(g, 1, "bottom")) problem.conditions.push_back({n, 2, {}});
#include <algorithm>
#include <array>
#include <map>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/input/gmsh_reader.hpp"
#include "gapfe/mesh/mesh.hpp"

namespace gapfe {

template <int NodesPerCell>
struct GmshFeMesh {
  Mesh<NodesPerCell> mesh;
  std::vector<int> node;       ///< Gmsh node index -> mesh node, -1 where no cell uses it
  std::vector<int> gmsh_node;  ///< mesh node -> Gmsh node index

  /// The mesh nodes (sorted) of a physical curve (dim 1) or surface (dim 2) of `g`, the mesh this was made
  /// from; a curve's nodes that no cell uses are left out. InputError for a name `g` does not have.
  std::vector<int> group_nodes(const GmshMesh& g, int dim, const std::string& name) const {
    const int tag = g.physical(dim, name);
    std::vector<int> out;
    for (const GmshElement& e : dim == 1 ? g.edges : g.cells)
      if (e.in(tag))
        for (int k = 0; k < e.node_count; ++k)
          if (const int n = node[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(k)])]; n >= 0)
            out.push_back(n);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
};

/// An order-2 mesh's cells and line elements reduced to their corners, in place (types 9 -> 2, 16 -> 3,
/// 8 -> 1): returns each cell side's (corner, corner, middle node), Gmsh node indices, for the quadratic
/// cells the scene then makes (input/scene_quadratic.hpp); empty for an order-1 mesh. The middle nodes are
/// then used by no element, so gmsh_fe_mesh<4> leaves them out.
inline std::vector<std::array<int, 3>> take_mid_sides(GmshMesh& g) {
  std::vector<std::array<int, 3>> sides;
  for (GmshElement& c : g.cells) {
    if (c.type != 9 && c.type != 16) continue;
    const int corners = c.type == 9 ? 3 : 4;
    for (int k = 0; k < corners; ++k)
      sides.push_back({c.nodes[static_cast<std::size_t>(k)],
                       c.nodes[static_cast<std::size_t>((k + 1) % corners)],
                       c.nodes[static_cast<std::size_t>(corners + k)]});
    c.type = corners == 3 ? 2 : 3, c.node_count = corners;
  }
  for (GmshElement& e : g.edges)
    if (e.type == 8) e.type = 1, e.node_count = 2;
  return sides;
}

/// The cells of `g` as a Mesh<4> (quadrangles 4, triangles 3) or Mesh<8> (quadrangles 8, triangles 6); others
/// are an InputError naming the line. `material_of_surface` (physical surface name -> material index): when
/// given, every cell must be in one of its surfaces.
template <int NodesPerCell>
GmshFeMesh<NodesPerCell> gmsh_fe_mesh(const GmshMesh& g,
                                      const std::map<std::string, int>& material_of_surface = {}) {
  static_assert(NodesPerCell == 4 || NodesPerCell == 8, "Gmsh meshes give 4- or 8-node cells");
  constexpr int kQuad = NodesPerCell == 4 ? 3 : 16;  // Gmsh's element types of the cells taken
  constexpr int kTri  = NodesPerCell == 4 ? 2 : 9;
  GmshFeMesh<NodesPerCell> fe;
  fe.node.assign(g.nodes.size(), -1);
  for (const GmshElement& c : g.cells) {
    if (c.type != kQuad && c.type != kTri) {
      const char* names[] = {"a 3-node triangle", "a 6-node triangle", "a 4-node quadrangle",
                             "an 8-node quadrangle"};
      const char* what    = names[c.type == 2 ? 0 : c.type == 9 ? 1 : c.type == 3 ? 2 : 3];
      throw InputError("line " + std::to_string(c.line) + ": " + what + ", but this mesh takes " +
                       (NodesPerCell == 4
                            ? "4-node quadrangles and 3-node triangles (mesh with Mesh.ElementOrder = 1)"
                            : "8-node quadrangles and 6-node triangles (Mesh.ElementOrder = 2 with "
                              "Mesh.SecondOrderIncomplete = 1)"));
    }
    for (int k = 0; k < c.node_count; ++k)
      fe.node[static_cast<std::size_t>(c.nodes[static_cast<std::size_t>(k)])] = 0;
  }
  for (std::size_t n = 0; n < g.nodes.size(); ++n)
    if (fe.node[n] == 0) {
      fe.node[n] = static_cast<int>(fe.gmsh_node.size());
      fe.gmsh_node.push_back(static_cast<int>(n));
      fe.mesh.nodes.push_back(g.nodes[n]);
    }
  std::map<int, int> material_of_tag;  // physical surface tag -> material index
  for (const auto& [name, material] : material_of_surface) material_of_tag[g.physical(2, name)] = material;
  for (const GmshElement& c : g.cells) {
    CellTag tag;
    if (!material_of_tag.empty()) {
      // One material per cell: a cell in two surfaces that each have a material is ambiguous.
      int found = -1, found_tag = 0;
      for (const int group : c.physical)
        if (const auto it = material_of_tag.find(group); it != material_of_tag.end()) {
          if (found >= 0 && it->second != found)
            throw InputError("line " + std::to_string(c.line) + ": the cell is in the surfaces \"" +
                             g.physical_names.at({2, found_tag}) + "\" and \"" +
                             g.physical_names.at({2, group}) + "\", which have different materials");
          found = it->second, found_tag = group;
        }
      if (found < 0)
        throw InputError("line " + std::to_string(c.line) +
                         ": the cell is in no physical surface that has a material");
      tag.material = found;
    }
    const auto at = [&](int k) {
      return fe.node[static_cast<std::size_t>(c.nodes[static_cast<std::size_t>(k)])];
    };
    if (c.type == kTri) {
      std::array<int, Mesh<NodesPerCell>::kTriangleNodes> triangle{};
      for (std::size_t k = 0; k < triangle.size(); ++k) triangle[k] = at(static_cast<int>(k));
      fe.mesh.triangles.push_back(triangle);
      fe.mesh.triangle_tags.push_back(tag);
    } else {
      std::array<int, NodesPerCell> cell{};
      for (int k = 0; k < NodesPerCell; ++k) cell[static_cast<std::size_t>(k)] = at(k);
      fe.mesh.cells.push_back(cell);
      fe.mesh.cell_tags.push_back(tag);
    }
  }
  return fe;
}

}  // namespace gapfe

#pragma once
// The mesh of a scene file (input/scene_file.hpp) and its named groups, from either source a scene's [mesh]
// table can name: a Gmsh file, whose physical groups are the names (here), or the seed's I-J generator
// (input/scene_grid.hpp). Both fill the scene's grid cells and mesh alike (cells in their numbering order,
// quadrilaterals as Mesh::cells, triangles as Mesh::triangles), so what a scene puts on its groups
// (materials, conditions, loads, contact) looks them up by name without knowing which source made them.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gapfe/input/gmsh_mesh.hpp"
#include "gapfe/input/gmsh_reader.hpp"
#include "gapfe/input/gmsh_refine.hpp"
#include "gapfe/input/model_description.hpp"
#include "gapfe/input/scene.hpp"
#include "gapfe/input/scene_quadratic.hpp"
#include "gapfe/input/scene_table.hpp"
#include "gapfe/mesh/ij_grid.hpp"

namespace gapfe {

/// A scene's mesh refined for `gapfe run --estimate` (docs/accuracy.md "Error bars"): a grid at 1 / 2^times
/// of its spacing from the same segment cards (input/deck_refine.hpp), a Gmsh mesh split in four `times`
/// times (input/gmsh_refine.hpp). The layer between each contact's two faces stays one cell thick.
struct SceneRefinement {
  int times = 0;
  std::vector<std::array<std::string, 2>> faces;  ///< each [[contact]]'s faces
  std::vector<std::string> soft;                  ///< their soft surfaces
};

}  // namespace gapfe

namespace gapfe::detail {

/// An edge of a curve group as scene nodes (-1: a node no cell uses), and how messages name it.
struct SceneEdge {
  int m = -1, n = -1;
  std::string where;  ///< "the line element at line 40 of the mesh (curve \"bore\")"
};

/// A scene's mesh and its named groups. Group lookups throw InputError naming the group and what the
/// mesh has instead.
class SceneMesh {
 public:
  virtual ~SceneMesh() = default;
  /// The cells (indices into Scene::grid.cells) of a surface group.
  virtual std::vector<int> surface_cells(const std::string& name) const = 0;
  /// The edges of a curve group, each once.
  virtual std::vector<SceneEdge> curve_edges(const std::string& name) const = 0;
  /// The nodes (scene nodes, sorted) of a curve or surface group.
  virtual std::vector<int> nodes(const std::string& name) const = 0;
  /// How a message names a cell: "the cell at line 12 of the mesh (surface group \"steel\")".
  virtual std::string cell_where(int cell) const = 0;
  /// How messages label each scene node: its Gmsh tag, or its 1-based node number on a grid.
  const std::vector<long>& labels() const { return labels_; }
  /// Whether a node is one of the mesh's own, not one a refinement added (a ring force stays on those).
  bool own(int node) const { return own_.empty() || own_[static_cast<std::size_t>(node)]; }
  /// What a refinement did, for the log ("" when none).
  const std::string& refined() const { return refined_; }

 protected:
  std::vector<long> labels_;
  std::vector<char> own_;  ///< per node, after a refinement; empty: every node
  std::string refined_;
};

/// What every scene mesh sets once its grid cells and mesh are in place: the per-cell arrays sized (material
/// 0: none yet) and each mesh cell's element number.
inline void size_scene_cells(Scene& s) {
  const std::size_t cells = s.grid.cells.size();
  s.material_id.assign(cells, 0);
  s.ijdir.assign(cells, 0);
  s.mesh.cell_tags.resize(s.mesh.cells.size());
  s.mesh.triangle_tags.resize(s.mesh.triangles.size());
  s.element_of_cell.resize(s.mesh.cells.size());
  s.element_of_triangle.resize(s.mesh.triangles.size());
  for (std::size_t e = 0; e < cells; ++e)
    (s.grid.cells[e].corners == 4 ? s.element_of_cell : s.element_of_triangle)[s.grid.cells[e].group_index] =
        static_cast<int>(e);
}

/// A Gmsh mesh: its linear cells as the scene's (gmsh_fe_mesh<4>: file order, the element numbers; the nodes
/// some cell uses, in file order), physical groups as the names.
class GmshSceneMesh final : public SceneMesh {
 public:
  GmshSceneMesh(const std::string& file, std::string_view text, Scene& s, const SceneRefinement& refine = {})
      : file_(file) {
    std::size_t coarse = 0;
    try {
      gmsh_                                       = read_gmsh(text);
      const std::vector<std::array<int, 3>> sides = take_mid_sides(gmsh_);
      if (!sides.empty() && refine.times > 0)
        throw InputError(
            "the mesh is of order 2, and --estimate splits order-1 meshes (a split would lose its curved "
            "sides); give its order-1 mesh with element = quad8");
      if (refine.times > 0) {
        std::vector<std::string> faces;
        for (const auto& pair : refine.faces) faces.insert(faces.end(), pair.begin(), pair.end());
        GmshSplit split = split_gmsh(gmsh_, refine.times, refine.soft, faces);
        gmsh_ = std::move(split.mesh), coarse = split.coarse_nodes;
        refined_ = "every cell split in four" +
                   (refine.times > 1 ? ", " + std::to_string(refine.times) + " times over" : std::string()) +
                   "; " + std::to_string(split.arc_points) + " new points put on circular arcs";
      }
      fe_ = gmsh_fe_mesh<4>(gmsh_);
      for (const auto& [a, b, middle] : sides)  // an order-2 mesh: the quadratic cells' middle nodes
        if (const int m = fe_.node[static_cast<std::size_t>(a)], n = fe_.node[static_cast<std::size_t>(b)];
            m >= 0 && n >= 0)
          s.given_mid_sides[{std::min(m, n), std::max(m, n)}] = gmsh_.nodes[static_cast<std::size_t>(middle)];
    } catch (const InputError& e) {
      throw InputError(file_ + ": " + e.what());
    }
    if (coarse > 0)
      for (const int n : fe_.gmsh_node) own_.push_back(static_cast<std::size_t>(n) < coarse);
    IJGrid& g = s.grid;  // a Gmsh mesh has no grid indices: I = J = 0
    g.nodes   = fe_.mesh.nodes;
    g.node_ij.assign(g.nodes.size(), {0, 0});
    g.placed.assign(g.nodes.size(), 1);
    for (const int n : fe_.gmsh_node) labels_.push_back(gmsh_.node_tags[static_cast<std::size_t>(n)]);
    int quads = 0, triangles = 0;
    for (const GmshElement& c : gmsh_.cells) {  // the file's order, as gmsh_fe_mesh keeps it
      GridCell cell;
      cell.corners     = c.node_count;
      cell.group_index = c.node_count == 4 ? quads++ : triangles++;
      for (int k = 0; k < c.node_count; ++k) cell.node[k] = fe_.node[c.nodes[k]];
      g.cells.push_back(cell);
    }
    s.mesh = std::move(fe_.mesh);  // fe_ keeps the node map
    size_scene_cells(s);
  }

  /// Why a named group can be empty: Gmsh's Mesh.SaveAll = 1 writes MSH 2.2 elements without their
  /// physical tags (the names stay in $PhysicalNames).
  std::string untagged() const {
    for (const GmshElement& c : gmsh_.cells)
      if (!c.physical.empty()) return "";
    return ": no cell of the mesh has a physical tag (Gmsh's Mesh.SaveAll = 1 writes MSH 2.2 without them; "
           "save with Mesh.SaveAll = 0, or as MSH 4.1)";
  }
  std::vector<int> surface_cells(const std::string& name) const override {
    const int tag = gmsh_.physical(2, name);
    std::vector<int> out;
    for (std::size_t e = 0; e < gmsh_.cells.size(); ++e)
      if (gmsh_.cells[e].in(tag)) out.push_back(static_cast<int>(e));
    if (out.empty())
      throw InputError("the surface group \"" + name + "\" has no cells in the mesh" + untagged());
    return out;
  }
  std::vector<SceneEdge> curve_edges(const std::string& name) const override {
    const int tag = gmsh_.physical(1, name);
    std::vector<SceneEdge> out;
    for (const GmshElement& x : gmsh_.edges)
      if (x.in(tag))
        out.push_back(
            {fe_.node[x.nodes[0]], fe_.node[x.nodes[1]],
             "the line element at line " + std::to_string(x.line) + " of the mesh (curve \"" + name + "\")"});
    if (out.empty())
      throw InputError("the curve group \"" + name + "\" has no line elements in the mesh" + untagged());
    return out;
  }
  std::vector<int> nodes(const std::string& name) const override {
    const bool curve = has(1, name), surface = has(2, name);
    if (curve && surface)
      throw InputError("the name \"" + name + "\" is both a curve and a surface group; rename one");
    if (!curve && !surface) {
      std::string known;
      for (const auto& [key, n] : gmsh_.physical_names)
        if (key.first == 1 || key.first == 2) known += (known.empty() ? "" : ", ") + ("\"" + n + "\"");
      throw InputError("the mesh has no curve or surface group \"" + name + "\" (it has " +
                       (known.empty() ? "none" : known) + ")");
    }
    std::vector<int> out = fe_.group_nodes(gmsh_, curve ? 1 : 2, name);
    if (out.empty())
      throw InputError("the " + std::string(curve ? "curve" : "surface") + " group \"" + name +
                       "\" has no node that a cell uses");
    return out;
  }
  std::string cell_where(int cell) const override {
    const GmshElement& c = gmsh_.cells[static_cast<std::size_t>(cell)];
    std::string groups;
    for (const int tag : c.physical)
      if (const auto name = gmsh_.physical_names.find({2, tag}); name != gmsh_.physical_names.end())
        groups += (groups.empty() ? "" : ", ") + ("\"" + name->second + "\"");
    return "the cell at line " + std::to_string(c.line) + " of the mesh " +
           (groups.empty() ? std::string("(in no named surface group)") : "(surface group " + groups + ")");
  }

 private:
  bool has(int dim, const std::string& name) const {
    for (const auto& [key, n] : gmsh_.physical_names)
      if (key.first == dim && n == name) return true;
    return false;
  }

  std::string file_;
  GmshMesh gmsh_;
  GmshFeMesh<4> fe_;  ///< its node map (Gmsh node -> scene node, -1: no cell uses it); the mesh moved out
};

}  // namespace gapfe::detail

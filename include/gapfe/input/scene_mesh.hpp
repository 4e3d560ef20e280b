#pragma once
// The mesh of a scene file (input/scene_file.hpp) and its named groups, from either source a scene's [mesh]
// table can name: a Gmsh file, whose physical groups are the names, or the seed's I-J generator (line
// segment cards, Appendix A Data 3-4), whose groups are rectangles of grid indices. Both fill the scene's
// grid cells and mesh alike (cells in their numbering order, quadrilaterals as Mesh::cells, triangles as
// Mesh::triangles), so what a scene puts on its groups (materials, conditions, loads, contact) looks them
// up by name without knowing which source made them.
//
// A grid's group `NAME = {i = [I1, I2], j = [J1, J2]}` (or one index for either) reads as a deck's cards do
// (input/deck_scene.hpp): its nodes are the grid points in the rectangle (a BC card); as a surface, its cells
// are those whose lower-left corner (I, J) has I1 <= I < I2 and J1 <= J < J2 (a material block); a
// rectangle one index wide (I1 = I2 or J1 = J2) is a curve, whose edges are the cell sides between
// neighbouring grid points on it.
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
#include "gapfe/input/model_description.hpp"
#include "gapfe/input/scene.hpp"
#include "gapfe/input/scene_table.hpp"
#include "gapfe/mesh/ij_grid.hpp"

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

 protected:
  std::vector<long> labels_;
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
  GmshSceneMesh(const std::string& file, std::string_view text, Scene& s) : file_(file) {
    try {
      gmsh_ = read_gmsh(text);
      fe_   = gmsh_fe_mesh<4>(gmsh_);
    } catch (const InputError& e) {
      throw InputError(file_ + ": " + e.what());
    }
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

/// The seed's I-J generator: [mesh] grid = [MAXI, MAXJ], [[mesh.segments]] (one line segment card each:
/// type, points = [[I, J, r, z], ...], centre = [r, z] for "arc-centre"), [mesh.groups] NAME = {i, j}.
class GridSceneMesh final : public SceneMesh {
 public:
  GridSceneMesh(const SceneTable& mesh, Scene& s, const InputLimits& limits) {
    const auto size        = mesh.numbers("grid", 2, "[MAXI, MAXJ], the grid's largest I and J");
    const std::string most = std::to_string(limits.max_grid_points);
    if (!(size[0] >= 1 && size[1] >= 1 && size[0] == std::floor(size[0]) && size[1] == std::floor(size[1]) &&
          size[0] * size[1] <= static_cast<double>(limits.max_grid_points)))
      mesh.fail("grid", "[MAXI, MAXJ], whole numbers >= 1 with MAXI x MAXJ at most " + most + " (" +
                            detail::number_text(size[0]) + " x " + detail::number_text(size[1]) + " is not)");
    const int max_i = static_cast<int>(size[0]), max_j = static_cast<int>(size[1]);
    std::vector<Segment> segments;
    const std::vector<SceneTable> cards = mesh.tables("segments", {"type", "points", "centre"});
    if (cards.empty()) mesh.fail("segments", "[[mesh.segments]] tables, one per line segment card");
    for (const SceneTable& c : cards) segments.push_back(segment(c, max_i, max_j));
    IJGrid g;
    try {
      g = generate_ij_grid(max_i, max_j, segments);
    } catch (const InputError& e) {
      // The generator numbers segment cards from 1: name the table instead.
      std::string message   = e.what();
      const std::string tag = "line segment card ";
      if (const auto at = message.find(tag); at != std::string::npos) {
        const int k = std::atoi(message.c_str() + at + tag.size());
        if (k >= 1 && k <= static_cast<int>(cards.size()))
          throw InputError("scene: " + cards[static_cast<std::size_t>(k - 1)].where() + ": " + message);
      }
      throw InputError("scene: [mesh] (the I-J generator): " + message);
    }
    grid_scene_mesh(std::move(g), s);
    size_scene_cells(s);
    grid_ = &s.grid;
    for (int n = 0; n < s.grid.node_count(); ++n) labels_.push_back(n + 1);
    if (const toml::node* groups = mesh.get("groups")) {  // names of the user's choosing, each {i, j}
      const char* expected = "a table of groups NAME = {i = [I1, I2], j = [J1, J2]}";
      if (!groups->is_table()) mesh.fail("groups", expected);
      for (auto&& [key, node] : *groups->as_table()) {
        const std::string name(key.str());
        if (!node.is_table())
          throw InputError("scene: key 'mesh.groups." + name + "' (line " +
                           std::to_string(SceneTable::line(node)) +
                           "): expected a group {i = [I1, I2], j = [J1, J2]}");
        const SceneTable t(*node.as_table(), "mesh.groups." + name, {"i", "j"});
        groups_[name] = {range(t, "i", max_i, "MAXI"), range(t, "j", max_j, "MAXJ")};
      }
    }
  }

  std::vector<int> surface_cells(const std::string& name) const override {
    const Rectangle& r = group(name);
    if (r.i[0] == r.i[1] || r.j[0] == r.j[1])
      throw InputError("the group \"" + name + "\" is one grid line (" + r.text() +
                       "), a curve; a surface needs a range of both I and J");
    std::vector<int> out;
    for (std::size_t e = 0; e < grid_->cells.size(); ++e) {
      const GridCell& c = grid_->cells[e];
      if (c.i >= r.i[0] && c.i < r.i[1] && c.j >= r.j[0] && c.j < r.j[1]) out.push_back(static_cast<int>(e));
    }
    if (out.empty())
      throw InputError("the group \"" + name + "\" (" + r.text() + ") holds no cell of the grid");
    return out;
  }
  std::vector<SceneEdge> curve_edges(const std::string& name) const override {
    const Rectangle& r = group(name);
    if (r.i[0] != r.i[1] && r.j[0] != r.j[1])
      throw InputError(
          "the group \"" + name + "\" (" + r.text() +
          ") spans a range of both I and J, a surface; a curve is one grid line (one I or one J)");
    std::vector<SceneEdge> out;
    std::set<std::pair<int, int>> seen;
    const auto on = [&](int n) {
      const auto [i, j] = grid_->node_ij[static_cast<std::size_t>(n)];
      return i >= r.i[0] && i <= r.i[1] && j >= r.j[0] && j <= r.j[1];
    };
    for (const GridCell& c : grid_->cells)
      for (int k = 0; k < c.corners; ++k) {
        const int m = c.node[k], n = c.node[(k + 1) % c.corners];
        if (on(m) && on(n) && seen.insert({std::min(m, n), std::max(m, n)}).second)
          out.push_back({m, n, "the edge from " + ij(m) + " to " + ij(n) + " (group \"" + name + "\")"});
      }
    if (out.empty())
      throw InputError("the group \"" + name + "\" (" + r.text() + ") holds no cell side of the grid");
    return out;
  }
  std::vector<int> nodes(const std::string& name) const override {
    const Rectangle& r = group(name);
    std::vector<int> out;
    const auto [i1, i2, j1, j2] = grid_->box_cut(r.i[0], r.i[1], r.j[0], r.j[1]);
    for (int j = j1; j <= j2; ++j)
      for (int i = i1; i <= i2; ++i)
        if (const int n = grid_->node(i, j); n >= 0) out.push_back(n);
    if (out.empty()) throw InputError("the group \"" + name + "\" (" + r.text() + ") holds no grid point");
    std::sort(out.begin(), out.end());
    return out;
  }
  std::string cell_where(int cell) const override {
    const GridCell& c = grid_->cells[static_cast<std::size_t>(cell)];
    return "element " + std::to_string(cell + 1) + " " + ij_text(c.i, c.j);
  }

 private:
  struct Rectangle {
    std::array<int, 2> i{}, j{};  ///< first and last index
    std::string text() const {
      const auto one = [](const char* axis, const std::array<int, 2>& v) {
        return std::string(axis) + " = " + std::to_string(v[0]) +
               (v[0] == v[1] ? std::string() : "-" + std::to_string(v[1]));
      };
      return one("I", i) + ", " + one("J", j);
    }
  };

  const Rectangle& group(const std::string& name) const {
    if (const auto it = groups_.find(name); it != groups_.end()) return it->second;
    std::string known;
    for (const auto& [n, r] : groups_) known += (known.empty() ? "" : ", ") + ("\"" + n + "\"");
    throw InputError("the grid has no group \"" + name + "\" (its [mesh.groups] are " +
                     (known.empty() ? "none" : known) + ")");
  }
  std::string ij(int n) const {
    const auto [i, j] = grid_->node_ij[static_cast<std::size_t>(n)];
    return ij_text(i, j);
  }

  /// A group's `i` or `j`: one index or [first, last], within 1..most.
  static std::array<int, 2> range(const SceneTable& t, const char* key, int most, const char* limit) {
    const std::string expected =
        "one index or [first, last] within 1.." + std::string(limit) + " = " + std::to_string(most);
    const std::vector<double> v = t.numbers(key, 2, expected.c_str());  // one number: both
    for (const double x : v)
      if (!(x >= 1 && x <= most && x == std::floor(x))) t.fail(key, expected);
    if (v[0] > v[1]) t.fail(key, expected + ", first <= last");
    return {static_cast<int>(v[0]), static_cast<int>(v[1])};
  }

  /// One [[mesh.segments]] table as a line segment card.
  static Segment segment(const SceneTable& t, int max_i, int max_j) {
    static constexpr std::array<std::pair<const char*, SegmentType>, 7> kTypes{
        {{"point", SegmentType::point},
         {"line", SegmentType::line},
         {"internal-diagonal", SegmentType::internal_diagonal},
         {"arc", SegmentType::arc_three_points},
         {"arc-centre", SegmentType::arc_centre},
         {"min-diagonal", SegmentType::min_diagonal},
         {"max-diagonal", SegmentType::max_diagonal}}};
    const std::string type = t.text("type", std::string("line"));
    Segment seg;
    const auto found =
        std::find_if(kTypes.begin(), kTypes.end(), [&](const auto& k) { return type == k.first; });
    if (found == kTypes.end())
      t.fail("type",
             "\"point\", \"line\", \"internal-diagonal\", \"arc\" (through three points), \"arc-centre\", "
             "\"min-diagonal\" or \"max-diagonal\"");
    seg.type        = found->second;
    const int count = seg.type == SegmentType::point ? 1 : seg.type == SegmentType::arc_three_points ? 3 : 2;
    const std::string e  = std::to_string(count) + " point(s) [I, J, r, z] (a " + type + ")";
    const toml::node* p  = t.get("points");
    const toml::array* a = p ? p->as_array() : nullptr;
    if (!a) t.fail("points", e);
    if (a->size() != static_cast<std::size_t>(count)) t.fail("points", e);
    for (int k = 0; k < count; ++k) {
      const toml::array* q = a->get(static_cast<std::size_t>(k))->as_array();
      std::array<double, 4> v{};
      for (int c = 0; c < 4; ++c) {
        const auto x =
            q && q->size() == 4 ? SceneTable::as_number(*q->get(static_cast<std::size_t>(c))) : std::nullopt;
        if (!x || !std::isfinite(*x)) t.fail("points", e);
        v[static_cast<std::size_t>(c)] = *x;
      }
      if (!(v[0] >= 1 && v[0] <= max_i && v[0] == std::floor(v[0]) && v[1] >= 1 && v[1] <= max_j &&
            v[1] == std::floor(v[1])))
        t.fail("points", e + " with I within 1.." + std::to_string(max_i) + " and J within 1.." +
                             std::to_string(max_j) + " (point " + std::to_string(k + 1) + ")");
      seg.p[static_cast<std::size_t>(k)] = {static_cast<int>(v[0]), static_cast<int>(v[1]), Vec2(v[2], v[3])};
    }
    if (seg.type == SegmentType::arc_centre) {
      const auto c = t.numbers("centre", 2, "the arc's centre [r, z]");
      seg.p[2].x   = Vec2(c[0], c[1]);
    } else if (t.has("centre")) {
      t.fail("centre", "no centre: only an \"arc-centre\" segment has one");
    }
    return seg;
  }

  const IJGrid* grid_ = nullptr;
  std::map<std::string, Rectangle> groups_;
};

}  // namespace gapfe::detail

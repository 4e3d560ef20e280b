#pragma once
// Gmsh's MSH file format, ASCII, versions 4.1 and 2.2: nodes, the 2-D cells of a meridian
// section (x = r, y = z, z = 0) and the 1-D edges of its boundary curves, each with the physical group it
// belongs to, so that a scene can give materials by surface group and loads and conditions by curve group.
//
// What is read (Gmsh reference manual, section "MSH file format"):
//   $MeshFormat     version (4.1 or 2.2), file type (0: ASCII; binary files are refused), data size;
//   $PhysicalNames  dimension, tag and quoted name of each physical group (optional);
//   $Entities       4.1 only: the physical tags of every curve and surface entity;
//   $Nodes          4.1: blocks per entity (tags first, then coordinates; parametric coordinates skipped);
//                   2.2: one line per node;
//   $Elements       4.1: blocks per entity with their type; 2.2: one line per element, its first tag the
//                   physical group. Any other section is skipped.
// Element types kept: 2-node and 3-node lines (Gmsh types 1, 8), 3-node and 6-node triangles (2, 9), 4-node
// and 8-node quadrangles (3, 16); a 9-node quadrangle (10, Gmsh's order 2 by default) is kept as an 8-node
// one, its centre node dropped (gapfe's Quad8 is the serendipity cell); points (15) are skipped; any other
// type (a volume element, a cubic cell) is an error naming its type and line. Node orderings are Gmsh's,
// which are gapfe's too (corners counterclockwise, then the mid-sides 0-1, 1-2, ...: element/quad8.hpp).
//
// Physical groups: an element may belong to several (a surface in "steel" and in "all"). MSH 4.1 gives the
// groups of each entity; MSH 2.2 writes the element once per group it is in, and those copies (the same
// nodes, type and elementary entity, another group) are read as one element in every group. A repeated
// element otherwise (the same corner set again: in the same group, in another entity, or in a 4.1 file) is
// an error, so that no cell is assembled twice.
//
// Checks, each an InputError naming the file's line: node tags may have gaps and come in any order, but each
// once, and every element's nodes must exist, each once in the element; x = r >= 0 (to 1e-12 of the mesh
// size: a node a rounding error left of the axis is put on it); z = 0 (a meridian section is flat); cells
// with zero or negative area are refused after clockwise ones (negative signed area of the corners in (r, z))
// are turned counterclockwise, which gapfe's elements need (element to the left of each edge); every count
// and tag in its range (tags up to 2^31 - 1); numbers are never quoted, names are ("" is no name); two
// physical groups of one dimension may not share a name; a truncated file names the section it ends in.
//
// Units: whatever the file holds, read as the model's length unit (the library never converts).
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/types.hpp"
#include "gapfe/input/gmsh_words.hpp"

namespace gapfe {

/// A 2-D cell or a 1-D edge of a Gmsh mesh: its nodes as indices into GmshMesh::nodes (Gmsh's order),
/// its physical groups and its Gmsh element type.
struct GmshElement {
  int type = 0;  ///< Gmsh element type: 1, 8 (lines), 2, 9 (triangles), 3, 16 (quadrangles; 10 read as 16)
  int node_count = 0;          ///< 2, 3, 6, 4 or 8
  std::array<int, 8> nodes{};  ///< 0-based node indices, counterclockwise for cells
  std::vector<int> physical;   ///< the physical group tags it belongs to (none: empty)
  int line = 0;                ///< line of the file where it is defined (for later errors)

  bool in(int group) const { return std::find(physical.begin(), physical.end(), group) != physical.end(); }
};

struct GmshMesh {
  std::vector<Vec2> nodes;         ///< (r, z) [length]
  std::vector<long> node_tags;     ///< Gmsh's tag of each node, parallel to nodes
  std::vector<GmshElement> cells;  ///< triangles and quadrangles
  std::vector<GmshElement> edges;  ///< lines (boundary curves, interfaces)
  /// Physical group names by (dimension, tag): 1 for curves, 2 for surfaces.
  std::map<std::pair<int, int>, std::string> physical_names;
  int flipped    = 0;  ///< cells given clockwise and turned counterclockwise
  double version = 0;

  /// The tag of the physical group of dimension `dim` named `name`; InputError listing the names there are.
  int physical(int dim, const std::string& name) const {
    std::string known;
    for (const auto& [key, n] : physical_names) {
      if (key.first != dim) continue;
      if (n == name) return key.second;
      known += (known.empty() ? "" : ", ") + ("\"" + n + "\"");
    }
    throw InputError("the mesh has no " + std::string(dim == 1 ? "curve" : "surface") + " physical group \"" +
                     name + "\" (it has " + (known.empty() ? "none" : known) + ")");
  }
};

namespace detail {

/// One read of an MSH file: the mesh so far, the node index and what each section left for the next; a
/// method per section. read_gmsh is its one user.
class GmshReading {
 public:
  explicit GmshReading(std::string_view text) : text_(text), in_(text) {}

  GmshMesh read() {
    while (!in_.done()) {
      const std::string section(in_.word("a section"));
      if (section.empty() || section[0] != '$')
        in_.fail("expected a section ($MeshFormat, $Nodes, ...), found '" + section + "'");
      const std::string name = section.substr(1);
      in_.enter(section);
      if (name == "MeshFormat")
        format_section();
      else if (!has_format_)
        in_.fail("the file does not start with $MeshFormat: not an MSH file?");
      else if (name == "PhysicalNames")
        physical_names();
      else if (name == "Entities" && m_.version == 4.1)
        entities();
      else if (name == "Nodes")
        nodes_section();
      else if (name == "Elements")
        elements_section();
      else
        in_.skip_section(name);  // $Entities of 2.2 files, $NodeData, $Periodic, ...
    }
    if (!has_format_) throw InputError("empty file: not an MSH file");
    if (!has_nodes_ || m_.nodes.empty()) throw InputError("the file has no $Nodes section or no nodes");
    if (!has_elements_ || m_.cells.empty())
      throw InputError(
          "the file has no triangles or quadrangles (a 2-D mesh of the meridian section is needed)");
    // x = r >= 0: the axis is r = 0; a node a rounding error left of it is put on it.
    Vec2 lo = m_.nodes.front(), hi = lo;
    for (const Vec2& x : m_.nodes) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    const double size = std::max((hi - lo).maxCoeff(), 1e-300);
    for (std::size_t k = 0; k < m_.nodes.size(); ++k) {
      if (m_.nodes[k](0) >= 0) continue;
      if (m_.nodes[k](0) > -1e-12 * size) {
        m_.nodes[k](0) = 0;
        continue;
      }
      throw InputError("node " + std::to_string(m_.node_tags[k]) +
                       " has x = r = " + std::to_string(m_.nodes[k](0)) +
                       " < 0: an axisymmetric section lies at r >= 0 (x = r, y = z)");
    }
    return std::move(m_);
  }

 private:
  void format_section() {
    m_.version      = in_.real("the version");
    const int ascii = in_.count("the file type", 0, 1);
    in_.real("the data size");
    if (m_.version != 4.1 && m_.version != 2.2)
      in_.fail("MSH version " + std::to_string(m_.version) +
               ": gapfe reads 4.1 and 2.2 (Gmsh: -format msh41 or msh22)");
    if (ascii != 0) in_.fail("a binary MSH file: gapfe reads ASCII (Gmsh: -bin 0, or Mesh.Binary = 0)");
    in_.expect("$EndMeshFormat");
    has_format_ = true;
  }

  void physical_names() {
    const int n = in_.count("the number of names", 0, 1'000'000);
    std::map<std::pair<int, std::string>, int> tag_of_name;  // (a linear scan was quadratic in n)
    for (int k = 0; k < n; ++k) {
      const int dim             = in_.count("a physical group's dimension", 0, 3);
      const int tag             = in_.count("a physical group's tag", 1, 2'147'483'647L);
      const std::string group   = std::string(in_.name("a physical group's name"));
      const auto [named, fresh] = tag_of_name.try_emplace({dim, group}, tag);
      if (!fresh && named->second != tag)
        in_.fail("physical groups " + std::to_string(named->second) + " and " + std::to_string(tag) +
                 " of dimension " + std::to_string(dim) + " are both named \"" + group +
                 "\": a name picks one group");
      if (!m_.physical_names.emplace(std::make_pair(dim, tag), group).second)
        in_.fail("physical group " + std::to_string(tag) + " of dimension " + std::to_string(dim) +
                 " is named twice");
    }
    in_.expect("$EndPhysicalNames");
  }

  void entities() {
    long counts[4];
    for (long& c : counts) c = in_.count("an entity count", 0, 100'000'000);
    for (int dim = 0; dim < 4; ++dim)
      for (long k = 0; k < counts[dim]; ++k) {
        const int tag = in_.count("an entity tag", 0, 2'147'483'647L);
        for (int c = 0; c < (dim == 0 ? 3 : 6); ++c) in_.real("an entity's bounding box");
        const int n = in_.count("the number of physical tags", 0, 1'000'000);
        for (int p = 0; p < n; ++p)  // (a negative tag gives the group's orientation)
          entity_physical_[{dim, tag}].push_back(
              static_cast<int>(std::labs(in_.count("a physical tag", -2'147'483'647L, 2'147'483'647L))));
        if (dim > 0) {
          const int b = in_.count("the number of bounding entities", 0, 100'000'000);
          for (int q = 0; q < b; ++q) in_.integer("a bounding entity");
        }
      }
    in_.expect("$EndEntities");
  }

  void add_node(long tag, double x, double y, double z) {
    if (tag < 1) in_.fail("node tag " + std::to_string(tag) + ": Gmsh's tags start at 1");
    if (!index_.emplace(tag, static_cast<int>(m_.nodes.size())).second)
      in_.fail("node " + std::to_string(tag) + " is given twice");
    if (z != 0)
      in_.fail("node " + std::to_string(tag) + " has z = " + std::to_string(z) +
               ": a meridian section lies in the plane z = 0 (x = r, y = z)");
    m_.nodes.emplace_back(x, y);
    m_.node_tags.push_back(tag);
  }

  void nodes_section() {
    if (has_nodes_) in_.fail("a second $Nodes section");
    has_nodes_ = true;
    if (m_.version == 4.1) {
      const int blocks = in_.count("the number of node blocks", 0, 100'000'000);
      const int total  = in_.count("the number of nodes", 0, 1'000'000'000);
      in_.integer("the smallest node tag");
      in_.integer("the largest node tag");
      // Counts come from the file: reserve no more than its text can hold (a node takes 8 characters or
      // more), so a header that claims a billion nodes in a short file costs nothing before it is found
      // short.
      m_.nodes.reserve(std::min(static_cast<std::size_t>(total), text_.size() / 8));
      for (int b = 0; b < blocks; ++b) {
        in_.count("a block's entity dimension", 0, 3);
        in_.integer("a block's entity tag");
        const int parametric = in_.count("a block's parametric flag", 0, 1);
        const int n          = in_.count("a block's node count", 0, 1'000'000'000);
        std::vector<long> tags;
        tags.reserve(std::min(static_cast<std::size_t>(n), text_.size() / 2));
        for (int k = 0; k < n; ++k) tags.push_back(in_.integer("a node tag"));
        for (const long t : tags) {
          const double x = in_.real("x"), y = in_.real("y"), z = in_.real("z");
          if (parametric)
            in_.fail("parametric node coordinates: save the mesh without them (Mesh.SaveParametric = 0)");
          add_node(t, x, y, z);
        }
      }
      if (static_cast<int>(m_.nodes.size()) != total)
        in_.fail("the header says " + std::to_string(total) + " nodes, the blocks hold " +
                 std::to_string(m_.nodes.size()));
    } else {
      const int n = in_.count("the number of nodes", 0, 1'000'000'000);
      for (int k = 0; k < n; ++k) {
        const long t   = in_.integer("a node tag");
        const double x = in_.real("x"), y = in_.real("y"), z = in_.real("z");
        add_node(t, x, y, z);
      }
    }
    in_.expect("$EndNodes");
  }

  int element_type() {
    const int type = in_.count("an element type", 1, 1000);
    if (detail::gmsh_node_count(type) < 0)
      in_.fail("element type " + std::to_string(type) +
               ": gapfe reads lines (1, 8), triangles (2, 9) and quadrangles (3, 16, 10) of a meridian "
               "section");
    return type;
  }

  void elements_section() {
    if (!has_nodes_) in_.fail("$Elements before $Nodes");
    if (has_elements_) in_.fail("a second $Elements section");
    has_elements_ = true;
    std::vector<long> tags(9);
    if (m_.version == 4.1) {
      const int blocks = in_.count("the number of element blocks", 0, 100'000'000);
      in_.count("the number of elements", 0, 1'000'000'000);
      in_.integer("the smallest element tag");
      in_.integer("the largest element tag");
      for (int b = 0; b < blocks; ++b) {
        const int dim                   = in_.count("a block's entity dimension", 0, 3);
        const int entity                = in_.count("a block's entity tag", 0, 2'147'483'647L);
        const int type                  = element_type();
        const int n                     = in_.count("a block's element count", 0, 1'000'000'000);
        const auto it                   = entity_physical_.find({dim, entity});
        const std::vector<int> physical = it == entity_physical_.end() ? std::vector<int>{} : it->second;
        const int count                 = std::max(detail::gmsh_node_count(type), type == 15 ? 1 : 0);
        for (int k = 0; k < n; ++k) {
          in_.integer("an element tag");
          const int line = in_.line();
          for (int a = 0; a < count; ++a)
            tags[static_cast<std::size_t>(a)] = in_.integer("an element's node");
          add_element(type, physical, -1, tags, line);
        }
      }
    } else {
      const int n = in_.count("the number of elements", 0, 1'000'000'000);
      for (int k = 0; k < n; ++k) {
        in_.integer("an element tag");
        const int line = in_.line();
        const int type = element_type();
        // Tags: the physical group (0: none), the elementary entity, then any others (partitions).
        const int ntags = in_.count("the number of element tags", 0, 100);
        int physical    = 0;
        long entity     = 0;
        for (int t = 0; t < ntags; ++t) {
          const int v = in_.count(t == 0 ? "an element's physical tag" : "an element tag value",
                                  t == 0 ? 0 : -2'147'483'647L, 2'147'483'647L);
          if (t == 0) physical = v;
          if (t == 1) entity = v;
        }
        const int count = std::max(detail::gmsh_node_count(type), type == 15 ? 1 : 0);
        for (int a = 0; a < count; ++a) tags[static_cast<std::size_t>(a)] = in_.integer("an element's node");
        add_element(type, physical > 0 ? std::vector<int>{physical} : std::vector<int>{}, entity, tags, line);
      }
    }
    in_.expect("$EndElements");
  }

  // Elements may name nodes of a $Nodes section that follows them only in files gapfe does not write;
  // Gmsh writes $Nodes first, and so the reader requires it.
  void add_element(int type, const std::vector<int>& physical, long entity, const std::vector<long>& tags,
                   int line) {
    if (type == 10) type = 16;  // a 9-node quadrangle as the 8-node one on its first 8 nodes
    const int count = detail::gmsh_node_count(type);
    if (count == 0) return;  // a point
    const std::string where = "line " + std::to_string(line) + " ($Elements): ";
    GmshElement e;
    e.type = type, e.node_count = count, e.physical = physical, e.line = line;
    for (int k = 0; k < count; ++k) {
      const auto it = index_.find(tags[static_cast<std::size_t>(k)]);
      if (it == index_.end())
        throw InputError(where + "node " + std::to_string(tags[static_cast<std::size_t>(k)]) +
                         " is not in $Nodes");
      e.nodes[static_cast<std::size_t>(k)] = it->second;
    }
    std::array<int, 8> key;
    key.fill(-1);
    std::copy(e.nodes.begin(), e.nodes.begin() + count, key.begin());
    std::sort(key.begin(), key.begin() + count);
    for (int k = 1; k < count; ++k)
      if (key[static_cast<std::size_t>(k)] == key[static_cast<std::size_t>(k - 1)])
        throw InputError(
            where + "the element names node " +
            std::to_string(m_.node_tags[static_cast<std::size_t>(key[static_cast<std::size_t>(k)])]) +
            " twice (a collapsed element)");
    const int dim                  = detail::gmsh_dimension(type);
    std::vector<GmshElement>& list = dim == 1 ? m_.edges : m_.cells;
    if (const auto it = seen_.find({dim, key}); it != seen_.end()) {
      GmshElement& first = list[static_cast<std::size_t>(it->second.index)];
      // MSH 2.2 writes an element once per physical group it is in: the same element in another group.
      const bool copy = m_.version == 2.2 && first.type == type && it->second.entity == entity &&
                        physical.size() == 1 && !first.physical.empty() && !first.in(physical.front());
      if (!copy)
        throw InputError(
            where + "the element repeats the one of line " + std::to_string(first.line) + " (the same nodes" +
            (physical.size() == 1 && first.in(physical.front()) ? ", in the same physical group" : "") +
            "): a cell or edge is given once (in every physical group it belongs to)");
      first.physical.push_back(physical.front());
      return;
    }
    seen_.emplace(std::make_pair(dim, key), Seen{static_cast<int>(list.size()), entity});
    if (dim == 1) {
      m_.edges.push_back(e);
      return;
    }
    // Twice the signed area of the corner polygon in (r, z), positive counterclockwise, and its longest
    // edge (for the scale of "zero").
    const int corners = detail::gmsh_corners(type);
    double area = 0, size = 0;
    for (int a = 0; a < corners; ++a) {
      const Vec2& p = m_.nodes[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(a)])];
      const Vec2& q =
          m_.nodes[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>((a + 1) % corners)])];
      area += p(0) * q(1) - q(0) * p(1);
      size = std::max(size, (q - p).norm());
    }
    if (area < 0) {  // clockwise: reverse the corners (keeping the first) and the mid-sides with them
      const std::array<int, 8> n = e.nodes;
      for (int a = 1; a < corners; ++a)
        e.nodes[static_cast<std::size_t>(a)] = n[static_cast<std::size_t>(corners - a)];
      // Mid-side k lies on edge (k, k + 1); reversed, new edge (a, a + 1) is old edge corners - 1 - a.
      if (count > corners)
        for (int a = 0; a < corners; ++a)
          e.nodes[static_cast<std::size_t>(corners + a)] = n[static_cast<std::size_t>(2 * corners - 1 - a)];
      ++m_.flipped, area = -area;
    }
    if (!(area > 1e-12 * size * size))
      throw InputError("line " + std::to_string(line) +
                       " ($Elements): element with zero area (degenerate or with repeated nodes)");
    m_.cells.push_back(e);
  }

  std::string_view text_;
  GmshWords in_;
  GmshMesh m_;
  std::unordered_map<long, int> index_;                              // node tag -> index
  std::map<std::pair<int, int>, std::vector<int>> entity_physical_;  // 4.1: (dim, entity tag) -> groups
  // Every element read so far by (dimension, its sorted nodes): where it is (index into cells or edges) and
  // its elementary entity (2.2; -1 in 4.1), to find MSH 2.2's copies of an element in another group.
  struct Seen {
    int index;
    long entity;
  };
  std::map<std::pair<int, std::array<int, 8>>, Seen> seen_;
  bool has_format_ = false, has_nodes_ = false, has_elements_ = false;
};

}  // namespace detail

/// Read an MSH 4.1 or 2.2 ASCII file held in `text`. Throws InputError naming the line and what was wrong.
inline GmshMesh read_gmsh(std::string_view text) {
  return detail::GmshReading(text).read();
}

}  // namespace gapfe

#pragma once
// Gmsh's MSH file format, ASCII, versions 4.1 and 2.2 (issue 16): nodes, the 2-D cells of a meridian
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
// and 8-node quadrangles (3, 16); points (15) are skipped; any other type (a volume element, the 9-node
// quadrangle) is an error naming its type and line. Node orderings are Gmsh's, which are gapfe's too
// (corners counterclockwise, then the mid-sides 0-1, 1-2, ...: element/quad8.hpp).
//
// Checks, each an InputError naming the file's line: node tags may have gaps and come in any order, but each
// once, and every element's nodes must exist; x = r >= 0 (to 1e-12 of the mesh size: a node a rounding error
// left of the axis is put on it); z = 0 (a meridian section is flat); cells with zero or negative area are
// refused after clockwise ones (negative signed area of the corners in (r, z)) are turned counterclockwise,
// which gapfe's elements need (element to the left of each edge); a truncated file names the section it
// ends in.
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

namespace gapfe {

/// A 2-D cell or a 1-D edge of a Gmsh mesh: its nodes as indices into GmshMesh::nodes (Gmsh's order),
/// its physical group (0: none) and its Gmsh element type.
struct GmshElement {
  int type       = 0;          ///< Gmsh element type: 1, 8 (lines), 2, 9 (triangles), 3, 16 (quadrangles)
  int node_count = 0;          ///< 2, 3, 6, 4 or 8
  std::array<int, 8> nodes{};  ///< 0-based node indices, counterclockwise for cells
  int physical = 0;            ///< physical group tag (0: the element belongs to none)
  int line     = 0;            ///< line of the file where it is defined (for later errors)
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

/// Gmsh's element types that gapfe reads, with their node counts (0: skipped, -1: not supported).
inline int gmsh_node_count(int type) {
  switch (type) {
    case 1:
      return 2;  // 2-node line
    case 8:
      return 3;  // 3-node line
    case 2:
      return 3;  // 3-node triangle
    case 9:
      return 6;  // 6-node triangle
    case 3:
      return 4;  // 4-node quadrangle
    case 16:
      return 8;  // 8-node quadrangle
    case 15:
      return 0;  // point: skipped
    default:
      return -1;
  }
}
/// The corners of a Gmsh cell type: 3 for triangles (2, 9), else 4 (quadrangles 3, 16).
inline int gmsh_corners(int type) {
  return type == 2 || type == 9 ? 3 : 4;
}
inline int gmsh_dimension(int type) {
  return type == 1 || type == 8 ? 1 : type == 15 ? 0 : 2;
}

/// The file as whitespace-separated words with their line numbers, read in order.
class GmshWords {
 public:
  explicit GmshWords(std::string_view text) : text_(text) {}

  /// The next word; InputError naming `what` and the section when the file ends.
  std::string_view word(const char* what) {
    skip_space();
    if (at_ >= text_.size())
      throw InputError("the file ends in " + section_ + " (line " + std::to_string(line_) + ") where " +
                       what + " was expected: truncated?");
    const std::size_t start = at_;
    if (text_[at_] == '"') {  // a quoted name, spaces included
      const std::size_t end = text_.find('"', at_ + 1);
      if (end == std::string_view::npos || text_.substr(at_, end - at_).find('\n') != std::string_view::npos)
        fail(std::string("an unterminated quoted name where ") + what + " was expected");
      at_ = end + 1;
      return text_.substr(start + 1, end - start - 1);
    }
    while (at_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
    return text_.substr(start, at_ - start);
  }
  long integer(const char* what) {
    const std::string_view w = word(what);
    long v                   = 0;
    std::size_t k            = w[0] == '-' || w[0] == '+' ? 1 : 0;
    if (k == w.size()) fail(std::string(what) + ": expected an integer, found '" + std::string(w) + "'");
    for (; k < w.size(); ++k) {
      if (w[k] < '0' || w[k] > '9' || v > 100'000'000'000L)
        fail(std::string(what) + ": expected an integer, found '" + std::string(w) + "'");
      v = v * 10 + (w[k] - '0');
    }
    return w[0] == '-' ? -v : v;
  }
  /// An integer in [lo, hi].
  int count(const char* what, long lo, long hi) {
    const long v = integer(what);
    if (v < lo || v > hi)
      fail(std::string(what) + " = " + std::to_string(v) + ": expected " + std::to_string(lo) + " to " +
           std::to_string(hi));
    return static_cast<int>(v);
  }
  double real(const char* what) {
    const std::string w(word(what));
    char* end      = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (end != w.c_str() + w.size() || !std::isfinite(v))
      fail(std::string(what) + ": expected a finite number, found '" + w + "'");
    return v;
  }
  /// Skip to the line after `$End<name>`.
  void skip_section(const std::string& name) {
    const std::string end = "$End" + name;
    for (;;) {
      const std::string_view w = word(end.c_str());
      if (w == end) return;
    }
  }
  void expect(const std::string& token) {
    const std::string_view w = word(token.c_str());
    if (w != token) fail("expected " + token + ", found '" + std::string(w) + "'");
  }
  bool done() {
    skip_space();
    return at_ >= text_.size();
  }
  int line() const { return line_; }
  void enter(const std::string& section) { section_ = section; }
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError("line " + std::to_string(line_) + " (" + section_ + "): " + why);
  }

 private:
  void skip_space() {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) {
      if (text_[at_] == '\n') ++line_;
      ++at_;
    }
  }
  std::string_view text_;
  std::size_t at_      = 0;
  int line_            = 1;
  std::string section_ = "the file's start";
};

}  // namespace detail

/// Read an MSH 4.1 or 2.2 ASCII file held in `text`. Throws InputError naming the line and what was wrong.
inline GmshMesh read_gmsh(std::string_view text) {
  GmshMesh m;
  detail::GmshWords in(text);
  std::unordered_map<long, int> index;                 // node tag -> index
  std::map<std::pair<int, int>, int> entity_physical;  // 4.1: (dim, entity tag) -> first physical tag
  bool format = false, nodes = false, elements = false;
  // Elements may name nodes of a $Nodes section that follows them only in files gapfe does not write;
  // Gmsh writes $Nodes first, and so the reader requires it.
  const auto add_element = [&](int type, int physical, const std::vector<long>& tags, int line) {
    const int count = detail::gmsh_node_count(type);
    if (count == 0) return;  // a point
    GmshElement e;
    e.type = type, e.node_count = count, e.physical = physical, e.line = line;
    for (int k = 0; k < count; ++k) {
      const auto it = index.find(tags[static_cast<std::size_t>(k)]);
      if (it == index.end())
        throw InputError("line " + std::to_string(line) + " ($Elements): node " +
                         std::to_string(tags[static_cast<std::size_t>(k)]) + " is not in $Nodes");
      e.nodes[static_cast<std::size_t>(k)] = it->second;
    }
    if (detail::gmsh_dimension(type) == 1) {
      m.edges.push_back(e);
      return;
    }
    // Twice the signed area of the corner polygon in (r, z), positive counterclockwise, and its longest
    // edge (for the scale of "zero").
    const int corners = detail::gmsh_corners(type);
    double area = 0, size = 0;
    for (int a = 0; a < corners; ++a) {
      const Vec2& p = m.nodes[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(a)])];
      const Vec2& q = m.nodes[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>((a + 1) % corners)])];
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
      ++m.flipped, area = -area;
    }
    if (!(area > 1e-12 * size * size))
      throw InputError("line " + std::to_string(line) +
                       " ($Elements): element with zero area (degenerate or with repeated nodes)");
    m.cells.push_back(e);
  };

  while (!in.done()) {
    const std::string section(in.word("a section"));
    if (section.empty() || section[0] != '$')
      in.fail("expected a section ($MeshFormat, $Nodes, ...), found '" + section + "'");
    const std::string name = section.substr(1);
    in.enter(section);
    if (name == "MeshFormat") {
      m.version       = in.real("the version");
      const int ascii = in.count("the file type", 0, 1);
      in.real("the data size");
      if (m.version != 4.1 && m.version != 2.2)
        in.fail("MSH version " + std::to_string(m.version) +
                ": gapfe reads 4.1 and 2.2 (Gmsh: -format msh41 or msh22)");
      if (ascii != 0) in.fail("a binary MSH file: gapfe reads ASCII (Gmsh: -bin 0, or Mesh.Binary = 0)");
      in.expect("$EndMeshFormat");
      format = true;
    } else if (!format) {
      in.fail("the file does not start with $MeshFormat: not an MSH file?");
    } else if (name == "PhysicalNames") {
      const int n = in.count("the number of names", 0, 1'000'000);
      for (int k = 0; k < n; ++k) {
        const int dim                = in.count("a physical group's dimension", 0, 3);
        const int tag                = in.count("a physical group's tag", 1, 2'147'483'647L);
        m.physical_names[{dim, tag}] = std::string(in.word("a physical group's name"));
      }
      in.expect("$EndPhysicalNames");
    } else if (name == "Entities" && m.version == 4.1) {
      long counts[4];
      for (long& c : counts) c = in.count("an entity count", 0, 100'000'000);
      for (int dim = 0; dim < 4; ++dim)
        for (long k = 0; k < counts[dim]; ++k) {
          const int tag = in.count("an entity tag", 0, 2'147'483'647L);
          for (int c = 0; c < (dim == 0 ? 3 : 6); ++c) in.real("an entity's bounding box");
          const int n = in.count("the number of physical tags", 0, 1'000'000);
          for (int p = 0; p < n; ++p) {
            const long physical = in.integer("a physical tag");
            if (p == 0) entity_physical[{dim, tag}] = static_cast<int>(std::labs(physical));
          }
          if (dim > 0) {
            const int b = in.count("the number of bounding entities", 0, 100'000'000);
            for (int q = 0; q < b; ++q) in.integer("a bounding entity");
          }
        }
      in.expect("$EndEntities");
    } else if (name == "Nodes") {
      if (nodes) in.fail("a second $Nodes section");
      nodes          = true;
      const auto add = [&](long tag, double x, double y, double z) {
        if (!index.emplace(tag, static_cast<int>(m.nodes.size())).second)
          in.fail("node " + std::to_string(tag) + " is given twice");
        if (z != 0)
          in.fail("node " + std::to_string(tag) + " has z = " + std::to_string(z) +
                  ": a meridian section lies in the plane z = 0 (x = r, y = z)");
        m.nodes.emplace_back(x, y);
        m.node_tags.push_back(tag);
      };
      if (m.version == 4.1) {
        const int blocks = in.count("the number of node blocks", 0, 100'000'000);
        const int total  = in.count("the number of nodes", 0, 1'000'000'000);
        in.integer("the smallest node tag");
        in.integer("the largest node tag");
        // Counts come from the file: reserve no more than its text can hold (a node takes 8 characters or
        // more), so a header that claims a billion nodes in a short file costs nothing before it is found
        // short.
        m.nodes.reserve(std::min(static_cast<std::size_t>(total), text.size() / 8));
        for (int b = 0; b < blocks; ++b) {
          in.count("a block's entity dimension", 0, 3);
          in.integer("a block's entity tag");
          const int parametric = in.count("a block's parametric flag", 0, 1);
          const int n          = in.count("a block's node count", 0, 1'000'000'000);
          std::vector<long> tags;
          tags.reserve(std::min(static_cast<std::size_t>(n), text.size() / 2));
          for (int k = 0; k < n; ++k) tags.push_back(in.integer("a node tag"));
          for (const long t : tags) {
            const double x = in.real("x"), y = in.real("y"), z = in.real("z");
            if (parametric)
              in.fail("parametric node coordinates: save the mesh without them (Mesh.SaveParametric = 0)");
            add(t, x, y, z);
          }
        }
        if (static_cast<int>(m.nodes.size()) != total)
          in.fail("the header says " + std::to_string(total) + " nodes, the blocks hold " +
                  std::to_string(m.nodes.size()));
      } else {
        const int n = in.count("the number of nodes", 0, 1'000'000'000);
        for (int k = 0; k < n; ++k) {
          const long t   = in.integer("a node tag");
          const double x = in.real("x"), y = in.real("y"), z = in.real("z");
          add(t, x, y, z);
        }
      }
      in.expect("$EndNodes");
    } else if (name == "Elements") {
      if (!nodes) in.fail("$Elements before $Nodes");
      if (elements) in.fail("a second $Elements section");
      elements = true;
      std::vector<long> tags(8);
      const auto read_type = [&] {
        const int type = in.count("an element type", 1, 1000);
        if (detail::gmsh_node_count(type) < 0)
          in.fail(
              "element type " + std::to_string(type) +
              ": gapfe reads lines (1, 8), triangles (2, 9) and quadrangles (3, 16) of a meridian section");
        return type;
      };
      if (m.version == 4.1) {
        const int blocks = in.count("the number of element blocks", 0, 100'000'000);
        in.count("the number of elements", 0, 1'000'000'000);
        in.integer("the smallest element tag");
        in.integer("the largest element tag");
        for (int b = 0; b < blocks; ++b) {
          const int dim      = in.count("a block's entity dimension", 0, 3);
          const int entity   = in.count("a block's entity tag", 0, 2'147'483'647L);
          const int type     = read_type();
          const int n        = in.count("a block's element count", 0, 1'000'000'000);
          const auto it      = entity_physical.find({dim, entity});
          const int physical = it == entity_physical.end() ? 0 : it->second;
          const int count    = std::max(detail::gmsh_node_count(type), type == 15 ? 1 : 0);
          for (int k = 0; k < n; ++k) {
            in.integer("an element tag");
            const int line = in.line();
            for (int a = 0; a < count; ++a)
              tags[static_cast<std::size_t>(a)] = in.integer("an element's node");
            add_element(type, physical, tags, line);
          }
        }
      } else {
        const int n = in.count("the number of elements", 0, 1'000'000'000);
        for (int k = 0; k < n; ++k) {
          in.integer("an element tag");
          const int line  = in.line();
          const int type  = read_type();
          const int ntags = in.count("the number of element tags", 0, 100);
          int physical    = 0;
          for (int t = 0; t < ntags; ++t) {
            const long v = in.integer("an element tag value");
            if (t == 0) physical = static_cast<int>(std::labs(v));
          }
          const int count = std::max(detail::gmsh_node_count(type), type == 15 ? 1 : 0);
          for (int a = 0; a < count; ++a) tags[static_cast<std::size_t>(a)] = in.integer("an element's node");
          add_element(type, physical, tags, line);
        }
      }
      in.expect("$EndElements");
    } else {
      in.skip_section(name);  // $Entities of 2.2 files, $NodeData, $Periodic, ...
    }
  }
  if (!format) throw InputError("empty file: not an MSH file");
  if (!nodes || m.nodes.empty()) throw InputError("the file has no $Nodes section or no nodes");
  if (!elements || m.cells.empty())
    throw InputError(
        "the file has no triangles or quadrangles (a 2-D mesh of the meridian section is needed)");
  // x = r >= 0: the axis is r = 0; a node a rounding error left of it is put on it.
  Vec2 lo = m.nodes.front(), hi = lo;
  for (const Vec2& x : m.nodes) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double size = std::max((hi - lo).maxCoeff(), 1e-300);
  for (std::size_t k = 0; k < m.nodes.size(); ++k) {
    if (m.nodes[k](0) >= 0) continue;
    if (m.nodes[k](0) > -1e-12 * size) {
      m.nodes[k](0) = 0;
      continue;
    }
    throw InputError("node " + std::to_string(m.node_tags[k]) +
                     " has x = r = " + std::to_string(m.nodes[k](0)) +
                     " < 0: an axisymmetric section lies at r >= 0 (x = r, y = z)");
  }
  return m;
}

}  // namespace gapfe

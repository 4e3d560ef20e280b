#pragma once
// A Gmsh mesh with every cell split in four, for the finer meshes of `gapfe run --estimate` on a scene file
// (docs/accuracy.md "Error bars"). Each side gets a new point at its middle, each quadrangle one at its
// centre (the mean of its side points, less half the mean of its corners: its centre when the sides are
// straight, the transfinite one when a side point moved), and each cell becomes four of its kind with the
// cell's physical groups; each line element becomes two. The mesh's nodes keep their indices and the new
// ones follow (GmshSplit::coarse_nodes tells them apart).
//
// Curves: the file keeps no geometry, so a side's new point goes where the mesh itself shows the curve. A
// boundary side or a side of a line element whose run of sides, with a neighbour on either end, lies on one
// circle (four points on it to round-off) gets its point on that circle, at its middle angle; any other
// side's point stays at the chord's middle. So arcs of three sides or more (a bore, a fillet, a sphere) stay
// arcs on the finer meshes; a spline or an ellipse stays the coarse mesh's polygon, and the finer meshes
// converge to that polygon's solution (the difference: the chords' sagitta, h^2 / 8R).
//
// Soft layers (a scene's [[contact]] soft surface: one cell between the two faces, soft while the gap is
// open) stay one cell thick: their quadrangles split only along the faces, into two, since cells in series
// across the gap would be another model. Their sides across the layer may touch no other cell.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/pair_key.hpp"
#include "gapfe/input/gmsh_reader.hpp"

namespace gapfe {

/// A split Gmsh mesh and what the split did.
struct GmshSplit {
  GmshMesh mesh;
  std::size_t coarse_nodes = 0;  ///< the nodes of the mesh as read: indices 0..coarse_nodes - 1
  long arc_points          = 0;  ///< new points put on a circle their curve lies on
};

namespace detail {

/// The circle through three points (centre, radius); none when they are (near) on one line.
inline std::optional<std::pair<Vec2, double>> circle_through(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 ab = b - a, ac = c - a;
  const double d = 2 * (ab(0) * ac(1) - ab(1) * ac(0));
  if (!(std::abs(d) > 1e-14 * (ab.squaredNorm() + ac.squaredNorm()))) return std::nullopt;
  const Vec2 centre = a + Vec2(ac(1) * ab.squaredNorm() - ab(1) * ac.squaredNorm(),
                               ab(0) * ac.squaredNorm() - ac(0) * ab.squaredNorm()) /
                              d;
  return std::pair{centre, (a - centre).norm()};
}

/// Where a curve side (p, q) gets its new point: on the circle four consecutive points of its run lie on
/// (`next(a, b)`: the point after b going from a, -1 at a junction or an end), else at the chord's middle.
/// A circle counts when it bends the side at least 1e-6 (radius at most 1e6 sides), each of the run's sides
/// spans at most 35 degrees of it (so four corners of a square are not an arc), and the fourth point lies on
/// it to 1e-10 of the coordinates' size plus 1e-8 of the side (MSH files carry 16 digits).
template <class Next>
std::optional<Vec2> arc_middle(const std::vector<Vec2>& x, int p, int q, Next&& next) {
  const int p1 = next(q, p), q1 = next(p, q);
  const int p2 = p1 >= 0 ? next(p, p1) : -1, q2 = q1 >= 0 ? next(q, q1) : -1;
  const double side = (x[q] - x[p]).norm();
  for (const std::array<int, 4> run :
       {std::array{p1, p, q, q1}, std::array{p2, p1, p, q}, std::array{p, q, q1, q2}}) {
    if (std::find(run.begin(), run.end(), -1) != run.end()) continue;
    std::set<int> distinct(run.begin(), run.end());
    if (distinct.size() != 4) continue;
    const auto circle = circle_through(x[run[0]], x[run[1]], x[run[2]]);
    if (!circle || circle->second > 1e6 * side) continue;
    const auto& [centre, radius] = *circle;
    bool short_sides = true;  // each side at most 35 degrees of the circle: a square's corners are not an arc
    for (int k = 0; k < 3; ++k)
      short_sides = short_sides && (x[run[k + 1]] - x[run[k]]).norm() <= 0.6 * radius;
    if (!short_sides) continue;
    double size = 0;
    for (const int n : run) size = std::max(size, x[n].cwiseAbs().maxCoeff());
    if (std::abs((x[run[3]] - centre).norm() - radius) > 1e-10 * size + 1e-8 * side) continue;
    const Vec2 chord = 0.5 * (x[p] + x[q]) - centre;
    if (chord.norm() < 1e-3 * radius) continue;  // a half circle in one side: no middle to tell
    return Vec2(centre + radius * chord.normalized());
  }
  return std::nullopt;
}

/// One split of `g` (see the top); `soft`: physical surface tags of soft layers, `faces`: physical curve
/// tags of the contact faces they lie between.
inline GmshMesh split_gmsh_once(const GmshMesh& g, const std::set<int>& soft, const std::set<int>& faces,
                                long& arc_points) {
  const auto in_any = [](const GmshElement& e, const std::set<int>& tags) {
    return std::any_of(e.physical.begin(), e.physical.end(), [&](int t) { return tags.count(t) > 0; });
  };
  const auto where = [](const GmshElement& e) {
    return "the cell at line " + std::to_string(e.line) + " of the mesh";
  };
  std::unordered_set<std::uint64_t> face_sides, kept;  // sides on the faces; sides across a soft layer
  for (const GmshElement& e : g.edges)  // a 3-node line's middle node would be a point of no cell side
    if (e.node_count != 2)
      throw InputError(
          "line " + std::to_string(e.line) +
          ": a 3-node line element in a mesh of linear cells; --estimate and --accuracy split first-order "
          "meshes (mesh with Mesh.ElementOrder = 1)");
  for (const GmshElement& e : g.edges)
    if (in_any(e, faces)) face_sides.insert(side_key(e.nodes[0], e.nodes[1]));
  // Which sides of each cell split: every side, but a soft quadrangle's across its layer.
  std::vector<std::array<char, 4>> splits(g.cells.size(), {1, 1, 1, 1});
  for (std::size_t c = 0; c < g.cells.size(); ++c) {
    const GmshElement& e = g.cells[c];
    if (!in_any(e, soft)) continue;
    if (e.node_count != 4)
      throw InputError(where(e) +
                       " is a soft cell (a [[contact]] soft surface) but not a quadrangle: --estimate "
                       "keeps a soft layer one cell thick, which needs quadrangles between the faces");
    std::array<char, 4> on{};
    for (int k = 0; k < 4; ++k) on[k] = face_sides.count(side_key(e.nodes[k], e.nodes[(k + 1) % 4])) > 0;
    if (!((on[0] && on[2] && !on[1] && !on[3]) || (on[1] && on[3] && !on[0] && !on[2])))
      throw InputError(
          where(e) +
          " is a soft cell whose two opposite sides are not on the contact's faces: --estimate splits "
          "a soft layer along its faces only, and cannot tell which way that is here");
    splits[c] = on;
    for (int k = 0; k < 4; ++k)
      if (!on[k]) kept.insert(side_key(e.nodes[k], e.nodes[(k + 1) % 4]));
  }
  std::unordered_map<std::uint64_t, int> uses;  // cells on each side: 1 on the boundary
  for (std::size_t c = 0; c < g.cells.size(); ++c) {
    const GmshElement& e = g.cells[c];
    for (int k = 0; k < e.node_count; ++k) {
      const std::uint64_t s = side_key(e.nodes[k], e.nodes[(k + 1) % e.node_count]);
      ++uses[s];
      if (kept.count(s) && !in_any(e, soft))
        throw InputError(where(e) +
                         " shares a side with a soft layer's cell across the layer; the split would "
                         "leave a point hanging there (end the soft layer at the boundary)");
    }
  }
  // The curves: boundary sides and line elements, each point's neighbours along them.
  std::unordered_map<int, std::vector<int>> along;
  std::unordered_set<std::uint64_t> curve;
  const auto add_curve = [&](int a, int b) {
    if (!curve.insert(side_key(a, b)).second) return;
    along[a].push_back(b), along[b].push_back(a);
  };
  for (const auto& [s, count] : uses)
    if (count == 1) add_curve(static_cast<int>(s >> 32), static_cast<int>(s & 0xffffffffu));
  for (const GmshElement& e : g.edges) add_curve(e.nodes[0], e.nodes[1]);
  const auto next = [&](int from, int at) {  // the point after `at` coming from `from`, -1 at a junction
    const auto it = along.find(at);
    if (it == along.end() || it->second.size() != 2) return -1;
    return it->second[0] == from ? it->second[1] : it->second[0];
  };

  GmshMesh out = g;
  out.cells.clear(), out.edges.clear();
  long tag = 0;
  for (const long t : g.node_tags) tag = std::max(tag, t);
  std::unordered_map<std::uint64_t, int> middle;
  const auto middle_of = [&](int a, int b) {
    const auto [it, added] = middle.try_emplace(side_key(a, b), static_cast<int>(out.nodes.size()));
    if (added) {
      Vec2 x = 0.5 * (g.nodes[a] + g.nodes[b]);
      if (curve.count(side_key(a, b)))
        if (const auto arc = arc_middle(g.nodes, a, b, next)) x = *arc, ++arc_points;
      out.nodes.push_back(x), out.node_tags.push_back(++tag);
    }
    return it->second;
  };
  const auto cell = [](const GmshElement& parent, std::initializer_list<int> nodes) {
    GmshElement e = parent;
    e.node_count  = static_cast<int>(nodes.size());
    std::copy(nodes.begin(), nodes.end(), e.nodes.begin());
    return e;
  };
  for (std::size_t c = 0; c < g.cells.size(); ++c) {
    const GmshElement& e = g.cells[c];
    const auto& n        = e.nodes;
    if (e.node_count == 3) {
      const int a = middle_of(n[0], n[1]), b = middle_of(n[1], n[2]), d = middle_of(n[2], n[0]);
      for (const auto& t :
           {std::array{n[0], a, d}, std::array{a, n[1], b}, std::array{d, b, n[2]}, std::array{a, b, d}})
        out.cells.push_back(cell(e, {t[0], t[1], t[2]}));
      continue;
    }
    if (splits[c] != std::array<char, 4>{1, 1, 1, 1}) {  // a soft quadrangle: two, along its faces
      const int k  = splits[c][0] ? 0 : 1;               // sides k and k + 2 split
      const int c0 = n[k], c1 = n[(k + 1) % 4], c2 = n[(k + 2) % 4], c3 = n[(k + 3) % 4];
      const int a = middle_of(c0, c1), b = middle_of(c2, c3);
      out.cells.push_back(cell(e, {c0, a, b, c3})), out.cells.push_back(cell(e, {a, c1, c2, b}));
      continue;
    }
    const int m0 = middle_of(n[0], n[1]), m1 = middle_of(n[1], n[2]), m2 = middle_of(n[2], n[3]),
              m3 = middle_of(n[3], n[0]);
    Vec2 centre  = Vec2::Zero();
    for (const int m : {m0, m1, m2, m3}) centre += 0.5 * out.nodes[m];
    for (int k = 0; k < 4; ++k) centre -= 0.25 * g.nodes[n[k]];
    const int o = static_cast<int>(out.nodes.size());
    out.nodes.push_back(centre), out.node_tags.push_back(++tag);
    for (const auto& q : {std::array{n[0], m0, o, m3}, std::array{m0, n[1], m1, o},
                          std::array{o, m1, n[2], m2}, std::array{m3, o, m2, n[3]}})
      out.cells.push_back(cell(e, {q[0], q[1], q[2], q[3]}));
  }
  for (const GmshElement& e : g.edges) {
    if (kept.count(side_key(e.nodes[0], e.nodes[1]))) {
      out.edges.push_back(e);
      continue;
    }
    const int m = middle_of(e.nodes[0], e.nodes[1]);
    out.edges.push_back(cell(e, {e.nodes[0], m})), out.edges.push_back(cell(e, {m, e.nodes[1]}));
  }
  return out;
}

}  // namespace detail

/// `g` split `times` times (see the top); `soft` and `faces`: the physical surface and curve names of the
/// soft layers and the faces they lie between, which stay one cell thick (names `g` lacks are left to the
/// scene's own checks). InputError for a soft layer that cannot stay one cell thick.
inline GmshSplit split_gmsh(const GmshMesh& g, int times, const std::vector<std::string>& soft = {},
                            const std::vector<std::string>& faces = {}) {
  const auto tags = [&](int dim, const std::vector<std::string>& names) {
    std::set<int> out;
    for (const auto& [key, name] : g.physical_names)
      if (key.first == dim && std::find(names.begin(), names.end(), name) != names.end())
        out.insert(key.second);
    return out;
  };
  const std::set<int> soft_tags = tags(2, soft), face_tags = tags(1, faces);
  GmshSplit out{g, g.nodes.size(), 0};
  for (int k = 0; k < times; ++k)
    out.mesh = detail::split_gmsh_once(out.mesh, soft_tags, face_tags, out.arc_points);
  return out;
}

}  // namespace gapfe

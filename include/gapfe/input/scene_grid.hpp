#pragma once
// A scene file's mesh from the seed's I-J generator (line segment cards, Appendix A Data 3-4), its groups
// rectangles of grid indices (input/scene_mesh.hpp has the other source, a Gmsh file).
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
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "gapfe/input/deck_refine.hpp"
#include "gapfe/input/scene_mesh.hpp"
#include "gapfe/mesh/ij_generator.hpp"

namespace gapfe::detail {

/// The seed's I-J generator: [mesh] grid = [MAXI, MAXJ], [[mesh.segments]] (one line segment card each:
/// type, points = [[I, J, r, z], ...], centre = [r, z] for "arc-centre"), [mesh.groups] NAME = {i, j}.
class GridSceneMesh final : public SceneMesh {
 public:
  GridSceneMesh(const SceneTable& mesh, Scene& s, const InputLimits& limits,
                const SceneRefinement& refine = {}) {
    const auto size        = mesh.numbers("grid", 2, "[MAXI, MAXJ], the grid's largest I and J");
    const std::string most = std::to_string(limits.max_grid_points);
    if (!(size[0] >= 1 && size[1] >= 1 && size[0] == std::floor(size[0]) && size[1] == std::floor(size[1]) &&
          size[0] * size[1] <= static_cast<double>(limits.max_grid_points)))
      mesh.fail("grid", "[MAXI, MAXJ], whole numbers >= 1 with MAXI x MAXJ at most " + most + " (" +
                            detail::number_text(size[0]) + " x " + detail::number_text(size[1]) + " is not)");
    const int max_i = static_cast<int>(size[0]), max_j = static_cast<int>(size[1]);
    std::vector<Segment> segments;
    std::vector<CardRef> refs;
    const std::vector<SceneTable> cards = mesh.tables("segments", {"type", "points", "centre"});
    if (cards.empty()) mesh.fail("segments", "[[mesh.segments]] tables, one per line segment card");
    for (const SceneTable& c : cards)
      segments.push_back(segment(c, max_i, max_j)),
          refs.push_back({"scene: [[mesh.segments]] table " + std::to_string(refs.size() + 1), c.line()});
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
    IJGrid g = generate(max_i, max_j, segments, [&](int k) { return cards[k].where(); });
    if (refine.times > 0) g = refined(g, segments, refs, refine, limits);
    grid_scene_mesh(std::move(g), s);
    size_scene_cells(s);
    grid_ = &s.grid;
    for (int n = 0; n < s.grid.node_count(); ++n) labels_.push_back(n + 1);
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

  /// The I-J generator's grid, its errors naming the segment table (`where(k)`: the k-th, from 0).
  template <class Where>
  static IJGrid generate(int max_i, int max_j, const std::vector<Segment>& segments, Where&& where) {
    try {
      return generate_ij_grid(max_i, max_j, segments);
    } catch (const InputError& e) {
      // The generator numbers segment cards from 1: name the table instead.
      std::string message   = e.what();
      const std::string tag = "line segment card ";
      if (const auto at = message.find(tag); at != std::string::npos) {
        const int k = std::atoi(message.c_str() + at + tag.size());
        if (k >= 1 && k <= static_cast<int>(segments.size()))
          throw InputError("scene: " + where(k - 1) + ": " + message);
      }
      throw InputError("scene: [mesh] (the I-J generator): " + message);
    }
  }

  /// `coarse`, the grid of `segments`, refined (SceneRefinement, input/deck_refine.hpp): the interval between
  /// two contact faces on neighbouring lines stays one cell; the groups move to the finer grid's lines.
  IJGrid refined(const IJGrid& coarse, const std::vector<Segment>& segments, const std::vector<CardRef>& refs,
                 const SceneRefinement& refine, const InputLimits& limits) {
    std::vector<char> kept_i(static_cast<std::size_t>(coarse.max_i) + 1, 0),
        kept_j(static_cast<std::size_t>(coarse.max_j) + 1, 0);
    // The cells between two faces, where both span (gap_direction as a deck's gap elements: 1 across I, 2
    // across J), whose finer corners on the faces a segment card must place (check_fine_points).
    std::vector<int> gap_direction(coarse.cells.size(), 0);
    for (const auto& [a, b] : refine.faces) {
      const auto p = groups_.find(a), q = groups_.find(b);
      if (p == groups_.end() || q == groups_.end()) continue;  // contact() names it
      for (int dir = 1; dir <= 2; ++dir) {
        const auto& u = dir == 1 ? p->second.i : p->second.j;  // across the gap
        const auto& v = dir == 1 ? q->second.i : q->second.j;
        const auto& s = dir == 1 ? p->second.j : p->second.i;  // along it
        const auto& t = dir == 1 ? q->second.j : q->second.i;
        if (u[0] != u[1] || v[0] != v[1] || std::abs(u[0] - v[0]) != 1) continue;
        const int k = std::min(u[0], v[0]), lo = std::max(s[0], t[0]), hi = std::min(s[1], t[1]);
        (dir == 1 ? kept_i : kept_j)[static_cast<std::size_t>(k)] = 1;
        for (std::size_t e = 0; e < coarse.cells.size(); ++e) {
          const GridCell& c = coarse.cells[e];
          const int across = dir == 1 ? c.i : c.j, along = dir == 1 ? c.j : c.i;
          if (across == k && along >= lo && along < hi) gap_direction[e] = dir;
        }
      }
    }
    const RefinedCards f =
        refine_cards(coarse.max_i, coarse.max_j, segments, refs, kept_i, kept_j, refine.times, limits);
    IJGrid fine = generate(f.max_i, f.max_j, f.segments,
                           [&](int k) { return f.refs[k].where() + " (on the finer grid)"; });
    check_fine_points(coarse, fine, f.index, gap_direction);
    for (auto& [name, r] : groups_)
      r.i = {f.index.i[r.i[0]], f.index.i[r.i[1]]}, r.j = {f.index.j[r.j[0]], f.index.j[r.j[1]]};
    std::vector<char> own_i(static_cast<std::size_t>(f.max_i) + 1, 0),
        own_j(static_cast<std::size_t>(f.max_j) + 1, 0);
    for (std::size_t k = 1; k < f.index.i.size(); ++k) own_i[f.index.i[k]] = 1;
    for (std::size_t k = 1; k < f.index.j.size(); ++k) own_j[f.index.j[k]] = 1;
    for (const auto& [i, j] : fine.node_ij) own_.push_back(own_i[i] && own_j[j]);
    refined_ = "the I-J grid at 1/" + std::to_string(1 << refine.times) + " of its spacing";
    return fine;
  }

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

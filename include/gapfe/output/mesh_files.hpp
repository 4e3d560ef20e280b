#pragma once
// What `gapfe mesh` writes: the deck's grid with its numbers, as a picture, two tables and a VTU file.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "gapfe/input/scene.hpp"
#include "gapfe/output/csv_rows.hpp"
#include "gapfe/output/grid_arrays.hpp"
#include "gapfe/output/output_file.hpp"
#include "gapfe/output/svg_canvas.hpp"
#include "gapfe/output/vtu_writer.hpp"

namespace gapfe {

/// `gapfe mesh`: mesh.svg (the grid with node and element numbers, like the seed's plot option),
/// mesh_nodes.csv, mesh_elements.csv and mesh.vtu in `dir`.
inline void write_mesh_files(const std::string& dir, const ModelDescription& d, const Scene& s) {
  const IJGrid& g = s.grid;
  {
    std::string t = "node,i,j,r,z,placed\n";
    for (int n = 0; n < g.node_count(); ++n) {
      for (const int k : {n + 1, g.node_ij[n][0], g.node_ij[n][1]})
        detail::append_number(t, static_cast<long long>(k)), t += ',';
      detail::csv_number(t, g.nodes[n](0)), detail::csv_number(t, g.nodes[n](1));
      t += g.placed[n] ? "1\n" : "0\n";
    }
    detail::write_file_atomically(dir + "/mesh_nodes.csv", t);
  }
  {
    std::string t = "element,i,j,material,ijdir,n1,n2,n3,n4\n";
    for (std::size_t e = 0; e < g.cells.size(); ++e) {
      const GridCell& c = g.cells[e];
      for (const int k : {static_cast<int>(e) + 1, c.i, c.j, s.material_id[e], s.ijdir[e]})
        detail::append_number(t, static_cast<long long>(k)), t += ',';
      for (int k = 0; k < 4; ++k) {
        if (k < c.corners) detail::append_number(t, static_cast<long long>(c.node[k] + 1));
        t += k < 3 ? ',' : '\n';
      }
    }
    detail::write_file_atomically(dir + "/mesh_elements.csv", t);
  }
  {
    VtuField placed{"placed_by_card", 1, {}, true};
    for (int n = 0; n < g.node_count(); ++n) placed.values.push_back(g.placed[n]);
    write_vtu(dir + "/mesh.vtu", g.nodes, detail::grid_cells(g), {placed}, detail::element_ids(s));
  }

  // ---- SVG: r to the right, z up; numbers only while they stay legible
  detail::SvgCanvas svg(
      g.nodes, d.title + " (" + std::to_string(g.node_count()) + " nodes, " + std::to_string(g.cells.size()) +
                   " elements; node numbers black, element numbers blue; r to the right, z up)");
  const bool labels = g.cells.size() <= 2500;
  const double font =
      labels
          ? std::clamp(0.25 * svg.scale * svg.extent() / std::sqrt(static_cast<double>(g.cells.size()) + 1.0),
                       4.0, 14.0)
          : 0;
  for (std::size_t e = 0; e < g.cells.size(); ++e) {
    const GridCell& c = g.cells[e];
    std::array<Vec2, 4> x;
    Vec2 centre = Vec2::Zero();
    for (int k = 0; k < c.corners; ++k) x[k] = g.nodes[c.node[k]], centre += x[k] / c.corners;
    svg.polygon(x, c.corners, detail::kMaterialFill[(std::max(s.material_id[e], 1) - 1) % 6], "#333", 0.6);
    if (labels) {
      const auto p = svg.px(centre);
      svg.text(p[0], p[1] + font / 3, font, std::to_string(e + 1), "#1f4fbf", "middle");
    }
  }
  if (labels)
    for (int n = 0; n < g.node_count(); ++n) {
      const auto p = svg.px(g.nodes[n]);
      svg.t += "<circle cx=\"", svg.num(p[0]), svg.t += "\" cy=\"", svg.num(p[1]), svg.t += "\" r=\"1.5\"/>";
      svg.text(p[0] + 2, p[1] - 2, 0.8 * font, std::to_string(n + 1));
    }
  svg.save(dir + "/mesh.svg");
}

}  // namespace gapfe

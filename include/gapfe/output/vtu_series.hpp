#pragma once
// The VTU files of a run and their collection result.pvd, for ParaView: one step_NNNN.vtu per completed
// step (step_NNNN_split_K.vtu at the points where a contact policy, load_pieces or a cut split it),
// result.pvd's timesteps t.
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "gapfe/input/scene.hpp"
#include "gapfe/output/grid_arrays.hpp"
#include "gapfe/output/result_tables.hpp"
#include "gapfe/output/vtu_writer.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

/// The increment's VTU arrays: displacement and reaction per node; stress, eqps and `extra_cells` per cell
/// (not the mesh: the files encode theirs once, the pictures take it at the end).
inline VtuData vtu_arrays(const Scene& scene, const Solution& solution,
                          const std::vector<PointValues>& values, std::vector<VtuField> extra_cells) {
  const IJGrid& g = scene.grid;
  const auto& u   = solution.displacement;
  VtuData d;
  std::vector<VtuField>& point = d.point_data;
  point                        = {{"displacement", 3, {}}, {"reaction", 3, {}}};
  point[0].values.reserve(3 * static_cast<std::size_t>(g.node_count()));
  point[1].values.reserve(3 * static_cast<std::size_t>(g.node_count()));
  for (int n = 0; n < g.node_count(); ++n)
    for (int c = 0; c < 3; ++c)
      point[0].values.push_back(u(n, c)), point[1].values.push_back(solution.reaction(n, c));
  std::vector<double> stress(6 * g.cells.size()), eqps(g.cells.size());
  for (std::size_t e = 0; e < g.cells.size(); ++e) {
    const PointValues& v = element_value(scene, values, e);
    for (int k = 0; k < 6; ++k) stress[6 * e + k] = v.stress(k);
    eqps[e] = v.eqps;
  }
  d.cell_data = {{"stress", 6, std::move(stress)}, {"eqps", 1, std::move(eqps)}};
  for (auto& f : extra_cells) d.cell_data.push_back(std::move(f));
  return d;
}

class VtuSeries {
 public:
  VtuSeries(std::string dir, const Scene& scene, double step_time)
      : dir_(std::move(dir)), scene_(scene), step_time_(step_time) {}

  /// A VTU file of the increment. The mesh and the element ids are the same in every file: from the second
  /// file on they are encoded once and copied.
  void write(int step, double inc, const VtuData& arrays) {
    const IJGrid& g = scene_.grid;
    char name[48];
    split_ = step == last_step_ ? split_ + 1 : 0, last_step_ = step;
    if (inc < step - 1e-12)  // a split point of a contact step; the step's own file comes last
      std::snprintf(name, sizeof name, "step_%04d_split_%d.vtu", step, split_ + 1);
    else
      std::snprintf(name, sizeof name, "step_%04d.vtu", step);
    const std::vector<VtuField>&point = arrays.point_data, &cell = arrays.cell_data;
    if (vtu_mesh_) {
      write_vtu(dir_ + "/" + name, *vtu_mesh_, point, cell, vtu_ids_);
    } else {
      VtuMesh mesh(g.nodes, detail::grid_cells(g));
      std::string ids;
      for (const VtuField& f : detail::element_ids(scene_)) detail::append_array(ids, f);
      write_vtu(dir_ + "/" + name, mesh, point, cell, ids);
      if (++fields_written_ == 2) vtu_mesh_.emplace(std::move(mesh)), vtu_ids_ = std::move(ids);
    }
    if (!pvd_) pvd_.emplace(dir_ + "/result.pvd");
    pvd_->add(inc * step_time_, name);
  }
  void close() {
    if (pvd_) pvd_->close();
  }

 private:
  std::string dir_;
  const Scene& scene_;
  double step_time_   = 1.0;
  int fields_written_ = 0;
  std::optional<VtuMesh> vtu_mesh_;  ///< the VTU files' mesh, from the second file on
  std::string vtu_ids_;              ///< and their element ids
  std::optional<PvdFile> pvd_;       ///< result.pvd, from the first VTU file on
  int last_step_ = 0, split_ = 0;
};

}  // namespace gapfe

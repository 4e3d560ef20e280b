#pragma once
// The VTU files of a run and their collection result.pvd, for ParaView: one step_NNNN.vtu per completed
// step (step_NNNN_split_K.vtu at the points where a contact policy, load_pieces or a cut split it),
// result.pvd's timesteps t. A partitioned run (output/part_rows.hpp) writes a piece per process,
// step_NNNN_pK.vtu (K the part), and its part 0 the parallel file step_NNNN.pvtu that lists the pieces;
// result.pvd then lists the .pvtu files. Part 0 lists an increment (its .pvtu, its line in result.pvd) only
// once every part has written its piece (publish), so that a run stopped at any moment lists only whole
// increments. The pieces carry the point array `node`, each point's deck node
// number, since their points are the parts' own (a node on the parts' boundary is in each of its pieces).
#include <cstdio>
#include <mutex>
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
/// (not the mesh: the files encode theirs once, the pictures take it at the end). A part's (`rows`): its
/// local nodes (the ghosts' rows holding their owners' values) and its cells, in its order, as `values`
/// and `extra_cells` hold them, with the point array `node`.
inline VtuData vtu_arrays(const Scene& scene, const Solution& solution,
                          const std::vector<PointValues>& values, std::vector<VtuField> extra_cells,
                          const PartRows* rows = nullptr) {
  const IJGrid& g         = scene.grid;
  const auto& u           = solution.displacement;
  const int nodes         = rows ? rows->local_nodes() : g.node_count();
  const std::size_t cells = rows ? rows->element.size() : g.cells.size();
  VtuData d;
  std::vector<VtuField>& point = d.point_data;
  point                        = {{"displacement", 3, {}}, {"reaction", 3, {}}};
  point[0].values.reserve(3 * static_cast<std::size_t>(nodes));
  point[1].values.reserve(3 * static_cast<std::size_t>(nodes));
  for (int n = 0; n < nodes; ++n)
    for (int c = 0; c < 3; ++c)
      point[0].values.push_back(u(n, c)), point[1].values.push_back(solution.reaction(n, c));
  if (rows) {
    point.push_back({"node", 1, std::vector<double>(static_cast<std::size_t>(nodes)), true});
    for (int n = 0; n < nodes; ++n) point.back().values[static_cast<std::size_t>(n)] = rows->node(n) + 1;
  }
  std::vector<double> stress(6 * cells), eqps(cells);
  for (std::size_t e = 0; e < cells; ++e) {
    const PointValues& v = rows ? values[e] : element_value(scene, values, e);
    for (int k = 0; k < 6; ++k) stress[6 * e + k] = v.stress(k);
    eqps[e] = v.eqps;
  }
  d.cell_data = {{"stress", 6, std::move(stress)}, {"eqps", 1, std::move(eqps)}};
  for (auto& f : extra_cells) d.cell_data.push_back(std::move(f));
  return d;
}

class VtuSeries {
 public:
  /// `rows`: a partitioned run's part (its piece of each increment; part 0 also writes the .pvtu files and
  /// result.pvd), nullptr for the whole mesh's files.
  VtuSeries(std::string dir, const Scene& scene, double step_time, const PartRows* rows = nullptr)
      : dir_(std::move(dir)), scene_(scene), step_time_(step_time), rows_(rows) {}

  /// A VTU file of the increment (a piece, and on part 0 the .pvtu, for a part). The mesh and the element
  /// ids are the same in every file: from the second file on they are encoded once and copied.
  void write(int step, double inc, const VtuData& arrays) {
    const IJGrid& g = scene_.grid;
    char stem[40];
    split_ = step == last_step_ ? split_ + 1 : 0, last_step_ = step;
    if (inc < step - 1e-12)  // a split point of a contact step; the step's own file comes last
      std::snprintf(stem, sizeof stem, "step_%04d_split_%d", step, split_ + 1);
    else
      std::snprintf(stem, sizeof stem, "step_%04d", step);
    const std::string file =
        rows_ ? std::string(stem) + "_p" + std::to_string(rows_->part) + ".vtu" : std::string(stem) + ".vtu";
    const std::vector<VtuField>&point = arrays.point_data, &cell = arrays.cell_data;
    if (vtu_mesh_) {
      write_vtu(dir_ + "/" + file, *vtu_mesh_, point, cell, vtu_ids_);
    } else {
      VtuMesh mesh(detail::grid_points(g, rows_), detail::grid_cells(g, rows_));
      std::string ids;
      for (const VtuField& f : detail::element_ids(scene_, rows_)) detail::append_array(ids, f);
      write_vtu(dir_ + "/" + file, mesh, point, cell, ids);
      if (++fields_written_ == 2) vtu_mesh_.emplace(std::move(mesh)), vtu_ids_ = std::move(ids);
    }
    ++written_;
    if (!rows_) return list(inc * step_time_, file);
    if (rows_->part != 0) return;
    // Part 0: the increment's parallel file waits for the other parts' pieces (publish); it declares the
    // arrays (their names and types, not their values).
    Pending p{stem, inc * step_time_, {}, {}};
    for (const VtuField& f : point) p.point.push_back({f.name, f.components, {}, f.integer});
    for (const VtuField& f : cell) p.cell.push_back({f.name, f.components, {}, f.integer});
    for (VtuField& f : detail::element_ids(scene_, rows_, /*declared_only=*/true))
      p.cell.push_back(std::move(f));
    const std::lock_guard<std::mutex> hold(pending_lock_);
    pending_.push_back(std::move(p));
  }

  /// The increments this series wrote (a part: its pieces).
  std::size_t written() const { return written_; }
  /// Part 0 of a partitioned run: lists the first `complete` increments (every part has written their
  /// pieces) that are not listed yet, each as its .pvtu and a line of result.pvd. May run while write()
  /// writes a later increment on another thread (app/run_output_impl.hpp's writer): they share pending_.
  void publish(std::size_t complete) {
    for (; published_ < complete; ++published_) {
      Pending p;
      {
        const std::lock_guard<std::mutex> hold(pending_lock_);
        if (pending_.empty()) return;
        p = std::move(pending_.front());
        pending_.erase(pending_.begin());
      }
      std::vector<std::string> pieces;
      for (int k = 0; k < rows_->parts; ++k) pieces.push_back(p.stem + "_p" + std::to_string(k) + ".vtu");
      write_pvtu(dir_ + "/" + p.stem + ".pvtu", pieces, p.point, p.cell);
      list(p.time, p.stem + ".pvtu");
    }
  }
  void close() {
    if (pvd_) pvd_->close();
  }

 private:
  std::string dir_;
  const Scene& scene_;
  double step_time_     = 1.0;
  const PartRows* rows_ = nullptr;  ///< a partitioned run's part; nullptr: the whole mesh
  int fields_written_   = 0;
  std::optional<VtuMesh> vtu_mesh_;  ///< the VTU files' mesh, from the second file on
  std::string vtu_ids_;              ///< and their element ids
  std::optional<PvdFile> pvd_;       ///< result.pvd, from the first VTU file on
  int last_step_ = 0, split_ = 0;
  struct Pending {  ///< an increment part 0 has written its piece of, not yet listed
    std::string stem;
    double time = 0;
    std::vector<VtuField> point, cell;  ///< the arrays' declarations
  };
  std::vector<Pending> pending_;
  std::mutex pending_lock_;
  std::size_t written_ = 0, published_ = 0;

  /// `file` at time `t` in result.pvd.
  void list(double t, const std::string& file) {
    if (!pvd_) pvd_.emplace(dir_ + "/result.pvd");
    pvd_->add(t, file);
  }
};

}  // namespace gapfe

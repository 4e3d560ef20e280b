#pragma once
// What `gapfe run` and `gapfe mesh` leave in their output directory:
//  * nodes.csv     step,inc,t,node,i,j,r,z,u_r,u_z,u_t
//  * elements.csv  step,inc,t,element,i,j,material,r,z,s_rr,s_zz,s_tt,s_rz,s_rt,s_zt,eqps (centroids)
//  * gaps.csv      step,inc,t,element,pair,node_a,node_b,status,gap,f_n,f_t per gap node pair (decks with
//                  gap elements)
//  * reactions.csv step,inc,t,node,i,j,r,z,R_r,R_z,R_t at every node with a prescribed component (BC card
//                  code != 0, or a face SAAC3X drives): the total ring reaction force, 0 in the free
//                  components; R_t is a force along theta (its torque about the axis is R_t r)
//  * result.pvd    one step_NNNN.vtu per completed step (step_NNNN_split_K.vtu at the points where a
//                  contact policy, load_pieces or a cut split the step), for ParaView
//  * deformed.svg  the last increment's deformed mesh (magnified), gap elements coloured open/closed
//  * plot_FIELD.svg the last increment's field on the deformed mesh (output/field_plot.hpp;
//  StepFiles::draw_fields)
//  * history.csv   one row per increment of a run of several steps (output/history_file.hpp)
//  * mesh.svg, mesh_nodes.csv, mesh_elements.csv, mesh.vtu (gapfe mesh: the grid with its numbers)
// A partitioned run writes these per process instead (output/part_rows.hpp; docs/cluster.md "Output"):
//  * nodes_pK.csv, elements_pK.csv, reactions_pK.csv: part K's rows, the same columns
//  * step_NNNN_pK.vtu: part K's piece; step_NNNN.pvtu lists the pieces, result.pvd the .pvtu files
// and part 0 alone the files of the whole run (history.csv, gaps.csv, plasticity.csv, deformed.svg and the
// pictures, which meshes of more than kSvgCellLimit cells do without).
// One header line per CSV, one block of rows per completed step, steps from 1; `inc` is the number
// of load increments applied so far and t = inc x the time a load step lasts (card 0's delta t in a
// rate-dependent deck, else 1: t = inc); result.pvd's timesteps are t. Node and element numbers are the
// deck's (1-based). Stresses in the deck's units, tension positive; s_rt is the theta-r shear, s_zt the
// z-theta shear. CSV rows are flushed after each step, so the steps before a failure survive it.
#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "gapfe/input/scene.hpp"
#include "gapfe/output/deformed_svg.hpp"
#include "gapfe/output/field_plot.hpp"
#include "gapfe/output/gap_file.hpp"
#include "gapfe/output/grid_arrays.hpp"
#include "gapfe/output/history_file.hpp"
#include "gapfe/output/mesh_files.hpp"
#include "gapfe/output/part_rows.hpp"
#include "gapfe/output/result_tables.hpp"
#include "gapfe/output/vtu_series.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

/// Writes the per-step result files of a run into `dir` (which must exist), each kind by its own writer:
/// the tables (ResultTables), the VTU files (VtuSeries), history.csv (HistoryFile), deformed.svg
/// (write_deformed_svg) and the field pictures (write_field_svg).
class StepFiles {
 public:
  /// `step_time`: how long a load step lasts (ModelDescription::step_time()), for the t column. `tables`
  /// (nodes.csv, elements.csv, reactions.csv) and `fields` (the VTU files, result.pvd): every increment, the
  /// last one (write() keeps it, finish() writes it) or none. `rows`: a partitioned run's part (its own
  /// tables and VTU pieces; the pictures only on part 0, from keep_last), nullptr for the whole mesh's.
  StepFiles(std::string dir, const Scene& scene, double step_time = 1.0, Increments tables = Increments::all,
            Increments fields = Increments::all, const PartRows* rows = nullptr)
      : dir_(std::move(dir)),
        scene_(scene),
        step_time_(step_time),
        tables_kind_(tables),
        fields_kind_(fields),
        rows_(rows) {
    if (tables != Increments::none) tables_.emplace(dir_, scene_, step_time_, rows_);
    if (fields != Increments::none) fields_.emplace(dir_, scene_, step_time_, rows_);
  }

  /// One increment: the nodal solution and the centroid values (one per cell, cells then triangles, as
  /// a driver's centroid_values() gives them); `extra_cells` are more VTU cell arrays (gap_fields'). A
  /// part's are its own (vtu_arrays).
  void write(int step, double inc, const Solution& solution, const std::vector<PointValues>& values,
             std::vector<VtuField> extra_cells = {}, const IncrementSummary& summary = {}) {
    if (history_) history_->write(step, inc, solution, summary);
    if (!rows_) keep_last(solution, values, extra_cells, /*arrays=*/false);
    const bool tables = tables_kind_ == Increments::all, fields = fields_kind_ == Increments::all;
    if (tables_kind_ == Increments::last || fields_kind_ == Increments::last)
      held_ = Held{step, inc, solution, values, fields ? std::vector<VtuField>{} : extra_cells};
    if (tables) tables_->write(step, inc, solution, values);
    const bool picture = !rows_ && draws_fields();
    if (!fields && !picture) return;
    VtuData arrays = vtu_arrays(scene_, solution, values, std::move(extra_cells), rows_);
    if (fields) fields_->write(step, inc, arrays);
    if (picture) last_arrays_ = std::move(arrays);
  }

  /// What finish() draws deformed.svg and the pictures from: the increment's whole solution, centroid values
  /// and cell arrays (a partitioned run's part 0 is given them gathered, on meshes it draws: draws()).
  /// `arrays`: the pictures' arrays too (write() makes them for a whole run).
  void keep_last(const Solution& whole, const std::vector<PointValues>& values,
                 const std::vector<VtuField>& extra_cells, bool arrays = true) {
    last_displacement_ = whole.displacement;  // deformed.svg's
    for (const auto& f : extra_cells)
      if (f.name == "gap_state") last_gap_state_ = f.values;
    if (arrays && draws_fields()) last_arrays_ = vtu_arrays(scene_, whole, values, extra_cells);
  }
  /// Whether finish() draws the pictures of fields (some asked for, a mesh small enough to draw).
  bool draws_fields() const { return !pictures_.empty() && scene_.grid.cells.size() <= kSvgCellLimit; }
  /// Whether a partitioned run gathers the whole mesh's results for deformed.svg and the pictures: it draws
  /// those of meshes of at most kSvgCellLimit cells, whose gather costs little, and no others.
  bool draws() const { return scene_.grid.cells.size() <= kSvgCellLimit; }

  /// history.csv (output/history_file.hpp) for a run of `steps` load steps, when there is more than one, with
  /// the optional `columns`.
  void keep_history(int steps, HistoryColumns columns = {}) {
    if (steps > 1) history_.emplace(dir_, scene_, steps, step_time_, columns);
  }

  /// The fields (output/field_plot.hpp) finish() draws for the last increment, as plot_FIELD.svg, in `units`;
  /// none by default. Meshes of more than kSvgCellLimit cells are left to `gapfe plot`.
  void draw_fields(std::vector<std::string> fields, PlotUnits units) {
    for (const auto& f : fields)
      if (std::find(plot_field_names().begin(), plot_field_names().end(), f) == plot_field_names().end())
        throw InputError("unknown field '" + f + "' to plot (known: " + detail::names_text() + ")");
    pictures_ = std::move(fields), units_ = std::move(units);
  }
  /// The pictures finish() wrote (paths), and the fields it did not draw with why.
  const std::vector<std::string>& pictures_written() const { return pictures_written_; }
  const std::string& pictures_skipped() const { return pictures_skipped_; }

  /// A partitioned run's VTU series (VtuSeries::publish, on part 0): the first `complete` increments are
  /// written by every part and may be listed.
  void publish(std::size_t complete) {
    if (fields_) fields_->publish(complete);
  }
  /// A partitioned run's VTU series closed after finish(): with `complete` (every part has finished its
  /// files) every increment listed, else only those published.
  void close_series(bool complete) {
    if (!fields_ || !rows_) return;
    if (complete) fields_->publish(fields_->written());
    fields_->close();
  }

  /// The end of a run: the held increment (a kind written `last`), the tables closed, then deformed.svg.
  void finish(const std::string& title) {
    if (held_) {
      Held h = std::move(*held_);
      held_.reset();
      if (tables_kind_ == Increments::last) tables_->write(h.step, h.inc, h.solution, h.values);
      if (fields_kind_ == Increments::last)
        fields_->write(h.step, h.inc,
                       vtu_arrays(scene_, h.solution, h.values, std::move(h.extra_cells), rows_));
    }
    if (tables_) tables_->close();
    if (fields_ && !rows_) fields_->close();  // a part's: close_series
    if (history_) history_->close();
    pictures_written_.clear(), pictures_skipped_.clear();
    if (rows_ && rows_->part != 0) return;  // part 0 draws
    if (rows_ && !draws()) {
      pictures_skipped_ = "deformed.svg" + std::string(pictures_.empty() ? "" : " and the fields") + ": " +
                          std::to_string(scene_.grid.cells.size()) +
                          " cells in a partitioned run, more than " + std::to_string(kSvgCellLimit) +
                          " (gapfe plot draws the fields from the VTU pieces)";
      return;
    }
    write_deformed_svg(dir_, scene_, last_displacement_, last_gap_state_, title);
    if (pictures_.empty()) return;
    if (scene_.grid.cells.size() > kSvgCellLimit) {
      pictures_skipped_ = std::to_string(scene_.grid.cells.size()) + " cells, more than " +
                          std::to_string(kSvgCellLimit) + " (gapfe plot draws them on request)";
      return;
    }
    if (last_arrays_.point_data.empty()) return;  // no increment
    last_arrays_.points = scene_.grid.nodes;      // the mesh, once
    for (const GridCell& c : scene_.grid.cells)
      last_arrays_.cells.emplace_back(c.node.begin(), c.node.begin() + c.corners);
    for (const VtuField& f : detail::element_ids(scene_)) last_arrays_.cell_data.push_back(f);  // material
    for (const auto& name : pictures_) {
      const std::string path = dir_ + "/plot_" + name + ".svg";
      try {
        write_field_svg(path, last_arrays_, plot_field(last_arrays_, name, units_), title, units_);
        pictures_written_.push_back(path);
      } catch (const InputError& e) {  // a field this run has not got (gap_state without gaps)
        pictures_skipped_ += (pictures_skipped_.empty() ? "" : "; ") + std::string(e.what());
      }
    }
  }

 private:
  std::string dir_;
  const Scene& scene_;
  double step_time_ = 1.0;
  Increments tables_kind_, fields_kind_;
  const PartRows* rows_ = nullptr;  ///< a partitioned run's part; nullptr: the whole mesh
  std::optional<ResultTables> tables_;
  std::optional<VtuSeries> fields_;
  struct Held {
    int step;
    double inc;
    Solution solution;
    std::vector<PointValues> values;
    std::vector<VtuField> extra_cells;
  };
  std::optional<Held> held_;  ///< a kind written `last`: the latest increment, written by finish()
  Eigen::Matrix<double, Eigen::Dynamic, 3> last_displacement_;
  std::vector<double> last_gap_state_;
  std::optional<HistoryFile> history_;
  std::vector<std::string> pictures_;  ///< fields drawn at the end (draw_fields)
  PlotUnits units_;
  VtuData last_arrays_;  ///< the last increment's arrays and mesh, for the pictures
  std::vector<std::string> pictures_written_;
  std::string pictures_skipped_;
};

}  // namespace gapfe

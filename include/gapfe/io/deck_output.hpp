#pragma once
// What `gapfe run` and `gapfe mesh` leave in their output directory (the deck issue's contract):
//  * nodes.csv     step,inc,t,node,i,j,r,z,u_r,u_z,u_t
//  * elements.csv  step,inc,t,element,i,j,material,r,z,s_rr,s_zz,s_tt,s_rz,s_rt,s_zt,eqps (centroids)
//  * gaps.csv      step,inc,t,element,pair,node_a,node_b,status,gap,f_n,f_t per gap node pair (decks with
//                  gap elements)
//  * reactions.csv step,inc,t,node,i,j,r,z,R_r,R_z,R_t at every node with a prescribed component (BC card
//                  code != 0, or a face SAAC3X drives): the total ring reaction force, 0 in the free
//                  components; R_t is a force along theta (its torque about the axis is R_t r)
//  * result.pvd    one step_NNNN.vtu per completed step (step_NNNN_split_K.vtu at the points where a
//                  contact policy split the step), for ParaView
//  * deformed.svg  the last increment's deformed mesh (magnified), gap elements coloured open/closed
//  * plot_FIELD.svg the last increment's field on the deformed mesh (io/field_plot.hpp;
//  StepFiles::draw_fields)
//  * history.csv   one row per increment of a run of several steps (io/history_file.hpp)
//  * mesh.svg, mesh_nodes.csv, mesh_elements.csv, mesh.vtu (gapfe mesh: the grid with its numbers)
// One header line per CSV, one block of rows per completed step, steps from 1; `inc` is the number
// of load increments applied so far and t = inc x the time a load step lasts (card 0's delta t in a
// rate-dependent deck, else 1: t = inc); result.pvd's timesteps are t. Node and element numbers are the
// deck's (1-based). Stresses in the deck's units, tension positive; s_rt is the theta-r shear, s_zt the
// z-theta shear. CSV rows are flushed after each step, so the steps before a failure survive it.
#include <algorithm>
#include <array>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "gapfe/contact/pair_state.hpp"
#include "gapfe/io/deck_scene.hpp"
#include "gapfe/io/field_plot.hpp"
#include "gapfe/io/history_file.hpp"
#include "gapfe/io/output_file.hpp"
#include "gapfe/io/svg_canvas.hpp"
#include "gapfe/io/vtu_writer.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

namespace detail {

inline VtuCells grid_cells(const IJGrid& g) {
  VtuCells cells;
  for (const auto& c : g.cells) cells.add(c.node.data(), c.corners);
  return cells;
}

/// Cell arrays every VTU of a deck carries: the deck's material number and the element number.
inline std::vector<VtuField> element_ids(const DeckScene& s) {
  std::vector<VtuField> f{{"material", 1, {}, true}, {"element", 1, {}, true}};
  for (std::size_t e = 0; e < s.grid.cells.size(); ++e)
    f[0].values.push_back(s.material_id[e]), f[1].values.push_back(static_cast<double>(e + 1));
  return f;
}

/// The outline (io/svg_canvas.hpp, outline_sides) of an I-J grid's cells.
inline std::vector<std::array<int, 2>> outline_edges(const IJGrid& g, const std::vector<int>& material) {
  return outline_sides(
      g.cells.size(),
      [&](std::size_t e, auto&& side) {
        const GridCell& c = g.cells[e];
        for (int k = 0; k < c.corners; ++k) side(c.node[k], c.node[(k + 1) % c.corners]);
      },
      material);
}

inline void csv_number(std::string& s, double v) {
  append_number(s, v);
  s += ',';
}

/// The first three columns of every result row: step,inc,t, (t = inc x step_time, see the top).
inline void csv_increment(std::string& s, int step, double inc, double step_time) {
  append_number(s, static_cast<long long>(step)), s += ',';
  csv_number(s, inc);
  csv_number(s, inc * step_time);
}

inline constexpr const char* kMaterialFill[] = {"#dbe8f6", "#f6e3c9", "#d8f0d2",
                                                "#eed8f0", "#f3f0c8", "#d5eeee"};

}  // namespace detail

/// Writes the per-step result files of a run into `dir` (which must exist).
class StepFiles {
 public:
  /// `step_time`: how long a load step lasts (Deck::step_time()), for the t column. `tables` (nodes.csv,
  /// elements.csv, reactions.csv) and `fields` (the VTU files, result.pvd): every increment, the last one
  /// (write() keeps it, finish() writes it) or none.
  StepFiles(std::string dir, const DeckScene& scene, double step_time = 1.0,
            Increments tables = Increments::all, Increments fields = Increments::all)
      : dir_(std::move(dir)), scene_(scene), step_time_(step_time), tables_(tables), fields_(fields) {
    prescribed_.assign(static_cast<std::size_t>(scene.grid.node_count()), 0);
    for (const NodalCondition& c : scene.conditions) {  // later conditions win in what they set (DofMap)
      int& code = prescribed_[static_cast<std::size_t>(c.node)];
      code      = (code & ~c.sets) | (c.code & c.sets);
    }
    for (const int n : scene.strain_rate_test.bottom) prescribed_[static_cast<std::size_t>(n)] |= 2 | 4;
    for (const int n : scene.strain_rate_test.top) prescribed_[static_cast<std::size_t>(n)] |= 2;
    if (tables_ == Increments::none) return;
    nodes_ = OutputFile(dir_ + "/nodes.csv");
    nodes_.append("step,inc,t,node,i,j,r,z,u_r,u_z,u_t\n");
    reactions_ = OutputFile(dir_ + "/reactions.csv");
    reactions_.append("step,inc,t,node,i,j,r,z,R_r,R_z,R_t\n");
    elements_ = OutputFile(dir_ + "/elements.csv");
    elements_.append("step,inc,t,element,i,j,material,r,z,s_rr,s_zz,s_tt,s_rz,s_rt,s_zt,eqps\n");
  }

  /// One increment: the nodal solution and the centroid values (one per cell, cells then triangles, as
  /// a driver's centroid_values() gives them); `extra_cells` are more VTU cell arrays (GapFile's).
  void write(int step, double inc, const Solution& solution, const std::vector<PointValues>& values,
             std::vector<VtuField> extra_cells = {}, const IncrementSummary& summary = {}) {
    if (history_) history_->write(step, inc, solution, summary);
    last_displacement_ = solution.displacement;  // deformed.svg's
    for (const auto& f : extra_cells)
      if (f.name == "gap_state") last_gap_state_ = f.values;
    const bool tables = tables_ == Increments::all, fields = fields_ == Increments::all;
    if (tables_ == Increments::last || fields_ == Increments::last)
      held_ = Held{step, inc, solution, values, fields ? std::vector<VtuField>{} : extra_cells};
    if (tables) write_tables(step, inc, solution, values);
    const bool picture = !pictures_.empty() && scene_.grid.cells.size() <= kSvgCellLimit;
    if (!fields && !picture) return;
    VtuData arrays = vtu_arrays(solution, values, std::move(extra_cells));
    if (fields) write_fields(step, inc, arrays);
    if (picture) last_arrays_ = std::move(arrays);
  }

  /// history.csv (io/history_file.hpp) for a run of `steps` load steps, when there is more than one, with
  /// the optional `columns`.
  void keep_history(int steps, HistoryColumns columns = {}) {
    if (steps > 1) history_.emplace(dir_, scene_, steps, step_time_, columns);
  }

  /// The fields (io/field_plot.hpp) finish() draws for the last increment, as plot_FIELD.svg, in `units`;
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

  /// The end of a run: the held increment (a kind written `last`), the tables closed, then deformed.svg.
  void finish(const std::string& title) {
    if (held_) {
      Held h = std::move(*held_);
      held_.reset();
      if (tables_ == Increments::last) write_tables(h.step, h.inc, h.solution, h.values);
      if (fields_ == Increments::last)
        write_fields(h.step, h.inc, vtu_arrays(h.solution, h.values, std::move(h.extra_cells)));
    }
    for (OutputFile* f : {&nodes_, &reactions_, &elements_}) f->close();
    if (pvd_) pvd_->close();
    if (history_) history_->close();
    write_deformed(title);
    pictures_written_.clear(), pictures_skipped_.clear();
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
  /// The tables' rows, written in chunks (a 1e6-node table is 100 MB of text). Every row starts with the
  /// increment's step,inc,t and the mesh's part of the row (node,i,j,r,z or element,i,j,material,r,z),
  /// which is formatted once, at the second increment written, and copied from then on.
  void write_tables(int step, double inc, const Solution& solution, const std::vector<PointValues>& values) {
    const IJGrid& g = scene_.grid;
    const auto& u   = solution.displacement;
    std::string prefix;
    detail::csv_increment(prefix, step, inc, step_time_);
    if (++tables_written_ == 2) {
      for (int n = 0; n < g.node_count(); ++n)
        node_head(node_heads_, n), node_head_end_.push_back(node_heads_.size());
      for (std::size_t e = 0; e < g.cells.size(); ++e)
        element_head(element_heads_, e, by_element(values, e)),
            element_head_end_.push_back(element_heads_.size());
    }
    const auto head = [](std::string& s, const std::string& heads, const std::vector<std::size_t>& end,
                         std::size_t k) {
      s.append(heads, k == 0 ? 0 : end[k - 1], end[k] - (k == 0 ? 0 : end[k - 1]));
    };
    std::string s;
    constexpr std::size_t kChunk = std::size_t(1) << 20;
    s.reserve(kChunk + 512);
    const auto row_end = [&](OutputFile& out) {  // (a piece of whole rows, one write: see output_file.hpp)
      s += '\n';
      if (s.size() >= kChunk) out.append(s), s.clear();
    };
    const auto flush  = [&](OutputFile& out) { out.append(s), s.clear(); };
    const bool cached = !node_heads_.empty();
    for (int n = 0; n < g.node_count(); ++n) {
      s += prefix;
      cached ? head(s, node_heads_, node_head_end_, static_cast<std::size_t>(n)) : node_head(s, n);
      detail::csv_number(s, u(n, 0)), detail::csv_number(s, u(n, 1)), detail::append_number(s, u(n, 2));
      row_end(nodes_);
    }
    flush(nodes_);
    for (int n = 0; n < g.node_count(); ++n) {
      const int code = prescribed_[static_cast<std::size_t>(n)];
      if (code == 0) continue;
      s += prefix;
      cached ? head(s, node_heads_, node_head_end_, static_cast<std::size_t>(n)) : node_head(s, n);
      for (int c = 0; c < 3; ++c) {
        detail::append_number(s, (code >> c) & 1 ? solution.reaction(n, c) : 0.0);
        if (c < 2) s += ',';
      }
      row_end(reactions_);
    }
    flush(reactions_);
    for (std::size_t e = 0; e < g.cells.size(); ++e) {
      const PointValues& v = by_element(values, e);
      s += prefix;
      cached ? head(s, element_heads_, element_head_end_, e) : element_head(s, e, v);
      for (const int k : {voigt::rr, voigt::zz, voigt::hoop, voigt::rz, voigt::theta_r, voigt::z_theta})
        detail::csv_number(s, v.stress(k));
      detail::append_number(s, v.eqps);
      row_end(elements_);
    }
    flush(elements_);
  }
  /// "node,i,j,r,z," of node n (0-based; the table's node numbers are the deck's, 1-based).
  void node_head(std::string& s, int n) const {
    const IJGrid& g = scene_.grid;
    for (const int k : {n + 1, g.node_ij[n][0], g.node_ij[n][1]})
      detail::append_number(s, static_cast<long long>(k)), s += ',';
    detail::csv_number(s, g.nodes[n](0)), detail::csv_number(s, g.nodes[n](1));
  }
  /// "element,i,j,material,r,z," of element e at its centroid value v.
  void element_head(std::string& s, std::size_t e, const PointValues& v) const {
    const GridCell& c = scene_.grid.cells[e];
    for (const int k : {static_cast<int>(e) + 1, c.i, c.j, scene_.material_id[e]})
      detail::append_number(s, static_cast<long long>(k)), s += ',';
    detail::csv_number(s, v.r), detail::csv_number(s, v.z);
  }

  /// The increment's VTU arrays: displacement and reaction per node; stress, eqps and `extra_cells` per cell
  /// (not the mesh: the files encode theirs once, the pictures take it at the end).
  VtuData vtu_arrays(const Solution& solution, const std::vector<PointValues>& values,
                     std::vector<VtuField> extra_cells) const {
    const IJGrid& g = scene_.grid;
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
      const PointValues& v = by_element(values, e);
      for (int k = 0; k < 6; ++k) stress[6 * e + k] = v.stress(k);
      eqps[e] = v.eqps;
    }
    d.cell_data = {{"stress", 6, std::move(stress)}, {"eqps", 1, std::move(eqps)}};
    for (auto& f : extra_cells) d.cell_data.push_back(std::move(f));
    return d;
  }

  /// A VTU file of the increment. The mesh and the element ids are the same in every file: from the second
  /// file on they are encoded once and copied.
  void write_fields(int step, double inc, const VtuData& arrays) {
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

  /// The centroid values of deck element e: they come cells first, then triangles.
  const PointValues& by_element(const std::vector<PointValues>& values, std::size_t e) const {
    const GridCell& c = scene_.grid.cells[e];
    return values[(c.corners == 4 ? 0 : scene_.mesh.cells.size()) + static_cast<std::size_t>(c.group_index)];
  }

 public:
  /// Above this many cells deformed.svg draws the outline (boundary and material interfaces) instead
  /// of every cell: a picture of 1e5 cells shows no cell, and writing it cost 10% of a 1e5-equation run.
  static constexpr std::size_t kSvgCellLimit = 20000;

  /// deformed.svg: the last increment's deformed mesh over the undeformed outline, displacements
  /// magnified to 5% of the section (a 1-2-5 factor, printed); gap elements coloured by their state.
  /// Meshes of more than kSvgCellLimit cells: the deformed outline over the undeformed one.
  void write_deformed(const std::string& title) const {
    const IJGrid& g = scene_.grid;
    if (last_displacement_.rows() != g.node_count()) return;  // no increment written
    const double factor =
        picture_magnification(g.nodes, last_displacement_.leftCols<2>().rowwise().norm().maxCoeff());
    std::vector<Vec2> deformed(g.nodes), both(g.nodes);
    for (int n = 0; n < g.node_count(); ++n) {
      deformed[n] = g.nodes[n] + factor * last_displacement_.row(n).head<2>().transpose();
      both.push_back(deformed[n]);
    }
    std::string factor_text;
    detail::append_number(factor_text, factor);
    detail::SvgCanvas svg(both, title + ": deformed x " + factor_text + " over the undeformed outline (grey)",
                          50);
    const bool gaps = !last_gap_state_.empty();
    if (g.cells.size() > kSvgCellLimit) {
      const auto edges = detail::outline_edges(g, scene_.material_id);
      for (const std::vector<Vec2>* x : {&g.nodes, static_cast<const std::vector<Vec2>*>(&deformed)})
        for (const auto& [a, b] : edges)
          svg.polygon(std::array<Vec2, 2>{(*x)[a], (*x)[b]}, 2, "none", x == &g.nodes ? "#b0b0b0" : "#333",
                      x == &g.nodes ? 0.5 : 0.8);
    }
    for (const auto& c : g.cells) {
      if (g.cells.size() > kSvgCellLimit) break;
      std::array<Vec2, 4> x;
      for (int k = 0; k < c.corners; ++k) x[k] = g.nodes[c.node[k]];
      svg.polygon(x, c.corners, "none", "#b0b0b0", 0.5);
    }
    // Structural cells first, then the gap elements on top with a heavy outline in their state's colour:
    // gap elements are usually slivers, and a sliver's outline is what stays visible.
    for (const bool gap_pass : {false, true})
      for (std::size_t e = 0; e < g.cells.size(); ++e) {
        const double state = gaps ? last_gap_state_[e] : 0;
        if ((state != 0) != gap_pass || (!gap_pass && g.cells.size() > kSvgCellLimit)) continue;
        const GridCell& c = g.cells[e];
        std::array<Vec2, 4> x;
        for (int k = 0; k < c.corners; ++k) x[k] = deformed[c.node[k]];
        if (!gap_pass) {
          svg.polygon(x, c.corners, detail::kMaterialFill[(std::max(scene_.material_id[e], 1) - 1) % 6],
                      "#333", 0.6);
          continue;
        }
        const char* colour = state < 0 ? "#8c8c8c" : state == 1 ? "#1f77b4" : "#d62728";
        svg.polygon(x, c.corners, colour, colour, 3.0);
      }
    if (gaps)
      svg.text(10, svg.height - 12, 13,
               "gap elements: red = closed (a node pair in contact), blue = open, grey = soft throughout "
               "(corners, IJDIR 0)");
    svg.save(dir_ + "/deformed.svg");
  }

 private:
  std::string dir_;
  const DeckScene& scene_;
  double step_time_ = 1.0;
  Increments tables_, fields_;
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
  OutputFile nodes_, elements_, reactions_;
  std::vector<int> prescribed_;  ///< per node: the OR of its BC codes (1 u_r, 2 u_z, 4 u_theta)
  int tables_written_ = 0, fields_written_ = 0;
  std::string node_heads_, element_heads_;  ///< the rows' mesh parts, from the second increment on
  std::vector<std::size_t> node_head_end_, element_head_end_;
  std::optional<VtuMesh> vtu_mesh_;  ///< the VTU files' mesh, from the second file on
  std::string vtu_ids_;              ///< and their element ids
  std::optional<PvdFile> pvd_;       ///< result.pvd, from the first VTU file on
  int last_step_ = 0, split_ = 0;
};

/// gaps.csv: one row per gap node pair per increment; status open | closed, or with friction open |
/// stick | slip; gap [length] (negative: overlap), f_n the normal force and f_t the resultant tangential
/// (friction) force |t| (total ring forces, f_n compressive positive; f_t 0 without friction). Element
/// numbers are the deck's, pair 1 | 2 the seed's contact states 2 | 3, node_a and node_b the pair's nodes
/// (the gap closes from a towards b). A status is the one the increment was solved with (for the seed's
/// extended model: the stick or slip its stress check chose at the increment before).
class GapFile {
 public:
  GapFile(const std::string& dir, const DeckScene& scene, bool friction = false, double step_time = 1.0)
      : scene_(scene), friction_(friction), step_time_(step_time) {
    out_ = OutputFile(dir + "/gaps.csv");
    out_.append("step,inc,t,element,pair,node_a,node_b,status,gap,f_n,f_t\n");
  }
  /// Writes the rows and returns the VTU cell arrays: gap_state (0 structural, -1 a gap element that
  /// stays soft, else the seed's contact state 1-4), gap_size (smallest pair gap, 0 elsewhere) and
  /// contact_force (the sum of its pairs' normal forces f_n, total ring force, compression positive).
  std::vector<VtuField> write(int step, double inc, const std::vector<GapPair>& pairs,
                              const std::vector<PairState>& states) {
    const std::size_t ne = scene_.grid.cells.size();
    VtuField state{"gap_state", 1, std::vector<double>(ne, 0.0), true},
        size{"gap_size", 1, std::vector<double>(ne, 0.0)},
        force{"contact_force", 1, std::vector<double>(ne, 0.0)};
    for (const int e : scene_.gaps.soft) state.values[static_cast<std::size_t>(e)] = -1;
    std::string s;
    for (std::size_t q = 0; q < pairs.size(); ++q) {
      const GapPair& p    = pairs[q];
      const PairState& st = states[q];
      const std::size_t e = static_cast<std::size_t>(p.element);
      detail::csv_increment(s, step, inc, step_time_);
      detail::append_number(s, static_cast<long long>(p.element + 1)), s += ',';
      detail::append_number(s, static_cast<long long>(p.pair + 1)), s += ',';
      detail::append_number(s, static_cast<long long>(p.node_a + 1)), s += ',';
      detail::append_number(s, static_cast<long long>(p.node_b + 1));
      s += !st.closed ? ",open," : !friction_ ? ",closed," : st.slipping ? ",slip," : ",stick,";
      detail::csv_number(s, st.gap), detail::csv_number(s, st.normal_force);
      detail::append_number(s, st.tangential_force.norm()), s += '\n';
      if (e >= ne) continue;  // a scene's gap element without a cell (io/scene_file.hpp): no cell to mark
      if (state.values[e] == 0) state.values[e] = 1, size.values[e] = st.gap;
      size.values[e] = std::min(size.values[e], st.gap);
      force.values[e] += st.normal_force;
      if (st.closed) state.values[e] += p.pair == 0 ? 1 : 2;  // 1 none, 2 first, 3 second, 4 both
    }
    out_.append(s);
    return {std::move(state), std::move(size), std::move(force)};
  }
  void close() { out_.close(); }

 private:
  const DeckScene& scene_;
  bool friction_;
  double step_time_ = 1.0;
  OutputFile out_;
};

/// `gapfe mesh`: mesh.svg (the grid with node and element numbers, like the seed's plot option),
/// mesh_nodes.csv, mesh_elements.csv and mesh.vtu in `dir`.
inline void write_mesh_files(const std::string& dir, const Deck& d, const DeckScene& s) {
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

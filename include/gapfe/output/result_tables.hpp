#pragma once
// nodes.csv, reactions.csv and elements.csv of a run (the columns: output/step_files.hpp): one block of rows
// per increment written, flushed after each, so the increments before a failure survive it. A process of a
// partitioned run writes its own share (output/part_rows.hpp) as nodes_pK.csv, reactions_pK.csv and
// elements_pK.csv (K its part): the same columns and numbers, the rows of the nodes it owns and its cells.
#include <string>
#include <vector>

#include "gapfe/input/scene.hpp"
#include "gapfe/output/csv_rows.hpp"
#include "gapfe/output/output_file.hpp"
#include "gapfe/output/part_rows.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

/// Where deck element e is among a driver's centroid_values() (and any array in their order): cells first,
/// then triangles.
inline std::size_t element_index(const Scene& scene, std::size_t e) {
  const GridCell& c = scene.grid.cells[e];
  return (c.corners == 4 ? 0 : scene.mesh.cells.size()) + static_cast<std::size_t>(c.group_index);
}

/// The centroid values of deck element e among a driver's centroid_values().
inline const PointValues& element_value(const Scene& scene, const std::vector<PointValues>& values,
                                        std::size_t e) {
  return values[element_index(scene, e)];
}

class ResultTables {
 public:
  /// Opens the three tables in `dir` with their header lines; `step_time`: how long a load step lasts;
  /// `rows`: a partitioned run's part (its own tables), nullptr for the whole mesh's.
  ResultTables(const std::string& dir, const Scene& scene, double step_time, const PartRows* rows = nullptr)
      : scene_(scene), step_time_(step_time), rows_(rows) {
    prescribed_.assign(static_cast<std::size_t>(scene.grid.node_count()), 0);
    for (const NodalCondition& c : scene.conditions) {  // later conditions win in what they set (DofMap)
      int& code = prescribed_[static_cast<std::size_t>(c.node)];
      code      = (code & ~c.sets) | (c.code & c.sets);
    }
    for (const int n : scene.strain_rate_test.bottom) prescribed_[static_cast<std::size_t>(n)] |= 2 | 4;
    for (const int n : scene.strain_rate_test.top) prescribed_[static_cast<std::size_t>(n)] |= 2;
    const std::string end = rows ? "_p" + std::to_string(rows->part) + ".csv" : ".csv";
    nodes_                = OutputFile(dir + "/nodes" + end);
    nodes_.append("step,inc,t,node,i,j,r,z,u_r,u_z,u_t\n");
    reactions_ = OutputFile(dir + "/reactions" + end);
    reactions_.append("step,inc,t,node,i,j,r,z,R_r,R_z,R_t\n");
    elements_ = OutputFile(dir + "/elements" + end);
    elements_.append("step,inc,t,element,i,j,material,r,z,s_rr,s_zz,s_tt,s_rz,s_rt,s_zt,eqps\n");
  }

  /// The tables' rows, formatted on every thread and written in chunks (a 1e6-node table is 100 MB of text).
  /// Every row starts with the increment's step,inc,t and the mesh's part of the row (node,i,j,r,z or
  /// element,i,j,material,r,z), which is formatted once, at the second increment written, and copied from
  /// then on. A part's `solution` and `values` are its own (local nodes, its cells in centroid order).
  void write(int step, double inc, const Solution& solution, const std::vector<PointValues>& values) {
    const IJGrid& g = scene_.grid;
    const auto& u   = solution.displacement;
    std::string prefix;
    detail::csv_increment(prefix, step, inc, step_time_);
    const std::size_t nodes    = rows_ ? static_cast<std::size_t>(rows_->owned_nodes())
                                       : static_cast<std::size_t>(g.node_count()),
                      elements = rows_ ? rows_->element.size() : g.cells.size();
    const auto node            = [&](std::size_t n) {
      return rows_ ? rows_->node(static_cast<int>(n)) : static_cast<int>(n);
    };
    const auto element = [&](std::size_t k) {
      return rows_ ? static_cast<std::size_t>(rows_->element[k]) : k;
    };
    const auto value = [&](std::size_t k) -> const PointValues& {
      return rows_ ? values[k] : by_element(values, k);
    };
    if (++tables_written_ == 2) {
      for (std::size_t n = 0; n < nodes; ++n)
        node_head(node_heads_, node(n)), node_head_end_.push_back(node_heads_.size());
      for (std::size_t k = 0; k < elements; ++k)
        element_head(element_heads_, element(k), value(k)),
            element_head_end_.push_back(element_heads_.size());
    }
    const auto head = [](std::string& s, const std::string& heads, const std::vector<std::size_t>& end,
                         std::size_t k) {
      s.append(heads, k == 0 ? 0 : end[k - 1], end[k] - (k == 0 ? 0 : end[k - 1]));
    };
    const bool cached = !node_heads_.empty();
    // Rows formatted on every thread, written in order (detail::write_rows).
    detail::write_rows(nodes_, nodes, [&](std::string& s, std::size_t n) {
      const auto i = static_cast<Eigen::Index>(n);
      s += prefix;
      cached ? head(s, node_heads_, node_head_end_, n) : node_head(s, node(n));
      detail::csv_number(s, u(i, 0)), detail::csv_number(s, u(i, 1)), detail::append_number(s, u(i, 2));
      return true;
    });
    detail::write_rows(reactions_, nodes, [&](std::string& s, std::size_t n) {
      const int code = prescribed_[static_cast<std::size_t>(node(n))];
      if (code == 0) return false;
      s += prefix;
      cached ? head(s, node_heads_, node_head_end_, n) : node_head(s, node(n));
      for (int c = 0; c < 3; ++c) {
        detail::append_number(s, (code >> c) & 1 ? solution.reaction(static_cast<Eigen::Index>(n), c) : 0.0);
        if (c < 2) s += ',';
      }
      return true;
    });
    detail::write_rows(elements_, elements, [&](std::string& s, std::size_t row) {
      const PointValues& v = value(row);
      s += prefix;
      cached ? head(s, element_heads_, element_head_end_, row) : element_head(s, element(row), v);
      for (const int k : {voigt::rr, voigt::zz, voigt::hoop, voigt::rz, voigt::theta_r, voigt::z_theta})
        detail::csv_number(s, v.stress(k));
      detail::append_number(s, v.eqps);
      return true;
    });
  }

  void close() {
    for (OutputFile* f : {&nodes_, &reactions_, &elements_}) f->close();
  }

 private:
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
  const PointValues& by_element(const std::vector<PointValues>& values, std::size_t e) const {
    return element_value(scene_, values, e);
  }

  const Scene& scene_;
  double step_time_     = 1.0;
  const PartRows* rows_ = nullptr;  ///< a partitioned run's part; nullptr: the whole mesh
  OutputFile nodes_, elements_, reactions_;
  std::vector<int> prescribed_;  ///< per node: the OR of its BC codes (1 u_r, 2 u_z, 4 u_theta)
  int tables_written_ = 0;
  std::string node_heads_, element_heads_;  ///< the rows' mesh parts, from the second increment on
  std::vector<std::size_t> node_head_end_, element_head_end_;
};

}  // namespace gapfe

#pragma once
// history.csv: one row per accepted increment of a run of more than one load step, the numbers a
// load-displacement, torque-twist or stress-time curve is drawn from (`gapfe plot DIR --x COL --y COL`):
//   step, inc, t           as in every table (output/step_files.hpp): t = inc x the time a load step lasts
//   load_factor            inc / the number of load steps: the fraction of the deck's total load applied
//                          (of each load's value, where a scene gives it a history: its amplitude)
//   R_r_CARD, R_z_CARD, R_t_CARD   the total reaction of each boundary card in the components it prescribes
//                          (CARD: bc1, bc2, ... for a deck's cards in order; a scene's [[boundary]] groups
//                          joined by '+'; saac3x_bottom, saac3x_top for the faces SAAC3X drives); total ring
//                          forces, R_t a force along theta (its torque about the axis is sum R_t r)
//   u_max                  the largest displacement |u| of any node
//   closed, slipping       gap node pairs closed, and of those slipping (friction)
//   cone_ratio             runs with friction: the largest |f_t| / (mu f_n) of a closed pair (ConeExcess,
//                          contact/pair_state.hpp): at most 1 under Coulomb, how far the seed's models
//                          stand outside the cone; inf for a pair carrying friction in tension
//   plastic_points         integration points on the yield surface
//   iterations             linear solves of the increment (1 for a linear step; Newton's, or the contact
//                          policy's, otherwise)
//   residual               the increment's relative residual (|K u - f| / |f|, or Newton's |R| / |F_int|;
//                          relative to the loads too, docs/checks.md)
//   applied_z, reaction_z  global equilibrium (Solution::balance): the axial force of every applied load
//                          (edge tractions, nodal forces, body forces) and of every reaction [force]
//   applied_torque, reaction_torque, gap_torque   with 3 DOF per node: their torques about the axis, and
//                          the gap pairs' own (Balance::gap_torque) [force x length]
//   balance                Balance::relative(): |applied + reaction| / the load's size, the larger of the
//                          two directions (about the axis, applied + reaction - gap_torque)
// Each row is one write (output/output_file.hpp), so a run that fails or is killed keeps the history of what
// it accepted, every row whole.
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/text.hpp"
#include "gapfe/input/scene.hpp"
#include "gapfe/output/card_reactions.hpp"
#include "gapfe/output/csv_rows.hpp"
#include "gapfe/output/output_file.hpp"
#include "gapfe/output/part_rows.hpp"
#include "gapfe/output/vtu_writer.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

/// Which optional columns history.csv has.
struct HistoryColumns {
  bool friction = false;  ///< the run has friction at its gap pairs: cone_ratio
  bool torque   = false;  ///< 3 DOF per node: applied_torque, reaction_torque, gap_torque
};

/// What an increment's driver knows beyond its solution.
struct IncrementSummary {
  int iterations = 1, plastic_points = 0, closed = 0, slipping = 0;
  double cone_ratio = 0;  ///< ConeExcess::ratio of a run with friction
  /// A partitioned run's history_node_figures, summed (and u_max the largest) over the parts; empty: the
  /// row takes them from the solution, which holds every node.
  std::vector<double> node_figures = {};
};

/// The figures of history.csv's row that come from the nodes: each card's reaction in each component it
/// prescribes (the R_* columns, in order), then u_max. A part's (`rows`): its owned nodes' shares, whose sum
/// over the parts (and, for u_max, largest) is the whole's.
inline std::vector<double> history_node_figures(const std::vector<CardNodes>& cards, const Solution& s,
                                                const PartRows* rows = nullptr) {
  std::vector<double> figures;
  for (const CardNodes& c : cards)
    for (int comp = 0; comp < 3; ++comp) {
      if (!((c.code >> comp) & 1)) continue;
      if (!rows) {
        figures.push_back(card_reaction(s, c, comp));
        continue;
      }
      double total = 0;
      for (const int n : c.nodes)
        if (const int local = rows->local(n); local >= 0 && local < rows->owned_nodes())
          total += s.reaction(local, comp);
      figures.push_back(total);
    }
  const Eigen::Index nodes = rows ? rows->owned_nodes() : s.displacement.rows();
  figures.push_back(nodes > 0 ? s.displacement.topRows(nodes).rowwise().norm().maxCoeff() : 0.0);
  return figures;
}

class HistoryFile {
 public:
  HistoryFile(const std::string& dir, const Scene& scene, int steps, double step_time,
              HistoryColumns columns = {})
      : steps_(steps), step_time_(step_time), columns_(columns) {
    cards_           = card_nodes(scene);
    std::string head = "step,inc,t,load_factor";
    std::set<std::string> used;
    for (CardNodes& c : cards_) {
      c.name           = detail::csv_name(c.name);
      std::string name = c.name;
      for (int k = 2; !used.insert(name).second; ++k) name = c.name + "_" + std::to_string(k);
      for (int comp = 0; comp < 3; ++comp)
        if ((c.code >> comp) & 1) head += std::string(",R_") + "rzt"[comp] + "_" + name;
    }
    head += std::string(",u_max,closed,slipping") + (columns.friction ? ",cone_ratio" : "") +
            ",plastic_points,iterations,residual,applied_z,reaction_z" +
            (columns.torque ? ",applied_torque,reaction_torque,gap_torque" : "") + ",balance\n";
    out_ = OutputFile(dir + "/history.csv");
    out_.append(head);
  }

  void write(int step, double inc, const Solution& s, const IncrementSummary& summary) {
    std::string row;
    for (const double v : {static_cast<double>(step), inc, inc * step_time_, inc / steps_}) {
      detail::append_number(row, v);
      row += ',';
    }
    const std::vector<double> figures =
        summary.node_figures.empty() ? history_node_figures(cards_, s) : summary.node_figures;
    for (std::size_t k = 0; k < figures.size(); ++k) {
      detail::append_number(row, figures[k]);
      if (k + 1 < figures.size()) row += ',';
    }
    for (const int v : {summary.closed, summary.slipping}) {
      row += ',';
      detail::append_number(row, static_cast<long long>(v));
    }
    if (columns_.friction) row += ',', detail::append_number(row, summary.cone_ratio);
    for (const int v : {summary.plastic_points, summary.iterations}) {
      row += ',';
      detail::append_number(row, static_cast<long long>(v));
    }
    const Balance& b = s.balance;
    std::vector<double> tail{s.residual, b.applied_axial, b.reaction_axial};
    if (columns_.torque) tail.insert(tail.end(), {b.applied_torque, b.reaction_torque, b.gap_torque});
    tail.push_back(b.relative());
    for (const double v : tail) {
      row += ',';
      detail::append_number(row, v);
    }
    row += '\n';
    out_.append(row);
  }
  void close() { out_.close(); }

 private:
  std::vector<CardNodes> cards_;
  int steps_        = 1;
  double step_time_ = 1;
  HistoryColumns columns_;
  OutputFile out_;
};

}  // namespace gapfe

#pragma once
// gaps.csv of a run with gap elements, and the gap cell arrays of its VTU files.
#include <algorithm>
#include <string>
#include <vector>

#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/contact/pair_state.hpp"
#include "gapfe/input/scene.hpp"
#include "gapfe/output/csv_rows.hpp"
#include "gapfe/output/output_file.hpp"
#include "gapfe/output/vtu_writer.hpp"

namespace gapfe {

/// The VTU cell arrays of the gap elements, one value per deck element: gap_state (0 structural, -1 a gap
/// element that stays soft, else the seed's contact state 1-4), gap_size (smallest pair gap, 0 elsewhere) and
/// contact_force (the sum of its pairs' normal forces f_n, total ring force, compression positive). Every
/// process of a partitioned run holds every pair, so each makes them alike.
inline std::vector<VtuField> gap_fields(const Scene& scene, const std::vector<GapPair>& pairs,
                                        const std::vector<PairState>& states) {
  const std::size_t ne = scene.grid.cells.size();
  VtuField state{"gap_state", 1, std::vector<double>(ne, 0.0), true},
      size{"gap_size", 1, std::vector<double>(ne, 0.0)},
      force{"contact_force", 1, std::vector<double>(ne, 0.0)};
  for (const int e : scene.gaps.soft) state.values[static_cast<std::size_t>(e)] = -1;
  for (std::size_t q = 0; q < pairs.size(); ++q) {
    const GapPair& p    = pairs[q];
    const PairState& st = states[q];
    const std::size_t e = static_cast<std::size_t>(p.element);
    if (e >= ne) continue;  // a scene's gap element without a cell (input/scene_file.hpp): no cell to mark
    if (state.values[e] == 0) state.values[e] = 1, size.values[e] = st.gap;
    size.values[e] = std::min(size.values[e], st.gap);
    force.values[e] += st.normal_force;
    if (st.closed) state.values[e] += p.pair == 0 ? 1 : 2;  // 1 none, 2 first, 3 second, 4 both
  }
  return {std::move(state), std::move(size), std::move(force)};
}

/// gaps.csv: one row per gap node pair per increment; status open | closed, or with friction open |
/// stick | slip; gap [length] (negative: overlap), f_n the normal force and f_t the resultant tangential
/// (friction) force |t| (total ring forces, f_n compressive positive; f_t 0 without friction). Element
/// numbers are the deck's, pair 1 | 2 the seed's contact states 2 | 3, node_a and node_b the pair's nodes
/// (the gap closes from a towards b). A status is the one the increment was solved with (for the seed's
/// extended model: the stick or slip its stress check chose at the increment before).
class GapFile {
 public:
  GapFile(const std::string& dir, bool friction = false, double step_time = 1.0)
      : friction_(friction), step_time_(step_time) {
    out_ = OutputFile(dir + "/gaps.csv");
    out_.append("step,inc,t,element,pair,node_a,node_b,status,gap,f_n,f_t\n");
  }
  /// Writes the increment's rows.
  void write(int step, double inc, const std::vector<GapPair>& pairs, const std::vector<PairState>& states) {
    std::string s;
    for (std::size_t q = 0; q < pairs.size(); ++q) {
      const GapPair& p    = pairs[q];
      const PairState& st = states[q];
      detail::csv_increment(s, step, inc, step_time_);
      detail::append_number(s, static_cast<long long>(p.element + 1)), s += ',';
      detail::append_number(s, static_cast<long long>(p.pair + 1)), s += ',';
      detail::append_number(s, static_cast<long long>(p.node_a + 1)), s += ',';
      detail::append_number(s, static_cast<long long>(p.node_b + 1));
      s += !st.closed ? ",open," : !friction_ ? ",closed," : st.slipping ? ",slip," : ",stick,";
      detail::csv_number(s, st.gap), detail::csv_number(s, st.normal_force);
      detail::append_number(s, st.tangential_force.norm()), s += '\n';
    }
    out_.append(s);
  }
  void close() { out_.close(); }

 private:
  bool friction_;
  double step_time_ = 1.0;
  OutputFile out_;
};

}  // namespace gapfe

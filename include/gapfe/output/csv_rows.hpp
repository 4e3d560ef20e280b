#pragma once
// The pieces every CSV row of a run starts with: a number and its comma, and an increment's step,inc,t
// (t = inc x the time a load step lasts; output/step_files.hpp gives the tables' columns).
#include <string>

#include "gapfe/output/output_file.hpp"

namespace gapfe::detail {

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

}  // namespace gapfe::detail

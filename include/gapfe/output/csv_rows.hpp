#pragma once
// The pieces every CSV row of a run starts with: a number and its comma, and an increment's step,inc,t
// (t = inc x the time a load step lasts; output/step_files.hpp gives the tables' columns).
#include <string>

#include "gapfe/core/text.hpp"
#include "gapfe/output/output_file.hpp"

namespace gapfe::detail {

/// A name as a CSV field or header: no control characters (core/text.hpp), no separators or quotes (a
/// scene's group may be named anything).
inline std::string csv_name(const std::string& name) {
  std::string s = visible_text(name);
  for (char& ch : s)
    if (ch == ',' || ch == '"') ch = '_';
  return s;
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

}  // namespace gapfe::detail

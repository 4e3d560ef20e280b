#pragma once
// The pieces every CSV row of a run starts with: a number and its comma, and an increment's step,inc,t
// (t = inc x the time a load step lasts; output/step_files.hpp gives the tables' columns); and a table's
// rows formatted on every thread (write_rows).
#include <algorithm>
#include <string>
#include <vector>

#include "gapfe/core/text.hpp"
#include "gapfe/core/workers.hpp"
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

/// Rows 0 .. count - 1 of a table into `out`: row(s, i) appends row i's text without its newline to `s`,
/// or returns false for no row. Formatted on the pool's threads (core/workers.hpp) in tasks of
/// kRowsPerTask rows, each into a text of its own, and appended in order, one round's texts while the next
/// round is formatted: the same bytes on any number of threads (OutputFile lays rows out from its own count
/// of bytes, whatever pieces they come in); ordered_rounds in core/workers.hpp pipelines the rounds.
template <class Row>
void write_rows(OutputFile& out, std::size_t count, Row&& row) {
  constexpr std::size_t kRowsPerTask = 8192, kTasksPerRound = 8;  // two rounds of texts of about 1 MB
  constexpr std::size_t kRound = kRowsPerTask * kTasksPerRound;
  const std::size_t rounds     = (count + kRound - 1) / kRound;
  std::vector<std::string> text(2 * kTasksPerRound);
  const auto tasks = [&](std::size_t r) {
    return (std::min(count - r * kRound, kRound) + kRowsPerTask - 1) / kRowsPerTask;
  };
  ordered_rounds(
      rounds, tasks,
      [&](std::size_t r, std::size_t t) {
        std::string& s = text[(r % 2) * kTasksPerRound + t];
        s.clear();
        const std::size_t begin = r * kRound + t * kRowsPerTask, end = std::min(count, begin + kRowsPerTask);
        for (std::size_t i = begin; i < end; ++i)
          if (row(s, i)) s += '\n';
      },
      [&](std::size_t r) {
        for (std::size_t k = 0; k < tasks(r); ++k) out.append(text[(r % 2) * kTasksPerRound + k]);
      });
}

}  // namespace gapfe::detail

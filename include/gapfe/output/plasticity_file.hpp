#pragma once
// plasticity.csv of a run of a law with history without gaps: the Newton record of every accepted
// increment. Columns step,inc,t (output/csv_rows.hpp), iterations (linear solves), plastic_points, drift
// (max |sqrt f - 1| over the plastic points), time_error (a rate-dependent law's estimated time-integration
// error, StepReport::time_error) and residuals (|R| / |F_int| after each linear solve, separated by spaces).
#include <string>

#include "gapfe/output/csv_rows.hpp"
#include "gapfe/output/output_file.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

class PlasticityFile {
 public:
  /// A file in `dir`; without one (a process of a partitioned run that writes no files), rows go nowhere.
  explicit PlasticityFile(const std::string* dir, double step_time) : step_time_(step_time) {
    if (dir) out_ = OutputFile(*dir + "/plasticity.csv");
    out_.append("step,inc,t,iterations,plastic_points,drift,time_error,residuals\n");
  }
  void write(int step, double inc, const StepReport& rep) {
    std::string row;
    detail::csv_increment(row, step, inc, step_time_);
    detail::append_number(row, static_cast<long long>(rep.iterations)), row += ',';
    detail::append_number(row, static_cast<long long>(rep.plastic_points)), row += ',';
    detail::csv_number(row, rep.drift);
    detail::csv_number(row, rep.time_error);
    for (std::size_t k = 0; k < rep.residuals.size(); ++k) {
      if (k > 0) row += ' ';
      detail::append_number(row, rep.residuals[k]);
    }
    row += '\n';
    out_.append(row);
  }
  void close() { out_.close(); }

 private:
  OutputFile out_;
  double step_time_ = 1;
};

}  // namespace gapfe

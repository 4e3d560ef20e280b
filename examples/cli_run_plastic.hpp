#pragma once
// `gapfe run` of a deck with yield cards: NonlinearStatic with Hill plasticity, integrated as the deck's
// `plasticity` option says (tangent: the seed's one solve per increment; return-mapping: Newton); with
// gap elements, ContactStatic over it under the seed's Saac policy (SAAC = SAGAEP + gaps). The two
// integrations are instantiated in two translation units (cli_run_plastic.cpp, cli_run_plastic_tangent.cpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>

#include "gapfe/driver/deck_run.hpp"
#include "gapfe/io/deck_output.hpp"
#include "gapfe/model.hpp"

#include "cli_run.hpp"
#include "cli_run_contact.hpp"

namespace gapfe::cli::plastic {

template <class M>
void run_law(const RunRequest& r, RunTimes& times) {
  StepFiles files(r.dir, r.scene);
  // plasticity.csv: the Newton record of every accepted increment (residuals: |R| / |F_int| after each
  // linear solve, separated by spaces; drift: max |sqrt f - 1| over the plastic points).
  std::ofstream record = detail::open_output(r.dir + "/plasticity.csv");
  record << "step,inc,iterations,plastic_points,drift,residuals\n";
  int last_step = 0;
  run_deck_plastic<M>(r.deck, r.scene, [&](int step, double inc, const NonlinearStatic<M>& fe) {
    const auto& rep = fe.report();
    times.solve += fe.solve_seconds();
    times.newton_iterations += rep.iterations;
    times.cut_steps += step == last_step || inc != std::floor(inc);
    times.plastic_points = rep.plastic_points;
    times.drift          = std::max(times.drift, rep.drift);
    times.worst_residual = std::max(times.worst_residual, rep.residuals.back());
    ++times.increments;
    std::string row;
    detail::append_number(row, static_cast<long long>(step)), row += ',';
    detail::csv_number(row, inc);
    detail::append_number(row, static_cast<long long>(rep.iterations)), row += ',';
    detail::append_number(row, static_cast<long long>(rep.plastic_points)), row += ',';
    detail::csv_number(row, rep.drift);
    for (std::size_t k = 0; k < rep.residuals.size(); ++k) {
      if (k > 0) row += ' ';
      detail::append_number(row, rep.residuals[k]);
    }
    record << row << '\n' << std::flush;
    last_step = step;
    write_increment(r, times, files, step, inc, fe);
  });
  progress_done(r);
  files.write_deformed(r.deck.title);
}

template <class Integration>
void run_integration(const RunRequest& r, RunTimes& times) {
  dispatch<Quad4, Quad4BBar>(r, [&]<class Kin, class Elem, class Solver>() {
    using M = Model<Kin, Elem, Hill<Integration>, Solver>;
    if (r.scene.needs.gaps.empty())
      run_law<M>(r, times);
    else
      contact::run_policy<M, Saac>(r, times);
  });
}

}  // namespace gapfe::cli::plastic

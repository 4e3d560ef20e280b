// `gapfe run` of a deck without gap elements or yield cards: LinearStatic, one factorization.
#include <chrono>
#include <cmath>

#include "gapfe/driver/deck_run.hpp"
#include "gapfe/io/deck_output.hpp"
#include "gapfe/model.hpp"

#include "cli_run.hpp"

namespace gapfe::cli {

void progress_line(const RunRequest& r, int step) {
  if (r.progress) r.err << "\rstep " << step << "/" << r.deck.steps() << std::flush;
}
void progress_done(const RunRequest& r) {
  if (r.progress) r.err << "\r" << std::string(32, ' ') << "\r" << std::flush;
}

void run_elastic(const RunRequest& r, RunTimes& times) {
  dispatch<LegacyQuad, Quad4, Quad4BBar>(r, [&]<class Kin, class Elem, class Solver>() {
    using M = Model<Kin, Elem, Orthotropic, Solver>;
    StepFiles files(r.dir, r.scene);
    run_deck<M>(r.deck, r.scene, [&](int step, double inc, const LinearStatic<M>& fe) {
      const auto& t = fe.timings();
      times.assemble += t.assemble, times.factorize += t.factorize, times.solve += t.solve + t.reactions;
      write_increment(r, times, files, step, inc, fe);
    });
    progress_done(r);
    files.write_deformed(r.deck.title);
  });
}

}  // namespace gapfe::cli

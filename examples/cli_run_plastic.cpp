// `gapfe run` of a deck with yield cards: NonlinearStatic with Hill plasticity, integrated as the deck's
// `plasticity` option says (tangent: the seed's one solve per increment; return-mapping: Newton).
#include <algorithm>
#include <chrono>
#include <cmath>

#include "gapfe/driver/deck_run.hpp"
#include "gapfe/io/deck_output.hpp"
#include "gapfe/model.hpp"

#include "cli_run.hpp"

namespace gapfe::cli {
namespace {

template <class M>
void run_law(const RunRequest& r, RunTimes& times) {
  StepFiles files(r.dir, r.scene);
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
    last_step = step;
    if (!fe.solution().displacement.allFinite())
      throw SolveError("load step " + std::to_string(step) + ": the solution is not finite");
    const auto start = std::chrono::steady_clock::now();
    files.write(step, inc, fe);
    times.write += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progress_line(r, step);
  });
  progress_done(r);
  files.write_deformed(r.deck.title);
}

}  // namespace

void run_plastic(const RunRequest& r, RunTimes& times) {
  if (!r.scene.needs.gaps.empty())
    throw InputError(
        "gap elements and yield cards in one deck: the plastic driver does not carry contact yet; "
        "blank the yield cards (elastic gap run) or remove material 2");
  if (r.element == "legacy")
    throw InputError(
        "element = legacy with yield cards: the legacy quad's condensed centre node is not in the "
        "plastic driver yet; use element = quad4bbar (the default for plastic decks) or quad4");
  dispatch<Quad4, Quad4BBar>(r, [&]<class Kin, class Elem, class Solver>() {
    if (r.deck.options.plasticity == "return-mapping")
      run_law<Model<Kin, Elem, Hill<ReturnMapping>, Solver>>(r, times);
    else
      run_law<Model<Kin, Elem, Hill<Tangent>, Solver>>(r, times);
  });
}

}  // namespace gapfe::cli

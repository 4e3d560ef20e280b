#pragma once
// `gapfe run` of a deck with gap elements: ContactStatic under the deck's contact policy. The 2-DOF
// variants are instantiated in cli_run_contact.cpp, the 3-DOF ones in cli_run_contact_saga.cpp, so that
// the two build in parallel.
#include <chrono>
#include <cmath>

#include "gapfe/driver/deck_run.hpp"
#include "gapfe/io/deck_output.hpp"
#include "gapfe/model.hpp"

#include "cli_run.hpp"

namespace gapfe::cli::contact {

template <class M, ContactPolicy P>
void run_policy(const RunRequest& r, RunTimes& times) {
  StepFiles files(r.dir, r.scene);
  GapFile gaps(r.dir, r.scene);
  run_deck_contact<M, P>(
      r.deck, r.scene, r.deck.options.gap_penalty, [&](int step, double inc, const ContactStatic<M, P>& c) {
        const auto& t = c.fe().timings();
        times.assemble += t.assemble, times.factorize += t.factorize, times.solve += t.solve + t.reactions;
        times.contact = c.counters(), ++times.increments, times.penalty = c.penalty_factor();
        times.pairs = static_cast<int>(c.pairs().size()), times.closed = 0;
        for (const auto& st : c.states()) times.closed += st.closed;
        write_increment(r, times, files, step, inc, c.fe(), gaps.write(step, inc, c));
      });
  progress_done(r);
  files.write_deformed(r.deck.title);
}

template <class Kin>
void run_contact_with(const RunRequest& r, RunTimes& times) {
  dispatch<LegacyQuad, Quad4, Quad4BBar>(r, [&]<class K, class Elem, class Solver>() {
    if constexpr (std::is_same_v<K, Kin>) {
      using M              = Model<Kin, Elem, Orthotropic, Solver>;
      const std::string& c = r.deck.options.contact;
      if (c == "saac") return run_policy<M, Saac>(r, times);
      if (c == "active-set") return run_policy<M, ActiveSet>(r, times);
      if (c == "augmented-lagrangian") return run_policy<M, AugmentedLagrangian>(r, times);
      return run_policy<M, NoContact>(r, times);
    }
  });
}

}  // namespace gapfe::cli::contact

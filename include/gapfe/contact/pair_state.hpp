#pragma once
// The record of one gap pair that a contact run keeps in its History (core/history.hpp) and writes out
// (gaps.csv, io/deck_output.hpp), and the work counters of a run. Forces are total ring forces,
// compressive positive; gaps are positive open (core/types.hpp).
namespace gapfe {

/// State of one gap pair.
struct PairState {
  bool closed          = false;
  double gap           = 0;   ///< [length]
  double normal_force  = 0;   ///< P [force]
  double multiplier    = 0;   ///< lambda (augmented Lagrangian) [force]
  double reference_gap = 0;   ///< g_ref: the penalty acts on g - g_ref [length]
  double closed_at     = -1;  ///< load factor at which it last closed (-1: never)
};

/// Work of the steps since the last reset, for the speed/accuracy tables.
struct ContactCounters {
  int solves = 0, factorizations = 0, splits = 0, multiplier_updates = 0;
};

}  // namespace gapfe

#pragma once
// History<T>: the one commit/reject protocol of everything that remembers the path, today the material
// points of a law with history (driver/nonlinear_static.hpp) and the gap pairs of a contact run
// (driver/contact_static.hpp); next the friction slip of a pair and the rate-dependent points.
//
// Two arrays of records, one per point or pair, in one contiguous vector each (deal.II step-18 keeps its
// quadrature-point history the same way, next to the points, indexed cell by cell):
//   committed  the state at the end of the last accepted increment; never written by a trial solve;
//   trial      what the current solve computes from `committed` (laws are pure: old state in, new out).
// An accepted increment calls commit(); a rejected, repeated or split one calls reject(), so it leaves
// no trace. The step's time and dt travel separately, in the StepContext (core/concepts.hpp).
#include <cstddef>
#include <vector>

namespace gapfe {

template <class T>
class History {
 public:
  History() = default;
  explicit History(std::size_t count, const T& initial = T{})
      : committed_(count, initial), trial_(committed_) {}

  std::size_t size() const { return committed_.size(); }
  const T& committed(std::size_t i) const { return committed_[i]; }
  const std::vector<T>& committed() const { return committed_; }
  T& trial(std::size_t i) { return trial_[i]; }
  const T& trial(std::size_t i) const { return trial_[i]; }
  const std::vector<T>& trial() const { return trial_; }

  /// The trial records become the committed state (an accepted increment).
  void commit() { committed_ = trial_; }
  /// Back to the committed state (a rejected or repeated increment).
  void reject() { trial_ = committed_; }
  /// Apply `change` to record i in both arrays: a decision taken at the accepted state itself (a gap
  /// pair declared closed at a split point) rather than computed by a trial.
  template <class Change>
  void amend(std::size_t i, Change&& change) {
    change(committed_[i]);
    change(trial_[i]);
  }

 private:
  std::vector<T> committed_, trial_;
};

}  // namespace gapfe

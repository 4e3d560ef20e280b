#pragma once
// RuntimeSolver<S...>: a LinearSolver whose implementation is one of S..., chosen at run time when the
// object is constructed. A program that offers its users several solvers (the gapfe command's `solver =`
// option) instantiates its models once with RuntimeSolver instead of once per solver: half the compile time
// with two solvers. The calls are per matrix (analyze, factorize, solve), so the one virtual call each costs
// nothing measurable; element and point code never sees it.
//
// The choice is the solver object's own, made when it is constructed (RuntimeSolver(index)): a driver is
// given its solver (LinearStatic, NonlinearStatic, ContactStatic take one), so two runs in one process may
// use different solvers.
#include <array>
#include <memory>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "gapfe/core/concepts.hpp"
#include "gapfe/core/error.hpp"

namespace gapfe {

template <LinearSolver... Solvers>
class RuntimeSolver {
 public:
  static constexpr const char* kName = "chosen at run time (RuntimeSolver)";
  /// One pattern serves whichever is chosen, so they must read the same entries.
  static constexpr MatrixStorage kStorage = storage_of<std::tuple_element_t<0, std::tuple<Solvers...>>>();
  static_assert(((storage_of<Solvers>() == kStorage) && ...),
                "RuntimeSolver: every solver must read the same storage (lower triangle or full)");

  /// The position in Solvers... of the solver whose kName is `name`.
  static std::size_t index_named(const std::string& name) {
    for (std::size_t k = 0; k < sizeof...(Solvers); ++k)
      if (name == kNames[k]) return k;
    throw InputError("RuntimeSolver: no solver named '" + name + "'");
  }
  /// The position of solver type S in Solvers....
  template <class S>
  static constexpr std::size_t index_of() {
    static_assert((std::is_same_v<S, Solvers> || ...),
                  "RuntimeSolver::index_of<S>: S is not one of its solvers");
    return position<S, Solvers...>();
  }

  /// The solver at position `index` of Solvers... (the first by default).
  explicit RuntimeSolver(std::size_t index = 0) : index_(index) {
    if (index >= sizeof...(Solvers))
      throw InputError("RuntimeSolver: no solver number " + std::to_string(index));
    impl_ = make<0>(index);
  }
  /// The chosen solver's kName.
  const char* name() const { return kNames[index_]; }

  void analyze(const SpMat& k) { impl_->analyze(k); }
  /// The caller's elimination order, for the chosen solver if it takes one (OrderedSolver).
  void analyze(const SpMat& k, const std::vector<int>& order) { impl_->analyze(k, order); }
  /// The layout of a partitioned system, for a distributed solver among Solvers when it is the chosen one
  /// (DistributedSolver); the others solve on one process and refuse it.
  void distribute(const EquationLayout& layout) requires(DistributedSolver<Solvers> || ...) {
    impl_->distribute(layout);
  }
  /// For the chosen solver when it decides itself whether a factorization can be skipped (PetscSolver).
  void skip_unchanged(bool on) { impl_->skip_unchanged(on); }
  /// The chosen solver's own count of numeric factorizations, or -1 when it keeps none.
  int factorizations() const { return impl_->factorizations(); }
  bool factorize(const SpMat& k) { return impl_->factorize(k); }
  VecX solve(const VecX& b) const { return impl_->solve(b); }
  std::string failure() const { return impl_->failure(); }
  int failed_equation() const { return impl_->failed_equation(); }
  /// The chosen solver's FactorStatistics, zeros when it keeps none.
  FactorStatistics statistics() { return impl_->statistics(); }

 private:
  struct Interface {
    virtual ~Interface()                                                = default;
    virtual void analyze(const SpMat& k)                                = 0;
    virtual void analyze(const SpMat& k, const std::vector<int>& order) = 0;
    virtual void distribute(const EquationLayout& layout)               = 0;
    virtual void skip_unchanged(bool on)                                = 0;
    virtual int factorizations() const                                  = 0;
    virtual bool factorize(const SpMat& k)                              = 0;
    virtual VecX solve(const VecX& b) const                             = 0;
    virtual std::string failure() const                                 = 0;
    virtual int failed_equation() const                                 = 0;
    virtual FactorStatistics statistics()                               = 0;
  };
  template <class S>
  struct Impl final : Interface {
    S s;
    void analyze(const SpMat& k) override { s.analyze(k); }
    void analyze(const SpMat& k, const std::vector<int>& order) override {
      if constexpr (OrderedSolver<S>)
        s.analyze(k, order);
      else
        s.analyze(k);
    }
    void distribute(const EquationLayout& layout) override {
      if constexpr (DistributedSolver<S>)
        s.distribute(layout);
      else
        throw InputError(std::string("the solver ") + S::kName +
                         " solves on one process; a partitioned problem needs a distributed one (PETSc)");
    }
    void skip_unchanged(bool on) override {
      if constexpr (requires { s.skip_unchanged(on); }) s.skip_unchanged(on);
    }
    int factorizations() const override {
      if constexpr (requires { s.factorizations(); })
        return s.factorizations();
      else
        return -1;
    }
    bool factorize(const SpMat& k) override { return s.factorize(k); }
    VecX solve(const VecX& b) const override { return s.solve(b); }
    std::string failure() const override { return s.failure(); }
    int failed_equation() const override {
      if constexpr (requires { s.failed_equation(); })
        return s.failed_equation();
      else
        return -1;
    }
    FactorStatistics statistics() override {
      if constexpr (requires { s.statistics(); })
        return s.statistics();
      else
        return {};
    }
  };
  template <std::size_t K>
  static std::unique_ptr<Interface> make(std::size_t index) {
    using S = std::tuple_element_t<K, std::tuple<Solvers...>>;
    if constexpr (K + 1 < sizeof...(Solvers))
      if (index != K) return make<K + 1>(index);
    return std::make_unique<Impl<S>>();
  }

  template <class S, class First, class... Rest>
  static constexpr std::size_t position() {
    if constexpr (std::is_same_v<S, First>)
      return 0;
    else
      return 1 + position<S, Rest...>();
  }

  static constexpr std::array<const char*, sizeof...(Solvers)> kNames{Solvers::kName...};
  std::size_t index_ = 0;
  std::unique_ptr<Interface> impl_;
};

}  // namespace gapfe

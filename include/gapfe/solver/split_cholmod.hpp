#pragma once
// SplitCholmod: the Cholesky factorization of K as two halves and their separator, the halves on two
// threads of the pool (core/workers.hpp): CHOLMOD's supernodal factorization is serial, and on 2-D meshes
// its supernodes are too small for the BLAS's threads to share (BENCHMARKS.md "Every core"). top_split
// (solver/top_split.hpp) finds halves 1 and 2 with no entry of K between them and the separator s,
// eliminated last:
//
//   K = [K11 0 K1s; 0 K22 K2s; Ks1 Ks2 Kss].
//
// CHOLMOD factorizes each half as M_i = [Kii Kis; Ksi C], C = diag(c_q) a bound of Kss scaled like its
// diagonal (shifts(): Kss <= C). M_i is positive definite whenever K is: Kss - S_1 - S_2 is, S_i = Ksi Kii^-1
// Kis, so S_i < Kss <= C. The last block Lam_i of M_i's factor (the separator's columns) has Lam_i Lam_i^T =
// C - S_i, so the separator's Schur complement is
//
//   S = Kss - S_1 - S_2 = Kss - 2 C + Lam_1 Lam_1^T + Lam_2 Lam_2^T,
//
// factorized dense (LAPACK). A solve: y_i = L_i^-1 [b_i; 0] on each half, whose separator part w_i gives
// Ksi Kii^-1 b_i = -Lam_i w_i; x_s = S^-1 (b_s - both of those); then x_i = Kii^-1 (b_i - Kis x_s), one back
// substitution of M_i's factor with Lam_i^T x_s in the separator's place.
//
// What it costs beyond one factorization of K: the separator's dense block three times (once in each half,
// where it is used only through Lam_i, and S) and two products Lam Lam^T, each about n_s^3 / 3 flops: 4e9
// of 5.6e10 at 1e6 equations (n_s = 1,414 on the tube). The rounding is not one factorization's (S is a
// sum of terms of size C), at the level of its backward error row by row (C scales with each row), and it
// does not depend on the number of threads: each half is factorized on one thread, with OpenBLAS on one
// (solver/threads.hpp), and the sums are added in one order.
//
// Memory: M_i's rows are put in a postorder of K's elimination tree (top_split) with the separator last,
// and CHOLMOD analyzes them in that order (no ordering of its own, no postorder), so it factorizes M_i's
// lower triangle where it lies instead of the two transposed copies a permuted analysis makes. The two M_i
// (values, rows and each value's place in K) are kept between factorizations and cost about what those
// copies did during one; S and the two Lam add 3 x 8 n_s^2 bytes (48 MB at n_s = 1,414), and the two
// products another 2 x 8 n_s^2 while S is formed.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>
#include <utility>
#include <vector>

#include "gapfe/core/concepts.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/core/workers.hpp"
#include "gapfe/solver/cholmod_factor.hpp"
#include "gapfe/solver/threads.hpp"
#include "gapfe/solver/top_split.hpp"

namespace gapfe {

class SplitCholmod {
 public:
  /// The split of K's pattern in `order` set up and each half analyzed; false when there is none worth
  /// making (top_split) or a half's analysis would not keep the separator last.
  bool analyze(const SpMat& k, const std::vector<int>& order) {
    if (!k.isCompressed()) return false;
    const TopSplit split = top_split(k, order, kMaxSeparator, kMinShare);
    if (!split.found()) return false;
    separator_  = split.separator;
    const int n = static_cast<int>(k.rows()), ns = separator_size();
    // Each equation's part (0, 1: a half; 2: the separator) and index in it.
    std::vector<signed char> part(std::size_t(n), -1);
    std::vector<int> local(std::size_t(n), -1);
    for (int q = 0; q < ns; ++q) {
      part[std::size_t(separator_[std::size_t(q)])]  = 2;
      local[std::size_t(separator_[std::size_t(q)])] = q;
    }
    for (int h = 0; h < 2; ++h) {
      Half& half     = half_[std::size_t(h)];
      half.equations = split.halves[std::size_t(h)];
      half.own       = static_cast<int>(half.equations.size());
      for (int i = 0; i < half.own; ++i) {
        part[std::size_t(half.equations[std::size_t(i)])]  = static_cast<signed char>(h);
        local[std::size_t(half.equations[std::size_t(i)])] = i;
      }
      half.equations.insert(half.equations.end(), separator_.begin(), separator_.end());
    }
    separator_entries_.clear();
    const int *outer = k.outerIndexPtr(), *inner = k.innerIndexPtr();
    for (int c = 0; c < n; ++c)
      for (int p = outer[c]; p < outer[c + 1]; ++p)
        if (part[std::size_t(inner[p])] == 2 && part[std::size_t(c)] == 2)
          separator_entries_.push_back({p, std::max(local[std::size_t(inner[p])], local[std::size_t(c)]),
                                        std::min(local[std::size_t(inner[p])], local[std::size_t(c)])});
    std::array<bool, 2> ok{false, false};
    parallel_for(2, [&](std::size_t h) {
      openmp_inline_on_this_thread();
      ok[h] = half_[h].analyze(k, part, local, int(h), ns);
    });
    return ok[0] && ok[1];
  }

  /// K's values into both halves, each factorized on a thread of its own, then S. False when a half's
  /// factor or S is not positive definite (the caller re-does it whole to say where).
  bool factorize(const SpMat& k) {
    const OneBlasThread one(true);
    const int ns                = separator_size();
    const std::vector<double> c = shifts(k);
    if (c.size() != std::size_t(ns)) return false;  // a separator pivot not positive: K is not definite
    std::array<Eigen::MatrixXd, 2> products;        // reversed: Lam Lam^T's (a, b) at (ns-1-a, ns-1-b)
    std::array<bool, 2> ok{false, false};
    parallel_for(2, [&](std::size_t h) {
      openmp_inline_on_this_thread();
      ok[h] = half_[h].factorize(k, c, ns);
      if (ok[h]) products[h] = detail::reversed_lower_times_transpose(half_[h].tail);
    });
    if (!ok[0] || !ok[1]) return false;
    schur_.setZero(ns, ns);
    const double* v = k.valuePtr();
    for (const Entry& e : separator_entries_) schur_(e.row, e.col) = v[e.value];
    for (int q = 0; q < ns; ++q) schur_(q, q) -= 2 * c[std::size_t(q)];
    for (int h = 0; h < 2; ++h)
      for (int b = 0; b < ns; ++b)
        for (int a = b; a < ns; ++a) {
          const int i = half_[h].tail_of[std::size_t(a)], j = half_[h].tail_of[std::size_t(b)];
          schur_(std::max(i, j), std::min(i, j)) += products[h](ns - 1 - a, ns - 1 - b);
        }
    return detail::cholesky_in_place(schur_);
  }

  /// (smallest / largest diagonal entry of the factors)^2, as cholmod_rcond estimates it for one factor.
  double rcond() const {
    double lo = INFINITY, hi = 0;
    const auto take = [&](double d) { lo = std::min(lo, std::abs(d)), hi = std::max(hi, std::abs(d)); };
    for (const Half& h : half_)
      detail::for_each_factor_column(*h.llt.factor(), [&](int j, const int*, const double* x, int) {
        if (j < h.own) take(x[0]);
      });
    for (int q = 0; q < separator_size(); ++q) take(schur_(q, q));
    return hi > 0 ? (lo / hi) * (lo / hi) : 0.0;
  }

  VecX solve(const VecX& b) {
    const OneBlasThread one(true);
    const int ns = separator_size();
    std::array<VecX, 2> y, coupled;  // L_i^-1 [b_i; 0]; Ksi Kii^-1 b_i by separator equation
    parallel_for(2, [&](std::size_t h) {
      Half& H         = half_[h];
      const int* perm = static_cast<const int*>(H.llt.factor()->Perm);
      VecX v(H.own + ns);
      for (int p = 0; p < H.own + ns; ++p)
        v[p] = perm[p] < H.own ? b[H.equations[std::size_t(perm[p])]] : 0.0;
      H.substitute(v, CHOLMOD_L);
      const VecX lam_w = H.tail.triangularView<Eigen::Lower>() * v.tail(ns);
      coupled[h].resize(ns);
      for (int q = 0; q < ns; ++q) coupled[h][H.tail_of[std::size_t(q)]] = -lam_w[q];
      y[h] = std::move(v);
    });
    VecX xs(ns);
    for (int q = 0; q < ns; ++q) xs[q] = b[separator_[std::size_t(q)]] - coupled[0][q] - coupled[1][q];
    schur_.triangularView<Eigen::Lower>().solveInPlace(xs);
    schur_.triangularView<Eigen::Lower>().transpose().solveInPlace(xs);
    VecX x(b.size());
    parallel_for(2, [&](std::size_t h) {
      Half& H = half_[h];
      VecX xq(ns);
      for (int q = 0; q < ns; ++q) xq[q] = xs[H.tail_of[std::size_t(q)]];
      VecX& v    = y[h];
      v.tail(ns) = H.tail.triangularView<Eigen::Lower>().transpose() * xq;
      H.substitute(v, CHOLMOD_Lt);
      const int* perm = static_cast<const int*>(H.llt.factor()->Perm);
      for (int p = 0; p < H.own + ns; ++p)
        if (perm[p] < H.own) x[H.equations[std::size_t(perm[p])]] = v[p];
    });
    for (int q = 0; q < ns; ++q) x[separator_[std::size_t(q)]] = xs[q];
    return x;
  }

  /// Flops of both halves' factors (CHOLMOD's counts, each with its separator block) and of the dense
  /// work (two products and S, n_s^3 / 3 each); entries of the halves' columns and of S; values stored,
  /// S and both Lam included.
  FactorStatistics statistics() {
    const double ns = separator_size(), dense = ns * ns * ns / 3, block = ns * (ns + 1) / 2;
    FactorStatistics s{3 * dense, block, 3 * ns * ns, separator_size(), true};
    for (Half& h : half_) {
      s.flops += h.llt.cholmod().fl;
      s.entries += h.llt.cholmod().lnz - h.tail_entries;
      s.stored += h.llt.factor() != nullptr ? static_cast<double>(h.llt.factor()->xsize) : 0.0;
    }
    return s;
  }
  int separator_size() const { return static_cast<int>(separator_.size()); }
  int half_size(int h) const { return half_[std::size_t(h)].own; }
  const std::vector<int>& separator() const { return separator_; }  ///< K's equations, in elimination order

  /// A split only where it pays: a separator of at most kMaxSeparator equations (S, the two Lam and the
  /// two products are dense: 5 x 8 n_s^2 bytes, 360 MB at the limit), halves of at least kMinShare of the
  /// rest each.
  static constexpr int kMaxSeparator = 3000;
  static constexpr double kMinShare  = 0.2;

 private:
  /// M's separator block is C = diag(c_q): its value q is coded -1 - q where a value of K's has its index.
  static constexpr int shift_code(int q) { return -1 - q; }
  struct Entry {
    int value, row, col;  ///< Kss's entry: its index in K's values, its place in S's lower triangle
  };

  struct Half {
    std::vector<int> equations;  ///< M's rows in K's numbering: the half's own, then the separator's
    int own = 0;                 ///< how many are the half's own
    SpMat m;                     ///< M's lower triangle
    std::vector<int> source;     ///< per value of m: its index in K's values, or shift_code(q)
    detail::CholmodFactor llt;
    std::vector<int> tail_of;  ///< the separator equation of L's column own + q
    Eigen::MatrixXd tail;      ///< Lam: L's separator block, in L's column order (lower)
    double tail_entries = 0;   ///< the exact factor's entries in those columns (CHOLMOD's ColCount)

    bool analyze(const SpMat& k, const std::vector<signed char>& part, const std::vector<int>& local, int h,
                 int ns);
    bool factorize(const SpMat& k, const std::vector<double>& c, int ns) {
      const double* v = k.valuePtr();
      double* m_value = m.valuePtr();
      for (std::size_t p = 0; p < source.size(); ++p)
        m_value[p] = source[p] >= 0 ? v[source[p]] : c[std::size_t(-source[p] - 1)];
      llt.factorize(m);
      if (llt.info() != Eigen::Success || !llt.factor()->is_super) return false;
      tail.setZero(ns, ns);
      detail::for_each_factor_column(*llt.factor(), [&](int j, const int* rows, const double* x, int count) {
        if (j < own) return;
        for (int t = 0; t < count; ++t)
          if (rows[t] >= own) tail(rows[t] - own, j - own) = x[t];
      });
      return true;
    }
    /// v := L^-1 v or L^-T v (system CHOLMOD_L or CHOLMOD_Lt), v in L's column order.
    void substitute(VecX& v, int system) {
      cholmod_dense in   = Eigen::viewAsCholmod(v);
      cholmod_dense* out = cholmod_solve(system, llt.factor(), &in, &llt.cholmod());
      if (out == nullptr) throw SolveError("CHOLMOD could not solve with a half's factor (out of memory?)");
      std::copy_n(static_cast<const double*>(out->x), v.size(), v.data());
      cholmod_free_dense(&out, &llt.cholmod());
    }
  };

  /// C = diag(c_q) of the top, scaled like Kss: c_q = 1.25 rho d_q, d = Kss's diagonal and rho the largest
  /// row sum of |D^-1/2 Kss D^-1/2| (Gershgorin), so Kss <= rho D < C. Scaled so that S's rounding, about
  /// eps sqrt(c_q c_l) in entry (q, l), is the whole factorization's whatever the rows' scales (a contact
  /// penalty's 1e8 beside a steel's 1). Empty when a diagonal entry is not positive (K is not definite).
  std::vector<double> shifts(const SpMat& k) const {
    const std::size_t ns = separator_.size();
    std::vector<double> d(ns, 0.0), sum(ns, 0.0);
    const double* v = k.valuePtr();
    for (const Entry& e : separator_entries_)
      if (e.row == e.col) d[std::size_t(e.row)] = v[e.value];
    for (const double x : d)
      if (!(x > 0) || !std::isfinite(x)) return {};
    for (const Entry& e : separator_entries_) {
      const double scaled = std::abs(v[e.value]) / std::sqrt(d[std::size_t(e.row)] * d[std::size_t(e.col)]);
      sum[std::size_t(e.row)] += scaled;
      if (e.row != e.col) sum[std::size_t(e.col)] += scaled;
    }
    const double rho = sum.empty() ? 1.0 : *std::max_element(sum.begin(), sum.end());
    for (double& x : d) x *= 1.25 * rho;
    return d;
  }

  std::array<Half, 2> half_;
  std::vector<int> separator_;  ///< K's equations of the separator, in elimination order
  std::vector<Entry> separator_entries_;
  Eigen::MatrixXd schur_;  ///< S's Cholesky factor (lower)
};

/// M's pattern (lower triangle, rows sorted) for half h, with the source of each value, and CHOLMOD's
/// analysis in M's own order; `local`: each equation's row in M (the half's own) or separator index.
inline bool SplitCholmod::Half::analyze(const SpMat& k, const std::vector<signed char>& part,
                                        const std::vector<int>& local, int h, int ns) {
  const int n       = own + ns;
  const auto inside = [&](int eq) { return part[std::size_t(eq)] == h || part[std::size_t(eq)] == 2; };
  const auto row_of = [&](int eq) {
    return part[std::size_t(eq)] == 2 ? own + local[std::size_t(eq)] : local[std::size_t(eq)];
  };
  const int *outer = k.outerIndexPtr(), *inner = k.innerIndexPtr();
  std::vector<int> start(std::size_t(n) + 1, 0);
  const auto each = [&](auto&& f) {  // K's entries that M takes from it: (row, column) in M, value index
    for (int c = 0; c < k.outerSize(); ++c)
      if (inside(c))
        for (int p = outer[c]; p < outer[c + 1]; ++p)
          if (inside(inner[p]) && (part[std::size_t(c)] != 2 || part[std::size_t(inner[p])] != 2)) {
            const int a = row_of(inner[p]), b = row_of(c);
            f(std::max(a, b), std::min(a, b), p);
          }
  };
  each([&](int, int col, int) { ++start[std::size_t(col) + 1]; });
  for (int q = 0; q < ns; ++q) start[std::size_t(own + q) + 1] = 1;  // the separator block: c I
  std::partial_sum(start.begin(), start.end(), start.begin());
  m.resize(n, n);
  m.resizeNonZeros(start.back());
  std::copy(start.begin(), start.end(), m.outerIndexPtr());
  source.assign(std::size_t(start.back()), 0);
  std::vector<int> fill(start.begin(), start.end() - 1);
  int* rows = m.innerIndexPtr();
  each([&](int row, int col, int p) {
    rows[fill[std::size_t(col)]]                  = row;
    source[std::size_t(fill[std::size_t(col)]++)] = p;
  });
  for (int q = 0; q < ns; ++q) {
    rows[fill[std::size_t(own + q)]]                  = own + q;
    source[std::size_t(fill[std::size_t(own + q)]++)] = shift_code(q);
  }
  std::vector<std::pair<int, int>> column;
  for (int c = 0; c < own; ++c) {  // rows in order: K's column order is not M's
    column.clear();
    for (int p = start[std::size_t(c)]; p < start[std::size_t(c) + 1]; ++p)
      column.push_back({rows[p], source[std::size_t(p)]});
    std::sort(column.begin(), column.end());
    for (int p = start[std::size_t(c)], t = 0; p < start[std::size_t(c) + 1]; ++p, ++t)
      rows[p] = column[std::size_t(t)].first, source[std::size_t(p)] = column[std::size_t(t)].second;
  }
  std::fill_n(m.valuePtr(), start.back(), 0.0);
  detail::relax_supernodes(llt.cholmod(), k.rows());
  llt.analyze_natural(m);  // M's rows are in a postorder of its tree (top_split), the separator last
  if (llt.factor() == nullptr) return false;
  const int* perm   = static_cast<const int*>(llt.factor()->Perm);  // the identity; checked, not assumed
  const int* counts = static_cast<const int*>(llt.factor()->ColCount);
  tail_entries      = 0;
  for (int q = 0; q < ns; ++q) tail_entries += counts[own + q];
  tail_of.resize(std::size_t(ns));
  for (int q = 0; q < ns; ++q) {
    if (perm[own + q] < own) return false;  // the separator is not last in L
    tail_of[std::size_t(q)] = perm[own + q] - own;
  }
  return true;
}

}  // namespace gapfe

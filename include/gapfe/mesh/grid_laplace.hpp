#pragma once
// The I-J generator's Laplace fill (docs/theory.md 9) solved on the index lattice: conjugate gradients
// preconditioned by one geometric multigrid V-cycle. The seed relaxes point by point, which needs
// O(n) sweeps of O(n) work; a sparse direct solve needs O(n^1.5) work and several seconds at
// 1000 x 1000 (BENCHMARKS.md). Multigrid on the lattice needs O(n) work for any grid size.
//
// Equations: for every unknown point p, deg_p x_p - sum over existing neighbours q of x_q = 0, where
// deg_p counts the existing points among its four lattice neighbours and fixed neighbours move to the
// right-hand side. The matrix is symmetric positive definite when every unknown connects to a fixed
// point (each row of the I-J grid ends on fixed points, so it does).
//
// Multigrid: coarse lattice points are the fine points with both indices even (0-based); a coarse
// point is unknown when its fine point is, and the coarse operator is the 5-point rule on the coarse
// lattice (rediscretization, every neighbour counted in the diagonal). Restriction is full weighting without
// the 1/4 (weights 1, 1/2, 1/4), prolongation its transpose, so that with the unscaled operators A_H e_H =
// P^T r is the coarse correction equation. Smoothing: two red-black Gauss-Seidel sweeps before, two in the
// reverse colour order after, which keeps the V-cycle symmetric, as a CG preconditioner must be. The coarsest
// lattice (about 2,000 points) is solved directly. Both coordinates are solved together (Vec2 per point).
//
// Precision: CG runs in double (its residual is what the tolerance measures); the V-cycle, a
// preconditioner, in single precision. The V-cycle is memory-bound, so halving its arrays halves its
// cost (BENCHMARKS.md, "I-J mesh generator"), and a preconditioner needs only to reduce the error by a good
// factor: the operator's coefficients (0 to 4, 1/deg) are the same, and CG, measuring in double, still
// reaches 1e-13. The symmetry CG needs holds in exact arithmetic; single-precision rounding in it is far
// below the reduction per cycle.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "gapfe/core/error.hpp"
#include "gapfe/core/types.hpp"

namespace gapfe::detail {

class GridLaplace {
 public:
  enum : char { absent = 0, fixed = 1, unknown = 2 };
  static constexpr int kSweeps = 2;  // Gauss-Seidel sweeps before and after the coarse correction

  /// `state` holds one of absent, fixed, unknown per point, at [j * ni + i] (0-based).
  GridLaplace(int ni, int nj, const std::vector<char>& state) {
    Level fine = make_level(ni, nj, 1, nullptr,
                            [&](int i, int j) { return state[static_cast<std::size_t>(j) * ni + i]; });
    levels_.push_back(std::move(fine));
    for (int spacing = 2;
         levels_.back().ni * levels_.back().nj > 2000 && levels_.back().ni > 2 && levels_.back().nj > 2;
         spacing *= 2) {
      const Level& f = levels_.back();
      Level c        = make_level((f.ni + 1) / 2, (f.nj + 1) / 2, spacing, &levels_.front(),
                                  [&](int i, int j) { return f.state[f.at(2 * i, 2 * j)]; });
      levels_.push_back(std::move(c));
    }
    build_coarsest();
  }

  /// Solve A x = b. b and x live on the fine lattice, (i, j) at [j * ni + i]; b is read at the unknowns
  /// only, x holds the initial guess at the unknowns on entry and the solution there on return (other
  /// points untouched). In place, because at 1e6 points every fresh array's first touch costs more than a
  /// CG pass over it (BENCHMARKS.md lever 11). Throws SolveError when CG does not reach `tolerance`
  /// (residual relative to b).
  void solve(const std::vector<Vec2>& b_lattice, std::vector<Vec2>& x_lattice, double tolerance = 1e-13,
             int max_iterations = 200) {
    Level& L            = levels_.front();
    const std::size_t n = L.state.size();
    std::vector<Vec2> x(n, Vec2::Zero()), r(n, Vec2::Zero()), p(n), q(n, Vec2::Zero());
    for (int j = 0; j < L.nj; ++j)
      for (int i = 0; i < L.ni; ++i) {
        const std::size_t k = L.at(i, j), m = static_cast<std::size_t>(j) * L.ni + i;
        if (L.state[k] == unknown) r[k] = b_lattice[m], x[k] = x_lattice[m];
      }
    const Vec2 b_norm = norms(r);
    apply(L, x, q);
    for (std::size_t k = 0; k < n; ++k) r[k] -= q[k];
    if (b_norm.maxCoeff() > 0) {
      // Preconditioned CG with z = V-cycle(r) never stored: r goes to the cycle's right-hand side in the
      // pass that updates it, and z is read back from the cycle's result where r . z and p need it (the
      // loop is memory-bound, so passes are what it costs).
      Vec2 r_norm = Vec2::Zero();
      for (std::size_t k = 0; k < n; ++k) r_norm += r[k].cwiseProduct(r[k]), L.f[k] = r[k].cast<float>();
      r_norm = r_norm.cwiseSqrt();
      v_cycle(0);
      Vec2 rz = Vec2::Zero();
      for (std::size_t k = 0; k < n; ++k) {
        p[k] = L.e[k].cast<double>();
        rz += r[k].cwiseProduct(p[k]);
      }
      int iter = 0;
      for (;; ++iter) {
        const Vec2 res = r_norm.cwiseQuotient(b_norm.cwiseMax(1e-300));
        if (res.maxCoeff() <= tolerance) break;
        if (iter == max_iterations) {
          if (res.maxCoeff() <= 1e-10) break;  // stagnation at round-off: good enough for coordinates
          throw SolveError("mesh: the Laplace fill did not converge (relative residual " +
                           std::to_string(res.maxCoeff()) + ")");
        }
        const Vec2 pq    = apply(L, p, q);
        const Vec2 alpha = (pq.array() > 0).select(rz.cwiseQuotient(pq.cwiseMax(1e-300)), 0.0);
        Vec2 rr          = Vec2::Zero();
        for (std::size_t k = 0; k < n; ++k) {
          x[k] += alpha.cwiseProduct(p[k]), r[k] -= alpha.cwiseProduct(q[k]);
          rr += r[k].cwiseProduct(r[k]);
          L.f[k] = r[k].cast<float>();
        }
        r_norm = rr.cwiseSqrt();
        v_cycle(0);
        Vec2 rz_new = Vec2::Zero();
        for (std::size_t k = 0; k < n; ++k) rz_new += r[k].cwiseProduct(L.e[k].cast<double>());
        const Vec2 beta = (rz.array() > 0).select(rz_new.cwiseQuotient(rz.cwiseMax(1e-300)), 0.0);
        rz              = rz_new;
        for (std::size_t k = 0; k < n; ++k) p[k] = L.e[k].cast<double>() + beta.cwiseProduct(p[k]);
      }
      iterations_ = iter;
    }
    for (int j = 0; j < L.nj; ++j)
      for (int i = 0; i < L.ni; ++i)
        if (const std::size_t k = L.at(i, j); L.state[k] == unknown)
          x_lattice[static_cast<std::size_t>(j) * L.ni + i] = x[k];
  }

  int iterations() const { return iterations_; }
  int levels() const { return static_cast<int>(levels_.size()); }

 private:
  using Vec2f = Eigen::Vector2f;
  /// A lattice with a one-point border of absent points, so that neighbours need no bounds checks. The
  /// V-cycle's arrays are single precision (see the top).
  struct Level {
    int ni = 0, nj = 0, stride = 0;
    std::vector<char> state;
    std::vector<float> diag;      ///< deg_p for unknowns, 0 elsewhere
    std::vector<float> inv_diag;  ///< 1 / deg_p for unknowns, 0 elsewhere
    std::vector<float> mask;  ///< 1 for unknowns, 0 elsewhere (branch-free loops: off-unknown values stay 0)
    std::vector<Vec2f> e, f, res;
    std::size_t at(int i, int j) const { return static_cast<std::size_t>(j + 1) * stride + (i + 1); }
  };

  /// Coarse levels (spacing H > 1 fine steps) count every lattice neighbour in the diagonal (absent ones
  /// as zero error), which keeps each coarse operator diagonally dominant and never singular, whatever
  /// survives coarsening. Where the coarse neighbour is absent because the fine lattice's fixed boundary
  /// lies between (a fine size that is not 2^k + 1: the last fine row is odd and no coarse row), that
  /// direction counts H / d instead of 1, d < H the distance in fine steps to the first fixed point: the
  /// finite-volume weight of a zero-error boundary at distance d (face H over distance d, unscaled as the
  /// interior's H / H = 1). Without it the coarse problem put that boundary at distance H and CG took
  /// 13-14 cycles on a 500 x 1000 annulus instead of the 7 of the aligned 513 x 1025 (BENCHMARKS.md).
  template <class State>
  static Level make_level(int ni, int nj, int spacing, const Level* finest, State&& state_of) {
    const bool coarse = spacing > 1;
    Level L;
    L.ni = ni, L.nj = nj, L.stride = ni + 2;
    const std::size_t n = static_cast<std::size_t>(ni + 2) * (nj + 2);
    L.state.assign(n, absent);
    L.diag.assign(n, 0.0);
    for (int j = 0; j < nj; ++j)
      for (int i = 0; i < ni; ++i) L.state[L.at(i, j)] = state_of(i, j);
    const std::size_t s = static_cast<std::size_t>(L.stride);
    for (std::size_t k = 0; k < n; ++k) {
      if (L.state[k] != unknown) continue;
      L.diag[k] = coarse ? 4.0f
                         : static_cast<float>((L.state[k - 1] != absent) + (L.state[k + 1] != absent) +
                                              (L.state[k - s] != absent) + (L.state[k + s] != absent));
      if (L.diag[k] == 0) L.state[k] = fixed;  // isolated on this lattice: no coarse correction there
    }
    if (coarse)
      for (int j = 0; j < nj; ++j)
        for (int i = 0; i < ni; ++i) {
          const std::size_t k = L.at(i, j);
          if (L.state[k] != unknown) continue;
          for (const auto& [di, dj] :
               {std::array{-1, 0}, std::array{1, 0}, std::array{0, -1}, std::array{0, 1}}) {
            if (L.state[L.at(i + di, j + dj)] != absent) continue;
            for (int d = 1; d < spacing; ++d) {  // the first fine point that is not an unknown
              const char fine = finest->state[finest->at(spacing * i + d * di, spacing * j + d * dj)];
              if (fine == unknown) continue;
              if (fine == fixed) L.diag[k] += static_cast<float>(spacing) / static_cast<float>(d) - 1.0f;
              break;
            }
          }
        }
    L.inv_diag.assign(n, 0.0f), L.mask.assign(n, 0.0f);
    for (std::size_t k = 0; k < n; ++k)
      if (L.state[k] == unknown) L.inv_diag[k] = 1.0f / L.diag[k], L.mask[k] = 1.0f;
    L.e.assign(n, Vec2f::Zero()), L.f.assign(n, Vec2f::Zero()), L.res.assign(n, Vec2f::Zero());
    return L;
  }

  /// y = b - A x over the unknowns of a level (0 elsewhere; without b: y = A x); returns x . y per
  /// component. x and b must be 0 off the unknowns. One pass for the product and its dot product. In
  /// double for CG, in single precision inside the V-cycle (V = Vec2 or Vec2f).
  template <class V>
  static Vec2 apply(const Level& L, const std::vector<V>& xv, std::vector<V>& yv,
                    const std::vector<V>* bv = nullptr) {
    using T             = typename V::Scalar;
    const std::size_t s = static_cast<std::size_t>(L.stride), n = L.state.size();
    const T* x     = xv.data()->data();
    const T* b     = bv ? bv->data()->data() : nullptr;
    T* y           = yv.data()->data();
    const float *d = L.diag.data(), *m = L.mask.data();
    double dot[2] = {0, 0};
    for (std::size_t k = s; k + s < n; ++k)
      for (int c = 0; c < 2; ++c) {
        const std::size_t a = 2 * k + c;
        const T ax          = T(m[k]) * (T(d[k]) * x[a] - x[a - 2] - x[a + 2] - x[a - 2 * s] - x[a + 2 * s]);
        y[a]                = b ? b[a] - ax : ax;
        dot[c] += double(x[a]) * double(y[a]);
      }
    return {dot[0], dot[1]};
  }

  /// One red-black Gauss-Seidel sweep on A e = f: points with i + j even, then odd (forward), or odd
  /// then even (backward), so that forward-then-backward is symmetric. Points of one colour do not
  /// depend on each other, so each half-sweep pipelines; e stays 0 off the unknowns.
  static void gauss_seidel(Level& L, bool forward) {
    const std::size_t s  = static_cast<std::size_t>(L.stride);
    float* e             = L.e.data()->data();
    const float* f       = L.f.data()->data();
    const float* w       = L.inv_diag.data();
    const auto relax_row = [&](int j, int colour) {
      const std::size_t row = L.at(0, j);
      for (int i = (colour + j) % 2; i < L.ni; i += 2) {
        const std::size_t k = row + static_cast<std::size_t>(i), a = 2 * k;
        const float wk = w[k];
        e[a]           = wk * (f[a] + e[a - 2] + e[a + 2] + e[a - 2 * s] + e[a + 2 * s]);
        e[a + 1]       = wk * (f[a + 1] + e[a - 1] + e[a + 3] + e[a + 1 - 2 * s] + e[a + 1 + 2 * s]);
      }
    };
    // Both colours in one pass over memory: the second colour trails the first by one row, which is
    // the same as a whole first-colour half-sweep followed by a whole second-colour one (a point of
    // the second colour in row j needs the first colour in rows j - 1, j and j + 1).
    if (forward) {
      for (int j = 0; j <= L.nj; ++j) {
        if (j < L.nj) relax_row(j, 0);
        if (j > 0) relax_row(j - 1, 1);
      }
    } else {
      for (int j = L.nj - 1; j >= -1; --j) {
        if (j >= 0) relax_row(j, 1);
        if (j < L.nj - 1) relax_row(j + 1, 0);
      }
    }
  }

  /// Visit the fine points around coarse point (I, J) with their full-weighting weights.
  template <class F>
  static void stencil(const Level& fine, int I, int J, F&& visit) {
    static constexpr float w[3] = {0.5f, 1.0f, 0.5f};
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        const int i = 2 * I + di, j = 2 * J + dj;
        if (i < 0 || j < 0 || i >= fine.ni || j >= fine.nj) continue;
        const std::size_t k = fine.at(i, j);
        if (fine.state[k] == unknown) visit(k, w[di + 1] * w[dj + 1]);
      }
  }

  /// e = V-cycle approximation of A^-1 f on level l (f in levels_[l].f, result in levels_[l].e).
  void v_cycle(std::size_t l) {
    Level& L = levels_[l];
    if (l + 1 == levels_.size()) {
      coarsest_solve();
      return;
    }
    std::fill(L.e.begin(), L.e.end(), Vec2f::Zero());
    for (int sweep = 0; sweep < kSweeps; ++sweep) gauss_seidel(L, true);
    apply(L, L.e, L.res, &L.f);  // res = f - A e, 0 off the unknowns
    Level& C = levels_[l + 1];
    for (int J = 0; J < C.nj; ++J)
      for (int I = 0; I < C.ni; ++I) {
        const std::size_t kc = C.at(I, J);
        Vec2f sum            = Vec2f::Zero();
        if (C.state[kc] == unknown) stencil(L, I, J, [&](std::size_t k, float wt) { sum += wt * L.res[k]; });
        C.f[kc] = sum;
      }
    v_cycle(l + 1);
    for (int J = 0; J < C.nj; ++J)
      for (int I = 0; I < C.ni; ++I) {
        const std::size_t kc = C.at(I, J);
        if (C.state[kc] == unknown)
          stencil(L, I, J, [&](std::size_t k, float wt) { L.e[k] += wt * C.e[kc]; });
      }
    for (int sweep = 0; sweep < kSweeps; ++sweep) gauss_seidel(L, false);
  }

  void build_coarsest() {
    Level& L = levels_.back();
    coarse_index_.assign(L.state.size(), -1);
    int n = 0;
    for (std::size_t k = 0; k < L.state.size(); ++k)
      if (L.state[k] == unknown) coarse_index_[k] = n++;
    std::vector<Eigen::Triplet<double, int>> t;
    const std::size_t s = static_cast<std::size_t>(L.stride);
    for (std::size_t k = 0; k < L.state.size(); ++k) {
      if (coarse_index_[k] < 0) continue;
      t.emplace_back(coarse_index_[k], coarse_index_[k], static_cast<double>(L.diag[k]));
      for (const std::size_t q : {k - 1, k + 1, k - s, k + s})
        if (coarse_index_[q] >= 0) t.emplace_back(coarse_index_[k], coarse_index_[q], -1.0);
    }
    if (n == 0) return;
    SpMat a(n, n);
    a.setFromTriplets(t.begin(), t.end());
    coarse_.compute(a);
    if (coarse_.info() != Eigen::Success)
      throw InputError(
          "mesh: the interior-point equations are singular (a group of grid points touches no "
          "point placed by a line segment card)");
  }

  void coarsest_solve() {
    Level& L = levels_.back();
    std::fill(L.e.begin(), L.e.end(), Vec2f::Zero());
    const int n = static_cast<int>(coarse_.rows());
    if (n == 0) return;
    Eigen::Matrix<double, Eigen::Dynamic, 2> b(n, 2);
    for (std::size_t k = 0; k < L.state.size(); ++k)
      if (coarse_index_[k] >= 0) b.row(coarse_index_[k]) = L.f[k].cast<double>().transpose();
    const Eigen::Matrix<double, Eigen::Dynamic, 2> x = coarse_.solve(b);
    for (std::size_t k = 0; k < L.state.size(); ++k)
      if (coarse_index_[k] >= 0) L.e[k] = x.row(coarse_index_[k]).transpose().cast<float>();
  }

  Vec2 dots(const std::vector<Vec2>& a, const std::vector<Vec2>& b) const {
    Vec2 s = Vec2::Zero();
    for (std::size_t k = 0; k < a.size(); ++k) s += a[k].cwiseProduct(b[k]);
    return s;
  }
  Vec2 norms(const std::vector<Vec2>& a) const { return dots(a, a).cwiseSqrt(); }

  std::vector<Level> levels_;
  std::vector<int> coarse_index_;
  Eigen::SimplicialLDLT<SpMat> coarse_;
  int iterations_ = 0;
};

}  // namespace gapfe::detail

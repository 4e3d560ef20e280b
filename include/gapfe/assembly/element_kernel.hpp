#pragma once
// The one element kernel every variant uses: stiffness, consistent loads, static condensation of
// interior nodes, and recovery of strains and stresses. Fixed-size Eigen types only, no allocation.
//
// DATA LAYOUT: element DOFs are node-major, (u_r, u_z[, u_theta]) per node; shape nodes are the
// element's nodes followed by its interior (condensed) nodes, so the first kDofs entries of a
// shape-level vector are the element's own DOFs. Strain vectors have Kin::kStrain entries, the
// rows Kin::kVoigt of the global Voigt-6 vector.
#include <algorithm>
#include <array>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "gapfe/core/concepts.hpp"

namespace gapfe {

/// Body force per unit volume from rigid-body motion of the frame (docs/theory.md 4.1, seed Data 12):
/// b = rho (omega^2 r, -a_z, -omega_dot r) in (r, z, theta), d'Alembert inertia.
struct BodyForce {
  double radial_per_r = 0.0;  ///< rho omega^2 [force / length^4]
  double axial        = 0.0;  ///< -rho a_z [force / length^3]
  double hoop_per_r   = 0.0;  ///< -rho omega_dot [force / length^4]
  bool any() const { return radial_per_r != 0 || axial != 0 || hoop_per_r != 0; }
};

template <class Kin, class Elem>
requires KinematicsFor<Kin, Elem>
struct ElementKernel {
  static constexpr int kDofsPerNode = Kin::kDofsPerNode;
  static constexpr int kStrain      = Kin::kStrain;
  static constexpr int kDofs        = kDofsPerNode * Elem::kNodes;
  static constexpr int kShapeDofs   = kDofsPerNode * Elem::kShapeNodes;
  static constexpr int kInner       = kShapeDofs - kDofs;

  using Coords       = Mat<Elem::kNodes, 2>;
  using Matrix       = Mat<kDofs, kDofs>;
  using Vector       = Vec<kDofs>;
  using ShapeMatrix  = Mat<kShapeDofs, kShapeDofs>;
  using ShapeVector  = Vec<kShapeDofs>;
  using StrainMatrix = Mat<kStrain, kStrain>;
  using StrainVector = Vec<kStrain>;

  /// The kinematics' block of a Voigt-6 matrix / vector.
  static StrainMatrix restrict(const Mat66& d) {
    StrainMatrix m;
    for (int i = 0; i < kStrain; ++i)
      for (int j = 0; j < kStrain; ++j) m(i, j) = d(Kin::kVoigt[i], Kin::kVoigt[j]);
    return m;
  }
  static StrainVector restrict(const Vec6& v) {
    StrainVector s;
    for (int i = 0; i < kStrain; ++i) s(i) = v(Kin::kVoigt[i]);
    return s;
  }
  static Vec6 extend(const StrainVector& s) {
    Vec6 v = Vec6::Zero();
    for (int i = 0; i < kStrain; ++i) v(Kin::kVoigt[i]) = s(i);
    return v;
  }

  using StrainDisplacement = Mat<kStrain, kShapeDofs>;
  using VolumetricRow      = Eigen::Matrix<double, 1, kShapeDofs>;

  /// B-bar (Hughes 1980; docs/theory.md 1.2): an element that declares kPressureModes has the volumetric
  /// strain eps_rr + eps_zz + eps_hoop at each point replaced by its projection, over the element and in
  /// the volume measure 2 pi r dA, on that many pressure modes: 1 (the mean dilatation) or 1, r, z (a
  /// pressure linear in the cell). This relieves the volumetric locking of near-incompressible (and plastic)
  /// flow; a quadratic cell needs the linear modes to keep its stresses second order where the pressure
  /// varies. A bilinear pressure (1, r, z, r z) was measured to lock on mapped cells and is not offered
  /// (docs/accuracy.md, "Near incompressibility").
  static constexpr int kPressureModes = [] {
    if constexpr (requires { Elem::kPressureModes; })
      return int{Elem::kPressureModes};
    else
      return 0;
  }();
  static_assert(kPressureModes == 0 || kPressureModes == 1 || kPressureModes == 3,
                "pressure modes: 1 (the mean) or 3 (linear)");
  static constexpr bool kBBar = kPressureModes > 0;
  using ModeRow               = Eigen::Matrix<double, 1, std::max(kPressureModes, 1)>;

  /// The projected volumetric strain of one element: at a point with pressure modes p (a row),
  /// eps_vol_bar = p * coefficients * u_s. Modes past the first are r and z about the nodes' centre, each
  /// over the nodes' extent in it (O(1) on a cell of any size or aspect; a thin cell along a diagonal still
  /// makes them nearly dependent), evaluated through the shape functions.
  struct Dilatation {
    Mat<std::max(kPressureModes, 1), kShapeDofs> coefficients = decltype(coefficients)::Zero();
    Vec<Elem::kShapeNodes> r = Vec<Elem::kShapeNodes>::Zero(), z = Vec<Elem::kShapeNodes>::Zero();
  };
  static ModeRow pressure_modes(const PointGeometry<Elem::kShapeNodes>& g, const Dilatation& d) {
    ModeRow p;
    p(0) = 1.0;
    if constexpr (kPressureModes == 3) p(1) = g.N.dot(d.r), p(2) = g.N.dot(d.z);
    return p;
  }

  /// The geometry of every stiffness point, for passes that visit them more than once (B-bar's projection,
  /// then each point): computed once per element.
  using Points = std::array<PointGeometry<Elem::kShapeNodes>, Elem::kStiffnessPoints>;
  static Points stiffness_points(const Coords& x) {
    Points p;
    double det = 0;
    for (int q = 0; q < Elem::kStiffnessPoints; ++q) p[q] = Elem::stiffness_point(x, q, det);
    return p;
  }

  /// The projection's coefficients, M^-1 int p^T (B_rr + B_zz + B_hoop) dV with M = int p^T p dV over the
  /// stiffness points (one mode: the mean, (1/V) int B_vol dV); zero without B-bar.
  static Dilatation dilatation(const Points& points, const Coords& x) {
    Dilatation d;
    if constexpr (kBBar) {
      if constexpr (kPressureModes > 1) {
        const auto xs     = Elem::shape_coords(x);
        const Vec2 centre = xs.colwise().mean().transpose();
        const Vec2 extent = (xs.colwise().maxCoeff() - xs.colwise().minCoeff()).transpose();
        d.r               = (xs.col(0).array() - centre(0)) / extent(0);
        d.z               = (xs.col(1).array() - centre(1)) / extent(1);
      }
      using Modes = Mat<std::max(kPressureModes, 1), std::max(kPressureModes, 1)>;
      Modes mass  = Modes::Zero();
      for (const auto& g : points) {
        const StrainDisplacement b     = Kin::B(g);
        const ModeRow p                = pressure_modes(g, d);
        const VolumetricRow volumetric = b.template topRows<3>().colwise().sum();
        // lazyProduct: small fixed products unrolled rather than sent to Eigen's GEMM (stiffness_rows).
        d.coefficients.noalias() += (g.weight * p.transpose()).lazyProduct(volumetric);
        mass.noalias() += (g.weight * p.transpose()).lazyProduct(p);
      }
      // M^-1 by Eigen's closed form for 3 x 3 (a factorization's solve took a tenth of the element's time in
      // its blocked triangular kernels); M is well scaled, its modes being O(1) on the cell.
      if constexpr (kPressureModes == 1)
        d.coefficients /= mass(0, 0);
      else
        d.coefficients = mass.inverse().lazyProduct(d.coefficients).eval();
    } else {
      (void)points, (void)x;
    }
    return d;
  }
  static Dilatation dilatation(const Coords& x) {
    if constexpr (kBBar)
      return dilatation(stiffness_points(x), x);
    else
      return {};
  }
  /// B at a point; with B-bar, B + (1/3) m (eps_vol_bar - B_vol), m = 1 on the normal rows rr, zz, hoop
  /// (the first three rows of both kinematics).
  static StrainDisplacement point_B(const PointGeometry<Elem::kShapeNodes>& g, const Dilatation& d) {
    StrainDisplacement b = Kin::B(g);
    if constexpr (kBBar) {
      VolumetricRow projected;
      if constexpr (kPressureModes == 1)
        projected = d.coefficients;
      else
        projected.noalias() = pressure_modes(g, d).lazyProduct(d.coefficients);
      const VolumetricRow shift = (projected - b.template topRows<3>().colwise().sum()) / 3.0;
      for (int i = 0; i < 3; ++i) b.row(i) += shift;
    }
    return b;
  }

  /// K_s = sum_q B^T D B 2 pi r |J| w over the stiffness points (before condensation).
  static ShapeMatrix shape_stiffness(const Coords& x, const StrainMatrix& D) {
    return stiffness_rows<0, kShapeDofs>(x, D);
  }
  /// Rows [First, First + Rows) of shape_stiffness: recovery's expand() needs the interior DOFs' rows only
  /// (for the legacy quad 2 of 10, a third of the products).
  template <int First, int Rows>
  static Mat<Rows, kShapeDofs> stiffness_rows(const Coords& x, const StrainMatrix& D) {
    Mat<Rows, kShapeDofs> k   = Mat<Rows, kShapeDofs>::Zero();
    const Points points       = stiffness_points(x);
    const Dilatation dilation = dilatation(points, x);
    for (const auto& g : points) {
      const StrainDisplacement b   = point_B(g, dilation);
      const StrainDisplacement d_b = D * b;
      // lazyProduct: Eigen sends a fixed 8 x 4 by 4 x 8 product (and larger) to its blocked GEMM, whose
      // packing costs more than the product; coefficient-based, it unrolls (BENCHMARKS.md, "Levers, each
      // measured").
      k.noalias() += g.weight * b.template middleCols<Rows>(First).transpose().lazyProduct(d_b);
    }
    return k;
  }

  /// f_s = int N^T b dV (load points) + int B^T D eps_th dV (stiffness points, the same rule as K so
  /// that a free uniform expansion is reproduced with zero stress; docs/theory.md 3.4 and V8).
  static ShapeVector shape_load(const Coords& x, const StrainMatrix& D, const StrainVector& eps_th,
                                const BodyForce& body) {
    ShapeVector f = ShapeVector::Zero();
    double det    = 0;
    if (body.any()) {
      for (int q = 0; q < Elem::kLoadPoints; ++q) {
        const auto g = Elem::load_point(x, q, det);
        for (int a = 0; a < Elem::kShapeNodes; ++a) {
          const double nw = g.N(a) * g.weight;
          f(kDofsPerNode * a) += nw * body.radial_per_r * g.r;
          f(kDofsPerNode * a + 1) += nw * body.axial;
          if constexpr (kDofsPerNode == 3) f(kDofsPerNode * a + 2) += nw * body.hoop_per_r * g.r;
        }
      }
    }
    if (!eps_th.isZero(0.0)) {
      const StrainVector s_th   = D * eps_th;
      const Dilatation dilation = dilatation(x);
      for (int q = 0; q < Elem::kStiffnessPoints; ++q) {
        const auto g = Elem::stiffness_point(x, q, det);
        f.noalias() += g.weight * (point_B(g, dilation).transpose() * s_th);
      }
    }
    return f;
  }

  /// Static condensation of interior DOFs (docs/theory.md 2 item 3):
  /// K* = Kcc - Kci Kii^-1 Kic,  F* = Fc - Kci Kii^-1 Fi. A no-op copy without interior nodes.
  static void condense(const ShapeMatrix& ks, const ShapeVector& fs, Matrix& k, Vector& f) {
    if constexpr (kInner == 0) {
      k = ks;
      f = fs;
    } else {
      const Eigen::LDLT<Mat<kInner, kInner>> kii(ks.template bottomRightCorner<kInner, kInner>());
      const Mat<kInner, kDofs> kii_kic = kii.solve(ks.template bottomLeftCorner<kInner, kDofs>());
      const Vec<kInner> kii_fi         = kii.solve(fs.template tail<kInner>());
      k = ks.template topLeftCorner<kDofs, kDofs>() - ks.template topRightCorner<kDofs, kInner>() * kii_kic;
      f = fs.template head<kDofs>() - ks.template topRightCorner<kDofs, kInner>() * kii_fi;
    }
  }
  /// Condensed stiffness only (no loads).
  static Matrix stiffness(const Coords& x, const StrainMatrix& D) {
    if constexpr (kInner == 0) {
      return shape_stiffness(x, D);
    } else {
      Matrix k;
      Vector f;
      condense(shape_stiffness(x, D), ShapeVector::Zero(), k, f);
      return k;
    }
  }

  /// Interior DOFs from the element's own: u_i = Kii^-1 (F_i - K_ic u_c); `inner` holds the interior
  /// rows of K_s, [K_ic K_ii] (inner_rows()).
  static ShapeVector expand(const Mat<kInner, kShapeDofs>& inner, const ShapeVector& fs,
                            const Vector& u) requires(kInner > 0) {
    ShapeVector us;
    us.template head<kDofs>() = u;
    const Eigen::LDLT<Mat<kInner, kInner>> kii(inner.template rightCols<kInner>());
    us.template tail<kInner>() = kii.solve(fs.template tail<kInner>() - inner.template leftCols<kDofs>() * u);
    return us;
  }
  /// The interior DOFs' rows of K_s, what expand() reads.
  static Mat<kInner, kShapeDofs> inner_rows(const Coords& x, const StrainMatrix& D) requires(kInner > 0) {
    return stiffness_rows<kDofs, kInner>(x, D);
  }

  /// Voigt-6 strain at a point from shape-level displacements (zero in slots the kinematics lacks);
  /// `d` from dilatation() of the same element.
  static Vec6 strain(const PointGeometry<Elem::kShapeNodes>& g, const Dilatation& d, const ShapeVector& us) {
    return extend(point_B(g, d) * us);
  }
};

}  // namespace gapfe

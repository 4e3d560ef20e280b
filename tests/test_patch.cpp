// Constant-strain patch tests: every element, both kinematics, patches on and off the axis.
#include <map>
#include <tuple>

#include "support.hpp"

using namespace gapfe;
using test::rel;

namespace {

/// A 2x2 patch of distorted cells on [r0, r0 + 2] x [0, 2]; the interior corner is moved off the grid.
/// Quad8 gets straight edges with mid-side nodes, its last cell split into two 6-node triangles (its mesh's
/// 3-corner cells); Tri3 and Tri6 split every quad along alternating diagonals.
template <class Elem>
Mesh<Elem::kNodes> patch(double r0) {
  Mesh<4> q;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) q.nodes.push_back({r0 + i, j * 1.0});
  q.nodes[4] += Vec2(0.13, -0.11);
  // Boundary nodes of the outer square are moved too so that no cell is a rectangle.
  q.nodes[1] += Vec2(0.07, 0.0);
  q.nodes[7] += Vec2(-0.09, 0.0);
  q.nodes[3] += Vec2(0.0, 0.08);
  q.nodes[5] += Vec2(0.0, -0.06);
  q.cells = {{0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}, {4, 5, 8, 7}};
  if constexpr (Elem::kNodes == 4) {
    return q;
  } else {
    Mesh<Elem::kNodes> m;
    m.nodes = q.nodes;
    std::map<std::pair<int, int>, int> mid;
    auto midside = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      if (auto it = mid.find(key); it != mid.end()) return it->second;
      m.nodes.push_back(0.5 * (q.nodes[a] + q.nodes[b]));
      return mid[key] = m.node_count() - 1;
    };
    const auto triangle = [&](int a, int b, int c) -> std::array<int, Elem::kNodes == 3 ? 3 : 6> {
      if constexpr (Elem::kNodes == 3)
        return {a, b, c};
      else
        return {a, b, c, midside(a, b), midside(b, c), midside(c, a)};
    };
    for (std::size_t e = 0; e < q.cells.size(); ++e) {
      const auto& c = q.cells[e];
      if constexpr (Elem::kNodes == 8) {
        if (e + 1 < q.cells.size())
          m.cells.push_back({c[0], c[1], c[2], c[3], midside(c[0], c[1]), midside(c[1], c[2]),
                             midside(c[2], c[3]), midside(c[3], c[0])});
        else
          m.triangles.push_back(triangle(c[0], c[1], c[2])),
              m.triangles.push_back(triangle(c[0], c[2], c[3]));
      } else if (e % 2 == 0) {
        m.cells.push_back(triangle(c[0], c[1], c[2])), m.cells.push_back(triangle(c[0], c[2], c[3]));
      } else {
        m.cells.push_back(triangle(c[0], c[1], c[3])), m.cells.push_back(triangle(c[1], c[2], c[3]));
      }
    }
    return m;
  }
}

/// The linear field u_r = a r, u_z = b z + c r + e, u_theta = w r: constant strain
/// (rr = hoop = a, zz = b, rz = c; the theta part is a rigid rotation).
struct LinearField {
  double a = 1.3e-3, b = -0.7e-3, c = 0.4e-3, e = 2e-4, w = 0.9e-3;
  Vec3 at(const Vec2& x) const { return {a * x(0), b * x(1) + c * x(0) + e, w * x(0)}; }
  Vec6 strain(bool shear) const { return (Vec6() << a, b, a, shear ? c : 0.0, 0, 0).finished(); }
};

/// Patch test: prescribe the field on every node (all_nodes) or on the patch boundary only; check
/// nodal displacements and every integration-point strain against the field to 1e-10 relative.
template <class M>
void patch_test(double r0, bool all_nodes) {
  using Elem        = typename M::Element;
  constexpr int kNd = M::kDofsPerNode;
  Problem<M> p;
  p.mesh      = patch<Elem>(r0);
  p.materials = {M::Material::constant(200e9, 0.3)};
  LinearField field;
  // A constant sigma_rz is not in equilibrium in a ring without body force (z: d(r s_rz)/dr / r != 0), so
  // it is exact only where every node is prescribed; LegacyQuad's condensed centre node is always free.
  if (!all_nodes || ElementKernel<typename M::Kinematics, Elem>::kInner > 0) field.c = 0;
  if (kNd == 2) field.w = 0;
  const double size = 2.0;
  for (int n = 0; n < p.mesh.node_count(); ++n) {
    const Vec2 x = p.mesh.nodes[n];
    const bool boundary =
        std::abs(x(0) - r0) < 1e-12 || x(1) == 0 || std::abs(x(0) - (r0 + 2)) < 1e-12 || x(1) == 2;
    if (all_nodes || boundary) {
      const Vec3 u = field.at(x);
      p.conditions.push_back({n, kNd == 3 ? 7 : 3, {u(0), u(1), u(2)}});
    }
  }
  (void)size;
  LinearStatic<M> analysis(std::move(p));
  const Solution& s    = analysis.solve();
  const double u_scale = field.at(Vec2(r0 + 2, 2)).norm();
  for (int n = 0; n < analysis.problem().mesh.node_count(); ++n) {
    const Vec3 exact = field.at(analysis.problem().mesh.nodes[n]);
    for (int c = 0; c < kNd; ++c) CHECK(std::abs(s.displacement(n, c) - exact(c)) <= 1e-10 * u_scale);
  }
  const Vec6 eps = field.strain(all_nodes);
  for (const auto& v : analysis.point_values()) CHECK((v.strain - eps).norm() <= 1e-10 * eps.norm());
  for (const auto& v : analysis.centroid_values()) CHECK((v.strain - eps).norm() <= 1e-10 * eps.norm());
}

}  // namespace

// Every element in both kinematics.
using AllVariants = std::tuple<Model<Axisym2, Quad4, Isotropic>, Model<Axisym3, Quad4, Isotropic>,
                               Model<Axisym2, LegacyQuad, Isotropic>, Model<Axisym3, LegacyQuad, Isotropic>,
                               Model<Axisym2, Quad8, Isotropic>, Model<Axisym3, Quad8, Isotropic>,
                               Model<Axisym2, Tri3, Isotropic>, Model<Axisym3, Tri3, Isotropic>,
                               Model<Axisym2, Tri6, Isotropic>, Model<Axisym3, Tri6, Isotropic>>;

TEST_CASE_TEMPLATE_DEFINE("[element] patch test, boundary prescribed, interior free", M, boundary_patch) {
  SUBCASE("off the axis") {
    patch_test<M>(1.0, false);
  }
  SUBCASE("touching r = 0") {
    patch_test<M>(0.0, false);
  }
}
TEST_CASE_TEMPLATE_APPLY(boundary_patch, AllVariants);

TEST_CASE_TEMPLATE_DEFINE("[element] patch test, every node prescribed (strain consistency incl. rz shear)",
                          M, all_nodes_patch) {
  SUBCASE("off the axis") {
    patch_test<M>(1.0, true);
  }
  SUBCASE("touching r = 0") {
    patch_test<M>(0.0, true);
  }
}
TEST_CASE_TEMPLATE_APPLY(all_nodes_patch, AllVariants);

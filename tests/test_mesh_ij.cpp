// The I-J mesh generator (seed Data 3-4, docs/theory.md 9): arcs on their circles, the Laplace fill of a
// rectangle is the uniform grid, boundary diagonals make triangles, numbering as the seed specifies.
#include <cmath>

#include <doctest/doctest.h>

#include "gapfe/mesh/ij_grid.hpp"

using namespace gapfe;

namespace {

Segment line(int i1, int j1, Vec2 a, int i2, int j2, Vec2 b, SegmentType t = SegmentType::line) {
  return {{GridPoint{i1, j1, a}, GridPoint{i2, j2, b}, GridPoint{}}, t};
}

std::vector<Segment> rectangle(int ni, int nj, double r0, double r1, double z0, double z1) {
  return {line(1, 1, {r0, z0}, ni, 1, {r1, z0}), line(ni, 1, {r1, z0}, ni, nj, {r1, z1}),
          line(ni, nj, {r1, z1}, 1, nj, {r0, z1}), line(1, nj, {r0, z1}, 1, 1, {r0, z0})};
}

}  // namespace

TEST_CASE("I-J mesh: a quarter annulus from arcs of type 3 and 4 has its boundary nodes on the circles") {
  // I runs outward along the radius (1..ni), J along the angle from the r axis (J = 1) to the z axis.
  const int ni = 6, nj = 13;
  const double ri = 1.0, ro = 2.0, h = std::sqrt(0.5);
  std::vector<Segment> s;
  s.push_back(line(1, 1, {ri, 0}, ni, 1, {ro, 0}));    // on the r axis
  s.push_back(line(ni, nj, {0, ro}, 1, nj, {0, ri}));  // on the z axis
  s.push_back({{GridPoint{ni, 1, {ro, 0}}, GridPoint{ni, nj, {0, ro}}, GridPoint{0, 0, {0, 0}}},
               SegmentType::arc_centre});  // outer, CCW
  s.push_back(
      {{GridPoint{1, 1, {ri, 0}}, GridPoint{1, (nj + 1) / 2, {h * ri, h * ri}}, GridPoint{1, nj, {0, ri}}},
       SegmentType::arc_three_points});  // inner
  const IJGrid g = generate_ij_grid(ni, nj, s);
  REQUIRE(g.node_count() == ni * nj);
  REQUIRE(g.cells.size() == static_cast<std::size_t>((ni - 1) * (nj - 1)));
  for (int j = 1; j <= nj; ++j) {
    const double angle = (kTwoPi / 4) * (j - 1) / (nj - 1);  // evenly spaced in angle
    for (const auto& [i, radius] : {std::pair{1, ri}, std::pair{ni, ro}}) {
      const Vec2 x = g.nodes[g.node(i, j)];
      CHECK(std::abs(x.norm() - radius) < 1e-12);
      CHECK(std::abs(std::atan2(x(1), x(0)) - angle) < 1e-12);
    }
  }
  // The Laplace fill stays inside the annulus and every cell is counterclockwise (checked on build).
  for (const auto& x : g.nodes) CHECK((x.norm() > ri - 1e-12 && x.norm() < ro + 1e-12));
  CHECK_FALSE(g.reversed);
}

TEST_CASE("I-J mesh: a rectangle's interior nodes form the uniform grid") {
  const int ni = 5, nj = 9;
  const IJGrid g = generate_ij_grid(ni, nj, rectangle(ni, nj, 1.0, 3.0, 0.0, 2.0));
  REQUIRE(g.node_count() == ni * nj);
  int interior = 0;
  for (int j = 1; j <= nj; ++j)
    for (int i = 1; i <= ni; ++i) {
      const Vec2 x = g.nodes[g.node(i, j)];
      CHECK(std::abs(x(0) - (1.0 + 0.5 * (i - 1))) < 1e-12);
      CHECK(std::abs(x(1) - 0.25 * (j - 1)) < 1e-12);
      interior += !g.placed[g.node(i, j)];
    }
  CHECK(interior == (ni - 2) * (nj - 2));
}

TEST_CASE(
    "I-J mesh: numbering is J ascending then I, element (I, J) has corners (I,J) (I+1,J) (I+1,J+1) (I,J+1)") {
  const int ni = 4, nj = 3;
  const IJGrid g = generate_ij_grid(ni, nj, rectangle(ni, nj, 0.0, 3.0, 0.0, 2.0));
  for (int j = 1; j <= nj; ++j)
    for (int i = 1; i <= ni; ++i) {
      const int n = g.node(i, j);
      CHECK(n + 1 == (j - 1) * ni + i);
      CHECK(g.node_ij[n] == std::array{i, j});
    }
  REQUIRE(g.cells.size() == 6);
  for (std::size_t e = 0; e < g.cells.size(); ++e) {
    const GridCell& c = g.cells[e];
    CHECK(static_cast<int>(e) + 1 == (c.j - 1) * (ni - 1) + c.i);
    CHECK(c.corners == 4);
    CHECK(c.node ==
          std::array{g.node(c.i, c.j), g.node(c.i + 1, c.j), g.node(c.i + 1, c.j + 1), g.node(c.i, c.j + 1)});
  }
  // Node 1 is (I, J) = (1, 1) on the r axis: r = 0 here.
  CHECK(g.nodes[0].isZero(0.0));
}

TEST_CASE("I-J mesh: type 5 boundary diagonals cut the cells beside them into triangles") {
  // Rows: J = 1 spans I 1..5, J = 2 spans 2..5, J = 3 spans 3..5; the diagonal (1,1)-(3,3) bounds it.
  std::vector<Segment> s = {line(1, 1, {0, 0}, 5, 1, {4, 0}), line(5, 1, {4, 0}, 5, 3, {4, 2}),
                            line(5, 3, {4, 2}, 3, 3, {2, 2}),
                            line(3, 3, {2, 2}, 1, 1, {0, 0}, SegmentType::min_diagonal)};
  const IJGrid g         = generate_ij_grid(5, 3, s);
  CHECK(g.row_min == std::vector{1, 2, 3});
  CHECK(g.row_max == std::vector{5, 5, 5});
  CHECK(g.node_count() == 5 + 4 + 3);
  const Mesh<4> m = g.to_mesh();
  CHECK(m.cells.size() == 5);
  REQUIRE(m.triangles.size() == 2);
  // In numbering order: element 1 is the triangle at (1, 1), element 5 the triangle at (2, 2).
  CHECK(g.cells[0].corners == 3);
  CHECK(g.cells[0].node[0] == g.node(1, 1));
  CHECK(g.cells[0].node[1] == g.node(2, 1));
  CHECK(g.cells[0].node[2] == g.node(2, 2));
  CHECK(g.cells[4].corners == 3);
  CHECK((g.cells[4].i == 2 && g.cells[4].j == 2));
  CHECK(m.triangles[1] == std::array{g.node(2, 2), g.node(3, 2), g.node(3, 3)});
  // The interior point (2, 2) sits on the diagonal's right: the Laplace mean of (3,2), (2,1) ... lies inside.
  const Vec2 x = g.nodes[g.node(3, 2)];
  CHECK((x(0) > 1.0 && x(0) < 4.0 && x(1) > 0.0 && x(1) < 2.0));
}

TEST_CASE("I-J mesh: I along z gives a clockwise grid, whose cells are reversed to stay counterclockwise") {
  const int ni = 3, nj = 4;
  std::vector<Segment> s = {line(1, 1, {0, 0}, ni, 1, {0, 2}), line(ni, 1, {0, 2}, ni, nj, {3, 2}),
                            line(ni, nj, {3, 2}, 1, nj, {3, 0}), line(1, nj, {3, 0}, 1, 1, {0, 0})};
  const IJGrid g         = generate_ij_grid(ni, nj, s);
  CHECK(g.reversed);
  for (const auto& c : g.cells) {
    const Vec2 a = g.nodes[c.node[0]], b = g.nodes[c.node[1]], d = g.nodes[c.node[2]];
    CHECK((b - a)(0) * (d - a)(1) - (b - a)(1) * (d - a)(0) > 0);
  }
}

TEST_CASE("I-J mesh: malformed segments and folded grids are errors that name the card or element") {
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // Not a row, column or 45-degree diagonal.
  CHECK(message([] {
          generate_ij_grid(4, 4, {line(1, 1, {0, 0}, 3, 2, {1, 1})});
        }).find("line segment card 1") != std::string::npos);
  // Index outside MAXI.
  CHECK(message([] {
          generate_ij_grid(4, 4, {line(1, 1, {0, 0}, 5, 1, {1, 0})});
        }).find("outside") != std::string::npos);
  // Collinear three-point arc.
  CHECK(message([] {
          generate_ij_grid(4, 4,
                           {{{GridPoint{1, 1, {0, 0}}, GridPoint{1, 2, {1, 0}}, GridPoint{1, 3, {2, 0}}},
                             SegmentType::arc_three_points}});
        }).find("collinear") != std::string::npos);
  // A rectangle whose top edge is given below its bottom edge folds: negative area.
  CHECK(message([] {
          generate_ij_grid(3, 3, rectangle(3, 3, 0.0, 2.0, 1.0, 1.0));
        }).find("zero or negative area") != std::string::npos);
}

TEST_CASE("I-J mesh: a 200 x 200 grid fills its interior by one sparse solve") {
  // Speed lives in bench/ (bench_mesh); here the result: the interior of a square is the uniform grid.
  const int n    = 200;
  const IJGrid g = generate_ij_grid(n, n, rectangle(n, n, 0.0, 1.0, 0.0, 1.0));
  double worst   = 0;
  for (int j = 1; j <= n; ++j)
    for (int i = 1; i <= n; ++i)
      worst =
          std::max(worst, (g.nodes[g.node(i, j)] - Vec2((i - 1.0) / (n - 1), (j - 1.0) / (n - 1))).norm());
  CHECK(worst < 1e-12);
}

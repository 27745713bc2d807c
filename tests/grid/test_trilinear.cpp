// Trilinear interpolation: properties of the interpolant against independent answers
// (linear fields, corner bounds, node values, a hand-written bilinear face formula,
// central differences for the gradient).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ppohdem/grid/trilinear.hpp"

namespace ppohdem {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

/// A grid whose origin is an integer and whose spacings are powers of two (2^-3 .. 2^3), so that
/// node positions, points o + (i + m/1024) h and the index coordinate (p - o)/h are all exact:
/// the tests below can then know the containing cell and local coordinates without rounding.
GridSpec gen_dyadic_grid(int min_nodes) {
  GridSpec g;
  for (int a = 0; a < 3; ++a) {
    g.origin[a] = *rc::gen::inRange(-50, 51);
    g.spacing[a] = std::ldexp(1.0, *rc::gen::inRange(-3, 4));  // anisotropic in general
    g.nodes[static_cast<std::size_t>(a)] = *rc::gen::inRange(min_nodes, 7);
  }
  return g;
}

/// Random node values in [-1000, 1000] with 1/16 resolution.
ScalarField gen_field(const GridSpec& g) {
  ScalarField f(g);
  for (double& v : f.values) v = *rc::gen::inRange(-16000, 16001) / 16.0;
  return f;
}

/// A point inside the grid given as (cell index, numerator m of t = m/1024) per axis, exactly.
struct CellPoint {
  Index3 cell;
  Vec3 t;
  Vec3 p;
};
CellPoint gen_point_in_cell(const GridSpec& g) {
  CellPoint c;
  for (int a = 0; a < 3; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    const int n = g.nodes[ua];
    if (n == 1) {
      c.cell[ua] = 0;
      c.t[a] = 0.0;
    } else {
      c.cell[ua] = *rc::gen::inRange(0, n - 1);
      c.t[a] = *rc::gen::inRange(0, 1025) / 1024.0;  // includes both faces of the cell
    }
    c.p[a] = g.origin[a] + (c.cell[ua] + c.t[a]) * g.spacing[a];
  }
  return c;
}

RC_GTEST_PROP(Trilinear, ReproducesLinearFieldValueAndGradient, ()) {
  const GridSpec g = gen_dyadic_grid(1);
  // Non-dyadic spacing on top, so the rounding path of a general grid is exercised too.
  GridSpec grid = g;
  for (int a = 0; a < 3; ++a) grid.spacing[a] *= *rc::gen::inRange(100, 1000) / 300.0;
  const double c0 = *rc::gen::inRange(-100000, 100001) / 100.0;
  const Vec3 b(*rc::gen::inRange(-10000, 10001) / 100.0, *rc::gen::inRange(-10000, 10001) / 100.0,
               *rc::gen::inRange(-10000, 10001) / 100.0);
  ScalarField f(grid);
  for (int k = 0; k < grid.nodes[2]; ++k)
    for (int j = 0; j < grid.nodes[1]; ++j)
      for (int i = 0; i < grid.nodes[0]; ++i) f.at(i, j, k) = c0 + b.dot(grid.position(i, j, k));

  Vec3 p;
  for (int a = 0; a < 3; ++a) {
    const int n = grid.nodes[static_cast<std::size_t>(a)];
    p[a] = grid.origin[a] + (n - 1) * grid.spacing[a] * (*rc::gen::inRange(0, 1001) / 1000.0);
    if (n == 1) p[a] = grid.origin[a];
  }
  const auto s = sample_trilinear(f, p);
  RC_ASSERT(s.has_value());

  // Tolerance: S bounds the magnitude of every term in f = c0 + b.x at any node or at p. Each
  // node value carries <= 4 roundings of size eps*S (3 products, 3 sums, position rounding), and
  // the nested lerps and t = (p - o)/h - i add a few more; 32 eps S covers this with margin
  // while a wrong weight would be off by O(|b| h), many orders of magnitude more.
  double S = std::abs(c0);
  for (int a = 0; a < 3; ++a) {
    S += std::abs(b[a]) * (std::abs(grid.origin[a]) + std::abs(grid.upper_corner()[a]) + std::abs(p[a]));
  }
  RC_ASSERT(std::abs(s->value - (c0 + b.dot(p))) <= 32 * kEps * S);
  for (int a = 0; a < 3; ++a) {
    // Along a single-node axis the field is constant by contract: derivative 0.
    const double expected = grid.nodes[static_cast<std::size_t>(a)] == 1 ? 0.0 : b[a];
    // Gradient = node differences / h: the node rounding eps*S is divided by h, hence S / h.
    RC_ASSERT(std::abs(s->gradient[a] - expected) <= 32 * kEps * S / grid.spacing[a]);
  }
}

RC_GTEST_PROP(Trilinear, StaysWithinTheCellCornerValues, ()) {
  const GridSpec g = gen_dyadic_grid(1);
  const ScalarField f = gen_field(g);
  const CellPoint c = gen_point_in_cell(g);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int dk = 0; dk < 2; ++dk)
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        const int i = std::min(c.cell[0] + di, g.nodes[0] - 1);
        const int j = std::min(c.cell[1] + dj, g.nodes[1] - 1);
        const int k = std::min(c.cell[2] + dk, g.nodes[2] - 1);
        lo = std::min(lo, f.at(i, j, k));
        hi = std::max(hi, f.at(i, j, k));
      }
  const auto s = sample_trilinear(f, c.p);
  RC_ASSERT(s.has_value());
  // Exact bound, no tolerance: std::lerp is bounded by its end points for t in [0,1].
  RC_ASSERT(s->value >= lo);
  RC_ASSERT(s->value <= hi);
}

RC_GTEST_PROP(Trilinear, EqualsNodeValuesAtNodes, ()) {
  const GridSpec g = gen_dyadic_grid(1);
  const ScalarField f = gen_field(g);
  const int i = *rc::gen::inRange(0, g.nodes[0]);
  const int j = *rc::gen::inRange(0, g.nodes[1]);
  const int k = *rc::gen::inRange(0, g.nodes[2]);
  const auto s = sample_trilinear(f, g.position(i, j, k));
  RC_ASSERT(s.has_value());
  // Exact: on a dyadic grid t is exactly 0 or 1 and std::lerp is exact there.
  RC_ASSERT(s->value == f.at(i, j, k));
}

TEST(Trilinear, EqualsNodeValuesAtNodesOfANonDyadicGrid) {
  // h = 0.1 and origin 0.3 are not binary fractions: t = (p - o)/h may land a few ulps off an
  // integer, so the sample may use the neighbouring cell with t ~ 1e-16; the error is then
  // t * |neighbour difference| <= ~1e-16 * 2 * 100, hence the 1e-12 tolerance.
  GridSpec g;
  g.origin = Vec3(0.3, -0.7, 1.1);
  g.spacing = Vec3(0.1, 0.3, 0.7);
  g.nodes = {7, 5, 4};
  ScalarField f(g);
  for (std::size_t n = 0; n < f.values.size(); ++n) f.values[n] = std::sin(3.0 * static_cast<double>(n)) * 100.0;
  for (int k = 0; k < g.nodes[2]; ++k)
    for (int j = 0; j < g.nodes[1]; ++j)
      for (int i = 0; i < g.nodes[0]; ++i) {
        const auto s = sample_trilinear(f, g.position(i, j, k));
        ASSERT_TRUE(s.has_value()) << i << " " << j << " " << k;
        EXPECT_NEAR(s->value, f.at(i, j, k), 1e-12) << i << " " << j << " " << k;
      }
}

RC_GTEST_PROP(Trilinear, IsContinuousAcrossCellFaces, ()) {
  const GridSpec g = gen_dyadic_grid(3);  // at least one interior face per axis
  const ScalarField f = gen_field(g);
  const int axis = *rc::gen::inRange(0, 3);
  const int face = *rc::gen::inRange(1, g.nodes[static_cast<std::size_t>(axis)] - 1);
  CellPoint c = gen_point_in_cell(g);
  c.p[axis] = g.origin[axis] + face * g.spacing[axis];

  // Independent oracle on the face: bilinear interpolation of its 4 nodes, written out.
  const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
  auto node = [&](int du, int dv) {
    Index3 idx;
    idx[static_cast<std::size_t>(axis)] = face;
    idx[static_cast<std::size_t>(u_axis)] = std::min(c.cell[static_cast<std::size_t>(u_axis)] + du, g.nodes[static_cast<std::size_t>(u_axis)] - 1);
    idx[static_cast<std::size_t>(v_axis)] = std::min(c.cell[static_cast<std::size_t>(v_axis)] + dv, g.nodes[static_cast<std::size_t>(v_axis)] - 1);
    return f.at(idx[0], idx[1], idx[2]);
  };
  const double u = c.t[u_axis], v = c.t[v_axis];
  const double face_value = (1 - u) * (1 - v) * node(0, 0) + u * (1 - v) * node(1, 0) +
                            (1 - u) * v * node(0, 1) + u * v * node(1, 1);
  const double fmax = 1000.0;  // |node values| <= 1000
  const auto on = sample_trilinear(f, c.p);
  RC_ASSERT(on.has_value());
  // Both formulas round ~6 times on values <= fmax.
  RC_ASSERT(std::abs(on->value - face_value) <= 16 * kEps * fmax);

  // Just below and just above the face (delta = h / 2^20) the value must agree with the face
  // value up to |grad| * delta <= (2 fmax / h_min) * 3 delta; a jump would be O(fmax).
  const double delta = std::ldexp(g.spacing[axis], -20);
  Vec3 below = c.p, above = c.p;
  below[axis] -= delta;
  above[axis] += delta;
  const auto sb = sample_trilinear(f, below);
  const auto sa = sample_trilinear(f, above);
  RC_ASSERT(sb.has_value() && sa.has_value());
  const double lipschitz = 3 * 2 * fmax / g.spacing[axis];
  RC_ASSERT(std::abs(sb->value - face_value) <= lipschitz * delta + 16 * kEps * fmax);
  RC_ASSERT(std::abs(sa->value - face_value) <= lipschitz * delta + 16 * kEps * fmax);
}

RC_GTEST_PROP(Trilinear, GradientMatchesCentralDifferenceInsideACell, ()) {
  const GridSpec g = gen_dyadic_grid(2);
  const ScalarField f = gen_field(g);
  CellPoint c = gen_point_in_cell(g);
  for (int a = 0; a < 3; ++a) {  // keep p and p +- 0.1 h in the same cell
    c.t[a] = 0.25 + 0.5 * c.t[a];
    c.p[a] = g.origin[a] + (c.cell[static_cast<std::size_t>(a)] + c.t[a]) * g.spacing[a];
  }
  const auto s = sample_trilinear(f, c.p);
  RC_ASSERT(s.has_value());
  for (int a = 0; a < 3; ++a) {
    // The interpolant is linear along each axis within a cell, so the central difference is
    // the exact derivative up to rounding: 2 values with error ~8 eps fmax over 2 delta.
    const double delta = 0.125 * g.spacing[a];
    Vec3 lo = c.p, hi = c.p;
    lo[a] -= delta;
    hi[a] += delta;
    const double fd = (sample_trilinear(f, hi)->value - sample_trilinear(f, lo)->value) / (2 * delta);
    RC_ASSERT(std::abs(s->gradient[a] - fd) <= 32 * kEps * 1000.0 / delta);
  }
}

TEST(Trilinear, ReturnsNulloptOutsideTheNodeBoxOrForNonFinitePoints) {
  GridSpec g;
  g.origin = Vec3(1, 2, 3);
  g.spacing = Vec3(0.5, 0.25, 2.0);
  g.nodes = {3, 5, 2};
  const ScalarField f(g, 7.0);
  const Vec3 lo = g.origin, hi = g.upper_corner();
  EXPECT_TRUE(sample_trilinear(f, lo).has_value());
  EXPECT_TRUE(sample_trilinear(f, hi).has_value());  // upper faces are inside
  const double inf = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    Vec3 below = lo, above = hi;
    below[a] = std::nextafter(lo[a], -inf);
    above[a] = std::nextafter(hi[a], inf);
    EXPECT_FALSE(sample_trilinear(f, below).has_value()) << "axis " << a;
    EXPECT_FALSE(sample_trilinear(f, above).has_value()) << "axis " << a;
    Vec3 nan_point = 0.5 * (lo + hi);
    nan_point[a] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(sample_trilinear(f, nan_point).has_value()) << "axis " << a;
    nan_point[a] = inf;
    EXPECT_FALSE(sample_trilinear(f, nan_point).has_value()) << "axis " << a;
  }
}

TEST(Trilinear, AnisotropicSpacingScalesGradientPerAxis) {
  // f = 2x + 3y - 5z on h = (0.5, 0.125, 4): hand values at p = (1.3, 0.41, 9).
  GridSpec g;
  g.spacing = Vec3(0.5, 0.125, 4.0);
  g.nodes = {5, 9, 4};
  ScalarField f(g);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 5; ++i) {
        const Vec3 x = g.position(i, j, k);
        f.at(i, j, k) = 2 * x.x() + 3 * x.y() - 5 * x.z();
      }
  const auto s = sample_trilinear(f, Vec3(1.3, 0.41, 9.0));
  ASSERT_TRUE(s.has_value());
  // Tolerance: values ~50, a few roundings: 1e-13.
  EXPECT_NEAR(s->value, 2 * 1.3 + 3 * 0.41 - 45.0, 1e-13);
  EXPECT_NEAR(s->gradient.x(), 2.0, 1e-13);
  EXPECT_NEAR(s->gradient.y(), 3.0, 1e-13);
  EXPECT_NEAR(s->gradient.z(), -5.0, 1e-13);
}

TEST(Trilinear, SingleNodeAxisIsConstantWithZeroDerivative) {
  GridSpec g;
  g.origin = Vec3(0, 4, 0);
  g.nodes = {2, 1, 2};
  ScalarField f(g);
  // f(i, k) = 1 + 2i + 4k (hand-chosen), a single y plane at y = 4.
  f.at(0, 0, 0) = 1;
  f.at(1, 0, 0) = 3;
  f.at(0, 0, 1) = 5;
  f.at(1, 0, 1) = 7;
  const auto s = sample_trilinear(f, Vec3(0.5, 4.0, 0.25));
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->value, 1 + 2 * 0.5 + 4 * 0.25);  // exact: dyadic weights
  EXPECT_EQ(s->gradient, Vec3(2, 0, 4));
  // The node box along y is the single coordinate y = 4.
  EXPECT_FALSE(sample_trilinear(f, Vec3(0.5, 4.5, 0.25)).has_value());
}

}  // namespace
}  // namespace ppohdem

// Shape functions: partition of unity, zero gradient sum, linear completeness (sum N x_i = x,
// sum x_i (x) grad N_i = I) and derivatives consistent with the weights, for the trilinear
// and the quadratic B-spline stencils at random points.
#include <gtest/gtest.h>

#include <random>

#include "shape_functions.hpp"

using namespace mpmdem::mpm;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

namespace {

template <class Shape>
void check_stencil_identities() {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 origin(-0.3, 1.2, 0.05);
  const double h = 0.07;
  for (int trial = 0; trial < 1000; ++trial) {
    const Vec3 x = origin + h * Vec3(10 * u(rng), 10 * u(rng), 10 * u(rng));
    const auto s = make_stencil<Shape>(x, origin, 1.0 / h);
    double sum_N = 0.0;
    Vec3 sum_grad = Vec3::Zero(), sum_Nx = Vec3::Zero();
    Mat3 sum_x_grad = Mat3::Zero();
    for_each_node(s, [&](int a, int b, int c, double N, const Vec3& gradN) {
      EXPECT_GE(N, 0.0);
      const Vec3 x_i = origin + h * Vec3(s.base[0] + a, s.base[1] + b, s.base[2] + c);
      sum_N += N;
      sum_grad += gradN;
      sum_Nx += N * x_i;
      sum_x_grad += x_i * gradN.transpose();
    });
    ASSERT_NEAR(sum_N, 1.0, 1e-14);
    ASSERT_LT(sum_grad.norm() * h, 1e-13);
    ASSERT_LT((sum_Nx - x).norm(), 1e-13);
    ASSERT_LT((sum_x_grad - Mat3::Identity()).norm(), 1e-12);
  }
}

// dw/dxi against a central difference of w, away from the knots where w is not smooth.
template <class Shape>
void check_derivatives() {
  for (double xi = 0.013; xi < 5.0; xi += 0.0917) {
    int base = 0, base_p = 0, base_m = 0;
    double w[3], dw[3], wp[3], wm[3], d[3];
    const double e = 1e-6;
    Shape::weights(xi, base, w, dw);
    Shape::weights(xi + e, base_p, wp, d);
    Shape::weights(xi - e, base_m, wm, d);
    if (base_p != base || base_m != base) continue;
    for (int a = 0; a < Shape::kWidth; ++a) {
      EXPECT_NEAR(dw[a], (wp[a] - wm[a]) / (2 * e), 1e-7) << "xi " << xi << " node " << a;
    }
  }
}

}  // namespace

TEST(ShapeFunctions, LinearPartitionOfUnityAndCompleteness) {
  check_stencil_identities<LinearShape>();
}

TEST(ShapeFunctions, QuadraticBSplinePartitionOfUnityAndCompleteness) {
  check_stencil_identities<QuadraticBSplineShape>();
}

TEST(ShapeFunctions, DerivativesMatchTheWeights) {
  check_derivatives<LinearShape>();
  check_derivatives<QuadraticBSplineShape>();
}

TEST(ShapeFunctions, InterpolatingAtNodesAndBSplineValues) {
  // Linear: at a node the weight is 1 on that node.
  int base = 0;
  double w[3], dw[3];
  LinearShape::weights(3.0, base, w, dw);
  EXPECT_EQ(base, 3);
  EXPECT_DOUBLE_EQ(w[0], 1.0);
  EXPECT_DOUBLE_EQ(w[1], 0.0);
  // Quadratic B-spline at a node: 1/8, 3/4, 1/8 around it.
  QuadraticBSplineShape::weights(3.0, base, w, dw);
  EXPECT_EQ(base, 2);
  EXPECT_DOUBLE_EQ(w[0], 0.125);
  EXPECT_DOUBLE_EQ(w[1], 0.75);
  EXPECT_DOUBLE_EQ(w[2], 0.125);
  EXPECT_DOUBLE_EQ(dw[1], 0.0);
  // At a cell centre: 1/2, 1/2 on the cell's two nodes, zero on the third.
  QuadraticBSplineShape::weights(3.5, base, w, dw);
  EXPECT_EQ(base, 3);
  EXPECT_DOUBLE_EQ(w[0], 0.5);
  EXPECT_DOUBLE_EQ(w[1], 0.5);
  EXPECT_DOUBLE_EQ(w[2], 0.0);
}

// Quadratic B-splines clamped at walls (boundary-modified): on an axis of n cells with walls at
// both ends they sum to 1, reproduce linear fields with the Greville abscissae, have
// derivatives consistent with the weights, and only the ghost slot's function is non-zero on a
// wall.
TEST(ShapeFunctions, ClampedQuadraticBSplinesAtWalls) {
  for (int n : {1, 2, 3, 6}) {
    ShapeAxis ax;
    ax.cells = n;
    ax.clamp_lo = ax.clamp_hi = true;
    for (double xi = 0.0; xi <= n; xi += 0.01 * n) {
      int base = 0;
      double w[3], dw[3], xn[3];
      QuadraticBSplineShape::weights(xi, ax, base, w, dw, xn);
      double sum = 0.0, sum_x = 0.0, sum_d = 0.0, sum_dx = 0.0;
      for (int a = 0; a < 3; ++a) {
        EXPECT_GE(w[a], 0.0);
        EXPECT_GE(base + a, -1);
        EXPECT_LE(base + a, n + 1);
        sum += w[a];
        sum_x += w[a] * xn[a];
        sum_d += dw[a];
        sum_dx += dw[a] * xn[a];
      }
      ASSERT_NEAR(sum, 1.0, 1e-13) << "n " << n << " xi " << xi;
      ASSERT_NEAR(sum_x, xi, 1e-12) << "n " << n << " xi " << xi;
      ASSERT_NEAR(sum_d, 0.0, 1e-12) << "n " << n << " xi " << xi;
      ASSERT_NEAR(sum_dx, 1.0, 1e-12) << "n " << n << " xi " << xi;
      // Derivative against a central difference (inside a span).
      const double e = 1e-7;
      if (xi > e && xi < n - e) {
        int bp = 0, bm = 0;
        double wp[3], wm[3], d[3], x2[3];
        QuadraticBSplineShape::weights(xi + e, ax, bp, wp, d, x2);
        QuadraticBSplineShape::weights(xi - e, ax, bm, wm, d, x2);
        if (bp == base && bm == base) {
          for (int a = 0; a < 3; ++a) EXPECT_NEAR(dw[a], (wp[a] - wm[a]) / (2 * e), 1e-5);
        }
      }
    }
    // On a wall only the ghost slot carries weight.
    int base = 0;
    double w[3], dw[3], xn[3];
    QuadraticBSplineShape::weights(0.0, ax, base, w, dw, xn);
    EXPECT_EQ(base, -1);
    EXPECT_DOUBLE_EQ(w[0], 1.0);
    EXPECT_DOUBLE_EQ(xn[0], 0.0);
    QuadraticBSplineShape::weights(n, ax, base, w, dw, xn);
    EXPECT_EQ(base + 2, n + 1);
    EXPECT_NEAR(w[2], 1.0, 1e-12);
    EXPECT_DOUBLE_EQ(xn[2], n);
  }
}

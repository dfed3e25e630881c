// Grid shape functions as tensor products of 1D weights, evaluated once per point per step
// into a fixed-size Stencil on the stack (no heap allocation).
//   N_ip(x_p) = w_x[a] w_y[b] w_z[c],  grad N_ip = (w'_x w_y w_z, w_x w'_y w_z, w_x w_y w'_z)
// for the node base + (a, b, c). Coordinates are in cell units xi = (x - origin) / h, so node
// lattice index k sits at xi = k.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>

namespace mpmdem::mpm {

// One grid axis as the shape functions see it: its cell count and whether its ends are walls.
// At a wall the quadratic B-splines are clamped (boundary-modified); the trilinear ones need
// nothing.
struct ShapeAxis {
  int cells = 1 << 30;
  bool clamp_lo = false;  // wall at xi = 0
  bool clamp_hi = false;  // wall at xi = cells
};

// Trilinear (tent) functions: 2 nodes per direction, 8 in all.
struct LinearShape {
  static constexpr int kWidth = 2;
  // base = floor(xi); w[a], dw[a] (d/dxi) and the node position xn[a] (cell units) for nodes
  // base + a.
  static void weights(double xi, const ShapeAxis&, int& base, double* w, double* dw, double* xn) {
    const double b = std::floor(xi);
    const double f = xi - b;  // in [0, 1)
    base = static_cast<int>(b);
    w[0] = 1.0 - f;
    w[1] = f;
    dw[0] = -1.0;
    dw[1] = 1.0;
    xn[0] = b;
    xn[1] = b + 1.0;
  }
  static void weights(double xi, int& base, double* w, double* dw) {
    double xn[kWidth];
    weights(xi, ShapeAxis{}, base, w, dw, xn);
  }
};

// Quadratic B-spline: 3 nodes per direction, 27 in all (C1, no cell-crossing noise).
// Away from walls: the uniform B-spline centred on each node (knots at the cell centres).
// Next to a wall (ShapeAxis::clamp_*): the B-splines of the knot vector clamped at the wall
// (knots 0, 0, 0, 1/2, 3/2, ... in cell units; Steffen et al. 2008, open knot vector), so only
// the function of the ghost slot is non-zero on the wall (it carries the wall's velocity), the
// slot of the boundary node holds the function centred at h/4 (its Greville abscissa) and the
// next one the function centred at node 1; from node 2 on they are the uniform ones. They
// still sum to 1 and reproduce linear fields, sum_a w_a xn_a = xi with xn the Greville
// abscissae, which APIC needs (its D_p stays diagonal).
struct QuadraticBSplineShape {
  static constexpr int kWidth = 3;
  // base = floor(xi - 1/2): the nodes base, base + 1, base + 2.
  static void weights(double xi, const ShapeAxis& ax, int& base, double* w, double* dw,
                      double* xn) {
    const double b = std::floor(xi - 0.5);
    base = static_cast<int>(b);
    const bool near_lo = ax.clamp_lo && xi < 1.5;
    const bool near_hi = ax.clamp_hi && xi > ax.cells - 1.5;
    if (!near_lo && !near_hi) {
      const double f = xi - b;  // in [1/2, 3/2): the distance to node base
      const double d0 = 1.5 - f, d1 = f - 1.0, d2 = f - 0.5;
      w[0] = 0.5 * d0 * d0;
      w[1] = 0.75 - d1 * d1;
      w[2] = 0.5 * d2 * d2;
      dw[0] = -d0;
      dw[1] = -2.0 * d1;
      dw[2] = d2;
      xn[0] = b;
      xn[1] = b + 1.0;
      xn[2] = b + 2.0;
      return;
    }
    const double n = ax.cells;
    // On the upper wall itself, evaluate just inside (the spans are half-open).
    const double x = near_hi ? std::min(xi, n * (1.0 - 1e-15)) : xi;
    for (int a = 0; a < kWidth; ++a) {
      double t[4];
      for (int j = 0; j < 4; ++j) {
        t[j] = b + a - 1.5 + j;  // the uniform knots of node base + a
        if (ax.clamp_lo) t[j] = std::max(t[j], 0.0);
        if (ax.clamp_hi) t[j] = std::min(t[j], n);
      }
      bspline2(t, x, w[a], dw[a]);
      xn[a] = 0.5 * (t[1] + t[2]);
    }
  }
  static void weights(double xi, int& base, double* w, double* dw) {
    double xn[kWidth];
    weights(xi, ShapeAxis{}, base, w, dw, xn);
  }

  // The quadratic B-spline on knots t[0] <= ... <= t[3] and its derivative at x.
  static void bspline2(const double* t, double x, double& w, double& dw) {
    w = 0.0;
    dw = 0.0;
    if (t[0] <= x && x < t[1]) {
      const double den = (t[2] - t[0]) * (t[1] - t[0]);
      w = (x - t[0]) * (x - t[0]) / den;
      dw = 2.0 * (x - t[0]) / den;
    } else if (t[1] <= x && x < t[2]) {
      const double A = (t[2] - t[0]) * (t[2] - t[1]), B = (t[3] - t[1]) * (t[2] - t[1]);
      w = (x - t[0]) * (t[2] - x) / A + (t[3] - x) * (x - t[1]) / B;
      dw = (t[2] + t[0] - 2.0 * x) / A + (t[3] + t[1] - 2.0 * x) / B;
    } else if (t[2] <= x && x < t[3]) {
      const double den = (t[3] - t[1]) * (t[3] - t[2]);
      w = (t[3] - x) * (t[3] - x) / den;
      dw = -2.0 * (t[3] - x) / den;
    }
  }
};

// 1D weights of one point in the three directions; gradients already in 1/m.
template <int W>
struct Stencil {
  int base[3];      // lattice index of the first node per direction
  double w[3][W];   // w[d][a]: weight of node base[d] + a along direction d
  double dw[3][W];  // d w[d][a] / d x_d  [1/m]
  double dx[3][W];  // x_i - x_p along d [m] (x_i: the node's Greville abscissa, see above)
  // APIC: D_d^-1 w[d][a] dx[d][a] with D_d = sum_a w[d][a] dx[d][a]^2 (D_p is diagonal since
  // the shapes reproduce linear fields). Trilinear: equal to dw (exactly, also where D_d = 0).
  double ga[3][W];  // [1/m]
};

template <class Shape>
inline Stencil<Shape::kWidth> make_stencil(const Eigen::Vector3d& x, const Eigen::Vector3d& origin,
                                           double inv_h,
                                           const std::array<ShapeAxis, 3>& axes = {}) {
  constexpr int W = Shape::kWidth;
  Stencil<W> s;
  const double h = 1.0 / inv_h;
  for (int d = 0; d < 3; ++d) {
    const double xi = (x[d] - origin[d]) * inv_h;
    double xn[W];
    Shape::weights(xi, axes[static_cast<std::size_t>(d)], s.base[d], s.w[d], s.dw[d], xn);
    double D = 0.0;
    for (int a = 0; a < W; ++a) {
      s.dw[d][a] *= inv_h;
      s.dx[d][a] = (xn[a] - xi) * h;
      D += s.w[d][a] * s.dx[d][a] * s.dx[d][a];
    }
    for (int a = 0; a < W; ++a) {
      // (On a wall itself a clamped spline interpolates and D_d = 0: the trilinear limit.)
      s.ga[d][a] = W == 2 || !(D > 1e-14 * h * h) ? s.dw[d][a] : s.w[d][a] * s.dx[d][a] / D;
    }
  }
  return s;
}

// Calls fn(a, b, c, N, gradN) for the W^3 nodes of a stencil (a fastest).
template <int W, class Fn>
inline void for_each_node(const Stencil<W>& s, Fn&& fn) {
  for (int c = 0; c < W; ++c) {
    for (int b = 0; b < W; ++b) {
      const double wyz = s.w[1][b] * s.w[2][c];
      const double dyz = s.dw[1][b] * s.w[2][c];
      const double ydz = s.w[1][b] * s.dw[2][c];
      for (int a = 0; a < W; ++a) {
        const Eigen::Vector3d grad(s.dw[0][a] * wyz, s.w[0][a] * dyz, s.w[0][a] * ydz);
        fn(a, b, c, s.w[0][a] * wyz, grad);
      }
    }
  }
}

}  // namespace mpmdem::mpm

// Grid shape functions as tensor products of 1D weights, evaluated once per point per step
// into a fixed-size Stencil on the stack (no heap allocation).
//   N_ip(x_p) = w_x[a] w_y[b] w_z[c],  grad N_ip = (w'_x w_y w_z, w_x w'_y w_z, w_x w_y w'_z)
// for the node base + (a, b, c). Coordinates are in cell units xi = (x - origin) / h, so node
// lattice index k sits at xi = k.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace mpmdem::mpm {

// Trilinear (tent) functions: 2 nodes per direction, 8 in all.
struct LinearShape {
  static constexpr int kWidth = 2;
  // base = floor(xi); w[a], dw[a] (d/dxi) for nodes base + a.
  static void weights(double xi, int& base, double* w, double* dw) {
    const double b = std::floor(xi);
    const double f = xi - b;  // in [0, 1)
    base = static_cast<int>(b);
    w[0] = 1.0 - f;
    w[1] = f;
    dw[0] = -1.0;
    dw[1] = 1.0;
  }
};

// Quadratic B-spline: 3 nodes per direction, 27 in all (C1, no cell-crossing noise).
struct QuadraticBSplineShape {
  static constexpr int kWidth = 3;
  // base = floor(xi - 1/2); f = xi - base in [1/2, 3/2) is the distance to node base.
  static void weights(double xi, int& base, double* w, double* dw) {
    const double b = std::floor(xi - 0.5);
    const double f = xi - b;
    base = static_cast<int>(b);
    const double d0 = 1.5 - f, d1 = f - 1.0, d2 = f - 0.5;
    w[0] = 0.5 * d0 * d0;
    w[1] = 0.75 - d1 * d1;
    w[2] = 0.5 * d2 * d2;
    dw[0] = -d0;
    dw[1] = -2.0 * d1;
    dw[2] = d2;
  }
};

// 1D weights of one point in the three directions; gradients already in 1/m.
template <int W>
struct Stencil {
  int base[3];      // lattice index of the first node per direction
  double w[3][W];   // w[d][a]: weight of node base[d] + a along direction d
  double dw[3][W];  // d w[d][a] / d x_d  [1/m]
};

template <class Shape>
inline Stencil<Shape::kWidth> make_stencil(const Eigen::Vector3d& x, const Eigen::Vector3d& origin,
                                           double inv_h) {
  Stencil<Shape::kWidth> s;
  for (int d = 0; d < 3; ++d) {
    Shape::weights((x[d] - origin[d]) * inv_h, s.base[d], s.w[d], s.dw[d]);
    for (int a = 0; a < Shape::kWidth; ++a) s.dw[d][a] *= inv_h;
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

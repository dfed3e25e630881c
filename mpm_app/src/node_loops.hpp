// Loops over the nodes of a point's stencil and the per-thread reduction of scattered node
// fields, shared by the transfers (transfers.cpp) and the XPIC filter (xpic.cpp).
#pragma once

#include <cstddef>
#include <vector>

#include "grid.hpp"
#include "shape_functions.hpp"

namespace mpmdem::mpm::detail {

// Calls fn(node, N_ip, grad N_ip, x_i - x_p, D_p^-1 N_ip (x_i - x_p)) for the W^3 nodes of a
// stencil (the last two for APIC).
template <int W, class Fn>
inline void for_each_node_affine(const Grid& g, const Stencil<W>& s, Fn&& fn) {
  const std::size_t sy = static_cast<std::size_t>(g.nodes[0]);
  const std::size_t sz = sy * static_cast<std::size_t>(g.nodes[1]);
  const std::size_t first = g.index(s.base[0], s.base[1], s.base[2]);
  for (int c = 0; c < W; ++c) {
    for (int b = 0; b < W; ++b) {
      const std::size_t row =
          first + static_cast<std::size_t>(b) * sy + static_cast<std::size_t>(c) * sz;
      const double wyz = s.w[1][b] * s.w[2][c];
      const double dyz = s.dw[1][b] * s.w[2][c];
      const double ydz = s.w[1][b] * s.dw[2][c];
      const double gyz = s.ga[1][b] * s.w[2][c];
      const double ygz = s.w[1][b] * s.ga[2][c];
      for (int a = 0; a < W; ++a) {
        const Vec3 grad(s.dw[0][a] * wyz, s.w[0][a] * dyz, s.w[0][a] * ydz);
        const Vec3 dx(s.dx[0][a], s.dx[1][b], s.dx[2][c]);
        const Vec3 g_aff(s.ga[0][a] * wyz, s.w[0][a] * gyz, s.w[0][a] * ygz);
        fn(row + static_cast<std::size_t>(a), s.w[0][a] * wyz, grad, dx, g_aff);
      }
    }
  }
}

// Calls fn(node, N_ip, grad N_ip) for the W^3 nodes of a stencil (the affine terms above are
// dead code once inlined).
template <int W, class Fn>
inline void for_each_node(const Grid& g, const Stencil<W>& s, Fn&& fn) {
  for_each_node_affine(
      g, s,
      [&](std::size_t i, double N, const Vec3& grad, const Vec3&, const Vec3&) { fn(i, N, grad); });
}

// Sum the per-thread copies of threads 1..used-1 into the grid field (inside a parallel region).
template <class T>
inline void reduce_into(std::vector<T>& field, std::vector<std::vector<T>>& copies, int used) {
  const auto n = static_cast<std::ptrdiff_t>(field.size());
#pragma omp for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    for (int t = 1; t < used; ++t) field[i] += copies[t - 1][i];
  }
}

}  // namespace mpmdem::mpm::detail

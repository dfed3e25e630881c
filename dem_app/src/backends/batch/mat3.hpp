// 3x3 matrices of the batch backend (row-major, 9 doubles) with the host and device code
// evaluating every expression in the order Eigen 3.4 evaluates the native backend's Eigen
// expressions on the host build (so the batch path gives the native backend's bits):
//  * the product of two 3x3 matrices and of a matrix and a vector: rows 0 and 1 sum their
//    three products left to right (Eigen computes them as one SSE2 packet), row 2 as
//    p0 + (p1 + p2) (its scalar reduction); with a row-major left factor every row left to
//    right;
//  * the determinant: Eigen's bruteforce_det3_helper; the inverse: compute_inverse (size 3),
//    its determinant from the cofactors of column 0 left to right.
// test_batch_mat3 checks every function against Eigen bit for bit on random matrices: a
// change of Eigen or of the build's vector flags shows there first.
#pragma once

#include "backends/batch/hd.hpp"

namespace mpmdem::dem::batch {

struct M3 {
  double a[9];
  MPMDEM_HD_INLINE double operator()(int i, int j) const { return a[3 * i + j]; }
  MPMDEM_HD_INLINE double& operator()(int i, int j) { return a[3 * i + j]; }
};

MPMDEM_HD_INLINE M3 m3_zero() {
  M3 m;
  for (double& x : m.a) x = 0;
  return m;
}
MPMDEM_HD_INLINE M3 m3_identity() {
  M3 m = m3_zero();
  m.a[0] = m.a[4] = m.a[8] = 1;
  return m;
}
MPMDEM_HD_INLINE M3 m3_load(const double* p) {
  M3 m;
  for (int k = 0; k < 9; ++k) m.a[k] = p[k];
  return m;
}
MPMDEM_HD_INLINE void m3_store(const M3& m, double* p) {
  for (int k = 0; k < 9; ++k) p[k] = m.a[k];
}
// Eigen's three-term sum of row `row` of a product (see above).
MPMDEM_HD_INLINE double sum3(int row, double p0, double p1, double p2) {
  return row < 2 ? (p0 + p1) + p2 : p0 + (p1 + p2);
}
MPMDEM_HD_INLINE M3 mul(const M3& x, const M3& y) {
  M3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r(i, j) = sum3(i, x(i, 0) * y(0, j), x(i, 1) * y(1, j), x(i, 2) * y(2, j));
  return r;
}
// The product with a row-major left factor (the native backend's Map<RowMajor3>(dF) * trsf):
// Eigen sums every row left to right.
MPMDEM_HD_INLINE M3 mul_row_major_lhs(const M3& x, const M3& y) {
  M3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r(i, j) = (x(i, 0) * y(0, j) + x(i, 1) * y(1, j)) + x(i, 2) * y(2, j);
  return r;
}
// x v (v: 3 doubles), into out.
MPMDEM_HD_INLINE void mul_vec(const M3& x, const double* v, double* out) {
  for (int i = 0; i < 3; ++i) out[i] = sum3(i, x(i, 0) * v[0], x(i, 1) * v[1], x(i, 2) * v[2]);
}
MPMDEM_HD_INLINE M3 add(const M3& x, const M3& y) {
  M3 r;
  for (int k = 0; k < 9; ++k) r.a[k] = x.a[k] + y.a[k];
  return r;
}
MPMDEM_HD_INLINE M3 sub(const M3& x, const M3& y) {
  M3 r;
  for (int k = 0; k < 9; ++k) r.a[k] = x.a[k] - y.a[k];
  return r;
}
MPMDEM_HD_INLINE M3 scale(double s, const M3& x) {  // s * x (Eigen: each s * x_k)
  M3 r;
  for (int k = 0; k < 9; ++k) r.a[k] = s * x.a[k];
  return r;
}
MPMDEM_HD_INLINE M3 scale_r(const M3& x, double s) {  // x * s
  M3 r;
  for (int k = 0; k < 9; ++k) r.a[k] = x.a[k] * s;
  return r;
}
MPMDEM_HD_INLINE M3 divide(const M3& x, double s) {  // x / s (each x_k / s)
  M3 r;
  for (int k = 0; k < 9; ++k) r.a[k] = x.a[k] / s;
  return r;
}
MPMDEM_HD_INLINE M3 transpose(const M3& x) {
  M3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = x(j, i);
  return r;
}
MPMDEM_HD_INLINE bool is_zero(const M3& x) {  // x == Zero() (-0.0 counts as zero, as in Eigen)
  for (double v : x.a)
    if (!(v == 0.0)) return false;
  return true;
}
MPMDEM_HD_INLINE bool equal(const M3& x, const M3& y) {
  for (int k = 0; k < 9; ++k)
    if (!(x.a[k] == y.a[k])) return false;
  return true;
}
MPMDEM_HD_INLINE double det(const M3& m) {
  const auto h = [&](int a, int b, int c) {
    return m(0, a) * (m(1, b) * m(2, c) - m(1, c) * m(2, b));
  };
  return h(0, 1, 2) - h(1, 0, 2) + h(2, 0, 1);
}
MPMDEM_HD_INLINE double cofactor(const M3& m, int i, int j) {
  const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
  return m(i1, j1) * m(i2, j2) - m(i1, j2) * m(i2, j1);
}
MPMDEM_HD_INLINE M3 inverse(const M3& m) {
  const double c0 = cofactor(m, 0, 0), c1 = cofactor(m, 1, 0), c2 = cofactor(m, 2, 0);
  const double d = (c0 * m(0, 0) + c1 * m(1, 0)) + c2 * m(2, 0);
  const double inv = 1.0 / d;
  M3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = cofactor(m, j, i) * inv;
  r(0, 0) = c0 * inv, r(0, 1) = c1 * inv, r(0, 2) = c2 * inv;
  return r;
}
// Dot product and squared norm of 3-vectors as Eigen's dot / squaredNorm: left to right.
MPMDEM_HD_INLINE double dot3(const double* x, const double* y) {
  return (x[0] * y[0] + x[1] * y[1]) + x[2] * y[2];
}

}  // namespace mpmdem::dem::batch

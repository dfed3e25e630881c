// The periodic cell of a batch RVE, for host and device (MPMDEM_HD): native::PeriodicCell's
// velGrad sequence (set -> next, activated by Newton: the one-step lag), integrateAndUpdate,
// the burst's velGrad rule of NativeBackend::burst (exact dF despite the lag) and
// PeriodicCell::flip, on the RVE's cell block (batch_layout.hpp's CellSlot), in Eigen's
// order (mat3.hpp).
#pragma once

#include <cmath>

#include "backends/batch/batch_layout.hpp"
#include "backends/batch/mat3.hpp"

namespace mpmdem::dem::batch {

MPMDEM_HD_INLINE M3 cell_get(const double* cb, int slot) {
  return m3_load(cb + slot);
}
MPMDEM_HD_INLINE void cell_set(double* cb, int slot, const M3& m) {
  m3_store(m, cb + slot);
}

MPMDEM_HD_INLINE void set_vel_grad(double* cb, std::int32_t* fl, const M3& l) {
  cell_set(cb, kNextVelGrad, l);
  fl[kVelGradChanged] = 1;
}
MPMDEM_HD_INLINE M3 pending_vel_grad(const double* cb, const std::int32_t* fl) {
  return cell_get(cb, fl[kVelGradChanged] ? kNextVelGrad : kVelGrad);
}
// Cell::integrateAndUpdate.
MPMDEM_HD_INLINE void integrate_and_update(double* cb, double dt) {
  const M3 l = cell_get(cb, kVelGrad);
  const M3 inc = scale(dt, l);
  const M3 h = cell_get(cb, kHsize);
  const M3 trsf = cell_get(cb, kTrsf);
  cell_set(cb, kTrsf, add(trsf, mul(inc, trsf)));
  cell_set(cb, kLh, mul(l, h));
  cell_set(cb, kHsize, add(h, mul(inc, h)));
}
// The head of NewtonIntegrator::action.
MPMDEM_HD_INLINE void activate_next(double* cb, std::int32_t* fl) {
  const M3 next = cell_get(cb, kNextVelGrad);
  if (fl[kVelGradChanged] || !is_zero(next)) {
    cell_set(cb, kVelGrad, next);
    fl[kVelGradChanged] = 0;
    cell_set(cb, kNextVelGrad, m3_zero());
  }
}
// Before substep j (1-based) of a burst of ns applying dF (row-major) from trsf_start:
// NativeBackend::burst's gradient for the substeps after j.
MPMDEM_HD_INLINE void burst_vel_grad(double* cb, std::int32_t* fl, const M3& target,
                                     const double* dF, int j, int ns, double dt) {
  const int remaining = ns - j;
  const M3 id = m3_identity();
  if (j == 1 || remaining == 1) {
    const M3 l = pending_vel_grad(cb, fl);
    const M3 after = mul(add(id, scale_r(l, dt)), cell_get(cb, kTrsf));
    set_vel_grad(cb, fl, divide(sub(mul(target, inverse(after)), id), remaining * dt));
  }
  if (remaining == 0) set_vel_grad(cb, fl, divide(sub(m3_load(dF), id), ns * dt));
}

// Cross product of columns of h (Eigen's cross: the same three expressions).
MPMDEM_HD_INLINE void col_cross(const M3& h, int a, int b, double* out) {
  out[0] = h(1, a) * h(2, b) - h(2, a) * h(1, b);
  out[1] = h(2, a) * h(0, b) - h(0, a) * h(2, b);
  out[2] = h(0, a) * h(1, b) - h(1, a) * h(0, b);
}

// PeriodicCell::flip on the cell block: returns whether the lattice changed, and the integer
// matrix M (row-major) with hsize_new = hsize_old M.
MPMDEM_HD_INLINE bool flip(double* cb, int* m_out) {
  M3 h = cell_get(cb, kHsize);
  int total[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    M3 base = h;
    double cr[3];
    col_cross(h, j, k, cr);
    for (int r = 0; r < 3; ++r) base(r, i) = cr[r];
    const M3 bi = inverse(base);
    const double col[3] = {h(0, i), h(1, i), h(2, i)};
    double coord[3];
    mul_vec(bi, col, coord);
    int step[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    step[3 * j + i] = -static_cast<int>(floor(coord[j] + 0.5));
    step[3 * k + i] = -static_cast<int>(floor(coord[k] + 0.5));
    M3 sd;
    for (int q = 0; q < 9; ++q) sd.a[q] = static_cast<double>(step[q]);
    h = add(h, mul(h, sd));
    int nt[9];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        int s = 0;
        for (int q = 0; q < 3; ++q) s += total[3 * r + q] * step[3 * q + c];
        nt[3 * r + c] = total[3 * r + c] + s;
      }
    for (int q = 0; q < 9; ++q) total[q] = nt[q];
  }
  bool changed = false;
  for (int q = 0; q < 9; ++q) changed = changed || total[q] != (q % 4 == 0 ? 1 : 0);
  if (changed) cell_set(cb, kHsize, h);
  for (int q = 0; q < 9; ++q) m_out[q] = total[q];
  return changed;
}

// The heights of the cell (volume over the area of the opposite face), PeriodicCell::heights.
MPMDEM_HD_INLINE void heights(const M3& h, double* out) {
  const double vol = fabs(det(h));
  for (int i = 0; i < 3; ++i) {
    double cr[3];
    col_cross(h, (i + 1) % 3, (i + 2) % 3, cr);
    out[i] = vol / sqrt((cr[0] * cr[0] + cr[1] * cr[1]) + cr[2] * cr[2]);
  }
}

}  // namespace mpmdem::dem::batch

// The per-sphere physics of the batch backend, for host and device (MPMDEM_HD): one sphere's
// NewtonIntegrator step (Cundall's non-viscous damping on the fluctuating velocity,
// homoDeform = 2, leapfrogTranslate, leapfrogSphericalRotate) and the quaternion operations
// of the measures, expression for expression those of native/newton.cpp and
// native/measures.cpp (Eigen's SSE2 quaternion product and normalisation written out).
#pragma once

#include <cmath>

#include "backends/batch/batch_layout.hpp"
#include "backends/batch/hd.hpp"
#include "backends/batch/mat3.hpp"

namespace mpmdem::dem::batch {

// What every sphere of an RVE's Newton step shares (native newton's StepConstants).
struct NewtonConstants {
  double dt, half_dt, quarter_dt2, damping;
  M3 prev;          // prevVelGrad
  M3 dvg;           // velGrad - prevVelGrad
  bool dvg_step;    // dvg != 0
  double dspin[3];  // spin of dvg
};

constexpr double kSeriesLimit = 1e-6;  // h^2 (native newton.cpp)

// Quaternions as 4 doubles x y z w (Eigen's storage).
// Eigen's SSE2 quat_product (Geometry_SIMD.h), its additions in its order.
MPMDEM_HD_INLINE void quat_mul(const double* a, const double* b, double* r) {
  const double ax = a[0], ay = a[1], az = a[2], aw = a[3];
  const double bx = b[0], by = b[1], bz = b[2], bw = b[3];
  r[0] = (aw * bx + ay * bz) - (az * by - ax * bw);
  r[1] = (aw * by + ay * bw) + (az * bx - ax * bz);
  r[2] = (aw * bz - ay * bx) + (az * bw + ax * by);
  r[3] = (aw * bw - ay * by) - (az * bz + ax * bx);
}
// Eigen's normalized(): coefficients over the norm, the squares summed in SSE2 pairs.
MPMDEM_HD_INLINE void quat_normalise(double* q) {
  const double n = sqrt((q[0] * q[0] + q[2] * q[2]) + (q[1] * q[1] + q[3] * q[3]));
  for (int k = 0; k < 4; ++k) q[k] = q[k] / n;
}

MPMDEM_HD_INLINE double damp(double damping, double half_dt, double vel, double accel) {
  const double x = accel * (vel + half_dt * accel);
  const double sign = (x > 0 ? 1.0 : 0.0) - (x < 0 ? 1.0 : 0.0);
  return accel * (1 - damping * sign);
}

// Sphere i (global index) of one Newton step.
MPMDEM_HD_INLINE void advance_sphere(const BatchView& v, const NewtonConstants& k, std::int64_t i) {
  constexpr double k6 = 1.0 / 6, k12 = 1.0 / 12, k20 = 1.0 / 20, k30 = 1.0 / 30;
  double x[3], vl[3], w[3], fluct[3], lin[3], f[3], t[3];
  for (int a = 0; a < 3; ++a) {
    x[a] = v.pos[a][i], vl[a] = v.vel[a][i], w[a] = v.ang[a][i];
    f[a] = v.force[a][i], t[a] = v.torque[a][i];
  }
  const double inv_m = v.inv_mass[i], inv_i = v.inv_inertia[i];
  for (int a = 0; a < 3; ++a) {
    fluct[a] = vl[a] - (k.prev(a, 0) * x[0] + k.prev(a, 1) * x[1] + k.prev(a, 2) * x[2]);
  }
  for (int a = 0; a < 3; ++a) lin[a] = damp(k.damping, k.half_dt, fluct[a], f[a] * inv_m);
  for (int a = 0; a < 3; ++a) {
    lin[a] += k.prev(a, 0) * vl[0] + k.prev(a, 1) * vl[1] + k.prev(a, 2) * vl[2];
  }
  for (int a = 0; a < 3; ++a) vl[a] += k.dt * lin[a];
  for (int a = 0; a < 3; ++a) w[a] += k.dt * damp(k.damping, k.half_dt, w[a], t[a] * inv_i);
  if (k.dvg_step) {
    for (int a = 0; a < 3; ++a) {
      vl[a] += k.dvg(a, 0) * x[0] + k.dvg(a, 1) * x[1] + k.dvg(a, 2) * x[2];
    }
  }
  for (int a = 0; a < 3; ++a) {
    v.pos[a][i] = x[a] + vl[a] * k.dt;
    v.vel[a][i] = vl[a];
  }
  for (int a = 0; a < 3; ++a) w[a] += k.dspin[a];
  for (int a = 0; a < 3; ++a) v.ang[a][i] = w[a];
  const double h2 = k.quarter_dt2 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  double* q = v.ori + 4 * i;
  const double before[4] = {q[0], q[1], q[2], q[3]};
  if (h2 < kSeriesLimit) {
    const double sh = k.half_dt * (1 - h2 * k6 * (1 - h2 * k20));
    const double c = 1 - 0.5 * h2 * (1 - h2 * k12 * (1 - h2 * k30));
    const double r1 = sh * w[0], r2 = sh * w[1], r3 = sh * w[2];
    const double q0 = q[3], q1 = q[0], q2 = q[1], q3 = q[2];
    const double o0 = c * q0 - r1 * q1 - r2 * q2 - r3 * q3;
    const double o1 = c * q1 + r1 * q0 + r2 * q3 - r3 * q2;
    const double o2 = c * q2 + r2 * q0 + r3 * q1 - r1 * q3;
    const double o3 = c * q3 + r3 * q0 + r1 * q2 - r2 * q1;
    const double inv = 1 / sqrt(o0 * o0 + o1 * o1 + o2 * o2 + o3 * o3);
    q[3] = o0 * inv, q[0] = o1 * inv, q[1] = o2 * inv, q[2] = o3 * inv;
    return;
  }
  // A fast spin: the exact rotation (native step_rotation: Quaternion(AngleAxis(dt |w|,
  // w / |w|)) * before, normalised). sin and cos are libm's on the host, CUDA's on the
  // device (which may differ in the last bit; rare: |w| dt / 2 >= 1e-3).
  const double angle2 = (w[0] * w[0] + w[1] * w[1]) + w[2] * w[2];
  const double angle = sqrt(angle2);
  const double ha = 0.5 * (angle * k.dt);
  const double s = sin(ha);
  const double rot[4] = {s * (w[0] / angle), s * (w[1] / angle), s * (w[2] / angle), cos(ha)};
  quat_mul(rot, before, q);
  quat_normalise(q);
}

// The rotation vector (axis * angle) of ref^-1 q (Eigen's AngleAxis of a quaternion), added to
// sum (native mean_rotation). atan2 is libm's or CUDA's.
MPMDEM_HD_INLINE void add_rotation(const double* ref, const double* q, double* sum) {
  const double conj[4] = {-ref[0], -ref[1], -ref[2], ref[3]};
  double d[4];
  quat_mul(conj, q, d);
  double n = sqrt((d[0] * d[0] + d[1] * d[1]) + d[2] * d[2]);
  double angle = 0, axis[3] = {1, 0, 0};
  if (n != 0.0) {
    angle = 2 * atan2(n, fabs(d[3]));
    if (d[3] < 0) n = -n;
    for (int a = 0; a < 3; ++a) axis[a] = d[a] / n;
  }
  for (int a = 0; a < 3; ++a) sum[a] += axis[a] * angle;
}

}  // namespace mpmdem::dem::batch

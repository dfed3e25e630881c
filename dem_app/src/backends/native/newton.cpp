// NewtonIntegrator of a native RVE (step 3 of integrator.hpp), over blocks of spheres whose
// fields are copied into xyz-split arrays so that the arithmetic vectorises (the sphere
// arrays themselves keep xyz interleaved). YADE's formulas: Cundall's non-viscous damping on
// the fluctuating velocity, homoDeform = 2, leapfrogTranslate and leapfrogSphericalRotate.
#include <algorithm>
#include <cmath>

#include "backends/native/integrator.hpp"
#include "backends/native/simd_clones.hpp"

namespace mpmdem::dem::native {

namespace {

constexpr int kBlock = 16;  // spheres per block (a multiple of every SIMD width)

// One block of spheres, xyz split (lane j is sphere i0 + j; lanes past the end hold zeros
// and the identity orientation, and are not written back).
struct Block {
  double x[3][kBlock], v[3][kBlock], w[3][kBlock], q[4][kBlock];  // q: w, x, y, z
  double f[3][kBlock], t[3][kBlock], inv_m[kBlock], inv_i[kBlock];
  double h2[kBlock];  // (dt |w| / 2)^2: at kSeriesLimit or above, redone by step_rotation
};

// The rotation of one step, by dt |w| about w / |w|: Eigen's Quaternion(AngleAxis(dt |w|,
// w / |w|)) = (cos h, sin h w / |w|), h = dt |w| / 2. When h < 1e-3 (advance), the Taylor
// series of cos h and sin h / |w| in h^2 = dt^2 |w|^2 / 4: their next terms (h^7/5040,
// h^8/40320) are below 1e-20 of the result, so they agree with libm to rounding, with no
// sqrt, sincos or division (a sphere turns by ~1e-6 rad per DEM step); above, this
// (angle2 = |w|^2 > 0).
constexpr double kSeriesLimit = 1e-6;  // h^2
constexpr double k6 = 1.0 / 6, k12 = 1.0 / 12, k20 = 1.0 / 20, k30 = 1.0 / 30;
Quat step_rotation(const Vec3& w, double angle2, double dt) {
  const double angle = std::sqrt(angle2);
  return Quat(Eigen::AngleAxisd(angle * dt, w / angle));
}

// What every sphere of a step shares.
struct StepConstants {
  double dt, half_dt, quarter_dt2, damping;
  Eigen::Matrix3d prev;  // NewtonIntegrator::prevVelGrad
  double dspin[3];       // spin of the change of the velocity gradient
};

// NewtonIntegrator::cundallDamp2nd on one component (branch-free sign: same values).
inline double damp(double damping, double half_dt, double vel, double accel) {
  const double x = accel * (vel + half_dt * accel);
  const double sign = (x > 0 ? 1.0 : 0.0) - (x < 0 ? 1.0 : 0.0);
  return accel * (1 - damping * sign);
}

void load(const Spheres& sp, std::size_t i0, int m, Block& b) {
  for (int a = 0; a < 3; ++a) {
    const double *x = sp.pos.c[a].data() + i0, *v = sp.vel.c[a].data() + i0;
    const double *w = sp.ang_vel.c[a].data() + i0, *f = sp.force.c[a].data() + i0;
    const double* t = sp.torque.c[a].data() + i0;
    for (int j = 0; j < m; ++j) {
      b.x[a][j] = x[j], b.v[a][j] = v[j], b.w[a][j] = w[j], b.f[a][j] = f[j], b.t[a][j] = t[j];
    }
    for (int j = m; j < kBlock; ++j) {
      b.x[a][j] = 0.0, b.v[a][j] = 0.0, b.w[a][j] = 0.0, b.f[a][j] = 0.0, b.t[a][j] = 0.0;
    }
  }
  for (int j = 0; j < kBlock; ++j) {
    const Quat o = j < m ? sp.ori[i0 + j] : Quat::Identity();
    b.q[0][j] = o.w(), b.q[1][j] = o.x(), b.q[2][j] = o.y(), b.q[3][j] = o.z();
    b.inv_m[j] = j < m ? sp.inv_mass[i0 + j] : 0.0;
    b.inv_i[j] = j < m ? sp.inv_inertia[i0 + j] : 0.0;
  }
}

// The block's arithmetic, lane by lane (no control flow: it vectorises); kDvg: the
// cell's gradient changed in this step (leapfrogTranslate's extra term).
template <bool kDvg>
MPMDEM_ALWAYS_INLINE void advance_lanes(Block& __restrict b, const StepConstants k,
                                        const Eigen::Matrix3d dvg) {
  for (int j = 0; j < kBlock; ++j) {
    double x[3], v[3], w[3], fluct[3], lin[3];
    for (int a = 0; a < 3; ++a) x[a] = b.x[a][j], v[a] = b.v[a][j], w[a] = b.w[a][j];
    for (int a = 0; a < 3; ++a) {
      fluct[a] = v[a] - (k.prev(a, 0) * x[0] + k.prev(a, 1) * x[1] + k.prev(a, 2) * x[2]);
    }
    for (int a = 0; a < 3; ++a)
      lin[a] = damp(k.damping, k.half_dt, fluct[a], b.f[a][j] * b.inv_m[j]);
    for (int a = 0; a < 3; ++a) {
      // + the convective term of homoDeform = 2
      lin[a] += k.prev(a, 0) * v[0] + k.prev(a, 1) * v[1] + k.prev(a, 2) * v[2];
    }
    for (int a = 0; a < 3; ++a) v[a] += k.dt * lin[a];
    for (int a = 0; a < 3; ++a)
      w[a] += k.dt * damp(k.damping, k.half_dt, w[a], b.t[a][j] * b.inv_i[j]);
    // leapfrogTranslate (dvg is zero while the cell's gradient does not change)
    if (kDvg) {
      for (int a = 0; a < 3; ++a) {
        v[a] += dvg(a, 0) * x[0] + dvg(a, 1) * x[1] + dvg(a, 2) * x[2];
      }
    }
    for (int a = 0; a < 3; ++a) b.x[a][j] = x[a] + v[a] * k.dt, b.v[a][j] = v[a];
    // leapfrogSphericalRotate: o = rotation * o, normalised (zero spin: c = 1, s w = 0,
    // the identity, as YADE's skipped rotation)
    for (int a = 0; a < 3; ++a) w[a] += k.dspin[a], b.w[a][j] = w[a];
    const double h2 = k.quarter_dt2 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    b.h2[j] = h2;
    const double sh = k.half_dt * (1 - h2 * k6 * (1 - h2 * k20));  // sin h / |w|
    const double c = 1 - 0.5 * h2 * (1 - h2 * k12 * (1 - h2 * k30));
    const double r1 = sh * w[0], r2 = sh * w[1], r3 = sh * w[2];
    const double q0 = b.q[0][j], q1 = b.q[1][j], q2 = b.q[2][j], q3 = b.q[3][j];
    const double o0 = c * q0 - r1 * q1 - r2 * q2 - r3 * q3;
    const double o1 = c * q1 + r1 * q0 + r2 * q3 - r3 * q2;
    const double o2 = c * q2 + r2 * q0 + r3 * q1 - r1 * q3;
    const double o3 = c * q3 + r3 * q0 + r1 * q2 - r2 * q1;
    const double inv = 1 / std::sqrt(o0 * o0 + o1 * o1 + o2 * o2 + o3 * o3);
    b.q[0][j] = o0 * inv, b.q[1][j] = o1 * inv, b.q[2][j] = o2 * inv, b.q[3][j] = o3 * inv;
  }
}

MPMDEM_SIMD_CLONES void advance(Block& __restrict b, const StepConstants& k) {
  advance_lanes<false>(b, k, Eigen::Matrix3d::Zero());
}
MPMDEM_SIMD_CLONES void advance_dvg(Block& __restrict b, const StepConstants& k,
                                    const Eigen::Matrix3d& dvg) {
  advance_lanes<true>(b, k, dvg);
}

}  // namespace

void newton(RveState& s, double damping) {
  auto& cell = s.cell;
  cell.activate_next();
  const double dt = s.dt;
  const Eigen::Matrix3d dvg = cell.vel_grad - cell.prev_vel_grad;
  const Eigen::Matrix3d rot = 0.5 * (dvg - dvg.transpose());
  const StepConstants k{dt,      0.5 * dt,           0.25 * dt * dt,
                        damping, cell.prev_vel_grad, {-rot(1, 2), rot(0, 2), -rot(0, 1)}};
  const bool dvg_nonzero = dvg != Eigen::Matrix3d::Zero();
  auto& sp = s.spheres;
  const std::size_t n = sp.size();
  Block b;
  for (std::size_t i0 = 0; i0 < n; i0 += kBlock) {
    const int m = static_cast<int>(std::min<std::size_t>(kBlock, n - i0));
    load(sp, i0, m, b);
    if (dvg_nonzero) {
      advance_dvg(b, k, dvg);
    } else {
      advance(b, k);
    }
    for (int a = 0; a < 3; ++a) {
      double *x = sp.pos.c[a].data() + i0, *v = sp.vel.c[a].data() + i0;
      double* w = sp.ang_vel.c[a].data() + i0;
      for (int j = 0; j < m; ++j) x[j] = b.x[a][j], v[j] = b.v[a][j], w[j] = b.w[a][j];
    }
    for (int j = 0; j < m; ++j) {
      const std::size_t i = i0 + j;
      if (b.h2[j] >= kSeriesLimit) {  // rare: a fast spin, the exact rotation
        const Vec3 w = sp.ang_vel[i];
        sp.ori[i] = (step_rotation(w, w.squaredNorm(), dt) * sp.ori[i]).normalized();
      } else {
        sp.ori[i] = Quat(b.q[0][j], b.q[1][j], b.q[2][j], b.q[3][j]);
      }
    }
  }
  cell.prev_vel_grad = cell.vel_grad;
}

}  // namespace mpmdem::dem::native

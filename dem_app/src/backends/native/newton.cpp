// NewtonIntegrator of a native RVE (step 3 of integrator.hpp), one loop over the spheres'
// xyz-split arrays that vectorises (SIMD clones). YADE's formulas: Cundall's non-viscous
// damping on the fluctuating velocity, homoDeform = 2, leapfrogTranslate and
// leapfrogSphericalRotate.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "backends/native/integrator.hpp"
#include "backends/native/simd_clones.hpp"

namespace mpmdem::dem::native {

namespace {

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
  Eigen::Matrix3d prev;    // NewtonIntegrator::prevVelGrad
  double dspin[3];         // spin of the change of the velocity gradient
  Eigen::Matrix3d skin_a;  // the skin check's homogeneous deformation (NeighbourList::moved)
};

// NewtonIntegrator::cundallDamp2nd on one component (branch-free sign: same values).
inline double damp(double damping, double half_dt, double vel, double accel) {
  const double x = accel * (vel + half_dt * accel);
  const double sign = (x > 0 ? 1.0 : 0.0) - (x < 0 ? 1.0 : 0.0);
  return accel * (1 - damping * sign);
}

// The arrays of one call (restrict: the vectoriser needs no alias checks); q: the
// orientations as Eigen stores them (x, y, z, w per sphere).
struct Arrays {
  double *x0, *x1, *x2, *v0, *v1, *v2, *w0, *w1, *w2;
  const double *f0, *f1, *f2, *t0, *t1, *t2, *inv_m, *inv_i;
  double *q, *q_old;
  const float* ref;
};

// The step of spheres [0, n), sphere by sphere (no control flow: it vectorises); kDvg: the
// cell's gradient changed in this step (leapfrogTranslate's extra term). A sphere spinning
// fast enough that the rotation's series is not exact (h^2 >= kSeriesLimit) is rotated
// exactly afterwards by newton(), from its orientation before (q_old, same layout as q).
// What the loop saw (with kSkin; without, fast is true and max_d2_bits 0): a fast spin;
// max_i |x_i - A x_ref_i|^2 (the skin check's) as the bits of a double (>= 0, so ordered as
// integers: an integer max reduction, which vectorises).
struct Seen {
  bool fast;
  std::int64_t max_d2_bits;
};

template <bool kDvg, bool kSkin>
MPMDEM_ALWAYS_INLINE Seen advance_spheres(
    std::size_t n, const StepConstants k, const Eigen::Matrix3d dvg, double* __restrict x0,
    double* __restrict x1, double* __restrict x2, double* __restrict v0, double* __restrict v1,
    double* __restrict v2, double* __restrict w0, double* __restrict w1, double* __restrict w2,
    const double* __restrict f0, const double* __restrict f1, const double* __restrict f2,
    const double* __restrict t0, const double* __restrict t1, const double* __restrict t2,
    const double* __restrict inv_m, const double* __restrict inv_i, double* __restrict qd,
    double* __restrict q_old, const float* __restrict ref) {
  unsigned fast = 0;  // some sphere spins too fast for the series (an OR reduction: vectorises)
  std::int64_t max_bits = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double x[3], v[3], w[3], fluct[3], lin[3];
    x[0] = x0[i], x[1] = x1[i], x[2] = x2[i];
    v[0] = v0[i], v[1] = v1[i], v[2] = v2[i];
    w[0] = w0[i], w[1] = w1[i], w[2] = w2[i];
    const double f[3] = {f0[i], f1[i], f2[i]}, t[3] = {t0[i], t1[i], t2[i]};
    for (int a = 0; a < 3; ++a) {
      fluct[a] = v[a] - (k.prev(a, 0) * x[0] + k.prev(a, 1) * x[1] + k.prev(a, 2) * x[2]);
    }
    for (int a = 0; a < 3; ++a) lin[a] = damp(k.damping, k.half_dt, fluct[a], f[a] * inv_m[i]);
    for (int a = 0; a < 3; ++a) {
      // + the convective term of homoDeform = 2
      lin[a] += k.prev(a, 0) * v[0] + k.prev(a, 1) * v[1] + k.prev(a, 2) * v[2];
    }
    for (int a = 0; a < 3; ++a) v[a] += k.dt * lin[a];
    for (int a = 0; a < 3; ++a) w[a] += k.dt * damp(k.damping, k.half_dt, w[a], t[a] * inv_i[i]);
    // leapfrogTranslate (dvg is zero while the cell's gradient does not change)
    if (kDvg) {
      for (int a = 0; a < 3; ++a) {
        v[a] += dvg(a, 0) * x[0] + dvg(a, 1) * x[1] + dvg(a, 2) * x[2];
      }
    }
    const double xn[3] = {x[0] + v[0] * k.dt, x[1] + v[1] * k.dt, x[2] + v[2] * k.dt};
    x0[i] = xn[0], x1[i] = xn[1], x2[i] = xn[2];
    if (kSkin) {  // NeighbourList::ensure's |x - A x_ref|^2; a NaN is skipped as it does
      const double d2 = NeighbourList::residual2(xn, k.skin_a, ref + 3 * i);
      std::int64_t u;
      std::memcpy(&u, &d2, sizeof u);
      u = d2 == d2 ? u : 0;
      max_bits = u > max_bits ? u : max_bits;
    }
    v0[i] = v[0], v1[i] = v[1], v2[i] = v[2];
    // leapfrogSphericalRotate: o = rotation * o, normalised (zero spin: c = 1, s w = 0,
    // the identity, as YADE's skipped rotation)
    for (int a = 0; a < 3; ++a) w[a] += k.dspin[a];
    w0[i] = w[0], w1[i] = w[1], w2[i] = w[2];
    const double h2 = k.quarter_dt2 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (kSkin) fast |= !(h2 < kSeriesLimit);                       // newton()'s test, NaN included
    const double sh = k.half_dt * (1 - h2 * k6 * (1 - h2 * k20));  // sin h / |w|
    const double c = 1 - 0.5 * h2 * (1 - h2 * k12 * (1 - h2 * k30));
    const double r1 = sh * w[0], r2 = sh * w[1], r3 = sh * w[2];
    double* q = qd + 4 * i;
    const double q0 = q[3], q1 = q[0], q2 = q[1], q3 = q[2];
    const double o0 = c * q0 - r1 * q1 - r2 * q2 - r3 * q3;
    const double o1 = c * q1 + r1 * q0 + r2 * q3 - r3 * q2;
    const double o2 = c * q2 + r2 * q0 + r3 * q1 - r1 * q3;
    const double o3 = c * q3 + r3 * q0 + r1 * q2 - r2 * q1;
    const double inv = 1 / std::sqrt(o0 * o0 + o1 * o1 + o2 * o2 + o3 * o3);
    q[3] = o0 * inv, q[0] = o1 * inv, q[1] = o2 * inv, q[2] = o3 * inv;
    double* old = q_old + 4 * i;  // for the exact rotation of a fast spin (newton())
    old[0] = q1, old[1] = q2, old[2] = q3, old[3] = q0;
  }
  return {!kSkin || fast != 0, max_bits};  // without kSkin, newton() scans the spheres
}

#define MPMDEM_NEWTON_ARGS                                                                       \
  n, k, dvg, a.x0, a.x1, a.x2, a.v0, a.v1, a.v2, a.w0, a.w1, a.w2, a.f0, a.f1, a.f2, a.t0, a.t1, \
      a.t2, a.inv_m, a.inv_i, a.q, a.q_old, a.ref
// ref: the neighbour list's reference positions (nullptr: no skin check). Not in the step
// that changes the gradient (advance_dvg): there its terms spill registers and cost more
// than the separate check in NeighbourList::ensure.
MPMDEM_SIMD_CLONES Seen advance(std::size_t n, const StepConstants& k, const Arrays& a) {
  const Eigen::Matrix3d dvg = Eigen::Matrix3d::Zero();
  if (a.ref) return advance_spheres<false, true>(MPMDEM_NEWTON_ARGS);
  return advance_spheres<false, false>(MPMDEM_NEWTON_ARGS);
}
MPMDEM_SIMD_CLONES Seen advance_dvg(std::size_t n, const StepConstants& k, const Arrays& a,
                                    const Eigen::Matrix3d& dvg) {
  return advance_spheres<true, false>(MPMDEM_NEWTON_ARGS);
}
#undef MPMDEM_NEWTON_ARGS

}  // namespace

void newton(RveState& s, double damping, NeighbourList* nl) {
  auto& cell = s.cell;
  cell.activate_next();
  const double dt = s.dt;
  const Eigen::Matrix3d dvg = cell.vel_grad - cell.prev_vel_grad;
  const Eigen::Matrix3d rot = 0.5 * (dvg - dvg.transpose());
  auto& sp = s.spheres;
  const std::size_t n = sp.size();
  const bool dvg_step = dvg != Eigen::Matrix3d::Zero();
  const float* ref = nl ? nl->ref_positions(n) : nullptr;
  // The lattice of the next step's cell move (PeriodicCell::integrate_and_update, the same
  // operations) and its deformation since the list's build, for the skin check.
  Eigen::Matrix3d h_next = cell.hsize;
  Eigen::Matrix3d skin_a = Eigen::Matrix3d::Identity();
  if (ref && !dvg_step) {
    const Eigen::Matrix3d inc = dt * cell.vel_grad;
    h_next += inc * h_next;
    skin_a = nl->deformation(h_next);
  }
  const StepConstants k{dt,      0.5 * dt,           0.25 * dt * dt,
                        damping, cell.prev_vel_grad, {-rot(1, 2), rot(0, 2), -rot(0, 1)},
                        skin_a};
  thread_local std::vector<double> q_old;  // scratch of this thread, not of the RVE
  q_old.resize(4 * n);
  Seen seen{false, 0};
  if (n > 0) {
    const Arrays a{sp.pos.c[0].data(),     sp.pos.c[1].data(),
                   sp.pos.c[2].data(),     sp.vel.c[0].data(),
                   sp.vel.c[1].data(),     sp.vel.c[2].data(),
                   sp.ang_vel.c[0].data(), sp.ang_vel.c[1].data(),
                   sp.ang_vel.c[2].data(), sp.force.c[0].data(),
                   sp.force.c[1].data(),   sp.force.c[2].data(),
                   sp.torque.c[0].data(),  sp.torque.c[1].data(),
                   sp.torque.c[2].data(),  sp.inv_mass.data(),
                   sp.inv_inertia.data(),  sp.ori[0].coeffs().data(),
                   q_old.data(),           ref};
    if (dvg_step) {
      seen = advance_dvg(n, k, a, dvg);
    } else {
      seen = advance(n, k, a);
    }
  }
  if (ref && !dvg_step) {
    double max_d2;
    std::memcpy(&max_d2, &seen.max_d2_bits, sizeof max_d2);
    nl->moved(max_d2, s.iter + 1, h_next, skin_a);  // dem_step's ++iter follows
  }
  const bool fast = seen.fast;
  // Rare: a fast spin (the series above is not exact), the exact rotation; the spheres are
  // scanned only if the loop above saw one (the same test on the same h^2).
  for (std::size_t i = 0; fast && i < n; ++i) {
    const Vec3 w = sp.ang_vel[i];
    const double w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    if (k.quarter_dt2 * w2 < kSeriesLimit) continue;
    const Quat before(q_old[4 * i + 3], q_old[4 * i], q_old[4 * i + 1], q_old[4 * i + 2]);
    sp.ori[i] = (step_rotation(w, w.squaredNorm(), dt) * before).normalized();
  }
  cell.prev_vel_grad = cell.vel_grad;
}

}  // namespace mpmdem::dem::native

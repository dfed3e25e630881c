// One coupling step of one batch RVE, for host and device: a thread group Ctx (the host batch
// path: one thread; the device: one thread block per RVE) runs the RVE's own ns substeps
// (burst_vel_grad: rve_driver.cpp's split_increment, the velGrad-lag correction; each group
// loops its own ns, so mixed counts serialise nothing), then its unbalanced force (when
// replied), kinetic energy and status (energy_status, the driver's rule), the flip of its
// cell, the tiling check and its reply (Love-Weber stress, stiffness bound, outputs), as the
// native backend does under the driver (rve_driver.cpp).
// Ctx: tid(), nt(), sync(), max_all(x) (a max over the group, to every thread), scan(x,
// &total) (exclusive prefix sum in tid order, total to every thread), atomic_add(int*, int)
// (returns the old value). Phases are separated by ctx.sync(); what must stay in one order
// (force sums per sphere, the contacts' order, the Love-Weber lanes) keeps the native order.
#pragma once

#include "backends/batch/substep.hpp"
#include "rve_status_rule.hpp"

namespace mpmdem::dem::batch {

constexpr double kTileHeight = 2.2;  // native cell_regularisation.hpp's
constexpr int kLanes = 8, kTerms = 15;

// The reply's stress and stiffness (native stress_and_stiffness): the terms of contact k go to
// lane k mod 8, each lane summed in contact order, the lanes added at the end. The lanes live
// in the RVE's first 120 `of` slots (scratch after the burst; capacity >= 128).
template <class Ctx>
MPMDEM_HD void reply_stress(const BatchView& v, const BatchParams& bp, int r, Ctx& ctx) {
  const std::int64_t s0 = v.sph0[r], c0 = v.con0[r], nc = v.n_con[r];
  const double* cb = v.cell + static_cast<std::int64_t>(r) * kCellDoubles;
  double h[3][3];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) h[a][b] = cb[kHsize + 3 * a + b];
  double* lanes = v.of[0] + c0;  // [term * kLanes + lane]
  for (int lane = ctx.tid(); lane < kLanes; lane += ctx.nt()) {
    double acc[kTerms] = {};
    for (std::int64_t k = lane; k < nc; k += kLanes) {
      double t[kTerms];
      stress_terms(v, h, v.young[r], v.ks_kn[r], s0, c0 + k, t);
      for (int q = 0; q < kTerms; ++q) acc[q] += t[q];
    }
    for (int q = 0; q < kTerms; ++q) lanes[q * kLanes + lane] = acc[q];
  }
  ctx.sync();
  if (ctx.tid() != 0) return;
  double sum[9] = {}, cii[3] = {}, si[3] = {};
  for (int j = 0; j < kLanes; ++j) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) sum[3 * a + b] += lanes[(3 * a + b) * kLanes + j];
      cii[a] += lanes[(9 + a) * kLanes + j];
      si[a] += lanes[(12 + a) * kLanes + j];
    }
  }
  const double volume = det(cell_get(cb, kHsize));
  StepOut& out = v.out[r];
  bool finite = true;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const double s = 0.5 * (sum[3 * a + b] / volume + sum[3 * b + a] / volume);
      out.stress[3 * a + b] = s;
      finite = finite && hd_isfinite(s);
    }
  if (!finite) {
    out.status = kStatusNonFinite;
    for (double& x : out.stress) x = 0;
    return;
  }
  double stiff = 0;
  if (bp.stiffness) {
    const double a = v.ks_kn[r];
    for (int i = 0; i < 3; ++i) {
      const double b = a <= 1 ? (1 - a) * cii[i] + a * si[i] : cii[i] + a * si[i];
      stiff = stiff < b ? b : stiff;
    }
    stiff /= volume;
  }
  out.stiffness = stiff;
}

// The optional outputs of RVE r (one thread; native fill_reply).
MPMDEM_HD_INLINE void reply_outputs(const BatchView& v, const BatchParams& bp, int r) {
  const std::int64_t s0 = v.sph0[r], n = v.sph0[r + 1] - s0, nc = v.n_con[r];
  StepOut& out = v.out[r];
  const double volume = det(cell_get(v.cell + static_cast<std::int64_t>(r) * kCellDoubles, kHsize));
  if (bp.outputs & kOutRotation) {
    double sum[3] = {0, 0, 0};
    for (std::int64_t i = 0; i < n; ++i)
      add_rotation(v.ref_ori + 4 * (s0 + i), v.ori + 4 * (s0 + i), sum);
    for (int a = 0; a < 3; ++a) out.rotation[a] = n ? sum[a] / static_cast<double>(n) : 0.0;
  }
  if (bp.outputs & kOutPorosity) {
    double vs = 0;
    for (std::int64_t i = 0; i < n; ++i) {
      const double rr = v.radius[s0 + i];
      vs += 4.0 / 3.0 * 3.14159265358979323846 * rr * rr * rr;
    }
    out.porosity = 1.0 - vs / fabs(volume);
  }
  if (bp.outputs & kOutCoordination) {
    out.coordination = n ? 2.0 * static_cast<double>(nc) / static_cast<double>(n) : 0.0;
  }
  if ((bp.outputs & kOutUnbalanced) && nc > 0) out.unbalanced = v.unbalanced[r];
}

// The whole coupling step of RVE r (all threads of the group).
template <class Ctx>
MPMDEM_HD void rve_step(const BatchView& v, const BatchParams& bp, int r, Ctx& ctx) {
  const StepIn& in = v.in[r];
  if (!(in.flags & kStepActive)) return;
  const std::int64_t s0 = v.sph0[r], n = v.sph0[r + 1] - s0, c0 = v.con0[r];
  double* cb = v.cell + static_cast<std::int64_t>(r) * kCellDoubles;
  std::int32_t* fl = v.flags + r * kRveFlags;
  StepOut& out = v.out[r];
  const bool t0 = ctx.tid() == 0;
  if (t0) {
    for (double& x : out.stress) x = 0;
    for (double& x : out.rotation) x = 0;
    out.porosity = out.coordination = out.unbalanced = out.stiffness = out.kinetic = 0;
    out.status = kStatusOk, out.error = kErrNone, out.tile = 0, out.rebuilds = 0;
  }
  const int ns = in.ns;
  // The burst (t0 keeps the target dF trsf_start in its registers).
  M3 target = m3_zero();
  if (t0 && ns > 0) target = mul_row_major_lhs(m3_load(in.dF), cell_get(cb, kTrsf));
  for (int j = 1; j <= ns; ++j) {
    if (t0) burst_vel_grad(cb, fl, target, in.dF, j, ns, v.dt[r]);
    const std::int32_t err = substep(v, bp, r, ctx);
    if (err != kErrNone) {
      if (t0) out.error = err;
      return;
    }
  }
  const std::int64_t nc = v.n_con[r];
  if (t0) {
    if (ns > 0 && (bp.outputs & kOutUnbalanced)) {  // native unbalanced_force
      double ub = 0;
      if (n > 0 && nc > 0) {
        double body = 0, contact = 0;
        for (std::int64_t i = 0; i < n; ++i) {
          const double f[3] = {v.force[0][s0 + i], v.force[1][s0 + i], v.force[2][s0 + i]};
          body += sqrt(dot3(f, f));
        }
        for (std::int64_t k = 0; k < nc; ++k) {
          const std::int64_t c = c0 + k;
          double kn, ks, fn[3];
          laws::Frict::stiffness(v.young[r], v.ks_kn[r], v.radius[s0 + v.id1[c]],
                                 v.radius[s0 + v.id2[c]], kn, ks);
          const double nrm[3] = {v.normal[0][c], v.normal[1][c], v.normal[2][c]};
          laws::Frict::stored_normal_force(kn, v.pen[c], 0.0, nrm, fn);
          double f[3];
          for (int q = 0; q < 3; ++q) f[q] = fn[q] + v.shear[q][c];
          contact += sqrt(dot3(f, f));
        }
        ub = (body / static_cast<double>(n)) / (contact / static_cast<double>(nc));
      }
      v.unbalanced[r] = ub;
    }
    // Kinetic energy of the fluctuating motion (native kinetic_energy) and the status.
    const M3 prev = cell_get(cb, kPrevVelGrad);
    double e = 0;
    for (std::int64_t i = 0; i < n; ++i) {
      const double x[3] = {v.pos[0][s0 + i], v.pos[1][s0 + i], v.pos[2][s0 + i]};
      double px[3], d[3];
      mul_vec(prev, x, px);
      for (int q = 0; q < 3; ++q) d[q] = v.vel[q][s0 + i] - px[q];
      const double w[3] = {v.ang[0][s0 + i], v.ang[1][s0 + i], v.ang[2][s0 + i]};
      e += 0.5 * v.mass[s0 + i] * dot3(d, d);
      e += 0.5 * v.inertia[s0 + i] * dot3(w, w);
    }
    out.kinetic = e;
    out.status = energy_status(e, det(cell_get(cb, kHsize)), bp.ke_threshold, v.p0[r]);
    // Flip (native flip_cell): the image offsets become M^-1 c.
    int m[9];
    fl[kScratch] = flip(cb, m) ? 1 : 0;
    if (fl[kScratch]) {
      M3 md;
      for (int q = 0; q < 9; ++q) md.a[q] = static_cast<double>(m[q]);
      cell_set(cb, kFlipInv, inverse(md));
      fl[kListValid] = 0;
    }
    // Tiling check (every 10th step, native tile_if_thin's test): the host tiles.
    if ((in.flags & kStepTileCheck) && n > 0) {
      double ht[3], rmax = 0;
      heights(cell_get(cb, kHsize), ht);
      for (std::int64_t i = 0; i < n; ++i) rmax = hd_max(rmax, v.radius[s0 + i]);
      const double hmin = hd_min(ht[0], hd_min(ht[1], ht[2]));
      out.tile = hmin < kTileHeight * (2.0 * rmax) ? 1 : 0;
    }
  }
  ctx.sync();
  if (fl[kScratch]) {
    const M3 inv = cell_get(cb, kFlipInv);
    for (std::int64_t k = ctx.tid(); k < nc; k += ctx.nt()) {
      const double c[3] = {static_cast<double>(v.ccell[0][c0 + k]),
                           static_cast<double>(v.ccell[1][c0 + k]),
                           static_cast<double>(v.ccell[2][c0 + k])};
      double w[3];
      mul_vec(inv, c, w);
      for (int a = 0; a < 3; ++a) v.ccell[a][c0 + k] = static_cast<std::int16_t>(llround(w[a]));
    }
  }
  ctx.sync();
  if (out.tile) return;  // the host tiles the RVE and replies from its state
  if (out.status == kStatusOk && nc == 0) {
    if (t0) out.status = kStatusNoContacts;
  } else if (out.status == kStatusOk) {
    reply_stress(v, bp, r, ctx);
  }
  ctx.sync();
  if (t0 && (out.status == kStatusOk || out.status == kStatusNoContacts)) reply_outputs(v, bp, r);
}

}  // namespace mpmdem::dem::batch

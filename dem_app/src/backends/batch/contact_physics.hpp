// The per-contact physics of the batch backend, for host and device (MPMDEM_HD): the contact
// update of a DEM step (Ig2_Sphere_Sphere_ScGeom with ScGeom::precompute/rotate and
// Law2_ScGeom_FrictPhys_CundallStrack with the rotating shear spring, kn and ks of
// Ip2_FrictMat_FrictMat_FrictPhys from the radii) and a contact's Love-Weber and stiffness
// terms. Expression for expression those of the native backend (native/contact_kernel.cpp's
// contact_loop, native/measures.cpp's contributions), so that the batch gives its bits; the law
// itself is the same source, backends/contact_laws/frict.hpp (the batch has the frict law only:
// coupling_rules.cpp's check_cuda_contact_law).
#pragma once

#include <cmath>

#include "backends/batch/batch_layout.hpp"
#include "backends/batch/hd.hpp"
#include "backends/contact_laws/frict.hpp"

namespace mpmdem::dem::batch {

// What every contact of an RVE's DEM step shares (native::LawConstants): the law's parameters
// (young, ks_kn, tan2; beta_n 0) and the step's.
struct Law : laws::LawParams {
  double dt, half_dt;
  double h[3][3];   // hsize
  double lh[3][3];  // velGrad * hsize before the step
};

// Contact slot c of the RVE whose spheres start at s0: normal, shear force and penetration
// updated in place, its forces written to of/ot1/ot2. A new contact has zero normal and shear.
MPMDEM_HD_INLINE void update_contact(const BatchView& v, const Law& k, std::int64_t s0,
                                     std::int64_t c) {
  const std::int64_t a = s0 + v.id1[c], b = s0 + v.id2[c];
  const double r1 = v.radius[a], r2 = v.radius[b];
  const double ci[3] = {static_cast<double>(v.ccell[0][c]), static_cast<double>(v.ccell[1][c]),
                        static_cast<double>(v.ccell[2][c])};
  double d[3], sv[3];
  for (int q = 0; q < 3; ++q) {
    const double shift = k.h[q][0] * ci[0] + k.h[q][1] * ci[1] + k.h[q][2] * ci[2];
    sv[q] = k.lh[q][0] * ci[0] + k.lh[q][1] * ci[1] + k.lh[q][2] * ci[2];
    d[q] = (v.pos[q][b] + shift) - v.pos[q][a];
  }
  const double dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const double inv_dist = 1 / dist;
  const double n[3] = {d[0] * inv_dist, d[1] * inv_dist, d[2] * inv_dist};
  const double rs = r1 + r2;
  const double pen = rs - dist;
  const double p[3] = {v.normal[0][c], v.normal[1][c], v.normal[2][c]};
  double w1[3], w2[3];
  for (int q = 0; q < 3; ++q) w1[q] = v.ang[q][a], w2[q] = v.ang[q][b];
  const double ax[3] = {p[1] * n[2] - p[2] * n[1], p[2] * n[0] - p[0] * n[2],
                        p[0] * n[1] - p[1] * n[0]};
  const double angle =
      k.half_dt * (p[0] * (w1[0] + w2[0]) + p[1] * (w1[1] + w2[1]) + p[2] * (w1[2] + w2[2]));
  const double tw[3] = {angle * p[0], angle * p[1], angle * p[2]};
  const double alpha = rs * inv_dist;
  double u[3], rel[3];
  for (int q = 0; q < 3; ++q) u[q] = r1 * w1[q] + r2 * w2[q];
  const double uxn[3] = {u[1] * n[2] - u[2] * n[1], u[2] * n[0] - u[0] * n[2],
                         u[0] * n[1] - u[1] * n[0]};
  for (int q = 0; q < 3; ++q) rel[q] = (v.vel[q][b] - v.vel[q][a] + sv[q]) * alpha - uxn[q];
  const double rn = n[0] * rel[0] + n[1] * rel[1] + n[2] * rel[2];
  double inc[3];
  for (int q = 0; q < 3; ++q) inc[q] = (rel[q] - rn * n[q]) * k.dt;
  double kn, ks;
  laws::Frict::stiffness(k.young, k.ks_kn, r1, r2, kn, ks);
  double fs[3] = {v.shear[0][c], v.shear[1][c], v.shear[2][c]};
  double t[3] = {fs[1] * ax[2] - fs[2] * ax[1], fs[2] * ax[0] - fs[0] * ax[2],
                 fs[0] * ax[1] - fs[1] * ax[0]};
  for (int q = 0; q < 3; ++q) fs[q] -= t[q];
  t[0] = fs[1] * tw[2] - fs[2] * tw[1];
  t[1] = fs[2] * tw[0] - fs[0] * tw[2];
  t[2] = fs[0] * tw[1] - fs[1] * tw[0];
  for (int q = 0; q < 3; ++q) fs[q] -= t[q];
  laws::Frict::shear_increment(ks, inc, fs);
  double fn[3], unused = 0;
  laws::Frict::normal_force(k, kn, pen, rn, unused, unused, n, fn, unused);
  laws::Frict::slide(k, fn, fs);
  const double f[3] = {-fn[0] - fs[0], -fn[1] - fs[1], -fn[2] - fs[2]};
  const double nf[3] = {n[1] * f[2] - n[2] * f[1], n[2] * f[0] - n[0] * f[2],
                        n[0] * f[1] - n[1] * f[0]};
  const double l1 = r1 - 0.5 * pen, l2 = r2 - 0.5 * pen;
  for (int q = 0; q < 3; ++q) {
    v.normal[q][c] = n[q];
    v.shear[q][c] = fs[q];
    v.of[q][c] = f[q];
    v.ot1[q][c] = l1 * nf[q];
    v.ot2[q][c] = l2 * nf[q];
  }
  v.pen[c] = pen;
}

// The 15 Love-Weber and stiffness terms of contact slot c (native measures' contributions):
// 9 stress (Fn + Fs) (-l)^T, 3 l^2 n_i^2 (kn n_i^2 + ks t_i^2), 3 kn l^2 n_i^2.
MPMDEM_HD_INLINE void stress_terms(const BatchView& v, const double (&h)[3][3], double young,
                                   double ks_kn, std::int64_t s0, std::int64_t c,
                                   double (&out)[15]) {
  const std::int64_t a = s0 + v.id1[c], b = s0 + v.id2[c];
  const double cc[3] = {static_cast<double>(v.ccell[0][c]), static_cast<double>(v.ccell[1][c]),
                        static_cast<double>(v.ccell[2][c])};
  const double n[3] = {v.normal[0][c], v.normal[1][c], v.normal[2][c]};
  const double fs[3] = {v.shear[0][c], v.shear[1][c], v.shear[2][c]};
  double l[3];
  for (int q = 0; q < 3; ++q) {
    l[q] = (v.pos[q][b] + (h[q][0] * cc[0] + h[q][1] * cc[1] + h[q][2] * cc[2])) - v.pos[q][a];
  }
  double kn, ks, fn[3];
  laws::Frict::stiffness(young, ks_kn, v.radius[a], v.radius[b], kn, ks);
  laws::Frict::stored_normal_force(kn, v.pen[c], 0.0, n, fn);
  for (int i = 0; i < 3; ++i) {
    const double f = fn[i] + fs[i];
    for (int j = 0; j < 3; ++j) out[3 * i + j] = f * -l[j];
  }
  const double l2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
  const double fs2 = fs[0] * fs[0] + fs[1] * fs[1] + fs[2] * fs[2];
  const double inv = 1 / fs2;
  const double inv_fs2 = fs2 > 0 ? inv : 0.0;
  for (int i = 0; i < 3; ++i) {
    const double ni2 = n[i] * n[i];
    const double ti2 = fs[i] * fs[i] * inv_fs2;
    out[9 + i] = l2 * ni2 * (kn * ni2 + ks * ti2);
    out[12 + i] = kn * l2 * ni2;
  }
}

// Ig2_Sphere_Sphere_ScGeom's overlap test of pair slot p (the native new-contact scan's:
// shift = hsize c as Eigen's product, r^2 - |d|^2 >= 0).
MPMDEM_HD_INLINE bool pair_overlaps(const BatchView& v, const double* hsize, std::int64_t s0,
                                    std::int64_t p) {
  const std::int64_t a = s0 + v.pi[p], j = s0 + v.pj[p];
  const double c[3] = {static_cast<double>(v.pc[0][p]), static_cast<double>(v.pc[1][p]),
                       static_cast<double>(v.pc[2][p])};
  double h[3];
  for (int i = 0; i < 3; ++i) {
    const double p0 = hsize[3 * i] * c[0], p1 = hsize[3 * i + 1] * c[1],
                 p2 = hsize[3 * i + 2] * c[2];
    h[i] = i < 2 ? (p0 + p1) + p2 : p0 + (p1 + p2);
  }
  const double d0 = (v.pos[0][j] + h[0]) - v.pos[0][a], d1 = (v.pos[1][j] + h[1]) - v.pos[1][a],
               d2 = (v.pos[2][j] + h[2]) - v.pos[2][a];
  const double r = v.radius[a] + v.radius[j];
  return r * r - ((d0 * d0 + d1 * d1) + d2 * d2) >= 0;
}

}  // namespace mpmdem::dem::batch

// Contact update over a range of contacts: see contact_kernel.hpp.
#include "backends/native/contact_kernel.hpp"

#include <algorithm>
#include <cmath>

#include "backends/native/simd_clones.hpp"

namespace mpmdem::dem::native {

namespace {

// The arrays one call reads and writes (restrict: the vectoriser needs no alias checks).
// Sphere and contact vector fields are xyz split (x0, x1, x2: the components of the position).
// Law: the RVE's contact law (backends/contact_laws/); a viscous one (Law::kViscous) also reads the
// masses and writes the viscous part of its normal force to visc_out; otherwise both are
// unused (nullptr).
template <class Law>
MPMDEM_ALWAYS_INLINE void contact_body(
    std::size_t m, const LawConstants& kc, const StagedContacts* __restrict st,
    double* __restrict nx, double* __restrict ny, double* __restrict nz, double* __restrict sx,
    double* __restrict sy, double* __restrict sz, double* __restrict pen_out,
    const double* __restrict x0, const double* __restrict x1, const double* __restrict x2,
    const double* __restrict v0, const double* __restrict v1, const double* __restrict v2,
    const double* __restrict w0, const double* __restrict w1_, const double* __restrict w2_,
    const double* __restrict rad, const double* __restrict mass, double* __restrict visc_out,
    ContactOut* __restrict out) {
  const double* const pos[3] = {x0, x1, x2};
  const double* const vel[3] = {v0, v1, v2};
  const double* const ang[3] = {w0, w1_, w2_};
  const LawConstants k = kc;
  for (std::size_t j = 0; j < m; ++j) {
    const std::int64_t a = st->a[j], b = st->b[j];
    const double r1 = rad[a], r2 = rad[b];
    const double ci[3] = {st->c[0][j], st->c[1][j], st->c[2][j]};
    // Image of sphere 2: x2 + H c and its extra velocity (L H_before) c (Cell::intrShiftVel);
    // zero for the contacts inside the cell (adding it changes no bit).
    double d[3], sv[3];
    for (int q = 0; q < 3; ++q) {
      const double shift = k.h[q][0] * ci[0] + k.h[q][1] * ci[1] + k.h[q][2] * ci[2];
      sv[q] = k.lh[q][0] * ci[0] + k.lh[q][1] * ci[1] + k.lh[q][2] * ci[2];
      d[q] = (pos[q][b] + shift) - pos[q][a];
    }
    // ScGeom: normal, penetration (one division for the normal and McNamara's alpha).
    const double dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double inv_dist = 1 / dist;
    const double n[3] = {d[0] * inv_dist, d[1] * inv_dist, d[2] * inv_dist};
    const double rs = r1 + r2;
    const double pen = rs - dist;
    // Rotation of the contact since the last step: orthonormal_axis = prev x n, twist_axis =
    // dt/2 (prev . (w1 + w2)) prev (zero for a new contact: prev = 0).
    const double p[3] = {nx[j], ny[j], nz[j]};
    double w1[3], w2[3];
    for (int q = 0; q < 3; ++q) w1[q] = ang[q][a], w2[q] = ang[q][b];
    const double ax[3] = {p[1] * n[2] - p[2] * n[1], p[2] * n[0] - p[0] * n[2],
                          p[0] * n[1] - p[1] * n[0]};
    const double angle =
        k.half_dt * (p[0] * (w1[0] + w2[0]) + p[1] * (w1[1] + w2[1]) + p[2] * (w1[2] + w2[2]));
    const double tw[3] = {angle * p[0], angle * p[1], angle * p[2]};
    // ScGeom::getIncidentVel with McNamara's alpha (r1 + r2) / dist, the spin terms in one
    // cross product: rel = (v2 - v1 + sv) alpha - (r1 w1 + r2 w2) x n, minus its normal part.
    const double alpha = rs * inv_dist;
    double u[3], rel[3];
    for (int q = 0; q < 3; ++q) u[q] = r1 * w1[q] + r2 * w2[q];
    const double uxn[3] = {u[1] * n[2] - u[2] * n[1], u[2] * n[0] - u[0] * n[2],
                           u[0] * n[1] - u[1] * n[0]};
    for (int q = 0; q < 3; ++q) rel[q] = (vel[q][b] - vel[q][a] + sv[q]) * alpha - uxn[q];
    const double rn = n[0] * rel[0] + n[1] * rel[1] + n[2] * rel[2];
    double inc[3];
    for (int q = 0; q < 3; ++q) inc[q] = (rel[q] - rn * n[q]) * k.dt;
    double kn, ks;
    Law::stiffness(k.young, k.ks_kn, r1, r2, kn, ks);
    // ScGeom::rotate: the shear force turned with the contact.
    double fs[3] = {sx[j], sy[j], sz[j]};
    double t[3] = {fs[1] * ax[2] - fs[2] * ax[1], fs[2] * ax[0] - fs[0] * ax[2],
                   fs[0] * ax[1] - fs[1] * ax[0]};
    for (int q = 0; q < 3; ++q) fs[q] -= t[q];
    t[0] = fs[1] * tw[2] - fs[2] * tw[1];
    t[1] = fs[2] * tw[0] - fs[0] * tw[2];
    t[2] = fs[0] * tw[1] - fs[1] * tw[0];
    for (int q = 0; q < 3; ++q) fs[q] -= t[q];
    // The law: shear increment, normal force, Coulomb cap.
    Law::shear_increment(ks, inc, fs);
    double m1 = 0, m2 = 0, fn[3], visc = 0;
    if constexpr (Law::kViscous) m1 = mass[a], m2 = mass[b];
    Law::normal_force(k, kn, pen, rn, m1, m2, n, fn, visc);
    if constexpr (Law::kViscous) visc_out[j] = visc;
    Law::slide(k, fn, fs);
    // Force on sphere 1, torques n x f with the branches r - pen / 2.
    const double f[3] = {-fn[0] - fs[0], -fn[1] - fs[1], -fn[2] - fs[2]};
    const double nf[3] = {n[1] * f[2] - n[2] * f[1], n[2] * f[0] - n[0] * f[2],
                          n[0] * f[1] - n[1] * f[0]};
    const double l1 = r1 - 0.5 * pen, l2 = r2 - 0.5 * pen;
    nx[j] = n[0], ny[j] = n[1], nz[j] = n[2];
    sx[j] = fs[0], sy[j] = fs[1], sz[j] = fs[2];
    pen_out[j] = pen;
    for (int q = 0; q < 3; ++q) {
      out->f[q][j] = f[q];
      out->t1[q][j] = l1 * nf[q];
      out->t2[q][j] = l2 * nf[q];
    }
  }
}

// One loop per law, compiled for AVX-512, AVX2 and the baseline (SIMD clones).
template <class Law>
MPMDEM_SIMD_CLONES void contact_loop(
    std::size_t m, const LawConstants& kc, const StagedContacts* __restrict st,
    double* __restrict nx, double* __restrict ny, double* __restrict nz, double* __restrict sx,
    double* __restrict sy, double* __restrict sz, double* __restrict pen_out,
    const double* __restrict x0, const double* __restrict x1, const double* __restrict x2,
    const double* __restrict v0, const double* __restrict v1, const double* __restrict v2,
    const double* __restrict w0, const double* __restrict w1_, const double* __restrict w2_,
    const double* __restrict rad, const double* __restrict mass, double* __restrict visc_out,
    ContactOut* __restrict out) {
  contact_body<Law>(m, kc, st, nx, ny, nz, sx, sy, sz, pen_out, x0, x1, x2, v0, v1, v2, w0, w1_,
                    w2_, rad, mass, visc_out, out);
}

}  // namespace

namespace {

MPMDEM_SIMD_CLONES void stage(std::size_t m, const std::uint32_t* __restrict id1,
                              const std::uint32_t* __restrict id2,
                              const std::int16_t* __restrict c0, const std::int16_t* __restrict c1,
                              const std::int16_t* __restrict c2, StagedContacts* __restrict st) {
  for (std::size_t j = 0; j < m; ++j) {
    st->a[j] = id1[j];
    st->b[j] = id2[j];
    st->c[0][j] = c0[j], st->c[1][j] = c1[j], st->c[2][j] = c2[j];
  }
}

}  // namespace

void stage_contacts(const RveState& s, std::size_t k0, std::size_t m, StagedContacts& st) {
  const auto& c = s.contacts;
  stage(m, c.id1.data() + k0, c.id2.data() + k0, c.cell.c[0].data() + k0, c.cell.c[1].data() + k0,
        c.cell.c[2].data() + k0, &st);
}

LawConstants law_constants(const RveState& s) {
  LawConstants k;
  k.dt = s.dt;
  k.half_dt = s.dt * 0.5;
  k.young = s.material.young;
  k.ks_kn = s.material.ks_kn;
  const double tan_phi = std::tan(s.material.friction_angle);
  k.tan2 = tan_phi * tan_phi;
  k.beta_n = s.law.viscous() ? s.law.beta_n : 0.0;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      k.h[a][b] = s.cell.hsize(a, b);
      k.lh[a][b] = s.cell.vgrad_times_prev_h(a, b);
    }
  }
  return k;
}

void update_contacts(RveState& s, const LawConstants& k, std::size_t k0, std::size_t m,
                     ContactOut& out, const double* rec) {
  if (m == 0) return;
  if (rec) {
    update_contacts_records(s, k, k0, m, rec, out);
    return;
  }
  auto& c = s.contacts;
  auto& sp = s.spheres;
  StagedContacts st;
  stage_contacts(s, k0, m, st);
  visit_law(s.law.kind, [&](auto law) {
    using Law = decltype(law);
    contact_loop<Law>(
        m, k, &st, c.normal.c[0].data() + k0, c.normal.c[1].data() + k0, c.normal.c[2].data() + k0,
        c.shear_force.c[0].data() + k0, c.shear_force.c[1].data() + k0,
        c.shear_force.c[2].data() + k0, c.penetration.data() + k0, sp.pos.c[0].data(),
        sp.pos.c[1].data(), sp.pos.c[2].data(), sp.vel.c[0].data(), sp.vel.c[1].data(),
        sp.vel.c[2].data(), sp.ang_vel.c[0].data(), sp.ang_vel.c[1].data(), sp.ang_vel.c[2].data(),
        sp.radius.data(), Law::kViscous ? sp.mass.data() : nullptr,
        Law::kViscous ? c.normal_viscous.data() + k0 : nullptr, &out);
  });
}

}  // namespace mpmdem::dem::native

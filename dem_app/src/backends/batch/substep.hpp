// One DEM step of one batch RVE (host and device; see rve_step.hpp for Ctx), in the native
// backend's order (native/integrator.cpp): cell move, Verlet check, existing contacts
// updated, new overlaps of the Verlet pairs (in row order) added and updated, the forces of
// the contacts added to each sphere in contact order (old contacts, then the new ones: the
// native scatter's additions, in its order), opened contacts removed keeping the order, new
// ones moved back into place by first sphere (Contacts::sift_back), then Newton.
#pragma once

#include "backends/batch/contact_physics.hpp"
#include "backends/batch/sphere_physics.hpp"
#include "backends/batch/verlet_pairs.hpp"

namespace mpmdem::dem::batch {

MPMDEM_HD_INLINE Law law_of(const BatchView& v, int r) {
  const double* cb = v.cell + static_cast<std::int64_t>(r) * kCellDoubles;
  Law k;
  k.dt = v.dt[r];
  k.half_dt = v.dt[r] * 0.5;
  k.young = v.young[r];
  k.ks_kn = v.ks_kn[r];
  k.tan2 = v.tan2[r];
  k.beta_n = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      k.h[a][b] = cb[kHsize + 3 * a + b];
      k.lh[a][b] = cb[kLh + 3 * a + b];
    }
  return k;
}

// Moves contact slot `from` to `to` (both absolute).
MPMDEM_HD_INLINE void move_contact(const BatchView& v, std::int64_t from, std::int64_t to) {
  v.id1[to] = v.id1[from];
  v.id2[to] = v.id2[from];
  for (int a = 0; a < 3; ++a) {
    v.ccell[a][to] = v.ccell[a][from];
    v.normal[a][to] = v.normal[a][from];
    v.shear[a][to] = v.shear[a][from];
  }
  v.pen[to] = v.pen[from];
  v.pair_of[to] = v.pair_of[from];
}
MPMDEM_HD_INLINE void swap_contacts(const BatchView& v, std::int64_t x, std::int64_t y) {
  const auto sw = [](auto& a, auto& b) {
    const auto t = a;
    a = b, b = t;
  };
  sw(v.id1[x], v.id1[y]);
  sw(v.id2[x], v.id2[y]);
  for (int a = 0; a < 3; ++a) {
    sw(v.ccell[a][x], v.ccell[a][y]);
    sw(v.normal[a][x], v.normal[a][y]);
    sw(v.shear[a][x], v.shear[a][y]);
  }
  sw(v.pen[x], v.pen[y]);
  sw(v.pair_of[x], v.pair_of[y]);
}

// Forces and torques of the spheres from the contacts [0, m) that did not open, each
// sphere's in contact order (an incidence list per sphere, sorted).
template <class Ctx>
MPMDEM_HD void gather_forces(const BatchView& v, int r, std::int64_t m, Ctx& ctx) {
  const std::int64_t s0 = v.sph0[r], n = v.sph0[r + 1] - s0, c0 = v.con0[r];
  std::int32_t* start = v.inc_start + s0 + r;  // n + 1
  std::int32_t* fill = v.inc_fill + s0;
  std::int32_t* inc = v.inc + 2 * c0;
  for (std::int64_t i = ctx.tid(); i <= n; i += ctx.nt()) start[i] = 0;
  for (std::int64_t i = ctx.tid(); i < n; i += ctx.nt()) fill[i] = 0;
  ctx.sync();
  for (std::int64_t k = ctx.tid(); k < m; k += ctx.nt()) {
    if (v.pen[c0 + k] < 0) continue;
    ctx.atomic_add(&start[v.id1[c0 + k] + 1], 1);
    ctx.atomic_add(&start[v.id2[c0 + k] + 1], 1);
  }
  ctx.sync();
  if (ctx.tid() == 0) {
    for (std::int64_t i = 0; i < n; ++i) start[i + 1] += start[i];
  }
  ctx.sync();
  for (std::int64_t k = ctx.tid(); k < m; k += ctx.nt()) {
    if (v.pen[c0 + k] < 0) continue;
    const std::uint32_t a = v.id1[c0 + k], b = v.id2[c0 + k];
    inc[start[a] + ctx.atomic_add(&fill[a], 1)] = static_cast<std::int32_t>(2 * k);
    inc[start[b] + ctx.atomic_add(&fill[b], 1)] = static_cast<std::int32_t>(2 * k + 1);
  }
  ctx.sync();
  for (std::int64_t i = ctx.tid(); i < n; i += ctx.nt()) {
    const std::int32_t lo = start[i], hi = start[i + 1];
    for (std::int32_t e = lo + 1; e < hi; ++e) {  // insertion sort: a handful per sphere
      const std::int32_t x = inc[e];
      std::int32_t q = e;
      for (; q > lo && inc[q - 1] > x; --q) inc[q] = inc[q - 1];
      inc[q] = x;
    }
    double f[3] = {0, 0, 0}, t[3] = {0, 0, 0};
    for (std::int32_t e = lo; e < hi; ++e) {
      const std::int64_t c = c0 + (inc[e] >> 1);
      if ((inc[e] & 1) == 0) {
        for (int a = 0; a < 3; ++a) f[a] += v.of[a][c], t[a] += v.ot1[a][c];
      } else {
        for (int a = 0; a < 3; ++a) f[a] -= v.of[a][c], t[a] += v.ot2[a][c];
      }
    }
    for (int a = 0; a < 3; ++a) v.force[a][s0 + i] = f[a], v.torque[a][s0 + i] = t[a];
  }
  ctx.sync();
}

// One DEM step of RVE r (after the burst's gradient for it is set). Returns a BatchError.
template <class Ctx>
MPMDEM_HD std::int32_t substep(const BatchView& v, const BatchParams& bp, int r, Ctx& ctx) {
  const std::int64_t s0 = v.sph0[r], n = v.sph0[r + 1] - s0, c0 = v.con0[r];
  const std::int64_t ccap = v.con0[r + 1] - c0, p0 = v.pair0[r];
  double* cb = v.cell + static_cast<std::int64_t>(r) * kCellDoubles;
  std::int32_t* fl = v.flags + r * kRveFlags;
  const bool t0 = ctx.tid() == 0;
  if (t0) integrate_and_update(cb, v.dt[r]);
  ctx.sync();
  if (list_stale(v, r, ctx)) {
    if (!build_pairs(v, bp, r, ctx)) return kErrPairs;
    if (t0) ++v.out[r].rebuilds;
  }
  // Existing contacts; an opened one frees its pair.
  const Law law = law_of(v, r);
  const std::int64_t nc = v.n_con[r];
  int opened = 0;
  for (std::int64_t k = ctx.tid(); k < nc; k += ctx.nt()) {
    update_contact(v, law, s0, c0 + k);
    if (v.pen[c0 + k] < 0) {
      opened = 1;
      if (v.pair_of[c0 + k] >= 0) v.in_contact[p0 + v.pair_of[c0 + k]] = 0;
    }
  }
  opened = ctx.max_all(opened) > 0 ? 1 : 0;
  // New contacts: the listed pairs without a contact that overlap, in row order.
  const std::int64_t np = v.n_pair[r];
  const std::int64_t chunk = (np + ctx.nt() - 1) / ctx.nt();
  const std::int64_t lo = hd_min_i64(np, ctx.tid() * chunk), hi = hd_min_i64(np, lo + chunk);
  int mine = 0;
  for (std::int64_t p = lo; p < hi; ++p) {
    mine += !v.in_contact[p0 + p] && pair_overlaps(v, cb + kHsize, s0, p0 + p);
  }
  int added = 0;
  std::int64_t slot = c0 + nc + ctx.scan(mine, &added);
  if (nc + added > ccap) return kErrContacts;
  for (std::int64_t p = lo; p < hi && mine > 0; ++p) {
    if (v.in_contact[p0 + p] || !pair_overlaps(v, cb + kHsize, s0, p0 + p)) continue;
    v.id1[slot] = v.pi[p0 + p];
    v.id2[slot] = v.pj[p0 + p];
    for (int a = 0; a < 3; ++a) {
      v.ccell[a][slot] = v.pc[a][p0 + p];
      v.normal[a][slot] = 0;
      v.shear[a][slot] = 0;
    }
    v.pen[slot] = 0;
    v.pair_of[slot] = static_cast<std::int32_t>(p);
    ++slot;
  }
  ctx.sync();
  for (std::int64_t k = nc + ctx.tid(); k < nc + added; k += ctx.nt()) {
    update_contact(v, law, s0, c0 + k);
    if (v.pen[c0 + k] >= 0) v.in_contact[p0 + v.pair_of[c0 + k]] = 1;
  }
  ctx.sync();
  gather_forces(v, r, nc + added, ctx);
  // Opened contacts out (order kept), new ones sifted back by first sphere (one thread).
  if (t0 && (opened || added > 0)) {
    std::int64_t kept = 0, old_kept = 0;
    for (std::int64_t k = 0; k < nc + added; ++k) {
      if (v.pen[c0 + k] < 0) continue;
      if (kept != k) move_contact(v, c0 + k, c0 + kept);
      ++kept;
      if (k < nc) old_kept = kept;
    }
    for (std::int64_t q = old_kept; q < kept; ++q) {
      const std::uint32_t a = v.id1[c0 + q];
      for (std::int64_t pos = q; pos > 0 && v.id1[c0 + pos - 1] > a; --pos) {
        swap_contacts(v, c0 + pos - 1, c0 + pos);
      }
    }
    v.n_con[r] = static_cast<std::int32_t>(kept);
  }
  if (t0) activate_next(cb, fl);
  ctx.sync();
  // Newton.
  NewtonConstants k;
  k.dt = v.dt[r];
  k.half_dt = 0.5 * k.dt;
  k.quarter_dt2 = 0.25 * k.dt * k.dt;
  k.damping = bp.damping;
  k.prev = cell_get(cb, kPrevVelGrad);
  k.dvg = sub(cell_get(cb, kVelGrad), k.prev);
  k.dvg_step = !is_zero(k.dvg);
  k.dspin[0] = -(0.5 * (k.dvg(1, 2) - k.dvg(2, 1)));
  k.dspin[1] = 0.5 * (k.dvg(0, 2) - k.dvg(2, 0));
  k.dspin[2] = -(0.5 * (k.dvg(0, 1) - k.dvg(1, 0)));
  for (std::int64_t i = ctx.tid(); i < n; i += ctx.nt()) advance_sphere(v, k, s0 + i);
  ctx.sync();
  if (t0) {
    cell_set(cb, kPrevVelGrad, cell_get(cb, kVelGrad));
    ++v.iter[r];
  }
  ctx.sync();
  return kErrNone;
}

}  // namespace mpmdem::dem::batch

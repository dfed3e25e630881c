// The Verlet pairs of a batch RVE (host and device, MPMDEM_HD, parallel over a thread group
// Ctx: rve_step.hpp): every pair (i < j, image c) within r_i + r_j + skin at the build, in the
// canonical order i, then j, then c lexicographic: the row order of native::NeighbourList, so
// the new contacts that overlap in a step are found in the native backend's order (the set is
// the same whatever the build times: every overlapping pair is listed). Rebuilt when
// 2 max_i |x_i - A x_ref,i| + |A - I|_F (2 r_max + skin) reaches the skin (A = H H_ref^-1, the
// native criterion without its single-precision references).
#pragma once

#include <cmath>

#include "backends/batch/batch_layout.hpp"
#include "backends/batch/cell_physics.hpp"

namespace mpmdem::dem::batch {

MPMDEM_HD_INLINE bool cell_less(const std::int16_t* a, const std::int16_t* b) {
  for (int q = 0; q < 3; ++q) {
    if (a[q] != b[q]) return a[q] < b[q];
  }
  return false;
}

// Pairs of sphere i with the spheres after it: counted (write false) or written from slot p.
MPMDEM_HD_INLINE int row_pairs(const BatchView& v, std::int64_t s0, std::int64_t n, std::int64_t i,
                               const M3& h, const M3& hinv, bool thick, double skin, bool write,
                               std::int64_t p, std::int64_t p_end) {
  int count = 0;
  for (std::int64_t j = i + 1; j < n; ++j) {
    double d[3], f[3];
    for (int a = 0; a < 3; ++a) d[a] = v.pos[a][s0 + j] - v.pos[a][s0 + i];
    mul_vec(hinv, d, f);
    int c0[3];
    for (int a = 0; a < 3; ++a) c0[a] = -static_cast<int>(llround(f[a]));
    const double cut = v.radius[s0 + i] + v.radius[s0 + j] + skin;
    for (int s = 0; s < 27; ++s) {
      const int st[3] = {s / 9 - 1, (s / 3) % 3 - 1, s % 3 - 1};
      if (thick && (st[0] != 0 || st[1] != 0 || st[2] != 0)) continue;
      const double c[3] = {static_cast<double>(c0[0] + st[0]), static_cast<double>(c0[1] + st[1]),
                           static_cast<double>(c0[2] + st[2])};
      double sh[3];
      mul_vec(h, c, sh);
      const double e0 = d[0] + sh[0], e1 = d[1] + sh[1], e2 = d[2] + sh[2];
      if (e0 * e0 + e1 * e1 + e2 * e2 >= cut * cut) continue;
      if (write && p + count < p_end) {
        const std::int64_t q = p + count;
        v.pi[q] = static_cast<std::uint32_t>(i);
        v.pj[q] = static_cast<std::uint32_t>(j);
        for (int a = 0; a < 3; ++a) v.pc[a][q] = static_cast<std::int16_t>(c0[a] + st[a]);
        v.in_contact[q] = 0;
      }
      ++count;
    }
  }
  return count;
}

// The pair slot of contact (a, b, c) (or (b, a, -c)) among the RVE's np pairs from p0, by
// binary search in the canonical order; -1 if not listed.
MPMDEM_HD_INLINE std::int64_t find_pair(const BatchView& v, std::int64_t p0, std::int64_t np,
                                        std::uint32_t a, std::uint32_t b, const std::int16_t* c) {
  std::int16_t cc[3] = {c[0], c[1], c[2]};
  if (a > b) {
    const std::uint32_t t = a;
    a = b, b = t;
    for (auto& x : cc) x = static_cast<std::int16_t>(-x);
  }
  std::int64_t lo = 0, hi = np;
  while (lo < hi) {  // first pair not less than (a, b, cc)
    const std::int64_t mid = (lo + hi) / 2, q = p0 + mid;
    const std::int16_t pcq[3] = {v.pc[0][q], v.pc[1][q], v.pc[2][q]};
    const bool less = v.pi[q] != a ? v.pi[q] < a : v.pj[q] != b ? v.pj[q] < b : cell_less(pcq, cc);
    if (less) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  if (lo == np) return -1;
  const std::int64_t q = p0 + lo;
  const bool same = v.pi[q] == a && v.pj[q] == b && v.pc[0][q] == cc[0] && v.pc[1][q] == cc[1] &&
                    v.pc[2][q] == cc[2];
  return same ? q : -1;
}

// Rebuilds the list of RVE r (all threads of ctx call it); false: more pairs than its capacity.
template <class Ctx>
MPMDEM_HD bool build_pairs(const BatchView& v, const BatchParams& bp, int r, Ctx& ctx) {
  const std::int64_t s0 = v.sph0[r], n = v.sph0[r + 1] - s0;
  const std::int64_t p0 = v.pair0[r], pcap = v.pair0[r + 1] - p0, c0 = v.con0[r];
  double* cb = v.cell + static_cast<std::int64_t>(r) * kCellDoubles;
  double rmin = 1e300, rmax = 0;
  for (std::int64_t i = ctx.tid(); i < n; i += ctx.nt()) {
    rmin = hd_min(rmin, v.radius[s0 + i]);
    rmax = hd_max(rmax, v.radius[s0 + i]);
  }
  rmin = -ctx.max_all(-rmin);
  rmax = ctx.max_all(rmax);
  const double skin = bp.skin_factor * rmin;
  const double max_cut = 2 * rmax + skin;
  const M3 h = cell_get(cb, kHsize);
  const M3 hinv = inverse(h);
  double ht[3];
  heights(h, ht);
  const double thick_cut = 2 * max_cut * (1 + 1e-6);
  const bool thick = ht[0] >= thick_cut && ht[1] >= thick_cut && ht[2] >= thick_cut;
  for (std::int64_t i = ctx.tid(); i < n; i += ctx.nt()) {
    for (int a = 0; a < 3; ++a) v.x_ref[a][s0 + i] = v.pos[a][s0 + i];
  }
  // Rows in contiguous chunks per thread: counted, offsets by a scan, written in order.
  const std::int64_t chunk = (n + ctx.nt() - 1) / ctx.nt();
  const std::int64_t lo = hd_min_i64(n, ctx.tid() * chunk), hi = hd_min_i64(n, lo + chunk);
  int mine = 0;
  for (std::int64_t i = lo; i < hi; ++i)
    mine += row_pairs(v, s0, n, i, h, hinv, thick, skin, false, 0, 0);
  int total = 0;
  std::int64_t p = p0 + ctx.scan(mine, &total);
  if (total <= pcap) {
    for (std::int64_t i = lo; i < hi; ++i) {
      p += row_pairs(v, s0, n, i, h, hinv, thick, skin, true, p, p0 + pcap);
    }
  }
  ctx.sync();
  if (total > pcap) return false;
  // The pairs of the existing contacts are flagged.
  const std::int64_t nc = v.n_con[r];
  for (std::int64_t k = ctx.tid(); k < nc; k += ctx.nt()) {
    const std::int64_t c = c0 + k;
    const std::int16_t cc[3] = {v.ccell[0][c], v.ccell[1][c], v.ccell[2][c]};
    const std::int64_t q = find_pair(v, p0, total, v.id1[c], v.id2[c], cc);
    v.pair_of[c] = static_cast<std::int32_t>(q < 0 ? -1 : q - p0);
    if (q >= 0) v.in_contact[q] = 1;
  }
  if (ctx.tid() == 0) {
    v.n_pair[r] = total;
    v.skin[r] = skin;
    v.max_cut[r] = max_cut;
    cell_set(cb, kHrefInv, hinv);
    v.flags[r * kRveFlags + kListValid] = 1;
  }
  ctx.sync();
  return true;
}

// Whether the list of RVE r must be rebuilt before this step's contacts (all threads).
template <class Ctx>
MPMDEM_HD bool list_stale(const BatchView& v, int r, Ctx& ctx) {
  if (!v.flags[r * kRveFlags + kListValid]) return true;
  const std::int64_t s0 = v.sph0[r], n = v.sph0[r + 1] - s0;
  const double* cb = v.cell + static_cast<std::int64_t>(r) * kCellDoubles;
  const M3 a = mul(cell_get(cb, kHsize), cell_get(cb, kHrefInv));
  double m = 0;
  for (std::int64_t i = ctx.tid(); i < n; i += ctx.nt()) {
    const double xr[3] = {v.x_ref[0][s0 + i], v.x_ref[1][s0 + i], v.x_ref[2][s0 + i]};
    double ax[3];
    mul_vec(a, xr, ax);
    double e2 = 0;
    for (int q = 0; q < 3; ++q) {
      const double e = v.pos[q][s0 + i] - ax[q];
      e2 += e * e;
    }
    m = e2 == e2 ? hd_max(m, e2) : m;
  }
  m = ctx.max_all(m);
  double strain2 = 0;
  for (int q = 0; q < 9; ++q) {
    const double e = a.a[q] - (q % 4 == 0 ? 1.0 : 0.0);
    strain2 += e * e;
  }
  const double motion = 2 * sqrt(m) + sqrt(strain2) * v.max_cut[r];
  return !(motion < v.skin[r] * (1 - 1e-6));  // a margin for the rounding of the bound
}

}  // namespace mpmdem::dem::batch

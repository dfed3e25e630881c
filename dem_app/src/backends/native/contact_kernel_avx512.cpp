// The contact update written for AVX-512 (contact_kernel.hpp, update_contacts with sphere
// records): the arithmetic of contact_kernel.cpp's contact_loop operation for operation (the
// same bits: no contraction, -ffp-contract=off; GCC's vector extensions keep the expressions
// as they are written there), 8 contacts per iteration, the last ones masked. What differs
// is how the spheres' fields reach the registers: instead of 20 gathers per 8 contacts, each
// sphere's position, radius, velocity and angular velocity are read from a packed record
// of 12 doubles (three 32-byte rows: x y z r | vx vy vz m | wx wy wz 0, built at the start of
// compute_forces by pack_sphere_records; m the mass for the frict_visco law, else 0) and 8 rows are
// transposed into 4 vectors (on this AMD CPU ~3x cheaper than the gathers). The stress and
// stiffness terms of measures.cpp go the same way (stress_terms_records: its contributions and
// add_to_lanes, the same bits).
#include <immintrin.h>

#include <cstdint>
#include <cstdlib>
#include <vector>

#include "backends/native/contact_kernel.hpp"
#include "backends/native/simd_clones.hpp"

namespace mpmdem::dem::native {

#ifdef MPMDEM_AVX512_KERNEL

// GCC 12's unpack and extract intrinsics start from _mm512_undefined_pd(), which it then
// reports as maybe uninitialised (a known false positive of these headers).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

namespace {

constexpr std::size_t kRec = 12;  // doubles per sphere record

typedef double v8d __attribute__((vector_size(64)));

// Rows p[0..7] (4 doubles each) into 4 vectors: o_f[l] = p[l][f].
#define MPMDEM_AVX512 __attribute__((target("avx512f,avx2")))
MPMDEM_AVX512 inline void load_rows(const double* const* p, v8d& o0, v8d& o1, v8d& o2, v8d& o3) {
  const __m512d z0 =
      _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(p[0])), _mm256_load_pd(p[4]), 1);
  const __m512d z1 =
      _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(p[1])), _mm256_load_pd(p[5]), 1);
  const __m512d z2 =
      _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(p[2])), _mm256_load_pd(p[6]), 1);
  const __m512d z3 =
      _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(p[3])), _mm256_load_pd(p[7]), 1);
  const __m512d a = _mm512_unpacklo_pd(z0, z1), b = _mm512_unpackhi_pd(z0, z1);  // x z, y r
  const __m512d c = _mm512_unpacklo_pd(z2, z3), d = _mm512_unpackhi_pd(z2, z3);
  const __m512i lo = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13);
  const __m512i hi = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
  o0 = (v8d)_mm512_permutex2var_pd(a, lo, c);
  o1 = (v8d)_mm512_permutex2var_pd(b, lo, d);
  o2 = (v8d)_mm512_permutex2var_pd(a, hi, c);
  o3 = (v8d)_mm512_permutex2var_pd(b, hi, d);
}

// The inverse: 4 vectors of 8 spheres into row f of their records (rec + kRec i + f).
MPMDEM_AVX512 inline void store_rows(double* rec, __m512d x, __m512d y, __m512d z, __m512d r) {
  const __m512d a = _mm512_unpacklo_pd(x, y), b = _mm512_unpackhi_pd(x, y);  // x0 y0 x2 y2..
  const __m512d c = _mm512_unpacklo_pd(z, r), d = _mm512_unpackhi_pd(z, r);
  const __m512i lo = _mm512_setr_epi64(0, 1, 8, 9, 2, 3, 10, 11);
  const __m512i hi = _mm512_setr_epi64(4, 5, 12, 13, 6, 7, 14, 15);
  const __m512d s02 = _mm512_permutex2var_pd(a, lo, c), s46 = _mm512_permutex2var_pd(a, hi, c);
  const __m512d s13 = _mm512_permutex2var_pd(b, lo, d), s57 = _mm512_permutex2var_pd(b, hi, d);
  _mm256_store_pd(rec, _mm512_castpd512_pd256(s02));
  _mm256_store_pd(rec + kRec, _mm512_castpd512_pd256(s13));
  _mm256_store_pd(rec + 2 * kRec, _mm512_extractf64x4_pd(s02, 1));
  _mm256_store_pd(rec + 3 * kRec, _mm512_extractf64x4_pd(s13, 1));
  _mm256_store_pd(rec + 4 * kRec, _mm512_castpd512_pd256(s46));
  _mm256_store_pd(rec + 5 * kRec, _mm512_castpd512_pd256(s57));
  _mm256_store_pd(rec + 6 * kRec, _mm512_extractf64x4_pd(s46, 1));
  _mm256_store_pd(rec + 7 * kRec, _mm512_extractf64x4_pd(s57, 1));
}

// (__builtin_cpu_init: this may run before libgcc's own initialisation)
const bool kHaveAvx512 = (__builtin_cpu_init(), __builtin_cpu_supports("avx512f"));

// The records of n spheres: per thread, not per RVE; 32-byte aligned rows.
double* sphere_buffer(std::size_t n) {
  thread_local std::vector<double> buf;
  buf.resize(kRec * n + 4);
  double* rec = buf.data();
  return rec + (4 - (reinterpret_cast<std::uintptr_t>(rec) / sizeof(double)) % 4) % 4;
}

// all_rows false: the first row (position, radius) only; with_mass: the masses in the second
// row's last slot (else 0).
MPMDEM_AVX512 void pack(std::size_t n, const Spheres& sp, double* __restrict rec, bool all_rows,
                        bool with_mass = false) {
  const double* x[3] = {sp.pos.c[0].data(), sp.pos.c[1].data(), sp.pos.c[2].data()};
  const double* v[3] = {sp.vel.c[0].data(), sp.vel.c[1].data(), sp.vel.c[2].data()};
  const double* w[3] = {sp.ang_vel.c[0].data(), sp.ang_vel.c[1].data(), sp.ang_vel.c[2].data()};
  const double* rad = sp.radius.data();
  const double* mass = sp.mass.data();
  std::size_t i = 0;
  const __m512d zero = _mm512_setzero_pd();
  for (; i + 8 <= n; i += 8) {
    double* r = rec + kRec * i;
    store_rows(r, _mm512_loadu_pd(x[0] + i), _mm512_loadu_pd(x[1] + i), _mm512_loadu_pd(x[2] + i),
               _mm512_loadu_pd(rad + i));
    if (!all_rows) continue;
    store_rows(r + 4, _mm512_loadu_pd(v[0] + i), _mm512_loadu_pd(v[1] + i),
               _mm512_loadu_pd(v[2] + i), with_mass ? _mm512_loadu_pd(mass + i) : zero);
    store_rows(r + 8, _mm512_loadu_pd(w[0] + i), _mm512_loadu_pd(w[1] + i),
               _mm512_loadu_pd(w[2] + i), zero);
  }
  for (; i < n; ++i) {
    double* r = rec + kRec * i;
    for (int q = 0; q < 3; ++q) r[q] = x[q][i];
    r[3] = rad[i];
    if (!all_rows) continue;
    for (int q = 0; q < 3; ++q) r[4 + q] = v[q][i], r[8 + q] = w[q][i];
    r[7] = with_mass ? mass[i] : 0, r[11] = 0;
  }
}

MPMDEM_AVX512 inline v8d vsqrt(v8d x) {
  return (v8d)_mm512_sqrt_pd((__m512d)x);
}

}  // namespace
}  // namespace mpmdem::dem::native

// The contact laws' arithmetic on 8 lanes (backends/contact_laws/law_math.hpp): the laws' templates
// compiled for v8d are inlined into the loops below, which have AVX-512.
template <>
struct mpmdem::dem::laws::LawMath<mpmdem::dem::native::v8d> {
  using v8d = mpmdem::dem::native::v8d;
  MPMDEM_AVX512 static inline void sqrt(const v8d& x, v8d& out) { out = native::vsqrt(x); }
  // LawMath<double>::cap, the same bits: the ratio is below 1 or exactly 1 where
  // fs2 > max_fs, and not below 1 elsewhere (NaN included), so the cap is the same when it
  // uses the ratio only there; it is computed only if a contact of the 8 slides.
  MPMDEM_AVX512 static inline void cap(v8d (&fs)[3], const v8d& max_fs, const v8d& fs2) {
    const __mmask8 slide = _mm512_cmp_pd_mask((__m512d)fs2, (__m512d)max_fs, _CMP_GT_OQ);
    if (slide) {
      const v8d zero = {0, 0, 0, 0, 0, 0, 0, 0}, one = zero + 1.0;
      const v8d ratio = native::vsqrt(max_fs) / native::vsqrt(fs2);
      const v8d scale = (v8d)_mm512_mask_blend_pd(slide, (__m512d)one, (__m512d)ratio);
      for (int q = 0; q < 3; ++q) fs[q] *= scale;
    }
  }
};

namespace mpmdem::dem::native {
namespace {

// The chunk of contacts [j, j + 8) of [0, m): the record pointers of both spheres and the
// image offsets as doubles; lanes past the end repeat the last contact. Returns the mask of
// the lanes inside [0, m).
MPMDEM_AVX512 inline __attribute__((always_inline)) __mmask8 chunk(
    std::size_t j, std::size_t m, const double* __restrict rec, const std::uint32_t* __restrict id1,
    const std::uint32_t* __restrict id2, const std::int16_t* const* cell, const double* (&pa)[8],
    const double* (&pb)[8], v8d (&ci)[3]) {
  const std::size_t left = m - j;
  if (left >= 8) {
    for (std::size_t l = 0; l < 8; ++l) pa[l] = rec + kRec * id1[j + l];
    for (std::size_t l = 0; l < 8; ++l) pb[l] = rec + kRec * id2[j + l];
    for (int q = 0; q < 3; ++q) {
      const __m128i c16 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cell[q] + j));
      ci[q] = (v8d)_mm512_cvtepi32_pd(_mm256_cvtepi16_epi32(c16));
    }
    return __mmask8(0xff);
  }
  double cd[3][8];
  for (std::size_t l = 0; l < 8; ++l) {
    const std::size_t jj = j + (l < left ? l : left - 1);
    pa[l] = rec + kRec * id1[jj];
    pb[l] = rec + kRec * id2[jj];
    for (int q = 0; q < 3; ++q) cd[q][l] = cell[q][jj];
  }
  for (int q = 0; q < 3; ++q) ci[q] = (v8d)_mm512_loadu_pd(cd[q]);
  return __mmask8((1u << left) - 1);
}

// Contacts [0, m) of the arrays (offset to the chunk by the caller); see contact_loop.
// Law: the RVE's contact law (contact_body<Law>); a viscous one reads the masses from the
// records and writes the viscous part of its normal force to visc_out; otherwise visc_out is
// unused (nullptr).
template <class Law>
MPMDEM_AVX512 void loop(std::size_t m, const LawConstants& kc, const double* __restrict rec,
                        const std::uint32_t* __restrict id1, const std::uint32_t* __restrict id2,
                        const std::int16_t* const* cell, double* const* nrm, double* const* shr,
                        double* __restrict pen_out, double* __restrict visc_out,
                        ContactOut* __restrict out) {
  const LawConstants k = kc;
  for (std::size_t j = 0; j < m; j += 8) {
    const double* pa[8];
    const double* pb[8];
    v8d ci[3];
    const __mmask8 mask = chunk(j, m, rec, id1, id2, cell, pa, pb, ci);
    v8d xa[3], xb[3], va[3], vb[3], w1[3], w2[3], r1, r2, m1, m2, unused;
    load_rows(pa, xa[0], xa[1], xa[2], r1);
    load_rows(pb, xb[0], xb[1], xb[2], r2);
    const double* qa[8];
    const double* qb[8];
    for (int l = 0; l < 8; ++l) qa[l] = pa[l] + 4, qb[l] = pb[l] + 4;
    load_rows(qa, va[0], va[1], va[2], m1);
    load_rows(qb, vb[0], vb[1], vb[2], m2);
    for (int l = 0; l < 8; ++l) qa[l] = pa[l] + 8, qb[l] = pb[l] + 8;
    load_rows(qa, w1[0], w1[1], w1[2], unused);
    load_rows(qb, w2[0], w2[1], w2[2], unused);
    v8d d[3], sv[3];
    for (int q = 0; q < 3; ++q) {
      const v8d shift = k.h[q][0] * ci[0] + k.h[q][1] * ci[1] + k.h[q][2] * ci[2];
      sv[q] = k.lh[q][0] * ci[0] + k.lh[q][1] * ci[1] + k.lh[q][2] * ci[2];
      d[q] = (xb[q] + shift) - xa[q];
    }
    const v8d dist = vsqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const v8d inv_dist = 1.0 / dist;
    const v8d n[3] = {d[0] * inv_dist, d[1] * inv_dist, d[2] * inv_dist};
    const v8d rs = r1 + r2;
    const v8d pen = rs - dist;
    v8d p[3];
    for (int q = 0; q < 3; ++q) p[q] = (v8d)_mm512_maskz_loadu_pd(mask, nrm[q] + j);
    const v8d ax[3] = {p[1] * n[2] - p[2] * n[1], p[2] * n[0] - p[0] * n[2],
                       p[0] * n[1] - p[1] * n[0]};
    const v8d angle =
        k.half_dt * (p[0] * (w1[0] + w2[0]) + p[1] * (w1[1] + w2[1]) + p[2] * (w1[2] + w2[2]));
    const v8d tw[3] = {angle * p[0], angle * p[1], angle * p[2]};
    const v8d alpha = rs * inv_dist;
    v8d u[3], rel[3];
    for (int q = 0; q < 3; ++q) u[q] = r1 * w1[q] + r2 * w2[q];
    const v8d uxn[3] = {u[1] * n[2] - u[2] * n[1], u[2] * n[0] - u[0] * n[2],
                        u[0] * n[1] - u[1] * n[0]};
    for (int q = 0; q < 3; ++q) rel[q] = (vb[q] - va[q] + sv[q]) * alpha - uxn[q];
    const v8d rn = n[0] * rel[0] + n[1] * rel[1] + n[2] * rel[2];
    v8d inc[3];
    for (int q = 0; q < 3; ++q) inc[q] = (rel[q] - rn * n[q]) * k.dt;
    v8d kn, ks;
    Law::stiffness(k.young, k.ks_kn, r1, r2, kn, ks);
    v8d fs[3];
    for (int q = 0; q < 3; ++q) fs[q] = (v8d)_mm512_maskz_loadu_pd(mask, shr[q] + j);
    v8d t[3] = {fs[1] * ax[2] - fs[2] * ax[1], fs[2] * ax[0] - fs[0] * ax[2],
                fs[0] * ax[1] - fs[1] * ax[0]};
    for (int q = 0; q < 3; ++q) fs[q] -= t[q];
    t[0] = fs[1] * tw[2] - fs[2] * tw[1];
    t[1] = fs[2] * tw[0] - fs[0] * tw[2];
    t[2] = fs[0] * tw[1] - fs[1] * tw[0];
    for (int q = 0; q < 3; ++q) fs[q] -= t[q];
    Law::shear_increment(ks, inc, fs);
    v8d fn[3], visc = {};
    Law::normal_force(k, kn, pen, rn, m1, m2, n, fn, visc);
    if constexpr (Law::kViscous) _mm512_mask_storeu_pd(visc_out + j, mask, (__m512d)visc);
    Law::slide(k, fn, fs);
    const v8d f[3] = {-fn[0] - fs[0], -fn[1] - fs[1], -fn[2] - fs[2]};
    const v8d nf[3] = {n[1] * f[2] - n[2] * f[1], n[2] * f[0] - n[0] * f[2],
                       n[0] * f[1] - n[1] * f[0]};
    const v8d l1 = r1 - 0.5 * pen, l2 = r2 - 0.5 * pen;
    for (int q = 0; q < 3; ++q) {
      _mm512_mask_storeu_pd(nrm[q] + j, mask, (__m512d)n[q]);
      _mm512_mask_storeu_pd(shr[q] + j, mask, (__m512d)fs[q]);
      _mm512_mask_storeu_pd(out->f[q] + j, mask, (__m512d)f[q]);
      _mm512_mask_storeu_pd(out->t1[q] + j, mask, (__m512d)(l1 * nf[q]));
      _mm512_mask_storeu_pd(out->t2[q] + j, mask, (__m512d)(l2 * nf[q]));
    }
    _mm512_mask_storeu_pd(pen_out + j, mask, (__m512d)pen);
  }
}

// measures.cpp's contributions (the same expressions) of contacts [0, m), added to
// lanes[t][k mod 8] in contact order: for a group of 8 contacts, which starts at a multiple
// of 8, one vector addition per term (masked for the last group). Law: the RVE's contact law
// (a viscous one with the viscous part visc of the normal force, contributions_body<Law>).
template <class Law>
MPMDEM_AVX512 void stress_loop(std::size_t m, const double (&h)[3][3], double young, double ks_kn,
                               const double* __restrict rec, const std::uint32_t* __restrict id1,
                               const std::uint32_t* __restrict id2, const std::int16_t* const* cell,
                               const double* const* nrm, const double* const* shr,
                               const double* __restrict pen, const double* __restrict visc,
                               double (&lanes)[15][8]) {
  v8d acc[15];
  for (int t = 0; t < 15; ++t) acc[t] = (v8d)_mm512_loadu_pd(lanes[t]);
  const v8d zero = {};
  for (std::size_t j = 0; j < m; j += 8) {
    const double* pa[8];
    const double* pb[8];
    v8d ci[3];
    const __mmask8 mask = chunk(j, m, rec, id1, id2, cell, pa, pb, ci);
    v8d xa[3], xb[3], r1, r2, n[3], fs[3], l[3], term[15];
    load_rows(pa, xa[0], xa[1], xa[2], r1);
    load_rows(pb, xb[0], xb[1], xb[2], r2);
    for (int q = 0; q < 3; ++q) {
      n[q] = (v8d)_mm512_maskz_loadu_pd(mask, nrm[q] + j);
      fs[q] = (v8d)_mm512_maskz_loadu_pd(mask, shr[q] + j);
    }
    const v8d pn = (v8d)_mm512_maskz_loadu_pd(mask, pen + j);
    v8d vn = zero;
    if constexpr (Law::kViscous) vn = (v8d)_mm512_maskz_loadu_pd(mask, visc + j);
    for (int q = 0; q < 3; ++q) {
      l[q] = (xb[q] + (h[q][0] * ci[0] + h[q][1] * ci[1] + h[q][2] * ci[2])) - xa[q];
    }
    v8d kn, ks, fn[3];
    Law::stiffness(young, ks_kn, r1, r2, kn, ks);
    Law::stored_normal_force(kn, pn, vn, n, fn);
    for (int i = 0; i < 3; ++i) {
      const v8d f = fn[i] + fs[i];
      for (int q = 0; q < 3; ++q) term[3 * i + q] = f * -l[q];
    }
    const v8d l2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
    const v8d fs2 = fs[0] * fs[0] + fs[1] * fs[1] + fs[2] * fs[2];
    const v8d inv = 1.0 / fs2;
    const v8d inv_fs2 = fs2 > zero ? inv : zero;
    for (int i = 0; i < 3; ++i) {
      const v8d ni2 = n[i] * n[i];
      const v8d ti2 = fs[i] * fs[i] * inv_fs2;
      term[9 + i] = l2 * ni2 * (kn * ni2 + ks * ti2);
      term[12 + i] = kn * l2 * ni2;
    }
    for (int t = 0; t < 15; ++t) {
      acc[t] = (v8d)_mm512_mask_add_pd((__m512d)acc[t], mask, (__m512d)acc[t], (__m512d)term[t]);
    }
  }
  for (int t = 0; t < 15; ++t) _mm512_storeu_pd(lanes[t], (__m512d)acc[t]);
}

}  // namespace

bool stress_terms_records(const RveState& s, const double (&h)[3][3], double (&lanes)[15][8]) {
  if (!kHaveAvx512) return false;
  const auto& c = s.contacts;
  const double* rec = sphere_buffer(s.spheres.size());
  pack(s.spheres.size(), s.spheres, const_cast<double*>(rec), false);
  const std::int16_t* cell[3] = {c.cell.c[0].data(), c.cell.c[1].data(), c.cell.c[2].data()};
  const double* nrm[3] = {c.normal.c[0].data(), c.normal.c[1].data(), c.normal.c[2].data()};
  const double* shr[3] = {c.shear_force.c[0].data(), c.shear_force.c[1].data(),
                          c.shear_force.c[2].data()};
  visit_law(s.law.kind, [&](auto law) {
    using Law = decltype(law);
    stress_loop<Law>(c.size(), h, s.material.young, s.material.ks_kn, rec, c.id1.data(),
                     c.id2.data(), cell, nrm, shr, c.penetration.data(),
                     Law::kViscous ? c.normal_viscous.data() : nullptr, lanes);
  });
  return true;
}

const double* pack_sphere_records(const RveState& s) {
  if (!kHaveAvx512) return nullptr;
  double* rec = sphere_buffer(s.spheres.size());
  pack(s.spheres.size(), s.spheres, rec, true, s.law.viscous());
  return rec;
}

void update_contacts_records(RveState& s, const LawConstants& k, std::size_t k0, std::size_t m,
                             const double* rec, ContactOut& out) {
  auto& c = s.contacts;
  const std::int16_t* cell[3] = {c.cell.c[0].data() + k0, c.cell.c[1].data() + k0,
                                 c.cell.c[2].data() + k0};
  double* nrm[3] = {c.normal.c[0].data() + k0, c.normal.c[1].data() + k0,
                    c.normal.c[2].data() + k0};
  double* shr[3] = {c.shear_force.c[0].data() + k0, c.shear_force.c[1].data() + k0,
                    c.shear_force.c[2].data() + k0};
  visit_law(s.law.kind, [&](auto law) {
    using Law = decltype(law);
    loop<Law>(m, k, rec, c.id1.data() + k0, c.id2.data() + k0, cell, nrm, shr,
              c.penetration.data() + k0, Law::kViscous ? c.normal_viscous.data() + k0 : nullptr,
              &out);
  });
}

#pragma GCC diagnostic pop

#else

const double* pack_sphere_records(const RveState&) {
  return nullptr;
}
bool stress_terms_records(const RveState&, const double (&)[3][3], double (&)[15][8]) {
  return false;
}
void update_contacts_records(RveState&, const LawConstants&, std::size_t, std::size_t,
                             const double*, ContactOut&) {}

#endif

}  // namespace mpmdem::dem::native

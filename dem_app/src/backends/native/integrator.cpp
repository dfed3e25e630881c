// One DEM step in YADE's order: see integrator.hpp.
#include "backends/native/integrator.hpp"

#include <cmath>
#include <cstdlib>

#include <algorithm>
#include <vector>

#include "backends/native/contact_kernel.hpp"

namespace mpmdem::dem::native {

namespace {

// Adds the outputs of contacts [k0, k0 + m) to their spheres in contact order, skipping the
// contacts that opened; returns whether one did. The first sphere's force and torque stay in
// registers over a run of contacts with the same first sphere (the contacts are kept sorted by it:
// Contacts:: sift_back), loaded before the run and stored after it: the same additions in the same
// order as one sphere update per contact, with 12 loads and stores per contact fewer.
// restrict: the six sphere arrays do not alias.
bool scatter_arrays(std::size_t m, const std::uint32_t* __restrict id1,
                    const std::uint32_t* __restrict id2, const double* __restrict pen,
                    const ContactOut& __restrict out, double* __restrict f0, double* __restrict f1,
                    double* __restrict f2, double* __restrict t0, double* __restrict t1,
                    double* __restrict t2) {
  if (m == 0) return false;
  bool opened = false;
  std::uint32_t a = id1[0];
  double fa0 = f0[a], fa1 = f1[a], fa2 = f2[a], ta0 = t0[a], ta1 = t1[a], ta2 = t2[a];
  for (std::size_t j = 0; j < m; ++j) {
    if (id1[j] != a) {  // the next run: the previous sphere's sums stored, this one's loaded
      f0[a] = fa0, f1[a] = fa1, f2[a] = fa2, t0[a] = ta0, t1[a] = ta1, t2[a] = ta2;
      a = id1[j];
      fa0 = f0[a], fa1 = f1[a], fa2 = f2[a], ta0 = t0[a], ta1 = t1[a], ta2 = t2[a];
    }
    if (pen[j] < 0) {
      opened = true;
      continue;
    }
    const std::uint32_t b = id2[j];
    const double fx = out.f[0][j], fy = out.f[1][j], fz = out.f[2][j];
    const double bx = out.t2[0][j], by = out.t2[1][j], bz = out.t2[2][j];
    fa0 += fx, fa1 += fy, fa2 += fz;
    ta0 += out.t1[0][j], ta1 += out.t1[1][j], ta2 += out.t1[2][j];
    if (b == a) {  // a sphere touching its own image (a cell under two diameters wide)
      fa0 -= fx, fa1 -= fy, fa2 -= fz;
      ta0 += bx, ta1 += by, ta2 += bz;
      continue;
    }
    f0[b] -= fx, f1[b] -= fy, f2[b] -= fz;
    t0[b] += bx, t1[b] += by, t2[b] += bz;
  }
  f0[a] = fa0, f1[a] = fa1, f2[a] = fa2, t0[a] = ta0, t1[a] = ta1, t2[a] = ta2;
  return opened;
}

bool scatter(RveState& s, std::size_t k0, std::size_t m, const ContactOut& out) {
  auto& c = s.contacts;
  auto& sp = s.spheres;
  return scatter_arrays(m, c.id1.data() + k0, c.id2.data() + k0, c.penetration.data() + k0, out,
                        sp.force.c[0].data(), sp.force.c[1].data(), sp.force.c[2].data(),
                        sp.torque.c[0].data(), sp.torque.c[1].data(), sp.torque.c[2].data());
}

// The first pair in [p, end) of sphere a's row that has no contact and overlaps now
// (Ig2_Sphere_Sphere_ScGeom's test), end if none: the scan of the new-contact search, its
// arrays in registers (the caller's contact insertions can move them, not this loop).
std::size_t next_overlap(const RveState& s, const NeighbourList& nl,
                         const double* __restrict shifts, std::uint32_t a, std::size_t p,
                         std::size_t end) {
  const auto& sp = s.spheres;
  const double* __restrict x0 = sp.pos.c[0].data();
  const double* __restrict x1 = sp.pos.c[1].data();
  const double* __restrict x2 = sp.pos.c[2].data();
  const double* __restrict rad = sp.radius.data();
  const std::uint32_t* __restrict pj = nl.pair_j_flagged();
  const std::uint16_t* __restrict pc = nl.pair_cell_indices();
  const double xa0 = x0[a], xa1 = x1[a], xa2 = x2[a], ra = rad[a];
  for (; p < end; ++p) {
    const std::uint32_t j = pj[p];
    if (j & NeighbourList::kInContact) continue;
    const double* h = shifts + 3 * pc[p];
    const double d0 = (x0[j] + h[0]) - xa0, d1 = (x1[j] + h[1]) - xa1, d2 = (x2[j] + h[2]) - xa2;
    const double r = ra + rad[j];
    if (r * r - ((d0 * d0 + d1 * d1) + d2 * d2) >= 0) break;
  }
  return p;
}

// Pair p of sphere a overlaps: its contact (zero normal and shear force) is updated and its
// forces added, or dropped if it opened again.
void add_contact(RveState& s, NeighbourList& nl, const LawConstants& law, const double* rec,
                 std::uint32_t a, std::size_t p, ContactOut& out) {
  auto& c = s.contacts;
  const std::size_t k = c.add(a, nl.pair_j(p), nl.pair_cell(p));
  update_contacts(s, law, k, 1, out, rec);
  if (c.penetration[k] < 0) {
    c.swap_remove(k);
    return;
  }
  scatter(s, k, 1, out);
  nl.contact_added(p);
}

// The same over the list of near_pairs from its entry q: the first entry whose pair has no
// contact and overlaps now, end if none.
std::size_t next_near_overlap(const RveState& s, const NeighbourList& nl,
                              const double* __restrict shifts, const std::uint32_t* __restrict near,
                              std::size_t q, std::size_t end) {
  const auto& sp = s.spheres;
  const double* __restrict x0 = sp.pos.c[0].data();
  const double* __restrict x1 = sp.pos.c[1].data();
  const double* __restrict x2 = sp.pos.c[2].data();
  const double* __restrict rad = sp.radius.data();
  const std::uint32_t* __restrict pj = nl.pair_j_flagged();
  const std::uint16_t* __restrict pc = nl.pair_cell_indices();
  for (; q < end; ++q) {
    const std::uint32_t a = near[2 * q], p = near[2 * q + 1];
    const std::uint32_t j = pj[p];
    if (j & NeighbourList::kInContact) continue;
    const double* h = shifts + 3 * pc[p];
    const double d0 = (x0[j] + h[0]) - x0[a], d1 = (x1[j] + h[1]) - x1[a],
                 d2 = (x2[j] + h[2]) - x2[a];
    const double r = rad[a] + rad[j];
    if (r * r - ((d0 * d0 + d1 * d1) + d2 * d2) >= 0) break;
  }
  return q;
}

}  // namespace

void compute_forces(RveState& s, NeighbourList& nl) {
  auto& sp = s.spheres;
  sp.prepare_scratch();  // released between coupling steps
  for (auto* v : {&sp.force, &sp.torque}) {
    for (auto& x : v->c) std::fill(x.begin(), x.end(), 0.0);
  }
  nl.ensure(s);
  auto& c = s.contacts;
  const LawConstants law = law_constants(s);
  ContactOut out;
  const double* rec = pack_sphere_records(s);  // nullptr: no AVX-512
  // Existing contacts, a chunk at a time: update (vectorised), then forces in contact order.
  bool opened = false;
  for (std::size_t k0 = 0; k0 < c.size(); k0 += kContactChunk) {
    const std::size_t m = std::min(kContactChunk, c.size() - k0);
    update_contacts(s, law, k0, m, out, rec);
    opened |= scatter(s, k0, m, out);
  }
  // Contacts that opened are removed (YADE erases them), keeping the others' order.
  if (opened) {
    std::size_t kept = 0;
    for (std::size_t k = 0; k < c.size(); ++k) {
      if (c.penetration[k] < 0) {
        nl.contact_removed(c, k);
        continue;
      }
      if (kept != k) c.move(k, kept);
      ++kept;
    }
    c.truncate(kept);
  }
  const std::size_t n_old = c.size();
  // New contacts: pairs of the Verlet list without a contact that now overlap. The image
  // shifts H c of the list's distinct offsets first (per thread: not kept with the RVE); the
  // shift of c = 0 adds a zero, which changes no squared distance.
  thread_local std::vector<double> shifts;
  shifts.resize(3 * nl.cells().size());
  for (std::size_t q = 0; q < nl.cells().size(); ++q) {
    const Vec3 h = s.cell.shift(nl.cells()[q]);
    shifts[3 * q] = h[0], shifts[3 * q + 1] = h[1], shifts[3 * q + 2] = h[2];
  }
  // Only the pairs that can overlap (NeighbourList::near_pairs, in row order) when the
  // spheres have moved little since the list's build, else every row.
  std::size_t n_near = 0;
  if (const std::uint32_t* near = nl.near_pairs(s, &n_near)) {
    for (std::size_t q = 0; q < n_near; ++q) {
      q = next_near_overlap(s, nl, shifts.data(), near, q, n_near);
      if (q == n_near) break;
      add_contact(s, nl, law, rec, near[2 * q], near[2 * q + 1], out);
    }
#ifdef MPMDEM_CHECK_NEAR  // debugging: every pair that overlaps now without a contact is listed
    for (std::uint32_t a = 0; a < sp.size(); ++a) {
      for (std::size_t p = nl.row_begin(a); p < nl.row_begin(a + 1); ++p) {
        if (next_overlap(s, nl, shifts.data(), a, p, p + 1) != p) continue;
        bool listed = false;
        for (std::size_t q = 0; q < n_near; ++q) listed |= near[2 * q + 1] == p;
        if (!listed) std::abort();
      }
    }
#endif
  } else {
    for (std::uint32_t a = 0; a < sp.size(); ++a) {
      const std::size_t row_end = nl.row_begin(a + 1);
      for (std::size_t p = nl.row_begin(a); p < row_end; ++p) {
        p = next_overlap(s, nl, shifts.data(), a, p, row_end);
        if (p == row_end) break;
        add_contact(s, nl, law, rec, a, p, out);
      }
    }
  }
  // The new contacts (in the order of their first sphere) into their places, the contacts
  // sorted by first sphere for the next step's scatter.
  for (std::size_t k = n_old; k < c.size(); ++k) c.sift_back(k);
}

void dem_step(RveState& s, NeighbourList& nl, double damping) {
  s.cell.integrate_and_update(s.dt);
  compute_forces(s, nl);
  newton(s, damping, &nl);
  ++s.iter;
}

}  // namespace mpmdem::dem::native

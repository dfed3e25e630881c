// One DEM step in YADE's order: see integrator.hpp.
#include "backends/native/integrator.hpp"

#include <cmath>

#include <algorithm>

#include "backends/native/contact_kernel.hpp"

namespace mpmdem::dem::native {

namespace {

// Adds the outputs of contacts [k0, k0 + m) to their spheres in contact order, skipping the
// contacts that opened.
void scatter(RveState& s, std::size_t k0, std::size_t m, const ContactOut& out) {
  auto& c = s.contacts;
  auto& sp = s.spheres;
  for (std::size_t j = 0; j < m; ++j) {
    const std::size_t k = k0 + j;
    if (c.penetration[k] < 0) continue;
    const std::uint32_t a = c.id1[k], b = c.id2[k];
    const Vec3 f(out.f[0][j], out.f[1][j], out.f[2][j]);
    sp.force[a] += f;
    sp.force[b] -= f;
    sp.torque[a] += Vec3(out.t1[0][j], out.t1[1][j], out.t1[2][j]);
    sp.torque[b] += Vec3(out.t2[0][j], out.t2[1][j], out.t2[2][j]);
  }
}

}  // namespace

void compute_forces(RveState& s, NeighbourList& nl) {
  auto& sp = s.spheres;
  sp.prepare_scratch();  // released between coupling steps
  std::fill(sp.force.begin(), sp.force.end(), Vec3::Zero());
  std::fill(sp.torque.begin(), sp.torque.end(), Vec3::Zero());
  nl.ensure(s);
  auto& c = s.contacts;
  const LawConstants law = law_constants(s);
  ContactOut out;
  // Existing contacts, a chunk at a time: update (vectorised), then forces in contact order.
  bool opened = false;
  for (std::size_t k0 = 0; k0 < c.size(); k0 += kContactChunk) {
    const std::size_t m = std::min(kContactChunk, c.size() - k0);
    update_contacts(s, law, k0, m, out);
    scatter(s, k0, m, out);
    for (std::size_t j = 0; j < m; ++j) opened |= c.penetration[k0 + j] < 0;
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
  // New contacts: pairs of the Verlet list without a contact that now overlap.
  for (std::uint32_t a = 0; a < sp.size(); ++a) {
    const std::size_t row_end = nl.row_begin(a + 1);
    for (std::size_t p = nl.row_begin(a); p < row_end; ++p) {
      if (nl.pair_in_contact(p)) continue;
      const std::uint32_t b = nl.pair_j(p);
      const bool zero = nl.pair_cell_zero(p);
      const Vec3 d =
          (zero ? sp.pos[b] : Vec3(sp.pos[b] + s.cell.shift(nl.pair_cell(p)))) - sp.pos[a];
      const double r = sp.radius[a] + sp.radius[b];
      if (r * r - d.squaredNorm() < 0) continue;           // Ig2_Sphere_Sphere_ScGeom's test
      const std::size_t k = c.add(a, b, nl.pair_cell(p));  // zero normal and shear force
      update_contacts(s, law, k, 1, out);
      if (c.penetration[k] < 0) {
        c.swap_remove(k);
        continue;
      }
      scatter(s, k, 1, out);
      nl.contact_added(p);
    }
  }
}

void dem_step(RveState& s, NeighbourList& nl, double damping) {
  s.cell.integrate_and_update(s.dt);
  compute_forces(s, nl);
  newton(s, damping);
  ++s.iter;
}

}  // namespace mpmdem::dem::native

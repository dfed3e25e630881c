// One DEM step in YADE's order: see integrator.hpp.
#include "backends/native/integrator.hpp"

#include <cmath>

#include "backends/native/contact_law.hpp"

namespace mpmdem::dem::native {

namespace {

// Updates contact k with ScGeom + CundallStrack; false when it opened (YADE erases it).
inline bool update_contact(RveState& s, std::size_t k, bool is_new, double tan_phi) {
  auto& c = s.contacts;
  auto& sp = s.spheres;
  const std::uint32_t a = c.id1[k], b = c.id2[k];
  // Most contacts lie inside the cell (cellDist 0): no image shift to compute (adding the
  // zero shift would change no bit).
  const bool image = c.cell[k] != CellDist::Zero();
  const Vec3 x2 = image ? Vec3(sp.pos[b] + s.cell.shift(c.cell[k])) : sp.pos[b];
  const Vec3 shift_vel = image ? s.cell.shift_vel(c.cell[k]) : Vec3::Zero();
  const ScGeom g = sc_geom(sp.pos[a], x2, sp.radius[a], sp.radius[b], sp.vel[a], sp.vel[b],
                           sp.ang_vel[a], sp.ang_vel[b], shift_vel, c.normal[k], is_new, s.dt);
  c.normal[k] = g.normal;
  c.penetration[k] = g.penetration;
  if (g.penetration < 0) return false;
  FrictPhys phys = contact_stiffness(s, k);
  phys.tan_phi = tan_phi;
  const Vec3 f = cundall_strack(g, phys, c.shear_force[k]);
  const Vec3 nf = g.normal.cross(f);
  sp.force[a] += f;
  sp.force[b] -= f;
  sp.torque[a] += (sp.radius[a] - 0.5 * g.penetration) * nf;
  sp.torque[b] += (sp.radius[b] - 0.5 * g.penetration) * nf;
  return true;
}

}  // namespace

void compute_forces(RveState& s, NeighbourList& nl) {
  auto& sp = s.spheres;
  sp.prepare_scratch();  // released between coupling steps
  for (std::size_t i = 0; i < sp.size(); ++i) {
    sp.force[i].setZero();
    sp.torque[i].setZero();
  }
  nl.ensure(s);
  auto& c = s.contacts;
  const double tan_phi = std::tan(s.material.friction_angle);  // one material per RVE
  for (std::size_t k = 0; k < c.size();) {
    if (update_contact(s, k, false, tan_phi)) {
      ++k;
      continue;
    }
    nl.contact_removed(c, k);
    c.swap_remove(k);
  }
  for (std::uint32_t a = 0; a < sp.size(); ++a) {
    const std::size_t row_end = nl.row_begin(a + 1);
    for (std::size_t p = nl.row_begin(a); p < row_end; ++p) {
      if (nl.pair_in_contact(p)) continue;
      const std::uint32_t b = nl.pair_j(p);
      const bool zero = nl.pair_cell_zero(p);
      const Vec3 d =
          (zero ? sp.pos[b] : Vec3(sp.pos[b] + s.cell.shift(nl.pair_cell(p)))) - sp.pos[a];
      const double r = sp.radius[a] + sp.radius[b];
      if (r * r - d.squaredNorm() < 0) continue;  // Ig2_Sphere_Sphere_ScGeom's test
      const std::size_t k = c.add(a, b, nl.pair_cell(p));
      if (update_contact(s, k, true, tan_phi)) {
        nl.contact_added(p);
      } else {
        c.swap_remove(k);
      }
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

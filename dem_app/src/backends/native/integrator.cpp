// One DEM step in YADE's order: see integrator.hpp.
#include "backends/native/integrator.hpp"

#include <cmath>

#include "backends/native/contact_law.hpp"

namespace mpmdem::dem::native {

namespace {

// Branch-free (the sign of an acceleration component is unpredictable): same values.
double sign(double x) {
  return static_cast<double>((x > 0) - (x < 0));
}

// Eigen's Quaternion(AngleAxis(angle, axis)) = (cos h, sin h axis), h = angle / 2, with the
// Taylor series of sin and cos when h < 1e-3: their next terms (h^7/5040, h^8/40320) are
// below 1e-20 of the result, so this agrees with libm to rounding, without the sincos call
// (a sphere turns by ~1e-6 rad per DEM step).
Quat rotation_quaternion(double angle, const Vec3& axis) {
  const double h = 0.5 * angle;
  if (h >= 1e-3) return Quat(Eigen::AngleAxisd(angle, axis));
  const double h2 = h * h;
  const double s = h * (1 - h2 / 6 * (1 - h2 / 20));
  const double c = 1 - h2 / 2 * (1 - h2 / 12 * (1 - h2 / 30));
  return Quat(c, s * axis[0], s * axis[1], s * axis[2]);
}

// NewtonIntegrator::cundallDamp2nd.
void cundall_damp(double damping, double dt, const Vec3& vel, Vec3& accel) {
  for (int i = 0; i < 3; ++i)
    accel[i] *= 1 - damping * sign(accel[i] * (vel[i] + 0.5 * dt * accel[i]));
}

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
  if (sp.force.size() != sp.size()) {  // released between coupling steps
    sp.force.resize(sp.size());
    sp.torque.resize(sp.size());
  }
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

void newton(RveState& s, double damping) {
  auto& cell = s.cell;
  cell.activate_next();
  const double dt = s.dt;
  const Eigen::Matrix3d& prev = cell.prev_vel_grad;
  const Eigen::Matrix3d dvg = cell.vel_grad - prev;
  const Eigen::Matrix3d rot = 0.5 * (dvg - dvg.transpose());
  const Vec3 dspin(-rot(1, 2), rot(0, 2), -rot(0, 1));
  const bool dvg_nonzero = dvg != Eigen::Matrix3d::Zero();
  auto& sp = s.spheres;
  // Each sphere's fields are read into locals once and written back once (the arrays cannot
  // alias, but the compiler cannot know it); the arithmetic is YADE's, in its order.
  const std::size_t n = sp.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 x = sp.pos[i];
    Vec3 v = sp.vel[i], w = sp.ang_vel[i];
    const Vec3 fluct = v - prev * x;
    Vec3 lin = sp.force[i] / sp.mass[i];
    cundall_damp(damping, dt, fluct, lin);
    lin += prev * v;  // convective term of homoDeform = 2
    v += dt * lin;
    Vec3 ang = sp.torque[i] / sp.inertia[i];
    cundall_damp(damping, dt, w, ang);
    w += dt * ang;
    // leapfrogTranslate (dvg is zero while the cell's gradient does not change)
    if (dvg_nonzero) v += dvg * x;
    sp.pos[i] = x + v * dt;
    sp.vel[i] = v;
    // leapfrogSphericalRotate
    w += dspin;
    sp.ang_vel[i] = w;
    const double angle2 = w.squaredNorm();
    Quat o = sp.ori[i];
    if (angle2 != 0) {
      const double angle = std::sqrt(angle2);
      o = rotation_quaternion(angle * dt, w / angle) * o;
    }
    sp.ori[i] = o.normalized();
  }
  cell.prev_vel_grad = cell.vel_grad;
}

void dem_step(RveState& s, NeighbourList& nl, double damping) {
  s.cell.integrate_and_update(s.dt);
  compute_forces(s, nl);
  newton(s, damping);
  ++s.iter;
}

}  // namespace mpmdem::dem::native

// The sphere-sphere contact of YADE's RVEs, formula for formula:
//   Ig2_Sphere_Sphere_ScGeom (avoidGranularRatcheting = true, its default) with
//   ScGeom::precompute/rotate, Ip2_FrictMat_FrictMat_FrictPhys, and
//   Law2_ScGeom_FrictPhys_CundallStrack (periodic branch: forces and torques on the spheres).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace mpmdem::dem::native {

struct FrictPhys {
  double kn, ks, tan_phi;
};

// Ip2_FrictMat_FrictMat_FrictPhys: harmonic means of r_i E_i (normal) and r_i E_i poisson_i
// (shear; FrictMat.poisson is ks/kn); tan_phi is left to the caller.
inline FrictPhys frict_stiffness(double e1, double r1, double p1, double e2, double r2, double p2) {
  FrictPhys f;
  f.kn = 2 * e1 * r1 * e2 * r2 / (e1 * r1 + e2 * r2);
  f.ks = 2 * e1 * r1 * p1 * e2 * r2 * p2 / (e1 * r1 * p1 + e2 * r2 * p2);
  f.tan_phi = 0;
  return f;
}

// Ip2_FrictMat_FrictMat_FrictPhys with the friction angle the smaller of the two.
inline FrictPhys frict_phys(double e1, double r1, double p1, double phi1, double e2, double r2,
                            double p2, double phi2) {
  FrictPhys f = frict_stiffness(e1, r1, p1, e2, r2, p2);
  f.tan_phi = std::tan(std::min(phi1, phi2));
  return f;
}

// ScGeom of one step (Ig2_Sphere_Sphere_ScGeom::go + ScGeom::precompute).
struct ScGeom {
  Eigen::Vector3d normal;            // unit, from sphere 1 to sphere 2's image
  double penetration = 0;            // r1 + r2 - distance (> 0 overlapping)
  Eigen::Vector3d shear_inc;         // tangential relative displacement of the step
  Eigen::Vector3d orthonormal_axis;  // rotation of the normal since the last step
  Eigen::Vector3d twist_axis;        // twist about the (previous) normal
};

// x2 is the position of sphere 2's image (pos2 + hsize c); shift_vel the image's extra
// velocity (Cell::intrShiftVel); prev_normal the normal of the last step (ignored if is_new).
inline ScGeom sc_geom(const Eigen::Vector3d& x1, const Eigen::Vector3d& x2, double r1, double r2,
                      const Eigen::Vector3d& v1, const Eigen::Vector3d& v2,
                      const Eigen::Vector3d& w1, const Eigen::Vector3d& w2,
                      const Eigen::Vector3d& shift_vel, const Eigen::Vector3d& prev_normal,
                      bool is_new, double dt) {
  ScGeom g;
  Eigen::Vector3d n = x2 - x1;
  const double dist = n.norm();
  const double inv_dist = 1 / dist;  // one division (YADE: n /= dist)
  n *= inv_dist;
  g.penetration = r1 + r2 - dist;
  if (!is_new) {
    g.orthonormal_axis = prev_normal.cross(n);
    const double angle = dt * 0.5 * prev_normal.dot(w1 + w2);
    g.twist_axis = angle * prev_normal;
  } else {
    g.orthonormal_axis.setZero();
    g.twist_axis.setZero();
  }
  g.normal = n;
  // ScGeom::getIncidentVel with avoidGranularRatcheting (McNamara's alpha,
  // (r1 + r2) / (r1 + r2 - penetration) = (r1 + r2) / dist to rounding).
  const double alpha = (r1 + r2) * inv_dist;
  // (v2 - v1) alpha + w2 x (-r2 n) - w1 x (r1 n) + alpha shift_vel, factored (to rounding).
  Eigen::Vector3d rel = (v2 - v1 + shift_vel) * alpha - (r1 * w1 + r2 * w2).cross(n);
  rel -= n.dot(rel) * n;
  g.shear_inc = rel * dt;
  return g;
}

// ScGeom::rotate: carry the shear force with the contact plane.
inline void rotate_shear(Eigen::Vector3d& fs, const ScGeom& g) {
  fs -= fs.cross(g.orthonormal_axis);
  fs -= fs.cross(g.twist_axis);
}

// Law2_ScGeom_FrictPhys_CundallStrack for an overlapping pair (g.penetration >= 0): updates
// the shear force; returns the force on sphere 1 (sphere 2 gets its opposite). The normal
// force kn max(penetration, 0) normal is not kept (Contacts::normal_force recomputes it).
inline Eigen::Vector3d cundall_strack(const ScGeom& g, const FrictPhys& p,
                                      Eigen::Vector3d& shear_force) {
  const Eigen::Vector3d normal_force = p.kn * std::max(g.penetration, 0.0) * g.normal;
  rotate_shear(shear_force, g);
  shear_force -= p.ks * g.shear_inc;
  const double max_fs = normal_force.squaredNorm() * std::pow(p.tan_phi, 2);
  if (shear_force.squaredNorm() > max_fs) shear_force *= std::sqrt(max_fs) / shear_force.norm();
  return -normal_force - shear_force;
}

}  // namespace mpmdem::dem::native

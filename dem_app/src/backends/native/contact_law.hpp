// The contact laws of the native RVEs (chosen per scene: coupling.<backend>.contact_law) and
// Ip2_FrictMat_FrictMat_FrictPhys of YADE's RVEs. The geometry and the law of a step
// (Ig2_Sphere_Sphere_ScGeom with avoidGranularRatcheting = true, its default,
// ScGeom::precompute/rotate, Law2_ScGeom_FrictPhys_CundallStrack) are in contact_kernel.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "backends/native/contact_law_kind.hpp"

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

}  // namespace mpmdem::dem::native

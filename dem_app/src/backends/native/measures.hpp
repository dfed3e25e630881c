// What a native RVE reports, as YADE's utils compute it (see docs/dem_backend.md):
// Love-Weber stress (utils.getStress: (1/V) sum_c (Fn + Fs) (x1 - x2 - H c)^T, tension
// positive; the reply symmetrises it), the stiffness bound M_b, kinetic energy of the
// fluctuating motion, mean rotation since ref_ori, porosity, coordination, unbalanced force.
#pragma once

#include <Eigen/Core>

#include "backends/native/rve_state.hpp"

namespace mpmdem::dem::native {

Eigen::Matrix3d love_weber_stress(const RveState& s);
// The stress and, in the same pass over the contacts, the stiffness bound
// max_i M_b,i = (1 - a) C_ii + a S_i with C YADE's Kruyt-Rothenburg tangent diagonal
// (1/V) sum l^2 n_i^2 [kn n_i^2 + ks t_i^2] (t: unit shear-force direction, 0 without
// shear force), S_i = (1/V) sum kn l^2 n_i^2 and a = ks/kn (mpmdem_rve.RveSet._stiffness);
// without `stiffness` the bound is 0 and not computed.
struct StressStiffness {
  Eigen::Matrix3d stress;
  double stiffness;
};
StressStiffness stress_and_stiffness(const RveState& s, bool stiffness);
// utils.kineticEnergy (periodic): 1/2 m |v - prevVelGrad x|^2 + 1/2 w.(I w).
double kinetic_energy(const RveState& s);
// Law2_ScGeom_FrictPhys_CundallStrack::elasticEnergy: sum 1/2 (|Fn|^2/kn + |Fs|^2/ks).
double elastic_energy(const RveState& s);
Eigen::Vector3d mean_rotation(const RveState& s);
double porosity(const RveState& s);
double coordination(const RveState& s);
double unbalanced_force(const RveState& s);

}  // namespace mpmdem::dem::native

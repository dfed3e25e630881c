// Automatic time step from a CFL condition on the current stiffness.
#pragma once

#include "particles.hpp"

namespace mpmdem::mpm {

// dt = min(dt_max, cfl h / max_p (c_p + |v_p|)),  c_p = sqrt(M_p / rho_p),  rho_p = m_p / V_p,
// M_p = Particles::stiffness (the provider's constrained-modulus estimate). dt_max when every
// point is at rest with zero stiffness.
double stable_time_step(const Particles& p, double h, double cfl, double dt_max);

}  // namespace mpmdem::mpm

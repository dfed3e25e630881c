// Energies of the material points (validation notes): E_p = sum m g z, i.e.
// E_p = -sum_p m_p g . x_p for any gravity vector; E_k = sum_p 1/2 m_p |v_p|^2;
// E_strain = sum_p strain_energy_p where the model defines it (local models: elastic energy of the
// stress), else 0. The dissipated energy is E_d = E_p0 - E_p - E_k.
#pragma once

#include "particles.hpp"

namespace mpmdem::mpm {

struct Energies {
  double E_p = 0.0;
  double E_k = 0.0;
  double E_strain = 0.0;
};

// Serial sums in point order, so the figures do not depend on the thread count.
inline double kinetic_energy(const Particles& p) {
  double E_k = 0.0;
  for (std::size_t q = 0; q < p.size(); ++q) E_k += 0.5 * p.m[q] * p.v[q].squaredNorm();
  return E_k;
}

inline Energies compute_energies(const Particles& p, const Vec3& gravity) {
  Energies e;
  for (std::size_t q = 0; q < p.size(); ++q) e.E_p -= p.m[q] * gravity.dot(p.x[q]);
  e.E_k = kinetic_energy(p);
  for (double w : p.strain_energy) e.E_strain += w;
  return e;
}

}  // namespace mpmdem::mpm

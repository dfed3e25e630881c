#include "state_guard.hpp"

#include <cmath>

namespace mpmdem::mpm {

bool find_first_non_finite(const Particles& p, NonFinite& where) {
  const std::size_t n = p.size();
  const bool stiffness = p.stiffness.size() == n, energy = p.strain_energy.size() == n;
  const bool rotation = p.rotation.size() == n, porosity = p.porosity.size() == n;
  const bool coordination = p.coordination.size() == n;
  const bool unbalanced = p.unbalanced_force.size() == n;
  for (std::size_t q = 0; q < p.size(); ++q) {
    const char* field = nullptr;
    if (!p.x[q].allFinite()) {
      field = "position";
    } else if (!p.v[q].allFinite()) {
      field = "velocity";
    } else if (!p.sigma[q].allFinite()) {
      field = "stress";
    } else if (!p.F[q].allFinite()) {
      field = "deformation gradient";
    } else if (!std::isfinite(p.V[q])) {
      field = "volume";
    } else if (stiffness && !std::isfinite(p.stiffness[q])) {
      field = "stiffness";
    } else if (energy && !std::isfinite(p.strain_energy[q])) {
      field = "strain energy";
    } else if (rotation && !p.rotation[q].allFinite()) {
      field = "rotation";
    } else if (porosity && !std::isfinite(p.porosity[q])) {
      field = "porosity";
    } else if (coordination && !std::isfinite(p.coordination[q])) {
      field = "coordination number";
    } else if (unbalanced && !std::isfinite(p.unbalanced_force[q])) {
      field = "unbalanced force";
    }
    if (field != nullptr) {
      where = {q, field};
      return true;
    }
  }
  return false;
}

}  // namespace mpmdem::mpm

#include "state_guard.hpp"

#include <algorithm>
#include <cmath>

#include "parallel.hpp"

namespace mpmdem::mpm {

namespace {

// The first non-finite field of point q, or nullptr.
const char* non_finite_field(const Particles& p, std::size_t q) {
  const std::size_t n = p.size();
  if (!p.x[q].allFinite()) return "position";
  if (!p.v[q].allFinite()) return "velocity";
  if (!p.sigma[q].allFinite()) return "stress";
  if (!p.F[q].allFinite()) return "deformation gradient";
  if (!std::isfinite(p.V[q])) return "volume";
  if (p.stiffness.size() == n && !std::isfinite(p.stiffness[q])) return "stiffness";
  if (p.strain_energy.size() == n && !std::isfinite(p.strain_energy[q])) return "strain energy";
  if (p.rotation.size() == n && !p.rotation[q].allFinite()) return "rotation";
  if (p.porosity.size() == n && !std::isfinite(p.porosity[q])) return "porosity";
  if (p.coordination.size() == n && !std::isfinite(p.coordination[q])) {
    return "coordination number";
  }
  if (p.unbalanced_force.size() == n && !std::isfinite(p.unbalanced_force[q])) {
    return "unbalanced force";
  }
  return nullptr;
}

}  // namespace

bool find_first_non_finite(const Particles& p, NonFinite& where) {
  // On the solver's threads: the smallest index of a bad point (min is order-independent).
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  std::ptrdiff_t first = n;
#pragma omp parallel for schedule(static) if (n > kParallelMin) reduction(min : first)
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    if (non_finite_field(p, static_cast<std::size_t>(q)) != nullptr) first = std::min(first, q);
  }
  if (first == n) return false;
  where = {static_cast<std::size_t>(first), non_finite_field(p, static_cast<std::size_t>(first))};
  return true;
}

}  // namespace mpmdem::mpm

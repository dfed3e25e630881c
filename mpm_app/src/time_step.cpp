#include "time_step.hpp"
#include "parallel.hpp"

#include <algorithm>
#include <cmath>

namespace mpmdem::mpm {

double stable_time_step(const Particles& p, double h, double cfl, double dt_max) {
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  double speed = 0.0;
#pragma omp parallel for schedule(static) if (n > kParallelMin) reduction(max : speed)
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const double rho = p.m[q] / p.V[q];
    const double c = std::sqrt(std::max(0.0, p.stiffness[q]) / rho);
    speed = std::max(speed, c + p.v[q].norm());
  }
  return speed > 0.0 ? std::min(dt_max, cfl * h / speed) : dt_max;
}

}  // namespace mpmdem::mpm

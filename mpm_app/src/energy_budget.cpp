#include "energy_budget.hpp"

#include <Eigen/LU>
#include <cmath>

#include "parallel.hpp"

namespace mpmdem::mpm {

void GridWork::before_update(const Grid& grid, const Vec3& gravity, double damping) {
  if (!(damping > 0.0)) {
    f_damp_.clear();
    return;
  }
  f_damp_.assign(grid.size(), Vec3::Zero());
  const double floor = grid.mass_floor;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double m = grid.m_i[i];
    if (!(m > floor)) continue;
    // As grid_update(): the damping force opposes v0 = mv / m, its size alpha |f| per component.
    const Vec3 v0 = grid.mv_i[i] / m;
    const Vec3 f = grid.f_i[i] + m * gravity;
    for (int d = 0; d < 3; ++d) {
      const double sign = (v0[d] > 0.0) - (v0[d] < 0.0);
      f_damp_[i][d] = -damping * std::abs(f[d]) * sign;
    }
  }
}

void GridWork::after_bc(const Grid& grid, double dt, EnergyBudget& budget) const {
  const double floor = grid.mass_floor;
  const bool damped = f_damp_.size() == grid.size();
  double w_damp = 0.0, w_bc = 0.0, e_k = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double m = grid.m_i[i];
    if (!(m > floor)) continue;
    const Vec3 v_mean = 0.5 * (grid.v0_i[i] + grid.v_i[i]);
    if (damped) w_damp -= dt * f_damp_[i].dot(v_mean);
    w_bc += m * (v_free_[i] - grid.v_i[i]).dot(v_mean);
    e_k += 0.5 * m * grid.v_i[i].squaredNorm();
  }
  budget.W_damp += w_damp;
  budget.W_bc += w_bc;
  budget.W_transfer += e_k;
}

double grid_kinetic_energy(const Grid& grid) {
  const double floor = grid.mass_floor;
  double e = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double m = grid.m_i[i];
    if (m > floor) e += 0.5 * grid.mv_i[i].squaredNorm() / m;
  }
  return e;
}

double stress_work(const Particles& p, bool volume_after_update, std::vector<double>& terms) {
  // Each point's term on the solver's threads, then summed in point order: the same bits as
  // a serial loop, whatever the thread count.
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  terms.resize(p.size());
#pragma omp parallel for schedule(static) if (n > kParallelMin)
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const Mat3& dF = p.dF[q];
    const Mat3 de = 0.5 * (dF + dF.transpose()) - Mat3::Identity();
    const double V = volume_after_update ? p.V[q] : p.V[q] / dF.determinant();
    terms[q] = V * (p.sigma[q].cwiseProduct(de)).sum();
  }
  double w = 0.0;
  for (double t : terms) w += t;
  return w;
}

}  // namespace mpmdem::mpm

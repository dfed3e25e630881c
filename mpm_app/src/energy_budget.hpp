// Energy budget of a run (docs/stability.md): the work terms that, with E_p and E_k, close the
// energy balance of the explicit MPM step, accumulated step by step by the solver.
//
//   E_err = E_p0 + E_k0 - E_p - E_k - W_int - W_damp - W_bc
//
//   W_int  internal (stress) work stored or dissipated in the material:
//          sum over steps of sum_p 1/2 (V_p^n sigma_p^n + V_p^{n+1} sigma_p^{n+1}) : sym(dF_p - I)
//          (trapezoidal in the stress; sym(dF - I) = dt d, d the rate of deformation). For an
//          elastic material it equals the strain energy, for plastic ones it also holds the
//          plastic dissipation, for RVEs it is the work the MPM did on them.
//   W_damp work removed by local (Cundall) damping on the grid: per step
//          -sum_i dt f_damp,i . (v0_i + v_i) / 2, v_i the final node velocity.
//   W_bc   work removed by the walls and velocity constraints: per step
//          sum_i m_i (v_free,i - v_i) . (v0_i + v_i) / 2 (the impulse they apply times the
//          mean node velocity; negative when a prescribed velocity feeds energy in). With
//          W_damp, the force terms and the grid kinetic energy change balance exactly node
//          by node: 1/2 m (|v_i|^2 - |v0_i|^2) = (impulse of all forces) . (v0_i + v_i) / 2.
//   E_err  what is left: the dissipation of the PIC part of the PIC/FLIP blend, the
//          transfer and time-integration errors, and any energy injected by an instability.
//   W_transfer  the part of E_err the particle-grid transfers remove, measured per step:
//          (E_k of the points - E_k of the grid after P2G) + (E_k of the grid after the
//          update and the walls - E_k of the points after G2P), E_k of the grid being
//          sum_i 1/2 m_i |v_i|^2 over the nodes above the mass floor. Signed: a FLIP part
//          can give energy back. E_err - W_transfer is then the time-integration part
//          (the stress work on the points against the grid's force work, gravity's work on
//          the positions against the grid's) and any energy an instability injects.
//   W_transfer_walls  the part of W_transfer at the walls: the work the walls' velocity jumps
//          dv_i = v_i - v_free,i do on the points, -sum_p m_p (sum_i N_ip dv_i) . (v_p^n +
//          v_p^{n+1}) / 2, less their work on the grid (W_bc's step). Every transfer moves a
//          point by sum_i N_ip dv_i for the walls (v_p^{n+1} - v_p^n = sum_i N_ip (v_i - v0_i)
//          + (1 - flip) (v_target's own part)), so the split is exact. When the points that
//          share a wall node move at different speeds, they lose more than the node: for a
//          FLIP point the excess is 1/2 |dv_i|^2 sum_p m_p N_ip (1 - N_ip) per node and step, a
//          jump of O(1), not O(dt), so it does not vanish with the step (docs/transfers.md, "The
//          walls' share of the transfers").
// Serial sums in node/point order, so the figures do not depend on the thread count.
#pragma once

#include <cassert>
#include <cstddef>
#include <vector>

#include "grid.hpp"
#include "node_loops.hpp"
#include "parallel.hpp"
#include "particles.hpp"
#include "transfers.hpp"

namespace mpmdem::mpm {

struct EnergyBudget {
  double E_k0 = 0.0;              // kinetic energy at t = 0 [J]
  double W_int = 0.0;             // [J]
  double W_damp = 0.0;            // [J]
  double W_bc = 0.0;              // [J]
  double W_transfer = 0.0;        // [J], included in E_err
  double W_transfer_walls = 0.0;  // [J], included in W_transfer
};

// sum_i 1/2 |mv_i|^2 / m_i over the nodes above the mass floor: the grid's kinetic energy as
// P2G left it (the points' is kinetic_energy(), energies.hpp).
double grid_kinetic_energy(const Grid& grid);

// The grid part of the budget, measured around grid_update() and the boundary conditions:
// before_update() with the grid as P2G left it and grid_update()'s arguments; before_bc()
// after grid_update(); after_bc() after the walls and constraints: adds W_damp and W_bc of
// the step to `budget`, and to budget.W_transfer the grid's kinetic energy
// sum_i 1/2 m_i |v_i|^2 that G2P then transfers back.
class GridWork {
 public:
  void before_update(const Grid& grid, const Vec3& gravity, double damping);
  void before_bc(const Grid& grid) { v_free_ = grid.v_i; }
  void after_bc(const Grid& grid, double dt, EnergyBudget& budget) const;
  // After G2P (stencils at x_p^n; v_before, C_before the points' velocities and, with APIC,
  // affine matrices before it, else empty): the work the walls' velocity jumps did on the
  // points, -sum_p m_p sum_i N_ip dv_i . (v_mean + C_mean (x_i - x_p)), means of before and
  // after (W_transfer_walls is this less W_bc's step). With APIC the point's velocity at a
  // node holds its affine part, which P2G puts there and the wall stops. Summed in point order.
  template <int W>
  double wall_work_on_points(const Grid& grid, const Stencils<W>& s, const Particles& p,
                             const std::vector<Vec3>& v_before,
                             const std::vector<Mat3>& C_before) const;

 private:
  std::vector<Vec3> f_damp_;             // damping force per node (empty: no damping)
  std::vector<Vec3> v_free_;             // node velocity before the boundary conditions
  mutable std::vector<double> w_point_;  // wall_work_on_points' per-point terms
};

template <int W>
double GridWork::wall_work_on_points(const Grid& grid, const Stencils<W>& s, const Particles& p,
                                     const std::vector<Vec3>& v_before,
                                     const std::vector<Mat3>& C_before) const {
  assert(v_free_.size() == grid.size() && v_before.size() == p.size());
  const bool affine = !C_before.empty();
  assert(!affine || C_before.size() == p.size());
  bool any = false;
  for (std::size_t i = 0; i < grid.size() && !any; ++i) any = grid.v_i[i] != v_free_[i];
  if (!any) return 0.0;  // no wall or constraint acted this step
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  w_point_.resize(p.size());
#pragma omp parallel for schedule(static) if (n > kParallelMin)
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const Vec3 v_mean = 0.5 * (v_before[q] + p.v[q]);
    const Mat3 C_mean = affine ? (0.5 * (C_before[q] + p.C[q])).eval() : Mat3::Zero().eval();
    double w = 0.0;
    detail::for_each_node_affine(
        grid, s[q], [&](std::size_t i, double N, const Vec3&, const Vec3& dx, const Vec3&) {
          const Vec3 jump = grid.v_i[i] - v_free_[i];
          w += N * jump.dot(affine ? (v_mean + C_mean * dx).eval() : v_mean);
        });
    w_point_[q] = -p.m[q] * w;
  }
  double w = 0.0;
  for (double x : w_point_) w += x;
  return w;
}

// sum_p V_p sigma_p : sym(dF_p - I) with V_p the current volume (volume_after_update: the
// volume after dF_p was applied) or V_p / det(dF_p) (the volume before the step).
double stress_work(const Particles& p, bool volume_after_update);

}  // namespace mpmdem::mpm

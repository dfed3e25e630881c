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
//          dv_i = v_i - v_free,i do on the points, -sum_p m_p sum_i N_ip dv_i . (v_mean +
//          C_mean (x_i - x_p)) (means over G2P; C only with APIC), less their work on the grid
//          (W_bc's step); G2P sums it (wall_work_tap.hpp). Every transfer moves a point by
//          sum_i N_ip dv_i for the walls (v_p^{n+1} - v_p^n = sum_i N_ip (v_i - v0_i) +
//          (1 - flip) (v_target's own part)), so the split is exact. A point only partly on a
//          wall node keeps part of its speed, and the points that share the node lose more
//          than the node: for FLIP points 1/2 |dv_i|^2 sum_p m_p N_ip (1 - N_ip) more per node
//          and step, with a jump of O(1), not O(dt), so it does not vanish with the step
//          (docs/transfers.md, "The walls' share of the transfers").
// Serial sums in node/point order, so the figures do not depend on the thread count.
#pragma once

#include <vector>

#include "grid.hpp"
#include "particles.hpp"

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
  // The node velocities before the walls and constraints (after before_bc()): G2P's
  // wall tap measures W_transfer_walls from them (wall_work_tap.hpp).
  const std::vector<Vec3>& v_free() const { return v_free_; }

 private:
  std::vector<Vec3> f_damp_;  // damping force per node (empty: no damping)
  std::vector<Vec3> v_free_;  // node velocity before the boundary conditions
};

// sum_p V_p sigma_p : sym(dF_p - I) with V_p the current volume (volume_after_update: the
// volume after dF_p was applied) or V_p / det(dF_p) (the volume before the step). terms:
// scratch for the per-point terms (its memory is reused from call to call).
double stress_work(const Particles& p, bool volume_after_update, std::vector<double>& terms);

}  // namespace mpmdem::mpm

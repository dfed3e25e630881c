// The explicit MPM solver: one call to step() advances the points by one time step.
//
// One step (shape functions evaluated once per point at x_p^n):
//   0 Points outside the grid: SimulationError (solver.on_exit: error) or removed (remove).
//   1 P2G      m_i = sum N_ip m_p,  mv_i = sum N_ip m_p v_p,  f_i = -sum V_p sigma_p grad N_ip
//   2 Grid     v0_i = mv_i / m_i;  f_i += m_i g;  local damping f_i -= alpha |f_i| sign(v0_i);
//              v_i = v0_i + dt f_i / m_i;  walls and active velocity constraints on v_i.
//   3 G2P      PIC/FLIP (the schema's default): v_p = flip (v_p + sum N (v_i - v0_i))
//              + (1 - flip) sum N v_i, flip = 1 - dt / solver.flip_time_scale when that is set;
//              APIC: v_p = sum N v_i, C_p = sum v_i (D_p^-1 N_ip (x_i - x_p))^T (P2G then
//              carries mv_i = sum N m_p (v_p + C_p (x_i - x_p))), with a time scale v_p is the
//              blend above; XPIC (transfers.hpp);  x_p += dt sum N v_i
//   4 Velocity gradient
//       MUSL (default): mv_i = sum N m_p v_p (re-projected), v_i = mv_i / m_i, BCs again,
//                       grad v_p = sum v_i (x) grad N_ip. The stress sees the velocity field
//                       of the updated points (smoother, less prone to cell-crossing noise).
//       USL:            grad v_p from the v_i of step 2 (one transfer fewer). With linear
//                       shape functions USL is unstable when points cross cells (a node
//                       with a tiny mass gets a huge acceleration that enters grad v_p);
//                       use it with quadratic B-splines only.
//     dF_p = I + dt grad v_p;  F_p = dF_p F_p;  V_p = det(dF_p) V_p.
//   5 Stress   provider->update(dF of all points) in one batched call; stress, stiffness and
//              outputs copied to the points; non-finite stress or a fatal RVE status:
//              SimulationError naming the point and the step.
//   6 Guard    a non-finite x, v, sigma, F, V or stiffness at any point: SimulationError
//              naming the point and the step (state_guard.hpp), before any output is written.
//   7 Next dt  min(dt_max, cfl h / max_p (sqrt(M_p / rho_p) + |v_p|)), or solver.dt_fixed
//              when set (stability studies: no CFL check); constraint releases.
//
// Energy budget (energy_budget.hpp), measured through hooks at the stages (step_energy.hpp):
// W_damp and W_bc from the grid around step 2, W_transfer around steps 1 and 3, W_int from
// the stresses before and after step 5. Each stage is one function of solver.cpp.
//
// The FLIP increment uses v0_i before the boundary conditions, so a wall or a prescribed
// velocity also changes the point velocities by exactly the impulse it applies to the grid.
//
// Removed points (on_exit: remove) are taken out of particles() (so outputs and energies see
// only the points in the grid); the provider keeps its batch size: every point has a fixed
// provider slot (its index at construction) and the slots of removed points receive dF = I.
// Mass is conserved exactly: m_p never changes.
//
// The initial stress comes from initial_stresses(scene, particles) (Particles::sigma on
// entry is ignored). Steps are not shortened to land on end_time: the last one may overshoot
// it by less than dt. E_strain is computed (ElasticLaw::strain_energy_density) only when the
// scene's model is local (linear_elastic, drucker_prager: the elastic energy of the stress); else
// 0.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "boundary_conditions.hpp"
#include "constitutive/provider.hpp"
#include "energies.hpp"
#include "energy_budget.hpp"
#include "errors.hpp"
#include "grid.hpp"
#include "mpmdem/laws/elastic_law.hpp"
#include "particles.hpp"
#include "scene.hpp"
#include "shape_functions.hpp"
#include "step_energy.hpp"
#include "transfers.hpp"

namespace mpmdem::mpm {

// Everything step() needs to continue a run exactly (checkpoints, output/checkpoint.hpp).
struct SolverState {
  Particles particles;
  std::vector<std::size_t> slot;  // provider slot of each point
  std::size_t n_slots = 0;        // provider batch size (points at the start)
  double time = 0.0, dt = 0.0, dt_next = 0.0, E_p0 = 0.0;
  std::int64_t step = 0;
  std::int64_t no_contact_updates = 0;
  std::size_t removed = 0;
  std::vector<char> constraint_active;
  EnergyBudget budget;
};

// Wall time of the phases of the last step [s] (issue 5: per-phase timing).
struct StepTiming {
  double p2g_s = 0.0;       // shape functions at x_p and particle-to-grid
  double grid_s = 0.0;      // grid momentum update and boundary conditions
  double g2p_s = 0.0;       // grid-to-particle, MUSL re-projection, dF, F, V
  double stress_s = 0.0;    // provider update (remote: the whole exchange) and responses
  ProviderTiming provider;  // the provider's own view of it
};

class Solver {
 public:
  // Calls provider->initialise(initial_stresses(scene, particles)) and keeps the responses,
  // checks the points are inside the grid, records E_p0 and the first time step.
  Solver(const Scene& scene, Particles particles, std::unique_ptr<ConstitutiveProvider> provider);
  // Continues a saved run: provider->resume(stresses per slot) instead of initialise (a
  // remote provider asks the restored servers for their state).
  Solver(const Scene& scene, SolverState state, std::unique_ptr<ConstitutiveProvider> provider);
  SolverState state() const;

  // One explicit step. Throws SimulationError (the run must stop). With the remote model a
  // step that throws leaves the state of the last completed step (the points are restored),
  // so that mpm_app's fault checkpoint after a failed exchange is one consistent step.
  void step();

  double time() const { return time_; }
  std::int64_t step_count() const { return step_; }
  // Time step used by the last step (before the first step: the one the first step will use).
  double dt() const { return step_ > 0 ? dt_ : dt_next_; }
  // Time step the next step will use.
  double next_dt() const { return dt_next_; }
  bool finished() const;

  const Particles& particles() const { return p_; }
  const Grid& grid() const { return grid_; }
  const Scene& scene() const { return scene_; }
  const BoundaryConditions& boundary_conditions() const { return bc_; }

  Energies energies() const;
  // Angular momentum of the points about the origin, affine part included (APIC): what the
  // next P2G puts on the grid (transfers.hpp).
  Vec3 angular_momentum() const;
  double initial_potential_energy() const { return E_p0_; }
  // E_k0 and the work terms accumulated up to now (energy_budget.hpp).
  const EnergyBudget& energy_budget() const { return energy_.budget(); }
  // Human-readable events since the last call (constraint releases, removed points).
  std::vector<std::string> take_events();

  ConstitutiveProvider& provider() { return *provider_; }
  const StepTiming& last_timing() const { return timing_; }
  std::size_t removed_points() const { return removed_; }
  // Point-updates that came back in state PointState::kNoContacts (an RVE that lost all
  // contacts, a disconnected point: zero stress), over the whole run.
  std::int64_t no_contact_updates() const { return no_contact_updates_; }
  // Points whose last update had that state.
  std::size_t no_contact_points() const;

 private:
  template <class Shape>
  void step_with(Stencils<Shape::kWidth>& stencils, double dt);
  // The stages of step_with, in order.
  template <int W>
  void points_to_grid(const Stencils<W>& stencils);
  template <int W>
  void update_grid(const Stencils<W>& stencils, double dt);
  template <int W>
  void grid_to_points(const Stencils<W>& stencils, double dt);
  template <int W>
  void deform_points(const Stencils<W>& stencils, double dt, std::int64_t step);
  void update_stresses(double dt, std::int64_t step);
  void prepare_next_step();
  void handle_points_outside_grid();
  void set_up_energy_law_and_mass_floor();
  void check_response_count(const char* what, std::size_t expected) const;
  void remove_points(const std::vector<char>& keep);
  void apply_responses();
  std::string describe_point(std::size_t q) const;
  void check_finite_state(std::int64_t step, double dt) const;
  double next_time_step() const;

  Scene scene_;
  Particles p_;
  Particles step_start_;  // remote model: p_ before the step being taken (restored if it throws)
  std::unique_ptr<ConstitutiveProvider> provider_;
  Grid grid_;
  BoundaryConditions bc_;
  ScatterBuffers buffers_;
  Stencils<LinearShape::kWidth> stencils_linear_;
  Stencils<QuadraticBSplineShape::kWidth> stencils_quadratic_;
  std::vector<std::size_t> slot_;  // provider slot of each point
  std::vector<Mat3> dF_slots_;     // batch sent to the provider (identity on removed slots)
  std::vector<PointResponse> responses_;
  std::optional<elastic::ElasticLaw> law_;  // strain energy (local models only)
  double time_ = 0.0;
  double dt_ = 0.0;
  double dt_next_ = 0.0;
  std::int64_t step_ = 0;
  double E_p0_ = 0.0;
  StepEnergy energy_;  // the energy budget, measured at the stages of each step
  std::size_t removed_ = 0;
  std::int64_t no_contact_updates_ = 0;
  std::vector<std::string> events_;
  StepTiming timing_;
};

}  // namespace mpmdem::mpm

#include "solver.hpp"
#include "parallel.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "constitutive/rve_outputs.hpp"
#include "particle_init.hpp"
#include "state_guard.hpp"
#include "time_step.hpp"
#include "xpic.hpp"

namespace mpmdem::mpm {

namespace {

// Keep the entries of v whose mask is set (only vectors that hold one entry per point).
template <class T>
void compact(std::vector<T>& v, const std::vector<char>& keep) {
  if (v.size() != keep.size()) return;
  std::size_t j = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (keep[i]) v[j++] = v[i];
  }
  v.resize(j);
}

// dst = src for one per-point field, the entries copied on the solver's threads into dst's
// memory (a field of another length than the points, e.g. an unused optional one, is assigned).
template <class T>
void copy_field(const std::vector<T>& src, std::vector<T>& dst, std::size_t n) {
  if (src.size() != n) {
    dst = src;
    return;
  }
  dst.resize(n);
  const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static) if (count > kParallelMin)
  for (std::ptrdiff_t q = 0; q < count; ++q) dst[q] = src[q];
}

// dst = src (every field of Particles), on the solver's threads.
void copy_points(const Particles& src, Particles& dst) {
  const std::size_t n = src.size();
  copy_field(src.id, dst.id, n);
  copy_field(src.region, dst.region, n);
  copy_field(src.m, dst.m, n);
  copy_field(src.V, dst.V, n);
  copy_field(src.V0, dst.V0, n);
  copy_field(src.x, dst.x, n);
  copy_field(src.x0, dst.x0, n);
  copy_field(src.v, dst.v, n);
  copy_field(src.C, dst.C, n);
  copy_field(src.F, dst.F, n);
  copy_field(src.dF, dst.dF, n);
  copy_field(src.sigma, dst.sigma, n);
  copy_field(src.stiffness, dst.stiffness, n);
  copy_field(src.strain_energy, dst.strain_energy, n);
  copy_field(src.rotation, dst.rotation, n);
  copy_field(src.porosity, dst.porosity, n);
  copy_field(src.coordination, dst.coordination, n);
  copy_field(src.unbalanced_force, dst.unbalanced_force, n);
  copy_field(src.state, dst.state, n);
  static_assert(sizeof(Particles) == 19 * sizeof(std::vector<double>),
                "a field was added to Particles: copy it in copy_points()");
}

template <class T>
void fill_if_empty(std::vector<T>& v, std::size_t n, const T& value) {
  if (v.empty()) v.assign(n, value);
  if (v.size() != n) {
    throw std::invalid_argument("Solver: a particle field has " + std::to_string(v.size()) +
                                " entries for " + std::to_string(n) + " points");
  }
}

std::string vec(const Vec3& x) {
  std::ostringstream s;
  s << "(" << x[0] << ", " << x[1] << ", " << x[2] << ")";
  return s.str();
}

}  // namespace

Solver::Solver(const Scene& scene, Particles particles,
               std::unique_ptr<ConstitutiveProvider> provider)
    : scene_(scene),
      p_(std::move(particles)),
      provider_(std::move(provider)),
      grid_(scene.grid),
      bc_(scene, grid_) {
  if (!provider_) throw std::invalid_argument("Solver: no constitutive provider");
  set_shape_axes(scene_, grid_);
  if (scene_.solver.transfer == Transfer::kAPIC && scene_.solver.shape == ShapeKind::kLinear) {
    throw std::invalid_argument("Solver: APIC needs quadratic B-splines (solver.shape bspline2)");
  }
  const std::size_t n = p_.size();
  fill_if_empty(p_.id, n, std::int64_t{0});
  fill_if_empty(p_.region, n, 0);
  fill_if_empty(p_.V, n, 0.0);
  fill_if_empty(p_.x, n, Vec3(Vec3::Zero()));
  fill_if_empty(p_.v, n, Vec3(Vec3::Zero()));
  fill_if_empty(p_.C, n, Mat3(Mat3::Zero()));
  if (p_.V0.empty()) p_.V0 = p_.V;
  if (p_.x0.empty()) p_.x0 = p_.x;
  fill_if_empty(p_.V0, n, 0.0);
  fill_if_empty(p_.x0, n, Vec3(Vec3::Zero()));
  fill_if_empty(p_.F, n, Mat3(Mat3::Identity()));
  fill_if_empty(p_.dF, n, Mat3(Mat3::Identity()));
  fill_if_empty(p_.sigma, n, Mat3(Mat3::Zero()));
  fill_if_empty(p_.stiffness, n, 0.0);
  fill_if_empty(p_.strain_energy, n, 0.0);
  fill_if_empty(p_.state, n, PointState::kOk);
  if (scene_.constitutive.is_remote()) {
    const RveOutputs out = rve_outputs(scene_.coupling.outputs);
    if (out.rotation) p_.rotation.assign(n, Vec3::Zero());
    if (out.porosity) p_.porosity.assign(n, 0.0);
    if (out.coordination) p_.coordination.assign(n, 0.0);
    if (out.unbalanced_force) p_.unbalanced_force.assign(n, 0.0);
  }
  set_up_energy_law_and_mass_floor();

  slot_.resize(n);
  for (std::size_t q = 0; q < n; ++q) slot_[q] = q;
  dF_slots_.assign(n, Mat3::Identity());

  provider_->initialise(initial_stresses(scene_, p_), responses_);
  check_response_count("initialised", n);
  apply_responses();
  handle_points_outside_grid();
  if (scene_.solver.scheme == Scheme::kUSL && scene_.solver.shape == ShapeKind::kLinear) {
    events_.push_back(
        "warning: solver.scheme usl with solver.shape linear is unstable when points cross "
        "cells (nodes with tiny mass); prefer scheme musl or shape bspline2");
  }
  E_p0_ = energies().E_p;
  energy_.set_initial_kinetic_energy(energies().E_k);
  dt_next_ = next_time_step();
  if (scene_.solver.dt_fixed > 0.0) {
    const double dt_cfl = stable_time_step(p_, grid_.h, 1.0, scene_.solver.dt_max);
    std::ostringstream msg;
    msg << "solver.dt_fixed = " << scene_.solver.dt_fixed << " s replaces the automatic step";
    if (scene_.solver.dt_fixed > dt_cfl) {
      msg << "; warning: it exceeds the CFL limit h / c = " << dt_cfl
          << " s at the start (the run is expected to be unstable)";
    }
    events_.push_back(msg.str());
  }
}

double Solver::next_time_step() const {
  const SolverParams& sp = scene_.solver;
  return sp.dt_fixed > 0.0 ? sp.dt_fixed : stable_time_step(p_, grid_.h, sp.cfl, sp.dt_max);
}

Solver::Solver(const Scene& scene, SolverState state,
               std::unique_ptr<ConstitutiveProvider> provider)
    : scene_(scene),
      p_(std::move(state.particles)),
      provider_(std::move(provider)),
      grid_(scene.grid),
      bc_(scene, grid_) {
  if (!provider_) throw std::invalid_argument("Solver: no constitutive provider");
  set_shape_axes(scene_, grid_);
  if (state.slot.size() != p_.size() || state.constraint_active.size() != bc_.constraint_count()) {
    throw std::invalid_argument(
        "Solver: the saved state does not match the scene (" + std::to_string(p_.size()) +
        " points, " + std::to_string(state.slot.size()) + " slots, " +
        std::to_string(state.constraint_active.size()) + " constraint flags)");
  }
  set_up_energy_law_and_mass_floor();
  slot_ = std::move(state.slot);
  dF_slots_.assign(state.n_slots, Mat3::Identity());
  std::vector<Mat3> slot_stress(state.n_slots, Mat3::Zero());
  for (std::size_t q = 0; q < p_.size(); ++q) slot_stress.at(slot_[q]) = p_.sigma[q];
  for (std::size_t c = 0; c < bc_.constraint_count(); ++c)
    bc_.set_active(c, state.constraint_active[c] != 0);
  time_ = state.time;
  dt_ = state.dt;
  dt_next_ = state.dt_next;
  step_ = state.step;
  E_p0_ = state.E_p0;
  energy_.set_budget(state.budget);
  removed_ = state.removed;
  no_contact_updates_ = state.no_contact_updates;
  provider_->resume(slot_stress, responses_);
  check_response_count("resumed", state.n_slots);
  // The saved stresses stand (a restored RVE reports the stress it was saved with).
}

void Solver::set_up_energy_law_and_mass_floor() {
  if (!scene_.constitutive.is_remote()) {
    // A local model: 1/2 sigma : C^-1 : sigma with its elastic moduli is the elastic strain
    // energy (of linear_elastic, and of drucker_prager: for perfect plasticity the elastic
    // strain is C^-1 : sigma).
    law_ =
        elastic::ElasticLaw{scene_.constitutive.youngs_modulus, scene_.constitutive.poisson_ratio};
  }
  // Nodes lighter than a 1e-12 fraction of the lightest point are empty.
  double m_min = 0.0;
  if (!p_.m.empty()) m_min = *std::min_element(p_.m.begin(), p_.m.end());
  grid_.mass_floor = 1e-12 * m_min;
}

void Solver::check_response_count(const char* what, std::size_t expected) const {
  if (responses_.size() == expected) return;
  throw SimulationError("constitutive provider '" + provider_->name() + "' " + what + " " +
                        std::to_string(responses_.size()) + " points, expected " +
                        std::to_string(expected));
}

SolverState Solver::state() const {
  SolverState s;
  s.particles = p_;
  s.slot = slot_;
  s.n_slots = dF_slots_.size();
  s.time = time_;
  s.dt = dt_;
  s.dt_next = dt_next_;
  s.E_p0 = E_p0_;
  s.step = step_;
  s.no_contact_updates = no_contact_updates_;
  s.removed = removed_;
  s.budget = energy_.budget();
  for (std::size_t c = 0; c < bc_.constraint_count(); ++c)
    s.constraint_active.push_back(bc_.constraint_active(c) ? 1 : 0);
  return s;
}

bool Solver::finished() const {
  const double end = scene_.solver.end_time;
  return time_ >= end - 1e-12 * std::abs(end);
}

Vec3 Solver::angular_momentum() const {
  const Transfer t = scene_.solver.transfer;
  if (scene_.solver.shape == ShapeKind::kQuadraticBSpline) {
    Stencils<QuadraticBSplineShape::kWidth> s;
    compute_stencils<QuadraticBSplineShape>(grid_, p_.x, s);
    return mpm::angular_momentum(p_, s, grid_, t);
  }
  Stencils<LinearShape::kWidth> s;
  compute_stencils<LinearShape>(grid_, p_.x, s);
  return mpm::angular_momentum(p_, s, grid_, t);
}

Energies Solver::energies() const {
  return compute_energies(p_, scene_.solver.gravity);
}

std::vector<std::string> Solver::take_events() {
  std::vector<std::string> e;
  e.swap(events_);
  return e;
}

void Solver::step() {
  handle_points_outside_grid();
  const double dt = dt_next_;
  // Remote model: a peer fault in the exchange must not leave step n+1 positions with step
  // n stresses. Time, step and the energy budget change only once the step succeeded; the
  // points are copied (reusing the copy's memory) and restored if the step throws.
  const bool restorable = scene_.constitutive.is_remote();
  if (restorable) copy_points(p_, step_start_);
  const std::int64_t before = step_;
  try {
    if (scene_.solver.shape == ShapeKind::kQuadraticBSpline) {
      step_with<QuadraticBSplineShape>(stencils_quadratic_, dt);
    } else {
      step_with<LinearShape>(stencils_linear_, dt);
    }
  } catch (...) {
    if (restorable && step_ == before) {  // else the step's state is whole
      copy_points(step_start_, p_);
      energy_.points_changed();
    }
    throw;
  }
}

namespace {

// The wall time of a step's phases (StepTiming): lap() is the seconds since the last lap.
class PhaseClock {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return s;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

// One step, stage by stage (solver.hpp's list). The energy budget hangs on the stages through
// energy_'s hooks (step_energy.hpp), the phase timings through the clock.
template <class Shape>
void Solver::step_with(Stencils<Shape::kWidth>& stencils, double dt) {
  const std::int64_t step = step_ + 1;
  PhaseClock clock;
  StepTiming timing;
  compute_stencils<Shape>(grid_, p_.x, stencils);  // at x_p^n, for every transfer of the step
  points_to_grid(stencils);                        // 1 P2G
  timing.p2g_s = clock.lap();
  update_grid(stencils, dt);  // 2 grid momentum, walls, constraints
  timing.grid_s = clock.lap();
  grid_to_points(stencils, dt);       // 3 G2P (4: MUSL's re-projection)
  deform_points(stencils, dt, step);  // 4 dF_p, F_p, V_p
  timing.g2p_s = clock.lap();
  update_stresses(dt, step);  // 5 stresses, 6 guard
  timing.stress_s = clock.lap();
  timing.provider = provider_->last_timing();
  timing_ = timing;
  prepare_next_step();  // 7 next dt, constraint releases
}

template <int W>
void Solver::points_to_grid(const Stencils<W>& stencils) {
  energy_.before_p2g(p_);
  p2g(p_, stencils, grid_, scene_.solver.transfer, buffers_);
  energy_.after_p2g(grid_);
}

template <int W>
void Solver::update_grid(const Stencils<W>& stencils, double dt) {
  const SolverParams& sp = scene_.solver;
  energy_.before_grid_update(grid_, sp.gravity, sp.local_damping);
  grid_update(grid_, sp.gravity, sp.local_damping, dt);
  energy_.before_bc(grid_);
  bc_.apply(grid_.v_i);
  energy_.after_bc(grid_, dt);
  // XPIC's filtered velocity field, from the grid velocities the walls have fixed.
  if (sp.transfer == Transfer::kXPIC) xpic_velocity(p_, stencils, grid_, sp.xpic_order, buffers_);
}

template <int W>
void Solver::grid_to_points(const Stencils<W>& stencils, double dt) {
  const SolverParams& sp = scene_.solver;
  const bool musl = sp.scheme == Scheme::kMUSL;
  g2p(p_, stencils, grid_, sp.transfer, flip_fraction(sp, dt), dt, musl, buffers_,
      energy_.g2p_walls());
  energy_.after_g2p(p_);
  if (musl) {  // the velocity gradient from the momentum of the updated points
    grid_velocity_from_momentum(grid_);
    bc_.apply(grid_.v_i);
  }
}

template <int W>
void Solver::deform_points(const Stencils<W>& stencils, double dt, std::int64_t step) {
  const std::size_t bad = update_deformation(p_, stencils, grid_, dt);
  if (bad != kNoPoint) {
    const SolverParams& sp = scene_.solver;
    std::ostringstream msg;
    msg << describe_point(bad) << " inverted or degenerated at step " << step
        << " (det dF = " << p_.dF[bad].determinant() << ", dt = " << dt
        << " s): the run is unstable; "
        << (sp.dt_fixed > 0.0 ? "unset solver.dt_fixed (automatic CFL step)"
                              : "reduce solver.cfl or solver.dt_max")
        << ", or check the material parameters";
    throw SimulationError(msg.str());
  }
  energy_.before_stress(p_);
}

// The whole batch of dF in one provider call; the step counts once its stresses are back
// and finite.
void Solver::update_stresses(double dt, std::int64_t step) {
  const auto n = static_cast<std::ptrdiff_t>(p_.size());
#pragma omp parallel for schedule(static) if (n > kParallelMin)
  for (std::ptrdiff_t q = 0; q < n; ++q) dF_slots_[slot_[q]] = p_.dF[q];
  provider_->update(dF_slots_, dt, step, time_ + dt, responses_);
  if (responses_.size() != dF_slots_.size()) {
    throw SimulationError("constitutive provider '" + provider_->name() + "' returned " +
                          std::to_string(responses_.size()) + " responses for " +
                          std::to_string(dF_slots_.size()) + " points at step " +
                          std::to_string(step));
  }
  time_ += dt;
  step_ = step;
  dt_ = dt;
  apply_responses();
  check_finite_state(step, dt);
  energy_.after_stress(p_);
}

void Solver::prepare_next_step() {
  dt_next_ = next_time_step();
  if (bc_.constraint_count() > 0) {
    const double E_k = bc_.needs_kinetic_energy() ? energies().E_k : 0.0;
    bc_.update_releases(time_, E_k, E_p0_, events_);
  }
}

void Solver::check_finite_state(std::int64_t step, double dt) const {
  NonFinite bad;
  if (!find_first_non_finite(p_, bad)) return;
  std::ostringstream msg;
  msg << "non-finite " << bad.field << " at " << describe_point(bad.point) << " at step " << step
      << " (dt = " << dt << " s): the run is unstable; nothing of this step is written. "
      << (scene_.solver.dt_fixed > 0.0 ? "Unset solver.dt_fixed (automatic CFL step)"
                                       : "Reduce solver.cfl or solver.dt_max")
      << ", or check the material parameters";
  throw SimulationError(msg.str());
}

std::string Solver::describe_point(std::size_t q) const {
  std::ostringstream s;
  s << "material point " << p_.id[q] << " (x = " << vec(p_.x[q]) << ", initial position "
    << vec(p_.x0[q]) << ")";
  return s.str();
}

void Solver::apply_responses() {
  const auto n = static_cast<std::ptrdiff_t>(p_.size());
  const bool rotation = p_.rotation.size() == p_.size();
  const bool porosity = p_.porosity.size() == p_.size();
  const bool coordination = p_.coordination.size() == p_.size();
  const bool unbalanced = p_.unbalanced_force.size() == p_.size();
  std::size_t bad = kNoPoint;
#pragma omp parallel for schedule(static) if (n > kParallelMin) reduction(min : bad)
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const PointResponse& r = responses_[slot_[q]];
    if (!r.stress.allFinite() || !std::isfinite(r.stiffness) || r.state == PointState::kFatal) {
      bad = std::min(bad, static_cast<std::size_t>(q));
      continue;
    }
    p_.sigma[q] = r.stress;
    p_.stiffness[q] = r.stiffness;
    p_.state[q] = r.state;
    if (rotation) p_.rotation[q] = r.rotation;
    if (porosity) p_.porosity[q] = r.porosity;
    if (coordination) p_.coordination[q] = r.coordination;
    if (unbalanced) p_.unbalanced_force[q] = r.unbalanced_force;
    p_.strain_energy[q] = law_ ? p_.V[q] * law_->strain_energy_density(r.stress) : 0.0;
  }
  if (bad == kNoPoint) {
    no_contact_updates_ += static_cast<std::int64_t>(no_contact_points());
    return;
  }
  const PointResponse& r = responses_[slot_[bad]];
  std::ostringstream msg;
  msg << "constitutive provider '" << provider_->name() << "' ";
  if (r.state == PointState::kFatal) {
    msg << "reports " << (r.failure.empty() ? std::string("a failed update") : r.failure)
        << " for ";
  } else if (!r.stress.allFinite()) {
    msg << "returned a non-finite stress for ";
  } else {
    msg << "returned a non-finite stiffness (" << r.stiffness << ") for ";
  }
  msg << describe_point(bad) << " at step " << step_ << " (t=" << time_ << " s)";
  throw SimulationError(msg.str());
}

std::size_t Solver::no_contact_points() const {
  return static_cast<std::size_t>(
      std::count(p_.state.begin(), p_.state.end(), PointState::kNoContacts));
}

void Solver::handle_points_outside_grid() {
  const auto n = static_cast<std::ptrdiff_t>(p_.size());
  std::size_t first = kNoPoint;
  std::size_t count = 0;
#pragma omp parallel for schedule(static) if (n > kParallelMin) reduction(min : first) reduction(+ : count)
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    if (!grid_.contains(p_.x[q])) {
      first = std::min(first, static_cast<std::size_t>(q));
      ++count;
    }
  }
  if (count == 0) return;
  auto outside = [this](std::size_t q) {
    return ": x = " + vec(p_.x[q]) + " is outside the grid box " + vec(grid_.origin) + " to " +
           vec(grid_.upper());
  };
  if (!p_.x[first].allFinite()) {  // not a geometric exit: the state is broken
    throw SimulationError(describe_point(first) + " has a non-finite position after step " +
                          std::to_string(step_) +
                          ": the run is unstable (reduce solver.cfl or solver.dt_max)");
  }
  if (scene_.solver.on_exit == OnExit::kError) {
    std::ostringstream msg;
    msg << "material point " << p_.id[first]
        << (step_ == 0 ? std::string(" is outside the grid at the start")
                       : " left the grid during step " + std::to_string(step_))
        << outside(first) << " (initial position " << vec(p_.x0[first]) << ")";
    if (count > 1) msg << "; " << count - 1 << " more point(s) too";
    msg << ". Enlarge grid.extent (or move grid.origin), or set solver.on_exit: remove";
    throw SimulationError(msg.str());
  }
  std::vector<char> keep(p_.size(), 1);
  constexpr std::size_t kMaxEvents = 20;
  std::size_t reported = 0;
  for (std::size_t q = first; q < p_.size(); ++q) {
    if (grid_.contains(p_.x[q])) continue;
    keep[q] = 0;
    dF_slots_[slot_[q]] = Mat3::Identity();  // its provider slot idles from now on
    if (reported++ < kMaxEvents) {
      events_.push_back("removed point " + std::to_string(p_.id[q]) + " at step " +
                        std::to_string(step_) + " (left the grid" + outside(q) + ")");
    }
  }
  if (reported > kMaxEvents) {
    events_.push_back("removed " + std::to_string(reported - kMaxEvents) +
                      " more point(s) at step " + std::to_string(step_) + " (left the grid)");
  }
  removed_ += count;
  remove_points(keep);
}

void Solver::remove_points(const std::vector<char>& keep) {
  energy_.points_changed();
  compact(p_.id, keep);
  compact(p_.region, keep);
  compact(p_.m, keep);
  compact(p_.V, keep);
  compact(p_.V0, keep);
  compact(p_.x, keep);
  compact(p_.x0, keep);
  compact(p_.v, keep);
  compact(p_.C, keep);
  compact(p_.F, keep);
  compact(p_.dF, keep);
  compact(p_.sigma, keep);
  compact(p_.stiffness, keep);
  compact(p_.strain_energy, keep);
  compact(p_.rotation, keep);
  compact(p_.porosity, keep);
  compact(p_.coordination, keep);
  compact(p_.unbalanced_force, keep);
  compact(p_.state, keep);
  compact(slot_, keep);
}

}  // namespace mpmdem::mpm

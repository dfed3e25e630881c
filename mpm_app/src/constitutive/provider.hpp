// Constitutive providers: the one interface through which the MPM gets stresses.
// A provider owns whatever state its points need (local: the stress; remote: RVEs on the
// DEM server) and is called once per step with the whole batch, so a remote provider
// makes one exchange per step.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "constitutive/point_state.hpp"

namespace mpmdem::mpm {

using Mat3 = Eigen::Matrix3d;

// Per-point results of one update. Optional fields are filled only when the scene asks.
struct PointResponse {
  Mat3 stress = Mat3::Zero();  // Cauchy, tension positive [Pa]
  double stiffness = 0.0;      // constrained modulus estimate for the CFL step [Pa]
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();  // mean particle rotation [rad]
  double porosity = 0.0;
  double coordination = 0.0;
  double unbalanced_force = 0.0;
  PointState state = PointState::kOk;
  std::string failure;  // kFatal: what failed, for messages; empty otherwise
};

// Wall times of the last update (remote: one exchange with the DEM servers).
struct ProviderTiming {
  double exchange_s = 0.0;  // the whole exchange as the client saw it
  double dem_max_s = 0.0;   // slowest server rank's backend time
  double dem_mean_s = 0.0;  // mean over the server ranks
};

class ConstitutiveProvider {
 public:
  virtual ~ConstitutiveProvider() = default;
  virtual std::string name() const = 0;
  // Set the starting stress of every point (e.g. geostatic) and get the first response.
  virtual void initialise(const std::vector<Mat3>& initial_stress,
                          std::vector<PointResponse>& out) = 0;
  // Apply one incremental deformation gradient per point over dt.
  virtual void update(const std::vector<Mat3>& dF, double dt, std::int64_t step, double time,
                      std::vector<PointResponse>& out) = 0;
  // Continue a checkpointed run: the state of every point is the given stress (local
  // models) or was restored by the provider's own means (remote: servers started with
  // --restore, asked for their current state). Default: initialise(stress).
  virtual void resume(const std::vector<Mat3>& stress, std::vector<PointResponse>& out) {
    initialise(stress, out);
  }
  // Ask the provider to save its state under dir (remote: the servers do it).
  virtual void checkpoint(const std::string& dir, std::int64_t step) {
    (void)dir;
    (void)step;
  }
  // Timing of the last update (remote; zeros for local models).
  virtual ProviderTiming last_timing() const { return {}; }
  // Each point's RVE backend time in the last update [s] and the server rank that ran it
  // (remote; false and untouched for local models).
  virtual bool last_rve_costs(std::vector<double>& /*cost_s*/, std::vector<int>& /*rank*/) const {
    return false;
  }
  // Particles in all RVEs at initialisation (remote; 0 for local models).
  virtual std::int64_t rve_particles() const { return 0; }
  // DEM server ranks this process is coupled to (remote; 0 for local models).
  virtual int dem_ranks() const { return 0; }
  // Load-balance migrations so far in this process (remote; coupling.load_balance).
  virtual std::int64_t rebalances() const { return 0; }
  // Lazy RVE evaluation (remote; coupling.lazy_tolerance): RVE runs and skipped runs so far
  // (over the whole run, also across a resume).
  virtual std::int64_t rve_evaluations() const { return 0; }
  virtual std::int64_t rve_skipped() const { return 0; }
  // State a provider keeps between steps that a checkpoint must carry (remote: the pending
  // accumulated dF of lazily skipped RVEs); restored after resume().
  virtual std::vector<double> save_state() const { return {}; }
  virtual void load_state(const std::vector<double>& /*state*/) {}
  // Orderly end (remote: shutdown message).
  virtual void finish() {}
};

}  // namespace mpmdem::mpm

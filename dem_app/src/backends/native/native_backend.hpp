// The native RVE backend (coupling.backend: native): YADE's RVE mechanics compiled in C++,
// no Python. Same protocol behaviour as the YADE backend (backends/yade_backend.cpp with
// dem_app/python/mpmdem_rve.py): initial consolidation to RveInit's stress, flip and tiling,
// checkpoint and migration (one compact binary state per RVE). What every DEM backend does
// per request (substep rule, the split of dF, status, kFlagSkip cache, fault messages) is the
// RveDriver's (rve_driver.hpp); this backend is its RveStepper: the DEM stepping of one RVE.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "backend.hpp"
#include "backends/native/binary_state.hpp"
#include "backends/native/neighbour_list.hpp"
#include "backends/native/rve_preparation.hpp"
#include "mpmdem/config/schema.hpp"
#include "rve_driver.hpp"
#include "substep_rule.hpp"

namespace mpmdem::dem {

struct NativeParams {
  std::string packing_dir;  // absolute or relative to the working directory
  std::vector<std::string> packings;
  std::int64_t seed = 1;
  int inline_spheres = 60;
  SubstepRule substeps;  // DEM substeps per update (coupling.native.ns_rule, ns, ...)
  double damping = 0.2;
  // The DEM time step of the updates over the packing's (coupling.native.time_step_scale);
  // the consolidation keeps the packing's.
  double time_step_scale = 1;
  double ke_threshold = 10;
  bool stiffness = true;
  double consolidation_tol = 1e-3, consolidation_unbalanced = 0.01;
  long consolidation_max_steps = 200000;
  bool consolidation_warn = false;  // consolidation_on_failure: warn
  // Folder of consolidated states reused across runs and ranks (rve_preparation.hpp); empty:
  // none (the RVEs of a rank still share one consolidation per distinct key).
  std::string consolidation_cache;
  double verlet_skin = 0.5;
  // Contact law of every RVE (coupling.native.contact_law, restitution_normal).
  native::ContactLaw law;
};

class NativeBackend final : public RveBackend, private RveStepper {
 public:
  explicit NativeBackend(const NativeParams& p);
  std::string name() const override { return "native"; }
  void setup(const BackendContext& ctx) override;
  void initialise(const protocol::RveInit* init, protocol::RveReply* reply) override;
  void step(const protocol::ControlHeader& header, const protocol::RveRequest* req,
            protocol::RveReply* reply) override;
  // One file per rank: <dir>/native_rank<r>.bin (RVE ids and their binary states).
  void checkpoint(const std::filesystem::path& dir) override;
  void restore(const std::filesystem::path& dir) override;
  std::string export_rve(std::uint64_t gid) override;
  void adopt(std::uint64_t first_rve, std::uint64_t n_rve,
             std::map<std::uint64_t, std::string> incoming) override;
  std::string last_fault_message() const override { return driver_.last_fault(); }

  // For tests and benchmarks: owned RVE k (local index).
  native::RveRecord& rve(std::size_t k) { return rves_[k]; }
  const native::NeighbourList& neighbour_list(std::size_t k) const { return lists_[k]; }
  // Apply dF to RVE k over ns substeps (split_increment: the velGrad lag corrected).
  void burst(std::size_t k, const double* dF, int ns) { split_increment(*this, k, dF, ns); }
  // Threads over the rank's RVEs in step(): OMP_NUM_THREADS if set, else 1 (each RVE is
  // independent, so the results do not depend on it).
  int threads() const { return threads_; }
  void set_threads(int n) { threads_ = n < 1 ? 1 : n; }
  // What the last initialise() consolidated, copied and read from the cache.
  const native::PreparationTally& preparation_tally() const { return last_tally_; }

 private:
  // Packing of RVE `point` (the draw of coupling.native.seed; empty: a built cloud).
  std::string packing_name(std::uint64_t point) const;
  // The packing's starting state and its hash, read once per name.
  struct Packing {
    native::RveState state;
    native::StateHash hash;
  };
  const Packing& packing(const std::string& name);
  native::RveState cloud(std::uint64_t point) const;
  void fill_reply(std::size_t k, std::int32_t status, std::int32_t n_sub,
                  protocol::RveReply& reply) const;
  void regularise(std::size_t k, std::uint64_t step);
  // RveStepper: the DEM stepping of RVE k.
  double dem_dt(std::size_t k) const override { return rves_[k].state.dt; }
  Eigen::Matrix3d trsf(std::size_t k) const override { return rves_[k].state.cell.trsf; }
  Eigen::Matrix3d pending_vel_grad(std::size_t k) const override {
    return rves_[k].state.cell.pending_vel_grad();
  }
  void set_vel_grad(std::size_t k, const Eigen::Matrix3d& l) override {
    rves_[k].state.cell.set_vel_grad(l);
  }
  void substep(std::size_t k) override;
  void end_burst(std::size_t k) override;
  RveEnergy energy(std::size_t k) const override;
  void measure(std::size_t k, std::uint64_t step, std::int32_t status, std::int32_t ns,
               protocol::RveReply& reply) override;
  void log_preparation(const native::PreparationTally& t, double seconds, double cpu_seconds) const;

  NativeParams p_;
  BackendContext ctx_;
  std::vector<native::RveRecord> rves_;
  std::vector<native::NeighbourList> lists_;
  RveDriver driver_;
  // Packings read once per name: the paper scene's 70,389 RVEs draw 8 packings, and parsing
  // a 600 KB text file per RVE took minutes.
  std::map<std::string, Packing> packing_cache_;
  std::unique_ptr<native::ConsolidationCache> consolidation_cache_;  // null: none
  native::PreparationTally last_tally_;
  int threads_ = 1;
};

NativeParams native_params(const config::Config& cfg);
std::unique_ptr<RveBackend> make_native_backend(const config::Config& cfg);

}  // namespace mpmdem::dem

// The per-RVE driver: what every DEM backend does with one kStep request, written once. For
// each owned RVE it
//   * serves a kFlagSkip request from its cache of the RVE's last reply (n_substeps 0),
//   * takes the substep count from the scene's rule (substep_rule.hpp),
//   * splits the increment dF into that many DEM steps with the velGrad lag corrected
//     (split_increment below: after the burst the cell's trsf is dF trsf_before to round-off),
//   * decides the status from the RVE's kinetic energy (rve_status_rule.hpp),
//   * has the backend measure its reply, times it (RveReply::cost_s), caches it, and names
//     the faulty RVEs in last_fault() (RankReport::message).
// A backend writes only the DEM stepping, through one of two interfaces:
//   * RveStepper: one RVE at a time (native; the driver runs the RVEs over OpenMP threads);
//   * BatchStepper: all active RVEs of the rank at once (cuda: one kernel launch, which runs
//     the same split and status rule on the device, backends/batch/rve_step.hpp).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mpmdem/protocol.hpp"
#include "substep_rule.hpp"

namespace mpmdem::dem {

// What the status rule needs of an RVE after its update.
struct RveEnergy {
  double kinetic = 0;  // kinetic energy of the fluctuating motion [J]
  double volume = 0;   // cell volume [m^3]
  double p0 = 1;       // reference pressure [Pa] (|mean initial stress|, at least 1)
};

// The DEM stepping of one RVE (owned RVE k, local index). The driver calls, per update:
// set_vel_grad / substep (the burst, from trsf, pending_vel_grad and dem_dt), end_burst,
// energy, then measure. Calls for different k may run on different threads at once.
class RveStepper {
 public:
  virtual ~RveStepper() = default;
  // The RVE's DEM time step [s].
  virtual double dem_dt(std::size_t k) const = 0;
  // Its cell's integrated transformation, and the velocity gradient its next DEM step will
  // apply (a gradient set now first moves the cell one step later: YADE's velGrad lag).
  virtual Eigen::Matrix3d trsf(std::size_t k) const = 0;
  virtual Eigen::Matrix3d pending_vel_grad(std::size_t k) const = 0;
  // Request the velocity gradient of the cell (active from the step after the next one).
  virtual void set_vel_grad(std::size_t k, const Eigen::Matrix3d& l) = 0;
  // One DEM step.
  virtual void substep(std::size_t k) = 0;
  // After the last substep of an update (not after a query): what only a burst changes.
  virtual void end_burst(std::size_t /*k*/) {}
  virtual RveEnergy energy(std::size_t k) const = 0;
  // Keep the cell regular (step: the coupling step) and fill the reply from the RVE's state:
  // `status` as decided (kNoContacts or kNonFinite when measuring finds them), n_substeps ns.
  virtual void measure(std::size_t k, std::uint64_t step, std::int32_t status, std::int32_t ns,
                       protocol::RveReply& reply) = 0;
};

// One RVE's part of a batch step.
struct BatchUpdate {
  bool active = false;         // stepped (false: served from the kFlagSkip cache)
  std::int32_t ns = 0;         // DEM substeps (0: a query, nothing applied)
  const double* dF = nullptr;  // the increment (row-major), null for a query
};

// The DEM stepping of all of a rank's RVEs at once.
class BatchStepper {
 public:
  virtual ~BatchStepper() = default;
  virtual double dem_dt(std::size_t k) const = 0;
  // Advance every active RVE k by its dF over its ns substeps (split_increment's split),
  // decide its status (energy_status), keep its cell regular and fill reply[k] (cost_s aside)
  // and kinetic[k]; leave the inactive ones alone. Throw when the batch itself fails.
  virtual void step_batch(const protocol::ControlHeader& header,
                          const std::vector<BatchUpdate>& updates, protocol::RveReply* reply,
                          double* kinetic) = 0;
};

// Apply the increment dF (row-major) to RVE k over ns DEM steps: before step j the velocity
// gradient pending for it is known, so the one after it is chosen from the remaining gap to
// dF trsf_start, uniform over the rest (j = 1) and exact on the last step (j = ns - 1); the
// one left pending for the next update is this one's mean rate (dF - I) / (ns dt) (rate
// continuity: docs/dem_backend.md, "velGrad lag at ns = 2").
void split_increment(RveStepper& s, std::size_t k, const double* dF, int ns);

class RveDriver {
 public:
  RveDriver(const SubstepRule& rule, double ke_threshold)
      : rule_(rule), ke_threshold_(ke_threshold) {}

  // One kStep exchange for the RVEs [first_rve, first_rve + n) of this rank: one reply each.
  // `threads` OpenMP threads over the RVEs (the results do not depend on it). An exception
  // of one RVE (a rate update without a valid dt) is rethrown after the loop.
  void step(const protocol::ControlHeader& header, const protocol::RveRequest* req,
            protocol::RveReply* reply, std::size_t n, std::uint64_t first_rve, RveStepper& s,
            int threads);
  void step(const protocol::ControlHeader& header, const protocol::RveRequest* req,
            protocol::RveReply* reply, std::size_t n, std::uint64_t first_rve, BatchStepper& s);
  // After kInitialise: names the RVEs whose first reply is not finite.
  void initialised(const protocol::RveReply* reply, std::size_t n, std::uint64_t first_rve);
  // Forget the cached replies (after initialise, checkpoint, restore): the next replies come
  // from the RVE states, in a run as in one resumed from its checkpoint.
  void forget() { last_reply_.clear(); }
  // The faults of the last initialised()/step(), for RankReport::message; empty if none.
  const std::string& last_fault() const { return fault_; }
  const SubstepRule& rule() const { return rule_; }

 private:
  // Serves RVE k from the cache if asked to and able; returns whether it did.
  bool serve_cached(const protocol::RveRequest& req, std::uint64_t gid, protocol::RveReply& reply);
  // Substeps of an update (0 for a query or an uncached skip).
  int substeps(const protocol::RveRequest& req, double dem_dt) const;
  // Caches the reply of an advanced RVE and notes its fault, if any.
  void record(std::uint64_t gid, std::uint64_t step, const protocol::RveReply& reply,
              double kinetic);

  SubstepRule rule_;
  double ke_threshold_;
  std::map<std::uint64_t, protocol::RveReply> last_reply_;  // kFlagSkip cache (by gid)
  std::string fault_;
};

}  // namespace mpmdem::dem

// The per-RVE driver: see rve_driver.hpp.
#include "rve_driver.hpp"

#include <Eigen/LU>
#include <chrono>
#include <cstddef>
#include <exception>

#include "rve_status_rule.hpp"

namespace mpmdem::dem {

namespace {

using Clock = std::chrono::steady_clock;
using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
using protocol::RveStatus;

static_assert(kEnergyOk == static_cast<std::int32_t>(RveStatus::kOk) &&
                  kEnergyNonFinite == static_cast<std::int32_t>(RveStatus::kNonFinite) &&
                  kEnergyExploding == static_cast<std::int32_t>(RveStatus::kExploding),
              "rve_status_rule.hpp's values are protocol::RveStatus's");

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

bool is(std::int32_t status, RveStatus s) {
  return status == static_cast<std::int32_t>(s);
}

void append(std::string& list, const std::string& item) {
  list += (list.empty() ? "" : "; ") + item;
}

}  // namespace

void split_increment(RveStepper& s, std::size_t k, const double* dF, int ns) {
  const double dt = s.dem_dt(k);
  const Eigen::Matrix3d target = Eigen::Map<const RowMajor3>(dF) * s.trsf(k);
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  for (int j = 1; j <= ns; ++j) {
    const int remaining = ns - j;
    if (j == 1 || remaining == 1) {
      // The gradient active during substep j is the pending one: predict the cell after j
      // and set the next one, uniform over the rest (j = 1) or exact (j = ns - 1).
      const Eigen::Matrix3d l = s.pending_vel_grad(k);
      const Eigen::Matrix3d after = (id + l * dt) * s.trsf(k);
      const Eigen::Matrix3d next = (target * after.inverse() - id) / (remaining * dt);
      s.set_vel_grad(k, next);
    }
    if (remaining == 0) {
      // Pending for the next update's first substep: this update's mean rate (rate
      // continuity). Substep ns still runs with the exact one above.
      s.set_vel_grad(k, (Eigen::Map<const RowMajor3>(dF) - id) / (ns * dt));
    }
    s.substep(k);
  }
}

bool RveDriver::serve_cached(const protocol::RveRequest& req, std::uint64_t gid,
                             protocol::RveReply& reply) {
  if (!(req.flags & protocol::kFlagSkip)) return false;
  const auto t0 = Clock::now();
  const auto cached = last_reply_.find(gid);
  if (cached == last_reply_.end()) return false;
  reply = cached->second;
  reply.n_substeps = 0;
  reply.cost_s = seconds_since(t0);
  return true;
}

int RveDriver::substeps(const protocol::RveRequest& req, double dem_dt) const {
  // A query, or a skip with no reply to repeat (the first one after a restart): nothing moves.
  if (req.flags & (protocol::kFlagQueryOnly | protocol::kFlagSkip)) return 0;
  return rule_.count(req, dem_dt);
}

void RveDriver::record(std::uint64_t gid, std::uint64_t step, const protocol::RveReply& reply,
                       double kinetic) {
  last_reply_[gid] = reply;
  const bool non_finite = is(reply.status, RveStatus::kNonFinite);
  if (!non_finite && !is(reply.status, RveStatus::kExploding)) return;
  append(fault_, "RVE " + std::to_string(gid) + " step " + std::to_string(step) + ": " +
                     (non_finite ? "non-finite values" : "exploding kinetic energy") +
                     " (kinetic energy " + std::to_string(kinetic) + " J)");
}

void RveDriver::step(const protocol::ControlHeader& header, const protocol::RveRequest* req,
                     protocol::RveReply* reply, std::size_t n, std::uint64_t first_rve,
                     RveStepper& s, int threads) {
  fault_.clear();
  // Served from the cache (serially: the map is shared) or advanced (in parallel: each RVE is
  // touched by one thread only).
  std::vector<char> advance(n, 1);
  for (std::size_t k = 0; k < n; ++k) advance[k] = !serve_cached(req[k], first_rve + k, reply[k]);
  std::vector<double> kinetic(n, 0.0);
  std::vector<std::exception_ptr> error(n);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (threads > 1 && n > 1)
  for (std::ptrdiff_t kk = 0; kk < static_cast<std::ptrdiff_t>(n); ++kk) {
    const auto k = static_cast<std::size_t>(kk);
    if (!advance[k]) continue;
    try {
      const auto t0 = Clock::now();
      const int ns = substeps(req[k], s.dem_dt(k));
      if (!(req[k].flags & (protocol::kFlagQueryOnly | protocol::kFlagSkip))) {
        split_increment(s, k, req[k].dF, ns);
        s.end_burst(k);
      }
      const RveEnergy e = s.energy(k);
      kinetic[k] = e.kinetic;
      s.measure(k, header.step, energy_status(e.kinetic, e.volume, ke_threshold_, e.p0), ns,
                reply[k]);
      reply[k].cost_s = seconds_since(t0);
    } catch (...) {
      error[k] = std::current_exception();
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (error[k]) std::rethrow_exception(error[k]);
    if (advance[k]) record(first_rve + k, header.step, reply[k], kinetic[k]);
  }
}

void RveDriver::step(const protocol::ControlHeader& header, const protocol::RveRequest* req,
                     protocol::RveReply* reply, std::size_t n, std::uint64_t first_rve,
                     BatchStepper& s) {
  const auto t0 = Clock::now();
  fault_.clear();
  std::vector<BatchUpdate> updates(n);
  std::size_t active = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (serve_cached(req[k], first_rve + k, reply[k])) continue;
    BatchUpdate& u = updates[k];
    u.active = true;
    u.ns = substeps(req[k], s.dem_dt(k));
    if (!(req[k].flags & (protocol::kFlagQueryOnly | protocol::kFlagSkip))) u.dF = req[k].dF;
    ++active;
  }
  std::vector<double> kinetic(n, 0.0);
  s.step_batch(header, updates, reply, kinetic.data());
  // The batch's time shared by its RVEs (what the load balance weighs).
  const double cost = active ? seconds_since(t0) / static_cast<double>(active) : 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!updates[k].active) continue;
    reply[k].cost_s = cost;
    record(first_rve + k, header.step, reply[k], kinetic[k]);
  }
}

void RveDriver::initialised(const protocol::RveReply* reply, std::size_t n,
                            std::uint64_t first_rve) {
  fault_.clear();
  forget();
  for (std::size_t k = 0; k < n; ++k) {
    if (is(reply[k].status, RveStatus::kNonFinite)) {
      append(fault_, "RVE " + std::to_string(first_rve + k) + " step 0: non-finite values");
    }
  }
}

}  // namespace mpmdem::dem

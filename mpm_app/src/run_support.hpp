// Helpers of the run driver (run_driver.cpp): the stop request set by SIGINT/SIGTERM, names
// of the scene's enums as summary.json writes them, checks and clocks, figures for summary.json.
#pragma once

#include <csignal>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "grid.hpp"
#include "particles.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

class BarVibrationMonitor;
class Solver;

namespace run_support {

bool stop_requested();
void clear_stop_request();

// SIGINT/SIGTERM ask the run to stop after the current step, for the guard's lifetime.
class SignalGuard {
 public:
  explicit SignalGuard(bool active);
  ~SignalGuard();
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

 private:
  bool active_;
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

const char* verification_name(VerificationKind kind);
double total_mass(const Particles& p);
// Sum of the node masses m_i (after a P2G: the mass the grid carries).
double total_mass(const Grid& g);
// Names the first non-finite value of the state, or returns "" if all are finite.
std::string find_non_finite(const Particles& p);
// CPU time of the whole process (all threads) [s].
double process_cpu_time();
std::string format_seconds(double s);

// summary.json's stop reason from the run's status and the column's end reason ("" if none).
std::string stop_reason(const std::string& status, const std::string& column_end);
// The figures of the scene's verification kind (empty for none; bar: null if not monitored).
std::vector<std::pair<std::string, double>> verification_figures(const Scene& scene,
                                                                 const Particles& p,
                                                                 const BarVibrationMonitor* bar);
// The remote model's counters for summary.json (RVE spheres, rebalances, evaluations, ...).
std::vector<std::pair<std::string, double>> remote_figures(Solver& solver,
                                                           std::int64_t rve_particles);

}  // namespace run_support
}  // namespace mpmdem::mpm

// One run of a scene, from a validated Scene to a finished run directory: particles,
// constitutive provider, solver (or a checkpoint's state); the time loop over the run's
// observers (run/observer.hpp: step log, verification, column collapse, outputs,
// checkpoints, progress); summary.json from the run's figures and every observer's.
//
// RunResult::exit_code, returned by mpm_app, and summary.json's "status" follow how the run
// ended: run_status.hpp (0 complete or truncated, 2 scene/directory fault, 3 handshake
// refused, 4 failed, 130 interrupted).
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>

#include "constitutive/provider.hpp"
#include "output/summary_json.hpp"
#include "particles.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

struct RunOptions {
  std::string out_dir;  // empty: runs/<scene>-<UTC timestamp>
  int threads = 0;      // > 0: overrides solver.threads
  bool force = false;   // reuse a directory that holds an earlier run
  // Continue the run in out_dir from this checkpoint (checkpoints/step_<n>; "latest": the
  // newest complete one). The DEM servers must have been started with --restore <it>/dem.
  std::string resume;
  // > 0: stop after this many steps in all (counted from step 0, also on resume) with
  // status "truncated" and exit code 0: fixed workloads for benchmarks (scaling study).
  std::int64_t max_steps = 0;
  bool handle_signals = true;            // install SIGINT/SIGTERM handlers for the run
  std::ostream* out = nullptr;           // progress and events (nullptr: std::cout)
  std::ostream* err = nullptr;           // errors (nullptr: std::cerr)
  Particles* final_particles = nullptr;  // if set, receives a copy of the final state
  // If set, builds the constitutive provider instead of the scene's model (tests inject
  // faulty or instrumented providers through it).
  std::function<std::unique_ptr<ConstitutiveProvider>(const Scene&, std::size_t n_points)>
      provider_factory;
  // If set, the wall clock (seconds from any fixed origin) that the run's wall time and its
  // time-triggered checkpoints read instead of std::chrono::steady_clock (tests inject a
  // deterministic one). The per-phase step timings always read the real clock.
  std::function<double()> clock;
};

struct RunResult {
  int exit_code = 0;
  std::string run_dir;  // empty if the run never got a directory
  RunSummary summary;
};

RunResult run_scene(const Scene& scene, const RunOptions& options);

// Asks a running run_scene to stop after the current step (what the signal handler does).
void request_stop();

}  // namespace mpmdem::mpm

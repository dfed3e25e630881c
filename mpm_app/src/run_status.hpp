// How a run ended: the one place that maps it to summary.json's "status" and to mpm_app's
// exit code (docs/outputs.md, "Exit codes").
//
//   status        summary.json   exit  when
//   kComplete     "complete"     0     the end time, the column at rest or its duration
//   kTruncated    "truncated"    0     --max-steps reached (a fixed workload for benchmarks)
//   kInterrupted  "interrupted"  130   SIGINT/SIGTERM: stopped after the current step
//   kConfigError  "failed"       2     the scene, the command line or the run directory
//   kRefused      "failed"       3     the handshake refused the peer (versions, config hash)
//   kFailed       "failed"       4     the simulation failed: SimulationError, non-finite
//                                      state, no DEM server, a peer fault, an I/O error
#pragma once

#include <exception>

namespace mpmdem::mpm {

enum class RunStatus { kComplete, kTruncated, kInterrupted, kConfigError, kRefused, kFailed };

// summary.json's "status" of a run that ended so.
const char* status_text(RunStatus status);
// A run that failed (status "failed": kConfigError, kRefused, kFailed).
bool is_failure(RunStatus status);
// summary.json's stop reason ("stop": {"reason": ...}) of a run that ended so: "end_time",
// "max_steps", "interrupted" or "failed". An observer that ended a complete run replaces
// "end_time" with its own reason (the column collapse: "duration", "at_rest").
const char* stop_reason(RunStatus status);
// mpm_app's exit code of a run that ended so.
int exit_code(RunStatus status);
// How a run ends that `e` stopped: kConfigError for a scene, config or run-directory fault,
// kRefused for a refused handshake, kFailed for anything else.
RunStatus failure_status(const std::exception& e);

}  // namespace mpmdem::mpm

// How a run ended, its summary status and exit code: see run_status.hpp.
#include "run_status.hpp"

#include "errors.hpp"
#include "mpmdem/config/schema.hpp"
#include "mpmdem/errors.hpp"
#include "output/run_directory.hpp"

namespace mpmdem::mpm {

const char* status_text(RunStatus status) {
  switch (status) {
    case RunStatus::kComplete:
      return "complete";
    case RunStatus::kTruncated:
      return "truncated";
    case RunStatus::kInterrupted:
      return "interrupted";
    case RunStatus::kConfigError:
    case RunStatus::kRefused:
    case RunStatus::kFailed:
      break;
  }
  return "failed";
}

bool is_failure(RunStatus status) {
  return status == RunStatus::kConfigError || status == RunStatus::kRefused ||
         status == RunStatus::kFailed;
}

const char* stop_reason(RunStatus status) {
  switch (status) {
    case RunStatus::kComplete:
      return "end_time";
    case RunStatus::kTruncated:
      return "max_steps";
    case RunStatus::kInterrupted:
      return "interrupted";
    case RunStatus::kConfigError:
    case RunStatus::kRefused:
    case RunStatus::kFailed:
      break;
  }
  return "failed";
}

int exit_code(RunStatus status) {
  switch (status) {
    case RunStatus::kComplete:
    case RunStatus::kTruncated:
      return 0;
    case RunStatus::kInterrupted:
      return 130;
    case RunStatus::kConfigError:
      return kExitConfigError;
    case RunStatus::kRefused:
      return kExitHandshakeError;
    case RunStatus::kFailed:
      break;
  }
  return kExitPeerError;
}

RunStatus failure_status(const std::exception& e) {
  if (dynamic_cast<const SceneError*>(&e) || dynamic_cast<const config::ConfigError*>(&e) ||
      dynamic_cast<const RunDirectoryError*>(&e)) {
    return RunStatus::kConfigError;
  }
  if (dynamic_cast<const HandshakeError*>(&e)) return RunStatus::kRefused;
  return RunStatus::kFailed;
}

}  // namespace mpmdem::mpm

#include "constitutive/rve_point_state.hpp"

#include <string>

#include "mpmdem/protocol.hpp"
#include "mpmdem/rve_status.hpp"

namespace mpmdem::mpm {

void read_rve_status(std::int32_t rve_status, PointResponse& r) {
  if (is_fatal(rve_status)) {
    r.state = PointState::kFatal;
    r.failure = "status " + std::to_string(rve_status) + " (" + status_name(rve_status) + ")";
    return;
  }
  r.state = rve_status == static_cast<std::int32_t>(protocol::RveStatus::kNoContacts)
                ? PointState::kNoContacts
                : PointState::kOk;
  r.failure.clear();
}

}  // namespace mpmdem::mpm

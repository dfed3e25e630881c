// The remote provider's reading of an RVE's status on the wire (protocol::RveStatus) as the
// MPM's PointState. Which statuses are fatal, and their names, are mpmdem::is_fatal and
// mpmdem::status_name (interface/include/mpmdem/rve_status.hpp).
#pragma once

#include <cstdint>

#include "constitutive/provider.hpp"

namespace mpmdem::mpm {

// Sets r.state and r.failure from an RVE status: kOk -> kOk, kNoContacts -> kNoContacts
// (failure empty); every fatal status, an unknown code included, -> kFatal with failure
// "status N (name)", e.g. "status 3 (exploding kinetic energy)".
void read_rve_status(std::int32_t rve_status, PointResponse& r);

}  // namespace mpmdem::mpm

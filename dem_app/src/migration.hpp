// Load balance on the server side (MessageKind::kRebalance): move the RVE states whose
// owner changes between the old and the new contiguous partition, point-to-point over the
// server's own communicator, and let each backend adopt its new range.
#pragma once

#include <mpi.h>

#include <vector>

#include "backend.hpp"
#include "mpmdem/partition.hpp"

namespace mpmdem::dem {

// Collective over `comm` (all server ranks; rank r owned old_parts[r] and owns next[r]
// afterwards). Throws std::runtime_error naming the peer rank if a transfer fails, or what
// the backend's export/adopt threw; the rank then reports kBackendError and the client
// aborts the run.
void migrate(RveBackend& backend, const std::vector<Partition>& old_parts,
             const std::vector<Partition>& next, int rank, MPI_Comm comm);

}  // namespace mpmdem::dem

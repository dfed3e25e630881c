// What a constitutive update says about a material point, in the MPM's terms. The local
// models set it; the remote provider reads it from the RVE's status on the wire
// (constitutive/rve_point_state.hpp). A point keeps the state of its last update
// (Particles::state); the output files store it as the enum's int32 value ("status").
#pragma once

#include <cstdint>
#include <vector>

namespace mpmdem::mpm {

enum class PointState : std::int32_t {
  kOk = 0,          // a continuum point: its stress and stiffness hold
  kNoContacts = 1,  // free-flying (an RVE without contacts, a disconnected Drucker-Prager
                    // point): zero stress and stiffness, no affine velocity (G2P)
  kFatal = 2,       // the update failed and the run stops (PointResponse::failure says
                    // why); no point keeps it
};

// The int32 codes the output files store, one per point.
std::vector<std::int32_t> state_codes(const std::vector<PointState>& states);
// Back from stored codes (a checkpoint). Throws std::runtime_error on a code that is not
// a state a point keeps (kOk, kNoContacts).
std::vector<PointState> states_from_codes(const std::vector<std::int32_t>& codes);

}  // namespace mpmdem::mpm

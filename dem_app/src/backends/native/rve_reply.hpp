// The reply of one native RVE from its state (NativeBackend's fill_reply, shared with the
// cuda backend's host side, which replies from a native state after tiling an RVE): status
// kNoContacts without contacts, the symmetrised Love-Weber stress and the stiffness bound
// (kNonFinite if the stress is not finite), the requested outputs.
#pragma once

#include <cstdint>

#include "backends/native/binary_state.hpp"
#include "mpmdem/protocol.hpp"

namespace mpmdem::dem::native {

void reply_from_state(const RveRecord& rec, std::int32_t status, std::int32_t n_sub,
                      std::uint32_t outputs, bool stiffness, protocol::RveReply& reply);

}  // namespace mpmdem::dem::native

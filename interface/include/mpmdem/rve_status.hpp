// The RVE status vocabulary of the coupling contract: which statuses end a run and what each
// is called. The one definition both programs use (the values are protocol::RveStatus).
#pragma once

#include <cstdint>
#include <string>

namespace mpmdem {

// A fatal RVE status: anything but kOk and kNoContacts, an unknown code included (a peer
// that sends a status this build does not know is not trusted to be fine).
bool is_fatal(std::int32_t rve_status);
// "ok", "no contacts", "non-finite values", "exploding kinetic energy", "backend error",
// or "unknown status N".
std::string status_name(std::int32_t rve_status);

}  // namespace mpmdem

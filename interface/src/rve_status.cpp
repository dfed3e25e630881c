#include "mpmdem/rve_status.hpp"

#include "mpmdem/protocol.hpp"

namespace mpmdem {

using protocol::RveStatus;

bool is_fatal(std::int32_t s) {
  return s != static_cast<std::int32_t>(RveStatus::kOk) &&
         s != static_cast<std::int32_t>(RveStatus::kNoContacts);
}

std::string status_name(std::int32_t s) {
  switch (static_cast<RveStatus>(s)) {
    case RveStatus::kOk:
      return "ok";
    case RveStatus::kNoContacts:
      return "no contacts";
    case RveStatus::kNonFinite:
      return "non-finite values";
    case RveStatus::kExploding:
      return "exploding kinetic energy";
    case RveStatus::kBackendError:
      return "backend error";
  }
  return "unknown status " + std::to_string(s);
}

}  // namespace mpmdem

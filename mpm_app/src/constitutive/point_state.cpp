#include "constitutive/point_state.hpp"

#include <stdexcept>
#include <string>

namespace mpmdem::mpm {

std::vector<std::int32_t> state_codes(const std::vector<PointState>& states) {
  std::vector<std::int32_t> codes(states.size());
  for (std::size_t i = 0; i < states.size(); ++i) codes[i] = static_cast<std::int32_t>(states[i]);
  return codes;
}

std::vector<PointState> states_from_codes(const std::vector<std::int32_t>& codes) {
  std::vector<PointState> states(codes.size());
  for (std::size_t i = 0; i < codes.size(); ++i) {
    const std::int32_t c = codes[i];
    if (c != static_cast<std::int32_t>(PointState::kOk) &&
        c != static_cast<std::int32_t>(PointState::kNoContacts)) {
      throw std::runtime_error("point " + std::to_string(i) + " has state code " +
                               std::to_string(c) + ", neither 0 (ok) nor 1 (no contacts)");
    }
    states[i] = static_cast<PointState>(c);
  }
  return states;
}

}  // namespace mpmdem::mpm

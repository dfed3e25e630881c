// The optional per-point fields a remote update fills (PointResponse::rotation, porosity,
// coordination, unbalanced_force), read from the scene's coupling.outputs: the OutputBits
// sent in the handshake (mpmdem/protocol.hpp).
#pragma once

#include <cstdint>

namespace mpmdem::mpm {

struct RveOutputs {
  bool rotation = false;
  bool porosity = false;
  bool coordination = false;
  bool unbalanced_force = false;
};

RveOutputs rve_outputs(std::uint32_t coupling_outputs);

}  // namespace mpmdem::mpm

#include "constitutive/rve_outputs.hpp"

#include "mpmdem/protocol.hpp"

namespace mpmdem::mpm {

RveOutputs rve_outputs(std::uint32_t coupling_outputs) {
  RveOutputs o;
  o.rotation = (coupling_outputs & protocol::kOutputRotation) != 0;
  o.porosity = (coupling_outputs & protocol::kOutputPorosity) != 0;
  o.coordination = (coupling_outputs & protocol::kOutputCoordination) != 0;
  o.unbalanced_force = (coupling_outputs & protocol::kOutputUnbalancedForce) != 0;
  return o;
}

}  // namespace mpmdem::mpm

// Typed errors of the MPM side (the second tier: user/config/run faults with a message that
// says what happened and what to change). Internal invariants use assert().
#pragma once

#include <stdexcept>

namespace mpmdem::mpm {

// A run that must stop: a point left the grid, a stress is not finite, a point inverted.
// The message names the material point id and the step.
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The scene is inconsistent when the state is generated (e.g. a region holds no material
// point positions). The message says which key to change.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace mpmdem::mpm

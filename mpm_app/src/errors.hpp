// Typed errors of the MPM side (the second tier: user/config/run faults with a message that
// says what happened and what to change). Internal invariants use assert().
#pragma once

#include <stdexcept>
#include <string>

namespace mpmdem::mpm {

// A run that must stop: a point left the grid, a stress is not finite, a point inverted.
// The message names the material point id and the step.
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The scene is inconsistent (e.g. a region holds no material point positions, a column
// that cannot collapse). The message says which key to change; a fault of one key carries
// it, so that the scene loader can report it with the key's file and line.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  // A fault of `key` (a dotted path, list items indexed: "regions[0].min"): what() is
  // "<key> <detail>".
  SceneError(const std::string& key, const std::string& detail)
      : std::runtime_error(key + " " + detail), key_(key), detail_(detail) {}
  const std::string& key() const { return key_; }  // empty: not about one key
  const std::string& detail() const { return detail_; }

 private:
  std::string key_, detail_;
};

}  // namespace mpmdem::mpm

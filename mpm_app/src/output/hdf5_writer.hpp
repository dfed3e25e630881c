// The final state in HDF5 (C API), readable with h5py:
//   datasets  id (n, int64), region (n, int32), x, x0, v (n x 3), stress, F (n x 3 x 3,
//             row-major, stress tension positive), volume, mass (n) — SI units; and when the
//             run has them: rotation (n x 3, mean RVE particle rotation [rad]), porosity,
//             coordination (n), status (n, int32: PointState, 0 ok, 1 no contacts);
//   attributes on the root group: time [s], step, scene (name), config_file.
#pragma once

#include <cstdint>
#include <string>

#include "particles.hpp"

namespace mpmdem::mpm {

struct StateInfo {
  double time = 0.0;
  std::int64_t step = 0;
  std::string scene;
  std::string config_file;
};

// Writes `path` through a temporary name and a rename. Throws std::runtime_error.
void write_final_state(const std::string& path, const Particles& p, const StateInfo& info);

}  // namespace mpmdem::mpm

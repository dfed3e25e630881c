// The last line of defence against NaN in the outputs: every step ends with a scan of the
// point state, and a non-finite value stops the run (SimulationError naming the point and the
// step) before any writer sees it. Writers (energies.csv, VTK, HDF5, checkpoints) can only
// be reached with a state that passed the scan.
#pragma once

#include <cstddef>
#include <string>

#include "particles.hpp"

namespace mpmdem::mpm {

struct NonFinite {
  std::size_t point = 0;   // index in Particles
  const char* field = "";  // "position", "velocity", "stress", "deformation gradient", ...
};

// First point (in point order) with a non-finite x, v, sigma, F, V, stiffness, strain energy or
// RVE output (rotation, porosity, coordination, unbalanced force: the fields a remote provider
// returns that no other check looks at); false if none.
bool find_first_non_finite(const Particles& p, NonFinite& where);

}  // namespace mpmdem::mpm

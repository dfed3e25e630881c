// Helpers of the run driver (run_driver.cpp) and its observers (run/): the name of the
// verification kind as summary.json writes it, masses, the non-finite check, clocks.
#pragma once

#include <cstdint>
#include <string>

#include "grid.hpp"
#include "particles.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

namespace run_support {

const char* verification_name(VerificationKind kind);
double total_mass(const Particles& p);
// Sum of the node masses m_i (after a P2G: the mass the grid carries).
double total_mass(const Grid& g);
// Names the first non-finite value of the state, or returns "" if all are finite.
std::string find_non_finite(const Particles& p);
// CPU time of the whole process (all threads) [s].
double process_cpu_time();
std::string format_seconds(double s);

}  // namespace run_support
}  // namespace mpmdem::mpm

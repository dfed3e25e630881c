// The status an RVE's own motion gives it after an update, for every DEM backend: the per-RVE
// driver (rve_driver.cpp) and the batch kernel (backends/batch/rve_step.hpp, host and device)
// call this one function. kNoContacts and a non-finite stress are found later, when the reply
// is measured (they depend on the contacts, not on the motion).
#pragma once

#include <cstdint>

#include "backends/batch/hd.hpp"

namespace mpmdem::dem {

// protocol::RveStatus values (no protocol dependency here: nvcc includes this header;
// rve_driver.cpp checks that they agree).
enum : std::int32_t { kEnergyOk = 0, kEnergyNonFinite = 2, kEnergyExploding = 3 };

// kinetic: the RVE's kinetic energy of fluctuation [J]; volume: its cell's [m^3]; p0: its
// reference pressure (|mean initial stress|, at least 1 Pa) [Pa]; ke_threshold:
// coupling.<backend>.ke_threshold. Non-finite energy: kNonFinite; an energy density above
// ke_threshold p0: kExploding; otherwise kOk.
MPMDEM_HD_INLINE std::int32_t energy_status(double kinetic, double volume, double ke_threshold,
                                            double p0) {
  if (!batch::hd_isfinite(kinetic)) return kEnergyNonFinite;
  if (kinetic / volume > ke_threshold * p0) return kEnergyExploding;
  return kEnergyOk;
}

}  // namespace mpmdem::dem

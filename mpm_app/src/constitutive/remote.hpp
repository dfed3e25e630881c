// The `remote` provider: RVEs on a DEM server (dem_app) reached over MPI ports.
#pragma once

#include <memory>
#include <string>

#include "constitutive/provider.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

// Connects (MPI must be initialised), performs the handshake for n_points RVEs, and
// returns the provider. Throws on connect timeout or handshake mismatch with a message
// naming both values.
std::unique_ptr<ConstitutiveProvider> make_remote_provider(const Scene& scene, std::size_t n_points,
                                                           const std::string& run_dir);

}  // namespace mpmdem::mpm

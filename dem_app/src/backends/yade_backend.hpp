// The YADE backend: this rank's RVEs as resident YADE scenes in an embedded Python 3.11
// (one interpreter per process). The per-RVE work lives in dem_app/python/mpmdem_rve.py;
// the C++ side makes one Python call per exchange. See docs/dem_backend.md.
#pragma once

#include <memory>

#include "backend.hpp"
#include "mpmdem/config/schema.hpp"

namespace mpmdem::dem {

// `cfg`: validated config_version + `coupling:` section (keys coupling.yade.*).
// The returned backend finalizes the interpreter when destroyed (before MPI_Finalize); only
// one YADE backend can exist per process, and none after the first one was destroyed.
std::unique_ptr<RveBackend> make_yade_backend(const config::Config& cfg, const BackendContext& ctx);

}  // namespace mpmdem::dem

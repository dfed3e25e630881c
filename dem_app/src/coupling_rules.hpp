// The rules between keys of the shared `coupling:` section, one function per rule. The
// schema (coupling_schema.hpp) checks each key alone; these check keys against each other
// and against the backend the scene names. Both programs call check_coupling() when they
// load a scene (mpm_app --check-config for a remote model, dem_app before it serves), so a
// scene the DEM server would refuse is refused before anything runs; the backends call the
// rule of their own section again when they are built from a Config. Each throws
// config::ConfigError naming the key, its value, the file and the line, and what to change.
#pragma once

#include <cstdint>
#include <string>

#include "backends/native/contact_law_kind.hpp"
#include "mpmdem/config/schema.hpp"

namespace mpmdem {

namespace dem {
// protocol::OutputBits the named backend computes (backend_catalog.hpp; the server advertises
// them in its Hello; the handshake refuses a client asking for more): every output for the
// DEM backends, none for the elastic stub (a continuum point has no rotation, porosity, ...).
std::uint32_t backend_outputs(const std::string& name);
}  // namespace dem

// The outputs rule and the rules of the scene's coupling.backend (its BackendSpec::check).
void check_coupling(const config::Config& cfg);

// coupling.backend elastic needs the section coupling.elastic (its moduli).
void check_elastic_section(const config::Config& cfg);
// Each name of coupling.outputs is computed by coupling.backend.
void check_outputs_provided(const config::Config& cfg);
// coupling.<backend>.ns_min <= coupling.<backend>.ns_max (backend yade or native).
void check_substep_bounds(const config::Config& cfg, const std::string& backend);
// coupling.<backend>.packings and .packing_spec need .packing_dir, and a .packing_dir needs
// at least one name in .packings (otherwise the library would be ignored and every RVE
// built in place).
void check_packing_library(const config::Config& cfg, const std::string& backend);
// coupling.<backend>.restitution_normal stays 1 (its default) unless contact_law is
// frict_visco: the frict law has no dashpot to set from it.
void check_contact_law(const config::Config& cfg, const std::string& backend);
// The law those keys choose (checked).
dem::native::ContactLaw contact_law(const config::Config& cfg, const std::string& backend);
// With backend cuda, coupling.native.contact_law is frict (the batch kernel has no other).
void check_cuda_contact_law(const config::Config& cfg);
// The three above: what the yade and native backends check of their own section.
void check_rve_backend(const config::Config& cfg, const std::string& backend);
// With backend yade, coupling.yade.consolidation_cache is empty (YADE keeps no cache).
void check_no_yade_consolidation_cache(const config::Config& cfg);
// With backend native, coupling.native.consolidation_cache, when given, names a folder
// (relative to the scene file's folder) that exists or can be created where this user can
// write. A check of the DEM host's file system: dem_app (its --check-config included) and
// the native backend call it, not check_coupling (mpm_app may run on other hosts).
void check_consolidation_cache(const config::Config& cfg);

}  // namespace mpmdem

// Schema of the shared `coupling:` section, declared once. Both programs read this section
// (mpm_app: connection and outputs; dem_app: everything) and hash its canonical form with
// defaults filled in, so a server started with other coupling settings is refused.
#pragma once

#include <cstdint>
#include <string>

#include "mpmdem/config/schema.hpp"

namespace mpmdem {

// Adds every `coupling.*` key (generic, elastic backend, yade backend) to `schema`.
void add_coupling_keys(config::Schema& schema);
// `config_version` + the `coupling:` section: what dem_app validates.
const config::Schema& coupling_schema();

// Canonical text of the `coupling:` section with schema defaults filled in: what both sides
// hash for the handshake (Hello::config_hash = fnv1a64(coupling_canonical_text(cfg))).
// `cfg` is a top-level Config loaded with a schema that includes add_coupling_keys().
std::string coupling_canonical_text(const config::Config& cfg);
// coupling.outputs as protocol::OutputBits.
std::uint32_t coupling_output_bits(const config::Config& cfg);
// The bit of one output name ("porosity"), 0 for an unknown name.
std::uint32_t coupling_output_bit(const std::string& name);
// The names of a set of output bits, "rotation, porosity" ("none" for 0).
std::string coupling_output_names(std::uint32_t bits);
// The rules between keys of the section: coupling_rules.hpp.

}  // namespace mpmdem

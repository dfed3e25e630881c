// The coupling contract's keys: the generic part of the scene's `coupling:` section, which
// both programs read (the backend's name, the connection, the exchange, the requested
// per-RVE outputs), and the canonical text both hash for the handshake. The DEM backends'
// own sections (coupling.elastic, .yade, .native, .cuda) are declared by dem_app; mpm_app
// accepts them unread and dem_app validates them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mpmdem/config/schema.hpp"

namespace mpmdem {

// Adds `coupling` and its generic keys to `schema`. `backends`: the names coupling.backend
// may take, each of which the caller declares a section for (dem_app); empty (mpm_app): any
// non-empty name, and the section's other keys are taken as sections the DEM server
// validates (KeySpec::open_sections).
void add_generic_coupling_keys(config::Schema& schema, const std::vector<std::string>& backends);

// Canonical text of the scene's `coupling:` section, what both sides hash for the handshake
// (Hello::config_hash = fnv1a64(coupling_canonical_text(cfg))): one flow map with keys sorted
// bytewise holding every generic key, normalised, with its default where absent, and every
// other key of the section (a backend's section) as written in the file (canonical_yaml);
// absent backend sections are left out. The same text whatever schema `cfg` was loaded
// with, so mpm_app, which does not know the backends' keys, and dem_app, which does, agree.
// docs/protocol.md states the rule for other clients.
std::string coupling_canonical_text(const config::Config& cfg);

// coupling.outputs as protocol::OutputBits.
std::uint32_t coupling_output_bits(const config::Config& cfg);
// The bit of one output name ("porosity"), 0 for an unknown name.
std::uint32_t coupling_output_bit(const std::string& name);
// The names of a set of output bits, "rotation, porosity" ("none" for 0).
std::string coupling_output_names(std::uint32_t bits);

}  // namespace mpmdem

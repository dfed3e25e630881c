// The key of a consolidated native RVE state (issue 36, item 5): every input that decides the
// bits of an RVE's state after its preparation (consolidation.hpp: consolidate, then
// finish_preparation), so that two RVEs with equal keys get equal states and one
// consolidation serves both (rve_preparation.hpp), in one run or, through the cache on disk
// (consolidation_cache.hpp), in a later one. Its parts, as raw bytes:
//  * the key's format version (kKeyVersion) and the binary state's format (binary_state.hpp);
//  * the code's fingerprint (code_fingerprint): the bits of a small fixed consolidation run
//    by this build, so that a change of the DEM step, the contact law or the servo (or a
//    machine that rounds differently) gives other keys instead of stale states;
//  * the packing: FNV-1a 64 of the RVE's whole starting state (encode: cell, material, dt,
//    every sphere and contact) and its size, so a packing is known by its content, not its
//    name (a rebuilt library with the same names gives other keys);
//  * the target stress, its 9 components bit for bit (the servo reads the diagonal);
//  * the contact law when it is not frict (frict_visco: its beta_n and visco_fingerprint);
//  * the parameters: stress and unbalanced-force tolerances, step limit, strain-rate bound,
//    damping and Verlet skin (coupling.native.consolidation_*, damping, verlet_skin).
// consolidation_on_failure is not part of it: a state kept unconverged (warn) is stored as
// such, and a run with `error` refuses it as a fresh consolidation would.
#pragma once

#include <cstdint>
#include <string>

#include "backends/native/consolidation.hpp"
#include "backends/native/rve_state.hpp"

namespace mpmdem::dem::native {

// Bump when the key's layout or the meaning of a stored state changes.
inline constexpr std::uint32_t kKeyVersion = 1;

struct ConsolidationKey {
  std::string bytes;  // the whole key (compared in full when a cache entry is read)
  // 16 hex digits of FNV-1a 64 of bytes: the cache entry's file name (without extension).
  std::string name() const;
  bool operator<(const ConsolidationKey& o) const { return bytes < o.bytes; }
  bool operator==(const ConsolidationKey& o) const { return bytes == o.bytes; }
};

// FNV-1a 64 of the encoded state (binary_state.hpp) and its size in bytes.
struct StateHash {
  std::uint64_t hash = 0;
  std::uint64_t size = 0;
};
StateHash state_hash(const RveState& s);

// The bits of this build's consolidation of a fixed 24-sphere cloud (computed once per
// process, a few milliseconds).
std::uint64_t code_fingerprint();
// The same run with the frict_visco law (e_n 0.5): part of the keys of frict_visco RVEs.
std::uint64_t visco_fingerprint();

ConsolidationKey consolidation_key(const StateHash& packing, const double (&stress)[9],
                                   const ConsolidationParams& p, double verlet_skin,
                                   const ContactLaw& law = ContactLaw{});

}  // namespace mpmdem::dem::native

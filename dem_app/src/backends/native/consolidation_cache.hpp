// Consolidated native RVE states on disk (coupling.native.consolidation_cache: a folder), one
// file per key (consolidation_key.hpp), <key name>.consol, so that a later run, or another
// rank of the same run, takes the state instead of consolidating again. A file holds:
//   "MPMDCC01", the key's size and bytes, the entry's size and bytes (DEM steps, converged,
//   unbalanced force, the encoded state: binary_state.hpp), FNV-1a 64 of all that.
// It is written to a temporary file in the folder and renamed over the final name, so a
// reader (any rank, any run) sees the whole file or none, and concurrent writers of one key
// (which write the same bytes) leave one whole file. A file that is truncated, fails its
// checksum, holds another key (a name collision) or does not decode is not used: load()
// warns, counts it and returns nothing, and the caller consolidates again and stores the
// state over it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include "backends/native/consolidation_key.hpp"
#include "backends/native/rve_state.hpp"

namespace mpmdem::dem::native {

// What an RVE's preparation leaves (consolidate, then finish_preparation): the state with
// its force scratch released, and what the backend reports of it.
struct PreparedRve {
  RveState state;
  double unbalanced = 0;  // unbalanced force ratio after the preparation's last step
  long steps = 0;         // DEM steps of the consolidation (0: no stress to reach)
  bool converged = true;  // false: kept as reached (consolidation_on_failure: warn)
};

std::string encode_entry(const ConsolidationKey& key, const PreparedRve& p);
// nullopt with *why set when the bytes are not a whole entry of this key.
std::optional<PreparedRve> decode_entry(const std::string& bytes, const ConsolidationKey& key,
                                        std::string* why);

class ConsolidationCache {
 public:
  // dir: the folder (created if missing); log: where load() writes its warnings.
  ConsolidationCache(std::filesystem::path dir, std::ostream& log);
  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path file(const ConsolidationKey& key) const;
  // The stored state of this key, or nullopt (no file, or an unusable one: counted in
  // rejected()).
  std::optional<PreparedRve> load(const ConsolidationKey& key);
  // Writes the entry atomically (temporary file + rename). Throws std::runtime_error naming
  // the file if it cannot be written.
  void store(const ConsolidationKey& key, const PreparedRve& p);
  std::size_t rejected() const { return rejected_; }

 private:
  std::filesystem::path dir_;
  std::ostream& log_;
  std::size_t rejected_ = 0;
};

}  // namespace mpmdem::dem::native

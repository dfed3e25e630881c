// The compact binary state of one native RVE, for checkpoints and load-balance migration
// (RveBackend::export_rve / adopt): raw little-endian doubles of every field, so a restored
// or migrated RVE continues bit for bit as it would have where it was (the Verlet list is
// not saved: it is rebuilt, which changes no result).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "backends/native/rve_state.hpp"

namespace mpmdem::dem::native {

// What the backend keeps per RVE besides the mechanics.
struct RveRecord {
  RveState state;
  std::uint64_t point = 0;  // material point (names its packing draw)
  double p0 = 1.0;          // initial mean pressure magnitude [Pa] (explosion threshold)
  std::string packing;      // packing name, empty for a built cloud
  std::int64_t tilings = 0;
  double unbalanced = 0;  // unbalanced force ratio after the last step (forces not kept)
};

std::string encode(const RveRecord& r);
// Throws std::runtime_error on a blob that is not a native RVE state.
RveRecord decode(const std::string& blob);

// One rank's checkpoint file (native_rank<r>.bin): a magic, the RVE count, then per RVE its
// global index, its blob's size and the blob (encode). Written by NativeBackend::checkpoint;
// read back by restore and by dem_app/tools/native_checkpoint_bench.
void write_checkpoint_header(std::ostream& out, std::uint64_t count);
void write_checkpoint_record(std::ostream& out, std::uint64_t gid, const std::string& blob);
// Calls fn(gid, blob) for each record of the file. Throws std::runtime_error naming the file
// if it is not a native checkpoint or is truncated.
void read_checkpoint(const std::filesystem::path& file,
                     const std::function<void(std::uint64_t, const std::string&)>& fn);

}  // namespace mpmdem::dem::native

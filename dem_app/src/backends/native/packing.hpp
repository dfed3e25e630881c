// Packings of native RVEs.
//  * read_packing: a packing exported from a YADE library (.yade.bz2) by
//    scripts/export_native_packings (dem_app/python/mpmdem_native_packing.py): every
//    sphere, the cell, dt, the material and every contact with its normal, shear force and
//    stiffnesses, in full precision, so the native RVE continues exactly the YADE state.
//  * build_cloud: a non-overlapping random cloud in a periodic cube (YADE's makeCloud
//    parameters: mean radius and relative fuzz), to be consolidated (consolidation.hpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "backends/native/rve_state.hpp"

namespace mpmdem::dem::native {

inline constexpr const char* kPackingMagic = "mpmdem-native-packing";
inline constexpr const char* kPackingExtension = ".native.txt";

// Throws std::runtime_error naming the file and line on a malformed file.
RveState read_packing(const std::filesystem::path& file);
void write_packing(const RveState& s, const std::filesystem::path& file);

struct CloudParams {
  int n_spheres = 60;
  double r_min = 0.92e-3, r_max = 1.38e-3;  // radii uniform in [r_min, r_max] [m]
  double porosity = 0.75;                   // of the cloud (cell sized to it)
  Material material;
  std::uint64_t seed = 1;
};
RveState build_cloud(const CloudParams& p);

}  // namespace mpmdem::dem::native

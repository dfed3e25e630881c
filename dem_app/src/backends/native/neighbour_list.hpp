// Verlet list of the sphere pairs (and periodic images) that may come into contact before the
// next rebuild: |x_j + hsize c - x_i| < r_i + r_j + skin when built. It is rebuilt only when
// the displacements since the last build, together with the cell's deformation acting on the
// image offsets, may have used up the skin:
//   2 max_i |x_i - x_i,ref| + |(H - H_ref) H_ref^-1|_F (extent + largest cutoff) >= skin
// (extent: the diagonal of the spheres' bounding box at the build). Under the small
// homogeneous increments of a coupling step this is rare. The list also maps pairs to the
// RVE's real contacts, so that only pairs without a contact are tested for a new one.
// Storage: compressed rows (pairs of sphere i are contiguous, i < j), 12 bytes per pair
// (j, three 16-bit image offsets, a contact flag), 4 per contact, 24 per sphere (x_ref),
// sized exactly at each build.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "backends/native/rve_state.hpp"

namespace mpmdem::dem::native {

class NeighbourList {
 public:
  // skin in units of the smallest radius (YADE's collider: verletDist = 0.5 min radius).
  explicit NeighbourList(double skin_factor = 0.5) : skin_factor_(skin_factor) {}
  // Rebuilds if the skin may be used up (or the list was invalidated).
  void ensure(const RveState& s);
  void invalidate() { valid_ = false; }
  std::int64_t rebuilds() const { return rebuilds_; }
  std::size_t heap_bytes() const;  // allocated capacity of the list's arrays

  // Pairs of sphere i (< j) are the rows [row_begin(i), row_begin(i + 1)) (compressed rows).
  std::size_t n_pairs() const { return pair_j_.size(); }
  std::size_t row_begin(std::size_t i) const { return row_[i]; }
  std::uint32_t pair_j(std::size_t p) const { return pair_j_[p]; }
  Eigen::Vector3i pair_cell(std::size_t p) const {
    return Eigen::Vector3i(pair_[p].c[0], pair_[p].c[1], pair_[p].c[2]);
  }
  bool pair_cell_zero(std::size_t p) const {
    return (pair_[p].c[0] | pair_[p].c[1] | pair_[p].c[2]) == 0;
  }
  bool pair_in_contact(std::size_t p) const { return pair_[p].in_contact != 0; }
  // Bookkeeping of the contact <-> pair map; call alongside Contacts::add / swap_remove.
  void contact_added(std::size_t pair, std::size_t contact);
  void contact_removed(std::size_t contact, std::size_t last);

 private:
  void rebuild(const RveState& s);
  // Index of the pair (a, b, c) or (b, a, -c); -1 if the list does not hold it.
  std::int64_t find(std::uint32_t a, std::uint32_t b, const Eigen::Vector3i& c) const;

  // Image offset of a pair (cellDist; |c| < 2^15 is checked at the build) and its flag.
  struct PairImage {
    std::int16_t c[3];
    std::uint8_t in_contact;
  };

  double skin_factor_;
  bool valid_ = false;
  std::int64_t rebuilds_ = 0;
  double skin_ = 0, extent_ = 0, max_cutoff_ = 0;
  Eigen::Matrix3d h_ref_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d h_ref_inv_ = Eigen::Matrix3d::Identity();
  std::vector<Vec3> x_ref_;
  std::vector<std::uint32_t> row_;     // n + 1 row starts
  std::vector<std::uint32_t> pair_j_;  // second sphere of each pair
  std::vector<PairImage> pair_;
  std::vector<std::int32_t> contact_pair_;  // pair index of each contact, -1: none
};

}  // namespace mpmdem::dem::native

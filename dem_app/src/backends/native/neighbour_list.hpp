// Verlet list of the sphere pairs (and periodic images) that may come into contact before the
// next rebuild: |x_j + hsize c - x_i| < r_i + r_j + skin when built. It is rebuilt only when
// the displacements since the last build, together with the cell's deformation acting on the
// image offsets, may have used up the skin:
//   2 max_i |x_i - x_i,ref| + |(H - H_ref) H_ref^-1|_F (extent + largest cutoff) >= skin
// (extent: the diagonal of the spheres' bounding box at the build). Under the small
// homogeneous increments of a coupling step this is rare. The list also maps pairs to the
// RVE's real contacts, so that only pairs without a contact are tested for a new one.
// Storage: compressed rows (pairs of sphere i are contiguous, i < j), 6 bytes per pair
// (j with the contact flag in its top bit, the 16-bit index of its image offset in a table of
// the build's distinct offsets, 6 bytes each: a few dozen), 12 per sphere (x_ref
// in single precision, its rounding added to the displacement bound), sized exactly at
// each build; nothing per contact (a removed contact's pair is found in its row).
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
  void invalidate() { valid_ = false, moved_iter_ = -1; }
  // The reference positions of the skin check (x, y, z floats per sphere), nullptr if the
  // list is not valid for n spheres. Newton computes max_i |x_i - x_ref_i|^2 with the new
  // positions as ensure() would (the same bits) and hands it over with moved(): ensure() of
  // the next step (s.iter == iter, the positions not moved since) then takes it instead of
  // scanning the spheres again. Code that moves spheres otherwise invalidates the list.
  const float* ref_positions(std::size_t n) const {
    return valid_ && x_ref_.size() == n ? x_ref_.data()->data() : nullptr;
  }
  void moved(double max_d2, std::int64_t iter) { moved_max_d2_ = max_d2, moved_iter_ = iter; }
  std::int64_t rebuilds() const { return rebuilds_; }
  std::size_t heap_bytes() const;  // allocated capacity of the list's arrays

  // Pairs of sphere i (< j) are the rows [row_begin(i), row_begin(i + 1)) (compressed rows).
  std::size_t n_pairs() const { return pair_j_.size(); }
  std::size_t row_begin(std::size_t i) const { return row_[i]; }
  std::uint32_t pair_j(std::size_t p) const { return pair_j_[p] & ~kInContact; }
  const CellDist& pair_cell(std::size_t p) const { return cells_[pair_cell_[p]]; }
  // The distinct image offsets of the pairs: pair p has cells()[pair_cell_index(p)].
  std::uint16_t pair_cell_index(std::size_t p) const { return pair_cell_[p]; }
  // The arrays behind pair_j (with the contact flag, kInContact) and pair_cell_index.
  static constexpr std::uint32_t kInContact = 0x80000000u;  // flag bit of pair_j_
  const std::uint32_t* pair_j_flagged() const { return pair_j_.data(); }
  const std::uint16_t* pair_cell_indices() const { return pair_cell_.data(); }
  const std::vector<CellDist>& cells() const { return cells_; }
  bool pair_in_contact(std::size_t p) const { return (pair_j_[p] & kInContact) != 0; }
  // Bookkeeping of the contacts' pairs: contact_added after Contacts::add of pair p's
  // contact, contact_removed before Contacts::swap_remove of contact k.
  void contact_added(std::size_t p);
  void contact_removed(const Contacts& c, std::size_t k);
  // The pairs without a contact that can overlap now, (a, p) per pair in row order (a: the
  // pair's first sphere), count of them in *count; nullptr (scan all rows) unless the bound on
  // the motion since the build that ensure() computed is below kNearGap skins: a pair whose
  // gap at the reference positions, |x_j,ref + H_ref c - x_i,ref| - r_i - r_j, is at least
  // that cannot overlap. Derived at each rebuild; a removed contact's pair is inserted, a
  // contact added keeps its pair here (flagged). Not kept in checkpoints (a restored list
  // rebuilds).
  const std::uint32_t* near_pairs(const RveState& s, std::size_t* count);
  static constexpr double kNearGap = 0.25;

 private:
  void rebuild(const RveState& s);
  // Index of the pair (a, b, c) or (b, a, -c); -1 if the list does not hold it.
  std::int64_t find(std::uint32_t a, std::uint32_t b, const CellDist& c) const;

  double skin_factor_;
  bool valid_ = false;
  std::int64_t rebuilds_ = 0;
  double skin_ = 0, extent_ = 0, max_cutoff_ = 0;
  double ref_rounding_ = 0;  // max_i |x_i - x_ref_i| at the build (single precision)
  double moved_max_d2_ = 0;  // max_i |x_i - x_ref_i|^2 from Newton, valid at moved_iter_
  std::int64_t moved_iter_ = -1;
  std::size_t n_contacts_ = 0;  // contacts of the RVE as the list last saw them
  double motion_ = 0;  // ensure()'s bound on the change of a pair's separation since the build
  bool near_stale_ = true;
  std::vector<std::uint32_t> near_;  // near_pairs: (a, p) per pair
  Eigen::Matrix3d h_ref_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d h_ref_inv_ = Eigen::Matrix3d::Identity();
  std::vector<Eigen::Vector3f> x_ref_;
  std::vector<std::uint32_t> row_;        // n + 1 row starts
  std::vector<std::uint32_t> pair_j_;     // second sphere of each pair | kInContact
  std::vector<std::uint16_t> pair_cell_;  // image offset of each pair: index in cells_
  std::vector<CellDist> cells_;           // the distinct image offsets, sorted
};

}  // namespace mpmdem::dem::native

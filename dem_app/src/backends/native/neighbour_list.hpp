// Verlet list of the sphere pairs (and periodic images) that may come into contact before the
// next rebuild: |x_j + hsize c - x_i| < r_i + r_j + skin when built. It is rebuilt only when
// the spheres' motion since the build, split into the cell's homogeneous deformation
// A = H H_ref^-1 and what is left of it (u_i = x_i - A x_i,ref), may have used up the skin:
//   2 max_i |u_i| + |A - I|_F (2 r_max + skin) >= skin.
// (A pair's separation is A d_ref + u_j - u_i, and |A d_ref| >= (1 - |A - I|) |d_ref|; a pair
// left out had |d_ref| >= r_i + r_j + skin.) The homogeneous part moves far spheres of a
// strained cell far (positions are not wrapped into the cell) without bringing any pair
// closer than the strain itself does, so it does not use up the skin (until 2026-11-27 the
// check took |x_i - x_i,ref| and |A - I| times the spheres' extent: 25x the rebuilds on the
// RVEs of a flowing column, docs/performance.md). Under the small homogeneous increments of a
// coupling step rebuilds are rare. The list also maps pairs to the RVE's real contacts, so that
// only pairs without a contact are tested for a new one. Storage: compressed rows (pairs of sphere
// i are contiguous, i < j), 6 bytes per pair (j with the contact flag in its top bit, the 16-bit
// index of its image offset in a table of the build's distinct offsets, 6 bytes each: a few dozen),
// 12 per sphere (x_ref in single precision, its rounding added to the displacement bound), sized
// exactly at each build; nothing per contact (a removed contact's pair is found in its row).
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
  // list is not valid for n spheres.
  const float* ref_positions(std::size_t n) const {
    return valid_ && x_ref_.size() == n ? x_ref_.data()->data() : nullptr;
  }
  // The homogeneous deformation since the build for a cell of lattice vectors h: h H_ref^-1.
  Eigen::Matrix3d deformation(const Eigen::Matrix3d& h) const { return h * h_ref_inv_; }
  // |x - a x_ref|^2 of one sphere (x_ref: the float triple at ref), in the one order of
  // operations that Newton's loop repeats (the same bits: no contraction in this library).
  static double residual2(const double x[3], const Eigen::Matrix3d& a, const float* ref) {
    const double r0 = ref[0], r1 = ref[1], r2 = ref[2];
    double e[3];
    for (int k = 0; k < 3; ++k) e[k] = x[k] - (a(k, 0) * r0 + a(k, 1) * r1 + a(k, 2) * r2);
    return e[0] * e[0] + (e[1] * e[1] + e[2] * e[2]);
  }
  // Newton computes max_i residual2(x_i, a, x_ref_i) with the new positions and a =
  // deformation(h), h the lattice that the next step's cell move will give, and hands it over
  // with moved(): ensure() of the next step (s.iter == iter, the positions not moved since,
  // the cell's lattice bit for bit h) then takes it instead of scanning the spheres again.
  // Code that moves spheres otherwise invalidates the list.
  void moved(double max_d2, std::int64_t iter, const Eigen::Matrix3d& h, const Eigen::Matrix3d& a) {
    moved_max_d2_ = max_d2, moved_iter_ = iter, moved_h_ = h, moved_a_ = a;
  }
  std::int64_t rebuilds() const { return rebuilds_; }
  // Builds that searched by bins (the others tested every pair: a cell under 4 bins thick).
  std::int64_t binned_builds() const { return binned_builds_; }
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
  // max_i residual2(x_i, a, x_ref_i) over the spheres (the scan Newton's hand-over saves).
  double max_residual2(const RveState& s, const Eigen::Matrix3d& a) const;
  // Index of the pair (a, b, c) or (b, a, -c); -1 if the list does not hold it.
  std::int64_t find(std::uint32_t a, std::uint32_t b, const CellDist& c) const;

  double skin_factor_;
  bool valid_ = false;
  std::int64_t rebuilds_ = 0, binned_builds_ = 0;
  double skin_ = 0, max_cutoff_ = 0;
  double ref_rounding_ = 0;  // max_i |x_i - x_ref_i| at the build (single precision)
  double ref_norm_ = 0;      // max_i |x_ref_i| (bounds the rounding of A x_ref)
  double moved_max_d2_ = 0;  // max_i |x_i - A x_ref_i|^2 from Newton, valid at moved_iter_
  Eigen::Matrix3d moved_h_ = Eigen::Matrix3d::Zero();      // the lattice Newton assumed
  Eigen::Matrix3d moved_a_ = Eigen::Matrix3d::Identity();  // its deformation(moved_h_)
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

// Verlet list with skin under homogeneous cell deformation: see neighbour_list.hpp.
#include "backends/native/neighbour_list.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace mpmdem::dem::native {

namespace {
using Key = std::tuple<std::uint32_t, std::uint32_t, int, int, int>;
// A pair's key independent of the order of its two spheres.
Key key_of(std::uint32_t a, std::uint32_t b, const Eigen::Vector3i& c) {
  if (a <= b) return {a, b, c[0], c[1], c[2]};
  return {b, a, -c[0], -c[1], -c[2]};
}
}  // namespace

void NeighbourList::ensure(const RveState& s) {
  if (valid_ && x_ref_.size() == s.spheres.size() && contact_pair_.size() == s.contacts.size()) {
    double max_d2 = 0;
    for (std::size_t i = 0; i < x_ref_.size(); ++i) {
      max_d2 = std::max(max_d2, (s.spheres.pos[i] - x_ref_[i]).squaredNorm());
    }
    const double strain = ((s.cell.hsize - h_ref_) * h_ref_inv_).norm();
    if (2 * std::sqrt(max_d2) + strain * (extent_ + max_cutoff_) < skin_) return;
  }
  rebuild(s);
}

void NeighbourList::rebuild(const RveState& s) {
  ++rebuilds_;
  valid_ = true;
  const auto& sp = s.spheres;
  const std::size_t n = sp.size();
  const double r_min = n ? *std::min_element(sp.radius.begin(), sp.radius.end()) : 0.0;
  const double r_max = n ? *std::max_element(sp.radius.begin(), sp.radius.end()) : 0.0;
  skin_ = skin_factor_ * r_min;
  max_cutoff_ = 2 * r_max + skin_;
  h_ref_ = s.cell.hsize;
  h_ref_inv_ = h_ref_.inverse();
  x_ref_ = sp.pos;
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const auto& x : sp.pos) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  extent_ = n ? (hi - lo).norm() : 0.0;

  Vec3 offsets[27];
  Eigen::Vector3i steps[27];
  int m = 0;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c) {
        steps[m] = Eigen::Vector3i(a, b, c);
        offsets[m++] = h_ref_ * Vec3(a, b, c);
      }
  pair_i_.clear();
  pair_j_.clear();
  pair_c_.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = i + 1; j < n; ++j) {
      const Vec3 d = sp.pos[j] - sp.pos[i];
      const Vec3 f = h_ref_inv_ * d;
      const Eigen::Vector3i c0(-static_cast<int>(std::lround(f[0])),
                               -static_cast<int>(std::lround(f[1])),
                               -static_cast<int>(std::lround(f[2])));
      const Vec3 d0 = d + h_ref_ * c0.cast<double>();
      const double cut = sp.radius[i] + sp.radius[j] + skin_;
      for (int k = 0; k < 27; ++k) {
        if ((d0 + offsets[k]).squaredNorm() < cut * cut) {
          pair_i_.push_back(i);
          pair_j_.push_back(j);
          pair_c_.push_back(c0 + steps[k]);
        }
      }
    }
  }
  // Map the existing contacts onto the new pairs.
  pair_contact_.assign(pair_i_.size(), -1);
  contact_pair_.assign(s.contacts.size(), -1);
  std::map<Key, std::int32_t> index;
  for (std::size_t p = 0; p < pair_i_.size(); ++p) {
    index.emplace(key_of(pair_i_[p], pair_j_[p], pair_c_[p]), static_cast<std::int32_t>(p));
  }
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    const auto it = index.find(key_of(s.contacts.id1[k], s.contacts.id2[k], s.contacts.cell[k]));
    if (it == index.end()) continue;  // an image the list does not hold: never re-created
    contact_pair_[k] = it->second;
    pair_contact_[it->second] = static_cast<std::int32_t>(k);
  }
}

void NeighbourList::contact_added(std::size_t pair, std::size_t contact) {
  if (contact_pair_.size() <= contact) contact_pair_.resize(contact + 1, -1);
  contact_pair_[contact] = static_cast<std::int32_t>(pair);
  pair_contact_[pair] = static_cast<std::int32_t>(contact);
}

void NeighbourList::contact_removed(std::size_t contact, std::size_t last) {
  const std::int32_t p = contact_pair_[contact];
  if (p >= 0) pair_contact_[p] = -1;
  if (contact != last) {
    contact_pair_[contact] = contact_pair_[last];
    if (contact_pair_[contact] >= 0) {
      pair_contact_[contact_pair_[contact]] = static_cast<std::int32_t>(contact);
    }
  }
  contact_pair_.pop_back();
}

}  // namespace mpmdem::dem::native

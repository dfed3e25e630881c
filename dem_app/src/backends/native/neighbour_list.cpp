// Verlet list with skin under homogeneous cell deformation: see neighbour_list.hpp.
#include "backends/native/neighbour_list.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace mpmdem::dem::native {

void NeighbourList::ensure(const RveState& s) {
  const std::size_t n = x_ref_.size();
  if (valid_ && n == s.spheres.size() && n_contacts_ == s.contacts.size()) {
    const Eigen::Matrix3d& h = s.cell.hsize;
    const bool handed = moved_iter_ == s.iter && h == moved_h_;
    const Eigen::Matrix3d a = handed ? moved_a_ : deformation(h);
    const double max_d2 = handed ? moved_max_d2_ : max_residual2(s, a);
#ifdef MPMDEM_CHECK_MOVED  // debugging: Newton's max against this scan, bit for bit
    if (handed) {
      const double m = max_residual2(s, a);
      if (std::memcmp(&m, &max_d2, sizeof m) != 0) std::abort();
    }
#endif
    // |u| <= |x - A x_ref (single)| + |A| (its rounding at the build) + the rounding of the
    // product A x_ref and of A itself (H - A H_ref is not exactly 0): a few ulps of |A| |x_ref|
    // and of |H| per image offset, 1e-12 of |A| max |x_ref| is ample.
    const double strain = (a - Eigen::Matrix3d::Identity()).norm();
    const double spread = (1 + strain) * (ref_rounding_ + 1e-12 * ref_norm_);
    motion_ = 2 * (std::sqrt(max_d2) + spread) + strain * max_cutoff_;
    if (motion_ < skin_) return;
  }
  rebuild(s);
}

double NeighbourList::max_residual2(const RveState& s, const Eigen::Matrix3d& a) const {
  double m = 0;
  for (std::size_t i = 0; i < x_ref_.size(); ++i) {
    const double x[3] = {s.spheres.pos.c[0][i], s.spheres.pos.c[1][i], s.spheres.pos.c[2][i]};
    const double d2 = residual2(x, a, x_ref_[i].data());
    m = d2 == d2 ? std::max(m, d2) : m;  // a NaN skipped, as Newton's loop does
  }
  return m;
}

void NeighbourList::rebuild(const RveState& s) {
  ++rebuilds_;
  valid_ = true;
  near_stale_ = true;
  moved_iter_ = -1;
  const auto& sp = s.spheres;
  const std::size_t n = sp.size();
  const double r_min = n ? *std::min_element(sp.radius.begin(), sp.radius.end()) : 0.0;
  const double r_max = n ? *std::max_element(sp.radius.begin(), sp.radius.end()) : 0.0;
  skin_ = skin_factor_ * r_min;
  max_cutoff_ = 2 * r_max + skin_;
  h_ref_ = s.cell.hsize;
  h_ref_inv_ = h_ref_.inverse();
  if (n >= kInContact) throw std::runtime_error("native backend: too many spheres in one RVE");
  x_ref_.resize(n);
  x_ref_.shrink_to_fit();
  ref_rounding_ = 0;
  ref_norm_ = 0;
  for (std::size_t i = 0; i < n; ++i) {
    x_ref_[i] = sp.pos[i].cast<float>();
    ref_rounding_ = std::max(ref_rounding_, (sp.pos[i] - x_ref_[i].cast<double>()).norm());
    ref_norm_ = std::max(ref_norm_, x_ref_[i].cast<double>().norm());
  }
  ref_rounding_ *= 1 + 1e-6;  // the rounding of the norm itself
  ref_norm_ *= 1 + 1e-6;
  motion_ = 4 * (ref_rounding_ + 1e-12 * ref_norm_);  // ensure()'s bound, no strain yet

  Vec3 offsets[27];
  Eigen::Vector3i steps[27];
  int m = 0;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c) {
        steps[m] = Eigen::Vector3i(a, b, c);
        offsets[m++] = h_ref_ * Vec3(a, b, c);
      }
  // Quick rejection in the cell's reduced frame: with f the reduced separation wrapped to
  // [-1/2, 1/2] and h_a the cell's height along a, every image of the pair is at least
  // |f_a| h_a away (s_a = 0) or (1 - |f_a|) h_a >= h_a / 2 (s_a != 0). So a pair with
  // |f_a| h_a >= cut on an axis where h_a >= 2 cut has no image within cut: it is skipped
  // before the exact test below (which alone decides, so the list is unchanged). The
  // relative margin 1e-6 covers the rounding of the per-sphere reduced coordinates.
  std::vector<Vec3> g(n);
  for (std::size_t i = 0; i < n; ++i) g[i] = h_ref_inv_ * sp.pos[i];
  Vec3 height;
  {
    const double vol = std::abs(h_ref_.determinant());
    for (int a = 0; a < 3; ++a) {
      height[a] = vol / h_ref_.col((a + 1) % 3).cross(h_ref_.col((a + 2) % 3)).norm();
    }
  }
  const auto wrapped = [](double f) {
    const double t = f + 0.5;
    double r = static_cast<double>(static_cast<long long>(t));
    if (r > t) r -= 1;  // floor(f + 1/2) without a libm call
    return std::abs(f - r);
  };
  const auto far = [&](std::size_t i, std::size_t j, double cut) {
    const double c = cut * (1 + 1e-6);
    for (int a = 0; a < 3; ++a) {
      if (height[a] >= 2 * c && wrapped(g[j][a] - g[i][a]) * height[a] >= c) return true;
    }
    return false;
  };
  // Candidates by bins of the reduced frame: nb_a bins along lattice vector a, each at least
  // the largest cutoff high (h_a / nb_a >= cut), so by the bound above two spheres whose bins
  // are not neighbours (cyclically) along some axis have no image within their cutoff; only
  // the spheres of the 27 neighbour bins (all bins along an axis of fewer than 4) are tested.
  // A sphere's candidates j > i are tested in ascending order, as by the all-pairs loop, so
  // the list is the same, bit for bit (until 2026-11-27 all pairs were tested: builds of
  // 800-3,200 spheres 1.7-3.5x dearer, docs/performance.md, "the Verlet build by bins").
  const double cut_all = max_cutoff_ * (1 + 1e-6);
  int nb[3];
  for (int a = 0; a < 3; ++a) {
    const double q = height[a] / cut_all;
    nb[a] = q >= 2 ? static_cast<int>(std::min(q, 1024.0)) : 1;  // 1 also for a NaN
  }
  const std::size_t max_bins = std::max<std::size_t>(27, 2 * n);  // a dilute cell: fewer, taller
  while (static_cast<std::size_t>(nb[0]) * nb[1] * nb[2] > max_bins) {
    int& big = *std::max_element(nb, nb + 3);
    big = (big + 1) / 2;
  }
  const bool all_bins = nb[0] < 4 && nb[1] < 4 && nb[2] < 4;
  // The images worth testing: along an axis at least two cutoffs high, the minimum image
  // (s_a = 0) is the only one that can be within the cutoff (|f_a + s_a| >= 1/2 otherwise), so
  // only the offsets with s_a = 0 on such axes are tested (1 of the 27 in a cell that is thick
  // on every axis), in the same order.
  int tested[27], n_tested = 0;
  for (int k = 0; k < 27; ++k) {
    bool needed = true;
    for (int a = 0; a < 3; ++a) needed = needed && (steps[k][a] == 0 || height[a] < 2 * cut_all);
    if (needed) tested[n_tested++] = k;
  }
  std::vector<std::uint32_t> bin_of, bin_start, bin_sphere;  // empty when searched whole
  if (!all_bins) {
    ++binned_builds_;
    bin_of.resize(n);
    const std::size_t n_bins = static_cast<std::size_t>(nb[0]) * nb[1] * nb[2];
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t b = 0;
      for (int a = 0; a < 3; ++a) {
        const double t = (g[i][a] - std::floor(g[i][a])) * nb[a];
        b = b * static_cast<std::uint32_t>(nb[a]) +
            static_cast<std::uint32_t>(t >= 0 ? std::min(static_cast<int>(t), nb[a] - 1) : 0);
      }
      bin_of[i] = b;
    }
    bin_start.assign(n_bins + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++bin_start[bin_of[i] + 1];
    for (std::size_t b = 0; b < n_bins; ++b) bin_start[b + 1] += bin_start[b];
    bin_sphere.resize(n);
    std::vector<std::uint32_t> fill(bin_start.begin(), bin_start.end() - 1);
    for (std::uint32_t i = 0; i < n; ++i) bin_sphere[fill[bin_of[i]]++] = i;
  }
  // The neighbour bins' indices along axis a of bin coordinate k: k - 1, k, k + 1 cyclically.
  const auto neighbours = [&](int a, int k, int* out) {
    if (nb[a] < 4) {
      for (int b = 0; b < nb[a]; ++b) out[b] = b;
      return nb[a];
    }
    out[0] = (k + nb[a] - 1) % nb[a], out[1] = k, out[2] = (k + 1) % nb[a];
    return 3;
  };
  row_.assign(n + 1, 0);
  pair_j_.clear();
  std::vector<CellDist> pair_cells;
  std::vector<std::uint32_t> candidates;
  const auto test = [&](std::uint32_t i, std::uint32_t j) {
    if (far(i, j, sp.radius[i] + sp.radius[j] + skin_)) return;
    const Vec3 d = sp.pos[j] - sp.pos[i];
    const Vec3 f = h_ref_inv_ * d;
    const Eigen::Vector3i c0(-static_cast<int>(std::lround(f[0])),
                             -static_cast<int>(std::lround(f[1])),
                             -static_cast<int>(std::lround(f[2])));
    const Vec3 d0 = d + h_ref_ * c0.cast<double>();
    const double cut = sp.radius[i] + sp.radius[j] + skin_;
    for (int t = 0; t < n_tested; ++t) {
      const int k = tested[t];
      if ((d0 + offsets[k]).squaredNorm() < cut * cut) {
        pair_j_.push_back(j);
        pair_cells.push_back(to_cell_dist(c0 + steps[k]));
      }
    }
  };
  for (std::uint32_t i = 0; i < n; ++i) {
    row_[i] = static_cast<std::uint32_t>(pair_j_.size());
    if (all_bins) {
      for (std::uint32_t j = i + 1; j < n; ++j) test(i, j);
      continue;
    }
    int k[3], nx[3], ny[3], nz[3];
    for (std::uint32_t b = bin_of[i], a = 3; a-- > 0;) {
      k[a] = static_cast<int>(b % static_cast<std::uint32_t>(nb[a]));
      b /= static_cast<std::uint32_t>(nb[a]);
    }
    const int mx = neighbours(0, k[0], nx), my = neighbours(1, k[1], ny),
              mz = neighbours(2, k[2], nz);
    candidates.clear();
    for (int x = 0; x < mx; ++x)
      for (int y = 0; y < my; ++y)
        for (int z = 0; z < mz; ++z) {
          const std::size_t b = (static_cast<std::size_t>(nx[x]) * nb[1] + ny[y]) * nb[2] + nz[z];
          for (std::uint32_t q = bin_start[b]; q < bin_start[b + 1]; ++q) {
            if (bin_sphere[q] > i) candidates.push_back(bin_sphere[q]);
          }
        }
    std::sort(candidates.begin(), candidates.end());
    for (const std::uint32_t j : candidates) test(i, j);
  }
  row_[n] = static_cast<std::uint32_t>(pair_j_.size());
  // Exact size: the pair count changes only here (rebuilds are rare).
  pair_j_.shrink_to_fit();
  // The distinct offsets (sorted), and each pair's index among them.
  const auto less = [](const CellDist& x, const CellDist& y) {
    return std::lexicographical_compare(x.data(), x.data() + 3, y.data(), y.data() + 3);
  };
  cells_ = pair_cells;
  std::sort(cells_.begin(), cells_.end(), less);
  cells_.erase(std::unique(cells_.begin(), cells_.end()), cells_.end());
  cells_.shrink_to_fit();
  if (cells_.size() > 0xffff) throw std::runtime_error("native backend: too many image offsets");
  pair_cell_.resize(pair_cells.size());
  pair_cell_.shrink_to_fit();
  for (std::size_t p = 0; p < pair_cells.size(); ++p) {
    pair_cell_[p] = static_cast<std::uint16_t>(
        std::lower_bound(cells_.begin(), cells_.end(), pair_cells[p], less) - cells_.begin());
  }
  // Flag the pairs of the existing contacts (an image the list does not hold is never
  // re-created).
  n_contacts_ = s.contacts.size();
  for (std::size_t k = 0; k < n_contacts_; ++k) {
    const std::int64_t p = find(s.contacts.id1[k], s.contacts.id2[k], s.contacts.cell[k]);
    if (p >= 0) pair_j_[p] |= kInContact;
  }
}

std::int64_t NeighbourList::find(std::uint32_t a, std::uint32_t b, const CellDist& c) const {
  const CellDist cc = a <= b ? c : CellDist(-c);
  const std::uint32_t i = std::min(a, b), j = std::max(a, b);
  if (i + 1 >= row_.size()) return -1;
  for (std::size_t p = row_[i]; p < row_[i + 1]; ++p) {
    if (pair_j(p) == j && cells_[pair_cell_[p]] == cc) return static_cast<std::int64_t>(p);
  }
  return -1;
}

std::size_t NeighbourList::heap_bytes() const {
  return x_ref_.capacity() * sizeof(Eigen::Vector3f) +
         (row_.capacity() + pair_j_.capacity() + near_.capacity()) * sizeof(std::uint32_t) +
         pair_cell_.capacity() * sizeof(std::uint16_t) + cells_.capacity() * sizeof(CellDist);
}

void NeighbourList::contact_added(std::size_t p) {
  pair_j_[p] |= kInContact;
  ++n_contacts_;
}

void NeighbourList::contact_removed(const Contacts& c, std::size_t k) {
  const std::int64_t p = find(c.id1[k], c.id2[k], c.cell[k]);
  if (p >= 0) pair_j_[p] &= ~kInContact;
  --n_contacts_;
  if (p < 0 || near_stale_) return;
  // Its pair without a contact now: into the near pairs, in row order (p ascending).
  std::size_t q = 0, end = near_.size() / 2;
  while (q < end) {  // binary search for the first entry with a larger pair index
    const std::size_t mid = (q + end) / 2;
    if (near_[2 * mid + 1] < p) {
      q = mid + 1;
    } else {
      end = mid;
    }
  }
  const std::uint32_t entry[2] = {std::min(c.id1[k], c.id2[k]), static_cast<std::uint32_t>(p)};
  if (near_.size() == near_.capacity()) near_.reserve(near_.size() + near_.size() / 8 + 16);
  near_.insert(near_.begin() + static_cast<std::ptrdiff_t>(2 * q), entry, entry + 2);
}

const std::uint32_t* NeighbourList::near_pairs(const RveState& s, std::size_t* count) {
  const double gap = kNearGap * skin_;
  if (!valid_ || !(motion_ < gap)) return nullptr;
  if (near_stale_) {
    const auto& r = s.spheres.radius;
    const double limit = gap * (1 + 1e-6);  // covers the rounding of the distances below
    const auto near = [&](std::uint32_t i, std::uint32_t p) {
      if (pair_j_[p] & kInContact) return false;
      const std::uint32_t j = pair_j_[p];
      const Vec3 d = (x_ref_[j].cast<double>() + h_ref_ * cells_[pair_cell_[p]].cast<double>()) -
                     x_ref_[i].cast<double>();
      return d.norm() - (r[i] + r[j]) < limit;
    };
    std::size_t listed = 0;  // sized exactly (a removal's insertion grows it by 1/8)
    for (std::uint32_t i = 0; i + 1 < row_.size(); ++i) {
      for (std::uint32_t p = row_[i]; p < row_[i + 1]; ++p) listed += near(i, p);
    }
    std::vector<std::uint32_t>().swap(near_);
    near_.reserve(2 * listed);
    for (std::uint32_t i = 0; i + 1 < row_.size(); ++i) {
      for (std::uint32_t p = row_[i]; p < row_[i + 1]; ++p) {
        if (near(i, p)) near_.push_back(i), near_.push_back(p);
      }
    }
    near_stale_ = false;
  }
  *count = near_.size() / 2;
  return near_.data();
}

}  // namespace mpmdem::dem::native

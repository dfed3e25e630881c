// MUSL's re-projection, in G2P's pass: each point's new momentum back on the grid with the same
// transfer and stencils, mv_i = sum_p N_ip m_p (v_p + C_p (x_i - x_p)) (C_p with an affine
// rule only). Thread t > 0 scatters into its own copy of mv_i (ScatterBuffers), summed into
// the grid node by node at the end: deterministic for a fixed thread count.
// A tap on G2P's pass (g2p_tap.hpp); kAffine: the transfer rule's.
#pragma once

#include <omp.h>

#include <algorithm>
#include <vector>

#include "g2p_tap.hpp"
#include "node_loops.hpp"
#include "transfers.hpp"

namespace mpmdem::mpm {

template <bool kAffine>
class MuslTap {
 public:
  // Off (every hook returns at once) without `reproject` (USL).
  MuslTap(Grid& grid, ScatterBuffers& buf, bool reproject)
      : on_(reproject), grid_(&grid), buf_(&buf) {
    if (on_) buf.resize(grid.size(), omp_get_max_threads());
  }

  void start_thread() {
    if (!on_) return;
    const int t = omp_get_thread_num();
    mv_i_ = t == 0 ? &grid_->mv_i : &buf_->mv[t - 1];
    std::fill(mv_i_->begin(), mv_i_->end(), Vec3::Zero());
  }

  struct Sums {};  // nothing per point before the blend
  void start_point(Sums&, const Particles&, std::size_t) const {}
  void at_node(Sums&, std::size_t, double, const Vec3&) const {}

  template <int W>
  void finish_point(Sums&, const Grid& grid, const Stencil<W>& s, const Particles& p,
                    std::size_t q) const {
    if (!on_) return;
    std::vector<Vec3>& mv_i = *mv_i_;
    const Vec3 mv_p = p.m[q] * p.v[q];
    if constexpr (kAffine) {
      const Mat3 mC_p = p.m[q] * p.C[q];
      detail::for_each_node_affine(
          grid, s, [&](std::size_t i, double N, const Vec3&, const Vec3& dx, const Vec3&) {
            mv_i[i] += N * (mv_p + mC_p * dx);
          });
    } else {
      detail::for_each_node(grid, s,
                            [&](std::size_t i, double N, const Vec3&) { mv_i[i] += N * mv_p; });
    }
  }

  void finish_thread() {
    if (!on_) return;
    const int used = omp_get_num_threads();
    if (used > 1) detail::reduce_into(grid_->mv_i, buf_->mv, used);
  }

 private:
  bool on_;
  Grid* grid_;
  ScatterBuffers* buf_;
  std::vector<Vec3>* mv_i_ = nullptr;  // this thread's momentum field
};

}  // namespace mpmdem::mpm

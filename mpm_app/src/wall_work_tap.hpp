// The walls' share of the energy budget, measured in G2P (energy_budget.hpp,
// W_transfer_walls; the StepEnergy hook g2p_walls() hands G2P the WallWork): per point the
// work the walls' velocity jumps v_i - v_free,i did on it,
//   work_p = -m_p sum_i N_ip (v_i - v_free,i) . (v_mean + C_mean (x_i - x_p)),
// the means over the point's velocity and (APIC) affine matrix before and after G2P, and
//   sum_i N jump_i . C_mean dx_i = (sum_i N jump_i dx_i^T) : C_mean  (0 without APIC).
// A tap on G2P's pass (g2p_tap.hpp); kAffine: the transfer rule's.
#pragma once

#include <cassert>

#include "g2p_tap.hpp"
#include "transfers.hpp"

namespace mpmdem::mpm {

template <bool kAffine>
class WallWorkTap {
 public:
  // Off (every hook returns at once) without walls.v_free: the work is not measured.
  WallWorkTap(const WallWork& walls, const Grid& grid, std::size_t points) {
    if (walls.v_free == nullptr) return;
    assert(walls.work != nullptr && walls.v_free->size() == grid.size());
    walls.work->resize(points);
    v_i_ = grid.v_i.data();
    v_free_ = walls.v_free->data();
    work_ = walls.work->data();
  }

  // The point's: its velocity and affine matrix before G2P, the walls' sums over its nodes.
  struct Sums {
    Vec3 v_old;
    Mat3 C_old;
    Vec3 jump;     // sum N (v_i - v_free,i): the walls' share of the FLIP increment
    Mat3 jump_dx;  // sum N (v_i - v_free,i) (x_i - x_p)^T (affine rules)
  };

  void start_thread() {}

  void start_point(Sums& sum, const Particles& p, std::size_t q) const {
    if (v_free_ == nullptr) return;
    sum.v_old = p.v[q];
    if constexpr (kAffine) sum.C_old = p.C[q];
    sum.jump.setZero();
    if constexpr (kAffine) sum.jump_dx.setZero();
  }

  void at_node(Sums& sum, std::size_t i, double N, const Vec3& dx) const {
    if (v_free_ == nullptr) return;
    if constexpr (kAffine) {
      if (v_i_[i] == v_free_[i]) return;  // most nodes: no wall acted
      const Vec3 j = N * (v_i_[i] - v_free_[i]);
      sum.jump += j;
      sum.jump_dx.noalias() += j * dx.transpose();
    } else {  // every node: the compare would cost more than the add (+0 on most nodes)
      sum.jump += N * (v_i_[i] - v_free_[i]);
    }
  }

  template <int W>
  void finish_point(Sums& sum, const Grid&, const Stencil<W>&, const Particles& p,
                    std::size_t q) const {
    if (v_free_ == nullptr) return;
    double w = sum.jump.dot(0.5 * (sum.v_old + p.v[q]));
    if constexpr (kAffine) {
      w += (sum.jump_dx.array() * (0.5 * (sum.C_old + p.C[q])).array()).sum();
    }
    work_[q] = -p.m[q] * w;
  }

  void finish_thread() {}

 private:
  const Vec3* v_i_ = nullptr;     // the node velocities after the walls
  const Vec3* v_free_ = nullptr;  // ... and before them (nullptr: the tap is off)
  double* work_ = nullptr;        // per point [J]
};

}  // namespace mpmdem::mpm

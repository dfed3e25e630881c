// XPIC(m) in G2P: v_target = sum N (v*_i + v_i - v0_i), with v* the filtered node velocity
// (xpic.hpp, computed after the grid update). The rule's contract: transfer_rule.hpp.
#pragma once

#include "node_loops.hpp"
#include "transfer_rule.hpp"

namespace mpmdem::mpm {

struct XpicRule {
  static constexpr bool kAffine = false;

  template <int W, class AtNode>
  static void gather(const Grid& grid, const Stencil<W>& s, Particles&, std::size_t, G2PGather& g,
                     AtNode&& at_node) {
    Vec3 v_star = Vec3::Zero();
    detail::for_each_node_affine(
        grid, s, [&](std::size_t i, double N, const Vec3&, const Vec3& dx, const Vec3&) {
          g.v_pic += N * grid.v_i[i];
          g.dv += N * (grid.v_i[i] - grid.v0_i[i]);
          v_star += N * grid.vstar_i[i];
          at_node(i, N, dx);
        });
    g.v_target = v_star + g.dv;
  }
};

}  // namespace mpmdem::mpm

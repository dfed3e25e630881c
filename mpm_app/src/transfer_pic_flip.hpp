// PIC/FLIP (the schema's default transfer): v_target = sum N v_i, blended with the FLIP
// update by the flip share. The rule's contract: transfer_rule.hpp.
#pragma once

#include "node_loops.hpp"
#include "transfer_rule.hpp"

namespace mpmdem::mpm {

struct PicFlipRule {
  static constexpr bool kAffine = false;

  template <int W, class AtNode>
  static void gather(const Grid& grid, const Stencil<W>& s, Particles&, std::size_t, G2PGather& g,
                     AtNode&& at_node) {
    detail::for_each_node_affine(
        grid, s, [&](std::size_t i, double N, const Vec3&, const Vec3& dx, const Vec3&) {
          g.v_pic += N * grid.v_i[i];
          g.dv += N * (grid.v_i[i] - grid.v0_i[i]);
          at_node(i, N, dx);
        });
    g.v_target = g.v_pic;
  }
};

}  // namespace mpmdem::mpm

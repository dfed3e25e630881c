// APIC (Jiang et al. 2015): v_target = sum N v_i and the point's affine velocity
// C_p = sum_i v_i (D_p^-1 N_ip (x_i - x_p))^T, which P2G and the MUSL re-projection carry
// (mv_i = sum N m_p (v_p + C_p (x_i - x_p))); with a FLIP share C_p stays APIC's (Fei et al.
// 2021). The rule's contract: transfer_rule.hpp.
#pragma once

#include "node_loops.hpp"
#include "transfer_rule.hpp"

namespace mpmdem::mpm {

struct ApicRule {
  static constexpr bool kAffine = true;

  template <int W, class AtNode>
  static void gather(const Grid& grid, const Stencil<W>& s, Particles& p, std::size_t q,
                     G2PGather& g, AtNode&& at_node) {
    Mat3 C = Mat3::Zero();
    detail::for_each_node_affine(
        grid, s, [&](std::size_t i, double N, const Vec3&, const Vec3& dx, const Vec3& ga) {
          g.v_pic += N * grid.v_i[i];
          g.dv += N * (grid.v_i[i] - grid.v0_i[i]);
          C.noalias() += grid.v_i[i] * ga.transpose();
          at_node(i, N, dx);
        });
    g.v_target = g.v_pic;
    // A point without contacts (a disconnected Drucker-Prager point, an RVE that lost all
    // contacts) is not a continuum: it carries no affine velocity field. Alone near a wall
    // its C would otherwise feed on itself (docs/transfers.md, "The disconnected state").
    // Dropping C removes no linear momentum: sum_i N_ip (x_i - x_p) = 0.
    p.C[q] = p.state[q] == PointState::kNoContacts ? Mat3::Zero().eval() : C;
  }
};

}  // namespace mpmdem::mpm

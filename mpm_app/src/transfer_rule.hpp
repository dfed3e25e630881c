// What a particle-grid transfer rule is (transfer_pic_flip.hpp, transfer_apic.hpp,
// transfer_xpic.hpp): the part of P2G and G2P that differs between PIC/FLIP, APIC and XPIC.
// transfers.cpp runs one loop per stage for any rule, chosen once per call from
// solver.transfer (with_transfer_rule there), never per point.
//
// A rule is a struct with
//   static constexpr bool kAffine;  // P2G and the MUSL re-projection carry the point's
//                                   // affine velocity C_p: mv_i = sum N m_p (v_p + C_p dx)
//   template <int W, class AtNode>
//   static void gather(const Grid&, const Stencil<W>&, Particles& p, std::size_t q,
//                      G2PGather& g, AtNode&& at_node);
//     G2P's sums over the point's nodes into g (and, for an affine rule, the point's new
//     C_p); at_node(i, N_ip, x_i - x_p) once per node, for the taps G2P carries (g2p_tap.hpp).
#pragma once

#include <cstddef>

#include "grid.hpp"
#include "particles.hpp"
#include "shape_functions.hpp"

namespace mpmdem::mpm {

// The sums G2P takes over a point's nodes; every rule then blends
// v_p = flip (v_p + dv) + (1 - flip) v_target and moves the point by dt v_pic.
struct G2PGather {
  Vec3 v_pic = Vec3::Zero();  // sum N v_i
  Vec3 dv = Vec3::Zero();     // sum N (v_i - v0_i): the FLIP increment
  Vec3 v_target;              // the rule's PIC-side velocity
};

}  // namespace mpmdem::mpm

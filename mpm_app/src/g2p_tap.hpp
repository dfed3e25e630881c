// What a G2P tap is (wall_work_tap.hpp, musl_tap.hpp): a concern that rides on G2P's one
// pass over the points without being written into it. The pass (g2p_points, transfers.cpp) is
//   for each point: gather (the transfer rule) -> blend v_p -> each tap's finish_point -> move,
// and G2P picks its taps once per call (with_g2p_taps there): a tap that is off is not in the
// pass at all. Fusing them into the pass matters: a second reading of every point's stencil
// costs ~14 % of the step (docs/results/performance.md).
//
// A tap is a copyable class; every thread of the pass takes its own copy, so a tap keeps its
// per-thread and per-point state in members. Its hooks, in the order the pass calls them:
//   void start_thread();                      // each thread, before its points
//   void start_point(const Particles& p, std::size_t q);
//                                             // before the rule's gather (v_p, C_p still old)
//   void at_node(std::size_t i, double N_ip, const Vec3& dx);
//                                             // from the rule's node loop, dx = x_i - x_p
//   template <int W> void finish_point(const Grid&, const Stencil<W>&, const Particles& p,
//                                      std::size_t q);
//                                             // after the blend: v_p, C_p new, x_p old
//   void finish_thread();                     // each thread, after every thread's points
//                                             // (may hold an `omp for`: all threads call it)
// Bits: a tap reads the point and grid fields the pass computes and writes only its own
// outputs, so the pass's results do not depend on which taps ride on it.
#pragma once

#include <cstddef>

#include "grid.hpp"
#include "particles.hpp"
#include "shape_functions.hpp"

// What a G2P tap is (wall_work_tap.hpp, musl_tap.hpp): a concern that rides on G2P's one
// pass over the points without being written into it. The pass (g2p_points, transfers.cpp) is
//   for each point: gather (the transfer rule) -> blend v_p -> each tap's finish_point -> move.
// Fused, not a pass of its own: a second reading of every point's stencil cost ~14 % of the
// step (docs/results/performance.md). G2P builds its taps once per call (g2p_taps there), each
// on or off for the whole call (its hooks then return at once): one instance of the pass per
// rule and shape, not one per combination of taps, which kept transfers.cpp's compile time and
// GCC's inlining of the pass as they were (the combinations as template arguments made the
// pass ~11 % longer in instructions: docs/results/performance.md, "The G2P taps").
//
// A tap is a copyable class; every thread of the pass takes its own copy (per-thread state in
// members), and each point gets a fresh `Sums` (the tap's per-point state, a local of the
// loop so that the compiler keeps it in registers). Its hooks, in the order the pass calls them:
//   struct Sums;                              // per point (may be empty)
//   void start_thread();                      // each thread, before its points
//   void start_point(Sums&, const Particles& p, std::size_t q) const;
//                                             // before the rule's gather (v_p, C_p still old)
//   void at_node(Sums&, std::size_t i, double N_ip, const Vec3& dx) const;
//                                             // from the rule's node loop, dx = x_i - x_p
//   template <int W> void finish_point(Sums&, const Grid&, const Stencil<W>&,
//                                      const Particles& p, std::size_t q) const;
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

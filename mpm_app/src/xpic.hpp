// XPIC(m), extended particle-in-cell of order m (Hammerquist & Nairn 2017, CMAME 318).
//
// With S the grid-to-point interpolation and S+ the mass-weighted point-to-grid projection,
// P2G gives v0 = S+ V. PIC replaces the point velocities V by S v0 every step, i.e. it removes
// the whole part (I - S S+) V that the grid does not hold, and so damps every step: its
// dissipation grows with the number of steps. FLIP keeps V, including the part in the null
// space of S+ that the grid cannot see (noise). XPIC(m) keeps V minus an m-term estimate of
// that null-space part:
//   V* = [I - (I - S S+)^m] V = S v*,   v* = sum_{k=1..m} (-1)^(k+1) C(m,k) (S+ S)^(k-1) v0,
// then updates the points with the FLIP increment:  v_p = sum_i N_ip (v*_i + v_i - v0_i).
// m = 1 is PIC; as m grows the damping of modes the grid resolves (eigenvalue lambda of S S+
// near 1) falls as (1 - lambda)^m, while null-space noise (lambda = 0) is still removed.
// (S+ S) u is a grid-to-grid smoothing: u_p = sum_j N_jp u_j, then
// (S+ S u)_i = sum_p m_p N_ip u_p / m_i; each order costs one such pass over the points.
#pragma once

#include "grid.hpp"
#include "particles.hpp"
#include "transfers.hpp"

namespace mpmdem::mpm {

// grid.vstar_i = v* of order m >= 1 from grid.v0_i (0 on empty nodes). buf holds the scratch
// node fields.
template <int W>
void xpic_velocity(const Particles& p, const Stencils<W>& s, Grid& grid, int m,
                   ScatterBuffers& buf);

}  // namespace mpmdem::mpm

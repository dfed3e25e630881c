// Particle <-> grid transfers of one explicit MPM step, as free functions that read like the
// algorithm. All of them use the stencils computed once per point per step at x_p^n.
//
// Threads: loops over points and over nodes are OpenMP-parallel. Scatters (P2G, the MUSL
// re-projection) write into per-thread copies of the node fields that are then summed node
// by node (no atomics, no locks); for a fixed thread count the result is deterministic.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "grid.hpp"
#include "particles.hpp"
#include "shape_functions.hpp"

namespace mpmdem::mpm {

// Per-thread node fields for the scatters (threads 1..T-1; thread 0 writes into the grid).
// Kept between steps: no allocation per step once sized.
struct ScatterBuffers {
  std::vector<std::vector<double>> m;
  std::vector<std::vector<Vec3>> mv;
  std::vector<std::vector<Vec3>> f;
  std::vector<Vec3> next;  // XPIC's node field (xpic.cpp)
  void resize(std::size_t nodes, int threads);
};

template <int W>
using Stencils = std::vector<Stencil<W>>;

// s_p = stencil of x_p (every x_p must be inside the grid: Grid::contains).
template <class Shape>
void compute_stencils(const Grid& grid, const std::vector<Vec3>& x_p, Stencils<Shape::kWidth>& s);

// P2G: m_i = sum_p N_ip m_p,  f_i = -sum_p V_p sigma_p grad N_ip,
//   APIC:     mv_i = sum_p N_ip m_p (v_p + C_p (x_i - x_p)),
//   PIC/FLIP: mv_i = sum_p N_ip m_p v_p.
template <int W>
void p2g(const Particles& p, const Stencils<W>& s, Grid& grid, Transfer transfer,
         ScatterBuffers& buf);

// Grid update on nodes with mass: v0_i = mv_i / m_i; f_i += m_i g; local (Cundall) damping
// f_i -= alpha |f_i| sign(v0_i) per component; v_i = v0_i + dt f_i / m_i. Empty nodes: 0.
void grid_update(Grid& grid, const Vec3& gravity, double damping, double dt);

// G2P, x_p += dt sum N v_i, then (reproject = MUSL) the new momenta back to the grid with the
// same transfer (and the stencils of x_p^n). Each transfer is a rule of its own
// (transfer_pic_flip.hpp, transfer_apic.hpp, transfer_xpic.hpp; transfer_rule.hpp), chosen
// once per call; P2G takes the same rule:
//   APIC:     v_p = sum N v_i,  C_p = sum_i v_i (D_p^-1 N_ip (x_i - x_p))^T  (Jiang et al. 2015;
//             conserves angular momentum; it still projects away the non-affine part of the
//             velocities at every step, docs/transfers.md); with flip > 0 (a time scale) v_p is
//             the PIC/FLIP blend below and C_p stays APIC's (Fei et al. 2021);
//   PIC/FLIP: v_p = flip (v_p + sum N (v_i - v0_i)) + (1 - flip) sum N v_i;
//   XPIC:     v_p = sum N (v*_i + v_i - v0_i)  (grid.vstar_i from xpic_velocity).
// With `walls` (v_free: the node velocities before the walls and constraints), also writes
// per point the work their velocity jumps v_i - v_free,i did on it (energy_budget.hpp,
// W_transfer_walls; wall_work_tap.hpp). The walls' work and the re-projection ride on the
// one pass over the points as taps chosen once per call (g2p_tap.hpp, musl_tap.hpp).
struct WallWork {
  const std::vector<Vec3>* v_free = nullptr;  // per node
  std::vector<double>* work = nullptr;        // per point, resized by g2p [J]
};
template <int W>
void g2p(Particles& p, const Stencils<W>& s, Grid& grid, Transfer transfer, double flip, double dt,
         bool reproject, ScatterBuffers& buf, const WallWork& walls = {});

// Angular momentum about the origin of the points, as the next P2G puts it on the grid:
// sum_p m_p x_p x v_p, plus with APIC sum_p sum_i N_ip (x_i - x_p) x m_p C_p (x_i - x_p).
template <int W>
Vec3 angular_momentum(const Particles& p, const Stencils<W>& s, const Grid& grid,
                      Transfer transfer);

// MUSL: v_i = mv_i / m_i from the re-projected momentum (0 on empty nodes).
void grid_velocity_from_momentum(Grid& grid);

// grad v_p = sum_i v_i (x) grad N_ip;  dF_p = I + dt grad v_p;  F_p = dF_p F_p;
// V_p = det(dF_p) V_p. Returns the index of the first point with det(dF_p) <= 0 or a
// non-finite dF_p (its dF_p is stored, F_p and V_p are not updated), or npos.
inline constexpr std::size_t kNoPoint = std::numeric_limits<std::size_t>::max();
template <int W>
std::size_t update_deformation(Particles& p, const Stencils<W>& s, const Grid& grid, double dt);

}  // namespace mpmdem::mpm

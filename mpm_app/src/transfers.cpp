#include "transfers.hpp"
#include "node_loops.hpp"
#include "parallel.hpp"
#include "transfer_apic.hpp"
#include "transfer_pic_flip.hpp"
#include "transfer_xpic.hpp"

#include <omp.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace mpmdem::mpm {

using detail::for_each_node;
using detail::for_each_node_affine;
using detail::reduce_into;

namespace {

// Calls fn(Rule{}) with the transfer rule of `transfer` (transfer_rule.hpp): the one place a
// transfer is chosen.
template <class Fn>
void with_transfer_rule(Transfer transfer, Fn&& fn) {
  switch (transfer) {
    case Transfer::kAPIC:
      fn(ApicRule{});
      return;
    case Transfer::kXPIC:
      fn(XpicRule{});
      return;
    case Transfer::kPicFlip:
      break;
  }
  fn(PicFlipRule{});
}

}  // namespace

void ScatterBuffers::resize(std::size_t nodes, int threads) {
  const auto copies = static_cast<std::size_t>(std::max(0, threads - 1));
  m.resize(copies);
  mv.resize(copies);
  f.resize(copies);
  for (std::size_t t = 0; t < copies; ++t) {
    m[t].resize(nodes);
    mv[t].resize(nodes);
    f[t].resize(nodes);
  }
}

template <class Shape>
void compute_stencils(const Grid& grid, const std::vector<Vec3>& x_p, Stencils<Shape::kWidth>& s) {
  s.resize(x_p.size());
  const auto n = static_cast<std::ptrdiff_t>(x_p.size());
#pragma omp parallel for schedule(static) if (n > kParallelMin)
  for (std::ptrdiff_t p = 0; p < n; ++p) {
    assert(grid.contains(x_p[p]));
    s[p] = make_stencil<Shape>(x_p[p], grid.origin, grid.inv_h, grid.axes);
    assert(s[p].base[0] >= -Grid::kGhost && s[p].base[1] >= -Grid::kGhost &&
           s[p].base[2] >= -Grid::kGhost);
    assert(s[p].base[0] + Shape::kWidth <= grid.cells[0] + Grid::kGhost + 1 &&
           s[p].base[1] + Shape::kWidth <= grid.cells[1] + Grid::kGhost + 1 &&
           s[p].base[2] + Shape::kWidth <= grid.cells[2] + Grid::kGhost + 1);
  }
}

template <int W, class Rule>
void p2g_with(const Particles& p, const Stencils<W>& s, Grid& grid, ScatterBuffers& buf) {
  const int threads = omp_get_max_threads();
  buf.resize(grid.size(), threads);
  const auto n = static_cast<std::ptrdiff_t>(p.size());
#pragma omp parallel num_threads(threads) if (n > kParallelMin)
  {
    const int t = omp_get_thread_num();
    const int used = omp_get_num_threads();
    std::vector<double>& m_i = t == 0 ? grid.m_i : buf.m[t - 1];
    std::vector<Vec3>& mv_i = t == 0 ? grid.mv_i : buf.mv[t - 1];
    std::vector<Vec3>& f_i = t == 0 ? grid.f_i : buf.f[t - 1];
    std::fill(m_i.begin(), m_i.end(), 0.0);
    std::fill(mv_i.begin(), mv_i.end(), Vec3::Zero());
    std::fill(f_i.begin(), f_i.end(), Vec3::Zero());
    // Project mass, momentum and internal force to the grid.
#pragma omp for schedule(static)
    for (std::ptrdiff_t q = 0; q < n; ++q) {
      const double m_p = p.m[q];
      const Vec3 mv_p = m_p * p.v[q];
      const Mat3 Vsigma = p.V[q] * p.sigma[q];
      if constexpr (Rule::kAffine) {
        // APIC: mv_i = sum_p N_ip m_p (v_p + C_p (x_i - x_p)).
        const Mat3 mC_p = m_p * p.C[q];
        for_each_node_affine(
            grid, s[q],
            [&](std::size_t i, double N, const Vec3& gradN, const Vec3& dx, const Vec3&) {
              m_i[i] += N * m_p;
              mv_i[i] += N * (mv_p + mC_p * dx);
              f_i[i] -= Vsigma * gradN;
            });
      } else {
        for_each_node(grid, s[q], [&](std::size_t i, double N, const Vec3& gradN) {
          m_i[i] += N * m_p;
          mv_i[i] += N * mv_p;
          f_i[i] -= Vsigma * gradN;
        });
      }
    }
    if (used > 1) {
      reduce_into(grid.m_i, buf.m, used);
      reduce_into(grid.mv_i, buf.mv, used);
      reduce_into(grid.f_i, buf.f, used);
    }
  }
}

template <int W>
void p2g(const Particles& p, const Stencils<W>& s, Grid& grid, Transfer transfer,
         ScatterBuffers& buf) {
  with_transfer_rule(transfer, [&](auto rule) { p2g_with<W, decltype(rule)>(p, s, grid, buf); });
}

void grid_update(Grid& grid, const Vec3& gravity, double damping, double dt) {
  const auto n = static_cast<std::ptrdiff_t>(grid.size());
  const double floor = grid.mass_floor;
#pragma omp parallel for schedule(static) if (n > kParallelMin)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const double m = grid.m_i[i];
    if (!(m > floor)) {
      grid.v0_i[i].setZero();
      grid.v_i[i].setZero();
      continue;
    }
    const Vec3 v0 = grid.mv_i[i] / m;
    Vec3 f = grid.f_i[i] + m * gravity;
    if (damping > 0.0) {
      for (int d = 0; d < 3; ++d) {
        const double sign = (v0[d] > 0.0) - (v0[d] < 0.0);
        f[d] -= damping * std::abs(f[d]) * sign;
      }
    }
    grid.f_i[i] = f;
    grid.v0_i[i] = v0;
    grid.v_i[i] = v0 + (dt / m) * f;
  }
}

template <int W, class Rule>
void g2p_with(Particles& p, const Stencils<W>& s, Grid& grid, double flip, double dt,
              bool reproject, ScatterBuffers& buf, const WallWork& walls) {
  const int threads = omp_get_max_threads();
  if (reproject) buf.resize(grid.size(), threads);
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  const bool track = walls.v_free != nullptr;
  assert(!track || (walls.work != nullptr && walls.v_free->size() == grid.size()));
  if (track) walls.work->resize(p.size());
  const Vec3* v_free = track ? walls.v_free->data() : nullptr;
  assert(p.state.size() == p.size());
#pragma omp parallel num_threads(threads) if (n > kParallelMin)
  {
    const int t = omp_get_thread_num();
    const int used = omp_get_num_threads();
    std::vector<Vec3>& mv_i = t == 0 ? grid.mv_i : buf.mv[t - 1];
    if (reproject) std::fill(mv_i.begin(), mv_i.end(), Vec3::Zero());
      // Interpolate the new velocity and its increment back to the points; move them.
#pragma omp for schedule(static)
    for (std::ptrdiff_t q = 0; q < n; ++q) {
      // Every transfer blends v_p = flip (v_p + sum N (v_i - v0_i)) + (1 - flip) v_target,
      // flip > 0 only with a FLIP share (solver.flip_time_scale or flip_velocity_scale).
      G2PGather g;
      const Vec3 v_old = p.v[q];
      const Mat3 C_old = track && Rule::kAffine ? p.C[q] : Mat3::Zero().eval();
      Rule::gather(grid, s[q], p, static_cast<std::size_t>(q), v_free, g);
      p.v[q] = flip * (p.v[q] + g.dv) + (1.0 - flip) * g.v_target;
      if (track) {
        // sum_i N jump_i . C_mean dx_i = (sum_i N jump_i dx_i^T) : C_mean; 0 without APIC.
        double w = g.jump.dot(0.5 * (v_old + p.v[q]));
        if constexpr (Rule::kAffine) {
          w += (g.jump_dx.array() * (0.5 * (C_old + p.C[q])).array()).sum();
        }
        (*walls.work)[q] = -p.m[q] * w;
      }
      p.x[q] += dt * g.v_pic;
      if (reproject) {
        // MUSL: the new point momenta back on the grid (same stencils, same transfer).
        const Vec3 mv_p = p.m[q] * p.v[q];
        if constexpr (Rule::kAffine) {
          const Mat3 mC_p = p.m[q] * p.C[q];
          for_each_node_affine(
              grid, s[q], [&](std::size_t i, double N, const Vec3&, const Vec3& dx, const Vec3&) {
                mv_i[i] += N * (mv_p + mC_p * dx);
              });
        } else {
          for_each_node(grid, s[q],
                        [&](std::size_t i, double N, const Vec3&) { mv_i[i] += N * mv_p; });
        }
      }
    }
    if (reproject && used > 1) reduce_into(grid.mv_i, buf.mv, used);
  }
}

template <int W>
void g2p(Particles& p, const Stencils<W>& s, Grid& grid, Transfer transfer, double flip, double dt,
         bool reproject, ScatterBuffers& buf, const WallWork& walls) {
  with_transfer_rule(transfer, [&](auto rule) {
    g2p_with<W, decltype(rule)>(p, s, grid, flip, dt, reproject, buf, walls);
  });
}

void grid_velocity_from_momentum(Grid& grid) {
  const auto n = static_cast<std::ptrdiff_t>(grid.size());
  const double floor = grid.mass_floor;
#pragma omp parallel for schedule(static) if (n > kParallelMin)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const double m = grid.m_i[i];
    if (m > floor) {
      grid.v_i[i] = grid.mv_i[i] / m;
    } else {
      grid.v_i[i].setZero();
    }
  }
}

template <int W>
std::size_t update_deformation(Particles& p, const Stencils<W>& s, const Grid& grid, double dt) {
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  std::size_t bad = kNoPoint;
#pragma omp parallel for schedule(static) if (n > kParallelMin) reduction(min : bad)
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    // grad_v(a, b) = sum_i v_i[a] dN_i/dx_b, accumulated column by column.
    Vec3 gx = Vec3::Zero(), gy = Vec3::Zero(), gz = Vec3::Zero();
    for_each_node(grid, s[q], [&](std::size_t i, double, const Vec3& gradN) {
      const Vec3& v = grid.v_i[i];
      gx += gradN[0] * v;
      gy += gradN[1] * v;
      gz += gradN[2] * v;
    });
    Mat3 grad_v;
    grad_v << gx, gy, gz;
    const Mat3 dF = Mat3::Identity() + dt * grad_v;
    const double J = dF.determinant();
    p.dF[q] = dF;
    if (!(J > 0.0) || !std::isfinite(J)) {
      bad = std::min(bad, static_cast<std::size_t>(q));
      continue;
    }
    p.F[q] = dF * p.F[q];
    p.V[q] *= J;
  }
  return bad;
}

template <int W>
Vec3 angular_momentum(const Particles& p, const Stencils<W>& s, const Grid& grid,
                      Transfer transfer) {
  Vec3 L = Vec3::Zero();
  for (std::size_t q = 0; q < p.size(); ++q) {
    L += p.m[q] * p.x[q].cross(p.v[q]);
    if (transfer != Transfer::kAPIC) continue;
    // sum_i N_ip (x_i - x_p) x m_p C_p (x_i - x_p): what the affine field adds on the grid.
    const Mat3 mC_p = p.m[q] * p.C[q];
    for_each_node_affine(grid, s[q],
                         [&](std::size_t, double N, const Vec3&, const Vec3& dx, const Vec3&) {
                           L += N * dx.cross(mC_p * dx);
                         });
  }
  return L;
}

// The two shape functions.
template void compute_stencils<LinearShape>(const Grid&, const std::vector<Vec3>&, Stencils<2>&);
template void compute_stencils<QuadraticBSplineShape>(const Grid&, const std::vector<Vec3>&,
                                                      Stencils<3>&);
template void p2g<2>(const Particles&, const Stencils<2>&, Grid&, Transfer, ScatterBuffers&);
template void p2g<3>(const Particles&, const Stencils<3>&, Grid&, Transfer, ScatterBuffers&);
template void g2p<2>(Particles&, const Stencils<2>&, Grid&, Transfer, double, double, bool,
                     ScatterBuffers&, const WallWork&);
template void g2p<3>(Particles&, const Stencils<3>&, Grid&, Transfer, double, double, bool,
                     ScatterBuffers&, const WallWork&);
template Vec3 angular_momentum<2>(const Particles&, const Stencils<2>&, const Grid&, Transfer);
template Vec3 angular_momentum<3>(const Particles&, const Stencils<3>&, const Grid&, Transfer);
template std::size_t update_deformation<2>(Particles&, const Stencils<2>&, const Grid&, double);
template std::size_t update_deformation<3>(Particles&, const Stencils<3>&, const Grid&, double);

}  // namespace mpmdem::mpm

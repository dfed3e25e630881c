#include "transfers.hpp"
#include "musl_tap.hpp"
#include "node_loops.hpp"
#include "parallel.hpp"
#include "transfer_apic.hpp"
#include "transfer_pic_flip.hpp"
#include "transfer_xpic.hpp"
#include "wall_work_tap.hpp"

#include <omp.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <tuple>
#include <utility>

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

// Calls fn(tap) for each tap of a tuple, in order.
template <class Taps, class Fn>
inline void each_tap(Taps& taps, Fn&& fn) {
  std::apply([&](auto&... tap) { (fn(tap), ...); }, taps);
}

// Calls fn(tap, sums) for each tap and its per-point sums, in order.
template <class Taps, class Sums, class Fn, std::size_t... k>
inline void each_tap(Taps& taps, Sums& sums, Fn&& fn, std::index_sequence<k...>) {
  (fn(std::get<k>(taps), std::get<k>(sums)), ...);
}
template <class Taps, class Sums, class Fn>
inline void each_tap(Taps& taps, Sums& sums, Fn&& fn) {
  each_tap(taps, sums, fn, std::make_index_sequence<std::tuple_size_v<Taps>>{});
}

// One thread's share of G2P's pass, with its own copies of the taps (g2p_tap.hpp).
template <int W, class Rule, class... Taps>
void g2p_points(Particles& p, const Stencils<W>& s, const Grid& grid, double flip, double dt,
                const Taps&... shared) {
  std::tuple<Taps...> taps{shared...};
  each_tap(taps, [](auto& tap) { tap.start_thread(); });
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  // Interpolate the new velocity and its increment back to the points; move them.
#pragma omp for schedule(static)
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const auto pq = static_cast<std::size_t>(q);
    std::tuple<typename Taps::Sums...> sums;  // each tap's over this point's nodes
    each_tap(taps, sums, [&](auto& tap, auto& sum) { tap.start_point(sum, p, pq); });
    G2PGather g;
    Rule::gather(grid, s[q], p, pq, g, [&](std::size_t i, double N, const Vec3& dx) {
      each_tap(taps, sums, [&](auto& tap, auto& sum) { tap.at_node(sum, i, N, dx); });
    });
    // Every transfer blends v_p = flip (v_p + sum N (v_i - v0_i)) + (1 - flip) v_target,
    // flip > 0 only with a FLIP share (solver.flip_time_scale or flip_velocity_scale).
    p.v[q] = flip * (p.v[q] + g.dv) + (1.0 - flip) * g.v_target;
    each_tap(taps, sums, [&](auto& tap, auto& sum) { tap.finish_point(sum, grid, s[q], p, pq); });
    p.x[q] += dt * g.v_pic;
  }
  each_tap(taps, [](auto& tap) { tap.finish_thread(); });
}

template <int W, class Rule, class... Taps>
void g2p_with(Particles& p, const Stencils<W>& s, Grid& grid, double flip, double dt,
              const Taps&... taps) {
  assert(p.state.size() == p.size());
  const auto n = static_cast<std::ptrdiff_t>(p.size());
#pragma omp parallel num_threads(omp_get_max_threads()) if (n > kParallelMin)
  g2p_points<W, Rule>(p, s, grid, flip, dt, taps...);
}

// The taps G2P carries for the rule, each on or off for the whole call: the walls' work when
// it is measured, MUSL's re-projection with `reproject`.
template <class Rule>
std::tuple<WallWorkTap<Rule::kAffine>, MuslTap<Rule::kAffine>> g2p_taps(
    Grid& grid, std::size_t points, bool reproject, ScatterBuffers& buf, const WallWork& walls) {
  return {WallWorkTap<Rule::kAffine>(walls, grid, points),
          MuslTap<Rule::kAffine>(grid, buf, reproject)};
}

template <int W>
void g2p(Particles& p, const Stencils<W>& s, Grid& grid, Transfer transfer, double flip, double dt,
         bool reproject, ScatterBuffers& buf, const WallWork& walls) {
  with_transfer_rule(transfer, [&](auto rule) {
    using Rule = decltype(rule);
    std::apply([&](const auto&... taps) { g2p_with<W, Rule>(p, s, grid, flip, dt, taps...); },
               g2p_taps<Rule>(grid, p.size(), reproject, buf, walls));
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

#include "xpic.hpp"
#include "node_loops.hpp"
#include "parallel.hpp"

#include <omp.h>

#include <cassert>

namespace mpmdem::mpm {

namespace {

// out = S+ S u: interpolate u to the points, project it back with the point masses.
template <int W>
void smooth(const Particles& p, const Stencils<W>& s, const Grid& grid, const std::vector<Vec3>& u,
            std::vector<Vec3>& out, ScatterBuffers& buf) {
  const int threads = omp_get_max_threads();
  const auto n = static_cast<std::ptrdiff_t>(p.size());
#pragma omp parallel num_threads(threads) if (n > kParallelMin)
  {
    const int t = omp_get_thread_num();
    const int used = omp_get_num_threads();
    std::vector<Vec3>& mu_i = t == 0 ? out : buf.mv[t - 1];
    std::fill(mu_i.begin(), mu_i.end(), Vec3::Zero());
#pragma omp for schedule(static)
    for (std::ptrdiff_t q = 0; q < n; ++q) {
      Vec3 u_p = Vec3::Zero();
      detail::for_each_node(grid, s[q],
                            [&](std::size_t i, double N, const Vec3&) { u_p += N * u[i]; });
      const Vec3 mu_p = p.m[q] * u_p;
      detail::for_each_node(grid, s[q],
                            [&](std::size_t i, double N, const Vec3&) { mu_i[i] += N * mu_p; });
    }
    if (used > 1) detail::reduce_into(out, buf.mv, used);
    const auto nodes = static_cast<std::ptrdiff_t>(out.size());
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < nodes; ++i) {
      const double m_i = grid.m_i[i];
      out[i] = m_i > grid.mass_floor ? Vec3(out[i] / m_i) : Vec3(Vec3::Zero());
    }
  }
}

}  // namespace

template <int W>
void xpic_velocity(const Particles& p, const Stencils<W>& s, Grid& grid, int m,
                   ScatterBuffers& buf) {
  assert(m >= 1);
  buf.resize(grid.size(), omp_get_max_threads());
  // Richardson form of the binomial sum: v*_1 = v0, v*_{k+1} = v0 + (I - S+S) v*_k, so
  // v*_m = sum_{j<m} (I - S+S)^j v0 = [I - (I - S+S)^m] (S+S)^-1 v0. The same polynomial as
  // sum_k (-1)^(k+1) C(m,k) (S+S)^(k-1) v0, without its alternating binomial coefficients
  // (C(m, m/2) grows like 2^m: the sum cancels digits for large m; this form does not).
  grid.vstar_i = grid.v0_i;
  buf.next.resize(grid.size());
  for (int k = 2; k <= m; ++k) {
    smooth(p, s, grid, grid.vstar_i, buf.next, buf);
    for (std::size_t i = 0; i < grid.size(); ++i) grid.vstar_i[i] += grid.v0_i[i] - buf.next[i];
  }
}

template void xpic_velocity<2>(const Particles&, const Stencils<2>&, Grid&, int, ScatterBuffers&);
template void xpic_velocity<3>(const Particles&, const Stencils<3>&, Grid&, int, ScatterBuffers&);

}  // namespace mpmdem::mpm

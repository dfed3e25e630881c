#include "particle_init.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <vector>

#include "boundary_conditions.hpp"
#include "errors.hpp"
#include "grid.hpp"

namespace mpmdem::mpm {

namespace {

bool inside(const RegionParams& r, const Vec3& x) {
  return (x.array() >= r.min.array()).all() && (x.array() < r.max.array()).all();
}

Vec3 initial_velocity(const RegionParams& r, const Vec3& x) {
  Vec3 v = r.velocity;
  if (r.sine_velocity) {
    const int a = r.sine_axis;
    const double L = r.max[a] - r.min[a];
    v[a] += r.sine_amplitude * std::sin(0.5 * M_PI * (x[a] - r.min[a]) / L);
  }
  return v;
}

// Gauss-Legendre nodes and weights of order n on [-1, 1] (Newton on P_n from the Chebyshev
// guess; converges to round-off in a few iterations for n <= 8).
void gauss_legendre(int n, std::vector<double>& xi, std::vector<double>& wi) {
  xi.assign(static_cast<std::size_t>(n), 0.0);
  wi.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;  // P_0, P_1, then up to P_n by the three-term recurrence
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      const double pn = n == 0 ? 1.0 : p1, pm = n == 1 ? 1.0 : p0;
      dp = n * (x * pn - pm) / (x * x - 1.0);
      const double dx = pn / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    xi[static_cast<std::size_t>(n - 1 - i)] = x;
    wi[static_cast<std::size_t>(n - 1 - i)] = 2.0 / ((1.0 - x * x) * dp * dp);
  }
}

// Candidate point coordinates along one axis and their length weights [m], in increasing
// order. cells: the centres of the n sub-cells of every grid cell, weight h/n. gauss: n
// Gauss-Legendre points in every knot span of the scene's shape functions cut by the region's
// faces (knots: the nodes for trilinear shapes; the cell centres and the domain's ends for
// quadratic B-splines, whose knots are clamped at walls; not the centre of a single cell
// between two walls), weight = span length x Gauss weight.
struct AxisPoint {
  double x, w;
};
std::vector<AxisPoint> axis_points(const Scene& scene, const Grid& grid, const RegionParams& reg,
                                   int d, int n) {
  const double h = grid.h, o = grid.origin[d];
  const int cells = grid.cells[static_cast<std::size_t>(d)];
  std::vector<AxisPoint> out;
  if (!reg.gauss_placement) {
    const double s = h / n;
    for (int i = 0; i < cells * n; ++i) {
      const double x = o + s * (i + 0.5);
      if (x >= reg.min[d] && x < reg.max[d]) out.push_back({x, s});  // as inside() tests
    }
    return out;
  }
  const double lo = std::max(0.0, (reg.min[d] - o) / h);
  const double hi = std::min(static_cast<double>(cells), (reg.max[d] - o) / h);
  std::vector<double> cut{lo, hi};
  const bool b2 = scene.solver.shape == ShapeKind::kQuadraticBSpline;
  const double shift = b2 ? 0.5 : 0.0;
  // A single cell between two walls (a plane-strain slice): the walls hold all its B-spline
  // slots (boundary_conditions.cpp), so no free function needs the cut at its centre.
  const bool slice = b2 && cells == 1 && grid.axes[static_cast<std::size_t>(d)].clamp_lo &&
                     grid.axes[static_cast<std::size_t>(d)].clamp_hi;
  for (int k = 0; k <= cells && !slice; ++k) {
    const double t = k + shift;
    if (t > lo && t < hi) cut.push_back(t);
  }
  std::sort(cut.begin(), cut.end());
  std::vector<double> xi, wi;
  gauss_legendre(n, xi, wi);
  for (std::size_t c = 0; c + 1 < cut.size(); ++c) {
    const double a = cut[c], b = cut[c + 1];
    if (!(b - a > 1e-9)) continue;
    for (std::size_t j = 0; j < xi.size(); ++j) {
      out.push_back({o + h * (a + 0.5 * (b - a) * (1.0 + xi[j])), 0.5 * (b - a) * wi[j] * h});
    }
  }
  return out;
}

}  // namespace

Particles generate_particles(const Scene& scene) {
  Grid grid(scene.grid);
  set_shape_axes(scene, grid);
  const double h = grid.h;
  Particles p;
  for (std::size_t r = 0; r < scene.regions.size(); ++r) {
    const RegionParams& reg = scene.regions[r];
    const std::array<int, 3> n{{reg.points_along(0), reg.points_along(1), reg.points_along(2)}};
    if (*std::min_element(n.begin(), n.end()) < 1) {
      throw SceneError("regions[" + std::to_string(r) + "] '" + reg.name +
                       "': points per cell must be >= 1 along every axis");
    }
    std::array<std::vector<AxisPoint>, 3> ax;
    for (int d = 0; d < 3; ++d) {
      ax[static_cast<std::size_t>(d)] =
          axis_points(scene, grid, reg, d, n[static_cast<std::size_t>(d)]);
    }
    std::size_t count = 0;
    for (const AxisPoint& pz : ax[2]) {
      for (const AxisPoint& py : ax[1]) {
        for (const AxisPoint& px : ax[0]) {
          const Vec3 x(px.x, py.x, pz.x);
          if (!inside(reg, x)) continue;
          bool earlier = false;  // already taken by an earlier region
          for (std::size_t q = 0; q < r && !earlier; ++q) earlier = inside(scene.regions[q], x);
          if (earlier) continue;
          const double volume = px.w * py.w * pz.w;
          p.id.push_back(static_cast<std::int64_t>(p.id.size()));
          p.region.push_back(static_cast<int>(r));
          p.m.push_back(reg.density * volume);
          p.V.push_back(volume);
          p.V0.push_back(volume);
          p.x.push_back(x);
          p.x0.push_back(x);
          p.v.push_back(initial_velocity(reg, x));
          ++count;
        }
      }
    }
    if (count == 0) {
      std::ostringstream msg;
      msg << "regions[" << r << "] '" << reg.name << "' (min [" << reg.min.transpose() << "], max ["
          << reg.max.transpose() << "]) contains no material point: points sit "
          << (reg.gauss_placement ? "at the Gauss points of the knot spans"
                                  : "at the centres of the sub-cells")
          << ", " << n[0] << "x" << n[1] << "x" << n[2] << " per cell (cell_size " << h
          << " m, grid from [" << grid.origin.transpose() << "] to [" << grid.upper().transpose()
          << "]); enlarge the region, move it inside the grid, or raise points_per_cell";
      throw SceneError(msg.str());
    }
  }
  const std::size_t np = p.m.size();
  p.F.assign(np, Mat3::Identity());
  p.dF.assign(np, Mat3::Identity());
  p.sigma.assign(np, Mat3::Zero());
  p.stiffness.assign(np, 0.0);
  p.strain_energy.assign(np, 0.0);
  p.state.assign(np, PointState::kOk);
  return p;
}

std::vector<Mat3> initial_stresses(const Scene& scene, const Particles& p) {
  std::vector<Mat3> sigma(p.size(), Mat3::Zero());
  const Vec3& g = scene.solver.gravity;
  const double g_norm = g.norm();
  if (g_norm == 0.0) return sigma;
  const Vec3 down = g / g_norm;
  const Mat3 vv = down * down.transpose();
  const Mat3 hh = Mat3::Identity() - vv;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const RegionParams& reg = scene.regions.at(static_cast<std::size_t>(p.region[i]));
    if (!reg.geostatic) continue;
    // Top of the box along -g: the corner with the smallest down . x.
    double top = 0.0;
    for (int d = 0; d < 3; ++d) top += down[d] * (down[d] > 0.0 ? reg.min[d] : reg.max[d]);
    const double depth = down.dot(p.x[i]) - top;
    const double sigma_v = -reg.density * g_norm * depth;
    sigma[i] = sigma_v * vv + reg.k0 * sigma_v * hh;
  }
  return sigma;
}

}  // namespace mpmdem::mpm

#include "particle_init.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

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

}  // namespace

Particles generate_particles(const Scene& scene) {
  const Grid grid(scene.grid);
  const double h = grid.h;
  Particles p;
  for (std::size_t r = 0; r < scene.regions.size(); ++r) {
    const RegionParams& reg = scene.regions[r];
    const std::array<int, 3> n{{reg.points_along(0), reg.points_along(1), reg.points_along(2)}};
    if (*std::min_element(n.begin(), n.end()) < 1) {
      throw SceneError("regions[" + std::to_string(r) + "] '" + reg.name +
                       "': points per cell must be >= 1 along every axis");
    }
    const Vec3 spacing(h / n[0], h / n[1], h / n[2]);
    const double volume = spacing.prod();
    const double mass = reg.density * volume;
    // Candidate lattice range: the region's bounding box, clipped to the grid.
    int lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      const double a = std::floor((reg.min[d] - grid.origin[d]) / spacing[d]) - 1.0;
      const double b = std::ceil((reg.max[d] - grid.origin[d]) / spacing[d]) + 1.0;
      lo[d] = static_cast<int>(std::max(0.0, std::min(a, 1e9)));
      hi[d] = static_cast<int>(std::min(
          static_cast<double>(grid.cells[d] * n[static_cast<std::size_t>(d)]), std::max(b, 0.0)));
    }
    std::size_t count = 0;
    for (int k = lo[2]; k < hi[2]; ++k) {
      for (int j = lo[1]; j < hi[1]; ++j) {
        for (int i = lo[0]; i < hi[0]; ++i) {
          const Vec3 x = grid.origin + spacing.cwiseProduct(Vec3(i + 0.5, j + 0.5, k + 0.5));
          if (!inside(reg, x)) continue;
          bool earlier = false;  // already taken by an earlier region
          for (std::size_t q = 0; q < r && !earlier; ++q) earlier = inside(scene.regions[q], x);
          if (earlier) continue;
          p.id.push_back(static_cast<std::int64_t>(p.id.size()));
          p.region.push_back(static_cast<int>(r));
          p.m.push_back(mass);
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
          << reg.max.transpose()
          << "]) contains no material point: points sit at the centres of the " << n[0] << "x"
          << n[1] << "x" << n[2] << " sub-cells of each grid cell (cell_size " << h
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
  p.status.assign(np, 0);
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

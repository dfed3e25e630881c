#include "verification/bar_vibration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "verification/elastic_column.hpp"

namespace mpmdem::mpm {

namespace {

// True if the bar cannot expand sideways: walls on both faces of each lateral axis and the
// region touching them (within half a point spacing).
bool laterally_confined(const Scene& scene, const RegionParams& reg, int axis) {
  const double tol = 0.5 * scene.grid.cell_size /
                     std::max({reg.points_along(0), reg.points_along(1), reg.points_along(2)});
  for (int a = 0; a < 3; ++a) {
    if (a == axis) continue;
    const WallParams& lo = scene.walls[static_cast<std::size_t>(2 * a)];
    const WallParams& hi = scene.walls[static_cast<std::size_t>(2 * a + 1)];
    if (lo.type == WallType::kFree || hi.type == WallType::kFree) return false;
    const double d_lo = scene.grid.origin[a];
    const double d_hi = scene.grid.origin[a] + scene.grid.extent[a];
    if (std::abs(reg.min[a] - d_lo) > tol || std::abs(reg.max[a] - d_hi) > tol) return false;
  }
  return true;
}

}  // namespace

std::vector<double> zero_crossings(const std::vector<double>& t, const std::vector<double>& s) {
  double amplitude = 0.0;
  for (double v : s) amplitude = std::max(amplitude, std::abs(v));
  const double threshold = 0.2 * amplitude;
  std::vector<double> crossings;
  int side = 0;  // sign of the last excursion beyond the threshold; 0: none yet
  double pending = std::numeric_limits<double>::quiet_NaN();  // last crossing off `side`
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (side != 0 && i > 0 && s[i - 1] * side > 0.0 && s[i] * side <= 0.0) {
      const double a = s[i - 1], b = s[i];
      pending = t[i - 1] + a / (a - b) * (t[i] - t[i - 1]);
    }
    if (std::abs(s[i]) > threshold) {
      const int sign = s[i] > 0.0 ? 1 : -1;
      // Confirmed once the signal is well beyond zero on the other side.
      if (side != 0 && sign != side && !std::isnan(pending)) crossings.push_back(pending);
      side = sign;
      pending = std::numeric_limits<double>::quiet_NaN();
    }
  }
  return crossings;
}

BarVibrationMonitor::BarVibrationMonitor(const Scene& scene) {
  if (scene.regions.empty()) throw std::runtime_error("bar_vibration: the scene has no region");
  const RegionParams* bar = &scene.regions.front();
  for (const RegionParams& reg : scene.regions)
    if (reg.sine_velocity) {
      bar = &reg;
      break;
    }
  const int axis = bar->sine_velocity ? bar->sine_axis : 0;
  const ElasticModuli mod = scene_elastic_moduli(scene);
  const double modulus = laterally_confined(scene, *bar, axis) ? mod.M : mod.E;
  expected_.axis = axis;
  expected_.length_m = bar->max[axis] - bar->min[axis];
  expected_.wave_speed_m_s = std::sqrt(modulus / bar->density);
  expected_.period_expected_s = 4.0 * expected_.length_m / expected_.wave_speed_m_s;
}

void BarVibrationMonitor::record(double time, const Particles& p) {
  double P = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) P += p.m[i] * p.v[i][expected_.axis];
  t_.push_back(time);
  P_.push_back(P);
}

BarVibrationResult BarVibrationMonitor::result() const {
  BarVibrationResult r = expected_;
  const std::vector<double> c = zero_crossings(t_, P_);
  r.crossings = static_cast<int>(c.size());
  if (c.size() < 2) {
    r.period_s = std::numeric_limits<double>::quiet_NaN();
    r.period_rel_error = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  // Least-squares slope of crossing time against index: half a period per crossing.
  const double n = static_cast<double>(c.size());
  double k_mean = 0.5 * (n - 1.0), t_mean = 0.0;
  for (double tc : c) t_mean += tc / n;
  double num = 0.0, den = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const double dk = static_cast<double>(k) - k_mean;
    num += dk * (c[k] - t_mean);
    den += dk * dk;
  }
  r.period_s = 2.0 * num / den;
  r.period_rel_error = std::abs(r.period_s - r.period_expected_s) / r.period_expected_s;
  return r;
}

}  // namespace mpmdem::mpm

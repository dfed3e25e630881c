// Verification of the vibrating elastic bar (fixed at x0, free at x0 + L, first-mode initial
// velocity): the period of its axial oscillation against 4 L / c.
//
// The monitor records the total momentum along the bar axis, P(t) = sum m_p v_p,a, after
// every step. P(t) ~ cos(2 pi t / T) for the first mode, so successive zero crossings
// (upward and downward, linearly interpolated between steps) are T/2 apart; T is twice the
// least-squares slope of crossing time against crossing index. A crossing counts only when
// P then goes beyond 20% of its maximum magnitude on the other side, so that noise near zero
// from higher modes does not add crossings.
//
// c = sqrt(M / rho) with the constrained modulus M when the bar is laterally confined
// (both lateral axes have non-free walls and the region spans the domain width), as in the
// scene configs/elastic_bar_vibration.yaml; c = sqrt(E / rho) for a laterally free bar.
#pragma once

#include <vector>

#include "particles.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

struct BarVibrationResult {
  double period_s = 0.0;  // NaN if fewer than two crossings were seen
  double period_expected_s = 0.0;
  double period_rel_error = 0.0;  // NaN if period_s is NaN
  int crossings = 0;
  double wave_speed_m_s = 0.0;
  double length_m = 0.0;
  int axis = 0;
};

class BarVibrationMonitor {
 public:
  // Throws std::runtime_error if the scene has no region to measure.
  explicit BarVibrationMonitor(const Scene& scene);
  void record(double time, const Particles& p);
  BarVibrationResult result() const;
  const std::vector<double>& momentum() const { return P_; }

 private:
  BarVibrationResult expected_;
  std::vector<double> t_;
  std::vector<double> P_;
};

// Zero crossings (interpolated times) of a sampled signal, with the 20% hysteresis above.
std::vector<double> zero_crossings(const std::vector<double>& t, const std::vector<double>& s);

}  // namespace mpmdem::mpm

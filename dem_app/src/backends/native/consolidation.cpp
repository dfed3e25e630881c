// Consolidation to a stress and the end of preparation: see consolidation.hpp.
#include "backends/native/consolidation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "backends/native/integrator.hpp"
#include "backends/native/measures.hpp"

namespace mpmdem::dem::native {

namespace {
// Servo time constant in DEM steps at the stiffness bound. The loose network's response is
// several times softer than the bound: 30 or 200 stalled at 1.8 kPa (creep outran the
// servo), 5 converges from 1.8 to 10 kPa (tests native_block_tiny, test_native_backend).
constexpr double kRelaxSteps = 5;
}  // namespace

Consolidation consolidate(RveState& s, NeighbourList& nl, const Eigen::Vector3d& goal,
                          const ConsolidationParams& p) {
  const double scale = goal.cwiseAbs().maxCoeff();
  if (!(scale > 0)) return {};
  for (long step = 0; step < p.max_steps; step += 100) {
    for (int k = 0; k < 100; ++k) {
      // The strain rate that would close the gap in kRelaxSteps steps at the network's
      // stiffness bound (an upper bound of its response: the approach is slower than that,
      // and stable), at most max_strain_rate; without contacts, proportional to the gap.
      const StressStiffness ss = stress_and_stiffness(s, true);
      const Eigen::Matrix3d& sigma = ss.stress;
      const double m = ss.stiffness;
      Eigen::Matrix3d l = Eigen::Matrix3d::Zero();
      for (int i = 0; i < 3; ++i) {
        // Too little compression (sigma above goal): shorten the cell.
        const double gap = sigma(i, i) - goal[i];
        const double rate =
            !(m > 0) ? p.max_strain_rate * gap / scale : gap / (m * kRelaxSteps * s.dt);
        l(i, i) = -std::clamp(rate, -p.max_strain_rate, p.max_strain_rate);
      }
      s.cell.set_vel_grad(l);
      dem_step(s, nl, p.damping);
    }
    const Eigen::Matrix3d sigma = love_weber_stress(s);
    double err = 0;
    for (int i = 0; i < 3; ++i) err = std::max(err, std::abs(sigma(i, i) - goal[i]) / scale);
    if (err < p.stress_tol && unbalanced_force(s) < p.unbalanced_tol) return {step + 100, true};
  }
  if (p.keep_on_failure) return {p.max_steps, false};
  throw std::runtime_error(not_converged_message(goal, p.max_steps));
}

std::string not_converged_message(const Eigen::Vector3d& goal, long max_steps) {
  return "consolidation to (" + std::to_string(goal[0]) + ", " + std::to_string(goal[1]) + ", " +
         std::to_string(goal[2]) + ") Pa did not converge in " + std::to_string(max_steps) +
         " steps (coupling.native.consolidation_max_steps)";
}

void finish_preparation(RveState& s, NeighbourList& nl, double damping) {
  s.cell.set_vel_grad(Eigen::Matrix3d::Zero());
  dem_step(s, nl, damping);  // the zero gradient becomes active from the next step
  dem_step(s, nl, damping);
  auto& sp = s.spheres;
  for (std::size_t i = 0; i < sp.size(); ++i) {
    sp.ref_ori[i] = sp.ori[i];
    sp.vel.set(i, Vec3::Zero());
    sp.ang_vel.set(i, Vec3::Zero());
  }
}

}  // namespace mpmdem::dem::native

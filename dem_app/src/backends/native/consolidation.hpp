// Preparing a native RVE for coupling, as mpmdem_rve.initialise does with YADE:
//  * consolidate: drive the cell's diagonal strain rate until the principal stresses reach
//    `goal` (tension positive) within stress_tol (relative to the largest |goal|, checked
//    every 100 steps) and the unbalanced force is below unbalanced_tol. YADE uses
//    PeriTriaxController (a cell with mass); this is a proportional strain-rate servo
//    (gap / (stiffness bound * 5 dt), at most max_strain_rate), so consolidated states
//    are equivalent, not identical.
//  * finish_preparation: mpmdem_packing.finish_preparation exactly: zero velocity gradient,
//    two DEM steps, velocities zeroed, reference orientations reset.
#pragma once

#include <Eigen/Core>
#include <string>

#include "backends/native/neighbour_list.hpp"
#include "backends/native/rve_state.hpp"

namespace mpmdem::dem::native {

struct ConsolidationParams {
  double stress_tol = 1e-3;
  double unbalanced_tol = 0.01;
  long max_steps = 200000;
  double max_strain_rate = 10.0;  // [1/s]
  double damping = 0.2;
  bool keep_on_failure = false;  // return instead of throwing when max_steps does not suffice
};

struct Consolidation {
  long steps = 0;         // DEM steps used
  bool converged = true;  // false only with keep_on_failure: the RVE stays as reached
};

// Throws std::runtime_error (not_converged_message) if max_steps does not suffice and
// keep_on_failure is not set.
Consolidation consolidate(RveState& s, NeighbourList& nl, const Eigen::Vector3d& goal,
                          const ConsolidationParams& p);
std::string not_converged_message(const Eigen::Vector3d& goal, long max_steps);
void finish_preparation(RveState& s, NeighbourList& nl, double damping);

}  // namespace mpmdem::dem::native

// One DEM step of a native RVE in YADE's order (Scene::moveToNextTimeStep with the engines
// ForceResetter, InsertionSortCollider, InteractionLoop, NewtonIntegrator):
//   1. the cell moves with its active velocity gradient (Cell::integrateAndUpdate);
//   2. forces are reset; existing contacts are updated (ScGeom, CundallStrack) and the ones
//      that opened are removed; pairs of the Verlet list that now overlap become contacts;
//   3. NewtonIntegrator: the requested velocity gradient becomes active, then leap-frog with
//      Cundall's non-viscous damping on the fluctuating velocity, the homogeneous-field terms
//      of Cell.homoDeform = 2 (YADE's default) and rotations by the angular velocity.
#pragma once

#include "backends/native/neighbour_list.hpp"
#include "backends/native/rve_state.hpp"

namespace mpmdem::dem::native {

void dem_step(RveState& s, NeighbourList& nl, double damping);
// Steps 2 and 3 split out (tests drive them separately).
void compute_forces(RveState& s, NeighbourList& nl);
// nl: hands the skin check's max displacement to the list's next ensure() (see
// NeighbourList::moved); s.iter is to be incremented after it, as dem_step does.
void newton(RveState& s, double damping, NeighbourList* nl = nullptr);

}  // namespace mpmdem::dem::native

// Scenes shared by the conservation and energy-budget tests (test_conservation.cpp,
// test_energy_budget.cpp).
#pragma once

#include "scene.hpp"

namespace mpmdem::mpm::test_scenes {

// A block flying with velocity and spin, no gravity, no walls.
inline Scene flying_block(ShapeKind shape, Scheme scheme, Transfer transfer, double flip) {
  Scene s;
  s.name = "flying_block";
  s.grid.origin = Vec3::Zero();
  s.grid.extent = Vec3(1.0, 1.0, 1.0);
  s.grid.cell_size = 0.05;
  RegionParams r;
  r.name = "block";
  r.min = Vec3(0.4, 0.42, 0.45);
  r.max = Vec3(0.6, 0.57, 0.6);
  r.points_per_cell = 2;
  r.density = 1500.0;
  s.regions.push_back(r);
  s.solver.shape = shape;
  s.solver.scheme = scheme;
  s.solver.transfer = transfer;
  s.solver.flip = flip;
  s.solver.gravity = Vec3::Zero();
  s.solver.cfl = 0.4;
  s.solver.end_time = 1.0;
  s.constitutive.youngs_modulus = 1e6;
  s.constitutive.poisson_ratio = 0.25;
  return s;
}

}  // namespace mpmdem::mpm::test_scenes

// Native backend's periodic cell under large deformation: a flip keeps every contact's image
// where it was (only the lattice description changes), tiling doubles a thin cell exactly,
// and the velocity-gradient lag is YADE's (a gradient set before step k moves the cell from
// step k + 1 on).
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "backends/native/cell_regularisation.hpp"
#include "backends/native/integrator.hpp"
#include "backends/native/measures.hpp"

namespace {

using namespace mpmdem::dem::native;

TEST(NativeCell, VelGradActsFromTheStepAfterItIsSet) {
  PeriodicCell c;
  Eigen::Matrix3d l = Eigen::Matrix3d::Zero();
  l(0, 1) = 3.0;
  const double dt = 1e-3;
  c.set_vel_grad(l);
  c.integrate_and_update(dt);  // step 1: the active gradient is still zero
  c.activate_next();
  EXPECT_EQ(c.trsf, Eigen::Matrix3d::Identity());
  c.integrate_and_update(dt);  // step 2: trsf = (I + dt L) trsf
  c.activate_next();
  EXPECT_EQ(c.trsf, Eigen::Matrix3d(Eigen::Matrix3d::Identity() + dt * l));
  EXPECT_EQ(c.pending_vel_grad(), l);  // stays active
}

TEST(NativeCell, FlipKeepsContactImagesInPlace) {
  RveState s;
  s.cell.hsize << 1e-2, 1.4e-2, 0, 0, 1e-2, 0, 0, 0, 1e-2;  // shear 1.4: flippable
  const double m = 1e-5;
  s.spheres.push_back(1e-3, m, 0.4 * m * 1e-6, Vec3(1e-3, 2e-3, 5e-3));
  s.spheres.push_back(1e-3, m, 0.4 * m * 1e-6, Vec3(8e-3, 9e-3, 5e-3));
  const Eigen::Vector3i c(1, -1, 0);
  s.contacts.add(0, 1, to_cell_dist(c));
  const Vec3 before = s.spheres.pos[1] + s.cell.shift(c);
  const double volume = s.cell.volume();
  NeighbourList nl;
  ASSERT_TRUE(flip_cell(s, nl));
  EXPECT_LT(std::abs(s.cell.hsize(0, 1)), 0.5 * 1e-2 + 1e-15);  // less skewed
  EXPECT_NEAR(s.cell.volume(), volume, 1e-12 * volume);
  const Vec3 after = s.spheres.pos[1] + s.cell.shift(s.contacts.cell[0]);
  EXPECT_LT((after - before).norm(), 1e-15);
  EXPECT_FALSE(flip_cell(s, nl));  // nothing left to flip
}

TEST(NativeCell, TilingDoublesAThinCellExactly) {
  RveState s;
  s.material = Material{6e8, 0.8, 2500, std::atan(0.518)};
  s.cell.hsize = Eigen::Vector3d(2e-2, 2e-2, 4e-3).asDiagonal();  // 4 mm < 2.2 * 2 mm
  const double m = 1e-5;
  s.spheres.push_back(1e-3, m, 0.4 * m * 1e-6, Vec3(5e-3, 5e-3, 1e-3));
  s.spheres.push_back(1e-3, m, 0.4 * m * 1e-6, Vec3(5e-3 + 1.999e-3, 5e-3, 1e-3));
  s.cell.vel_grad(2, 2) = -1.0;
  s.spheres.vel.set(0, Vec3(0, 0, -1e-3));
  s.dt = 1e-7;
  NeighbourList nl;
  compute_forces(s, nl);
  const Eigen::Matrix3d sigma = love_weber_stress(s);
  ASSERT_EQ(s.contacts.size(), 1u);
  EXPECT_EQ(tile_if_thin(s, nl), 2);
  ASSERT_EQ(s.spheres.size(), 4u);
  EXPECT_EQ(s.cell.hsize(2, 2), 8e-3);
  EXPECT_EQ(s.spheres.pos[2], Vec3(5e-3, 5e-3, 5e-3));
  // The copy moves with the homogeneous field: v + L shift.
  EXPECT_EQ(s.spheres.vel[2], Vec3(0, 0, -1e-3 - 4e-3));
  EXPECT_EQ(s.contacts.size(), 0u);  // rebuilt without shear forces, as YADE's collider
  compute_forces(s, nl);
  EXPECT_EQ(s.contacts.size(), 2u);
  // Twice the contacts in twice the volume: the same stress.
  EXPECT_LT((love_weber_stress(s) - sigma).norm(), 1e-9 * sigma.norm());
  EXPECT_EQ(tile_if_thin(s, nl), -1);  // 8 mm >= 4.4 mm
}

}  // namespace

// The energy budget's transfer terms (energy_budget.hpp): W_transfer is what the particle-grid
// transfers remove (pure PIC on a spinning block), W_transfer_walls the part of it the walls
// cause (a block sliding into a fixed base, pure FLIP).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "scene_builder.hpp"
#include "solver.hpp"

using namespace mpmdem::mpm;
using test_fixture::flying_block;
using test_fixture::SceneBuilder;

// The energy budget's W_transfer (energy_budget.hpp) is the kinetic energy the transfers
// remove. Pure PIC projects the velocities twice per step (P2G and G2P), and with lumped
// masses neither projection can add kinetic energy: W_transfer never decreases. A rigid
// spin is not in the grid's space, so PIC dissipates it, and the measured W_transfer is
// then the budget's residual E_err up to the time integration's error. A uniform
// translation is in that space: nothing is removed.
TEST(EnergyBudget, TransferTermIsWhatPicRemoves) {
  const SceneBuilder scene = flying_block()
                                 .shape(ShapeKind::kQuadraticBSpline)
                                 .scheme(Scheme::kUSL)
                                 .transfer(Transfer::kPicFlip, 0.0);
  Particles p = scene.particles();
  const Vec3 c(0.5, 0.495, 0.525), omega(2.0, -1.0, 3.0);
  for (std::size_t q = 0; q < p.size(); ++q) p.v[q] = omega.cross(p.x[q] - c);
  Solver solver = scene.solver(p);
  const double E_k0 = solver.energies().E_k;
  double W_prev = 0.0;
  for (int n = 0; n < 60; ++n) {
    solver.step();
    const double W = solver.energy_budget().W_transfer;
    ASSERT_GE(W, W_prev - 1e-12 * E_k0) << "step " << n + 1;
    W_prev = W;
  }
  const EnergyBudget& b = solver.energy_budget();
  const Energies e = solver.energies();
  const double E_err = b.E_k0 - e.E_k - b.W_int - b.W_damp - b.W_bc;  // no gravity: E_p fixed
  EXPECT_GT(E_err, 0.2 * E_k0);  // PIC takes a large part of the spin's energy
  EXPECT_NEAR(b.W_transfer, E_err, 0.02 * E_err);
  std::printf("spinning block, PIC, 60 steps: E_err / E_k0 = %.4f, W_transfer / E_k0 = %.4f\n",
              E_err / E_k0, b.W_transfer / E_k0);

  Particles t = scene.particles();
  for (auto& v : t.v) v = Vec3(0.7, -0.3, 0.2);
  Solver translating = scene.solver(t);
  for (int n = 0; n < 100; ++n) translating.step();
  EXPECT_LT(std::abs(translating.energy_budget().W_transfer), 1e-12 * translating.energies().E_k);
  EXPECT_EQ(b.W_transfer_walls, 0.0);  // no wall reached
}

// W_transfer_walls (energy_budget.hpp): the walls' velocity jumps move every point by
// sum_i N_ip dv_i, so the points lose more than the nodes the walls stop whenever a point is
// only partly on wall nodes. A block sliding at a uniform u into a fixed base, pure FLIP, no
// stress and no gravity: in the first step only the base acts. A point keeps (1 - S_p) u,
// S_p = sum over wall nodes of N_ip; the nodes lose W_bc = 1/2 |u|^2 sum_p m_p S_p, the
// points 1/2 |u|^2 sum_p m_p (2 S_p - S_p^2), and the excess is
// W_transfer_walls = 1/2 |u|^2 sum_p m_p S_p (1 - S_p), all of W_transfer.
TEST(EnergyBudget, WallsStopThePointsMoreThanTheNodes) {
  for (ShapeKind shape : {ShapeKind::kLinear, ShapeKind::kQuadraticBSpline}) {
    const SceneBuilder scene =
        flying_block()
            .shape(shape)
            .scheme(Scheme::kUSL)
            .transfer(Transfer::kPicFlip, 1.0)
            .with([](Scene& s) { s.regions[0].min.z() = 0.0; })  // on the base
            .base(WallType::kFixed);
    Particles p = scene.particles();
    const Vec3 u(0.5, 0.1, -0.2);
    for (auto& v : p.v) v = u;
    Solver solver = scene.solver(p);
    const double K0 = solver.energies().E_k;
    solver.step();
    const Particles& P = solver.particles();
    double excess = 0.0, touched = 0.0, mass = 0.0;
    for (std::size_t q = 0; q < P.size(); ++q) {
      const double S = 1.0 - P.v[q].dot(u) / u.squaredNorm();
      ASSERT_LT((P.v[q] - (1.0 - S) * u).norm(), 1e-12) << "point " << q;  // only the base acted
      excess += 0.5 * u.squaredNorm() * P.m[q] * S * (1.0 - S);
      if (S > 1e-12) touched += P.m[q];
      mass += P.m[q];
    }
    const EnergyBudget& b = solver.energy_budget();
    EXPECT_GT(touched, 0.03 * mass);  // the base reaches the lowest layer of points (of 24)
    EXPECT_GT(b.W_transfer_walls, 0.05 * b.W_bc);
    EXPECT_NEAR(b.W_transfer_walls, excess, 1e-12 * K0);
    EXPECT_NEAR(b.W_transfer, b.W_transfer_walls, 1e-12 * K0);
    EXPECT_NEAR(K0 - solver.energies().E_k, b.W_bc + b.W_transfer_walls, 1e-12 * K0);
  }
}

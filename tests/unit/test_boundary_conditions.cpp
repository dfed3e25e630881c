// Walls and velocity constraints, checked on small scenes against mechanics:
//   - a block under gravity on a fixed base (started geostatic, damped) stays at rest;
//   - a slip base keeps the tangential velocity of a sliding block exactly, a fixed one
//     does not;
//   - a Coulomb friction base decelerates a sliding block at mu g;
//   - velocity constraints hold their components and are released at a time or when
//     E_k / E_p0 drops below the ratio after the minimum time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "boundary_conditions.hpp"
#include "scene_builder.hpp"
#include "solver.hpp"

using namespace mpmdem::mpm;
using test_fixture::Face;
using test_fixture::SceneBuilder;

namespace {

constexpr double kG = 9.81;

// A block of E = 1e7 Pa, nu = 0.3, rho = 2000 kg/m^3 (c = 82 m/s; the builder's defaults) in a
// grid of 0.025 m cells, gravity g along -z.
SceneBuilder block_scene(const Vec3& extent, const Vec3& min, const Vec3& max) {
  return SceneBuilder().name("block").domain(extent).cell(0.025).block(min, max);
}

double M_of(const Scene& s) {
  const double E = s.constitutive.youngs_modulus, nu = s.constitutive.poisson_ratio;
  return E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
}

Vec3 mean_velocity(const Particles& p) {
  Vec3 mv = Vec3::Zero();
  double m = 0.0;
  for (std::size_t q = 0; q < p.size(); ++q) {
    mv += p.m[q] * p.v[q];
    m += p.m[q];
  }
  return mv / m;
}

double max_speed(const Particles& p) {
  double v = 0.0;
  for (const Vec3& v_p : p.v) v = std::max(v, v_p.norm());
  return v;
}

void run_until(Solver& solver, double t) {
  while (solver.time() < t) solver.step();
}

}  // namespace

TEST(Walls, BlockOnAFixedBaseStaysAtRest) {
  // 0.1 x 0.05 x 0.3 m between slip side walls on a fixed base, starting from the 1D-strain
  // geostatic state (K0 = nu / (1 - nu)).
  const SceneBuilder b = block_scene(Vec3(0.1, 0.05, 0.4), Vec3::Zero(), Vec3(0.1, 0.05, 0.3))
                             .geostatic(0.3 / 0.7)
                             .side_walls(WallType::kSlip)
                             .base(WallType::kFixed)
                             .damping(0.1);
  const Scene s = b.build();
  Solver solver = b.solver();
  // Scales of the self-weight problem: strain rho g H / M, settlement rho g H^2 / (2 M),
  // and the velocity a settling wave would carry, strain * c.
  const double H = 0.3, M = M_of(s), rho = 2000.0;
  const double strain = rho * kG * H / M, settlement = 0.5 * strain * H;
  const double v_scale = strain * std::sqrt(M / rho);
  double v_max = 0.0;
  while (solver.time() < 0.2) {
    solver.step();
    v_max = std::max(v_max, max_speed(solver.particles()));
  }
  double u_max = 0.0;
  const Particles& p = solver.particles();
  for (std::size_t q = 0; q < p.size(); ++q) u_max = std::max(u_max, (p.x[q] - p.x0[q]).norm());
  std::cout << "resting block: max |v| " << v_max << " m/s (scale " << v_scale << "), max |u| "
            << u_max << " m (settlement scale " << settlement << ")\n";
  EXPECT_LT(v_max, 0.05 * v_scale);
  EXPECT_LT(u_max, 0.05 * settlement);
  EXPECT_LT(max_speed(p), 0.01 * v_scale);
}

TEST(Walls, BlockOnAFixedBaseSettlesWithDamping) {
  // The same block started stress-free: it settles, and local damping brings it to rest.
  const SceneBuilder b = block_scene(Vec3(0.1, 0.05, 0.4), Vec3::Zero(), Vec3(0.1, 0.05, 0.3))
                             .side_walls(WallType::kSlip)
                             .base(WallType::kFixed)
                             .damping(0.15);
  const Scene s = b.build();
  Solver solver = b.solver();
  double v_peak = 0.0;
  while (solver.time() < 0.3) {
    solver.step();
    v_peak = std::max(v_peak, max_speed(solver.particles()));
  }
  const double v_end = max_speed(solver.particles());
  // Top settlement against rho g H^2 / (2 M) (cell-averaged stresses: a few % at 12 cells).
  const Particles& p = solver.particles();
  double u_top = 0.0;
  int n_top = 0;
  for (std::size_t q = 0; q < p.size(); ++q) {
    if (p.x0[q].z() < 0.29) continue;
    u_top += p.x0[q].z() - p.x[q].z();
    ++n_top;
  }
  u_top /= n_top;
  const double M = M_of(s), H = 0.3, Z = 0.29375;
  const double u_expected = 2000.0 * kG / M * (H * Z - 0.5 * Z * Z);
  std::cout << "settling block: peak |v| " << v_peak << ", final " << v_end << ", u_top " << u_top
            << " (expected " << u_expected << ")\n";
  EXPECT_LT(v_end, 0.01 * v_peak);
  EXPECT_NEAR(u_top, u_expected, 0.03 * u_expected);
}

namespace {

// A block 0.2 x 0.05 x 0.1 m sliding at 1 m/s along x on the base, slip walls in y.
Solver sliding_block(WallType base, double mu) {
  return block_scene(Vec3(0.6, 0.05, 0.2), Vec3(0.05, 0.0, 0.0), Vec3(0.25, 0.05, 0.1))
      .velocity(Vec3(1.0, 0.0, 0.0))
      .geostatic(0.3 / 0.7)
      .wall(Face::kYMin, WallType::kSlip)
      .wall(Face::kYMax, WallType::kSlip)
      .base(base, mu)
      .flip(1.0)
      .solver();
}

}  // namespace

TEST(Walls, SlipBaseKeepsTheTangentialVelocity) {
  Solver slip = sliding_block(WallType::kSlip, 0.0);
  double min_z = 1.0;
  while (slip.time() < 0.1) {
    slip.step();
    for (const Vec3& x : slip.particles().x) min_z = std::min(min_z, x.z());
  }
  const Vec3 v = mean_velocity(slip.particles());
  EXPECT_NEAR(v.x(), 1.0, 1e-9);
  EXPECT_LT(std::abs(v.z()), 0.01 * kG * slip.time());  // supported, not falling
  EXPECT_GT(min_z, 0.0);

  // The same block on a fixed (no-slip) base is held back.
  Solver fixed = sliding_block(WallType::kFixed, 0.0);
  run_until(fixed, 0.1);
  EXPECT_LT(mean_velocity(fixed.particles()).x(), 0.9);
}

TEST(Walls, FrictionBaseDeceleratesAtMuG) {
  const double mu = 0.3;
  Solver solver = sliding_block(WallType::kFriction, mu);
  run_until(solver, 0.05);
  const double t1 = solver.time(), v1 = mean_velocity(solver.particles()).x();
  run_until(solver, 0.25);
  const double t2 = solver.time(), v2 = mean_velocity(solver.particles()).x();
  const double a = (v2 - v1) / (t2 - t1);
  std::cout << "friction: a = " << a << " m/s^2, -mu g = " << -mu * kG << "\n";
  EXPECT_NEAR(a, -mu * kG, 0.03 * mu * kG);
  // It stops (sliding ends at t = v0 / (mu g) = 0.34 s) and does not reverse.
  run_until(solver, 0.5);
  const double v_end = mean_velocity(solver.particles()).x();
  EXPECT_LT(std::abs(v_end), 0.02);
}

TEST(VelocityConstraints, HeldUntilTheReleaseTime) {
  // A block in the air, propped by a constraint holding v_z = 0 on every node until 0.02 s.
  VelocityConstraintParams c;
  c.name = "prop";
  c.min = Vec3(-1, -1, -1);
  c.max = Vec3(1, 1, 1);
  c.components = {{false, false, true}};
  c.release_time = 0.02;
  Solver solver = block_scene(Vec3(0.2, 0.2, 0.4), Vec3(0.05, 0.05, 0.25), Vec3(0.15, 0.15, 0.35))
                      .constraint(c)
                      .solver();
  ASSERT_EQ(solver.boundary_conditions().constraint_count(), 1u);
  EXPECT_EQ(solver.boundary_conditions().constraint_nodes(0).size(), solver.grid().size());
  double t_release = -1.0;
  while (t_release < 0.0 && solver.time() < 0.1) {
    solver.step();
    const auto events = solver.take_events();
    if (!events.empty()) {
      ASSERT_EQ(events.size(), 1u);
      EXPECT_NE(events[0].find("constraint 'prop' released at t="), std::string::npos) << events[0];
      EXPECT_NE(events[0].find("release_time"), std::string::npos) << events[0];
      t_release = solver.time();
    } else {
      EXPECT_LT(std::abs(mean_velocity(solver.particles()).z()), 1e-12);
    }
  }
  ASSERT_GE(t_release, 0.02);
  EXPECT_LT(t_release, 0.02 + solver.dt() * 1.01);
  EXPECT_FALSE(solver.boundary_conditions().constraint_active(0));
  // Free fall afterwards.
  run_until(solver, t_release + 0.03);
  EXPECT_NEAR(mean_velocity(solver.particles()).z(), -kG * (solver.time() - t_release),
              0.01 * kG * 0.03);
}

TEST(VelocityConstraints, ReleasedWhenKineticEnergyRatioDrops) {
  // A block settling on a fixed base with damping; 'lateral' holds v_x = 0 on the plane
  // x = 0.05 and is released once E_k / E_p0 < ratio after 0.03 s.
  VelocityConstraintParams c;
  c.name = "lateral";
  c.min = Vec3(0.05, -1, -1);
  c.max = Vec3(0.05, 1, 1);
  c.components = {{true, false, false}};
  c.release_kinetic_ratio = 1e-7;
  c.release_min_time = 0.03;
  Solver solver = block_scene(Vec3(0.1, 0.05, 0.3), Vec3::Zero(), Vec3(0.1, 0.05, 0.2))
                      .wall(Face::kYMin, WallType::kSlip)
                      .wall(Face::kYMax, WallType::kSlip)
                      .base(WallType::kFixed)
                      .damping(0.2)
                      .constraint(c)
                      .solver();
  // The plane's nodes: all at x = 0.05.
  for (std::size_t i : solver.boundary_conditions().constraint_nodes(0)) {
    const auto l = solver.grid().lattice(i);
    EXPECT_NEAR(solver.grid().position(l[0], l[1], l[2]).x(), 0.05, 1e-12);
  }
  EXPECT_FALSE(solver.boundary_conditions().constraint_nodes(0).empty());
  const double E_p0 = solver.initial_potential_energy();
  ASSERT_GT(E_p0, 0.0);
  double t_release = -1.0, ratio_at_release = 0.0;
  bool below_before_min_time = false;
  while (t_release < 0.0 && solver.time() < 0.5) {
    solver.step();
    const double ratio = solver.energies().E_k / E_p0;
    const auto events = solver.take_events();
    if (!events.empty()) {
      EXPECT_NE(events[0].find("constraint 'lateral' released at t="), std::string::npos);
      EXPECT_NE(events[0].find("E_k/E_p0="), std::string::npos) << events[0];
      t_release = solver.time();
      ratio_at_release = ratio;
    } else if (solver.time() >= 0.03) {
      EXPECT_GE(ratio, 1e-7) << "not released at t=" << solver.time();
    } else if (ratio < 1e-7) {
      below_before_min_time = true;
    }
  }
  std::cout << "released at t=" << t_release << " s, E_k/E_p0=" << ratio_at_release << "\n";
  ASSERT_GE(t_release, 0.03);
  EXPECT_LT(ratio_at_release, 1e-7);
  EXPECT_TRUE(below_before_min_time);  // the minimum time mattered
  EXPECT_FALSE(solver.boundary_conditions().constraint_active(0));
}

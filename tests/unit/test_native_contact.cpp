// Native backend contact law against closed forms: two spheres (normal force and energy,
// tangential spring carried by a rigid rotation of the pair, sliding at the Coulomb limit,
// energy of an undamped collision) and a contact through the periodic boundary.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "backends/native/contact_law.hpp"
#include "backends/native/integrator.hpp"
#include "backends/native/measures.hpp"

namespace {

using namespace mpmdem::dem::native;

constexpr double kR = 1e-3;      // radius [m]
constexpr double kE = 6e8;       // FrictMat.young [Pa]
constexpr double kKsKn = 0.8;    // FrictMat.poisson = ks/kn
constexpr double kMu = 0.518;    // tan of the friction angle
constexpr double kEdge = 0.05;   // periodic cell edge [m], large: no other image
constexpr double kDelta = 1e-6;  // overlap [m]

// Two spheres of radius kR in a cubic cell, sphere 1 at x1, sphere 2 at x1 + d.
RveState two_spheres(const Vec3& x1, const Vec3& d) {
  RveState s;
  s.material = Material{kE, kKsKn, 2500, std::atan(kMu)};
  s.cell.hsize = kEdge * Eigen::Matrix3d::Identity();
  const double m = 2500 * 4.0 / 3.0 * M_PI * kR * kR * kR;
  s.spheres.push_back(kR, m, 0.4 * m * kR * kR, x1);
  s.spheres.push_back(kR, m, 0.4 * m * kR * kR, x1 + d);
  s.dt = 1e-7;
  return s;
}

TEST(NativeContact, StiffnessesAreYadesFrictPhys) {
  const FrictPhys p = frict_phys(kE, 1e-3, kKsKn, 0.3, 2 * kE, 2e-3, 0.5, 0.2);
  const double a = kE * 1e-3, b = 2 * kE * 2e-3;
  EXPECT_DOUBLE_EQ(p.kn, 2 * a * b / (a + b));
  EXPECT_DOUBLE_EQ(p.ks, 2 * a * kKsKn * b * 0.5 / (a * kKsKn + b * 0.5));
  EXPECT_DOUBLE_EQ(p.tan_phi, std::tan(0.2));
  // Same material: kn = E r1 r2 * 2 / (r1 + r2), ks = (ks/kn) kn.
  const FrictPhys q = frict_phys(kE, 1e-3, kKsKn, 0.3, kE, 1e-3, kKsKn, 0.3);
  EXPECT_DOUBLE_EQ(q.kn, kE * 1e-3);
  EXPECT_NEAR(q.ks, kKsKn * q.kn, 1e-9 * q.kn);
}

TEST(NativeContact, NormalForceStressAndEnergyOfAnOverlap) {
  const Vec3 n = Vec3(1, 2, 2) / 3.0;
  RveState s = two_spheres(Vec3::Constant(0.02), (2 * kR - kDelta) * n);
  NeighbourList nl;
  compute_forces(s, nl);
  ASSERT_EQ(s.contacts.size(), 1u);
  const double kn = kE * kR;               // 2 E r r / (r + r)
  const Vec3 expected = -kn * kDelta * n;  // on sphere 1, pushed away from sphere 2
  EXPECT_LT((s.spheres.force[0] - expected).norm(), 1e-9 * expected.norm());
  EXPECT_LT((s.spheres.force[1] + expected).norm(), 1e-9 * expected.norm());
  EXPECT_LT(s.spheres.torque[0].norm(), 1e-12 * expected.norm() * kR);
  EXPECT_NEAR(elastic_energy(s), 0.5 * kn * kDelta * kDelta, 1e-9 * kn * kDelta * kDelta);
  // Love-Weber: sigma = -(1/V) kn delta l n n^T (compression negative).
  const Eigen::Matrix3d sigma = love_weber_stress(s);
  const Eigen::Matrix3d closed =
      -kn * kDelta * (2 * kR - kDelta) * n * n.transpose() / std::pow(kEdge, 3);
  EXPECT_LT((sigma - closed).norm(), 1e-9 * closed.norm());
}

TEST(NativeContact, ContactThroughThePeriodicBoundaryActsAsInside) {
  // Sphere 1 near the x = 0 face, sphere 2 near x = L: they touch through the boundary.
  const Vec3 x1(0.4 * kR, 0.01, 0.01);
  const Vec3 x2(kEdge - (2 * kR - kDelta) + 0.4 * kR, 0.01, 0.01);
  RveState s = two_spheres(x1, x2 - x1);
  NeighbourList nl;
  compute_forces(s, nl);
  ASSERT_EQ(s.contacts.size(), 1u);
  EXPECT_EQ(s.contacts.cell[0], CellDist(-1, 0, 0));
  const double kn = kE * kR;
  // Sphere 1's neighbour is at -x: it is pushed towards +x.
  EXPECT_NEAR(s.spheres.force[0][0], kn * kDelta, 1e-9 * kn * kDelta);
  const Eigen::Matrix3d sigma = love_weber_stress(s);
  EXPECT_NEAR(sigma(0, 0), -kn * kDelta * (2 * kR - kDelta) / std::pow(kEdge, 3),
              1e-9 * std::abs(sigma(0, 0)));
}

TEST(NativeContact, ShearSpringSlidesAtTheCoulombLimit) {
  // Sphere 2 moves tangentially at v (positions held: overlap and normal fixed). Each step
  // adds ks * alpha * v * dt to the spring, alpha = (r1 + r2) / (r1 + r2 - delta), until
  // |Fs| reaches mu |Fn|, where it stays.
  const Vec3 n(0, 0, 1);
  RveState s = two_spheres(Vec3::Constant(0.02), (2 * kR - kDelta) * n);
  const double v = 0.1;  // the spring reaches the cap after ~65 steps
  s.spheres.vel.set(1, Vec3(v, 0, 0));
  NeighbourList nl;
  const double kn = kE * kR, ks = kKsKn * kn;
  const double alpha = 2 * kR / (2 * kR - kDelta);
  const double limit = kMu * kn * kDelta;
  bool slid = false;
  for (int k = 1; k <= 400; ++k) {
    compute_forces(s, nl);
    const Vec3& fs = s.contacts.shear_force[0];
    const double elastic = ks * alpha * v * s.dt * k;
    if (elastic < limit) {
      EXPECT_NEAR(fs.norm(), elastic, 1e-9 * elastic) << "step " << k;
      EXPECT_LT(fs.x(), 0.0);  // opposes the motion of sphere 2 relative to sphere 1
    } else {
      slid = true;
      EXPECT_NEAR(fs.norm(), limit, 1e-12 * limit) << "step " << k;
    }
    EXPECT_NEAR(std::abs(fs.dot(n)), 0.0, 1e-15 * limit);
  }
  EXPECT_TRUE(slid);
  EXPECT_NEAR(elastic_energy(s), 0.5 * kn * kDelta * kDelta + 0.5 * limit * limit / ks,
              1e-9 * kn * kDelta * kDelta);
}

TEST(NativeContact, ShearSpringTurnsWithARigidRotationOfThePair) {
  // The pair turns rigidly (positions rotated, v = W x, w = W): the contact's relative
  // velocity is zero (McNamara's alpha), so the shear force must only turn with the pair,
  // here by 0.1 rad about an axis normal to the contact (orthonormal_axis) and by 0.1 rad
  // about the normal (twist_axis). ScGeom::rotate is first order: error ~ angle * step.
  const Vec3 n0(1, 0, 0), c(0.02, 0.02, 0.02);
  for (const Vec3& axis : {Vec3(0, 0, 1), Vec3(1, 0, 0)}) {
    RveState s = two_spheres(c, (2 * kR - kDelta) * n0);
    NeighbourList nl;
    compute_forces(s, nl);  // the contact exists, without shear force
    const Vec3 fs0(0, 2e-4, 1e-4);
    s.contacts.shear_force.set(0, fs0);
    const int steps = 1000;
    const double total = 0.1, dphi = total / steps;
    const Vec3 w = axis * dphi / s.dt;
    const Vec3 x1 = s.spheres.pos[0] - c, x2 = s.spheres.pos[1] - c;
    for (int k = 1; k <= steps; ++k) {
      const Eigen::Matrix3d rot = Eigen::AngleAxisd(k * dphi, axis).toRotationMatrix();
      s.spheres.pos.set(0, c + rot * x1);
      s.spheres.pos.set(1, c + rot * x2);
      s.spheres.vel.set(0, w.cross(rot * x1));
      s.spheres.vel.set(1, w.cross(rot * x2));
      s.spheres.ang_vel.set(0, w);
      s.spheres.ang_vel.set(1, w);
      compute_forces(s, nl);
    }
    const Vec3 expected = Eigen::AngleAxisd(total, axis) * fs0;
    EXPECT_LT((s.contacts.shear_force[0] - expected).norm(), 2e-3 * fs0.norm())
        << "axis " << axis.transpose() << ": " << s.contacts.shear_force[0].transpose() << " vs "
        << expected.transpose();
    EXPECT_NEAR(normal_force(s, 0).norm(), kE * kR * kDelta, 1e-6 * kE * kR * kDelta);
  }
}

TEST(NativeContact, UndampedCollisionConservesEnergy) {
  // Head-on collision without damping: kinetic + elastic energy is conserved by the
  // leap-frog up to O(dt^2), and the spheres separate with their initial speed.
  const Vec3 n(0, 1, 0);
  RveState s = two_spheres(Vec3::Constant(0.02), (2 * kR + 1e-7) * n);
  const double v = 0.05;
  s.spheres.vel.set(0, 0.5 * v * n);
  s.spheres.vel.set(1, -0.5 * v * n);
  const double m = s.spheres.mass[0];
  const double e0 = 2 * 0.5 * m * (0.5 * v) * (0.5 * v);
  NeighbourList nl;
  double worst = 0;
  bool touched = false;
  for (int k = 0; k < 4000; ++k) {
    dem_step(s, nl, 0.0);
    touched = touched || s.contacts.size() > 0;
    worst = std::max(worst, std::abs(kinetic_energy(s) + elastic_energy(s) - e0) / e0);
  }
  EXPECT_TRUE(touched);
  EXPECT_EQ(s.contacts.size(), 0u);
  EXPECT_LT(worst, 0.1);  // half-step kinetic energy: O(omega dt) = 3 %
  EXPECT_NEAR(kinetic_energy(s), e0, 1e-3 * e0);
}

}  // namespace

// Newton's rotation of a free sphere: the series path (h = dt |w| / 2 < 1e-3) and the exact
// AngleAxis path of a fast spin both follow the closed form exp(t w) ori0.
TEST(NativeContact, FreeSpinRotatesAsAngleAxis) {
  RveState s = two_spheres(Vec3(0.01, 0.01, 0.01), Vec3(0.01, 0, 0));  // far apart
  const Vec3 slow(30.0, -60.0, 80.0), fast(3e4, 2e4, -4e4);            // h = 5e-6 and 2.7e-3
  s.spheres.ang_vel.set(0, slow);
  s.spheres.ang_vel.set(1, fast);
  const Quat ori0(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  s.spheres.ori[0] = s.spheres.ori[1] = ori0;
  NeighbourList nl;
  const int steps = 50;
  for (int k = 0; k < steps; ++k) dem_step(s, nl, 0.0);
  EXPECT_EQ(s.contacts.size(), 0u);
  for (int i = 0; i < 2; ++i) {
    const Vec3 w = i == 0 ? slow : fast;
    EXPECT_EQ(s.spheres.ang_vel[i], w);
    const Quat expected = Quat(Eigen::AngleAxisd(steps * s.dt * w.norm(), w.normalized())) * ori0;
    EXPECT_LT(s.spheres.ori[i].angularDistance(expected), 1e-12) << "sphere " << i;
  }
}

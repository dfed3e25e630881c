// Lazy RVE evaluation (issue 6, item 2): the skip decision and that no increment is lost.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "constitutive/lazy_evaluation.hpp"

namespace mpmdem::mpm {
namespace {

using Mat3 = Eigen::Matrix3d;

Mat3 small_increment(std::mt19937& rng, double size) {
  std::uniform_real_distribution<double> u(-size, size);
  Mat3 d = Mat3::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) d(i, j) += u(rng);
  }
  return d;
}

TEST(LazyEvaluation, ToleranceZeroRunsEveryStepWithTheIncrementItself) {
  LazyEvaluation lazy(0.0);
  std::mt19937 rng(1);
  for (int s = 0; s < 20; ++s) {
    const Mat3 dF = small_increment(rng, 1e-9);
    Mat3 run;
    double dt = 0.0;
    ASSERT_TRUE(lazy.next(0, dF, 1e-4, run, dt));
    EXPECT_EQ(run, dF);  // bitwise: tolerance 0 is the plain scheme
    EXPECT_EQ(dt, 1e-4);
  }
  EXPECT_EQ(lazy.evaluations(), 20);
  EXPECT_EQ(lazy.skipped(), 0);
}

TEST(LazyEvaluation, NoIncrementIsLostAndSkipsStayWithinTheTolerance) {
  const double tol = 1e-3;
  LazyEvaluation lazy(tol);
  std::mt19937 rng(7);
  Mat3 all = Mat3::Identity(), sent = Mat3::Identity();
  double t_all = 0.0, t_sent = 0.0;
  for (int s = 0; s < 2000; ++s) {
    const Mat3 dF = small_increment(rng, 2e-4);
    all = dF * all;
    t_all += 1e-4;
    Mat3 run;
    double dt = 0.0;
    if (lazy.next(3, dF, 1e-4, run, dt)) {
      EXPECT_GT((run - Mat3::Identity()).cwiseAbs().maxCoeff(), tol);  // ran: beyond tol
      sent = run * sent;
      t_sent += dt;
    }
    const Mat3& pending = lazy.pending()[3];
    EXPECT_LE((pending - Mat3::Identity()).cwiseAbs().maxCoeff(), tol);
    // Everything sent, then everything pending, is everything: nothing lost.
    EXPECT_LT(((pending * sent) - all).cwiseAbs().maxCoeff(), 1e-12) << "step " << s;
  }
  EXPECT_GT(lazy.skipped(), 0);
  EXPECT_GT(lazy.evaluations(), 0);
  EXPECT_EQ(lazy.skipped() + lazy.evaluations(), 2000);
  EXPECT_LE(t_sent, t_all + 1e-12);
}

TEST(LazyEvaluation, ARigidRotationIsNotHeldForever) {
  // 1e-4 rad per step about z: the accumulated rotation reaches the tolerance and runs.
  LazyEvaluation lazy(1e-3);
  const Mat3 R = Eigen::AngleAxisd(1e-4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  int runs = 0;
  for (int s = 0; s < 100; ++s) {
    Mat3 run;
    double dt = 0.0;
    if (lazy.next(0, R, 1e-4, run, dt)) {
      ++runs;
      EXPECT_NEAR(std::atan2(run(1, 0), run(0, 0)), 11e-4, 1e-12);  // 11 steps of rotation
      EXPECT_NEAR(dt, 11e-4, 1e-15);
    }
  }
  EXPECT_EQ(runs, 9);  // every 11th step
}

TEST(LazyEvaluation, CheckpointStateRoundTrips) {
  LazyEvaluation a(1e-3), b(1e-3);
  std::mt19937 rng(3);
  for (int s = 0; s < 50; ++s) {
    for (std::size_t p = 0; p < 4; ++p) {
      Mat3 run;
      double dt = 0.0;
      a.next(p, small_increment(rng, 3e-4), 1e-4, run, dt);
    }
  }
  b.load(a.save());
  EXPECT_EQ(b.save(), a.save());
  EXPECT_EQ(b.skipped(), a.skipped());
  std::mt19937 r1(9), r2(9);
  for (int s = 0; s < 30; ++s) {  // both continue identically
    Mat3 ra, rb;
    double da = 0.0, db = 0.0;
    const bool xa = a.next(1, small_increment(r1, 3e-4), 1e-4, ra, da);
    const bool xb = b.next(1, small_increment(r2, 3e-4), 1e-4, rb, db);
    ASSERT_EQ(xa, xb);
    if (xa) {
      EXPECT_EQ(ra, rb);
    }
  }
  EXPECT_THROW(b.load({2.0, 0.0, 0.0, 1.0}), std::runtime_error);
}

}  // namespace
}  // namespace mpmdem::mpm

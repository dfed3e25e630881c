// The MPM side's per-point loops that run on the solver's threads (issue 36, item 4) give
// the same bits on 1 and 2 threads as the serial loops they replaced: the remote provider's
// lazy decision and packing, the stress work (per-point terms summed in point order) and the
// non-finite scan (the first bad point in point order). Sizes above kParallelMin, so that the
// parallel branch runs.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/LU>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "constitutive/lazy_evaluation.hpp"
#include "energy_budget.hpp"
#include "parallel.hpp"
#include "state_guard.hpp"

namespace mpmdem::mpm {
namespace {

constexpr std::size_t kPoints = 3 * static_cast<std::size_t>(kParallelMin) + 17;

Particles random_points(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Particles p;
  p.m.assign(n, 1.0);
  p.V.resize(n);
  p.x.resize(n);
  p.v.resize(n);
  p.F.assign(n, Mat3::Identity());
  p.dF.resize(n);
  p.sigma.resize(n);
  for (std::size_t q = 0; q < n; ++q) {
    p.V[q] = 1e-4 * (1.5 + u(rng));
    p.x[q] = Vec3(u(rng), u(rng), u(rng));
    p.v[q] = Vec3(u(rng), u(rng), u(rng));
    p.dF[q] = Mat3::Identity() + 1e-3 * Mat3::Random();
    p.sigma[q] = 1e4 * Mat3::Random();
  }
  return p;
}

// The loop stress_work() replaced: one running sum in point order.
double serial_stress_work(const Particles& p, bool after) {
  double w = 0.0;
  for (std::size_t q = 0; q < p.size(); ++q) {
    const Mat3& dF = p.dF[q];
    const Mat3 de = 0.5 * (dF + dF.transpose()) - Mat3::Identity();
    const double V = after ? p.V[q] : p.V[q] / dF.determinant();
    w += V * (p.sigma[q].cwiseProduct(de)).sum();
  }
  return w;
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

class ThreadBits : public ::testing::Test {
 protected:
  void SetUp() override { threads_ = omp_get_max_threads(); }
  void TearDown() override { omp_set_num_threads(threads_); }
  int threads_ = 1;
};

TEST_F(ThreadBits, StressWorkIsTheSerialSumOnAnyThreadCount) {
  const Particles p = random_points(kPoints, 7);
  std::vector<double> terms;
  for (bool after : {false, true}) {
    const double want = serial_stress_work(p, after);
    ASSERT_NE(want, 0.0);
    for (int t : {1, 2, 3}) {
      omp_set_num_threads(t);
      const double got = stress_work(p, after, terms);
      EXPECT_TRUE(same_bits(got, want)) << t << " threads: " << got << " against " << want;
    }
  }
}

TEST_F(ThreadBits, NonFiniteScanNamesTheFirstBadPointInPointOrder) {
  Particles p = random_points(kPoints, 8);
  NonFinite where;
  omp_set_num_threads(2);
  EXPECT_FALSE(find_first_non_finite(p, where));
  // Two bad points in different halves (different threads); the later one is bad in a field
  // checked earlier, so a scan that kept the last hit or the first field would be caught.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  p.x[kPoints - 5].x() = nan;
  p.sigma[kPoints / 3](1, 2) = std::numeric_limits<double>::infinity();
  for (int t : {1, 2, 3}) {
    omp_set_num_threads(t);
    ASSERT_TRUE(find_first_non_finite(p, where)) << t;
    EXPECT_EQ(where.point, kPoints / 3) << t;
    EXPECT_STREQ(where.field, "stress") << t;
  }
  p.V[0] = nan;
  ASSERT_TRUE(find_first_non_finite(p, where));
  EXPECT_EQ(where.point, 0u);
  EXPECT_STREQ(where.field, "volume");
}

// The remote provider's loop: prepare(n), decide(p) on the threads, count(): the same
// pending increments, runs and counts as next() point after point.
TEST_F(ThreadBits, LazyDecisionsOnThreadsEqualTheSerialOnes) {
  const double tol = 2e-3;
  LazyEvaluation serial(tol), threaded(tol);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Mat3> dF(kPoints), run_s(kPoints), run_t(kPoints);
  std::vector<double> dt_s(kPoints), dt_t(kPoints);
  std::vector<char> go_s(kPoints), go_t(kPoints);
  omp_set_num_threads(2);
  std::int64_t skipped_total = 0;
  for (int step = 0; step < 8; ++step) {
    for (std::size_t q = 0; q < kPoints; ++q) {
      // Some points move fast (run every step), most slowly (held for a few steps).
      const double size = (q % 7 == 0 ? 2e-2 : 4e-4) * (1.0 + 0.5 * u(rng));
      dF[q] = Mat3::Identity() + size * Mat3::Random();
    }
    for (std::size_t q = 0; q < kPoints; ++q) {
      go_s[q] = serial.next(q, dF[q], 1e-4, run_s[q], dt_s[q]);
    }
    const auto n = static_cast<std::ptrdiff_t>(kPoints);
    threaded.prepare(kPoints);
    std::int64_t runs = 0;
#pragma omp parallel for schedule(static) reduction(+ : runs)
    for (std::ptrdiff_t q = 0; q < n; ++q) {
      const auto i = static_cast<std::size_t>(q);
      go_t[i] = threaded.decide(i, dF[i], 1e-4, run_t[i], dt_t[i]);
      runs += go_t[i] ? 1 : 0;
    }
    threaded.count(runs, n - runs);
    for (std::size_t q = 0; q < kPoints; ++q) {
      ASSERT_EQ(go_s[q], go_t[q]) << "step " << step << " point " << q;
      if (go_s[q]) {
        ASSERT_EQ(run_s[q], run_t[q]) << "step " << step << " point " << q;
        ASSERT_TRUE(same_bits(dt_s[q], dt_t[q]));
      }
    }
    skipped_total = serial.skipped();
  }
  EXPECT_GT(skipped_total, 0);  // the test exercises both branches
  EXPECT_GT(serial.evaluations(), 8 * static_cast<std::int64_t>(kPoints) / 7);
  EXPECT_EQ(threaded.evaluations(), serial.evaluations());
  EXPECT_EQ(threaded.skipped(), serial.skipped());
  const std::vector<double> a = serial.save(), b = threaded.save();
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
}

}  // namespace
}  // namespace mpmdem::mpm

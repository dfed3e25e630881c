// The at-rest detector of the column collapse (analysis/at_rest.hpp): the threshold, the hold
// time, the earliest stop, a transient dip below the threshold that must not stop the run, and
// the state a checkpoint restores.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "analysis/at_rest.hpp"

using mpmdem::mpm::AtRestDetector;

namespace {

// Feeds E_k/E_p0 = ratio(t) at t = 0, dt, 2 dt, ... up to t_end; returns the first time the
// detector reports rest, or -1.
template <class F>
double first_rest(AtRestDetector& d, double dt, double t_end, F ratio) {
  for (int k = 0; k * dt <= t_end + 1e-12; ++k) {
    const double t = k * dt;
    if (d.update(t, ratio(t))) return t;
  }
  return -1.0;
}

}  // namespace

TEST(AtRestDetector, StopsAfterTheHoldBelowTheThreshold) {
  // Below 1e-5 from t = 2 on, hold 0.5: at rest at t = 2.5 exactly (steps of 0.01).
  AtRestDetector d(1e-5, 0.5, 1.0);
  const double stop =
      first_rest(d, 0.01, 5.0, [](double t) { return t < 2.0 - 1e-9 ? 1e-3 : 5e-6; });
  EXPECT_NEAR(stop, 2.5, 1e-9);
  EXPECT_TRUE(d.at_rest());
  EXPECT_NEAR(*d.at_rest_time(), 2.5, 1e-9);
  EXPECT_NEAR(*d.quiet_since(), 2.0, 1e-9);
  // Once at rest it stays so, whatever comes next.
  EXPECT_TRUE(d.update(2.6, 1.0));
  EXPECT_NEAR(*d.at_rest_time(), 2.5, 1e-9);
}

TEST(AtRestDetector, TheThresholdIsStrict) {
  // Exactly at the threshold is not below it.
  AtRestDetector d(1e-5, 0.1, 0.0);
  EXPECT_EQ(first_rest(d, 0.01, 2.0, [](double) { return 1e-5; }), -1.0);
  EXPECT_FALSE(d.quiet_since().has_value());
}

TEST(AtRestDetector, ATransientDipDoesNotStopTheRun) {
  // A dip below the threshold shorter than the hold (t in [1.5, 1.8)), then motion again,
  // then rest from t = 3: the stop comes at 3 + hold, not during the dip.
  AtRestDetector d(1e-4, 0.5, 1.0);
  auto ratio = [](double t) {
    if (t >= 1.5 - 1e-9 && t < 1.8 - 1e-9) return 1e-6;  // the dip: 0.3 < hold
    if (t < 3.0 - 1e-9) return 1e-2;
    return 1e-6;
  };
  for (int k = 0; k <= 250; ++k) {  // up to t = 2.5: through the dip, no stop
    const double t = 0.01 * k;
    ASSERT_FALSE(d.update(t, ratio(t))) << "stopped at t = " << t;
    if (t > 1.6 && t < 1.75) {
      EXPECT_NEAR(*d.quiet_since(), 1.5, 1e-9) << t;
    }
  }
  EXPECT_FALSE(d.quiet_since().has_value());  // the motion after the dip reset the window
  double stop = -1.0;
  for (int k = 251; k <= 500 && stop < 0.0; ++k) {
    if (d.update(0.01 * k, ratio(0.01 * k))) stop = 0.01 * k;
  }
  EXPECT_NEAR(stop, 3.5, 1e-9);
}

TEST(AtRestDetector, ASingleStepAboveRestartsTheHold) {
  AtRestDetector d(1e-4, 0.5, 0.0);
  auto ratio = [](double t) { return std::abs(t - 0.4) < 1e-6 ? 2e-4 : 1e-6; };
  EXPECT_NEAR(first_rest(d, 0.1, 5.0, ratio), 0.5 + 0.5, 1e-9);  // window restarts at 0.5
}

TEST(AtRestDetector, NotBeforeTheEarliestTime) {
  // Quiet from the start (a column just released is at rest too): the stop waits for the
  // earliest time, then needs no further hold since the window is already long enough.
  AtRestDetector d(1e-4, 0.5, 1.0);
  EXPECT_NEAR(first_rest(d, 0.1, 5.0, [](double) { return 0.0; }), 1.0, 1e-9);
  EXPECT_NEAR(*d.quiet_since(), 0.0, 1e-12);
}

TEST(AtRestDetector, NonFiniteRatioIsNeverRest) {
  AtRestDetector d(1e-4, 0.1, 0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(first_rest(d, 0.01, 1.0, [nan](double) { return nan; }), -1.0);
}

TEST(AtRestDetector, RestoredStateContinuesExactly) {
  // A detector restored half-way through a quiet window stops at the same time as the one that
  // ran through (what a checkpoint inside the window must give).
  auto ratio = [](double t) { return t < 1.0 - 1e-9 ? 1e-2 : 1e-6; };
  AtRestDetector whole(1e-4, 0.5, 0.0), first(1e-4, 0.5, 0.0);
  const double stop = first_rest(whole, 0.01, 5.0, ratio);
  for (int k = 0; k <= 120; ++k) ASSERT_FALSE(first.update(0.01 * k, ratio(0.01 * k)));
  ASSERT_TRUE(first.quiet_since().has_value());
  AtRestDetector resumed(1e-4, 0.5, 0.0);
  resumed.restore(first.quiet_since(), first.at_rest_time());
  double stop2 = -1.0;
  for (int k = 121; k <= 500 && stop2 < 0.0; ++k) {
    if (resumed.update(0.01 * k, ratio(0.01 * k))) stop2 = 0.01 * k;
  }
  EXPECT_EQ(stop2, stop);
  EXPECT_NEAR(stop, 1.5, 1e-9);
  // Without the restored window the wait would start again at the resume (a later stop).
  AtRestDetector fresh(1e-4, 0.5, 0.0);
  double stop3 = -1.0;
  for (int k = 121; k <= 500 && stop3 < 0.0; ++k) {
    if (fresh.update(0.01 * k, ratio(0.01 * k))) stop3 = 0.01 * k;
  }
  EXPECT_NEAR(stop3, 1.71, 1e-9);
}

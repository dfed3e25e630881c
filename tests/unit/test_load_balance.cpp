// Cost-aware load balance (issue 5, item 4): the partition algorithm and the client's
// balancer. Migration itself is tested end to end in tests/integration/load_balance.sh.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "constitutive/load_balancer.hpp"
#include "mpmdem/partition.hpp"

namespace mpmdem {
namespace {

void expect_valid(const std::vector<Partition>& parts, std::size_t n, int ranks) {
  ASSERT_EQ(parts.size(), static_cast<std::size_t>(ranks));
  std::uint64_t next = 0;
  for (const Partition& p : parts) {
    EXPECT_EQ(p.offset, next) << "ranges must be contiguous and in order";
    if (n >= static_cast<std::size_t>(ranks)) {
      EXPECT_GE(p.count, 1u) << "empty rank";
    }
    next += p.count;
  }
  EXPECT_EQ(next, n) << "every RVE must be owned";
}

double worst(const std::vector<double>& c, const std::vector<Partition>& parts) {
  double w = 0.0;
  for (const Partition& p : parts) {
    w = std::max(w,
                 std::accumulate(c.begin() + static_cast<std::ptrdiff_t>(p.offset),
                                 c.begin() + static_cast<std::ptrdiff_t>(p.offset + p.count), 0.0));
  }
  return w;
}

// Brute force over all contiguous splits into 3 ranges: the optimum bottleneck.
double best_of_three(const std::vector<double>& c) {
  double best = 1e300;
  for (std::size_t a = 1; a + 2 <= c.size(); ++a) {
    for (std::size_t b = a + 1; b + 1 <= c.size(); ++b) {
      const std::vector<Partition> p{{0, a}, {a, b - a}, {b, c.size() - b}};
      best = std::min(best, worst(c, p));
    }
  }
  return best;
}

TEST(PartitionByCost, UniformCostGivesTheEvenSplit) {
  const std::vector<double> c(10, 1.0);
  const auto p = partition_by_cost(c, 3);
  expect_valid(p, 10, 3);
  EXPECT_DOUBLE_EQ(worst(c, p), 4.0);  // ceil(10/3)
}

TEST(PartitionByCost, ExpensiveTailIsSpreadOverMoreRanks) {
  // The column's spreading front: the last quarter of the RVEs costs 4x (tiled cells).
  std::vector<double> c(240, 1.0);
  for (std::size_t i = 180; i < 240; ++i) c[i] = 4.0;
  const auto even = partition_contiguous(240, 2);
  const auto p = partition_by_cost(c, 2);
  expect_valid(p, 240, 2);
  EXPECT_GT(partition_imbalance(c, even), 1.4);                     // 300 of a mean 210: 1.43
  EXPECT_LT(partition_imbalance(c, p), 1.0 + 4.0 / 210.0 + 1e-12);  // within one RVE of ideal
}

TEST(PartitionByCost, MatchesTheBruteForceOptimum) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<double> c(3 + trial % 12);
    for (double& x : c) x = u(rng) < 0.2 ? 10.0 * u(rng) : u(rng);
    const auto p = partition_by_cost(c, 3);
    expect_valid(p, c.size(), 3);
    EXPECT_NEAR(worst(c, p), best_of_three(c), 1e-9 * best_of_three(c)) << "trial " << trial;
  }
}

TEST(PartitionByCost, FewerRvesThanRanksAndZeroCosts) {
  const auto p = partition_by_cost({1.0, 2.0}, 4);
  expect_valid(p, 2, 4);
  const auto z = partition_by_cost(std::vector<double>(7, 0.0), 3);
  expect_valid(z, 7, 3);
  const auto even = partition_contiguous(7, 3);
  for (std::size_t r = 0; r < 3; ++r) EXPECT_EQ(z[r].count, even[r].count);
}

std::vector<protocol::RveReply> replies_with_cost(const std::vector<double>& c) {
  std::vector<protocol::RveReply> r(c.size(), protocol::RveReply{});
  for (std::size_t i = 0; i < c.size(); ++i) r[i].cost_s = c[i];
  return r;
}

// --- the order of the RVEs on the wire (coupling.rve_order) -----------------------------

TEST(RveOrder, BothOrdersArePermutations) {
  for (std::uint64_t n : {0u, 1u, 2u, 7u, 240u, 1000u, 1024u}) {
    for (RveOrder kind : {RveOrder::kContiguous, RveOrder::kInterleaved}) {
      std::vector<std::uint64_t> o = rve_order(n, kind);
      ASSERT_EQ(o.size(), n);
      if (kind == RveOrder::kContiguous) {
        for (std::uint64_t s = 0; s < n; ++s) EXPECT_EQ(o[s], s);
      }
      std::sort(o.begin(), o.end());
      for (std::uint64_t s = 0; s < n; ++s) ASSERT_EQ(o[s], s) << "n " << n;
    }
  }
}

TEST(RveOrder, InterleavedFirstHalfHoldsTheEvenPoints) {
  for (std::uint64_t n : {7u, 240u, 241u}) {
    const std::vector<std::uint64_t> o = rve_order(n, RveOrder::kInterleaved);
    const std::uint64_t half = (n + 1) / 2;
    for (std::uint64_t s = 0; s < n; ++s) EXPECT_EQ(o[s] % 2, s < half ? 0u : 1u) << s;
  }
}

// Material points are numbered cell by cell, and an RVE's cost follows the local strain rate:
// a cost that grows across the body (here linearly, from 1 to 3) is what the equal-count
// split of the identity order turns into imbalance (the last rank gets the dear end);
// interleaved, every rank count from 2 to 16 gets nearly the same mix.
TEST(RveOrder, InterleavedSplitsACostGradientAcrossTheBodyEvenly) {
  const std::uint64_t n = 240;  // the default column's points
  std::vector<double> cost_of_point(n);
  for (std::uint64_t p = 0; p < n; ++p) cost_of_point[p] = 1.0 + 2.0 * double(p) / double(n - 1);
  for (int ranks = 2; ranks <= 16; ++ranks) {
    for (RveOrder kind : {RveOrder::kContiguous, RveOrder::kInterleaved}) {
      const std::vector<std::uint64_t> o = rve_order(n, kind);
      std::vector<double> cost_of_slot(n);
      for (std::uint64_t s = 0; s < n; ++s) cost_of_slot[s] = cost_of_point[o[s]];
      const double imb = partition_imbalance(cost_of_slot, partition_contiguous(n, ranks));
      if (kind == RveOrder::kInterleaved) {
        // 240 / 13 ranks: 19 or 18 RVEs, so 1.03 from the counts alone.
        EXPECT_LT(imb, ranks == 2 ? 1.005 : 1.06) << ranks << " ranks";
      } else {
        EXPECT_GT(imb, 1.2) << ranks << " ranks";
      }
    }
  }
}

TEST(LoadBalancer, OffByDefaultAndHonoursThresholdAndInterval) {
  std::vector<double> c(100, 1e-3);
  for (std::size_t i = 75; i < 100; ++i) c[i] = 4e-3;  // imbalance of the even split: 1.43
  const auto even = partition_contiguous(100, 2);
  const auto replies = replies_with_cost(c);

  mpm::LoadBalancer off(0.0, 1, 1.0);
  for (int s = 1; s < 20; ++s) EXPECT_FALSE(off.observe(s, replies, even).has_value());

  mpm::LoadBalancer lb(0.1, 10, 1.0);
  for (int s = 1; s <= 10; ++s) EXPECT_FALSE(lb.observe(s, replies, even).has_value()) << s;
  const auto next = lb.observe(11, replies, even);
  ASSERT_TRUE(next.has_value());
  expect_valid(*next, 100, 2);
  EXPECT_NEAR(lb.last_imbalance_before(), 0.125 / 0.0875, 1e-9);  // 1.43
  EXPECT_LT(lb.last_imbalance_predicted(), 1.02);
  lb.applied(11);
  EXPECT_EQ(lb.rebalances(), 1);
  // Balanced now: nothing more to do, and not before min_interval anyway.
  for (int s = 12; s < 40; ++s) EXPECT_FALSE(lb.observe(s, replies, *next).has_value()) << s;

  mpm::LoadBalancer loose(0.5, 1, 1.0);  // 1.43 < 1.5: within the threshold
  for (int s = 1; s < 5; ++s) EXPECT_FALSE(loose.observe(s, replies, even).has_value());
}

TEST(LoadBalancer, SmoothingDampsASingleSpike) {
  const auto even = partition_contiguous(10, 2);
  mpm::LoadBalancer lb(0.2, 1, 0.1);
  const std::vector<double> flat(10, 1.0);
  std::vector<double> spike = flat;
  spike[0] = 4.0;  // one slow step of one RVE (within the spike cap)
  EXPECT_FALSE(lb.observe(1, replies_with_cost(flat), even).has_value());
  EXPECT_FALSE(lb.observe(2, replies_with_cost(spike), even).has_value())
      << "smoothed: 1 + 0.1 * 3 = 1.3 on rank 0 -> imbalance 1.03 < 1.2";
  EXPECT_NEAR(lb.smoothed_cost()[0], 1.3, 1e-12);
}

// A paused process (or a preempted core) makes one step of one RVE look 1000x dearer: it
// counts as at most kSpikeCap times the smoothed cost, and moves no RVE; a lasting 2x
// change (a tiled cell) still gets through in full.
TEST(LoadBalancer, APauseIsCappedButALastingChangeIsFollowed) {
  const auto even = partition_contiguous(10, 2);
  mpm::LoadBalancer lb(0.2, 1, 0.5);
  const std::vector<double> flat(10, 1.0);
  std::vector<double> pause = flat;
  pause[0] = 1000.0;
  EXPECT_FALSE(lb.observe(1, replies_with_cost(flat), even).has_value());
  EXPECT_FALSE(lb.observe(2, replies_with_cost(pause), even).has_value())
      << "capped: 0.5 * 1 + 0.5 * 4 = 2.5 on RVE 0 -> rank 0 6.5 vs 5: imbalance 1.13 < 1.2";
  EXPECT_NEAR(lb.smoothed_cost()[0], 2.5, 1e-12);
  std::vector<double> doubled = flat;
  for (int i = 0; i < 5; ++i) doubled[static_cast<std::size_t>(i)] = 2.0;
  for (int s = 3; s < 20; ++s) (void)lb.observe(s, replies_with_cost(doubled), even);
  EXPECT_NEAR(lb.smoothed_cost()[1], 2.0, 1e-4) << "a lasting 2x change is followed in full";
}

}  // namespace
}  // namespace mpmdem

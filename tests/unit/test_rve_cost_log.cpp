// rve_costs.csv / rve_ranks.csv (output.rve_costs): one cost row per step in microseconds,
// a rank row only when the ranks change, and a resumed run keeps the rows up to its step.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "output/rve_cost_log.hpp"
#include "test_support.hpp"

namespace {

using mpmdem::mpm::RveCostLog;
using test_support::read_file;
using test_support::TempDir;

TEST(RveCostLog, CostsEveryStepRanksOnlyWhenTheyChange) {
  TempDir dir("rve_costs", TempDir::kCreate);
  {
    RveCostLog log(dir.str(), 3);
    log.append(1, {1.5e-3, 2.5e-7, 0.0}, {0, 1, 0});
    log.append(2, {1e-3, 3e-6, 4e-6}, {0, 1, 0});
    log.append(3, {2e-3, 1e-6, 5e-6}, {1, 1, 0});  // a migration after step 2
  }
  EXPECT_EQ(read_file(dir.path() / "rve_costs.csv"),
            "step,p0,p1,p2\n1,1500,0.25,0\n2,1000,3,4\n3,2000,1,5\n");
  EXPECT_EQ(read_file(dir.path() / "rve_ranks.csv"), "step,p0,p1,p2\n1,0,1,0\n3,1,1,0\n");
}

TEST(RveCostLog, AResumedRunKeepsTheRowsUpToItsStep) {
  TempDir dir("rve_costs_resume", TempDir::kCreate);
  {
    RveCostLog log(dir.str(), 2);
    log.append(1, {1e-6, 2e-6}, {0, 1});
    log.append(2, {3e-6, 4e-6}, {1, 0});
    log.append(3, {5e-6, 6e-6}, {1, 0});  // after the checkpoint at step 2: discarded
  }
  {
    RveCostLog log(dir.str(), 2, 2);
    log.append(3, {7e-6, 8e-6}, {0, 1});  // the servers restart on the default partition
  }
  EXPECT_EQ(read_file(dir.path() / "rve_costs.csv"), "step,p0,p1\n1,1,2\n2,3,4\n3,7,8\n");
  EXPECT_EQ(read_file(dir.path() / "rve_ranks.csv"), "step,p0,p1\n1,0,1\n2,1,0\n3,0,1\n");
}

}  // namespace

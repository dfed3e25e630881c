// Checkpoints on by default (issue 16, item 1): the schedule of the step and wall-time
// triggers, the pruning to the newest complete checkpoints, the default scene's setting, a
// time-triggered run that ends exactly where a run without checkpoints ends and resumes
// bitwise from a time-triggered checkpoint, and the points of a step whose exchange failed
// restored (the fault checkpoint holds one consistent step).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>

#include "constitutive/linear_elastic.hpp"
#include "mpmdem/errors.hpp"
#include "output/checkpoint.hpp"
#include "output/checkpoint_schedule.hpp"
#include "run_driver.hpp"
#include "scene_builder.hpp"
#include "solver.hpp"
#include "test_support.hpp"

using namespace mpmdem::mpm;
using test_fixture::quiet_options;
using test_fixture::SceneBuilder;
using test_support::TempDir;
namespace fs = std::filesystem;

TEST(CheckpointSchedule, StepTrigger) {
  const CheckpointSchedule c(100, 0.0, 0.0);
  EXPECT_TRUE(c.enabled());
  EXPECT_FALSE(c.due(99, 1e9));  // no time trigger: wall time is irrelevant
  EXPECT_TRUE(c.due(100, 0.0));
  EXPECT_TRUE(c.due(300, 0.0));
}

TEST(CheckpointSchedule, TimeTriggerCountsFromTheLastCheckpoint) {
  CheckpointSchedule c(0, 60.0, 1000.0);  // the run started (or resumed) at 1000 s
  EXPECT_FALSE(c.due(1, 1059.9));
  EXPECT_TRUE(c.due(2, 1060.0));
  c.written(1061.0, 1.0);  // writing took 1 s: the next one is due 60 s after it ended
  EXPECT_FALSE(c.due(3, 1120.5));
  EXPECT_TRUE(c.due(4, 1121.0));
}

TEST(CheckpointSchedule, BothTriggersWhicheverComesFirst) {
  CheckpointSchedule c(50, 10.0, 0.0);
  EXPECT_TRUE(c.due(50, 1.0));  // the step trigger, before the time
  c.written(1.0, 0.1);          // ... restarts the wall-time count
  EXPECT_FALSE(c.due(51, 10.9));
  EXPECT_TRUE(c.due(52, 11.0));  // the time trigger, between two step multiples
}

// A checkpoint that took 3 s: the next time-triggered one waits 49 x 3 s = 147 s > 60 s,
// so checkpoints take at most 3 / (147 + 3) = 2 % of the wall time.
TEST(CheckpointSchedule, SlowCheckpointsAreSpacedToCostAtMostTwoPercent) {
  CheckpointSchedule c(0, 60.0, 0.0);
  EXPECT_TRUE(c.due(10, 60.0));
  c.written(63.0, 3.0);
  EXPECT_DOUBLE_EQ(c.gap_s(), 147.0);
  EXPECT_FALSE(c.due(20, 63.0 + 146.9));
  EXPECT_TRUE(c.due(21, 63.0 + 147.0));
  EXPECT_LE(3.0 / (c.gap_s() + 3.0), CheckpointSchedule::kMaxCost + 1e-15);
  c.written(300.0, 0.5);  // quick again: the configured interval rules
  EXPECT_DOUBLE_EQ(c.gap_s(), 60.0);
  // The step trigger is not spaced: the user asked for every n steps.
  const CheckpointSchedule s(5, 60.0, 0.0);
  EXPECT_TRUE(s.due(5, 0.0));
}

TEST(CheckpointSchedule, ZeroTurnsBothOff) {
  const CheckpointSchedule c(0, 0.0, 0.0);
  EXPECT_FALSE(c.enabled());
  EXPECT_FALSE(c.due(1, 1e12));
}

namespace {

void make_checkpoint(const std::string& run, std::int64_t step, bool complete) {
  const std::string d = checkpoint_directory(run, step);
  fs::create_directories(d + "/dem");
  std::ofstream(d + "/mpm.h5") << "x";
  if (complete) std::ofstream(d + "/COMPLETE") << "complete\n";
}

}  // namespace

TEST(CheckpointPruning, KeepsTheNewestTwoCompleteAndDropsOlderIncompleteOnes) {
  TempDir run("prune", TempDir::kCreate);
  const std::string r = run.str();
  make_checkpoint(r, 10, true);
  make_checkpoint(r, 20, false);  // a run stopped while writing it
  make_checkpoint(r, 30, true);
  fs::create_directories(fault_checkpoint_directory(r, 35));
  make_checkpoint(r, 40, false);  // being written now
  commit_checkpoint(r, checkpoint_directory(r, 40), 2);
  EXPECT_FALSE(fs::exists(checkpoint_directory(r, 10)));
  EXPECT_FALSE(fs::exists(checkpoint_directory(r, 20)));
  EXPECT_TRUE(fs::exists(checkpoint_directory(r, 30) + "/COMPLETE"));
  EXPECT_TRUE(fs::exists(checkpoint_directory(r, 40) + "/COMPLETE"));
  EXPECT_TRUE(fs::exists(fault_checkpoint_directory(r, 35)));  // never pruned
  EXPECT_EQ(latest_checkpoint(r), checkpoint_directory(r, 40));
  make_checkpoint(r, 50, true);
  commit_checkpoint(r, checkpoint_directory(r, 50), 2);
  EXPECT_FALSE(fs::exists(checkpoint_directory(r, 30)));
  EXPECT_TRUE(fs::exists(checkpoint_directory(r, 40)));
  EXPECT_EQ(latest_checkpoint(r), checkpoint_directory(r, 50));
  make_checkpoint(r, 60, false);  // incomplete newest: not resumed from
  EXPECT_EQ(latest_checkpoint(r), checkpoint_directory(r, 50));
}

TEST(CheckpointDefaults, TheDefaultSceneCheckpointsByWallTime) {
  const Scene s = SceneBuilder::config("configs/column_collapse.yaml").build();
  EXPECT_EQ(s.output.checkpoint_interval_steps, 0);  // the scene sets no step interval ...
  EXPECT_GT(s.output.checkpoint_interval_s, 0.0);    // ... and is checkpointed all the same
  EXPECT_EQ(s.output.checkpoints_kept, 2);
  EXPECT_EQ(s.output.checkpoint_interval_s, OutputParams().checkpoint_interval_s);
}

namespace {

struct Ran {
  RunResult result;
  Particles final_state;
  std::string energies;
};

// clock: the run's wall clock (empty: the real one).
Ran run(const Scene& scene, const std::string& dir, const std::string& resume = "",
        std::function<double()> clock = {}) {
  Ran r;
  std::ostringstream sink;
  RunOptions o = quiet_options(dir, sink, &r.final_state);
  o.clock = std::move(clock);
  o.force = true;
  o.resume = resume;
  r.result = run_scene(scene, o);
  r.energies = test_support::read_file(dir + "/energies.csv");
  return r;
}

double figure(const RunSummary& s, const std::string& key) {
  for (const auto& [k, v] : s.analysis)
    if (k == key) return v;
  return 0.0;
}

void expect_same_points(const Particles& a, const Particles& b) {
  ASSERT_GT(a.size(), 0u) << "no points to compare (no final state returned?)";
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t q = 0; q < a.size(); ++q) {
    ASSERT_EQ(a.x[q], b.x[q]) << "point " << q;
    ASSERT_EQ(a.v[q], b.v[q]) << "point " << q;
    ASSERT_EQ(a.F[q], b.F[q]) << "point " << q;
    ASSERT_EQ(a.sigma[q], b.sigma[q]) << "point " << q;
  }
}

}  // namespace

// The Drucker-Prager column (240 points, ~2000 steps, well under a second): checkpoints
// every 20 ms of wall time, two kept. On a real clock the time trigger picks other steps on
// every run; the result must not depend on them. The run reads an injected clock that moves
// 1 ms at every reading, so that which steps it checkpoints (and how many) does not depend on
// the machine's speed or load: a checkpoint then costs 1 ms, and the trigger waits
// 1 ms / kMaxCost - 1 ms = 49 ms, over the 20 ms asked for.
TEST(CheckpointTime, TimeTriggeredRunEndsAsWithoutAndResumesBitwise) {
  auto ticking_clock = [] { return [t = 0.0]() mutable { return t += 1e-3; }; };
  TempDir plain("ckpt_plain"), timed("ckpt_timed"), resumed("ckpt_resumed");
  Scene scene = SceneBuilder::config("configs/column_collapse_mc.yaml")
                    .with([](Scene& s) {
                      s.output.vtk = false;
                      s.output.checkpoint_interval_steps = 0;
                      s.output.checkpoint_interval_s = 0.0;
                    })
                    .build();
  const Ran a = run(scene, plain.str());
  ASSERT_EQ(a.result.exit_code, 0);
  EXPECT_FALSE(fs::exists(plain.path() / "checkpoints"));
  EXPECT_EQ(figure(a.result.summary, "checkpoints"), 0.0);

  scene.output.checkpoint_interval_s = 0.02;
  const Ran b = run(scene, timed.str(), "", ticking_clock());
  ASSERT_EQ(b.result.exit_code, 0);
  const double written = figure(b.result.summary, "checkpoints");
  std::cout << written << " time-triggered checkpoints in " << b.result.summary.wall_time_s
            << " s (" << figure(b.result.summary, "checkpoint_wall_time_s") << " s in them)\n";
  // Asked for every 20 ms, they are spaced to cost 2 % (1 ms each, one per 50 ms; without the
  // spacing: 5 %). The clock is read about once per step (the trigger), so ~1 per 50 steps.
  const double share =
      figure(b.result.summary, "checkpoint_wall_time_s") / b.result.summary.wall_time_s;
  EXPECT_GT(share, 0.015);
  EXPECT_LE(share, 0.021);
  EXPECT_GE(written, 0.01 * static_cast<double>(a.result.summary.steps));
  int complete = 0;
  for (const auto& e : fs::directory_iterator(timed.path() / "checkpoints"))
    complete += fs::exists(e.path() / "COMPLETE") ? 1 : 0;
  EXPECT_EQ(complete, 2) << written << " written, the newest two kept";
  expect_same_points(a.final_state, b.final_state);
  EXPECT_EQ(a.energies, b.energies);

  // Resume a copy from the older of the two kept (time-triggered) checkpoints.
  fs::copy(timed.path(), resumed.path(), fs::copy_options::recursive);
  const std::string newest = latest_checkpoint(resumed.str());
  fs::remove_all(newest);
  const std::string from = latest_checkpoint(resumed.str());
  ASSERT_FALSE(from.empty());
  const Ran c = run(scene, resumed.str(), "latest", ticking_clock());
  ASSERT_EQ(c.result.exit_code, 0) << from;
  EXPECT_EQ(c.result.summary.steps, a.result.summary.steps);
  expect_same_points(a.final_state, c.final_state);
  EXPECT_EQ(a.energies, c.energies);
}

namespace {

// Linear elastic whose exchange fails (PeerError, as a dead DEM rank) at one step.
class FailingProvider : public ConstitutiveProvider {
 public:
  FailingProvider(const ConstitutiveParams& p, std::int64_t fail_at)
      : inner_(make_linear_elastic(p)), fail_at_(fail_at) {}
  std::string name() const override { return "failing"; }
  void initialise(const std::vector<Mat3>& s0, std::vector<PointResponse>& out) override {
    inner_->initialise(s0, out);
  }
  void update(const std::vector<Mat3>& dF, double dt, std::int64_t step, double time,
              std::vector<PointResponse>& out) override {
    if (step == fail_at_) throw mpmdem::PeerError("DEM server rank 1 died during step 3");
    inner_->update(dF, dt, step, time, out);
  }

 private:
  std::unique_ptr<ConstitutiveProvider> inner_;
  std::int64_t fail_at_;
};

}  // namespace

// Before: a failed exchange left step n+1 positions with step n stresses in the fault
// checkpoint. Now the solver's state after the fault is exactly that after step n.
TEST(FaultState, FailedExchangeLeavesTheLastCompletedStep) {
  const SceneBuilder b = SceneBuilder::config("configs/elastic_column.yaml")
                             .model(kRemoteModel)  // points restorable, as with a DEM server
                             .with([](Scene& s) { s.coupling.outputs = 0; });
  const Scene s = b.build();
  Solver failing = b.solver(std::make_unique<FailingProvider>(s.constitutive, 3));
  Solver reference = b.solver(std::make_unique<FailingProvider>(s.constitutive, -1));
  for (int i = 0; i < 2; ++i) {
    failing.step();
    reference.step();
  }
  EXPECT_THROW(failing.step(), mpmdem::PeerError);
  const SolverState f = failing.state(), r = reference.state();
  EXPECT_EQ(f.step, 2);
  EXPECT_EQ(f.time, r.time);
  expect_same_points(f.particles, r.particles);
  EXPECT_EQ(f.particles.dF, r.particles.dF);
  EXPECT_EQ(f.particles.V, r.particles.V);
  // The points moved in step 3 before the exchange: the restore is not vacuous.
  reference.step();
  EXPECT_NE(reference.particles().x, f.particles.x);
}

// The observers of a run's time loop (mpm_app/src/run/observer.hpp): each keeps its own part
// of a checkpoint (what one saves, a fresh one restored from it saves again), and a column
// snapshot gets its VTK frame by asking the outputs for one (RunContext::frame_wanted).
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "output/run_outputs.hpp"
#include "run/checkpoints.hpp"
#include "run/column_observer.hpp"
#include "run/model_observer.hpp"
#include "run/observer.hpp"
#include "scene_builder.hpp"
#include "test_support.hpp"

using namespace mpmdem::mpm;
using test_fixture::SceneBuilder;
using test_support::TempDir;

namespace {

SceneBuilder column_scene() {
  return SceneBuilder::config("configs/column_collapse_mc.yaml");
}

// The observers that keep a part of a checkpoint, in the run's order.
struct Stateful {
  Stateful(const Scene& scene, Solver& solver, const std::string& dir)
      : column(scene),
        model(solver),
        checkpoints([] { return DriverState{}; }),
        outputs(scene, dir) {}
  std::vector<Observer*> all() { return {&column, &model, &checkpoints, &outputs}; }
  DriverState save() {
    DriverState d;
    for (Observer* o : all()) o->save(d);
    return d;
  }
  ColumnCollapseObserver column;
  ModelObserver model;
  Checkpoints checkpoints;
  RunOutputs outputs;
};

}  // namespace

// The column past its release and its first snapshot (t_r + t*): the stage, the snapshots
// done, the output schedule and the frames so far survive save -> restore -> save.
TEST(Observers, EachRestoresTheStateItSaved) {
  TempDir dir("observers", TempDir::kCreate);
  const SceneBuilder b = column_scene();
  const Scene scene = b.build();
  Solver solver = b.solver();
  std::ostringstream out;
  const std::string run_dir = dir.str();
  RunContext run{scene,
                 run_dir,
                 solver,
                 out,
                 out,
                 [] { return 0.0; },
                 [&scene] { return scene.solver.end_time; }};
  Stateful first(scene, solver, run_dir);
  for (Observer* o : first.all()) o->on_start(run);
  while (solver.time() < 0.5) {
    solver.step();
    run.dt = solver.dt();
    for (Observer* o : first.all()) o->after_step(run);
  }
  ASSERT_NE(out.str().find("snapshot t_star_1"), std::string::npos) << out.str();
  const DriverState saved = first.save();
  ASSERT_TRUE(saved.column.release_time.has_value());
  ASSERT_FALSE(saved.frame_times.empty());

  DriverState resumed = saved;
  resumed.wall_time_s = 12.5;
  run.resumed = true;
  Stateful second(scene, solver, run_dir);
  for (Observer* o : second.all()) o->restore(run, resumed);
  const DriverState again = second.save();
  EXPECT_EQ(again.next_frame, saved.next_frame);
  EXPECT_EQ(again.next_energy, saved.next_energy);
  EXPECT_EQ(again.frame_times, saved.frame_times);
  EXPECT_EQ(again.last_frame_step, saved.last_frame_step);
  EXPECT_EQ(again.last_energy_step, saved.last_energy_step);
  EXPECT_EQ(again.column.release_time, saved.column.release_time);
  EXPECT_EQ(again.column.E_p0_release, saved.column.E_p0_release);
  EXPECT_EQ(again.column.snapshots_done, saved.column.snapshots_done);
  EXPECT_EQ(again.column.rest_quiet_since, saved.column.rest_quiet_since);
  EXPECT_EQ(again.column.rest_time, saved.column.rest_time);
  EXPECT_EQ(again.rve_particles, saved.rve_particles);
  EXPECT_EQ(second.checkpoints.newest_wall_time_s(), 12.5);
}

// An observer asks for a frame of this step; the outputs write it after their own rows,
// once, and take the request back.
TEST(Observers, AFrameAskedForIsWrittenOnceByTheOutputs) {
  TempDir dir("observers_frame", TempDir::kCreate);
  // No frames by time: only the one at t = 0 and those asked for.
  const SceneBuilder b = column_scene().with([](Scene& s) { s.output.interval = 0.0; });
  const Scene scene = b.build();
  Solver solver = b.solver();
  std::ostringstream out;
  const std::string run_dir = dir.str();
  RunContext run{scene,
                 run_dir,
                 solver,
                 out,
                 out,
                 [] { return 0.0; },
                 [&scene] { return scene.solver.end_time; }};
  RunOutputs outputs(scene, run_dir);
  outputs.on_start(run);
  EXPECT_TRUE(outputs.frame_written_at(0));
  solver.step();
  run.dt = solver.dt();
  outputs.after_step(run);
  EXPECT_FALSE(outputs.frame_written_at(1));
  solver.step();
  run.dt = solver.dt();
  run.frame_wanted = true;
  outputs.after_step(run);
  EXPECT_TRUE(outputs.frame_written_at(2));
  EXPECT_FALSE(run.frame_wanted);
  DriverState d;
  outputs.save(d);
  EXPECT_EQ(d.frame_times.size(), 2u);
}

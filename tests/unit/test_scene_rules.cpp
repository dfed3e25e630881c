// The rules of a scene between its sections (mpm_app/src/config/scene_rules.hpp), each
// refusing the scene with the key, the value, the file and the line; and
// column_collapse.release_constraint: none, stage 2 from t = 0 as documented.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "analysis/column_collapse.hpp"
#include "boundary_conditions.hpp"
#include "config_test_support.hpp"
#include "grid.hpp"
#include "particle_init.hpp"
#include "scene_builder.hpp"

using namespace config_test;
using namespace mpmdem::mpm;
using mpmdem::mpm::test_fixture::SceneBuilder;

namespace {

// A plane constraint to append to kMinimal (lines 15-19); its release keys follow at 20.
const std::string kGate =
    "  - name: gate\n"                                              // 16
    "    min: [0.5, 0, 0]\n"                                        // 17
    "    max: [0.5, 1, 1]\n"                                        // 18
    "    components: [x]\n";                                        // 19
const std::string kConstraint = "velocity_constraints:\n" + kGate;  // 15

// configs/column_collapse_mc.yaml with `from` replaced by `to`.
std::string mc_with(const std::string& from, const std::string& to) {
  std::ifstream in(std::string(MPMDEM_SOURCE_DIR) + "/configs/column_collapse_mc.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  return replaced(ss.str(), from, to);
}

}  // namespace

TEST(SceneRules, ConstraintNamesAreUnique) {
  const std::string two = std::string(kMinimal) + kConstraint + kGate;
  EXPECT_CONTAINS(load_error("names.yaml", two),
                  "velocity_constraints[1].name 'gate' is used by velocity_constraints[0] too");
}

TEST(SceneRules, AReleaseMustBeAbleToHappenWithinTheRun) {
  const std::string base = std::string(kMinimal) + kConstraint;  // end_time 0.1
  EXPECT_EQ(load_error("held.yaml", base), "");                  // held for good: fine
  EXPECT_EQ(load_error("early.yaml", base + "    release_time: 0.05\n"), "");
  int line = 0;
  try {
    load_scene(write_file("late.yaml", base + "    release_time: 0.1\n"));
    ADD_FAILURE() << "a release at the end time was accepted";
  } catch (const ConfigError& e) {
    EXPECT_CONTAINS(std::string(e.what()),
                    "velocity_constraints[0].release_time 0.1 is not before solver.end_time 0.1");
    line = e.line();
  }
  EXPECT_EQ(line, 20);
  // By the ratio: not before release_min_time.
  EXPECT_CONTAINS(load_error("ratio.yaml",
                             base + "    release_kinetic_ratio: 0.1\n    release_min_time: 0.2\n"),
                  "velocity_constraints[0].release_min_time 0.2 is not before solver.end_time 0.1");
  // Whichever comes first: a late release_time with an earlier ratio release is fine ...
  EXPECT_EQ(load_error("either.yaml", base + "    release_time: 0.5\n"
                                             "    release_kinetic_ratio: 0.1\n"
                                             "    release_min_time: 0.05\n"),
            "");
  // ... but a ratio whose earliest time is not before release_time could never act.
  EXPECT_CONTAINS(load_error("moot.yaml", base + "    release_time: 0.05\n"
                                                 "    release_kinetic_ratio: 0.1\n"
                                                 "    release_min_time: 0.05\n"),
                  "velocity_constraints[0].release_min_time 0.05 is not below release_time 0.05");
}

TEST(SceneRules, FixedStepShorterThanTheRun) {
  EXPECT_EQ(load_error("dt.yaml", replaced(kMinimal, "  end_time: 0.1\n",
                                           "  end_time: 0.1\n  dt_fixed: 0.01\n")),
            "");
  EXPECT_CONTAINS(load_error("dt2.yaml", replaced(kMinimal, "  end_time: 0.1\n",
                                                  "  end_time: 0.1\n  dt_fixed: 0.1\n")),
                  "solver.dt_fixed 0.1 is not below solver.end_time 0.1");
}

TEST(SceneRules, VerificationNeedsWhatItsSolutionAssumes) {
  const std::string column = std::string(kMinimal) + "verification:\n  kind: elastic_column\n";
  EXPECT_EQ(load_error("v.yaml", column), "");
  EXPECT_CONTAINS(load_error("v_g.yaml", replaced(column, "  end_time: 0.1\n",
                                                  "  end_time: 0.1\n  gravity: [0, -9.81, 0]\n")),
                  "solver.gravity [0, -9.81, 0] does not point along -z, which verification.kind "
                  "elastic_column needs");
  const std::string remote =
      replaced(column, "  linear_elastic:\n    youngs_modulus: 1e6\n    poisson_ratio: 0.25\n",
               "  model: remote\n") +
      "coupling:\n  backend: elastic\n  elastic: {youngs_modulus: 1e6, poisson_ratio: 0.25}\n";
  EXPECT_EQ(load_error("v_remote.yaml", remote), "");
  for (const std::string kind : {"elastic_column", "bar_vibration"}) {
    EXPECT_CONTAINS(
        load_error("v_native.yaml",
                   replaced(replaced(remote, "backend: elastic", "backend: native"),
                            "kind: elastic_column", "kind: " + kind)),
        "verification.kind " + kind +
            " compares with linear elasticity, but the remote model's coupling.backend is "
            "native");
  }
}

TEST(SceneRules, ColumnCollapseRulesNameTheirKeys) {
  const std::vector<std::pair<std::pair<std::string, std::string>, std::string>> cases = {
      {{"  z_min: fixed", "  z_min: free"}, "walls.z_min is free, but it is the column's base"},
      {{"  x_min: slip ", "  x_min: free "}, "walls.x_min is free, but it is the column's back"},
      {{"  region: column", "  region: pile"},
       "column_collapse.region 'pile' names no entry of regions[] (names: 'column')"},
      {{"    release_time: 0.5\n", ""}, ""},  // still released by the ratio: fine
      {{"    release_kinetic_ratio: 1.0e-4\n    release_min_time: 0.05\n    release_time: 0.5\n",
        ""},
       "velocity_constraints[0] 'lateral_face' holds the column in stage 1"},
      {{"  - name: lateral_face", "  - name: none"},
       "column_collapse.release_constraint 'lateral_face' names no entry"},
  };
  for (const auto& [edit, part] : cases) {
    SCOPED_TRACE(edit.second);
    const std::string e = load_error("column.yaml", mc_with(edit.first, edit.second));
    if (part.empty()) {
      EXPECT_EQ(e, "");
    } else {
      EXPECT_CONTAINS(e, part);
    }
  }
  // none is reserved: a constraint of that name makes it ambiguous.
  EXPECT_CONTAINS(
      load_error("ambiguous.yaml",
                 replaced(mc_with("  - name: lateral_face", "  - name: none"),
                          "release_constraint: lateral_face", "release_constraint: none")),
      "column_collapse.release_constraint 'none' is ambiguous");
}

// Documented: release_constraint none starts stage 2 at t = 0 (the column collapses from its
// initial state, here geostatic) while the velocity constraints keep their own release.
TEST(SceneRules, ReleaseConstraintNoneStartsStageTwoAtTimeZero) {
  const std::string file = write_file(
      "none.yaml", mc_with("release_constraint: lateral_face", "release_constraint: none"));
  const Scene scene = load_scene(file);
  ASSERT_EQ(scene.constraints.size(), 1u);
  EXPECT_EQ(column_geometry(scene).constraint, -1);
  const Grid grid(scene.grid);
  const BoundaryConditions bc(scene, grid);
  const Particles p = generate_particles(scene);
  ColumnCollapseMonitor none(scene);
  ASSERT_TRUE(bc.constraint_active(0));   // the face is still held ...
  EXPECT_TRUE(none.observe(0.0, bc, p));  // ... and stage 2 has started
  ASSERT_TRUE(none.release_time().has_value());
  EXPECT_EQ(*none.release_time(), 0.0);
  EXPECT_EQ(none.end_time(), scene.column_collapse.duration_t_star * none.geometry().t_star);
  // The shipped scene, for contrast: stage 1 lasts while the constraint holds the face.
  const Scene held = SceneBuilder::config("configs/column_collapse_mc.yaml").build();
  ColumnCollapseMonitor gated(held);
  EXPECT_EQ(column_geometry(held).constraint, 0);
  EXPECT_FALSE(gated.observe(0.0, BoundaryConditions(held, grid), p));
  EXPECT_FALSE(gated.released());
}

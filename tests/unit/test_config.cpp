// The configuration machinery: validation messages (key path, value, file, line), version
// gate, defaults, cross-key checks of the scene loader, canonical hashing of the coupling
// section, section-only loading, the reference, and every shipped scene file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "config/scene_loader.hpp"
#include "coupling_schema.hpp"
#include "mpmdem/config/schema.hpp"
#include "mpmdem/config_hash.hpp"
#include "mpmdem/protocol.hpp"

namespace fs = std::filesystem;
using mpmdem::config::Config;
using mpmdem::config::ConfigError;
using mpmdem::config::key;
using mpmdem::config::Schema;
using mpmdem::config::Type;
using mpmdem::mpm::load_scene;
using mpmdem::mpm::scene_schema;

namespace {

// EXPECT_CONTAINS(text, part): `text` contains `part` (prints both otherwise).
::testing::AssertionResult contains(const char* text_expr, const char*, const std::string& text,
                                    const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << text_expr << " is\n  " << text << "\nwhich does not contain\n  " << part;
}
#define EXPECT_CONTAINS(text, part) EXPECT_PRED_FORMAT2(contains, text, part)

// A small valid scene; line numbers are referred to by the tests below.
const char* const kMinimal =
    "config_version: 1\n"         // 1
    "grid:\n"                     // 2
    "  extent: [1, 1, 1]\n"       // 3
    "  cell_size: 0.1\n"          // 4
    "regions:\n"                  // 5
    "  - min: [0, 0, 0]\n"        // 6
    "    max: [0.5, 0.5, 0.5]\n"  // 7
    "    density: 1000\n"         // 8
    "solver:\n"                   // 9
    "  end_time: 0.1\n"           // 10
    "constitutive:\n"             // 11
    "  linear_elastic:\n"         // 12
    "    youngs_modulus: 1e6\n"   // 13
    "    poisson_ratio: 0.25\n";  // 14

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "test text has no '" << from << "'";
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

// Writes `text` to a file in the build tree and returns its path.
std::string write_file(const std::string& name, const std::string& text) {
  const fs::path dir = fs::path(MPMDEM_BINARY_DIR) / "test_config_files";
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

// The message of the ConfigError that validating `text` as a scene raises ("" if none).
std::string scene_error(const std::string& text, int* line = nullptr) {
  try {
    Config::from_string(text, scene_schema(), "configs/x.yaml");
  } catch (const ConfigError& e) {
    if (line) *line = e.line();
    return e.what();
  }
  return "";
}

// The message of the ConfigError that load_scene raises for `text` ("" if none).
std::string load_error(const std::string& name, const std::string& text) {
  const std::string file = write_file(name, text);
  try {
    load_scene(file);
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), file);
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ConfigValidation, MinimalSceneIsValid) {
  EXPECT_EQ(scene_error(kMinimal), "");
}

TEST(ConfigValidation, UnknownTopLevelKeyNamesPathFileAndLine) {
  int line = 0;
  const std::string msg = scene_error(std::string(kMinimal) + "solvr:\n  cfl: 0.5\n", &line);
  EXPECT_CONTAINS(msg, std::string("unknown key 'solvr'"));
  EXPECT_CONTAINS(msg, std::string("did you mean 'solver'"));
  EXPECT_CONTAINS(msg, std::string("configs/x.yaml line 15"));
  EXPECT_EQ(line, 15);
}

TEST(ConfigValidation, UnknownKeyInsideListItemNamesItemIndex) {
  const std::string text = std::string(kMinimal) +
                           "velocity_constraints:\n"  // 15
                           "  - min: [0, 0, 0]\n"     // 16
                           "    max: [1, 1, 0]\n"     // 17
                           "    components: [z]\n"    // 18
                           "  - min: [0, 0, 0]\n"     // 19
                           "    max: [1, 1, 0]\n"     // 20
                           "    componets: [z]\n";    // 21
  const std::string msg = scene_error(text);
  EXPECT_CONTAINS(msg, std::string("unknown key 'velocity_constraints[1].componets'"));
  EXPECT_CONTAINS(msg, std::string("did you mean 'components'"));
  EXPECT_CONTAINS(msg, std::string("configs/x.yaml line 21"));

  const std::string msg2 =
      scene_error(replaced(kMinimal, "    density: 1000\n", "    density: 1000\n    densty: 3\n"));
  EXPECT_CONTAINS(msg2, std::string("unknown key 'regions[0].densty'"));
  EXPECT_CONTAINS(msg2, std::string("line 9"));
}

TEST(ConfigValidation, UnknownNestedKeyWithoutCloseMatchListsKnownKeys) {
  const std::string msg =
      scene_error(replaced(kMinimal, "  end_time: 0.1\n", "  end_time: 0.1\n  zzzzzz: 1\n"));
  EXPECT_CONTAINS(msg, std::string("unknown key 'solver.zzzzzz'"));
  EXPECT_CONTAINS(msg, std::string("known keys here: scheme, shape, flip, cfl"));
  EXPECT_CONTAINS(msg, std::string("line 11"));
}

TEST(ConfigValidation, WrongTypeNamesKeyValueAndLine) {
  const std::string msg =
      scene_error(replaced(kMinimal, "  end_time: 0.1\n", "  end_time: 0.1\n  cfl: abc\n"));
  EXPECT_CONTAINS(msg,
                  std::string("solver.cfl must be a number, got 'abc' (configs/x.yaml line 11)"));

  EXPECT_CONTAINS(scene_error(replaced(kMinimal, "cell_size: 0.1", "cell_size: \"0.1\"")),
                  std::string("grid.cell_size must be a number, got the quoted string \"0.1\""));
  EXPECT_CONTAINS(scene_error(replaced(kMinimal, "extent: [1, 1, 1]", "extent: [1, 1]")),
                  std::string("grid.extent must be a list of 3 numbers [x, y, z], got a list"));
  EXPECT_CONTAINS(scene_error(replaced(kMinimal, "extent: [1, 1, 1]", "extent: [1, x, 1]")),
                  std::string("grid.extent[1] must be a number, got 'x' (configs/x.yaml line 3)"));
  EXPECT_CONTAINS(scene_error(std::string(kMinimal) + "output:\n  vtk: yes\n"),
                  std::string("output.vtk must be true or false, got 'yes'"));
  EXPECT_CONTAINS(
      scene_error(replaced(kMinimal, "    density: 1000\n",
                           "    density: 1000\n    points_per_cell: 2.5\n")),
      std::string(
          "regions[0].points_per_cell must be an integer, got '2.5' (configs/x.yaml line 9)"));
  EXPECT_CONTAINS(scene_error(replaced(kMinimal, "solver:\n  end_time: 0.1\n", "solver: 3\n")),
                  std::string("solver must be a map of keys, got '3' (configs/x.yaml line 9)"));
  EXPECT_CONTAINS(scene_error(replaced(kMinimal, "cell_size: 0.1", "cell_size: .nan")),
                  std::string("grid.cell_size must be a number"));
}

TEST(ConfigValidation, OutOfRangeGivesAllowedRange) {
  EXPECT_CONTAINS(
      scene_error(replaced(kMinimal, "  end_time: 0.1\n", "  end_time: 0.1\n  cfl: 1.5\n")),
      std::string("solver.cfl must be in (0, 1], got 1.5 (configs/x.yaml line 11)"));
  EXPECT_CONTAINS(scene_error(replaced(kMinimal, "cell_size: 0.1", "cell_size: 0")),
                  std::string("grid.cell_size must be > 0, got 0 (configs/x.yaml line 4)"));
  EXPECT_CONTAINS(
      scene_error(replaced(kMinimal, "poisson_ratio: 0.25", "poisson_ratio: 0.5")),
      std::string("constitutive.linear_elastic.poisson_ratio must be in [0, 0.5), got 0.5"));
  EXPECT_CONTAINS(scene_error(replaced(kMinimal, "extent: [1, 1, 1]", "extent: [1, -2, 1]")),
                  std::string("grid.extent components must be > 0, got [1, -2, 1]"));
  EXPECT_CONTAINS(scene_error(replaced(kMinimal, "    density: 1000\n",
                                       "    density: 1000\n    points_per_cell: 9\n")),
                  std::string("regions[0].points_per_cell must be in [1, 8], got 9"));
}

TEST(ConfigValidation, BadEnumListsChoices) {
  const std::string msg =
      scene_error(replaced(kMinimal, "  end_time: 0.1\n", "  end_time: 0.1\n  scheme: xyz\n"));
  EXPECT_CONTAINS(msg, std::string("solver.scheme must be one of usl, musl; got 'xyz'"));
  EXPECT_CONTAINS(msg, std::string("line 11"));
  EXPECT_CONTAINS(
      scene_error(std::string(kMinimal) + "coupling:\n  outputs: [rotation, spin]\n"),
      std::string("coupling.outputs[1] must be one of rotation, porosity, coordination, "
                  "unbalanced_force; got 'spin' (configs/x.yaml line 16)"));
  EXPECT_CONTAINS(
      scene_error(std::string(kMinimal) + "walls:\n  z_min: rough\n"),
      std::string("walls.z_min must be one of free, fixed, slip, friction; got 'rough'"));
}

TEST(ConfigValidation, MalformedYamlGivesFileAndLine) {
  try {
    Config::from_string("config_version: 1\ngrid:\n  extent: [1, 1\n  cell_size: 0.1\n",
                        scene_schema(), "configs/bad.yaml");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_CONTAINS(std::string(e.what()), std::string("malformed YAML"));
    EXPECT_CONTAINS(std::string(e.what()), std::string("configs/bad.yaml line"));
    EXPECT_GT(e.line(), 1);
  }
  EXPECT_CONTAINS(scene_error("config_version: 1\n\tgrid: 3\n"), std::string("malformed YAML"));
  EXPECT_CONTAINS(scene_error("- just\n- a list\n"), std::string("top level must be a map"));
  EXPECT_CONTAINS(scene_error(""), std::string("the file is empty"));
}

TEST(ConfigValidation, MissingFileIsConfigError) {
  try {
    Config::load("/nonexistent/scene.yaml", scene_schema());
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_CONTAINS(std::string(e.what()),
                    std::string("cannot open config file '/nonexistent/scene.yaml'"));
  }
}

TEST(ConfigValidation, ConfigVersionMissingNewerOlder) {
  const std::string body = std::string(kMinimal).substr(std::string("config_version: 1\n").size());
  EXPECT_CONTAINS(scene_error(body), std::string("config_version is missing"));
  int line = 0;
  const std::string newer = scene_error("config_version: 2\n" + body, &line);
  EXPECT_CONTAINS(newer, std::string("config_version 2 is newer than this build reads (1): upgrade "
                                     "mpmdem (configs/x.yaml line 1)"));
  EXPECT_EQ(line, 1);
  const std::string older = scene_error("config_version: 0\n" + body);
  EXPECT_CONTAINS(older, std::string("config_version 0 is older than this build reads (1)"));
  EXPECT_CONTAINS(older, std::string("no older format"));
  EXPECT_CONTAINS(scene_error("config_version: one\n" + body),
                  std::string("config_version must be an integer, got 'one'"));
  // The version gate comes before unknown keys: a newer file is not picked apart.
  EXPECT_CONTAINS(scene_error("config_version: 3\nnew_section: {}\n" + body), std::string("newer"));
}

TEST(ConfigValidation, MissingRequiredKeyNamesSectionLine) {
  int line = 0;
  const std::string msg = scene_error(replaced(kMinimal, "  cell_size: 0.1\n", ""), &line);
  EXPECT_CONTAINS(msg, std::string("grid.cell_size is required but missing in 'grid' (line 2)"));
  EXPECT_EQ(line, 2);
  EXPECT_CONTAINS(
      scene_error(replaced(kMinimal, "    density: 1000\n", "")),
      std::string("regions[0].density is required but missing in 'regions[0]' (line 6)"));
  EXPECT_CONTAINS(scene_error(replaced(kMinimal, "solver:\n  end_time: 0.1\n", "")),
                  std::string("solver is required but missing at the top level"));
  // An optional map, once present, needs its required keys.
  EXPECT_CONTAINS(scene_error(replaced(kMinimal, "    density: 1000\n",
                                       "    density: 1000\n    sine_velocity:\n      axis: x\n")),
                  std::string("regions[0].sine_velocity.amplitude is required but missing"));
}

TEST(ConfigValidation, DuplicateKeyRejected) {
  const std::string msg =
      scene_error(replaced(kMinimal, "  end_time: 0.1\n", "  end_time: 0.1\n  end_time: 2\n"));
  EXPECT_CONTAINS(msg, std::string("solver.end_time appears twice (lines 10 and 11)"));
}

TEST(ConfigDefaults, AppliedWhereAbsentAndOverriddenWhereGiven) {
  const std::string file = write_file("defaults.yaml", kMinimal);
  const mpmdem::mpm::Scene s = load_scene(file);
  EXPECT_EQ(s.name, "defaults");  // scene.name absent: file stem
  EXPECT_EQ(s.source_file, file);
  EXPECT_EQ(s.grid.origin, mpmdem::mpm::Vec3::Zero());
  EXPECT_DOUBLE_EQ(s.grid.cell_size, 0.1);
  ASSERT_EQ(s.regions.size(), 1u);
  EXPECT_EQ(s.regions[0].name, "region0");
  EXPECT_EQ(s.regions[0].points_per_cell, 2);
  EXPECT_DOUBLE_EQ(s.regions[0].density, 1000.0);
  EXPECT_FALSE(s.regions[0].sine_velocity);
  EXPECT_FALSE(s.regions[0].geostatic);
  for (const auto& w : s.walls) EXPECT_EQ(w.type, mpmdem::mpm::WallType::kFree);
  EXPECT_TRUE(s.constraints.empty());
  EXPECT_EQ(s.solver.scheme, mpmdem::mpm::Scheme::kMUSL);
  EXPECT_EQ(s.solver.shape, mpmdem::mpm::ShapeKind::kLinear);
  EXPECT_DOUBLE_EQ(s.solver.flip, 0.99);
  EXPECT_DOUBLE_EQ(s.solver.cfl, 0.5);
  EXPECT_DOUBLE_EQ(s.solver.dt_max, 1e-3);
  EXPECT_DOUBLE_EQ(s.solver.end_time, 0.1);
  EXPECT_EQ(s.solver.gravity, mpmdem::mpm::Vec3(0, 0, -9.81));
  EXPECT_DOUBLE_EQ(s.solver.local_damping, 0.0);
  EXPECT_EQ(s.solver.on_exit, mpmdem::mpm::OnExit::kError);
  EXPECT_EQ(s.solver.threads, 0);
  EXPECT_EQ(s.constitutive.model, mpmdem::mpm::ModelKind::kLinearElastic);
  EXPECT_DOUBLE_EQ(s.constitutive.youngs_modulus, 1e6);
  EXPECT_DOUBLE_EQ(s.constitutive.poisson_ratio, 0.25);
  EXPECT_EQ(s.coupling.backend, "elastic");
  EXPECT_EQ(s.coupling.outputs, 0u);
  EXPECT_EQ(s.coupling.service_name, "mpmdem");
  EXPECT_DOUBLE_EQ(s.coupling.connect_timeout_s, 60.0);
  EXPECT_DOUBLE_EQ(s.output.interval, 0.0);
  EXPECT_TRUE(s.output.vtk);
  EXPECT_TRUE(s.output.hdf5);
  EXPECT_DOUBLE_EQ(s.output.progress_interval_s, 2.0);
  EXPECT_EQ(s.verification.kind, mpmdem::mpm::VerificationKind::kNone);

  const std::string given = std::string(kMinimal) + "solver_extra_placeholder\n";  // replaced below
  const std::string text = replaced(
      replaced(given, "solver_extra_placeholder\n",
               "walls:\n  z_min: friction\n  x_max: slip\n  friction: 0.4\n"
               "velocity_constraints:\n  - name: gate\n    min: [0.5, 0, 0]\n"
               "    max: [0.5, 1, 1]\n    components: [x]\n    release_kinetic_ratio: 0.01\n"
               "    release_min_time: 0.2\ncoupling:\n  outputs: [porosity, rotation]\n"
               "output:\n  vtk: false\n"),
      "  end_time: 0.1\n",
      "  end_time: 0.1\n  scheme: usl\n  shape: bspline2\n  threads: 2\n  on_exit: remove\n");
  const mpmdem::mpm::Scene g = load_scene(write_file("given.yaml", text));
  EXPECT_EQ(g.walls[4].type, mpmdem::mpm::WallType::kFriction);
  EXPECT_DOUBLE_EQ(g.walls[4].friction, 0.4);
  EXPECT_EQ(g.walls[1].type, mpmdem::mpm::WallType::kSlip);
  EXPECT_DOUBLE_EQ(g.walls[1].friction, 0.0);
  ASSERT_EQ(g.constraints.size(), 1u);
  EXPECT_EQ(g.constraints[0].name, "gate");
  EXPECT_EQ(g.constraints[0].components, (std::array<bool, 3>{{true, false, false}}));
  EXPECT_FALSE(g.constraints[0].release_time.has_value());
  ASSERT_TRUE(g.constraints[0].release_kinetic_ratio.has_value());
  EXPECT_DOUBLE_EQ(*g.constraints[0].release_kinetic_ratio, 0.01);
  EXPECT_DOUBLE_EQ(g.constraints[0].release_min_time, 0.2);
  EXPECT_EQ(g.solver.scheme, mpmdem::mpm::Scheme::kUSL);
  EXPECT_EQ(g.solver.shape, mpmdem::mpm::ShapeKind::kQuadraticBSpline);
  EXPECT_EQ(g.solver.threads, 2);
  EXPECT_EQ(g.solver.on_exit, mpmdem::mpm::OnExit::kRemove);
  EXPECT_EQ(g.coupling.outputs,
            mpmdem::protocol::kOutputPorosity | mpmdem::protocol::kOutputRotation);
  EXPECT_FALSE(g.output.vtk);
}

TEST(ConfigAccess, ViewsLinesAndProgrammingErrors) {
  const Config cfg = Config::from_string(kMinimal, scene_schema(), "configs/x.yaml");
  EXPECT_TRUE(cfg.has("solver.end_time"));
  EXPECT_FALSE(cfg.has("solver.cfl"));
  EXPECT_DOUBLE_EQ(cfg.number("solver.cfl"), 0.5);
  EXPECT_EQ(cfg.line("solver.end_time"), 10);
  EXPECT_EQ(cfg.line("solver.cfl"), 9);  // absent: the section's line
  const std::vector<Config> regions = cfg.list("regions");
  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(regions[0].line("density"), 8);
  EXPECT_EQ(regions[0].shown("max"), "regions[0].max");
  EXPECT_EQ(regions[0].vec3("max")[2], 0.5);
  try {
    regions[0].fail("max", "is wrong");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "regions[0].max is wrong (configs/x.yaml line 7)");
    EXPECT_EQ(e.key(), "regions[0].max");
  }
  EXPECT_THROW(cfg.number("solver.nonexistent"), std::logic_error);
  EXPECT_THROW(cfg.integer("solver.cfl"), std::logic_error);
  // Reading must not modify the document (yaml-cpp's operator[] can).
  EXPECT_EQ(mpmdem::config::canonical_yaml(cfg.root()),
            mpmdem::config::canonical_yaml(YAML::Load(kMinimal)));
}

TEST(ConfigSchema, DeclarationErrorsAreLogicErrors) {
  Schema s;
  s.add(key("a", Type::kMap, "", "section"));
  s.add(key("a.x", Type::kDouble, "m", "x").def("1"));
  EXPECT_THROW(s.add(key("a.x", Type::kDouble, "m", "again")), std::logic_error);
  EXPECT_THROW(s.add(key("a.y", Type::kDouble, "m", "bad default").def("abc")), std::logic_error);
  EXPECT_THROW(s.add(key("a.z", Type::kDouble, "m", "out of range").def("-1").gt(0)),
               std::logic_error);
  EXPECT_THROW(s.add(key("l[].k", Type::kDouble, "", "no list")), std::logic_error);
  EXPECT_THROW(s.add(key("a.e", Type::kEnum, "", "no choices")), std::logic_error);
  s.add(key("b.c.d", Type::kInt, "", "implicit parents").def("3"));
  ASSERT_NE(s.find("b.c"), nullptr);
  EXPECT_EQ(s.find("b.c")->type, Type::kMap);
  s.add(key("a", Type::kMap, "", "maps may be re-declared"));
  EXPECT_EQ(s.find("a")->doc, "maps may be re-declared");
}

TEST(ConfigCrossChecks, RegionOutsideDomain) {
  const std::string msg = load_error(
      "outside.yaml", replaced(kMinimal, "max: [0.5, 0.5, 0.5]", "max: [0.1, 0.1, 2.5]"));
  EXPECT_CONTAINS(msg,
                  std::string("regions[0].max [0.1, 0.1, 2.5] lies outside the domain grid.origin "
                              ".. grid.origin + grid.extent = [0, 0, 0] .. [1, 1, 1]"));
  EXPECT_CONTAINS(msg, std::string("outside.yaml line 7"));
}

TEST(ConfigCrossChecks, RegionMinNotBelowMax) {
  EXPECT_CONTAINS(
      load_error("minmax.yaml", replaced(kMinimal, "max: [0.5, 0.5, 0.5]", "max: [0.5, 0.0, 0.5]")),
      std::string("regions[0].max [0.5, 0, 0.5] must be > min [0, 0, 0] in every component "
                  "(y is not)"));
}

TEST(ConfigCrossChecks, RegionThinnerThanPointSpacingIsEmpty) {
  const std::string msg =
      load_error("thin.yaml", replaced(kMinimal, "max: [0.5, 0.5, 0.5]", "max: [0.5, 0.04, 0.5]"));
  EXPECT_CONTAINS(msg,
                  std::string("regions[0] is 0.04 m thick along y, less than one point spacing"));
  EXPECT_CONTAINS(msg, std::string("0.05 m"));
  EXPECT_CONTAINS(msg, std::string("line 6"));
  EXPECT_CONTAINS(load_error("noregion.yaml",
                             replaced(kMinimal,
                                      "  - min: [0, 0, 0]\n    max: [0.5, 0.5, 0.5]\n    density: "
                                      "1000\n",
                                      "  []\n")),
                  std::string("regions is empty"));
}

TEST(ConfigCrossChecks, DuplicateRegionNames) {
  const std::string text = replaced(kMinimal, "regions:\n  - ",
                                    "regions:\n  - {name: a, min: [0, 0, 0], max: [1, 1, 1], "
                                    "density: 1}\n  - name: a\n    ");
  EXPECT_CONTAINS(load_error("dupname.yaml", text),
                  std::string("regions[1].name 'a' is used by regions[0] too"));
}

TEST(ConfigCrossChecks, ConstraintChecks) {
  const std::string base = std::string(kMinimal) +
                           "velocity_constraints:\n"
                           "  - min: [0.5, 0, 0]\n"
                           "    max: [0.5, 1, 1]\n"
                           "    components: [x]\n";
  EXPECT_EQ(load_error("c_ok.yaml", base), "");
  EXPECT_CONTAINS(
      load_error("c_empty.yaml", replaced(base, "components: [x]", "components: []")),
      std::string("velocity_constraints[0].components is empty: list at least one of x, "
                  "y, z"));
  // Both release rules: whichever holds first releases the constraint.
  EXPECT_EQ(
      load_error("c_both.yaml", base + "    release_time: 1\n    release_kinetic_ratio: 0.1\n"),
      "");
  EXPECT_CONTAINS(load_error("c_min.yaml", base + "    release_min_time: 1\n"),
                  std::string("release_min_time only applies with release_kinetic_ratio"));
  EXPECT_CONTAINS(
      load_error("c_nonode.yaml", replaced(replaced(base, "min: [0.5, 0, 0]", "min: [0.52, 0, 0]"),
                                           "max: [0.5, 1, 1]", "max: [0.53, 1, 1]")),
      std::string("contains no grid node along x"));
  EXPECT_CONTAINS(
      load_error("c_out.yaml", replaced(base, "max: [0.5, 1, 1]", "max: [0.5, 1, 1.5]")),
      std::string("velocity_constraints[0].max [0.5, 1, 1.5] lies outside the domain"));
}

TEST(ConfigCrossChecks, WallsAndModels) {
  EXPECT_CONTAINS(load_error("fric.yaml", std::string(kMinimal) + "walls:\n  z_min: friction\n"),
                  std::string("walls.friction must be > 0 when a wall is of type friction"));
  const std::string remote =
      replaced(kMinimal, "  linear_elastic:\n    youngs_modulus: 1e6\n    poisson_ratio: 0.25\n",
               "  model: remote\n");
  EXPECT_CONTAINS(
      load_error("remote.yaml", remote),
      std::string("constitutive.model is remote but the file has no coupling: section"));
  EXPECT_CONTAINS(load_error("remote2.yaml", remote + "coupling:\n  backend: elastic\n"),
                  std::string("coupling.backend is elastic but the section coupling.elastic"));
  EXPECT_EQ(load_error("remote3.yaml", remote + "coupling:\n  elastic:\n    youngs_modulus: 1e6\n"
                                                "    poisson_ratio: 0.25\n"),
            "");
  EXPECT_CONTAINS(
      load_error("nolinel.yaml",
                 replaced(kMinimal,
                          "  linear_elastic:\n    youngs_modulus: 1e6\n    poisson_ratio: 0.25\n",
                          "  model: linear_elastic\n")),
      std::string(
          "constitutive.model is linear_elastic but the section constitutive.linear_elastic"));
}

TEST(ConfigCanonical, GenericTextSortsKeysKeepsListOrder) {
  EXPECT_EQ(mpmdem::config::canonical_yaml(YAML::Load("{b: 1, a: [z, y], c: {e: 'x y', d: ~}}")),
            "{a: [z, y], b: 1, c: {d: ~, e: \"x y\"}}");
  EXPECT_EQ(mpmdem::config::format_number(0.3), "0.3");
  EXPECT_EQ(mpmdem::config::format_number(1e7), "10000000");
  EXPECT_EQ(mpmdem::config::format_number(2.5e-7), "2.5e-07");
  EXPECT_EQ(mpmdem::config::format_number(60.0), "60");
}

namespace {
std::uint64_t coupling_hash(const std::string& coupling_text) {
  const Config cfg = Config::from_string("config_version: 1\n" + coupling_text,
                                         mpmdem::coupling_schema(), "coupling.yaml", "coupling");
  return mpmdem::fnv1a64(mpmdem::coupling_canonical_text(cfg));
}
}  // namespace

TEST(ConfigCanonical, CouplingHashIgnoresOrderAndOmittedDefaults) {
  const std::uint64_t a = coupling_hash(
      "coupling:\n  backend: elastic\n  outputs: [rotation]\n"
      "  elastic: {youngs_modulus: 1e7, poisson_ratio: 0.3}\n");
  // Reordered keys, defaults written out, numbers written differently.
  const std::uint64_t b = coupling_hash(
      "coupling:\n  elastic: {poisson_ratio: 0.30, youngs_modulus: 10000000.0}\n"
      "  connect_timeout_s: 60.0\n  outputs: [rotation]\n  service_name: mpmdem\n"
      "  port_file: \"dem_port.txt\"\n");
  EXPECT_EQ(a, b);
  // Any change of value changes the hash.
  EXPECT_NE(a, coupling_hash("coupling:\n  backend: elastic\n  outputs: [rotation]\n"
                             "  elastic: {youngs_modulus: 1e7, poisson_ratio: 0.31}\n"));
  EXPECT_NE(a, coupling_hash("coupling:\n  outputs: [rotation, porosity]\n"
                             "  elastic: {youngs_modulus: 1e7, poisson_ratio: 0.3}\n"));
  EXPECT_NE(a, coupling_hash("coupling:\n  outputs: [rotation]\n  connect_timeout_s: 61\n"
                             "  elastic: {youngs_modulus: 1e7, poisson_ratio: 0.3}\n"));
}

TEST(ConfigCanonical, SceneAndServerComputeTheSameHash) {
  // mpm_app loads the whole scene, dem_app only the coupling section: same hash.
  const std::string file =
      (fs::path(MPMDEM_SOURCE_DIR) / "configs/elastic_column_remote.yaml").string();
  const mpmdem::mpm::Scene scene = load_scene(file);
  const Config server = Config::load(file, mpmdem::coupling_schema(), "coupling");
  EXPECT_EQ(scene.coupling.canonical_text, mpmdem::coupling_canonical_text(server));
  EXPECT_EQ(scene.coupling.hash, mpmdem::fnv1a64(mpmdem::coupling_canonical_text(server)));
  EXPECT_CONTAINS(scene.coupling.canonical_text, std::string("backend: elastic"));
  EXPECT_CONTAINS(scene.coupling.canonical_text, std::string("youngs_modulus: 10000000"));
}

TEST(ConfigSection, SectionOnlyLoadingIgnoresOtherSections) {
  const std::string text =
      "config_version: 1\n"
      "grid: {whatever: 3}\n"
      "not_a_section_dem_app_knows: [1, 2]\n"
      "coupling:\n"
      "  backend: yade\n";
  const Config cfg = Config::from_string(text, mpmdem::coupling_schema(), "scene.yaml", "coupling");
  EXPECT_EQ(cfg.string("coupling.backend"), "yade");
  // Without a section the same text is refused.
  EXPECT_THROW(Config::from_string(text, mpmdem::coupling_schema(), "scene.yaml"), ConfigError);
  // Inside the section, validation is as strict as ever; the version gate too.
  try {
    Config::from_string(text + "  backnd: elastic\n", mpmdem::coupling_schema(), "scene.yaml",
                        "coupling");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_CONTAINS(
        std::string(e.what()),
        std::string("unknown key 'coupling.backnd' (did you mean 'backend'?) (scene.yaml "
                    "line 6)"));
  }
  EXPECT_THROW(Config::from_string("config_version: 2\ncoupling: {}\n", mpmdem::coupling_schema(),
                                   "scene.yaml", "coupling"),
               ConfigError);
  // No coupling section at all: defaults.
  const Config none = Config::from_string("config_version: 1\ngrid: 1\n", mpmdem::coupling_schema(),
                                          "s.yaml", "coupling");
  EXPECT_EQ(none.string("coupling.service_name"), "mpmdem");
}

TEST(ConfigReference, MentionsEveryKeyWithItsDoc) {
  const std::string ref = scene_schema().reference();
  for (const auto& k : scene_schema().keys()) {
    const bool section =
        k.path.find('.') == std::string::npos && (k.type == Type::kMap || k.type == Type::kList);
    if (section) {
      EXPECT_CONTAINS(ref, std::string("## `" + k.path + "`"));  // a heading
    } else {
      EXPECT_CONTAINS(ref, std::string("| `" + k.path + "` |"));  // a row
    }
    EXPECT_FALSE(k.doc.empty()) << k.path << " has no doc";
  }
  EXPECT_CONTAINS(ref, std::string("| `solver.cfl` | number | `0.5` | - | in (0, 1] |"));
  EXPECT_CONTAINS(ref, std::string("| `solver.scheme` | choice | `musl` |  | `usl`, `musl` |"));
  EXPECT_CONTAINS(ref, std::string("| `grid.cell_size` | number | **required** | m | > 0 |"));
  EXPECT_CONTAINS(ref, std::string("## `regions` (list)"));
}

TEST(ShippedConfigs, EveryConfigLoads) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(fs::path(MPMDEM_SOURCE_DIR) / "configs")) {
    if (entry.path().extension() != ".yaml") continue;
    names.insert(entry.path().filename().string());
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(load_scene(entry.path().string()));
  }
  EXPECT_TRUE(names.count("elastic_column.yaml"));
  EXPECT_TRUE(names.count("elastic_bar_vibration.yaml"));
  EXPECT_TRUE(names.count("elastic_column_remote.yaml"));
}

TEST(ShippedConfigs, ElasticColumnAndBarAreTheDocumentedProblems) {
  using namespace mpmdem::mpm;
  const std::string dir = (fs::path(MPMDEM_SOURCE_DIR) / "configs").string();
  const Scene col = load_scene(dir + "/elastic_column.yaml");
  EXPECT_EQ(col.name, "elastic_column");
  EXPECT_EQ(col.verification.kind, VerificationKind::kElasticColumn);
  ASSERT_EQ(col.regions.size(), 1u);
  EXPECT_DOUBLE_EQ(col.regions[0].max.z() - col.regions[0].min.z(), 1.0);
  for (int f = 0; f < 4; ++f) EXPECT_EQ(col.walls[f].type, WallType::kSlip);
  EXPECT_EQ(col.walls[4].type, WallType::kFixed);
  EXPECT_GT(col.solver.local_damping, 0.0);
  // Settled after many P-wave periods T = 4H/c.
  const double E = col.constitutive.youngs_modulus, nu = col.constitutive.poisson_ratio;
  const double M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  const double T = 4.0 / std::sqrt(M / col.regions[0].density);
  EXPECT_NEAR(T, 0.048756, 1e-5);  // the value quoted in the file's comments
  EXPECT_GT(col.solver.end_time, 10 * T);
  // The remote column is the same problem with the stub's material equal to the local one.
  const Scene rem = load_scene(dir + "/elastic_column_remote.yaml");
  EXPECT_EQ(rem.constitutive.model, ModelKind::kRemote);
  EXPECT_EQ(rem.coupling.backend, "elastic");
  const Config rc = Config::load(dir + "/elastic_column_remote.yaml", scene_schema());
  EXPECT_DOUBLE_EQ(rc.number("coupling.elastic.youngs_modulus"), E);
  EXPECT_DOUBLE_EQ(rc.number("coupling.elastic.poisson_ratio"), nu);
  EXPECT_EQ(rem.grid.extent, col.grid.extent);
  EXPECT_EQ(rem.solver.end_time, col.solver.end_time);

  const Scene bar = load_scene(dir + "/elastic_bar_vibration.yaml");
  EXPECT_EQ(bar.verification.kind, VerificationKind::kBarVibration);
  EXPECT_TRUE(bar.regions[0].sine_velocity);
  EXPECT_EQ(bar.regions[0].sine_axis, 0);
  EXPECT_EQ(bar.walls[0].type, WallType::kFixed);
  EXPECT_EQ(bar.walls[1].type, WallType::kFree);
  EXPECT_EQ(bar.solver.gravity, Vec3::Zero());
  EXPECT_EQ(bar.solver.local_damping, 0.0);
  EXPECT_GT(bar.solver.end_time, 3 * T);  // same material and length as the column
}

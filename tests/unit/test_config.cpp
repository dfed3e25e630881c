// The configuration machinery: validation messages (key path, value, file, line), version
// gate, defaults, access, schema declaration errors and the cross-key checks of the scene
// loader. Canonical hashing, sections, the reference and the shipped files:
// test_config_files.cpp.
#include "config_test_support.hpp"

using namespace config_test;

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
  EXPECT_CONTAINS(
      msg,
      std::string("known keys here: scheme, shape, transfer, xpic_order, flip, flip_time_scale, "
                  "flip_velocity_scale, cfl"));
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
  EXPECT_EQ(s.solver.transfer, mpmdem::mpm::Transfer::kPicFlip);
  EXPECT_DOUBLE_EQ(s.solver.flip, 0.99);
  EXPECT_DOUBLE_EQ(s.solver.cfl, 0.5);
  EXPECT_DOUBLE_EQ(s.solver.dt_max, 1e-3);
  EXPECT_DOUBLE_EQ(s.solver.end_time, 0.1);
  EXPECT_EQ(s.solver.gravity, mpmdem::mpm::Vec3(0, 0, -9.81));
  EXPECT_DOUBLE_EQ(s.solver.local_damping, 0.0);
  EXPECT_EQ(s.solver.on_exit, mpmdem::mpm::OnExit::kError);
  EXPECT_EQ(s.solver.threads, 0);
  EXPECT_EQ(s.constitutive.model, "linear_elastic");
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
               "    release_min_time: 0.05\ncoupling:\n  outputs: [porosity, rotation]\n"
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
  EXPECT_DOUBLE_EQ(g.constraints[0].release_min_time, 0.05);
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
  // Paths into list items from the top: the key's line, else the item's, else the list's.
  EXPECT_EQ(cfg.line("regions[0].density"), 8);
  EXPECT_EQ(cfg.line("regions[0].k0"), 6);
  EXPECT_EQ(cfg.line("regions[3].min"), 5);
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
  // Choices on a string would not be checked: a word from a set is a kEnum.
  EXPECT_THROW(s.add(key("a.s", Type::kString, "", "choices").one_of({"p", "q"})),
               std::logic_error);
  EXPECT_THROW(s.add(key("a.n", Type::kDouble, "", "not a string").not_empty()), std::logic_error);
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
  // The elastic stub's missing section is dem_app's to refuse (CouplingRules.*): mpm_app
  // does not read the backends' sections.
  EXPECT_EQ(load_error("remote2.yaml", remote + "coupling:\n  backend: elastic\n"), "");
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

TEST(ConfigCrossChecks, ApicNeedsBSplinesAndNoFlip) {
  const std::string linear = load_error(
      "apic.yaml", replaced(kMinimal, "  end_time: 0.1\n", "  end_time: 0.1\n  transfer: apic\n"));
  EXPECT_CONTAINS(linear, std::string("solver.transfer"));
  EXPECT_CONTAINS(linear, std::string("apic needs solver.shape: bspline2"));
  EXPECT_CONTAINS(linear, std::string("apic.yaml line 11"));
  const std::string flip =
      load_error("apic_flip.yaml", replaced(kMinimal, "  end_time: 0.1\n",
                                            "  end_time: 0.1\n  transfer: apic\n  shape: "
                                            "bspline2\n  flip: 0.99\n"));
  EXPECT_CONTAINS(flip, std::string("solver.flip"));
  EXPECT_CONTAINS(flip, std::string("applies only to solver.transfer: pic_flip"));
  EXPECT_CONTAINS(flip, std::string("apic_flip.yaml line 13"));
}

TEST(ConfigCrossChecks, XpicOrderOnlyWithXpic) {
  const std::string order = load_error(
      "xo.yaml", replaced(kMinimal, "  end_time: 0.1\n", "  end_time: 0.1\n  xpic_order: 3\n"));
  EXPECT_CONTAINS(order, std::string("solver.xpic_order"));
  EXPECT_CONTAINS(order, std::string("applies only to solver.transfer: xpic"));
  const std::string flip = load_error(
      "xf.yaml",
      replaced(kMinimal, "  end_time: 0.1\n", "  end_time: 0.1\n  transfer: xpic\n  flip: 0.9\n"));
  EXPECT_CONTAINS(flip, std::string("applies only to solver.transfer: pic_flip (the transfer is "
                                    "xpic)"));
  const std::string high =
      load_error("xh.yaml", replaced(kMinimal, "  end_time: 0.1\n",
                                     "  end_time: 0.1\n  transfer: xpic\n  xpic_order: 257\n"));
  EXPECT_CONTAINS(high, std::string("solver.xpic_order"));
  EXPECT_CONTAINS(high, std::string("xh.yaml"));
  mpmdem::mpm::SolverParams sp;
  sp.transfer = mpmdem::mpm::Transfer::kXPIC;
  EXPECT_DOUBLE_EQ(mpmdem::mpm::flip_fraction(sp, 0.003), 0.0);  // pure XPIC unless a time scale
  sp.flip_time_scale = 0.03;
  EXPECT_DOUBLE_EQ(mpmdem::mpm::flip_fraction(sp, 0.003), 0.9);
}

// solver.flip_velocity_scale U sets the filter time scale to cell_size / U, and excludes
// solver.flip and solver.flip_time_scale.
TEST(ConfigCrossChecks, FlipVelocityScaleSetsTheTimeScaleFromTheCell) {
  const std::string file = write_file(
      "fvs.yaml",
      replaced(kMinimal, "  end_time: 0.1\n", "  end_time: 0.1\n  flip_velocity_scale: 1.6\n"));
  const mpmdem::mpm::Scene scene = load_scene(file);
  EXPECT_DOUBLE_EQ(scene.solver.flip_time_scale, 0.1 / 1.6);  // kMinimal: cell_size 0.1
  EXPECT_DOUBLE_EQ(mpmdem::mpm::flip_fraction(scene.solver, 0.00625), 0.9);
  const std::string with_flip = load_error(
      "fvs_flip.yaml", replaced(kMinimal, "  end_time: 0.1\n",
                                "  end_time: 0.1\n  flip: 0.99\n  flip_velocity_scale: 1.6\n"));
  EXPECT_CONTAINS(with_flip, std::string("solver.flip_velocity_scale"));
  EXPECT_CONTAINS(with_flip, std::string("replaces solver.flip, which is set too"));
  const std::string with_tau = load_error(
      "fvs_tau.yaml",
      replaced(kMinimal, "  end_time: 0.1\n",
               "  end_time: 0.1\n  flip_time_scale: 0.03\n  flip_velocity_scale: 1.6\n"));
  EXPECT_CONTAINS(with_tau, std::string("solver.flip_velocity_scale"));
  EXPECT_CONTAINS(with_tau, std::string("which is set too"));
  // APIC takes the FLIP share too (Fei et al. 2021); without a time scale it is pure APIC.
  const mpmdem::mpm::Scene apic = load_scene(
      write_file("fvs_apic.yaml", replaced(kMinimal, "  end_time: 0.1\n",
                                           "  end_time: 0.1\n  shape: bspline2\n  transfer: apic\n"
                                           "  flip_velocity_scale: 1.6\n")));
  EXPECT_DOUBLE_EQ(mpmdem::mpm::flip_fraction(apic.solver, 0.00625), 0.9);
  mpmdem::mpm::SolverParams pure;
  pure.transfer = mpmdem::mpm::Transfer::kAPIC;
  EXPECT_DOUBLE_EQ(mpmdem::mpm::flip_fraction(pure, 0.00625), 0.0);
}

TEST(ConfigCrossChecks, FlipTimeScaleReplacesFlip) {
  const std::string both =
      load_error("fts.yaml", replaced(kMinimal, "  end_time: 0.1\n",
                                      "  end_time: 0.1\n  flip: 0.99\n  flip_time_scale: 0.03\n"));
  EXPECT_CONTAINS(both, std::string("solver.flip_time_scale"));
  EXPECT_CONTAINS(both, std::string("replaces solver.flip, which is set too"));
  mpmdem::mpm::SolverParams sp;
  sp.flip_time_scale = 0.03;
  EXPECT_DOUBLE_EQ(mpmdem::mpm::flip_fraction(sp, 0.003), 0.9);
  EXPECT_DOUBLE_EQ(mpmdem::mpm::flip_fraction(sp, 0.06), 0.0);
  sp.flip_time_scale = 0.0;
  EXPECT_DOUBLE_EQ(mpmdem::mpm::flip_fraction(sp, 0.003), 0.99);
}

// The configuration machinery, continued: canonical hashing of the coupling section,
// section-only loading, the generated reference, and every shipped scene file.
#include "config_test_support.hpp"

using namespace config_test;

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
  // Reordered keys; the generic keys' defaults written out and their numbers written
  // differently; the backend's section reordered.
  const std::uint64_t b = coupling_hash(
      "coupling:\n  elastic: {poisson_ratio: 0.3, youngs_modulus: 1e7}\n"
      "  connect_timeout_s: 60.0\n  outputs: [rotation]\n  service_name: mpmdem\n"
      "  port_file: \"dem_port.txt\"\n  lazy_tolerance: 0e0\n");
  EXPECT_EQ(a, b);
  // Any change of value changes the hash.
  EXPECT_NE(a, coupling_hash("coupling:\n  backend: elastic\n  outputs: [rotation]\n"
                             "  elastic: {youngs_modulus: 1e7, poisson_ratio: 0.31}\n"));
  EXPECT_NE(a, coupling_hash("coupling:\n  outputs: [rotation, porosity]\n"
                             "  elastic: {youngs_modulus: 1e7, poisson_ratio: 0.3}\n"));
  EXPECT_NE(a, coupling_hash("coupling:\n  outputs: [rotation]\n  connect_timeout_s: 61\n"
                             "  elastic: {youngs_modulus: 1e7, poisson_ratio: 0.3}\n"));
  // A backend's section counts as written (mpm_app does not know its keys): another spelling
  // of a number, a default written out, or another backend's section change the hash.
  EXPECT_NE(a, coupling_hash("coupling:\n  outputs: [rotation]\n"
                             "  elastic: {youngs_modulus: 10000000, poisson_ratio: 0.3}\n"));
  EXPECT_NE(a, coupling_hash("coupling:\n  outputs: [rotation]\n  native: {seed: 0}\n"
                             "  elastic: {youngs_modulus: 1e7, poisson_ratio: 0.3}\n"));
}

TEST(ConfigCanonical, CouplingTextFollowsTheDocumentedRule) {
  // docs/protocol.md's rule, byte for byte: generic keys normalised with defaults, the
  // backend's section as written (sorted; a scalar that is not plain-safe quoted), absent
  // backend sections left out.
  const Config cfg = Config::from_string(
      "config_version: 1\ncoupling:\n  backend: native\n  connect_timeout_s: 6e1\n"
      "  native: {seed: 01, packing_dir: ../packings/x, damping: 0.20}\n",
      mpmdem::coupling_schema(), "c.yaml", "coupling");
  EXPECT_EQ(mpmdem::coupling_canonical_text(cfg),
            "{backend: native, connect_timeout_s: 60, lazy_tolerance: 0, load_balance: "
            "{min_interval_steps: 50, smoothing: 0.2, threshold: 0}, native: {damping: 0.20, "
            "packing_dir: \"../packings/x\", seed: 01}, outputs: [], peer_timeout_s: 300, "
            "port_file: dem_port.txt, rve_order: interleaved, service_name: mpmdem}");
}

TEST(ConfigCanonical, SceneAndServerComputeTheSameHash) {
  // mpm_app loads the whole scene without the backends' keys, dem_app only the coupling
  // section with them: the same text, so the same hash.
  for (const char* name : {"configs/elastic_column_remote.yaml", "configs/column_collapse_3d.yaml",
                           "configs/column_collapse.yaml"}) {
    SCOPED_TRACE(name);
    const std::string file = (fs::path(MPMDEM_SOURCE_DIR) / name).string();
    const mpmdem::mpm::Scene scene = load_scene(file);
    const Config server = Config::load(file, mpmdem::coupling_schema(), "coupling");
    EXPECT_EQ(scene.coupling.canonical_text, mpmdem::coupling_canonical_text(server));
    EXPECT_EQ(scene.coupling.hash, mpmdem::fnv1a64(mpmdem::coupling_canonical_text(server)));
  }
  const mpmdem::mpm::Scene scene =
      load_scene((fs::path(MPMDEM_SOURCE_DIR) / "configs/elastic_column_remote.yaml").string());
  EXPECT_CONTAINS(scene.coupling.canonical_text, std::string("backend: elastic"));
  EXPECT_CONTAINS(scene.coupling.canonical_text, std::string("youngs_modulus: 1.0e7"));
}

TEST(ConfigCanonical, MpmSideTakesBackendSectionsUnreadServerChecksThem) {
  const std::string text = "config_version: 1\ncoupling:\n  backend: native\n  native: {sed: 1}\n";
  // mpm_app's schema: the backend's section is dem_app's; a generic key is still checked.
  EXPECT_NO_THROW(Config::from_string(text, scene_schema(), "s.yaml", "coupling"));
  EXPECT_THROW(
      Config::from_string(text + "  servce_name: x\n", scene_schema(), "s.yaml", "coupling"),
      ConfigError);
  try {
    Config::from_string(text + "  yade: 3\n", scene_schema(), "s.yaml", "coupling");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_CONTAINS(std::string(e.what()), std::string("coupling.yade must be a map of keys"));
  }
  // dem_app's schema knows the section and refuses the typo.
  try {
    Config::from_string(text, mpmdem::coupling_schema(), "s.yaml", "coupling");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_CONTAINS(std::string(e.what()), std::string("unknown key 'coupling.native.sed'"));
  }
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
  EXPECT_EQ(rem.constitutive.model, kRemoteModel);
  EXPECT_EQ(rem.coupling.backend, "elastic");
  const Config rc =
      Config::load(dir + "/elastic_column_remote.yaml", mpmdem::coupling_schema(), "coupling");
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

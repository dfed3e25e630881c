// The rules between keys of the `coupling:` section (dem_app/src/coupling_rules.hpp): each
// refuses its scene naming the key, the value, the file and the line; the schema's own
// checks of single keys that the DEM server relied on (not empty, choices).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "backend_catalog.hpp"
#include "backend_factory.hpp"
#include "backends/native/native_backend.hpp"
#include "config_test_support.hpp"
#include "coupling_rules.hpp"

using namespace config_test;

namespace {

// The message check_coupling() raises for the section `coupling` ("" if none), and its line.
std::string coupling_error(const std::string& coupling, int* line = nullptr) {
  try {
    const Config cfg = Config::from_string("config_version: 1\ncoupling:\n" + coupling,
                                           mpmdem::coupling_schema(), "c.yaml", "coupling");
    mpmdem::check_coupling(cfg);
  } catch (const ConfigError& e) {
    if (line) *line = e.line();
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CouplingRules, SubstepBoundsAreAPair) {
  for (const std::string b : {"native", "yade"}) {
    SCOPED_TRACE(b);
    const std::string head = "  backend: " + b + "\n  " + b + ":\n";
    EXPECT_EQ(coupling_error(head + "    ns_min: 5\n    ns_max: 5\n"), "");
    int line = 0;
    EXPECT_CONTAINS(coupling_error(head + "    ns_min: 6\n    ns_max: 5\n", &line),
                    "coupling." + b + ".ns_min 6 exceeds coupling." + b + ".ns_max 5");
    EXPECT_EQ(line, 5);
    // Against the default ns_max 100 when only ns_min is given.
    EXPECT_CONTAINS(coupling_error(head + "    ns_min: 101\n"), "ns_max 100");
  }
  // The section of a backend not in use is not looked into.
  EXPECT_EQ(coupling_error("  backend: native\n  yade:\n    ns_min: 6\n    ns_max: 5\n"), "");
}

TEST(CouplingRules, PackingLibraryKeysReferToEachOther) {
  for (const std::string b : {"native", "yade"}) {
    SCOPED_TRACE(b);
    const std::string head = "  backend: " + b + "\n  " + b + ":\n";
    EXPECT_EQ(coupling_error(head + "    packing_dir: lib\n    packings: [p1]\n"), "");
    EXPECT_EQ(coupling_error(head + "    inline_spheres: 40\n"), "");
    EXPECT_CONTAINS(coupling_error(head + "    packings: [p1, p2]\n"),
                    "coupling." + b + ".packings [p1, p2] names packings but coupling." + b +
                        ".packing_dir is empty");
    int line = 0;
    EXPECT_CONTAINS(
        coupling_error(head + "    packing_dir: lib\n    packings: []\n", &line),
        "coupling." + b + ".packing_dir 'lib' is given but coupling." + b + ".packings is empty");
    EXPECT_EQ(line, 5);
    EXPECT_CONTAINS(coupling_error(head + "    packing_spec: spec.yaml\n"),
                    "coupling." + b + ".packing_spec 'spec.yaml' is given but coupling." + b +
                        ".packing_dir is empty");
  }
}

TEST(CouplingRules, OutputsAreThoseTheBackendComputes) {
  const std::string elastic = "  elastic: {youngs_modulus: 1e6, poisson_ratio: 0.25}\n";
  EXPECT_EQ(coupling_error("  backend: elastic\n  outputs: []\n" + elastic), "");
  int line = 0;
  EXPECT_CONTAINS(
      coupling_error("  backend: elastic\n  outputs: [porosity]\n" + elastic, &line),
      "coupling.outputs [porosity] asks for 'porosity', which backend elastic does not compute "
      "(it provides: none)");
  EXPECT_EQ(line, 4);
  EXPECT_EQ(coupling_error("  backend: native\n  outputs: [rotation, porosity, coordination, "
                           "unbalanced_force]\n"),
            "");
  EXPECT_EQ(mpmdem::dem::backend_outputs("elastic"), 0u);
  EXPECT_EQ(mpmdem::dem::backend_outputs("yade"), mpmdem::protocol::kKnownOutputs);
  EXPECT_EQ(mpmdem::dem::backend_outputs("native"), mpmdem::protocol::kKnownOutputs);
  EXPECT_CONTAINS(coupling_error("  backend: elastic\n"),
                  "coupling.backend is elastic but the section coupling.elastic");
}

TEST(CouplingRules, SchemaRefusesWhatTheServerCouldNotUse) {
  EXPECT_CONTAINS(coupling_error("  backend: native\n  service_name: ''\n"),
                  "coupling.service_name must not be empty");
  EXPECT_CONTAINS(coupling_error("  backend: native\n  port_file: \"\"\n"),
                  "coupling.port_file must not be empty");
  // A string key with fixed choices is an enum: a value outside them is refused.
  EXPECT_CONTAINS(coupling_error("  backend: native\n  native:\n"
                                 "    consolidation_on_failure: ignore\n"),
                  "coupling.native.consolidation_on_failure must be one of error, warn; got "
                  "'ignore'");
  EXPECT_EQ(coupling_error("  backend: native\n  native:\n    consolidation_on_failure: warn\n"),
            "");
}

// coupling.native.consolidation_cache names a folder that exists or can be made (checked by
// dem_app, where the DEM runs); YADE keeps no cache and refuses the key.
TEST(CouplingRules, ConsolidationCacheIsAFolderAndNativeOnly) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("rules_cache_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "a_file";
  std::ofstream(file) << "x";
  auto cache_error = [&](const std::string& value, int* line = nullptr) {
    try {
      const Config cfg = Config::from_string(
          "config_version: 1\ncoupling:\n  backend: native\n  native:\n    "
          "consolidation_cache: \"" +
              value + "\"\n",
          mpmdem::coupling_schema(), (dir / "c.yaml").string(), "coupling");
      mpmdem::check_consolidation_cache(cfg);
    } catch (const ConfigError& e) {
      if (line) *line = e.line();
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(cache_error(""), "");
  EXPECT_EQ(cache_error((dir / "new" / "cache").string()), "");  // made when the run starts
  EXPECT_EQ(cache_error("relative/cache"), "");                  // under the scene's folder
  int line = 0;
  EXPECT_CONTAINS(
      cache_error(file.string(), &line),
      "coupling.native.consolidation_cache '" + file.string() + "' exists and is not a folder");
  EXPECT_EQ(line, 5);
  EXPECT_CONTAINS(cache_error("a_file/cache"), "is not a folder this user can write in");
  EXPECT_CONTAINS(coupling_error("  backend: yade\n  yade:\n    consolidation_cache: c\n", &line),
                  "coupling.yade.consolidation_cache 'c' is given, but the YADE backend "
                  "consolidates every RVE itself");
  EXPECT_EQ(line, 5);
  EXPECT_EQ(coupling_error("  backend: yade\n  yade:\n    consolidation_cache: \"\"\n"), "");
  fs::remove_all(dir);
}

TEST(CouplingRules, ContactLawAndRestitution) {
  for (const std::string b : {"native", "yade"}) {
    SCOPED_TRACE(b);
    const std::string head = "  backend: " + b + "\n  " + b + ":\n";
    EXPECT_EQ(coupling_error(head + "    contact_law: frict\n"), "");
    EXPECT_EQ(coupling_error(head + "    contact_law: frict_visco\n    restitution_normal: 0.5\n"),
              "");
    // e_n without the dashpot's law: refused naming key, value and file.
    int line = 0;
    const std::string e = coupling_error(head + "    restitution_normal: 0.5\n", &line);
    EXPECT_CONTAINS(e, "coupling." + b + ".restitution_normal 0.5 is given but coupling." + b +
                           ".contact_law is frict");
    EXPECT_CONTAINS(e, "c.yaml");
    EXPECT_EQ(line, 5);
    // Unknown law, and e_n outside (0, 1].
    EXPECT_CONTAINS(coupling_error(head + "    contact_law: visc_el\n"), "visc_el");
    EXPECT_CONTAINS(coupling_error(head + "    contact_law: visc_el\n"),
                    "coupling." + b + ".contact_law");
    for (const char* bad : {"0", "-0.5", "1.5"}) {
      const std::string msg = coupling_error(
          head + "    contact_law: frict_visco\n    restitution_normal: " + bad + "\n");
      EXPECT_CONTAINS(msg, "coupling." + b + ".restitution_normal");
      EXPECT_CONTAINS(msg, bad);
    }
  }
  // The law the keys give.
  const Config cfg = Config::from_string(
      "config_version: 1\ncoupling:\n  backend: native\n  native:\n    contact_law: "
      "frict_visco\n    restitution_normal: 0.8\n",
      mpmdem::coupling_schema(), "c.yaml", "coupling");
  const auto law = mpmdem::contact_law(cfg, "native");
  EXPECT_TRUE(law.viscous());
  EXPECT_EQ(law.restitution_n, 0.8);
  EXPECT_EQ(law.beta_n, mpmdem::dem::native::restitution_damping_ratio(0.8));
  // cuda has the frict law only.
  const std::string cuda = coupling_error(
      "  backend: cuda\n  native:\n    contact_law: frict_visco\n    restitution_normal: 0.5\n");
  EXPECT_CONTAINS(cuda,
                  "coupling.native.contact_law frict_visco is not available with backend "
                  "cuda");
}

// coupling.<backend>.time_step_scale: the DEM step as a fraction of the packing's, in (0, 1]
// (a larger step than YADE's 0.5 PWaveTimeStep would not be stable); the native backend
// reads it.
TEST(CouplingRules, TimeStepScaleIsAFractionOfThePackingsStep) {
  for (const std::string b : {"native", "yade"}) {
    SCOPED_TRACE(b);
    const std::string head = "  backend: " + b + "\n  " + b + ":\n";
    EXPECT_EQ(coupling_error(head + "    time_step_scale: 0.5\n"), "");
    for (const char* bad : {"0", "-0.5", "1.5"}) {
      const std::string msg =
          coupling_error(head + "    time_step_scale: " + std::string(bad) + "\n");
      EXPECT_CONTAINS(msg, "coupling." + b + ".time_step_scale");
      EXPECT_CONTAINS(msg, bad);
    }
  }
  const Config cfg = Config::from_string(
      "config_version: 1\ncoupling:\n  backend: native\n  native:\n    time_step_scale: 0.25\n",
      mpmdem::coupling_schema(), "c.yaml", "coupling");
  EXPECT_EQ(mpmdem::dem::native_params(cfg).time_step_scale, 0.25);
  const Config plain = Config::from_string("config_version: 1\ncoupling:\n  backend: native\n",
                                           mpmdem::coupling_schema(), "c.yaml", "coupling");
  EXPECT_EQ(mpmdem::dem::native_params(plain).time_step_scale, 1.0);
}

// The backends by name (backend_catalog.hpp): every row declares its section and its rules,
// the schema's coupling.backend takes exactly the catalog's names, and every backend built
// into this dem_app is a row of it (elastic, native and cuda always).
TEST(BackendCatalog, EveryBackendDeclaresItsSectionRulesAndOutputs) {
  const auto& schema = mpmdem::coupling_schema();
  std::vector<std::string> names;
  for (const mpmdem::dem::BackendSpec& b : mpmdem::dem::backend_catalog()) {
    SCOPED_TRACE(b.name);
    names.push_back(b.name);
    ASSERT_NE(b.add_keys, nullptr);
    ASSERT_NE(b.check, nullptr);
    EXPECT_FALSE(b.summary.empty());
    const auto* section = schema.find("coupling." + b.name);
    ASSERT_NE(section, nullptr);
    EXPECT_EQ(section->type, mpmdem::config::Type::kMap);
    EXPECT_EQ(mpmdem::dem::backend_outputs(b.name), b.outputs);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"elastic", "yade", "native", "cuda"}));
  EXPECT_EQ(schema.find("coupling.backend")->choices, names);
  for (const std::string& built : mpmdem::dem::available_backends()) {
    EXPECT_NE(mpmdem::dem::find_backend(built), nullptr) << built;
  }
  for (const char* always : {"elastic", "native", "cuda"}) {
    const auto built = mpmdem::dem::available_backends();
    EXPECT_NE(std::find(built.begin(), built.end(), always), built.end()) << always;
  }
  EXPECT_EQ(mpmdem::dem::find_backend("gpu"), nullptr);
  EXPECT_EQ(mpmdem::dem::backend_outputs("gpu"), 0u);
}

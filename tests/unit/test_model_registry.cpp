// The registry of local constitutive models (constitutive/model_registry.hpp), and a local
// model added in this one file and nowhere else: `test_bulk`, a pressure-only model,
// sigma = K (J - 1) I with J the point's volume ratio since the start. Registered below, it
// is a value of constitutive.model, has its section constitutive.test_bulk in the schema,
// and runs a scene through run_scene (docs/add_a_model.md).
#include <gtest/gtest.h>

#include <Eigen/LU>

#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/scene_loader.hpp"
#include "constitutive/model_registry.hpp"
#include "mpmdem/config/schema.hpp"
#include "run_driver.hpp"
#include "scene_builder.hpp"
#include "test_support.hpp"

using namespace mpmdem::mpm;
using test_support::TempDir;

namespace {

// ---- The model: parameters, provider, keys, load, registration. ---------------------------

struct TestBulkParams final : ModelParams {
  double bulk_modulus = 0.0;  // K [Pa]
};

class TestBulkProvider final : public ConstitutiveProvider {
 public:
  explicit TestBulkProvider(double K) : K_(K) {}
  std::string name() const override { return "test_bulk"; }
  // The pressure starts from the volume the points have at the start (J = 1); the given
  // initial stress is not used (the scenes below start from zero stress).
  void initialise(const std::vector<Mat3>& initial_stress,
                  std::vector<PointResponse>& out) override {
    J_.assign(initial_stress.size(), 1.0);
    respond(out);
  }
  void update(const std::vector<Mat3>& dF, double /*dt*/, std::int64_t /*step*/, double /*time*/,
              std::vector<PointResponse>& out) override {
    for (std::size_t i = 0; i < J_.size(); ++i) J_[i] *= dF[i].determinant();
    respond(out);
  }

 private:
  void respond(std::vector<PointResponse>& out) const {
    out.assign(J_.size(), PointResponse{});
    for (std::size_t i = 0; i < J_.size(); ++i) {
      out[i].stress = K_ * (J_[i] - 1.0) * Mat3::Identity();
      out[i].stiffness = K_;  // the P-wave modulus of a material without shear stiffness
    }
  }
  double K_;
  std::vector<double> J_;
};

void add_keys(mpmdem::config::Schema& s, const std::string& section) {
  s.add(mpmdem::config::key(section + ".bulk_modulus", mpmdem::config::Type::kDouble, "Pa",
                            "bulk modulus K")
            .req()
            .gt(0));
}

// The moduli every local model gives: E = 3 K (1 - 2 nu) with nu = 0, so that the energy
// budget's 1/2 sigma : C^-1 : sigma is p^2 / (2 K), this model's stored energy to first order.
void load(const mpmdem::config::Config& cfg, const std::string& section, ConstitutiveParams& c) {
  auto own = std::make_shared<TestBulkParams>();
  own->bulk_modulus = cfg.number(section + ".bulk_modulus");
  c.youngs_modulus = 3.0 * own->bulk_modulus;
  c.poisson_ratio = 0.0;
  c.own = own;
}

std::unique_ptr<ConstitutiveProvider> make(const ConstitutiveParams& c) {
  const auto* own = dynamic_cast<const TestBulkParams*>(c.own.get());
  if (!own) throw std::invalid_argument("test_bulk: no TestBulkParams (scene not loaded?)");
  return std::make_unique<TestBulkProvider>(own->bulk_modulus);
}

[[maybe_unused]] const bool registered = register_local_model(
    {"test_bulk", "pressure only, K (J - 1) (tests/unit/test_model_registry.cpp)", add_keys, load,
     make});

// ---- Scenes. ---------------------------------------------------------------------------

// A column on a fixed floor under gravity between frictionless walls (it is compressed
// without spreading), with `constitutive_section`.
std::string scene_text(const std::string& constitutive_section) {
  return "config_version: 1\n"
         "scene:\n"
         "  name: registry_block\n"
         "grid:\n"
         "  extent: [0.4, 0.4, 0.6]\n"
         "  cell_size: 0.1\n"
         "walls:\n"
         "  x_min: slip\n"
         "  x_max: slip\n"
         "  y_min: slip\n"
         "  y_max: slip\n"
         "  z_min: fixed\n"
         "regions:\n"
         "  - min: [0, 0, 0]\n"
         "    max: [0.4, 0.4, 0.3]\n"
         "    density: 1000\n"
         "solver:\n"
         "  end_time: 0.1\n"
         "output:\n"
         "  vtk: false\n"
         "  hdf5: false\n"
         "constitutive:\n" +
         constitutive_section;
}

std::string write_scene(const TempDir& dir, const std::string& text) {
  std::filesystem::create_directories(dir.path());
  const std::string file = dir.str() + "/scene.yaml";
  std::ofstream(file) << text;
  return file;
}

std::string load_error(const TempDir& dir, const std::string& text) {
  try {
    load_scene(write_scene(dir, text));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// Every built-in model is registered, also in a program that references none of their
// files (this one): the model files are linked whole (mpm_core is an OBJECT library).
TEST(ModelRegistry, ListsTheBuiltInModelsAndTheOneOfThisFile) {
  std::vector<std::string> names;
  for (const LocalModel* m : local_models()) names.push_back(m->name);
  EXPECT_EQ(names, (std::vector<std::string>{"drucker_prager", "linear_elastic", "test_bulk"}));
  EXPECT_EQ(local_model_names(), "drucker_prager, linear_elastic, test_bulk");
  ASSERT_NE(find_local_model("drucker_prager"), nullptr);
  EXPECT_NE(find_local_model("drucker_prager")->figures, nullptr);
  EXPECT_EQ(find_local_model(kRemoteModel), nullptr);  // remote is not a local model
}

TEST(ModelRegistry, TheSchemaOffersEachModelAndItsSection) {
  const mpmdem::config::Schema& s = scene_schema();
  const mpmdem::config::KeySpec* model = s.find("constitutive.model");
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->choices,
            (std::vector<std::string>{"drucker_prager", "linear_elastic", "test_bulk", "remote"}));
  EXPECT_EQ(model->default_yaml, "linear_elastic");
  ASSERT_NE(s.find("constitutive.test_bulk"), nullptr);
  EXPECT_NE(s.find("constitutive.test_bulk")->doc.find("(model test_bulk)"), std::string::npos);
  ASSERT_NE(s.find("constitutive.test_bulk.bulk_modulus"), nullptr);
  ASSERT_NE(s.find("constitutive.drucker_prager.mu_i.grain_density"), nullptr);
}

TEST(ModelRegistry, RefusesRegisteringANameTwiceOrRemote) {
  LocalModel again{"linear_elastic", "again", add_keys, load, make};
  EXPECT_THROW(register_local_model(again), std::logic_error);
  LocalModel remote{kRemoteModel, "not local", add_keys, load, make};
  EXPECT_THROW(register_local_model(remote), std::logic_error);
  LocalModel no_make{"no_make", "lacks make", add_keys, load, nullptr};
  EXPECT_THROW(register_local_model(no_make), std::logic_error);
  EXPECT_EQ(find_local_model("no_make"), nullptr);
}

TEST(ModelRegistry, AnUnknownModelIsRefusedNamingTheRegisteredOnes) {
  TempDir dir("registry_unknown", TempDir::kCreate);
  const std::string e = load_error(dir, scene_text("  model: no_such_model\n"));
  EXPECT_NE(e.find("constitutive.model"), std::string::npos) << e;
  EXPECT_NE(e.find("must be one of drucker_prager, linear_elastic, test_bulk, remote"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("no_such_model"), std::string::npos) << e;
  // A scene built in code with an unknown name: the run does not start, and says why.
  try {
    (void)local_model("no_such_model");
    ADD_FAILURE() << "local_model accepted an unknown name";
  } catch (const std::invalid_argument& x) {
    EXPECT_NE(std::string(x.what()).find("registered: drucker_prager, linear_elastic, test_bulk"),
              std::string::npos)
        << x.what();
  }
}

TEST(ModelRegistry, AMissingSectionNamesTheModelsRequiredKeys) {
  TempDir dir("registry_missing", TempDir::kCreate);
  const std::string e = load_error(dir, scene_text("  model: test_bulk\n"));
  EXPECT_NE(e.find("constitutive.model is test_bulk but the section constitutive.test_bulk "
                   "(bulk_modulus) is missing"),
            std::string::npos)
      << e;
  const std::string dp = load_error(dir, scene_text("  model: drucker_prager\n"));
  EXPECT_NE(dp.find("the section constitutive.drucker_prager (youngs_modulus, poisson_ratio, "
                    "friction_angle_deg, ...) is missing"),
            std::string::npos)
      << dp;
}

// The model of this file, from a scene file to a run: each point's stress is K (J - 1) I
// with J = det F (the provider's J and the solver's F accumulate the same increments).
TEST(ModelRegistry, ASceneWithTheModelOfThisFileRunsWithItsClosedFormStress) {
  const double K = 2e5;
  TempDir dir("registry_run", TempDir::kCreate);
  const Scene scene = load_scene(
      write_scene(dir, scene_text("  model: test_bulk\n  test_bulk:\n    bulk_modulus: 2e5\n")));
  EXPECT_EQ(scene.constitutive.model, "test_bulk");
  EXPECT_EQ(scene.constitutive.youngs_modulus, 3.0 * K);
  EXPECT_EQ(scene.constitutive.poisson_ratio, 0.0);

  std::ostringstream log;
  Particles final_state;
  const RunResult r =
      run_scene(scene, test_fixture::quiet_options(dir.str() + "/run", log, &final_state));
  ASSERT_EQ(r.exit_code, 0) << log.str();
  EXPECT_EQ(r.summary.model, "test_bulk");
  EXPECT_GT(r.summary.steps, 10);
  ASSERT_GT(final_state.size(), 0u);
  double min_J = 1.0;
  for (std::size_t q = 0; q < final_state.size(); ++q) {
    const double J = final_state.F[q].determinant();
    min_J = std::min(min_J, J);
    const Mat3 expected = K * (J - 1.0) * Mat3::Identity();
    EXPECT_LE((final_state.sigma[q] - expected).cwiseAbs().maxCoeff(), 1e-9 * K)
        << "point " << q << ": sigma\n"
        << final_state.sigma[q] << "\nexpected\n"
        << expected;
  }
  // Under gravity on the floor the column is compressed: the check above is not of zeros.
  EXPECT_LT(min_J, 1.0 - 1e-4);
}

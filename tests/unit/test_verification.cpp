// Verification against analytic solutions, run in-process through the run driver:
//   - elastic column under self-weight (configs/elastic_column.yaml): stress profile and top
//     settlement within 1%;
//   - vibrating bar (configs/elastic_bar_vibration.yaml): period within 2% of 4 L / c;
//   - mass conserved exactly (bitwise) over a run;
//   - a non-finite stress fails the run (exit 4, summary "failed"), a stop request ends it
//     after the current step with outputs written (exit 130, "interrupted").
// The verifiers themselves are checked first on synthetic states with known errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <string>

#include "constitutive/linear_elastic.hpp"
#include "hooked_provider.hpp"
#include "particle_init.hpp"
#include "run_driver.hpp"
#include "scene_builder.hpp"
#include "test_support.hpp"
#include "verification/bar_vibration.hpp"
#include "verification/elastic_column.hpp"

namespace fs = std::filesystem;
using namespace mpmdem::mpm;
using test_fixture::HookedProvider;
using test_fixture::quiet_options;
using test_fixture::SceneBuilder;
using test_fixture::Update;
using test_support::read_file;
using test_support::TempDir;

namespace {

double figure(const RunSummary& s, const std::string& key) {
  for (const auto& [k, v] : s.verification)
    if (k == key) return v;
  ADD_FAILURE() << "summary has no " << key;
  return std::numeric_limits<double>::quiet_NaN();
}

// The column's exact static state (1D strain) for a given scene, built on its particles.
Particles exact_column(const Scene& scene) {
  Particles p = generate_particles(scene);
  const double g = -scene.solver.gravity.z();
  const double M = scene_elastic_moduli(scene).M;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const RegionParams& reg = scene.regions[static_cast<std::size_t>(p.region[i])];
    const double H = reg.max.z() - reg.min.z();
    const double Z = p.x0[i].z() - reg.min.z();
    p.sigma[i] = Mat3::Zero();
    p.sigma[i](2, 2) = -reg.density * g * (H - Z);
    p.x[i].z() = p.x0[i].z() - reg.density * g / M * (H * Z - 0.5 * Z * Z);
  }
  return p;
}

}  // namespace

TEST(ElasticColumnVerifier, ExactStateHasNoErrorAndKnownPerturbationsAreMeasured) {
  const Scene scene = SceneBuilder::config("configs/elastic_column.yaml").build();
  Particles p = exact_column(scene);
  ElasticColumnResult r = verify_elastic_column(scene, p);
  EXPECT_LT(r.stress_rel_error, 1e-12);
  EXPECT_LT(r.settlement_rel_error, 1e-12);
  EXPECT_GT(r.top_layer_points, 0u);
  // Surface settlement rho g H^2 / (2M) of the scene's comment: 7.288e-4 m.
  EXPECT_NEAR(r.settlement_surface_expected_m, 7.288e-4, 1e-6);

  for (std::size_t i = 0; i < p.size(); ++i) {
    p.sigma[i](2, 2) *= 1.03;
    p.x[i].z() = p.x0[i].z() - 1.05 * (p.x0[i].z() - p.x[i].z());
  }
  r = verify_elastic_column(scene, p);
  EXPECT_NEAR(r.stress_rel_error, 0.03, 1e-12);
  EXPECT_NEAR(r.settlement_rel_error, 0.05, 1e-9);
}

TEST(BarVibrationVerifier, PeriodOfASampledCosineWithNoise) {
  const double T = 0.0487;
  std::vector<double> t, s;
  for (int i = 0; i <= 2000; ++i) {
    t.push_back(i * 1e-4);
    // First mode plus a small third harmonic that wiggles near the crossings.
    s.push_back(std::cos(2 * M_PI * t.back() / T) + 0.05 * std::cos(6 * M_PI * t.back() / T));
  }
  const std::vector<double> c = zero_crossings(t, s);
  ASSERT_EQ(c.size(), 8u);  // 0.2 s is 4.1 periods: crossings at T/4, 3T/4, ...
  EXPECT_NEAR(c[0], T / 4, 1e-5);
  EXPECT_NEAR((c.back() - c.front()) / 3.5, T, 1e-5);
}

TEST(BarVibrationVerifier, SmallExcursionsAcrossZeroAreNotCrossings) {
  // +1, a dip to -0.1 and back (noise), then -1, +1: two real crossings only.
  const std::vector<double> t{0, 1, 2, 3, 4, 5, 6, 7, 8};
  const std::vector<double> s{1.0, 0.5, -0.1, 0.5, 1.0, -1.0, -1.0, 1.0, 1.0};
  const std::vector<double> c = zero_crossings(t, s);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_DOUBLE_EQ(c[0], 4.5);  // the last crossing before -1 was reached
  EXPECT_DOUBLE_EQ(c[1], 6.5);
}

TEST(Verification, ElasticColumnMatchesTheStaticSolutionAndConservesMass) {
  const Scene scene = SceneBuilder::config("configs/elastic_column.yaml").build();
  TempDir dir("column");
  std::ostringstream log;
  Particles final_state;
  const RunResult r = run_scene(scene, quiet_options(dir.str(), log, &final_state));
  ASSERT_EQ(r.exit_code, 0) << log.str();
  const double stress = figure(r.summary, "stress_rel_error");
  const double settlement = figure(r.summary, "settlement_rel_error");
  std::cout << "elastic column: stress_rel_error " << stress << ", settlement_rel_error "
            << settlement << ", " << r.summary.steps << " steps, " << r.summary.n_material_points
            << " points\n";
  EXPECT_LE(stress, 0.01);
  EXPECT_LE(settlement, 0.01);
  EXPECT_NE(read_file(dir.str() + "/summary.json").find("\"stress_rel_error\""), std::string::npos);

  // Mass: every point keeps its mass bit for bit, so the total is bitwise the same.
  const Particles initial = generate_particles(scene);
  ASSERT_EQ(final_state.size(), initial.size());
  for (std::size_t i = 0; i < initial.size(); ++i) {
    ASSERT_EQ(final_state.id[i], initial.id[i]);
    ASSERT_EQ(final_state.m[i], initial.m[i]);
  }
  // The grid carried all of the mass at the last step (partition of unity).
  EXPECT_NEAR(r.summary.mass_grid_kg, r.summary.mass_initial_kg, 1e-12 * r.summary.mass_initial_kg);
}

TEST(Verification, BarVibratesWithThePeriodOfItsFirstMode) {
  const Scene scene = SceneBuilder::config("configs/elastic_bar_vibration.yaml").build();
  TempDir dir("bar");
  std::ostringstream log;
  const RunResult r = run_scene(scene, quiet_options(dir.str(), log));
  ASSERT_EQ(r.exit_code, 0) << log.str();
  const double period = figure(r.summary, "period_s");
  const double expected = figure(r.summary, "period_expected_s");
  const double error = figure(r.summary, "period_rel_error");
  std::cout << "bar vibration: period " << period << " s, expected " << expected << " s, rel error "
            << error << "\n";
  // 4 L / c with c = sqrt(M / rho): the scene's comment says 0.04876 s.
  EXPECT_NEAR(expected, 0.04876, 1e-4);
  EXPECT_GE(figure(r.summary, "zero_crossings"), 4.0);
  EXPECT_LE(error, 0.02);
  // The grid carried all of the mass at the last step (partition of unity).
  EXPECT_NEAR(r.summary.mass_grid_kg, r.summary.mass_initial_kg, 1e-12 * r.summary.mass_initial_kg);
}

TEST(Verification, NonFiniteStressFailsTheRunAndMarksTheResults) {
  const Scene scene = SceneBuilder::config("configs/elastic_column.yaml").end_time(0.05).build();
  TempDir dir("fault");
  std::ostringstream log;
  RunOptions o = quiet_options(dir.str(), log);
  o.provider_factory = [](const Scene& s, std::size_t) -> std::unique_ptr<ConstitutiveProvider> {
    return std::make_unique<HookedProvider>(
        make_linear_elastic(s.constitutive), [](const Update& u, auto& out) {
          if (u.call == 5) out[7].stress(2, 2) = std::numeric_limits<double>::quiet_NaN();
        });
  };
  const RunResult r = run_scene(scene, o);
  EXPECT_EQ(r.exit_code, 4) << log.str();
  EXPECT_EQ(r.summary.status, "failed");
  EXPECT_LE(r.summary.steps, 6);
  const std::string summary = read_file(dir.str() + "/summary.json");
  EXPECT_NE(summary.find("\"status\": \"failed\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"error\": "), std::string::npos);
  EXPECT_NE(summary.find("material point 7"), std::string::npos) << summary;
  const std::regex non_finite(":\\s*-?(nan|inf)", std::regex::icase);
  EXPECT_FALSE(std::regex_search(summary, non_finite)) << summary;
  EXPECT_FALSE(fs::exists(dir.str() + "/final_state.h5"));
  // Whatever was logged before the fault is finite.
  const std::string energies = read_file(dir.str() + "/energies.csv");
  EXPECT_EQ(energies.find("nan"), std::string::npos);
  EXPECT_EQ(energies.find("inf"), std::string::npos);
}

TEST(Verification, StopRequestEndsAfterTheCurrentStepWithOutputs) {
  const Scene scene = SceneBuilder::config("configs/elastic_column.yaml").build();
  TempDir dir("stop");
  std::ostringstream log;
  RunOptions o = quiet_options(dir.str(), log);
  o.provider_factory = [](const Scene& s, std::size_t) -> std::unique_ptr<ConstitutiveProvider> {
    return std::make_unique<HookedProvider>(make_linear_elastic(s.constitutive),
                                            [](const Update& u, auto&) {
                                              if (u.call == 10) request_stop();
                                            });
  };
  const RunResult r = run_scene(scene, o);
  EXPECT_EQ(r.exit_code, 130) << log.str();
  EXPECT_EQ(r.summary.status, "interrupted");
  EXPECT_GE(r.summary.steps, 9);
  EXPECT_LE(r.summary.steps, 11);
  EXPECT_LT(r.summary.time_s, scene.solver.end_time);
  EXPECT_TRUE(fs::exists(dir.str() + "/final_state.h5"));
  EXPECT_NE(read_file(dir.str() + "/summary.json").find("\"status\": \"interrupted\""),
            std::string::npos);
}

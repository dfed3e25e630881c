// The mu(I) option of the drucker_prager model (constitutive/drucker_prager.hpp,
// constitutive.drucker_prager.mu_i): the slope's law and limits, the return onto the
// rate-dependent cone, steady simple shear at an imposed inertial number against the law
// of Jop, Forterre & Pouliquen (2006), the rate-independent limit, the provider's use of
// dt, and the config keys.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "config_test_support.hpp"
#include "constitutive/drucker_prager.hpp"
#include "stress_invariants.hpp"

using namespace mpmdem::mpm;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kD = 2.3e-3, kRhoS = 2500.0, kI0 = 0.279;

ConstitutiveParams mu_i_params(double phi_deg, double phi_2_deg, double c = 0.0) {
  ConstitutiveParams p;
  p.model = "drucker_prager";
  p.youngs_modulus = 1.0e9;
  p.poisson_ratio = 0.3;
  DruckerPragerParams& dp = edit_drucker_prager_params(p);
  dp.friction_angle_deg = phi_deg;
  dp.cohesion = c;
  dp.matching = ConeMatching::kPlaneStrain;
  dp.mu_i_friction_angle_2_deg = phi_2_deg;
  dp.mu_i_inertial_number_0 = kI0;
  dp.mu_i_grain_diameter = kD;
  dp.mu_i_grain_density = kRhoS;
  return p;
}

using stress_test::pressure;
using stress_test::von_mises;
double sin_deg(double a) {
  return std::sin(a * kPi / 180.0);
}

// Jop et al.'s mu(I) with mu = sin(phi) (plane-strain matching, no dilation).
double mu_of(double I, double phi, double phi_2) {
  const double mu_s = sin_deg(phi), mu_2 = sin_deg(phi_2);
  return mu_s + (mu_2 - mu_s) / (kI0 / I + 1.0);
}

}  // namespace

TEST(MuI, SlopeFollowsTheLawBetweenItsLimits) {
  const DruckerPragerLaw law(mu_i_params(20.0, 36.9));
  ASSERT_TRUE(law.rate_dependent());
  const double eta_s = std::sqrt(3.0) * sin_deg(20.0), eta_2 = std::sqrt(3.0) * sin_deg(36.9);
  EXPECT_NEAR(law.slope(0.0), eta_s, 1e-14);
  EXPECT_NEAR(law.slope(kI0), 0.5 * (eta_s + eta_2), 1e-14);
  EXPECT_NEAR(law.slope(std::numeric_limits<double>::infinity()), eta_2, 1e-14);
  EXPECT_NEAR(law.slope(1e-3), eta_s + (eta_2 - eta_s) * 1e-3 / (kI0 + 1e-3), 1e-14);
  // I = sqrt(3) dlambda / dt d / sqrt(p / rho_s); no pressure: infinite
  EXPECT_NEAR(law.inertial_number(1e-4, 1e4, 1e-3), std::sqrt(3.0) * 0.1 * kD / 2.0, 1e-15);
  EXPECT_TRUE(std::isinf(law.inertial_number(1e-4, 0.0, 1e-3)));
  // without mu_i the slope is eta_s at any I
  ConstitutiveParams off = mu_i_params(20.0, 36.9);
  edit_drucker_prager_params(off).mu_i_friction_angle_2_deg = 0.0;
  const DruckerPragerLaw plain(off);
  EXPECT_FALSE(plain.rate_dependent());
  EXPECT_EQ(plain.slope(10.0), plain.eta());
}

TEST(MuI, InvalidParametersAreRefused) {
  EXPECT_THROW(DruckerPragerLaw(mu_i_params(20.0, 20.0)), std::invalid_argument);
  EXPECT_THROW(DruckerPragerLaw(mu_i_params(20.0, 90.0)), std::invalid_argument);
  ConstitutiveParams p = mu_i_params(20.0, 30.0);
  edit_drucker_prager_params(p).mu_i_grain_diameter = 0.0;
  EXPECT_THROW(DruckerPragerLaw{p}, std::invalid_argument);
  p = mu_i_params(20.0, 30.0);
  edit_drucker_prager_params(p).mu_i_inertial_number_0 = -1.0;
  EXPECT_THROW(DruckerPragerLaw{p}, std::invalid_argument);
}

// Trial stresses beyond the cone, at several dt: the returned stress keeps the deviator's
// direction and the pressure (no dilation), lies between the cones of phi and phi_2, and on
// the cone of the inertial number of its own plastic increment.
TEST(MuI, ReturnLandsOnTheConeOfItsOwnInertialNumber) {
  const double c = 2e3;
  const DruckerPragerLaw law(mu_i_params(20.0, 36.9, c));
  const double G = law.shear_modulus(), p_apex = law.apex_pressure();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checked = 0;
  for (int k = 0; k < 200; ++k) {
    Mat3 a;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a(i, j) = u(rng);
    Mat3 dev = 0.5 * (a + a.transpose());
    dev -= dev.trace() / 3.0 * Mat3::Identity();
    dev /= von_mises(dev);
    const double p_tr = 1e4 * (1.0 + u(rng)), q_tr = 2e4 * (1.0 + u(rng));
    const Mat3 trial = q_tr * dev - p_tr * Mat3::Identity();
    const double dt = std::pow(10.0, -6.0 + 3.0 * (u(rng) + 1.0));
    const Mat3 s = law.return_map(trial, dt);
    if (law.yield_function(trial) <= 0.0) {
      EXPECT_EQ(s, trial);
      continue;
    }
    const double q = von_mises(s), p = pressure(s);
    if (q == 0.0) continue;  // apex
    ++checked;
    EXPECT_NEAR(p, p_tr, 1e-9 * p_tr);
    const Mat3 dev_s = (s + p * Mat3::Identity()) / q;
    EXPECT_LT((dev_s - dev).norm(), 1e-9);
    const double dlambda = (q_tr - q) / (3.0 * G);
    const double eta = law.slope(law.inertial_number(dlambda, p, dt));
    EXPECT_NEAR(q, eta * (p - p_apex), 1e-9 * q_tr) << "dt " << dt;
    EXPECT_GE(q, law.eta() * (p - p_apex) * (1 - 1e-12));
    EXPECT_LE(q, law.slope(std::numeric_limits<double>::infinity()) * (p - p_apex) * (1 + 1e-12));
  }
  EXPECT_GT(checked, 50);
}

// Constant-volume simple shear at rate gamma_dot under a pressure p0 (E = 1 GPa, so the
// elastic strain is ~1e-5 and the steady shear is all plastic): the stress ratio
// sqrt(J2)/p reaches Jop et al.'s mu(I) at the imposed I = gamma_dot d / sqrt(p / rho_s),
// from the quasi-static sin(phi) to near sin(phi_2).
TEST(MuI, SteadySimpleShearGivesMuOfTheImposedInertialNumber) {
  const double phi = 20.0, phi_2 = 36.9, p0 = 1e4;
  const DruckerPragerLaw law(mu_i_params(phi, phi_2));
  double previous = 0.0;
  for (const double I : {1e-4, 1e-2, 0.1, 0.279, 1.0, 10.0}) {
    const double gamma_dot = I * std::sqrt(p0 / kRhoS) / kD;
    const double d_gamma = 2e-5, dt = d_gamma / gamma_dot;
    Mat3 dF = Mat3::Identity();
    dF(0, 2) = d_gamma;
    Mat3 sigma = -p0 * Mat3::Identity();
    for (int step = 0; step < 1500; ++step) sigma = law.update(sigma, dF, dt);
    const double p = pressure(sigma);
    const double ratio = von_mises(sigma) / std::sqrt(3.0) / p;  // sqrt(J2) / p
    const double I_now = gamma_dot * kD / std::sqrt(p / kRhoS);
    EXPECT_NEAR(p, p0, 1e-3 * p0) << "I " << I;
    EXPECT_NEAR(ratio, mu_of(I_now, phi, phi_2), 2e-3 * ratio) << "I " << I;
    EXPECT_GT(ratio, previous) << "I " << I;
    previous = ratio;
  }
  EXPECT_GT(previous, 0.95 * sin_deg(phi_2));
}

// dt -> infinity at a given increment: the rate-independent return (dt = infinity exactly,
// or a slow enough step to within the slope's change).
TEST(MuI, SlowStepsReturnTheRateIndependentLaw) {
  const DruckerPragerLaw law(mu_i_params(20.0, 36.9));
  ConstitutiveParams off = mu_i_params(20.0, 36.9);
  edit_drucker_prager_params(off).mu_i_friction_angle_2_deg = 0.0;
  const DruckerPragerLaw plain(off);
  Mat3 dev;
  dev << 0.7, 0.2, -0.1, 0.2, -0.4, 0.3, -0.1, 0.3, -0.3;
  dev /= von_mises(dev);
  const Mat3 trial = 2e4 * dev - 1e4 * Mat3::Identity();
  EXPECT_EQ(law.return_map(trial), plain.return_map(trial));
  const Mat3 slow = law.return_map(trial, 1e6), fast = law.return_map(trial, 1e-7);
  EXPECT_LT((slow - plain.return_map(trial)).norm(), 1e-6 * trial.norm());
  EXPECT_GT(von_mises(fast), von_mises(slow) * 1.01);
  // tension: the apex (no stress without cohesion) at any dt
  EXPECT_EQ(law.return_map(1e3 * Mat3::Identity() + 1e3 * dev, 1e-4), Mat3::Zero());
}

// The provider hands the step's dt to the law: the same shear increment in a shorter step
// (I ~ 1 against ~1e-6) leaves a larger shear stress.
TEST(MuI, ProviderUsesTheTimeStep) {
  const auto slow = make_drucker_prager(mu_i_params(20.0, 36.9));
  const auto fast = make_drucker_prager(mu_i_params(20.0, 36.9));
  std::vector<PointResponse> out_slow, out_fast;
  const std::vector<Mat3> sigma0{-1e4 * Mat3::Identity()};
  slow->initialise(sigma0, out_slow);
  fast->initialise(sigma0, out_fast);
  Mat3 dF = Mat3::Identity();
  dF(0, 2) = 1e-3;
  for (int step = 0; step < 20; ++step) {
    slow->update({dF}, 1.0, step, 0.0, out_slow);
    fast->update({dF}, 1e-6, step, 0.0, out_fast);
  }
  const double q_slow = von_mises(out_slow[0].stress), q_fast = von_mises(out_fast[0].stress);
  EXPECT_NEAR(q_slow / std::sqrt(3.0) / 1e4, sin_deg(20.0), 2e-3);
  EXPECT_GT(q_fast, 1.2 * q_slow);
}

TEST(MuIConfig, KeysDefaultsAndChecks) {
  const std::string base = config_test::replaced(config_test::kMinimal,
                                                 "  linear_elastic:\n"
                                                 "    youngs_modulus: 1e6\n"
                                                 "    poisson_ratio: 0.25\n",
                                                 "  model: drucker_prager\n"
                                                 "  drucker_prager:\n"
                                                 "    youngs_modulus: 2e6\n"
                                                 "    poisson_ratio: 0.3\n"
                                                 "    friction_angle_deg: 20\n");
  const Scene none = load_scene(config_test::write_file("mu_i_none.yaml", base));
  EXPECT_EQ(drucker_prager_params(none.constitutive).mu_i_friction_angle_2_deg, 0.0);
  const Scene given = load_scene(
      config_test::write_file("mu_i_given.yaml", base + "    mu_i:\n"
                                                        "      friction_angle_2_deg: 36.9\n"
                                                        "      grain_diameter: 2.3e-3\n"
                                                        "      grain_density: 2500\n"));
  EXPECT_EQ(drucker_prager_params(given.constitutive).mu_i_friction_angle_2_deg, 36.9);
  EXPECT_EQ(drucker_prager_params(given.constitutive).mu_i_inertial_number_0, 0.279);
  EXPECT_EQ(drucker_prager_params(given.constitutive).mu_i_grain_diameter, 2.3e-3);
  EXPECT_EQ(drucker_prager_params(given.constitutive).mu_i_grain_density, 2500.0);
  const std::string low =
      config_test::load_error("mu_i_low.yaml", base +
                                                   "    mu_i:\n"
                                                   "      friction_angle_2_deg: 15\n"
                                                   "      grain_diameter: 2.3e-3\n"
                                                   "      grain_density: 2500\n");
  EXPECT_NE(low.find("constitutive.drucker_prager.mu_i.friction_angle_2_deg 15 is not above "
                     "friction_angle_deg 20"),
            std::string::npos)
      << low;
  EXPECT_NE(low.find("mu_i_low.yaml"), std::string::npos) << low;
  const std::string missing =
      config_test::load_error("mu_i_missing.yaml", base +
                                                       "    mu_i:\n"
                                                       "      friction_angle_2_deg: 30\n"
                                                       "      grain_density: 2500\n");
  EXPECT_NE(missing.find("grain_diameter"), std::string::npos) << missing;
  const std::string typo =
      config_test::load_error("mu_i_typo.yaml", base +
                                                    "    mu_i:\n"
                                                    "      friction_angle_2_deg: 30\n"
                                                    "      grain_diameter: 2.3e-3\n"
                                                    "      grain_density: 2500\n"
                                                    "      I0: 0.3\n");
  EXPECT_NE(typo.find("I0"), std::string::npos) << typo;
}

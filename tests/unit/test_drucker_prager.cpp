// The drucker_prager model (constitutive/drucker_prager.hpp): elasticity below yield equal
// to linear_elastic, the closed-form return (cone and apex, flow direction of the dilation
// angle), drained triaxial and plane-strain compression against Mohr-Coulomb, objectivity
// under large rotations, K0 in oedometric loading, and a solver run: a slope gentler than
// the friction angle stays at rest, the same slope with a lower friction angle flows.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>

#include "config/scene_loader.hpp"
#include "constitutive/drucker_prager.hpp"
#include "constitutive/linear_elastic.hpp"
#include "mpmdem/laws/elastic_law.hpp"
#include "scene_builder.hpp"
#include "solver.hpp"
#include "stress_invariants.hpp"

using namespace mpmdem::mpm;
using test_fixture::Face;
using test_fixture::SceneBuilder;

namespace {

constexpr double kPi = 3.14159265358979323846;

ConstitutiveParams dp_params(double phi_deg, double psi_deg = 0.0, double c = 0.0,
                             ConeMatching matching = ConeMatching::kCompression) {
  ConstitutiveParams p;
  p.model = "drucker_prager";
  p.youngs_modulus = 1.0e7;
  p.poisson_ratio = 0.3;
  DruckerPragerParams& dp = edit_drucker_prager_params(p);
  dp.friction_angle_deg = phi_deg;
  dp.dilation_angle_deg = psi_deg;
  dp.cohesion = c;
  dp.matching = matching;
  return p;
}

using stress_test::deviator;
using stress_test::pressure;
using stress_test::von_mises;

// A traceless, non-axisymmetric direction with q = 1.
Mat3 unit_deviator() {
  Mat3 d;
  d << 0.7, 0.2, -0.1,  //
      0.2, -0.4, 0.3,   //
      -0.1, 0.3, -0.3;
  return d / von_mises(d);
}

// Compliance C^-1 : sigma.
Mat3 compliance(double E, double nu, const Mat3& s) {
  return ((1.0 + nu) * s - nu * s.trace() * Mat3::Identity()) / E;
}

Mat3 diag(double a, double b, double c) {
  return Eigen::Vector3d(a, b, c).asDiagonal();
}

// One strain-driven step with sigma_xx held at `lateral`: finds the lateral stretch(es) by
// the secant method. plane_strain: only x is free (y stretch 1), else x and y together.
Mat3 lateral_controlled_step(const DruckerPragerLaw& law, const Mat3& sigma, double axial,
                             double lateral, bool plane_strain) {
  const auto trial = [&](double e) {
    const Mat3 dF =
        plane_strain ? diag(1.0 + e, 1.0, 1.0 + axial) : diag(1.0 + e, 1.0 + e, 1.0 + axial);
    return law.update(sigma, dF);
  };
  const auto g = [&](double e) { return trial(e)(0, 0) - lateral; };
  double e0 = -0.3 * axial, e1 = -0.6 * axial;
  double g0 = g(e0), g1 = g(e1);
  for (int it = 0; it < 100 && std::abs(g1) > 1e-10 * std::abs(lateral); ++it) {
    const double e2 = e1 - g1 * (e1 - e0) / (g1 - g0);
    e0 = e1;
    g0 = g1;
    e1 = e2;
    g1 = g(e1);
  }
  EXPECT_LE(std::abs(g1), 1e-9 * std::abs(lateral)) << "lateral stress not held";
  return trial(e1);
}

// Mobilised Mohr-Coulomb angle from the largest and smallest principal stresses.
double mobilised_sin_phi(const Mat3& sigma) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig(sigma);
  const double s1 = -eig.eigenvalues()[0], s3 = -eig.eigenvalues()[2];  // compression +
  return (s1 - s3) / (s1 + s3);
}

}  // namespace

TEST(DruckerPrager, ConeParametersOfBothMatchings) {
  const double phi = 30.0 * kPi / 180.0, s = std::sin(phi);
  const DruckerPragerLaw tc(dp_params(30.0, 10.0, 5e3));
  EXPECT_NEAR(tc.eta(), 6 * s / (3 - s), 1e-14);
  EXPECT_NEAR(tc.xi(), 6 * std::cos(phi) / (3 - s), 1e-14);
  EXPECT_NEAR(tc.apex_pressure(), -5e3 / std::tan(phi), 1e-9);
  const double sp = std::sin(10.0 * kPi / 180.0);
  EXPECT_NEAR(tc.eta_g(), 6 * sp / (3 - sp), 1e-14);
  // Plane strain, psi = 0: the classical sqrt(J2) = sin(phi) p + c cos(phi).
  const DruckerPragerLaw ps0(dp_params(30.0, 0.0, 5e3, ConeMatching::kPlaneStrain));
  EXPECT_NEAR(ps0.eta(), std::sqrt(3.0) * s, 1e-14);
  EXPECT_NEAR(ps0.xi(), std::sqrt(3.0) * std::cos(phi), 1e-14);
  // Plane strain, associated: 3 sqrt(3) tan(phi) / sqrt(9 + 12 tan^2 phi).
  const DruckerPragerLaw psa(dp_params(30.0, 30.0, 0.0, ConeMatching::kPlaneStrain));
  const double t = std::tan(phi);
  EXPECT_NEAR(psa.eta(), 3 * std::sqrt(3.0) * t / std::sqrt(9 + 12 * t * t), 1e-14);
  EXPECT_NEAR(psa.eta_g(), psa.eta(), 1e-14);
  // Stiffness for the CFL step: K + 4G/3 = the constrained modulus.
  const mpmdem::elastic::ElasticLaw el{1e7, 0.3};
  EXPECT_NEAR(tc.constrained_modulus(), el.constrained_modulus(), 1e-6);
}

TEST(DruckerPrager, InvalidParametersAreRefused) {
  EXPECT_THROW(DruckerPragerLaw(dp_params(0.0)), std::invalid_argument);
  EXPECT_THROW(DruckerPragerLaw(dp_params(90.0)), std::invalid_argument);
  EXPECT_THROW(DruckerPragerLaw(dp_params(30.0, 31.0)), std::invalid_argument);
  EXPECT_THROW(DruckerPragerLaw(dp_params(30.0, 0.0, -1.0)), std::invalid_argument);
  ConstitutiveParams p = dp_params(30.0);
  p.poisson_ratio = 0.5;
  EXPECT_THROW(make_drucker_prager(p), std::invalid_argument);
}

// Random small increments (stretch and rotation) around a confined state that stays inside
// the cone: the stresses equal linear_elastic's to round-off.
TEST(DruckerPrager, ElasticBelowYieldEqualsLinearElastic) {
  const ConstitutiveParams p = dp_params(30.0);
  auto dp = make_drucker_prager(p);
  auto le = make_linear_elastic(p);
  const DruckerPragerLaw law(p);
  const std::size_t n = 20;
  std::vector<Mat3> s0(n, Mat3(-1e5 * Mat3::Identity()));
  std::vector<PointResponse> r_dp, r_le;
  dp->initialise(s0, r_dp);
  le->initialise(s0, r_le);
  EXPECT_EQ(dp->name(), "drucker_prager");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2e-4, 2e-4);
  for (int step = 0; step < 50; ++step) {
    std::vector<Mat3> dF(n);
    for (auto& f : dF) {
      f = Mat3::Identity();
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) f(a, b) += u(rng);
    }
    dp->update(dF, 1e-4, step, 0.0, r_dp);
    le->update(dF, 1e-4, step, 0.0, r_le);
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_LT(law.yield_function(r_dp[i].stress), -1e4);  // really elastic
      EXPECT_LE((r_dp[i].stress - r_le[i].stress).norm(), 1e-12 * r_le[i].stress.norm());
      EXPECT_EQ(r_dp[i].stiffness, law.constrained_modulus());
    }
  }
}

// A trial stress beyond the cone returns onto it; the plastic strain C^-1 : (trial - sigma)
// points along the flow direction 3 s / (2 q) + eta_g / 3 I of the dilation angle; the
// deviator keeps its direction.
TEST(DruckerPrager, ConeReturnOntoTheSurfaceAlongTheDilationAngle) {
  for (const auto matching : {ConeMatching::kCompression, ConeMatching::kPlaneStrain}) {
    for (const double psi : {0.0, 10.0, 30.0}) {
      for (const double c : {0.0, 2e4}) {
        const ConstitutiveParams prm = dp_params(30.0, psi, c, matching);
        const DruckerPragerLaw law(prm);
        const double p0 = 1e5;
        const Mat3 trial = -p0 * Mat3::Identity() + 3.0 * law.eta() * p0 * unit_deviator();
        ASSERT_GT(law.yield_function(trial), 0.0);
        const Mat3 sigma = law.return_map(trial);
        EXPECT_LE(std::abs(law.yield_function(sigma)), 1e-10 * p0);
        // Flow direction.
        const Mat3 d_eps_p = compliance(1e7, 0.3, trial - sigma);
        const Mat3 n =
            1.5 * deviator(sigma) / von_mises(sigma) + law.eta_g() / 3.0 * Mat3::Identity();
        EXPECT_LE((d_eps_p / d_eps_p.norm() - n / n.norm()).norm(), 1e-10)
            << "psi " << psi << " c " << c;
        // Deviator direction kept, q reduced, p raised by K eta_g dlambda only.
        EXPECT_LE((deviator(sigma) / von_mises(sigma) - unit_deviator()).norm(), 1e-12);
        const double dlambda = (von_mises(trial) - von_mises(sigma)) / (3 * law.shear_modulus());
        EXPECT_GT(dlambda, 0.0);
        EXPECT_NEAR(pressure(sigma) - p0, law.bulk_modulus() * law.eta_g() * dlambda, 1e-10 * p0);
        if (psi == 0.0) {
          EXPECT_NEAR(pressure(sigma), p0, 1e-12 * p0);  // no volume change
        }
      }
    }
  }
}

// Tension beyond the apex: zero stress without cohesion, the isotropic tension c cot(phi)
// with it; f = 0 at the apex.
TEST(DruckerPrager, ApexReturnForTension) {
  const Mat3 tension = 1e4 * Mat3::Identity() + 2e3 * unit_deviator();
  const DruckerPragerLaw cohesionless(dp_params(30.0, 10.0));
  const Mat3 zero = cohesionless.return_map(tension);
  EXPECT_EQ(zero.norm(), 0.0);
  // Also through an update: a stress-free point stretched in every direction.
  EXPECT_EQ(cohesionless.update(Mat3::Zero(), diag(1.001, 1.002, 1.003)).norm(), 0.0);
  const double c = 3e3, t = 1.0 / std::tan(30.0 * kPi / 180.0);
  const DruckerPragerLaw cohesive(dp_params(30.0, 0.0, c));
  const Mat3 apex = cohesive.return_map(1e5 * Mat3::Identity() + 1e3 * unit_deviator());
  EXPECT_LE((apex - c * t * Mat3::Identity()).norm(), 1e-10 * c);
  EXPECT_LE(std::abs(cohesive.yield_function(apex)), 1e-10 * c);
}

// Drained triaxial compression, lateral stress held: q/p rises elastically (q = E eps_a
// while elastic) and reaches the compression-cone slope 6 sin(phi)/(3 - sin(phi)), i.e. the
// Mohr-Coulomb angle phi, and stays there.
TEST(DruckerPrager, DrainedTriaxialCompressionReachesTheMohrCoulombStrength) {
  const double phi = 27.5, p0 = 1e5;
  const DruckerPragerLaw law(dp_params(phi));
  const double s = std::sin(phi * kPi / 180.0);
  const double eta = 6 * s / (3 - s);
  Mat3 sigma = -p0 * Mat3::Identity();
  double ratio_max = 0.0, eps_a = 0.0;
  bool checked_elastic = false;
  for (int step = 0; step < 400; ++step) {
    sigma = lateral_controlled_step(law, sigma, -1e-4, -p0, false);
    eps_a += -std::log1p(-1e-4);
    const double q = -sigma(2, 2) + sigma(0, 0), ratio = q / pressure(sigma);
    ratio_max = std::max(ratio_max, ratio);
    if (!checked_elastic && step == 50) {  // elastic: q = E eps_a (Hencky strains)
      EXPECT_NEAR(q, 1e7 * eps_a, 1e-8 * q);
      checked_elastic = true;
    }
  }
  const double ratio = von_mises(sigma) / pressure(sigma);
  EXPECT_NEAR(ratio, eta, 1e-6 * eta);
  EXPECT_LE(ratio_max, eta * (1 + 1e-10));
  EXPECT_NEAR(mobilised_sin_phi(sigma), s, 1e-6 * s);
  EXPECT_NEAR(-sigma(0, 0), p0, 1e-8 * p0);
}

// Plane-strain compression (out-of-plane stretch 1, lateral stress held) with the
// plane_strain matching: at steady flow the in-plane Mohr-Coulomb angle equals phi, for a
// non-associated and an associated flow rule. The compression matching is stronger.
TEST(DruckerPrager, PlaneStrainMatchingGivesMohrCoulombInPlaneStrain) {
  const double phi = 30.0, p0 = 1e5, s = std::sin(phi * kPi / 180.0);
  for (const double psi : {0.0, 30.0}) {
    const DruckerPragerLaw law(dp_params(phi, psi, 0.0, ConeMatching::kPlaneStrain));
    Mat3 sigma = -p0 * Mat3::Identity();
    for (int step = 0; step < 3000; ++step) {
      sigma = lateral_controlled_step(law, sigma, -2e-4, -p0, true);
    }
    EXPECT_NEAR(mobilised_sin_phi(sigma), s, 1e-6 * s) << "psi " << psi;
  }
  const DruckerPragerLaw tc(dp_params(phi, 0.0, 0.0, ConeMatching::kCompression));
  Mat3 sigma = -p0 * Mat3::Identity();
  for (int step = 0; step < 2000; ++step) {
    sigma = lateral_controlled_step(tc, sigma, -1e-4, -p0, true);
  }
  EXPECT_GT(mobilised_sin_phi(sigma), s * 1.05);
}

// Rigid rotations rotate the stress exactly, inside and on the cone, and leave f unchanged.
TEST(DruckerPrager, PureRotationRotatesTheStress) {
  const DruckerPragerLaw law(dp_params(30.0, 5.0));
  const double p0 = 1e5;
  const Mat3 inside = -p0 * Mat3::Identity() + 0.5 * law.eta() * p0 * unit_deviator();
  const Mat3 on = law.return_map(-p0 * Mat3::Identity() + 3 * law.eta() * p0 * unit_deviator());
  for (const Mat3& sigma : {inside, on}) {
    // One large rotation.
    const Mat3 R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    const Mat3 rotated = law.update(sigma, R);
    EXPECT_LE((rotated - R * sigma * R.transpose()).norm(), 1e-12 * sigma.norm());
    EXPECT_NEAR(law.yield_function(rotated), law.yield_function(sigma), 1e-10 * p0);
    // Many small ones, half a turn in total.
    const Mat3 dR =
        Eigen::AngleAxisd(kPi / 200, Eigen::Vector3d(-1, 0.5, 2).normalized()).toRotationMatrix();
    Mat3 s = sigma, Rt = Mat3::Identity();
    for (int i = 0; i < 200; ++i) {
      s = law.update(s, dR);
      Rt = dR * Rt;
    }
    EXPECT_LE((s - Rt * sigma * Rt.transpose()).norm(), 1e-11 * sigma.norm());
    EXPECT_NEAR(law.yield_function(s), law.yield_function(sigma), 1e-9 * p0);
  }
}

// One-dimensional (oedometric) compression from zero stress: elastic, sigma_h / sigma_v =
// K0 = nu / (1 - nu) and sigma_v = M ln(stretch) with M = K + 4G/3.
// The disconnected state (disconnection_volume_ratio J_c, Dunatunga & Kamrin 2015). One point
// under compression, stretched isotropically past J_c, compacted a little (still beyond J_c),
// then back below it. Beyond J_c: zero stress and stiffness, state no contacts. Back below
// J_c: the stress restarts from zero with that step's increment (it does not return to the
// stress held before the point disconnected), and the modulus is back. Without J_c the same
// path never disconnects. A checkpoint carries the volume ratios.
TEST(DruckerPrager, DisconnectsBeyondTheVolumeRatioAndReconnectsFromZeroStress) {
  ConstitutiveParams params = dp_params(30.0);
  edit_drucker_prager_params(params).disconnection_volume_ratio = 1.5;
  const DruckerPragerLaw law(params);
  const auto no_contacts = PointState::kNoContacts;
  const auto ok = PointState::kOk;
  const Mat3 sigma0 = diag(-8e3, -8e3, -1e4);
  // J after each increment: 1.158, 1.626 (disconnects), 1.578 (still), 1.150 (reconnects),
  // 1.147.
  const std::vector<Mat3> path = {1.05 * Mat3::Identity(), 1.12 * Mat3::Identity(),
                                  0.99 * Mat3::Identity(), 0.9 * Mat3::Identity(),
                                  0.999 * Mat3::Identity()};
  auto dp = make_drucker_prager(params);
  auto plain = make_drucker_prager(dp_params(30.0));
  std::vector<PointResponse> out, out_plain;
  dp->initialise({sigma0}, out);
  plain->initialise({sigma0}, out_plain);
  double J = 1.0;
  Mat3 expected = sigma0;
  bool was_disconnected = false, reconnected = false;
  std::vector<double> saved;
  for (std::size_t k = 0; k < path.size(); ++k) {
    dp->update({path[k]}, 1e-3, static_cast<std::int64_t>(k + 1), 0.0, out);
    plain->update({path[k]}, 1e-3, static_cast<std::int64_t>(k + 1), 0.0, out_plain);
    J *= path[k].determinant();
    EXPECT_EQ(out_plain[0].state, ok);
    if (J > 1.5) {
      EXPECT_EQ(out[0].state, no_contacts) << "J = " << J;
      EXPECT_EQ(out[0].stress, Mat3::Zero()) << "J = " << J;
      EXPECT_EQ(out[0].stiffness, 0.0);
      expected = Mat3::Zero();
      was_disconnected = true;
      saved = dp->save_state();
    } else {
      if (was_disconnected) reconnected = true;
      expected = law.update(expected, path[k]);
      EXPECT_EQ(out[0].state, ok) << "J = " << J;
      EXPECT_LT((out[0].stress - expected).norm(), 1e-9 * (1.0 + expected.norm())) << "J = " << J;
      EXPECT_EQ(out[0].stiffness, law.constrained_modulus());
    }
  }
  ASSERT_TRUE(was_disconnected && reconnected) << "the path must cross J_c both ways";
  // Both models lost their stress to the tension cutoff while stretched, but the plain one
  // carries pressure again from the first compaction (J 1.626 -> 1.578, ~K * 3 %); the
  // disconnected point only from J_c down.
  EXPECT_GT(-out_plain[0].stress.trace() / 3.0, -out[0].stress.trace() / 3.0 + 1e5);
  // A provider resumed from the checkpoint taken while disconnected (stress zero) follows the
  // same path back: J travels in save_state().
  ASSERT_EQ(saved.size(), 1u);
  auto resumed = make_drucker_prager(params);
  std::vector<PointResponse> out_resumed;
  resumed->resume({Mat3::Zero()}, out_resumed);
  resumed->load_state(saved);
  resumed->update({0.9 * Mat3::Identity()}, 1e-3, 4, 0.0, out_resumed);
  EXPECT_EQ(out_resumed[0].state, ok);
  EXPECT_EQ(out_resumed[0].stress, law.update(Mat3::Zero(), 0.9 * Mat3::Identity()));
  EXPECT_THROW(resumed->load_state({1.0, 1.0}), std::runtime_error);
  // Ratios at or below 1 would disconnect points that did not dilate.
  edit_drucker_prager_params(params).disconnection_volume_ratio = 1.0;
  EXPECT_THROW(make_drucker_prager(params), std::invalid_argument);
}

TEST(DruckerPrager, OedometricLoadingGivesElasticK0) {
  for (const double nu : {0.2, 0.3}) {
    ConstitutiveParams prm = dp_params(40.0);  // K0 = 0.25 lies inside the cone for phi > 35 deg
    prm.poisson_ratio = nu;
    const DruckerPragerLaw law(prm);
    Mat3 sigma = Mat3::Zero();
    double strain = 0.0;
    for (int i = 0; i < 100; ++i) {
      sigma = law.update(sigma, diag(1.0, 1.0, 1.0 - 1e-4));
      strain += std::log1p(-1e-4);
      EXPECT_LT(law.yield_function(sigma), 0.0);
    }
    EXPECT_NEAR(sigma(0, 0) / sigma(2, 2), nu / (1 - nu), 1e-12);
    EXPECT_NEAR(sigma(1, 1), sigma(0, 0), 1e-12 * std::abs(sigma(0, 0)));
    EXPECT_NEAR(sigma(2, 2), law.constrained_modulus() * strain, 1e-12 * std::abs(sigma(2, 2)));
  }
}

// ---- Solver level: a half pile (symmetry plane x = 0, slope angle beta = 30 deg, 0.29 m
// high, about 5 cells) on a rough base, plane strain (slip walls in y), starting stress-free
// under gravity, with a little local damping for the elastic ringing. A cohesionless slope
// stands if phi > beta. On this coarse grid the pile is stronger than the continuum (phi = 20
// deg still stands), so the two cases keep wide margins: phi = 45 deg must stay at rest,
// phi = 10 deg must flow.

namespace {

constexpr double kBeta = 30.0 * kPi / 180.0;

struct PileResult {
  double max_displacement = 0.0;  // [m]
  double toe_advance = 0.0;       // largest x of any point minus the initial one [m]
  double top_drop = 0.0;          // initial minus final highest z [m]
  double Ek_over_Ep0 = 0.0;       // at the end
  double E_strain = 0.0;
};

PileResult run_pile(double phi_deg) {
  const double h = 0.05, L = 0.5;
  Solver solver = SceneBuilder()
                      .name("pile")
                      .cell(h)
                      .domain(Vec3(1.0, h, 0.4))
                      .end_time(1.0)  // ~6 t* of the 0.29 m pile
                      .cfl(0.5)
                      .damping(0.1)
                      .wall(Face::kXMin, WallType::kSlip)  // symmetry plane
                      .wall(Face::kYMin, WallType::kSlip)  // y_min, y_max: plane strain
                      .wall(Face::kYMax, WallType::kSlip)
                      .base(WallType::kFixed)  // rough base
                      .with([&](Scene& s) { s.constitutive = dp_params(phi_deg); })
                      .moduli(2e6, 0.3)
                      .block("box", Vec3(0, 0, 0), Vec3(L, h, L * std::tan(kBeta)))
                      // Cut the box to the slope z <= tan(beta) (L - x).
                      .cut([&](const Vec3& x) { return x.z() <= std::tan(kBeta) * (L - x.x()); })
                      .solver();
  while (!solver.finished()) solver.step();
  PileResult res;
  const Particles& q = solver.particles();
  double x_max0 = 0.0, x_max = 0.0, z_max0 = 0.0, z_max = 0.0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    res.max_displacement = std::max(res.max_displacement, (q.x[i] - q.x0[i]).norm());
    x_max0 = std::max(x_max0, q.x0[i].x());
    x_max = std::max(x_max, q.x[i].x());
    z_max0 = std::max(z_max0, q.x0[i].z());
    z_max = std::max(z_max, q.x[i].z());
  }
  res.toe_advance = x_max - x_max0;
  res.top_drop = z_max0 - z_max;
  const Energies e = solver.energies();
  res.Ek_over_Ep0 = e.E_k / solver.initial_potential_energy();
  res.E_strain = e.E_strain;
  return res;
}

}  // namespace

TEST(DruckerPragerSolver, SlopeGentlerThanTheFrictionAngleStaysSteeperFlows) {
  const PileResult stable = run_pile(45.0);   // beta < phi
  const PileResult flowing = run_pile(10.0);  // beta > phi
  // Elastic settlement scale rho g H / M of the pile's height H.
  const double M = mpmdem::elastic::ElasticLaw{2e6, 0.3}.constrained_modulus();
  const double settle = 2000.0 * 9.81 * 0.5 * std::tan(kBeta) / M;
  std::printf(
      "phi 45: max displacement %.3e m, toe %.3e m, top drop %.3e m, Ek/Ep0 %.3e\n"
      "phi 10: max displacement %.3e m, toe %.3e m, top drop %.3e m, Ek/Ep0 %.3e\n"
      "elastic settlement scale %.3e m\n",
      stable.max_displacement, stable.toe_advance, stable.top_drop, stable.Ek_over_Ep0,
      flowing.max_displacement, flowing.toe_advance, flowing.top_drop, flowing.Ek_over_Ep0, settle);
  EXPECT_LT(stable.max_displacement, settle);  // elastic settlement only
  EXPECT_LT(stable.Ek_over_Ep0, 1e-8);         // at rest
  EXPECT_GT(stable.E_strain, 0.0);
  EXPECT_GT(flowing.toe_advance, 0.05);  // the toe moves out by more than a cell
  EXPECT_GT(flowing.top_drop, 0.05);     // and the top comes down by more than a cell
}

// ---- Config: the constitutive.drucker_prager keys, their defaults and the cross-key check.

namespace {

std::string scene_text(const std::string& dp_keys) {
  return "config_version: 1\n"
         "grid:\n"
         "  extent: [1, 1, 1]\n"
         "  cell_size: 0.1\n"
         "regions:\n"
         "  - min: [0, 0, 0]\n"
         "    max: [0.5, 0.5, 0.5]\n"
         "    density: 1000\n"
         "solver:\n"
         "  end_time: 0.1\n"
         "constitutive:\n"
         "  model: drucker_prager\n" +
         dp_keys;
}

std::string write_scene(const std::string& name, const std::string& text) {
  const std::string file = std::string(MPMDEM_BINARY_DIR) + "/test_drucker_prager_" + name;
  std::ofstream(file) << text;
  return file;
}

std::string load_error(const std::string& name, const std::string& text) {
  try {
    load_scene(write_scene(name, text));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// The registry's contract (model_registry.hpp): the model's own parameters live in
// ConstitutiveParams::own, which its load hook fills and its make hook reads; a copy changed
// with edit_drucker_prager_params leaves the original as it was.
TEST(DruckerPragerConfig, ParametersAreTheModelsOwn) {
  const Scene a = load_scene(write_scene("own.yaml", scene_text("  drucker_prager:\n"
                                                                "    youngs_modulus: 2e6\n"
                                                                "    poisson_ratio: 0.25\n"
                                                                "    friction_angle_deg: 22\n")));
  ASSERT_NE(dynamic_cast<const DruckerPragerParams*>(a.constitutive.own.get()), nullptr);
  Scene b = a;
  edit_drucker_prager_params(b.constitutive).friction_angle_deg = 35.0;
  EXPECT_EQ(drucker_prager_params(a.constitutive).friction_angle_deg, 22.0);
  EXPECT_EQ(drucker_prager_params(b.constitutive).friction_angle_deg, 35.0);
  ConstitutiveParams elastic;  // linear_elastic: no parameters of drucker_prager
  EXPECT_THROW(drucker_prager_params(elastic), std::invalid_argument);
  EXPECT_THROW(make_drucker_prager(elastic), std::invalid_argument);
}

TEST(DruckerPragerConfig, KeysDefaultsAndChecks) {
  const Scene a =
      load_scene(write_scene("defaults.yaml", scene_text("  drucker_prager:\n"
                                                         "    youngs_modulus: 2e6\n"
                                                         "    poisson_ratio: 0.25\n"
                                                         "    friction_angle_deg: 22\n")));
  EXPECT_EQ(a.constitutive.model, "drucker_prager");
  EXPECT_EQ(a.constitutive.youngs_modulus, 2e6);
  EXPECT_EQ(a.constitutive.poisson_ratio, 0.25);
  EXPECT_EQ(drucker_prager_params(a.constitutive).friction_angle_deg, 22.0);
  EXPECT_EQ(drucker_prager_params(a.constitutive).dilation_angle_deg, 0.0);
  EXPECT_EQ(drucker_prager_params(a.constitutive).cohesion, 0.0);
  EXPECT_EQ(drucker_prager_params(a.constitutive).matching, ConeMatching::kCompression);
  EXPECT_EQ(drucker_prager_params(a.constitutive).disconnection_volume_ratio, 0.0);
  const Scene b = load_scene(write_scene("given.yaml", scene_text("  drucker_prager:\n"
                                                                  "    youngs_modulus: 2e6\n"
                                                                  "    poisson_ratio: 0.25\n"
                                                                  "    friction_angle_deg: 30\n"
                                                                  "    dilation_angle_deg: 5\n"
                                                                  "    cohesion: 100\n"
                                                                  "    matching: plane_strain\n"
                                                                  "    disconnection_volume_ratio: "
                                                                  "1.5\n")));
  EXPECT_EQ(drucker_prager_params(b.constitutive).dilation_angle_deg, 5.0);
  EXPECT_EQ(drucker_prager_params(b.constitutive).cohesion, 100.0);
  EXPECT_EQ(drucker_prager_params(b.constitutive).matching, ConeMatching::kPlaneStrain);
  EXPECT_EQ(drucker_prager_params(b.constitutive).disconnection_volume_ratio, 1.5);
  const std::string jc = load_error("jc.yaml", scene_text("  drucker_prager:\n"
                                                          "    youngs_modulus: 2e6\n"
                                                          "    poisson_ratio: 0.25\n"
                                                          "    friction_angle_deg: 20\n"
                                                          "    disconnection_volume_ratio: 0.8\n"));
  EXPECT_NE(jc.find("constitutive.drucker_prager.disconnection_volume_ratio 0.8 would disconnect"),
            std::string::npos)
      << jc;
  EXPECT_NE(jc.find("test_drucker_prager_jc.yaml"), std::string::npos) << jc;
  const std::string psi = load_error("psi.yaml", scene_text("  drucker_prager:\n"
                                                            "    youngs_modulus: 2e6\n"
                                                            "    poisson_ratio: 0.25\n"
                                                            "    friction_angle_deg: 20\n"
                                                            "    dilation_angle_deg: 25\n"));
  EXPECT_NE(psi.find("constitutive.drucker_prager.dilation_angle_deg 25 is larger than "
                     "friction_angle_deg 20"),
            std::string::npos)
      << psi;
  const std::string missing = load_error("missing.yaml", scene_text(""));
  EXPECT_NE(missing.find("constitutive.drucker_prager"), std::string::npos) << missing;
  const std::string phi = load_error("phi.yaml", scene_text("  drucker_prager:\n"
                                                            "    youngs_modulus: 2e6\n"
                                                            "    poisson_ratio: 0.25\n"
                                                            "    friction_angle_deg: 90\n"));
  EXPECT_NE(phi.find("friction_angle_deg"), std::string::npos) << phi;
}

// The objective linear-elastic law (mpmdem/laws/elastic_law.hpp) and the linear_elastic
// provider built on it.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "constitutive/linear_elastic.hpp"
#include "mpmdem/laws/elastic_law.hpp"

using mpmdem::elastic::ElasticLaw;
using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

namespace {

const ElasticLaw kLaw{1.0e7, 0.3};

Mat3 rotation(double angle, Vec3 axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

Mat3 some_stress() {
  Mat3 s;
  s << -2.0e4, 3.1e3, -1.2e3,  //
      3.1e3, -1.5e4, 0.7e3,    //
      -1.2e3, 0.7e3, -3.3e4;
  return s;
}

}  // namespace

TEST(ElasticLaw, Moduli) {
  const double E = 1e7, nu = 0.3;
  EXPECT_NEAR(kLaw.constrained_modulus(), E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)), 1e-6);
  EXPECT_NEAR(kLaw.constrained_modulus(), 1.3461538e7, 1.0);
  EXPECT_NEAR(kLaw.lame_lambda() + 2 * kLaw.shear_modulus(), kLaw.constrained_modulus(), 1e-6);
}

TEST(ElasticLaw, UniaxialStrainGivesMAndLambda) {
  for (double eps : {1e-6, -1e-4, 2e-3}) {
    Mat3 dF = Mat3::Identity();
    dF(2, 2) += eps;
    const Mat3 s = kLaw.update(Mat3::Zero(), dF);
    const double hencky = std::log1p(dF(2, 2) - 1.0);  // of the stretch actually stored
    // Exactly the Hencky strain through C (series path for 1e-6 and -1e-4, spectral for 2e-3)
    EXPECT_NEAR(s(2, 2), kLaw.constrained_modulus() * hencky, 1e-11 * std::abs(s(2, 2)));
    EXPECT_NEAR(s(0, 0), kLaw.lame_lambda() * hencky, 1e-11 * std::abs(s(0, 0)));
    EXPECT_NEAR(s(1, 1), s(0, 0), 1e-12 * std::abs(s(0, 0)));
    EXPECT_LT(std::abs(s(0, 1)) + std::abs(s(0, 2)) + std::abs(s(1, 2)), 1e-12 * std::abs(s(2, 2)));
    // ... which is M eps to first order.
    EXPECT_NEAR(s(2, 2), kLaw.constrained_modulus() * eps, 0.6 * std::abs(eps) * std::abs(s(2, 2)));
  }
}

TEST(ElasticLaw, SimpleShearGivesMuGamma) {
  const double gamma = 1e-6;
  Mat3 dF = Mat3::Identity();
  dF(0, 1) = gamma;
  const Mat3 s = kLaw.update(Mat3::Zero(), dF);
  EXPECT_NEAR(s(0, 1), kLaw.shear_modulus() * gamma, 1e-6 * kLaw.shear_modulus() * gamma);
  EXPECT_NEAR(s(1, 0), s(0, 1), 1e-15 * kLaw.E);
  EXPECT_LT(std::abs(s.trace()), 1e-5 * std::abs(s(0, 1)));
}

TEST(ElasticLaw, PureRotationRotatesTheStressExactly) {
  const Mat3 sigma = some_stress();
  for (double angle : {1e-7, 0.3, 1.7, 3.0}) {
    const Mat3 R = rotation(angle, Vec3(0.3, -1.0, 0.6));
    const Mat3 s = kLaw.update(sigma, R);
    EXPECT_LT((s - R * sigma * R.transpose()).norm(), 1e-12 * sigma.norm()) << angle;
  }
}

TEST(ElasticLaw, ObjectiveUnderSuperposedRotation) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Mat3 sigma = some_stress();
  for (int trial = 0; trial < 50; ++trial) {
    Mat3 dF = Mat3::Identity();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) dF(i, j) += 1e-3 * u(rng);
    const Mat3 Q = rotation(2.0 * u(rng), Vec3(u(rng), u(rng), u(rng)));
    const Mat3 s = kLaw.update(sigma, dF);
    const Mat3 s_rotated = kLaw.update(sigma, Q * dF);
    EXPECT_LT((s_rotated - Q * s * Q.transpose()).norm(), 1e-12 * s.norm());
  }
}

TEST(ElasticLaw, CoaxialIncrementsAddUpAsHenckyStrains) {
  // Two coaxial stretches: log strains add exactly, so the stress is C : log(l1 l2).
  const Mat3 R = rotation(0.8, Vec3(1, 2, 3));
  const Vec3 l1(1.001, 0.999, 1.0005), l2(0.998, 1.002, 1.001);
  const Mat3 dF1 = R * l1.asDiagonal() * R.transpose();
  const Mat3 dF2 = R * l2.asDiagonal() * R.transpose();
  const Mat3 s = kLaw.update(kLaw.update(Mat3::Zero(), dF1), dF2);
  const Vec3 log_l(std::log(l1[0] * l2[0]), std::log(l1[1] * l2[1]), std::log(l1[2] * l2[2]));
  const Mat3 expected = kLaw.stress_increment(R * log_l.asDiagonal() * R.transpose());
  EXPECT_LT((s - expected).norm(), 1e-10 * expected.norm());
}

TEST(ElasticLaw, StrainEnergyDensity) {
  // Uniaxial stress: w = s^2 / (2E).
  Mat3 s = Mat3::Zero();
  s(2, 2) = -2.0e4;
  EXPECT_NEAR(kLaw.strain_energy_density(s), 2.0e4 * 2.0e4 / (2 * kLaw.E), 1e-12);
  // Uniaxial strain: w = 1/2 M eps^2.
  const double eps = 1e-4;
  Mat3 e = Mat3::Zero();
  e(2, 2) = eps;
  const double w = kLaw.strain_energy_density(kLaw.stress_increment(e));
  EXPECT_NEAR(w, 0.5 * kLaw.constrained_modulus() * eps * eps, 1e-9 * w);
}

TEST(LinearElasticProvider, AppliesTheLawPerPointAndReportsM) {
  mpmdem::mpm::ConstitutiveParams params;
  params.youngs_modulus = kLaw.E;
  params.poisson_ratio = kLaw.nu;
  auto provider = mpmdem::mpm::make_linear_elastic(params);
  EXPECT_EQ(provider->name(), "linear_elastic");
  std::vector<Mat3> s0(5, some_stress());
  s0[2].setZero();
  std::vector<mpmdem::mpm::PointResponse> out;
  provider->initialise(s0, out);
  ASSERT_EQ(out.size(), 5u);
  EXPECT_EQ(out[0].stress, s0[0]);
  EXPECT_EQ(out[4].stiffness, kLaw.constrained_modulus());
  std::vector<Mat3> dF(5, Mat3::Identity());
  dF[1] = rotation(0.4, Vec3(0, 0, 1));
  dF[2](0, 0) = 1.0 - 1e-4;
  provider->update(dF, 1e-4, 1, 1e-4, out);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(out[i].stress, kLaw.update(s0[i], dF[i])) << i;  // bit-identical to the law
    EXPECT_EQ(out[i].state, mpmdem::mpm::PointState::kOk);
  }
  EXPECT_THROW(provider->update(std::vector<Mat3>(4, Mat3::Identity()), 1e-4, 2, 2e-4, out),
               std::logic_error);
  params.poisson_ratio = 0.5;
  EXPECT_THROW(mpmdem::mpm::make_linear_elastic(params), std::invalid_argument);
}

TEST(ElasticLaw, SeriesAndSpectralPathsAgreeAtTheSwitch) {
  // Just below and above |E| = kSeriesLimit the two evaluations of log(I + 2E)/2 and
  // (I + 2E)^(-1/2) must agree (no jump in the stress when a step crosses the limit).
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    Mat3 A;
    for (int i = 0; i < 9; ++i) A.data()[i] = u(rng);
    Mat3 E = 0.5 * (A + A.transpose());
    E *= 0.999 * ElasticLaw::kSeriesLimit / E.norm();
    Mat3 eps_s, inv_s, eps_e, inv_e;
    ElasticLaw::series(E, eps_s, inv_s);
    ElasticLaw::spectral(E, eps_e, inv_e);
    EXPECT_LT((eps_s - eps_e).norm(), 1e-11 * eps_e.norm());
    EXPECT_LT((inv_s - inv_e).norm(), 1e-13);
  }
}

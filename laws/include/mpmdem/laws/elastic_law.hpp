// Isotropic linear elasticity with an objective (rotation-exact) incremental update.
//
// Header-only and Eigen-only on purpose: mpm_app's local `linear_elastic` provider and
// dem_app's elastic stub backend both include this file (target mpmdem_laws), so they
// return bit-identical stresses for identical dF. Keep it deterministic: no threads, no
// randomness, the same operations in the same order for every caller.
//
// Update for one increment dF (the incremental deformation gradient of a step):
//   polar decomposition dF = dR dU with dU = sqrt(dF^T dF) = sqrt(I + 2E), where
//   E = (dF^T dF - I)/2 is the Green-Lagrange increment (computed as (H + H^T + H^T H)/2,
//   H = dF - I, which keeps small strains accurate);
//   Hencky strain increment  d_eps = log(dU) = log(I + 2E)/2;
//   both functions of E by power series for small increments (|E| <= 1e-3: every ordinary
//   step, several times cheaper and more accurate near E = 0 than a closed-form eigen
//   solver), else by the eigen-decomposition of E (SelfAdjointEigenSolver::computeDirect);
//   sigma_new = dR (sigma + lambda tr(d_eps) I + 2 mu d_eps) dR^T.
// A rigid rotation (dF = R) gives d_eps = 0 and dR = R: the stress is rotated exactly.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace mpmdem::elastic {

struct ElasticLaw {
  double E;   // Young's modulus [Pa]
  double nu;  // Poisson's ratio [-]

  double lame_lambda() const { return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); }
  double shear_modulus() const { return E / (2.0 * (1.0 + nu)); }
  // Constrained (P-wave) modulus M = lambda + 2 mu = E (1 - nu) / ((1 + nu)(1 - 2 nu)).
  double constrained_modulus() const { return E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)); }

  // Stress change of a small strain: C : eps = lambda tr(eps) I + 2 mu eps.
  Eigen::Matrix3d stress_increment(const Eigen::Matrix3d& eps) const {
    return lame_lambda() * eps.trace() * Eigen::Matrix3d::Identity() + 2.0 * shear_modulus() * eps;
  }

  // Objective update of the Cauchy stress (tension positive) over one increment dF.
  Eigen::Matrix3d update(const Eigen::Matrix3d& sigma, const Eigen::Matrix3d& dF) const {
    const Eigen::Matrix3d H = dF - Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d E_gl = 0.5 * (H + H.transpose() + H.transpose() * H);
    Eigen::Matrix3d d_eps, dU_inv;
    if (E_gl.squaredNorm() <= kSeriesLimit * kSeriesLimit) {
      series(E_gl, d_eps, dU_inv);
    } else {
      spectral(E_gl, d_eps, dU_inv);
    }
    const Eigen::Matrix3d dR = dF * dU_inv;
    const Eigen::Matrix3d s = dR * (sigma + stress_increment(d_eps)) * dR.transpose();
    return 0.5 * (s + s.transpose());
  }

  // |E| up to which the power series are used.
  static constexpr double kSeriesLimit = 1e-3;

  // Small increments (every ordinary step): power series in E to fourth order,
  //   d_eps  = log(I + 2E)/2    = E - E^2 + 4/3 E^3 - 2 E^4       (next: +16/5 E^5)
  //   dU^-1  = (I + 2E)^(-1/2)  = I - E + 3/2 E^2 - 5/2 E^3 + 35/8 E^4  (next: -63/8 E^5)
  // Truncation: < 8 |E|^5, i.e. relative to d_eps < 8 |E|^4 (< 1e-11 at the limit, 1e-19 at
  // a typical step's |E| ~ 1e-5): exact to round-off where it matters, and a rigid rotation
  // (E = 0 up to round-off) gives d_eps = 0, dU^-1 = I.
  static void series(const Eigen::Matrix3d& E, Eigen::Matrix3d& d_eps, Eigen::Matrix3d& dU_inv) {
    const Eigen::Matrix3d E2 = E * E;
    const Eigen::Matrix3d E3 = E2 * E;
    const Eigen::Matrix3d E4 = E2 * E2;
    d_eps = E - E2 + (4.0 / 3.0) * E3 - 2.0 * E4;
    d_eps = 0.5 * (d_eps + d_eps.transpose());
    dU_inv = Eigen::Matrix3d::Identity() - E + 1.5 * E2 - 2.5 * E3 + (35.0 / 8.0) * E4;
  }

  // Large increments: eigen-decomposition E = Q diag(e) Q^T,
  //   d_eps = Q diag(log(1 + 2e)/2) Q^T,  dU^-1 = Q diag(1/sqrt(1 + 2e)) Q^T.
  static void spectral(const Eigen::Matrix3d& E, Eigen::Matrix3d& d_eps, Eigen::Matrix3d& dU_inv) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(E);
    const Eigen::Matrix3d& Q = eig.eigenvectors();
    const Eigen::Vector3d& e = eig.eigenvalues();
    Eigen::Vector3d log_stretch, inv_stretch;
    for (int a = 0; a < 3; ++a) {
      log_stretch[a] = 0.5 * std::log1p(2.0 * e[a]);       // log of the principal stretch
      inv_stretch[a] = 1.0 / std::sqrt(1.0 + 2.0 * e[a]);  // 1 / principal stretch
    }
    d_eps = Q * log_stretch.asDiagonal() * Q.transpose();
    dU_inv = Q * inv_stretch.asDiagonal() * Q.transpose();
  }

  // Complementary strain energy density 1/2 sigma : C^-1 : sigma
  //   = ((1 + nu) sigma:sigma - nu tr(sigma)^2) / (2 E)   [J/m^3].
  double strain_energy_density(const Eigen::Matrix3d& sigma) const {
    const double tr = sigma.trace();
    return ((1.0 + nu) * sigma.squaredNorm() - nu * tr * tr) / (2.0 * E);
  }
};

}  // namespace mpmdem::elastic

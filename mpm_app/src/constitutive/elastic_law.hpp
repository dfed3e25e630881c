// Isotropic linear elasticity with an objective (rotation-exact) incremental update.
//
// Header-only and Eigen-only on purpose: dem_app's elastic stub server includes this same
// file (target mpm_elastic_law), so the local `linear_elastic` provider and the remote stub
// return bit-identical stresses for identical dF. Keep it deterministic: no threads, no
// randomness, the same operations in the same order for every caller.
//
// Update for one increment dF (the incremental deformation gradient of a step):
//   polar decomposition dF = dR dU with dU = sqrt(dF^T dF), computed from the eigen-
//   decomposition of the Green-Lagrange increment E = (dF^T dF - I)/2 = Q diag(e) Q^T
//   (H = dF - I, E = (H + H^T + H^T H)/2 keeps small strains accurate);
//   Hencky strain increment  d_eps = log(dU) = Q diag(log(1 + 2 e)/2) Q^T;
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
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(E_gl);
    const Eigen::Matrix3d& Q = eig.eigenvectors();
    const Eigen::Vector3d& e = eig.eigenvalues();
    Eigen::Vector3d log_stretch, inv_stretch;
    for (int a = 0; a < 3; ++a) {
      log_stretch[a] = 0.5 * std::log1p(2.0 * e[a]);       // log of the principal stretch
      inv_stretch[a] = 1.0 / std::sqrt(1.0 + 2.0 * e[a]);  // 1 / principal stretch
    }
    const Eigen::Matrix3d d_eps = Q * log_stretch.asDiagonal() * Q.transpose();
    const Eigen::Matrix3d dU_inv = Q * inv_stretch.asDiagonal() * Q.transpose();
    const Eigen::Matrix3d dR = dF * dU_inv;
    const Eigen::Matrix3d s = dR * (sigma + stress_increment(d_eps)) * dR.transpose();
    return 0.5 * (s + s.transpose());
  }

  // Complementary strain energy density 1/2 sigma : C^-1 : sigma
  //   = ((1 + nu) sigma:sigma - nu tr(sigma)^2) / (2 E)   [J/m^3].
  double strain_energy_density(const Eigen::Matrix3d& sigma) const {
    const double tr = sigma.trace();
    return ((1.0 + nu) * sigma.squaredNorm() - nu * tr * tr) / (2.0 * E);
  }
};

}  // namespace mpmdem::elastic

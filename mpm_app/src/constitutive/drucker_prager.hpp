// The `drucker_prager` provider: local, in-process elastic-perfectly plastic Drucker-Prager
// model fitted to Mohr-Coulomb, the phenomenological (continuum) counterpart of the
// multiscale model. It owns one Cauchy stress per point.
//
// Notation: stress tension positive; p = -tr(sigma)/3 (pressure, compression positive),
// s = sigma + p I, q = sqrt(3/2 s:s); K bulk and G shear modulus from E and nu.
//   yield      f = q - eta p - xi c            (a cone in principal stress space)
//   potential  g = q - eta_g p                 (eta_g from the dilation angle psi)
// Flow n = dg/dsigma = 3 s / (2 q) + eta_g / 3 I: a plastic increment dlambda n changes the
// volume by eta_g dlambda (dilation for psi > 0) and, for psi = 0, keeps it.
//
// Fit to Mohr-Coulomb (phi, psi, c), selected by `matching`:
//   compression  (default) the cone passes through the compression corners of the
//                Mohr-Coulomb pyramid: the two models agree in triaxial compression,
//                q / p = eta = 6 sin(phi) / (3 - sin(phi)),  xi = 6 cos(phi) / (3 - sin(phi)),
//                eta_g = 6 sin(psi) / (3 - sin(psi)). Stronger than Mohr-Coulomb everywhere
//                else (in triaxial extension by (3 + sin phi)/(3 - sin phi)).
//   plane_strain the two models give the same limit load in plane strain (out-of-plane
//                plastic strain zero with the potential above; derivation in
//                docs/configuration.md):
//                eta = 3 sin(phi) sqrt(3 + sin^2 psi) / (3 + sin(phi) sin(psi)),
//                eta_g = 3 sin(psi) / sqrt(3 + sin^2 psi) (the same formula with phi = psi),
//                e.g. eta = sqrt(3) sin(phi) for psi = 0.
//   In both xi = eta cot(phi): the apex is Mohr-Coulomb's, at p = -c cot(phi). That apex is
//   the tension cutoff: a cohesionless material (c = 0) carries no tension at all.
//
// Update for one increment dF: the objective update of elastic_law.hpp with a return
// mapping inserted before the rotation. With dF = dR dU and the Hencky increment
// d_eps = log(dU),
//   sigma_trial = sigma + lambda tr(d_eps) I + 2 mu d_eps,
//   sigma_new   = dR return_map(sigma_trial) dR^T.
// The return map is isotropic, so it commutes with the rotation: a rigid rotation rotates
// the stress exactly and leaves f unchanged, and the small-strain return below is applied to
// a co-rotated stress (exact for large rotations; the strain increment of a step is small).
//
// Return mapping, closed form (perfect plasticity: the cone does not move):
//   f_trial <= 0: elastic, sigma = sigma_trial;
//   cone:  dlambda = f_trial / (3 G + eta eta_g K),
//          q = q_trial - 3 G dlambda,  p = p_trial + K eta_g dlambda,  s = s_trial q / q_trial,
//          valid while q >= 0;
//   apex:  otherwise sigma = -p_apex I with p_apex = -c cot(phi) (0 for c = 0).
// The result satisfies f = 0 to round-off. Below yield the stress equals linear_elastic's
// (same kinematics and moduli; bit-identical in the GCC Release build; tested to 1e-12).
//
// mu(I) (optional, `mu_i`; Jop, Forterre & Pouliquen 2006, in the elasto-plastic form of
// Dunatunga & Kamrin 2015): the cone's slope depends on the inertial number of the plastic
// shear rate,
//   eta(I) = eta_s + (eta_2 - eta_s) I / (I_0 + I),   I = gamma_dot_p d / sqrt(p / rho_s),
// eta_s and eta_2 the slopes the matching gives for phi and phi_2 (for plane_strain and
// psi = 0, sqrt(J2) / p = sin(phi): the mu of Jop et al. is sin(phi) here), and
// gamma_dot_p = sqrt(2 de_p : de_p) / dt = sqrt(3) dlambda / dt the plastic shear rate
// (the engineering shear rate gamma_dot of a simple shear that is all plastic). The apex
// stays at -c cot(phi): f = q - eta(I) (p - p_apex). The return solves the scalar equation
//   q_trial - 3 G dlambda = eta(I(dlambda, p)) (p_trial + K eta_g dlambda - p_apex)
// for dlambda, bracketed between 0 (f_trial > 0) and the rate-independent dlambda (where
// the right side is the larger, eta >= eta_s), by the Illinois method to round-off. As
// dt -> infinity at a given strain increment, I -> 0 and the rate-independent law returns.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <memory>

#include "constitutive/provider.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

// How the cone is fitted to Mohr-Coulomb (the file comment).
enum class ConeMatching { kCompression, kPlaneStrain };

// drucker_prager's own parameters, beyond the elastic moduli of ConstitutiveParams: its
// ConstitutiveParams::own, read from constitutive.drucker_prager (drucker_prager_model.cpp).
struct DruckerPragerParams final : ModelParams {
  double friction_angle_deg = 30.0;  // Mohr-Coulomb friction angle phi [deg]
  double dilation_angle_deg = 0.0;   // psi, 0 <= psi <= phi [deg]
  double cohesion = 0.0;             // Mohr-Coulomb cohesion c [Pa]
  ConeMatching matching = ConeMatching::kCompression;
  // J_c: a point whose volume exceeds J_c times its initial volume is disconnected (no
  // stress, no stiffness) until compacted below it again; 0: never.
  double disconnection_volume_ratio = 0.0;
  // mu(I) (constitutive.drucker_prager.mu_i; the file comment): the cone's slope grows from
  // that of friction_angle_deg to that of mu_i_friction_angle_2_deg with the inertial number.
  // mu_i_friction_angle_2_deg = 0: off.
  double mu_i_friction_angle_2_deg = 0.0;
  double mu_i_inertial_number_0 = 0.279;
  double mu_i_grain_diameter = 0.0;  // d [m]
  double mu_i_grain_density = 0.0;   // rho_s [kg/m3]
};

// The drucker_prager parameters in params.own; std::invalid_argument if it holds none.
const DruckerPragerParams& drucker_prager_params(const ConstitutiveParams& params);
// A copy of them (default ones if params.own is empty) put into params.own for the caller to
// change; other copies of params keep theirs. std::invalid_argument if params.own holds
// another model's parameters.
DruckerPragerParams& edit_drucker_prager_params(ConstitutiveParams& params);

class DruckerPragerLaw {
 public:
  // E and nu from params, the rest from params.own (DruckerPragerParams). Throws
  // std::invalid_argument unless E > 0, -1 < nu < 0.5, 0 < phi < 90 deg, 0 <= psi <= phi
  // and c >= 0, and with mu(I) unless phi < phi_2 < 90 deg, I_0 > 0, d > 0 and rho_s > 0.
  explicit DruckerPragerLaw(const ConstitutiveParams& params);

  double bulk_modulus() const { return K_; }
  double shear_modulus() const { return G_; }
  // K + 4 G / 3, the stiffness returned for the CFL step.
  double constrained_modulus() const { return K_ + 4.0 * G_ / 3.0; }
  double eta() const { return eta_; }
  double eta_g() const { return eta_g_; }
  double xi() const { return xi_; }
  // Pressure of the apex, -c cot(phi) [Pa].
  double apex_pressure() const { return p_apex_; }

  // f(sigma) = q - eta p - xi c [Pa]; <= 0 on or inside the cone.
  double yield_function(const Mat3& sigma) const;
  // True when mu(I) is on (DruckerPragerParams::mu_i_friction_angle_2_deg > 0).
  bool rate_dependent() const { return mu_i_; }
  // eta(I), the cone's slope at inertial number I (eta_s without mu(I)).
  double slope(double inertial_number) const;
  // I = sqrt(3) dlambda / dt * d / sqrt(p / rho_s); infinite for p <= 0.
  double inertial_number(double dlambda, double p, double dt) const;
  // Return of a trial stress onto the cone or its apex (identity if inside) for a step of
  // dt: closed form without mu(I) or for dt = infinity, else the scalar root above.
  Mat3 return_map(const Mat3& sigma_trial,
                  double dt = std::numeric_limits<double>::infinity()) const;
  // Objective update over one increment dF taken in dt (see the file comment).
  Mat3 update(const Mat3& sigma, const Mat3& dF,
              double dt = std::numeric_limits<double>::infinity()) const;
  // Elastic strain energy density 1/2 sigma : C^-1 : sigma [J/m^3] (for perfect plasticity
  // the elastic strain is C^-1 : sigma).
  double strain_energy_density(const Mat3& sigma) const;

 private:
  DruckerPragerLaw(const ConstitutiveParams& params, const DruckerPragerParams& own);

  double E_, nu_, K_, G_, lambda_;
  double eta_, eta_g_, xi_, c_, p_apex_;
  bool mu_i_ = false;
  double eta_2_ = 0.0, i_0_ = 0.0, d_ = 0.0, rho_s_ = 0.0;
};

// Reads youngs_modulus and poisson_ratio of params, and friction_angle_deg, dilation_angle_deg,
// cohesion, matching, the mu_i_* parameters and disconnection_volume_ratio (the disconnected
// state, drucker_prager.cpp) of its DruckerPragerParams. Throws std::invalid_argument for a
// ratio that is neither 0 nor > 1.
std::unique_ptr<ConstitutiveProvider> make_drucker_prager(const ConstitutiveParams& params);

}  // namespace mpmdem::mpm

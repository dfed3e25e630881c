#include "constitutive/drucker_prager.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "mpmdem/laws/elastic_law.hpp"
#include "parallel.hpp"

namespace mpmdem::mpm {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Compression-cone slope 6 sin(a) / (3 - sin(a)).
double compression_slope(double sin_a) {
  return 6.0 * sin_a / (3.0 - sin_a);
}

// The cone's slope eta for friction angle phi under the matching (file comment of the header);
// with phi = psi it is the potential's slope eta_g.
double cone_slope(ConeMatching matching, double sin_phi, double sin_psi) {
  if (matching == ConeMatching::kCompression) return compression_slope(sin_phi);
  return 3.0 * sin_phi * std::sqrt(3.0 + sin_psi * sin_psi) / (3.0 + sin_phi * sin_psi);
}

}  // namespace

const DruckerPragerParams& drucker_prager_params(const ConstitutiveParams& params) {
  if (const auto* own = dynamic_cast<const DruckerPragerParams*>(params.own.get())) return *own;
  throw std::invalid_argument("constitutive parameters of model '" + params.model +
                              "' hold no drucker_prager parameters (ConstitutiveParams::own)");
}

DruckerPragerParams& edit_drucker_prager_params(ConstitutiveParams& params) {
  auto own = params.own ? std::make_shared<DruckerPragerParams>(drucker_prager_params(params))
                        : std::make_shared<DruckerPragerParams>();
  params.own = own;
  return *own;
}

DruckerPragerLaw::DruckerPragerLaw(const ConstitutiveParams& constitutive)
    : DruckerPragerLaw(constitutive, drucker_prager_params(constitutive)) {}

DruckerPragerLaw::DruckerPragerLaw(const ConstitutiveParams& constitutive,
                                   const DruckerPragerParams& params)
    : E_(constitutive.youngs_modulus), nu_(constitutive.poisson_ratio), c_(params.cohesion) {
  const double phi_deg = params.friction_angle_deg, psi_deg = params.dilation_angle_deg;
  if (!(E_ > 0.0) || !(nu_ > -1.0 && nu_ < 0.5) || !(phi_deg > 0.0 && phi_deg < 90.0) ||
      !(psi_deg >= 0.0 && psi_deg <= phi_deg) || !(c_ >= 0.0)) {
    throw std::invalid_argument(
        "drucker_prager needs youngs_modulus > 0, -1 < poisson_ratio < 0.5, 0 < "
        "friction_angle_deg < 90, 0 <= dilation_angle_deg <= friction_angle_deg and cohesion "
        ">= 0, got E=" +
        std::to_string(E_) + ", nu=" + std::to_string(nu_) + ", phi=" + std::to_string(phi_deg) +
        ", psi=" + std::to_string(psi_deg) + ", c=" + std::to_string(c_));
  }
  const elastic::ElasticLaw law{E_, nu_};
  G_ = law.shear_modulus();
  lambda_ = law.lame_lambda();
  K_ = lambda_ + 2.0 * G_ / 3.0;
  const double sin_phi = std::sin(phi_deg * kPi / 180.0);
  const double sin_psi = std::sin(psi_deg * kPi / 180.0);
  const double tan_phi = std::tan(phi_deg * kPi / 180.0);
  eta_ = cone_slope(params.matching, sin_phi, sin_psi);
  eta_g_ = cone_slope(params.matching, sin_psi, sin_psi);
  xi_ = eta_ / tan_phi;
  p_apex_ = -c_ / tan_phi;
  const double phi_2_deg = params.mu_i_friction_angle_2_deg;
  if (phi_2_deg != 0.0) {
    if (!(phi_2_deg > phi_deg && phi_2_deg < 90.0) || !(params.mu_i_inertial_number_0 > 0.0) ||
        !(params.mu_i_grain_diameter > 0.0) || !(params.mu_i_grain_density > 0.0)) {
      throw std::invalid_argument(
          "drucker_prager mu(I) needs friction_angle_deg < friction_angle_2_deg < 90, "
          "inertial_number_0 > 0, grain_diameter > 0 and grain_density > 0, got phi=" +
          std::to_string(phi_deg) + ", phi_2=" + std::to_string(phi_2_deg) +
          ", I_0=" + std::to_string(params.mu_i_inertial_number_0) +
          ", d=" + std::to_string(params.mu_i_grain_diameter) +
          ", rho_s=" + std::to_string(params.mu_i_grain_density));
    }
    mu_i_ = true;
    eta_2_ = cone_slope(params.matching, std::sin(phi_2_deg * kPi / 180.0), sin_psi);
    i_0_ = params.mu_i_inertial_number_0;
    d_ = params.mu_i_grain_diameter;
    rho_s_ = params.mu_i_grain_density;
  }
}

double DruckerPragerLaw::slope(double inertial_number) const {
  if (!mu_i_ || !(inertial_number > 0.0)) return eta_;
  if (std::isinf(inertial_number)) return eta_2_;
  return eta_ + (eta_2_ - eta_) * inertial_number / (i_0_ + inertial_number);
}

double DruckerPragerLaw::inertial_number(double dlambda, double p, double dt) const {
  if (!(p > 0.0)) return std::numeric_limits<double>::infinity();
  return std::sqrt(3.0) * dlambda / dt * d_ / std::sqrt(p / rho_s_);
}

double DruckerPragerLaw::yield_function(const Mat3& sigma) const {
  const double p = -sigma.trace() / 3.0;
  const Mat3 s = sigma + p * Mat3::Identity();
  const double q = std::sqrt(1.5 * s.squaredNorm());
  return q - eta_ * p - xi_ * c_;
}

Mat3 DruckerPragerLaw::return_map(const Mat3& sigma_trial, double dt) const {
  const double p_tr = -sigma_trial.trace() / 3.0;
  const Mat3 s_tr = sigma_trial + p_tr * Mat3::Identity();
  const double q_tr = std::sqrt(1.5 * s_tr.squaredNorm());
  const double f_tr = q_tr - eta_ * p_tr - xi_ * c_;
  if (f_tr <= 0.0) return sigma_trial;
  const double dlambda = f_tr / (3.0 * G_ + eta_ * eta_g_ * K_);
  const double q = q_tr - 3.0 * G_ * dlambda;
  if (!mu_i_ || std::isinf(dt)) {
    if (q > 0.0) {
      // Cone. p from the consistency condition rather than p_tr + K eta_g dlambda, which is
      // the same number up to round-off, so that f = 0 holds to round-off also for small q.
      const double p = (q - xi_ * c_) / eta_;
      return (q / q_tr) * s_tr - p * Mat3::Identity();
    }
    return -p_apex_ * Mat3::Identity();
  }
  // mu(I): g(dl) = q(dl) - eta(I(dl)) (p(dl) - p_apex) falls from g(0) = f_tr > 0; the root
  // lies below the rate-independent dlambda (g <= 0 there), or below q = 0 if that one is at
  // the apex. No root with q > 0: apex.
  const auto p_of = [&](double dl) { return p_tr + K_ * eta_g_ * dl; };
  const auto g = [&](double dl) {
    const double p = p_of(dl);
    return q_tr - 3.0 * G_ * dl - slope(inertial_number(dl, p, dt)) * (p - p_apex_);
  };
  double lo = 0.0, g_lo = f_tr;
  double hi = q > 0.0 ? dlambda : q_tr / (3.0 * G_);
  double g_hi = g(hi);
  if (g_hi > 0.0) return -p_apex_ * Mat3::Identity();
  // Illinois variant of regula falsi: keeps the bracket, converges superlinearly.
  const double tol = 1e-13 * q_tr;
  int side = 0;
  double dl = hi;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
    dl = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
    const double g_dl = g(dl);
    if (std::abs(g_dl) <= tol) break;
    if (g_dl > 0.0) {
      lo = dl;
      g_lo = g_dl;
      if (side == 1) g_hi *= 0.5;
      side = 1;
    } else {
      hi = dl;
      g_hi = g_dl;
      if (side == -1) g_lo *= 0.5;
      side = -1;
    }
  }
  const double q_rd = q_tr - 3.0 * G_ * dl;
  if (!(q_rd > 0.0)) return -p_apex_ * Mat3::Identity();
  return (q_rd / q_tr) * s_tr - p_of(dl) * Mat3::Identity();
}

Mat3 DruckerPragerLaw::update(const Mat3& sigma, const Mat3& dF, double dt) const {
  // The kinematics of elastic::ElasticLaw::update (polar decomposition and Hencky increment).
  const Mat3 H = dF - Mat3::Identity();
  const Mat3 E_gl = 0.5 * (H + H.transpose() + H.transpose() * H);
  Mat3 d_eps, dU_inv;
  if (E_gl.squaredNorm() <= elastic::ElasticLaw::kSeriesLimit * elastic::ElasticLaw::kSeriesLimit) {
    elastic::ElasticLaw::series(E_gl, d_eps, dU_inv);
  } else {
    elastic::ElasticLaw::spectral(E_gl, d_eps, dU_inv);
  }
  const Mat3 dR = dF * dU_inv;
  const Mat3 trial = sigma + (lambda_ * d_eps.trace() * Mat3::Identity() + 2.0 * G_ * d_eps);
  const Mat3 s = dR * return_map(trial, dt) * dR.transpose();
  return 0.5 * (s + s.transpose());
}

double DruckerPragerLaw::strain_energy_density(const Mat3& sigma) const {
  const double tr = sigma.trace();
  return ((1.0 + nu_) * sigma.squaredNorm() - nu_ * tr * tr) / (2.0 * E_);
}

namespace {

// The disconnected state (disconnection_volume_ratio J_c > 0; Dunatunga & Kamrin 2015): the
// provider tracks each point's volume ratio J = prod det(dF). While J > J_c the point is a
// granular gas below the critical density: no stress, no stiffness (so it does not set the
// CFL step through its falling density), state kNoContacts (as an RVE that lost all its
// contacts). Compacted back to J <= J_c it reconnects: the stress restarts from zero with the
// increment of that step, not from a stress it held before it disconnected.
class DruckerPragerProvider final : public ConstitutiveProvider {
 public:
  DruckerPragerProvider(const DruckerPragerLaw& law, double disconnection_volume_ratio)
      : law_(law), j_c_(disconnection_volume_ratio) {}

  std::string name() const override { return "drucker_prager"; }

  // The initial stress is taken as given (a geostatic state outside the cone is returned to
  // it by the first update).
  void initialise(const std::vector<Mat3>& initial_stress,
                  std::vector<PointResponse>& out) override {
    sigma_ = initial_stress;
    J_.assign(sigma_.size(), 1.0);
    out.resize(sigma_.size());
    for (std::size_t i = 0; i < sigma_.size(); ++i) fill(i, out[i]);
  }

  // A resumed run keeps the stress of each point (resume() = initialise()); the volume
  // ratios, which the stress does not carry, travel in the checkpoint.
  std::vector<double> save_state() const override {
    return j_c_ > 0.0 ? J_ : std::vector<double>{};
  }
  void load_state(const std::vector<double>& state) override {
    if (j_c_ <= 0.0) return;
    if (state.size() != J_.size()) {
      throw std::runtime_error("drucker_prager: the checkpoint holds " +
                               std::to_string(state.size()) + " volume ratios for " +
                               std::to_string(J_.size()) +
                               " points (was it written without constitutive.drucker_prager."
                               "disconnection_volume_ratio?)");
    }
    J_ = state;
  }

  // sigma_p <- DruckerPragerLaw::update(sigma_p, dF_p, dt) for every point (independent points:
  // parallel like linear_elastic).
  void update(const std::vector<Mat3>& dF, double dt, std::int64_t /*step*/, double /*time*/,
              std::vector<PointResponse>& out) override {
    if (dF.size() != sigma_.size()) {
      throw std::logic_error("drucker_prager: update with " + std::to_string(dF.size()) +
                             " dF for " + std::to_string(sigma_.size()) + " points");
    }
    out.resize(sigma_.size());
    const auto n = static_cast<std::ptrdiff_t>(sigma_.size());
#pragma omp parallel for schedule(static) if (n > kParallelMin)
    for (std::ptrdiff_t p = 0; p < n; ++p) {
      const auto i = static_cast<std::size_t>(p);
      if (j_c_ > 0.0) {
        J_[i] *= dF[i].determinant();
        if (J_[i] > j_c_) {
          sigma_[i].setZero();
          out[i] = PointResponse{};  // zero stress and stiffness
          out[i].state = PointState::kNoContacts;
          continue;
        }
      }
      sigma_[i] = law_.update(sigma_[i], dF[i], dt);
      fill(i, out[i]);
    }
  }

 private:
  void fill(std::size_t i, PointResponse& r) const {
    r.stress = sigma_[i];
    r.stiffness = law_.constrained_modulus();
    r.state = PointState::kOk;
  }

  DruckerPragerLaw law_;
  double j_c_;  // disconnection volume ratio; 0: never
  std::vector<Mat3> sigma_;
  std::vector<double> J_;  // volume ratio of each point (tracked only with j_c_ > 0)
};

}  // namespace

std::unique_ptr<ConstitutiveProvider> make_drucker_prager(const ConstitutiveParams& params) {
  const DruckerPragerParams& dp = drucker_prager_params(params);
  if (dp.disconnection_volume_ratio != 0.0 && !(dp.disconnection_volume_ratio > 1.0)) {
    throw std::invalid_argument("drucker_prager needs disconnection_volume_ratio 0 or > 1, got " +
                                std::to_string(dp.disconnection_volume_ratio));
  }
  return std::make_unique<DruckerPragerProvider>(DruckerPragerLaw(params),
                                                 dp.disconnection_volume_ratio);
}

}  // namespace mpmdem::mpm

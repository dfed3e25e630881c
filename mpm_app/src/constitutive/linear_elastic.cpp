#include "constitutive/linear_elastic.hpp"

#include <stdexcept>
#include <string>

#include "constitutive/model_registry.hpp"
#include "mpmdem/laws/elastic_law.hpp"
#include "parallel.hpp"

namespace mpmdem::mpm {

namespace {

class LinearElasticProvider final : public ConstitutiveProvider {
 public:
  explicit LinearElasticProvider(const elastic::ElasticLaw& law) : law_(law) {}

  std::string name() const override { return "linear_elastic"; }

  void initialise(const std::vector<Mat3>& initial_stress,
                  std::vector<PointResponse>& out) override {
    sigma_ = initial_stress;
    respond(out);
  }

  // sigma_p <- ElasticLaw::update(sigma_p, dF_p) for every point.
  void update(const std::vector<Mat3>& dF, double /*dt*/, std::int64_t /*step*/, double /*time*/,
              std::vector<PointResponse>& out) override {
    if (dF.size() != sigma_.size()) {
      throw std::logic_error("linear_elastic: update with " + std::to_string(dF.size()) +
                             " dF for " + std::to_string(sigma_.size()) + " points");
    }
    out.resize(sigma_.size());
    const double M = law_.constrained_modulus();
    const auto n = static_cast<std::ptrdiff_t>(sigma_.size());
#pragma omp parallel for schedule(static) if (n > kParallelMin)
    for (std::ptrdiff_t p = 0; p < n; ++p) {
      const auto i = static_cast<std::size_t>(p);
      sigma_[i] = law_.update(sigma_[i], dF[i]);
      out[i].stress = sigma_[i];
      out[i].stiffness = M;
      out[i].state = PointState::kOk;
    }
  }

 private:
  void respond(std::vector<PointResponse>& out) const {
    out.resize(sigma_.size());
    const double M = law_.constrained_modulus();
    const auto n = static_cast<std::ptrdiff_t>(sigma_.size());
#pragma omp parallel for schedule(static) if (n > kParallelMin)
    for (std::ptrdiff_t p = 0; p < n; ++p) {
      const auto i = static_cast<std::size_t>(p);
      out[i].stress = sigma_[i];
      out[i].stiffness = M;
      out[i].state = PointState::kOk;
    }
  }

  elastic::ElasticLaw law_;
  std::vector<Mat3> sigma_;
};

}  // namespace

std::unique_ptr<ConstitutiveProvider> make_linear_elastic(const ConstitutiveParams& params) {
  const double E = params.youngs_modulus, nu = params.poisson_ratio;
  if (!(E > 0.0) || !(nu > -1.0 && nu < 0.5)) {
    throw std::invalid_argument(
        "linear_elastic needs youngs_modulus > 0 and -1 < poisson_ratio < 0.5, got E=" +
        std::to_string(E) + ", nu=" + std::to_string(nu));
  }
  return std::make_unique<LinearElasticProvider>(elastic::ElasticLaw{E, nu});
}

namespace {

// The model `linear_elastic` (model_registry.hpp): the section holds the moduli only.
[[maybe_unused]] const bool registered =
    register_local_model({"linear_elastic", "isotropic linear elasticity with an objective update",
                          add_elastic_moduli_keys, load_elastic_moduli, make_linear_elastic});

}  // namespace

}  // namespace mpmdem::mpm

// The `linear_elastic` provider: local, in-process isotropic elasticity with the objective
// update of elastic_law.hpp. It owns one Cauchy stress per point.
#pragma once

#include <memory>

#include "constitutive/provider.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

// Reads youngs_modulus and poisson_ratio of params (whatever params.model says).
std::unique_ptr<ConstitutiveProvider> make_linear_elastic(const ConstitutiveParams& params);

}  // namespace mpmdem::mpm

// The grains of the paper's Table 1 (docs/element_tests.md, docs/dem_backend.md): the
// defaults of the native RVEs' material (native::Material) and of the clouds they build in
// place (coupling.native.inline_spheres). YADE's packings carry their own material, read with
// them.
#pragma once

namespace mpmdem::dem::laws::table1 {

constexpr double kYoung = 6e8;                                // contact modulus E [Pa]
constexpr double kKsKn = 0.8;                                 // FrictMat.poisson: ks / kn
constexpr double kDensity = 2500;                             // [kg/m3]
constexpr double kFriction = 0.518;                           // tan of the friction angle
constexpr double kRadiusMin = 0.92e-3, kRadiusMax = 1.38e-3;  // [m]

}  // namespace mpmdem::dem::laws::table1

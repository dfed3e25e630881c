// Material points of a scene: generated on a cell-aligned lattice in each region box, with
// their initial stresses.
#pragma once

#include <vector>

#include "particles.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

// n = points_per_cell points per cell per direction (placement cells: at the centres of the n^3
// sub-cells of every grid cell, volume (h/n)^3; placement gauss: n Gauss-Legendre points per
// direction in every knot span of the shape functions, volume = the product of the weights),
// kept where they fall inside a region box (min <= x < max; a point in several regions
// belongs to the first). Mass = density * volume, velocity from the region (uniform, plus the
// optional sine profile along its axis), F = dF = I. Points are ordered region by region, then cell
// by cell (x fastest). id = index. Throws SceneError when a region holds no point position.
Particles generate_particles(const Scene& scene);

// Initial Cauchy stress per point: zero, or geostatic for regions that ask for it:
//   sigma_v = -rho |g| d, sigma_h = K0 sigma_v, d = depth below the region's top along g,
//   sigma = sigma_v g^ g^T + sigma_h (I - g^ g^T), g^ = g / |g|.
// The depth is measured within the point's own region (no overburden of other regions).
std::vector<Mat3> initial_stresses(const Scene& scene, const Particles& p);

}  // namespace mpmdem::mpm

// Verification of the elastic column under self-weight (1D compression: frictionless side
// walls, fixed base, gravity along -z) against its analytic solution.
//
// Stress. In uniaxial strain the lateral area of a slice does not change, so the Cauchy
// stress at the material point that started at height Z is the weight of the material above
// it per unit area, exactly (not only for small strains):
//   sigma_zz(Z) = -rho g (H - Z),   Z = reference (initial) height x0_z, H = top of the region.
// We therefore compare each point's sigma_zz with the analytic value at its reference height:
//   stress_rel_error = ||sigma_zz,p + rho g (H - Z_p)||_2 / ||rho g (H - Z_p)||_2 over points.
// (With trilinear shape functions the computed stress is constant over a cell, so this
// point-wise error is first order in the cell size: ~0.43 h / H.)
//
// Settlement. Linear (small-strain) theory gives u(Z) = rho g / M (H Z' - Z'^2 / 2), Z' = Z -
// base, so u(H) = rho g H^2 / (2M), M = E (1 - nu) / ((1 + nu)(1 - 2 nu)). The top layer of
// material points sits half a point spacing below H, so the mean settlement of that layer
// (u_p = Z_p - z_p) is compared with the mean of u(Z_p) over the same points:
//   settlement_rel_error = |mean u_p - mean u(Z_p)| / mean u(Z_p).
// The scene must use a strain rho g H / M well below 1% for linear theory to hold to 1%.
#pragma once

#include <cstddef>

#include "particles.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

// Constrained (P-wave) modulus M and Young's modulus E of the elastic material the scene
// uses: a local model's elastic moduli (ConstitutiveParams), or coupling.elastic when the
// model is remote, which needs coupling.backend elastic (SceneError naming
// verification.kind otherwise: a DEM backend has no closed-form moduli).
struct ElasticModuli {
  double E = 0.0;
  double nu = 0.0;
  double M = 0.0;
};
ElasticModuli scene_elastic_moduli(const Scene& scene);

struct ElasticColumnResult {
  double stress_rel_error = 0.0;
  double settlement_rel_error = 0.0;
  double settlement_top_m = 0.0;               // mean u_p of the top layer
  double settlement_top_expected_m = 0.0;      // mean u(Z_p) over the same points
  double settlement_surface_expected_m = 0.0;  // rho g H^2 / (2M)
  std::size_t top_layer_points = 0;
};

// What the verification needs of the scene: gravity along -z and known elastic moduli
// (scene_elastic_moduli). Throws SceneError naming the key; the scene loader calls it for
// verification.kind elastic_column, so a scene it refuses never runs.
void check_elastic_column_scene(const Scene& scene);
// Throws SceneError if the scene is not one check_elastic_column_scene() accepts.
ElasticColumnResult verify_elastic_column(const Scene& scene, const Particles& p);

}  // namespace mpmdem::mpm

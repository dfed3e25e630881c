#include "verification/elastic_column.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "errors.hpp"
#include "mpmdem/config/schema.hpp"
#include "run_support.hpp"

namespace mpmdem::mpm {

namespace {

// coupling.elastic.{youngs_modulus, poisson_ratio} from the canonical coupling section.
bool remote_elastic(const Scene& scene, double& E, double& nu) {
  if (scene.coupling.canonical_text.empty()) return false;
  try {
    YAML::Node root = YAML::Load(scene.coupling.canonical_text);
    if (root["coupling"]) root = root["coupling"];
    const YAML::Node el = root["elastic"];
    if (!el || !el["youngs_modulus"] || !el["poisson_ratio"]) return false;
    E = el["youngs_modulus"].as<double>();
    nu = el["poisson_ratio"].as<double>();
    return true;
  } catch (const YAML::Exception&) {
    return false;
  }
}

}  // namespace

ElasticModuli scene_elastic_moduli(const Scene& scene) {
  ElasticModuli m;
  m.E = scene.constitutive.youngs_modulus;
  m.nu = scene.constitutive.poisson_ratio;
  if (scene.constitutive.is_remote() && scene.coupling.backend != "elastic") {
    throw SceneError("verification.kind",
                     std::string(run_support::verification_name(scene.verification.kind)) +
                         " compares with linear elasticity, but the remote model's "
                         "coupling.backend is " +
                         scene.coupling.backend +
                         ", whose moduli are not known in closed form: use coupling.backend "
                         "elastic, or verification.kind none");
  }
  if (scene.constitutive.is_remote() && !remote_elastic(scene, m.E, m.nu)) {
    throw SceneError("coupling.backend",
                     "is elastic but the section coupling.elastic (youngs_modulus, "
                     "poisson_ratio) is missing or incomplete: " +
                         std::string(run_support::verification_name(scene.verification.kind)) +
                         " compares with the stub's moduli");
  }
  m.M = m.E * (1.0 - m.nu) / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu));
  return m;
}

void check_elastic_column_scene(const Scene& scene) {
  const Vec3& g = scene.solver.gravity;
  if (!(g.z() < 0.0) || std::abs(g.x()) > 1e-12 * std::abs(g.z()) ||
      std::abs(g.y()) > 1e-12 * std::abs(g.z())) {
    throw SceneError("solver.gravity",
                     "[" + config::format_number(g.x()) + ", " + config::format_number(g.y()) +
                         ", " + config::format_number(g.z()) +
                         "] does not point along -z, which verification.kind elastic_column "
                         "needs (its analytic column is loaded along -z)");
  }
  (void)scene_elastic_moduli(scene);
}

ElasticColumnResult verify_elastic_column(const Scene& scene, const Particles& p) {
  check_elastic_column_scene(scene);
  const Vec3& g_vec = scene.solver.gravity;
  if (p.size() == 0) throw std::runtime_error("elastic_column verification: no points");
  const double g = -g_vec.z();
  const double M = scene_elastic_moduli(scene).M;

  ElasticColumnResult r;
  // Stress profile against the weight of the material above each point.
  double err2 = 0.0, ref2 = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const RegionParams& reg = scene.regions.at(static_cast<std::size_t>(p.region[i]));
    const double expected = -reg.density * g * (reg.max.z() - p.x0[i].z());
    const double diff = p.sigma[i](2, 2) - expected;
    err2 += diff * diff;
    ref2 += expected * expected;
  }
  r.stress_rel_error = std::sqrt(err2 / ref2);

  // Settlement of the top layer against linear theory at the same reference heights.
  double z_top = -std::numeric_limits<double>::infinity();
  for (const Vec3& x0 : p.x0) z_top = std::max(z_top, x0.z());
  double min_spacing = std::numeric_limits<double>::infinity();
  for (const RegionParams& reg : scene.regions)
    min_spacing = std::min(
        min_spacing, scene.grid.cell_size /
                         std::max({reg.points_along(0), reg.points_along(1), reg.points_along(2)}));
  double u_sum = 0.0, u_expected_sum = 0.0, surface_sum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.x0[i].z() < z_top - 0.25 * min_spacing) continue;
    const RegionParams& reg = scene.regions.at(static_cast<std::size_t>(p.region[i]));
    const double H = reg.max.z() - reg.min.z();
    const double Z = p.x0[i].z() - reg.min.z();
    const double k = reg.density * g / M;
    u_sum += p.x0[i].z() - p.x[i].z();
    u_expected_sum += k * (H * Z - 0.5 * Z * Z);
    surface_sum += 0.5 * k * H * H;
    ++r.top_layer_points;
  }
  const double n_top = static_cast<double>(r.top_layer_points);
  r.settlement_top_m = u_sum / n_top;
  r.settlement_top_expected_m = u_expected_sum / n_top;
  r.settlement_surface_expected_m = surface_sum / n_top;
  r.settlement_rel_error =
      std::abs(r.settlement_top_m - r.settlement_top_expected_m) / r.settlement_top_expected_m;
  return r;
}

}  // namespace mpmdem::mpm

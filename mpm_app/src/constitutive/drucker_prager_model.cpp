// The model `drucker_prager` (model_registry.hpp): its section constitutive.drucker_prager,
// how it is read, and its summary figures. The law and the provider: drucker_prager.hpp.
#include <memory>
#include <string>
#include <utility>

#include "constitutive/drucker_prager.hpp"
#include "constitutive/model_registry.hpp"
#include "solver.hpp"

namespace mpmdem::mpm {

namespace {

using config::key;
using config::Type;

void add_keys(config::Schema& s, const std::string& k) {
  add_elastic_moduli_keys(s, k);
  s.add(key(k + ".friction_angle_deg", Type::kDouble, "deg", "Mohr-Coulomb friction angle phi")
            .req()
            .gt(0)
            .lt(90));
  s.add(key(k + ".dilation_angle_deg", Type::kDouble, "deg",
            "dilation angle psi, at most friction_angle_deg; 0: plastic flow keeps the volume")
            .def("0")
            .ge(0)
            .lt(90));
  s.add(key(k + ".cohesion", Type::kDouble, "Pa",
            "Mohr-Coulomb cohesion c; the cone's apex at p = -c cot(phi) is the tension "
            "cutoff (0: no tension)")
            .def("0")
            .ge(0));
  s.add(key(k + ".matching", Type::kEnum, "",
            "compression: the cone through Mohr-Coulomb's triaxial-compression corners, q/p = "
            "6 sin(phi)/(3 - sin(phi)); plane_strain: the same plane-strain limit load as "
            "Mohr-Coulomb")
            .def("compression")
            .one_of({"compression", "plane_strain"}));
  s.add(key(k + ".disconnection_volume_ratio", Type::kDouble, "-",
            "J_c > 1: a point whose volume exceeds J_c times its initial volume is "
            "disconnected (the granular state below the critical density of Dunatunga & "
            "Kamrin 2015): no stress and no stiffness, reported as no contacts, and no affine "
            "velocity with transfer apic; compacted below J_c it reconnects from zero stress. "
            "0: never (docs/transfers.md, \"The disconnected state\")")
            .def("0")
            .ge(0));
  s.add(key(k + ".mu_i", Type::kMap, "",
            "optional: the mu(I) rheology (Jop, Forterre & Pouliquen 2006). The cone's slope "
            "grows from that of friction_angle_deg to that of friction_angle_2_deg with the "
            "inertial number I = gamma_dot_p d / sqrt(p / rho_s) of the plastic shear rate: "
            "eta(I) = eta_s + (eta_2 - eta_s) I / (I_0 + I). Absent: rate independent "
            "(docs/configuration.md)"));
  s.add(key(k + ".mu_i.friction_angle_2_deg", Type::kDouble, "deg",
            "friction angle phi_2 of the limit I >> I_0, above friction_angle_deg (with "
            "plane_strain matching and no dilation, mu = sqrt(J2)/p = sin(phi))")
            .req()
            .gt(0)
            .lt(90));
  s.add(key(k + ".mu_i.inertial_number_0", Type::kDouble, "-",
            "I_0, the inertial number at which the slope is halfway from eta_s to eta_2 "
            "(0.279 for the glass beads of Jop et al. 2006)")
            .def("0.279")
            .gt(0));
  s.add(
      key(k + ".mu_i.grain_diameter", Type::kDouble, "m", "grain diameter d in the inertial number")
          .req()
          .gt(0));
  s.add(key(k + ".mu_i.grain_density", Type::kDouble, "kg/m3",
            "density of the grains' solid rho_s in the inertial number (not the bulk density)")
            .req()
            .gt(0));
}

void load(const config::Config& cfg, const std::string& k, ConstitutiveParams& params) {
  load_elastic_moduli(cfg, k, params);
  auto c = std::make_shared<DruckerPragerParams>();
  c->friction_angle_deg = cfg.number(k + ".friction_angle_deg");
  c->dilation_angle_deg = cfg.number(k + ".dilation_angle_deg");
  c->cohesion = cfg.number(k + ".cohesion");
  c->disconnection_volume_ratio = cfg.number(k + ".disconnection_volume_ratio");
  if (c->disconnection_volume_ratio > 0.0 && c->disconnection_volume_ratio <= 1.0) {
    cfg.fail(k + ".disconnection_volume_ratio",
             config::format_number(c->disconnection_volume_ratio) +
                 " would disconnect points at or below their initial volume; give a ratio "
                 "above 1 (e.g. 1.5) or 0 (never)");
  }
  c->matching = cfg.string(k + ".matching") == "plane_strain" ? ConeMatching::kPlaneStrain
                                                              : ConeMatching::kCompression;
  if (cfg.has(k + ".mu_i")) {
    c->mu_i_friction_angle_2_deg = cfg.number(k + ".mu_i.friction_angle_2_deg");
    c->mu_i_inertial_number_0 = cfg.number(k + ".mu_i.inertial_number_0");
    c->mu_i_grain_diameter = cfg.number(k + ".mu_i.grain_diameter");
    c->mu_i_grain_density = cfg.number(k + ".mu_i.grain_density");
    if (!(c->mu_i_friction_angle_2_deg > c->friction_angle_deg)) {
      cfg.fail(k + ".mu_i.friction_angle_2_deg",
               config::format_number(c->mu_i_friction_angle_2_deg) +
                   " is not above friction_angle_deg " +
                   config::format_number(c->friction_angle_deg) +
                   "; mu(I) needs the limit angle above the angle at rest (or drop the "
                   "mu_i section for a rate-independent law)");
    }
  }
  if (c->dilation_angle_deg > c->friction_angle_deg) {
    cfg.fail(k + ".dilation_angle_deg",
             config::format_number(c->dilation_angle_deg) + " is larger than friction_angle_deg " +
                 config::format_number(c->friction_angle_deg) +
                 "; the dilation angle must not exceed the friction angle");
  }
  params.own = std::move(c);
}

// The disconnected state (when on): point updates spent disconnected, and the points
// disconnected at the end.
Figures figures(const ConstitutiveParams& params, const Solver& solver) {
  if (!(drucker_prager_params(params).disconnection_volume_ratio > 0.0)) return {};
  return {{"disconnected_point_updates", static_cast<double>(solver.no_contact_updates())},
          {"disconnected_points_final", static_cast<double>(solver.no_contact_points())}};
}

[[maybe_unused]] const bool registered = register_local_model(
    {"drucker_prager",
     "elastic-perfectly plastic Drucker-Prager cone fitted to Mohr-Coulomb, non-associated, "
     "with the objective update of linear_elastic",
     add_keys, load, make_drucker_prager, figures});

}  // namespace

}  // namespace mpmdem::mpm

// The choice of contact law of the native RVEs (coupling.<backend>.contact_law and
// restitution_normal): which law, and the damping ratio a coefficient of restitution gives.
// No Eigen here: the configuration rules (coupling_rules.cpp) build it too.
#pragma once

#include <cmath>
#include <cstdint>

namespace mpmdem::dem::native {

// The law of every contact of an RVE (docs/theory_contact_law.md):
//  * kFrict: FrictMat, Law2_ScGeom_FrictPhys_CundallStrack (linear spring, Coulomb slider);
//  * kFrictVisco: FrictViscoMat, Law2_ScGeom_FrictViscoPhys_CundallStrackVisco: the same
//    springs and slider plus a normal dashpot F_v = -c_n (n . v_incident) n, with
//    c_n = beta_n 2 sqrt(m* kn) (m* = m1 m2 / (m1 + m2)) and beta_n from the coefficient of
//    restitution e_n of a binary collision (restitution_damping_ratio). The dashpot is part
//    of the normal force (also in the Coulomb limit and the stress) and is not clipped at
//    zero, so e_n holds exactly for the linear spring-dashpot.
enum class ContactLawKind : std::int32_t { kFrict = 0, kFrictVisco = 1 };

struct ContactLaw {
  ContactLawKind kind = ContactLawKind::kFrict;
  double restitution_n = 1;  // e_n (kFrictVisco)
  double beta_n = 0;         // c_n / (2 sqrt(m* kn)): FrictViscoMat.betan
  bool viscous() const { return kind == ContactLawKind::kFrictVisco; }
};

// beta = -ln e / sqrt(pi^2 + ln^2 e): the damping ratio of a linear spring-dashpot whose
// half-period of damped oscillation ends with the velocity e v_in (e in (0, 1]).
inline double restitution_damping_ratio(double e) {
  const double l = std::log(e);
  return -l / std::sqrt(M_PI * M_PI + l * l);
}

inline ContactLaw frict_visco_law(double e_n) {
  ContactLaw law;
  law.kind = ContactLawKind::kFrictVisco;
  law.restitution_n = e_n;
  law.beta_n = restitution_damping_ratio(e_n);
  return law;
}

// "frict" or "frict_visco" (the values of coupling.<backend>.contact_law).
inline const char* contact_law_name(ContactLawKind k) {
  return k == ContactLawKind::kFrictVisco ? "frict_visco" : "frict";
}

}  // namespace mpmdem::dem::native

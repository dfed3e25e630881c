// The choice of contact law of the native RVEs (coupling.<backend>.contact_law and
// restitution_normal): which law, and the damping ratio a coefficient of restitution gives.
// No Eigen here: the configuration rules (coupling_rules.cpp) build it too.
#pragma once

#include <cmath>
#include <cstdint>

#include "backends/contact_laws/registry.hpp"

namespace mpmdem::dem::native {

// The law of every contact of an RVE (docs/theory_contact_law.md): its id in
// laws::AllLaws (backends/contact_laws/registry.hpp), where each law is one file:
//  * kFrict: contact_laws/frict.hpp (FrictMat, Law2_ScGeom_FrictPhys_CundallStrack);
//  * kFrictVisco: contact_laws/frict_visco.hpp (FrictViscoMat, the same springs and slider plus a
//    normal dashpot set from the coefficient of restitution e_n of a binary collision,
//    restitution_damping_ratio).
enum class ContactLawKind : std::int32_t { kFrict = 0, kFrictVisco = 1 };
static_assert(laws::kLaws.size() == 2, "one ContactLawKind per law of laws::AllLaws");

// f(Law{}) for that kind's law (laws::visit_law).
template <class F>
decltype(auto) visit_law(ContactLawKind k, F&& f) {
  return laws::visit_law(static_cast<int>(k), static_cast<F&&>(f));
}

struct ContactLaw {
  ContactLawKind kind = ContactLawKind::kFrict;
  double restitution_n = 1;  // e_n (kFrictVisco)
  double beta_n = 0;         // c_n / (2 sqrt(m* kn)): FrictViscoMat.betan
  bool viscous() const { return known() && laws::kLaws[static_cast<std::size_t>(kind)].viscous; }
  // kind is the id of a law of laws::AllLaws (a binary state read from a file checks it)
  bool known() const {
    return kind >= ContactLawKind{} && static_cast<std::size_t>(kind) < laws::kLaws.size();
  }
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
  const auto i = static_cast<std::size_t>(k);
  return i < laws::kLaws.size() ? laws::kLaws[i].name : "unknown";
}

}  // namespace mpmdem::dem::native

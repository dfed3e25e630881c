// The frict_visco contact law (coupling.<backend>.contact_law: frict_visco, with
// restitution_normal e_n): YADE's FrictViscoMat with Ip2_FrictViscoMat_FrictViscoMat_
// FrictViscoPhys and Law2_ScGeom_FrictViscoPhys_CundallStrackVisco: frict's springs and slider
// (frict.hpp) plus a normal dashpot F_v = -c_n (n . v_incident) n, c_n = 2 sqrt(m* kn) beta_n
// (m* = m1 m2 / (m1 + m2)), beta_n from e_n (contact_law_kind.hpp's
// restitution_damping_ratio). The dashpot is part of the normal force (also in the Coulomb
// limit and the stress) and is not clipped at zero, so e_n holds exactly for the linear
// spring-dashpot (docs/theory_contact_law.md). Only the normal force differs from frict.
#pragma once

#include "backends/contact_laws/frict.hpp"

namespace mpmdem::dem::laws {

struct FrictVisco : Frict {
  static constexpr const char* kName = "frict_visco";
  static constexpr const char* kSummary =
      "FrictViscoMat, Law2_ScGeom_FrictViscoPhys_CundallStrackVisco: frict plus a normal "
      "dashpot set by restitution_normal (e_n)";
  static constexpr bool kViscous = true;

  // frict's spring force minus the dashpot's c_n rn n; visc = c_n rn (kept per contact).
  // v_incident's normal part is rn (its rotational terms are normal to n).
  template <class T>
  static MPMDEM_LAW_INLINE void normal_force(const LawParams& k, const T& kn, const T& pen,
                                             const T& rn, const T& m1, const T& m2, const T (&n)[3],
                                             T (&fn)[3], T& visc) {
    Frict::normal_force(k, kn, pen, rn, m1, m2, n, fn, visc);
    const T mbar = m1 * m2 / (m1 + m2);
    T root;
    LawMath<T>::sqrt(mbar * kn, root);
    const T cn = 2. * root * k.beta_n;
    for (int q = 0; q < 3; ++q) fn[q] -= cn * (rn * n[q]);
    visc = cn * rn;
  }

  template <class T>
  static MPMDEM_LAW_INLINE void stored_normal_force(const T& kn, const T& pen, const T& visc,
                                                    const T (&n)[3], T (&fn)[3]) {
    Frict::stored_normal_force(kn, pen, visc, n, fn);
    for (int q = 0; q < 3; ++q) fn[q] -= visc * n[q];
  }
};

}  // namespace mpmdem::dem::laws

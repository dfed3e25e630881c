// The frict contact law (coupling.<backend>.contact_law: frict): YADE's FrictMat with
// Ip2_FrictMat_FrictMat_FrictPhys and Law2_ScGeom_FrictPhys_CundallStrack, a linear normal
// spring, a linear shear spring that rotates with the contact, and a Coulomb slider.
// Written once over the lane type T (law_math.hpp): the native scalar and AVX-512 kernels,
// the native measures and the batch backend (host and CUDA) all call these functions. The
// geometry (Ig2_Sphere_Sphere_ScGeom, ScGeom::rotate of the shear force) is the kernels'.
// A kernel's contact update calls, in this order of meaning (their operations are
// independent, so the order of the calls changes no bit):
//   stiffness -> shear_increment -> normal_force -> slide,
// and a contact's force as stored after the step (stress, energy, unbalanced force) is
// stored_normal_force + the stored shear force.
#pragma once

#include "backends/contact_laws/law_math.hpp"

namespace mpmdem::dem::laws {

struct Frict {
  static constexpr const char* kName = "frict";
  static constexpr const char* kSummary =
      "FrictMat, Law2_ScGeom_FrictPhys_CundallStrack: linear normal and shear springs, "
      "Coulomb slider";
  // A viscous law reads the spheres' masses (m1, m2 below) and keeps per contact the viscous
  // part of its normal force (Contacts::normal_viscous, `visc` below); frict does neither.
  static constexpr bool kViscous = false;

  // Ip2_FrictMat_FrictMat_FrictPhys for the RVE's one material: kn the harmonic mean of
  // E r1 and E r2, ks = (ks/kn) kn (YADE's second harmonic mean, to rounding, without its
  // division).
  template <class T>
  static MPMDEM_LAW_INLINE void stiffness(const double& young, const double& ks_kn, const T& r1,
                                          const T& r2, T& kn, T& ks) {
    const T e1 = young * r1, e2 = young * r2;
    kn = 2.0 * e1 * e2 / (e1 + e2);
    ks = ks_kn * kn;
  }

  // CundallStrack's shear spring: fs (already rotated with the contact) -= ks inc, inc the
  // tangential relative displacement of the step.
  template <class T>
  static MPMDEM_LAW_INLINE void shear_increment(const T& ks, const T (&inc)[3], T (&fs)[3]) {
    for (int q = 0; q < 3; ++q) fs[q] -= ks * inc[q];
  }

  // The normal force of a step: kn max(pen, 0) n (pen the penetration, n the unit normal
  // 1 -> 2; rn = n . v_incident, m1 and m2 the masses: unused here). visc: untouched.
  template <class T>
  static MPMDEM_LAW_INLINE void normal_force(const LawParams&, const T& kn, const T& pen, const T&,
                                             const T&, const T&, const T (&n)[3], T (&fn)[3], T&) {
    const T zero{};
    const T fn_mag = kn * (pen < zero ? zero : pen);  // std::max(pen, 0.0) (a NaN kept)
    for (int q = 0; q < 3; ++q) fn[q] = fn_mag * n[q];
  }

  // Coulomb: |fs| capped at tan(phi) |fn|.
  template <class T>
  static MPMDEM_LAW_INLINE void slide(const LawParams& k, const T (&fn)[3], T (&fs)[3]) {
    const T max_fs = (fn[0] * fn[0] + fn[1] * fn[1] + fn[2] * fn[2]) * k.tan2;
    const T fs2 = fs[0] * fs[0] + fs[1] * fs[1] + fs[2] * fs[2];
    LawMath<T>::cap(fs, max_fs, fs2);
  }

  // The normal force normal_force computed, from what a contact keeps after the step (its
  // penetration, normal and, for a viscous law, visc).
  template <class T>
  static MPMDEM_LAW_INLINE void stored_normal_force(const T& kn, const T& pen, const T&,
                                                    const T (&n)[3], T (&fn)[3]) {
    const T zero{};
    const T fn_mag = kn * (pen < zero ? zero : pen);
    for (int q = 0; q < 3; ++q) fn[q] = fn_mag * n[q];
  }
};

}  // namespace mpmdem::dem::laws

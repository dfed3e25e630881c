// Stress invariants shared by the constitutive tests (test_drucker_prager.cpp, test_mu_i.cpp):
// tension positive, p = -tr(sigma)/3 (compression positive), s = sigma + p I, q = sqrt(3/2 s:s).
#pragma once

#include <cmath>

#include "constitutive/provider.hpp"

namespace stress_test {

using mpmdem::mpm::Mat3;

inline double pressure(const Mat3& s) {
  return -s.trace() / 3.0;
}
inline Mat3 deviator(const Mat3& s) {
  return s + pressure(s) * Mat3::Identity();
}
inline double von_mises(const Mat3& s) {
  return std::sqrt(1.5 * deviator(s).squaredNorm());
}

}  // namespace stress_test

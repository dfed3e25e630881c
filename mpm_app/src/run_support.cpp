#include "run_support.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>

namespace mpmdem::mpm {

namespace run_support {

const char* verification_name(VerificationKind kind) {
  switch (kind) {
    case VerificationKind::kElasticColumn:
      return "elastic_column";
    case VerificationKind::kBarVibration:
      return "bar_vibration";
    case VerificationKind::kNone:
      break;
  }
  return "";
}

double total_mass(const Particles& p) {
  double m = 0.0;
  for (double m_p : p.m) m += m_p;
  return m;
}

double total_mass(const Grid& g) {
  double m = 0.0;
  for (double m_i : g.m_i) m += m_i;
  return m;
}

namespace {

bool finite(const Vec3& v) {
  return v.allFinite();
}
bool finite(const Mat3& v) {
  return v.allFinite();
}
bool finite(double v) {
  return std::isfinite(v);
}

}  // namespace

std::string find_non_finite(const Particles& p) {
  auto where = [&p](std::size_t i, const char* field) {
    std::ostringstream msg;
    msg << "non-finite " << field << " at material point " << p.id[i] << " (initial position "
        << p.x0[i].transpose() << ")";
    return msg.str();
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!finite(p.x[i])) return where(i, "position");
    if (!finite(p.v[i])) return where(i, "velocity");
    if (!finite(p.sigma[i])) return where(i, "stress");
    if (!finite(p.F[i])) return where(i, "deformation gradient");
    if (!finite(p.V[i])) return where(i, "volume");
    if (!finite(p.m[i])) return where(i, "mass");
  }
  return "";
}

double process_cpu_time() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::string format_seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", s);
  return buf;
}

}  // namespace run_support

}  // namespace mpmdem::mpm

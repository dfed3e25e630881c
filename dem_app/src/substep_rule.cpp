// The substep rule: see substep_rule.hpp.
#include "substep_rule.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mpmdem::dem {

int SubstepRule::count(const protocol::RveRequest& req, double dem_dt) const {
  if (kind == Kind::kFixed) return ns;
  double want = 0;
  if (kind == Kind::kRate) {
    // ns dt_dem = the update's dt (to within one DEM step): the RVE deforms at the MPM's rate
    if (!(std::isfinite(req.dt) && req.dt >= 0.0)) {
      throw std::runtime_error("ns_rule rate: the update's dt is " + std::to_string(req.dt) +
                               " s; the client must send a finite dt >= 0 (RveRequest::dt)");
    }
    want = req.dt / dem_dt;
  } else {
    double g = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        g = std::max(g, std::abs(req.dF[3 * i + j] - (i == j ? 1.0 : 0.0)));
    want = ns_factor * g;
  }
  // clamped as a double first: a huge want must not overflow the int
  const double n = std::ceil(std::min(want, static_cast<double>(ns_max)));
  return std::max(ns_min, static_cast<int>(n));
}

SubstepRule substep_rule(const config::Config& cfg, const std::string& backend) {
  const std::string p = "coupling." + backend + ".";
  SubstepRule r;
  const std::string kind = cfg.string(p + "ns_rule");
  r.kind = kind == "fixed"  ? SubstepRule::Kind::kFixed
           : kind == "rate" ? SubstepRule::Kind::kRate
                            : SubstepRule::Kind::kProportional;
  r.ns = static_cast<int>(cfg.integer(p + "ns"));
  r.ns_factor = cfg.number(p + "ns_factor");
  r.ns_min = static_cast<int>(cfg.integer(p + "ns_min"));
  r.ns_max = static_cast<int>(cfg.integer(p + "ns_max"));
  return r;
}

}  // namespace mpmdem::dem

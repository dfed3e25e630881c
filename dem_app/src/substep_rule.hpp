// How many DEM substeps an RVE takes for one update (coupling.<backend>.ns_rule, ns, ns_factor,
// ns_min, ns_max), the same rule for every DEM backend (rve_driver.hpp applies it).
#pragma once

#include <string>

#include "mpmdem/config/schema.hpp"
#include "mpmdem/protocol.hpp"

namespace mpmdem::dem {

struct SubstepRule {
  // fixed: ns; proportional: to the strain increment (ns_factor max|dF - I|); rate: the
  // update's dt over the RVE's DEM step (the RVE strained at the MPM's rate).
  enum class Kind { kFixed, kProportional, kRate } kind = Kind::kProportional;
  int ns = 10, ns_min = 2, ns_max = 100;
  double ns_factor = 1e5;

  // Substeps for the update `req` of an RVE whose DEM step is dem_dt [s]: ns (fixed), or
  // clamp(ceil(want), ns_min, ns_max) with want = ns_factor max|dF - I| (proportional) or
  // req.dt / dem_dt (rate). Throws std::runtime_error for a rate update whose dt is not a
  // finite time >= 0 (the client's fault).
  int count(const protocol::RveRequest& req, double dem_dt) const;
};

// The rule of coupling.<backend>.* (a validated config; backend "native" or "yade").
SubstepRule substep_rule(const config::Config& cfg, const std::string& backend);

}  // namespace mpmdem::dem

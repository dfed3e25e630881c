// Keys shared by the RVE backends (`coupling.<backend>.*` for yade and native): packings,
// substep rule, damping, fault thresholds, initial consolidation. Declared once here with the
// backend's name in the key and its packing file in the descriptions; yade_schema.cpp and
// native_schema.cpp add them and their own keys.
#pragma once

#include <string>

#include "mpmdem/config/schema.hpp"

namespace mpmdem {

struct RveBackendKeys {
  std::string backend;          // "yade" or "native": the keys are coupling.<backend>.*
  std::string title;            // description of the coupling.<backend> map
  std::string packing_dir;      // description of packing_dir
  std::string packing_file;     // "<name>.yade.bz2"
  std::string spec_builds;      // what scripts/run does with packing_spec
  std::string seed_also;        // what else the seed draws ("" or e.g. " and of ...")
  std::string damping;          // description of damping
  std::string stiffness_bound;  // description of the tangent stiffness choice
};

void add_rve_backend_keys(config::Schema& schema, const RveBackendKeys& k);

}  // namespace mpmdem

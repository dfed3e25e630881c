// The DEM backends by name: see backend_catalog.hpp.
#include "backend_catalog.hpp"

#include "coupling_rules.hpp"
#include "cuda_schema.hpp"
#include "elastic_schema.hpp"
#include "mpmdem/protocol.hpp"
#include "native_schema.hpp"
#include "yade_schema.hpp"

namespace mpmdem::dem {

namespace {

void check_yade(const config::Config& cfg) {
  check_rve_backend(cfg, "yade");
  check_no_yade_consolidation_cache(cfg);
}
void check_native(const config::Config& cfg) {
  check_rve_backend(cfg, "native");
}
void check_cuda(const config::Config& cfg) {
  check_rve_backend(cfg, "native");  // its physics keys are coupling.native.*
  check_cuda_contact_law(cfg);
}

}  // namespace

const std::vector<BackendSpec>& backend_catalog() {
  static const std::vector<BackendSpec> catalog = {
      {"elastic", "the closed-form linear-elastic stand-in (coupling.elastic; no RVE outputs)",
       add_elastic_keys, check_elastic_section, 0},
      {"yade", "YADE in embedded Python, one scene per RVE (the reference backend)", add_yade_keys,
       check_yade, protocol::kKnownOutputs},
      {"native", "the compiled DEM of the RVEs (YADE's laws, vectorised; the default's)",
       add_native_keys, check_native, protocol::kKnownOutputs},
      {"cuda", "the native RVEs as one batch, on a GPU or its host path (coupling.cuda)",
       add_cuda_keys, check_cuda, protocol::kKnownOutputs},
  };
  return catalog;
}

const BackendSpec* find_backend(const std::string& name) {
  for (const BackendSpec& b : backend_catalog()) {
    if (b.name == name) return &b;
  }
  return nullptr;
}

std::vector<std::string> backend_names() {
  std::vector<std::string> names;
  for (const BackendSpec& b : backend_catalog()) names.push_back(b.name);
  return names;
}

}  // namespace mpmdem::dem

// The rules between keys of the `coupling:` section: see coupling_rules.hpp.
#include "coupling_rules.hpp"

#include <unistd.h>

#include <filesystem>
#include <sstream>
#include <system_error>
#include <vector>

#include "backend_catalog.hpp"
#include "coupling_schema.hpp"
#include "mpmdem/protocol.hpp"

namespace mpmdem {

namespace {

std::string list_text(const std::vector<std::string>& items) {
  std::string s = "[";
  for (std::size_t i = 0; i < items.size(); ++i) s += (i ? ", " : "") + items[i];
  return s + "]";
}

}  // namespace

namespace dem {

std::uint32_t backend_outputs(const std::string& name) {
  const BackendSpec* b = find_backend(name);
  return b ? b->outputs : 0;
}

}  // namespace dem

void check_elastic_section(const config::Config& cfg) {
  if (cfg.string("coupling.backend") == "elastic" && !cfg.has("coupling.elastic")) {
    cfg.fail("coupling.backend",
             "is elastic but the section coupling.elastic (youngs_modulus, poisson_ratio) is "
             "missing");
  }
}

void check_outputs_provided(const config::Config& cfg) {
  const std::string backend = cfg.string("coupling.backend");
  const std::uint32_t provided = dem::backend_outputs(backend);
  for (const std::string& name : cfg.strings("coupling.outputs")) {
    if ((coupling_output_bit(name) & provided) == 0) {
      cfg.fail("coupling.outputs",
               list_text(cfg.strings("coupling.outputs")) + " asks for '" + name +
                   "', which backend " + backend +
                   " does not compute (it provides: " + coupling_output_names(provided) +
                   "); remove it, or use a DEM backend (native, cuda or yade)");
    }
  }
}

void check_substep_bounds(const config::Config& cfg, const std::string& backend) {
  const std::string p = "coupling." + backend + ".";
  const std::int64_t lo = cfg.integer(p + "ns_min"), hi = cfg.integer(p + "ns_max");
  if (lo > hi) {
    cfg.fail(p + "ns_min", std::to_string(lo) + " exceeds " + p + "ns_max " + std::to_string(hi) +
                               ": the fewest substeps must not exceed the most; lower ns_min "
                               "or raise ns_max");
  }
}

void check_packing_library(const config::Config& cfg, const std::string& backend) {
  const std::string p = "coupling." + backend + ".";
  const std::string dir = cfg.string(p + "packing_dir"), spec = cfg.string(p + "packing_spec");
  const std::vector<std::string> names = cfg.strings(p + "packings");
  if (!names.empty() && dir.empty()) {
    cfg.fail(p + "packings", list_text(names) + " names packings but " + p +
                                 "packing_dir is empty: give the library folder, or write "
                                 "packings: [] to build every RVE in place");
  }
  if (!dir.empty() && names.empty()) {
    cfg.fail(p + "packing_dir", "'" + dir + "' is given but " + p +
                                    "packings is empty, so the library would not be used: list "
                                    "at least one packing of it, or write packing_dir: \"\" to "
                                    "build every RVE in place");
  }
  if (!spec.empty() && dir.empty()) {
    cfg.fail(p + "packing_spec", "'" + spec + "' is given but " + p +
                                     "packing_dir is empty: name the folder the spec's "
                                     "packings go to, or remove packing_spec");
  }
}

void check_contact_law(const config::Config& cfg, const std::string& backend) {
  const std::string p = "coupling." + backend + ".";
  const double e = cfg.number(p + "restitution_normal");
  if (cfg.string(p + "contact_law") == "frict" && e != 1.0) {
    std::ostringstream v;
    v << e;
    cfg.fail(p + "restitution_normal",
             v.str() + " is given but " + p +
                 "contact_law is frict, which has no dashpot to set from it: write "
                 "contact_law: frict_visco, or remove restitution_normal");
  }
}

dem::native::ContactLaw contact_law(const config::Config& cfg, const std::string& backend) {
  check_contact_law(cfg, backend);
  const std::string p = "coupling." + backend + ".";
  // The schema accepts only the registry's names (rve_schema.cpp).
  const int id = dem::laws::find_law(cfg.string(p + "contact_law"));
  if (id == static_cast<int>(dem::native::ContactLawKind::kFrictVisco)) {
    return dem::native::frict_visco_law(cfg.number(p + "restitution_normal"));
  }
  dem::native::ContactLaw law;
  law.kind = static_cast<dem::native::ContactLawKind>(id < 0 ? 0 : id);
  return law;
}

void check_cuda_contact_law(const config::Config& cfg) {
  const std::string key = "coupling.native.contact_law";
  if (cfg.string("coupling.backend") != "cuda" || cfg.string(key) == "frict") return;
  cfg.fail(key, cfg.string(key) +
                    " is not available with backend cuda, whose batch kernel has the frict law "
                    "only: use backend native (or yade) for this law, or contact_law: frict");
}

void check_rve_backend(const config::Config& cfg, const std::string& backend) {
  check_substep_bounds(cfg, backend);
  check_packing_library(cfg, backend);
  check_contact_law(cfg, backend);
}

void check_consolidation_cache(const config::Config& cfg) {
  if (cfg.string("coupling.backend") != "native") return;
  const std::string key = "coupling.native.consolidation_cache";
  const std::string value = cfg.string(key);
  if (value.empty()) return;
  namespace fs = std::filesystem;
  fs::path dir(value);
  if (dir.is_relative()) dir = fs::path(cfg.file()).parent_path() / dir;
  dir = dir.lexically_normal();
  const std::string shown =
      "'" + value + "'" + (dir.string() == value ? "" : " (" + dir.string() + ")");
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    cfg.fail(key, shown +
                      " exists and is not a folder: name a folder (it is created if missing), "
                      "or write \"\" for no cache");
  }
  // The folder, or the nearest existing folder above it, where it will be created.
  fs::path existing = dir;
  while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.parent_path();
  if (existing.empty()) existing = ".";
  if (!fs::is_directory(existing, ec) || ::access(existing.c_str(), W_OK | X_OK) != 0) {
    cfg.fail(key, shown + ": " + existing.string() +
                      " is not a folder this user can write in: name a writable folder, or "
                      "write \"\" for no cache");
  }
}

void check_no_yade_consolidation_cache(const config::Config& cfg) {
  const std::string key = "coupling.yade.consolidation_cache";
  if (cfg.string("coupling.backend") != "yade" || cfg.string(key).empty()) return;
  cfg.fail(key, "'" + cfg.string(key) +
                    "' is given, but the YADE backend consolidates every RVE itself and keeps no "
                    "cache of consolidated states: remove the key, or use backend: native with "
                    "coupling.native.consolidation_cache");
}

void check_coupling(const config::Config& cfg) {
  check_outputs_provided(cfg);
  if (const dem::BackendSpec* b = dem::find_backend(cfg.string("coupling.backend"))) b->check(cfg);
}

}  // namespace mpmdem

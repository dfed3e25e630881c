// The `coupling:` section as dem_app reads it: the generic keys of the coupling contract
// (mpmdem/coupling_keys.hpp) and the section of each DEM backend (backend_catalog.hpp).
#include "coupling_schema.hpp"

#include "backend_catalog.hpp"
#include "mpmdem/coupling_keys.hpp"

namespace mpmdem {

void add_coupling_keys(config::Schema& s) {
  add_generic_coupling_keys(s, dem::backend_names());
  for (const dem::BackendSpec& b : dem::backend_catalog()) b.add_keys(s);
}

const config::Schema& coupling_schema() {
  static const config::Schema schema = [] {
    config::Schema s;
    add_coupling_keys(s);
    return s;
  }();
  return schema;
}

}  // namespace mpmdem

// The `coupling:` section as dem_app reads it: the generic keys of the coupling contract
// (mpmdem/coupling_keys.hpp) and the section of each DEM backend.
#include "coupling_schema.hpp"

#include "cuda_schema.hpp"
#include "elastic_schema.hpp"
#include "mpmdem/coupling_keys.hpp"
#include "native_schema.hpp"
#include "yade_schema.hpp"

namespace mpmdem {

void add_coupling_keys(config::Schema& s) {
  add_generic_coupling_keys(s, {"elastic", "yade", "native", "cuda"});
  add_elastic_keys(s);
  add_yade_keys(s);
  add_native_keys(s);
  add_cuda_keys(s);
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

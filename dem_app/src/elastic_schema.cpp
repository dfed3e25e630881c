// Keys of `coupling.elastic.*`: the material of the elastic stub backend
// (backends/elastic_backend.cpp).
#include "elastic_schema.hpp"

namespace mpmdem {

using config::key;
using config::Type;

void add_elastic_keys(config::Schema& s) {
  s.add(key("coupling.elastic", Type::kMap, "",
            "material of the elastic stub backend (required when backend is elastic)"));
  s.add(
      key("coupling.elastic.youngs_modulus", Type::kDouble, "Pa", "Young's modulus E").req().gt(0));
  s.add(key("coupling.elastic.poisson_ratio", Type::kDouble, "-", "Poisson's ratio nu")
            .req()
            .ge(0)
            .lt(0.5));
}

}  // namespace mpmdem

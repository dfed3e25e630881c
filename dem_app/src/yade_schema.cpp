// Keys of `coupling.yade.*`: the RVE backend keys (rve_schema.hpp) with YADE's packing
// library. Read by backends/yade_backend.cpp; see docs/dem_backend.md.
#include "yade_schema.hpp"

#include "rve_schema.hpp"

namespace mpmdem {

using config::key;
using config::Type;

void add_yade_keys(config::Schema& s) {
  add_rve_backend_keys(
      s, {"yade", "settings of the YADE backend (backend: yade)",
          "packing library folder written by scripts/build_packings, relative to the scene "
          "file's folder unless absolute (empty: build small packings in place from "
          "coupling.yade.inline_spheres, for tests)",
          "<name>.yade.bz2", "builds packing_dir's packings", "",
          "NewtonIntegrator non-viscous damping during coupling",
          "an upper bound of the constrained modulus built from utils.getStressAndTangent, at "
          "least the affine one: docs/dem_backend.md"});
  s.add(key("coupling.yade.consolidation_cache", Type::kString, "",
            "not available with YADE, which consolidates every RVE itself (docs/dem_backend.md, "
            "\"Consolidation once per packing and stress\"): must be empty; the native backend "
            "has it (coupling.native.consolidation_cache)")
            .def("\"\""));
}

}  // namespace mpmdem

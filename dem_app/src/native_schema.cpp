// Keys of `coupling.native.*`: the RVE backend keys (rve_schema.hpp) with native packings,
// and the Verlet skin. Read by backends/native/native_backend.cpp; the shared meaning of the
// substep and fault keys is the one of coupling.yade.* (docs/dem_backend.md).
#include "native_schema.hpp"

#include "rve_schema.hpp"

namespace mpmdem {

using config::key;
using config::Type;

void add_native_keys(config::Schema& s) {
  add_rve_backend_keys(
      s, {"native", "settings of the native (compiled) backend (backend: native)",
          "folder of native packings (<name>.native.txt, written from a YADE library by "
          "scripts/export_native_packings), relative to the scene file's folder unless "
          "absolute (empty: build small packings in place from "
          "coupling.native.inline_spheres)",
          "<name>.native.txt",
          "builds the YADE packings into packing_dir and exports them (<name>.native.txt)",
          " and of the in-place clouds",
          "Newton non-viscous damping (YADE's NewtonIntegrator.damping)",
          "the bound of the YADE backend, docs/dem_backend.md"});
  s.add(key("coupling.native.verlet_skin", Type::kDouble, "-",
            "Verlet-list skin in smallest sphere radii (YADE's collider: 0.5); results do "
            "not depend on it, only the rebuild frequency")
            .def("0.5")
            .gt(0));
  s.add(key("coupling.native.consolidation_on_failure", Type::kEnum, "",
            "what the initial consolidation does with an RVE that does not reach its stress "
            "within consolidation_max_steps: error (stop the run, naming the stress) or warn "
            "(keep the RVE as reached and count it in dem_app's log; for cost studies, and "
            "scenes whose near-surface RVEs cannot reach stresses of a few hundred Pa)")
            .def("error")
            .one_of({"error", "warn"}));
  s.add(key("coupling.native.consolidation_cache", Type::kString, "",
            "folder of consolidated RVE states (one file per packing content, stress and "
            "consolidation parameters; created if missing), relative to the scene file's "
            "folder unless absolute: a later run, and the other ranks of this one, take a "
            "stored state instead of consolidating again, with the same result; empty: none "
            "(the RVEs of a rank with equal packing and stress are still consolidated once)")
            .def("\"\""));
}

}  // namespace mpmdem

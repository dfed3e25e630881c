// Keys of `coupling.native.*`: packings, substep rule, damping, fault thresholds, initial
// consolidation, Verlet skin. Read by backends/native/native_backend.cpp; the shared meaning
// of the substep and fault keys is the one of coupling.yade.* (docs/dem_backend.md).
#include "native_schema.hpp"

namespace mpmdem {

using config::key;
using config::Type;

void add_native_keys(config::Schema& s) {
  s.add(key("coupling.native", Type::kMap, "",
            "settings of the native (compiled) backend (backend: native)"));
  s.add(key("coupling.native.packing_dir", Type::kString, "",
            "folder of native packings (<name>.native.txt, written from a YADE library by "
            "scripts/export_native_packings), relative to the scene file's folder unless "
            "absolute (empty: build small packings in place from "
            "coupling.native.inline_spheres)")
            .def("\"\""));
  s.add(key("coupling.native.packings", Type::kStringList, "",
            "packing names in packing_dir; one: every RVE uses it; several: each RVE draws "
            "one with coupling.native.seed")
            .def("[]"));
  s.add(key("coupling.native.seed", Type::kInt, "-",
            "seed of the per-RVE packing draw and of the in-place clouds")
            .def("1")
            .ge(0));
  s.add(key("coupling.native.inline_spheres", Type::kInt, "-",
            "spheres per RVE when packing_dir is empty (Table 1 material and sizes)")
            .def("60")
            .ge(2));
  s.add(key("coupling.native.ns_rule", Type::kEnum, "",
            "DEM substeps per coupling step: fixed (coupling.native.ns) or proportional "
            "(clamp(ceil(ns_factor*max|dF-I|), ns_min, ns_max))")
            .def("proportional")
            .one_of({"fixed", "proportional"}));
  s.add(key("coupling.native.ns", Type::kInt, "-", "substeps for ns_rule fixed").def("10").ge(2));
  s.add(key("coupling.native.ns_factor", Type::kDouble, "-", "substeps per unit of max|dF-I|")
            .def("1e5")
            .gt(0));
  s.add(key("coupling.native.ns_min", Type::kInt, "-", "fewest substeps (proportional rule)")
            .def("2")
            .ge(2));
  s.add(key("coupling.native.ns_max", Type::kInt, "-", "most substeps (proportional rule)")
            .def("100")
            .ge(2));
  s.add(key("coupling.native.damping", Type::kDouble, "-",
            "Newton non-viscous damping (YADE's NewtonIntegrator.damping)")
            .def("0.2")
            .ge(0)
            .lt(1));
  s.add(key("coupling.native.ke_threshold", Type::kDouble, "-",
            "an RVE explodes when its kinetic energy per volume exceeds this times its initial "
            "mean pressure")
            .def("10")
            .gt(0));
  s.add(key("coupling.native.stiffness", Type::kEnum, "",
            "stiffness estimate returned: tangent (the bound of the YADE backend, "
            "docs/dem_backend.md) or none (0)")
            .def("tangent")
            .one_of({"tangent", "none"}));
  s.add(key("coupling.native.consolidation_tol", Type::kDouble, "-",
            "relative stress tolerance of the initial consolidation to RveInit's stress")
            .def("1e-3")
            .gt(0));
  s.add(key("coupling.native.consolidation_unbalanced", Type::kDouble, "-",
            "unbalanced force below which the initial consolidation stops")
            .def("0.01")
            .gt(0));
  s.add(key("coupling.native.consolidation_max_steps", Type::kInt, "-",
            "DEM steps allowed for the initial consolidation of one RVE")
            .def("200000")
            .ge(100));
  s.add(key("coupling.native.verlet_skin", Type::kDouble, "-",
            "Verlet-list skin in smallest sphere radii (YADE's collider: 0.5); results do "
            "not depend on it, only the rebuild frequency")
            .def("0.5")
            .gt(0));
}

}  // namespace mpmdem

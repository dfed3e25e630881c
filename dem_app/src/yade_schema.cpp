// Keys of `coupling.yade.*`: packings, substep rule, damping, fault thresholds, initial
// consolidation. Read by backends/yade_backend.cpp; see docs/dem_backend.md.
#include "yade_schema.hpp"

namespace mpmdem {

using config::key;
using config::Type;

void add_yade_keys(config::Schema& s) {
  s.add(key("coupling.yade", Type::kMap, "", "settings of the YADE backend (backend: yade)"));
  s.add(key("coupling.yade.packing_dir", Type::kString, "",
            "packing library folder written by scripts/build_packings, relative to the scene "
            "file's folder unless absolute (empty: build small packings in place from "
            "coupling.yade.inline_spheres, for tests)")
            .def("\"\""));
  s.add(key("coupling.yade.packing_spec", Type::kString, "",
            "packing spec (a scripts/build_packings --config file, relative to the scene "
            "file's folder) from which scripts/run builds packing_dir's packings when they are "
            "missing; empty: none (the library must exist)")
            .def("\"\""));
  s.add(key("coupling.yade.packings", Type::kStringList, "",
            "packing names in packing_dir (<name>.yade.bz2); one: every RVE uses it; several: "
            "each RVE draws one with coupling.yade.seed")
            .def("[]"));
  s.add(key("coupling.yade.seed", Type::kInt, "-", "seed of the per-RVE packing draw")
            .def("1")
            .ge(0));
  s.add(key("coupling.yade.inline_spheres", Type::kInt, "-",
            "spheres per RVE when packing_dir is empty (Table 1 otherwise)")
            .def("60")
            .ge(2));
  s.add(key("coupling.yade.ns_rule", Type::kEnum, "",
            "DEM substeps per coupling step: fixed (coupling.yade.ns) or proportional "
            "(clamp(ceil(ns_factor*max|dF-I|), ns_min, ns_max), as YADE's FEMxDEM)")
            .def("proportional")
            .one_of({"fixed", "proportional"}));
  s.add(key("coupling.yade.ns", Type::kInt, "-", "substeps for ns_rule fixed").def("10").ge(2));
  s.add(key("coupling.yade.ns_factor", Type::kDouble, "-", "substeps per unit of max|dF-I|")
            .def("1e5")
            .gt(0));
  s.add(key("coupling.yade.ns_min", Type::kInt, "-", "fewest substeps (proportional rule)")
            .def("2")
            .ge(2));
  s.add(key("coupling.yade.ns_max", Type::kInt, "-", "most substeps (proportional rule)")
            .def("100")
            .ge(2));
  s.add(key("coupling.yade.damping", Type::kDouble, "-",
            "NewtonIntegrator non-viscous damping during coupling")
            .def("0.2")
            .ge(0)
            .lt(1));
  s.add(key("coupling.yade.ke_threshold", Type::kDouble, "-",
            "an RVE explodes when its kinetic energy per volume exceeds this times its initial "
            "mean pressure")
            .def("10")
            .gt(0));
  s.add(key("coupling.yade.stiffness", Type::kEnum, "",
            "stiffness estimate returned: tangent (an upper bound of the constrained modulus "
            "built from utils.getStressAndTangent, at least the affine one: "
            "docs/dem_backend.md) or none (0: the client uses its own bound)")
            .def("tangent")
            .one_of({"tangent", "none"}));
  s.add(key("coupling.yade.consolidation_tol", Type::kDouble, "-",
            "relative stress tolerance of the initial consolidation to RveInit's stress")
            .def("1e-3")
            .gt(0));
  s.add(key("coupling.yade.consolidation_unbalanced", Type::kDouble, "-",
            "unbalanced force below which the initial consolidation stops")
            .def("0.01")
            .gt(0));
  s.add(key("coupling.yade.consolidation_max_steps", Type::kInt, "-",
            "DEM steps allowed for the initial consolidation of one RVE")
            .def("200000")
            .ge(100));
}

}  // namespace mpmdem

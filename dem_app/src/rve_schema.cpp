// Keys shared by the RVE backends (see rve_schema.hpp).
#include "rve_schema.hpp"

#include "backends/contact_laws/registry.hpp"

namespace mpmdem {

using config::key;
using config::Type;

void add_rve_backend_keys(config::Schema& s, const RveBackendKeys& k) {
  const std::string p = "coupling." + k.backend + ".";
  s.add(key("coupling." + k.backend, Type::kMap, "", k.title));
  s.add(key(p + "packing_dir", Type::kString, "", k.packing_dir + "; needs " + p + "packings")
            .def("\"\""));
  s.add(key(p + "packing_spec", Type::kString, "",
            "packing spec (a scripts/build_packings --config file, relative to the scene "
            "file's folder) from which scripts/run " +
                k.spec_builds + " when they are missing; needs " + p +
                "packing_dir; empty: none (the library must exist)")
            .def("\"\""));
  s.add(key(p + "packings", Type::kStringList, "",
            "packing names in packing_dir (" + k.packing_file +
                "); one: every RVE uses it; several: each RVE draws one with " + p +
                "seed; needs " + p + "packing_dir")
            .def("[]"));
  s.add(key(p + "seed", Type::kInt, "-", "seed of the per-RVE packing draw" + k.seed_also)
            .def("1")
            .ge(0));
  s.add(key(p + "inline_spheres", Type::kInt, "-",
            "spheres per RVE when packing_dir is empty (Table 1 material and sizes)")
            .def("60")
            .ge(2));
  s.add(key(p + "ns_rule", Type::kEnum, "",
            "DEM substeps per coupling step: fixed (" + p +
                "ns), proportional (clamp(ceil(ns_factor*max|dF-I|), ns_min, ns_max), as "
                "YADE's FEMxDEM: a fixed strain per substep, so a rate-independent RVE) or rate "
                "(clamp(ceil(dt/dt_dem), ns_min, ns_max): the RVE strained at the MPM's rate)")
            .def("proportional")
            .one_of({"fixed", "proportional", "rate"}));
  s.add(key(p + "ns", Type::kInt, "-", "substeps for ns_rule fixed").def("10").ge(2));
  s.add(
      key(p + "ns_factor", Type::kDouble, "-", "substeps per unit of max|dF-I|").def("1e5").gt(0));
  s.add(key(p + "ns_min", Type::kInt, "-",
            "fewest substeps (proportional and rate rules), at most " + p + "ns_max")
            .def("2")
            .ge(2));
  s.add(key(p + "ns_max", Type::kInt, "-", "most substeps (proportional and rate rules)")
            .def("100")
            .ge(2));
  s.add(key(p + "damping", Type::kDouble, "-", k.damping).def("0.2").ge(0).lt(1));
  s.add(key(p + "time_step_scale", Type::kDouble, "-",
            "the DEM time step of every update is this times the packing's own (0.5 "
            "PWaveTimeStep, YADE's safety factor, stored with the packing; the initial "
            "consolidation keeps the packing's, so every value starts from the same state): "
            "below 1 to check that a result does not move with the DEM integration (the rate "
            "rule's substeps grow as 1/time_step_scale)")
            .def("1")
            .gt(0)
            .le(1));
  s.add(key(p + "ke_threshold", Type::kDouble, "-",
            "an RVE explodes when its kinetic energy per volume exceeds this times its initial "
            "mean pressure")
            .def("10")
            .gt(0));
  s.add(key(p + "stiffness", Type::kEnum, "",
            "stiffness estimate returned: tangent (" + k.stiffness_bound +
                ") or none (0: the client uses its own bound)")
            .def("tangent")
            .one_of({"tangent", "none"}));
  s.add(key(p + "contact_law", Type::kEnum, "",
            "contact law of every RVE: frict (FrictMat, Law2_ScGeom_FrictPhys_CundallStrack) or "
            "frict_visco (the same springs and slider with a normal dashpot set by " +
                p +
                "restitution_normal: FrictViscoMat, "
                "Law2_ScGeom_FrictViscoPhys_CundallStrackVisco; docs/theory_contact_law.md)")
            .def("frict")
            .one_of(dem::laws::law_names()));
  s.add(key(p + "restitution_normal", Type::kDouble, "-",
            "coefficient of normal restitution e_n of a binary collision (contact_law "
            "frict_visco; 1: no dashpot); must stay 1 with contact_law frict")
            .def("1")
            .gt(0)
            .le(1));
  s.add(key(p + "consolidation_tol", Type::kDouble, "-",
            "relative stress tolerance of the initial consolidation to RveInit's stress")
            .def("1e-3")
            .gt(0));
  s.add(key(p + "consolidation_unbalanced", Type::kDouble, "-",
            "unbalanced force below which the initial consolidation stops")
            .def("0.01")
            .gt(0));
  s.add(key(p + "consolidation_max_steps", Type::kInt, "-",
            "DEM steps allowed for the initial consolidation of one RVE")
            .def("200000")
            .ge(100));
}

}  // namespace mpmdem

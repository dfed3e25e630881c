// The scene schema: every key of a scene file, declared once (type, default, unit, doc,
// range). `mpm_app --print-config-reference` prints it; docs/configuration.md explains it.
// SI units throughout. Keys map 1:1 onto the structs of scene.hpp.
#include "config/scene_loader.hpp"
#include "constitutive/model_registry.hpp"
#include "mpmdem/coupling_keys.hpp"

namespace mpmdem::mpm {

using config::key;
using config::Type;

namespace {

void add_scene_keys(config::Schema& s) {
  s.add(key("scene", Type::kMap, "", "what this scene is"));
  s.add(key("scene.name", Type::kString, "", "short name; the file name without .yaml if empty")
            .def("''"));
  s.add(key("scene.description", Type::kString, "", "one or two sentences").def("''"));
}

void add_grid_keys(config::Schema& s) {
  s.add(
      key("grid", Type::kMap, "", "background grid: a box of cubic cells; its faces are the walls")
          .req());
  s.add(key("grid.origin", Type::kVec3, "m", "lower corner of the domain").def("[0, 0, 0]"));
  s.add(key("grid.extent", Type::kVec3, "m", "size of the domain; rounded up to whole cells")
            .req()
            .gt(0));
  s.add(key("grid.cell_size", Type::kDouble, "m", "edge of a cubic cell").req().gt(0));
}

void add_region_keys(config::Schema& s) {
  s.add(key("regions", Type::kList, "",
            "boxes filled with material points (at least one); each item is a map")
            .req());
  s.add(key("regions[].name", Type::kString, "", "label; region<i> if empty").def("''"));
  s.add(key("regions[].min", Type::kVec3, "m", "lower corner of the box").req());
  s.add(key("regions[].max", Type::kVec3, "m", "upper corner of the box").req());
  s.add(key("regions[].points_per_cell", Type::kInt, "-", "material points per cell per direction")
            .def("2")
            .ge(1)
            .le(8));
  s.add(key("regions[].points_per_cell_xyz", Type::kVec3, "-",
            "points per cell along x, y and z (integers 1-8); overrides points_per_cell, e.g. "
            "[2, 1, 2] for a plane-strain slice one cell wide"));
  s.add(key("regions[].placement", Type::kEnum, "",
            "where the points of a cell sit: cells (the centres of the n^3 sub-cells, equal "
            "volumes) or gauss (n Gauss-Legendre points per direction in every knot span of "
            "the shape functions, volumes = the Gauss weights: the point quadrature starts "
            "exact for quadratic B-splines, also in the half spans next to a wall; "
            "docs/transfers.md)")
            .def("cells")
            .one_of({"cells", "gauss"}));
  s.add(key("regions[].density", Type::kDouble, "kg/m^3", "initial mass density").req().gt(0));
  s.add(key("regions[].velocity", Type::kVec3, "m/s", "initial velocity").def("[0, 0, 0]"));
  s.add(key("regions[].sine_velocity", Type::kMap, "",
            "optional first-mode velocity v(s) = amplitude sin(pi/2 s/L), s measured along "
            "axis from the box's min face, L its length (fixed at min, free at max); added to "
            "velocity"));
  s.add(key("regions[].sine_velocity.axis", Type::kEnum, "", "direction of the velocity and of s")
            .req()
            .one_of({"x", "y", "z"}));
  s.add(key("regions[].sine_velocity.amplitude", Type::kDouble, "m/s", "velocity at the free end")
            .req());
  s.add(key("regions[].initial_stress", Type::kEnum, "",
            "none, or geostatic: sigma_v = -density |g| depth below the region's top along "
            "gravity, sigma_h = k0 sigma_v")
            .def("none")
            .one_of({"none", "geostatic"}));
  s.add(key("regions[].k0", Type::kDouble, "-", "lateral earth pressure ratio for geostatic")
            .def("1")
            .ge(0));
}

void add_wall_keys(config::Schema& s) {
  s.add(key("walls", Type::kMap, "",
            "condition on each face of the grid box: free (nothing), fixed (no-slip, a rough "
            "wall), slip (frictionless: normal velocity zero), friction (Coulomb, "
            "coefficient walls.friction)"));
  for (const char* face : {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"}) {
    s.add(key(std::string("walls.") + face, Type::kEnum, "", std::string("the ") + face + " face")
              .def("free")
              .one_of({"free", "fixed", "slip", "friction"}));
  }
  s.add(key("walls.friction", Type::kDouble, "-",
            "Coulomb friction coefficient of every friction wall")
            .def("0")
            .ge(0));
}

void add_constraint_keys(config::Schema& s) {
  s.add(key("velocity_constraints", Type::kList, "",
            "grid velocity components held at a value on the nodes inside a box (a plane if "
            "min = max along one axis) until released"));
  s.add(
      key("velocity_constraints[].name", Type::kString, "", "label, unique; constraint<i> if empty")
          .def("''"));
  s.add(key("velocity_constraints[].min", Type::kVec3, "m", "lower corner of the box").req());
  s.add(key("velocity_constraints[].max", Type::kVec3, "m", "upper corner of the box").req());
  s.add(key("velocity_constraints[].components", Type::kStringList, "",
            "velocity components held (at least one)")
            .req()
            .one_of({"x", "y", "z"}));
  s.add(key("velocity_constraints[].value", Type::kVec3, "m/s",
            "held velocity (only the listed components are used)")
            .def("[0, 0, 0]"));
  s.add(key("velocity_constraints[].release_time", Type::kDouble, "s",
            "release at this time, before solver.end_time (optional; never released if neither "
            "release key is given; with release_kinetic_ratio too, whichever comes first)")
            .ge(0));
  s.add(key("velocity_constraints[].release_kinetic_ratio", Type::kDouble, "-",
            "release when E_k / E_p0 falls below this after release_min_time (optional)")
            .gt(0));
  s.add(key("velocity_constraints[].release_min_time", Type::kDouble, "s",
            "earliest release by release_kinetic_ratio; before solver.end_time, and before "
            "release_time when that is given too")
            .def("0")
            .ge(0));
}

void add_solver_keys(config::Schema& s) {
  s.add(key("solver", Type::kMap, "", "time stepping").req());
  s.add(key("solver.scheme", Type::kEnum, "",
            "usl (stress update last) or musl (modified USL: velocities re-mapped to the grid "
            "before the stress update)")
            .def("musl")
            .one_of({"usl", "musl"}));
  s.add(key("solver.shape", Type::kEnum, "",
            "shape functions: linear (trilinear, 8 nodes) or bspline2 (quadratic B-spline, "
            "27 nodes, clamped at walls)")
            .def("linear")
            .one_of({"linear", "bspline2"}));
  s.add(key("solver.transfer", Type::kEnum, "",
            "particle-grid velocity transfer: apic (affine PIC, Jiang et al. 2015: conserves "
            "angular momentum; needs shape bspline2), pic_flip (the blend set by solver.flip; "
            "its PIC share damps every step) or xpic (extended PIC of order "
            "solver.xpic_order, Hammerquist & Nairn 2017: FLIP with the grid's null-space "
            "noise filtered out)")
            .def("pic_flip")
            .one_of({"apic", "pic_flip", "xpic"}));
  s.add(key("solver.xpic_order", Type::kInt, "-",
            "m of XPIC(m), xpic only: 1 is PIC; each order adds one grid-to-grid smoothing "
            "pass and damps resolved modes less")
            .def("4")
            .ge(1)
            .le(256));
  s.add(key("solver.flip", Type::kDouble, "-",
            "FLIP fraction of the PIC/FLIP blend (1: pure FLIP); only with transfer pic_flip")
            .def("0.99")
            .ge(0)
            .le(1));
  s.add(key("solver.flip_time_scale", Type::kDouble, "s",
            "pic_flip: the PIC share of a step is dt / flip_time_scale instead of 1 - flip, "
            "so the blend filters the velocities at a fixed rate per unit time and the result "
            "does not drift with the time step; 0: off (solver.flip). xpic: the XPIC share of "
            "a step is dt / flip_time_scale, the rest FLIP; 0: pure XPIC. apic: the point "
            "velocities take the FLIP share 1 - dt / flip_time_scale and the affine matrices "
            "stay APIC's (Fei et al. 2021); 0: pure APIC")
            .def("0")
            .ge(0));
  s.add(key("solver.flip_velocity_scale", Type::kDouble, "m/s",
            "pic_flip, xpic or apic: sets solver.flip_time_scale to grid.cell_size / "
            "flip_velocity_scale, i.e. the blend filters once per time a point moving at this "
            "speed needs to cross a cell. As flip_time_scale the result does not drift with "
            "the time step or the material's stiffness, and the filter follows the cell size "
            "as the PIC/FLIP 0.99 blend does at cfl 0.5 (1.75 m/s reproduces that blend's "
            "column collapse at 0.11 m cells: docs/transfers.md); 0: off")
            .def("0")
            .ge(0));
  s.add(key("solver.cfl", Type::kDouble, "-",
            "Courant number: dt = cfl cell_size / c, c the largest P-wave speed")
            .def("0.5")
            .gt(0)
            .le(1));
  s.add(
      key("solver.dt_max", Type::kDouble, "s", "cap on the automatic time step").def("1e-3").gt(0));
  s.add(key("solver.dt_fixed", Type::kDouble, "s",
            "fixed time step in place of the automatic (CFL) one, for stability studies: "
            "not checked against the CFL limit (a warning says when it exceeds it), below "
            "solver.end_time; 0: automatic")
            .def("0")
            .ge(0));
  s.add(key("solver.end_time", Type::kDouble, "s", "simulated time to run").req().gt(0));
  s.add(key("solver.gravity", Type::kVec3, "m/s^2", "gravitational acceleration")
            .def("[0, 0, -9.81]"));
  s.add(key("solver.local_damping", Type::kDouble, "-",
            "Cundall local (non-viscous) damping coefficient on the grid forces")
            .def("0")
            .ge(0)
            .lt(1));
  s.add(key("solver.on_exit", Type::kEnum, "",
            "a material point leaving the grid: error (stop, naming point and step) or remove")
            .def("error")
            .one_of({"error", "remove"}));
  s.add(key("solver.threads", Type::kInt, "-", "OpenMP threads; 0: the OpenMP default")
            .def("0")
            .ge(0)
            .le(1024));
}

void add_constitutive_keys(config::Schema& s) {
  s.add(key("constitutive", Type::kMap, "", "stress at the material points").req());
  add_constitutive_model_keys(s);  // constitutive.model and each local model's section
}

void add_output_keys(config::Schema& s) {
  s.add(key("output", Type::kMap, "", "files written to the run directory"));
  s.add(key("output.interval", Type::kDouble, "s",
            "simulated time between VTK frames; 0: first and last only")
            .def("0")
            .ge(0));
  s.add(key("output.energy_interval", Type::kDouble, "s",
            "simulated time between rows of energies.csv; 0: every step")
            .def("0")
            .ge(0));
  s.add(key("output.vtk", Type::kBool, "", "write .vtu frames and a .pvd series").def("true"));
  s.add(key("output.hdf5", Type::kBool, "", "write the final state to HDF5").def("true"));
  s.add(key("output.rve_costs", Type::kBool, "",
            "remote model: write rve_costs.csv (each point's RVE backend time per step) and "
            "rve_ranks.csv (the server rank of each point), for load-balance analysis")
            .def("false"));
  s.add(key("output.checkpoint_interval_steps", Type::kInt, "-",
            "write a checkpoint of both sides every this many steps (checkpoints/step_<n>/; "
            "scripts/run --resume RUN continues from the newest complete one); 0: none")
            .def("0")
            .ge(0));
  s.add(key("output.checkpoint_interval_s", Type::kDouble, "s",
            "also write a checkpoint once this much wall time has passed since the last one, "
            "and at least 49 times the time the last one took, so that they cost <= 2 % of "
            "the run (mpm_app decides after a step and both sides save that step; with "
            "checkpoint_interval_steps, whichever comes first); 0: no time-triggered "
            "checkpoints")
            .def("60")
            .ge(0));
  s.add(key("output.checkpoints_kept", Type::kInt, "-",
            "newest complete checkpoints kept (older ones are removed)")
            .def("2")
            .ge(1));
  s.add(key("output.progress_interval_s", Type::kDouble, "s",
            "wall time between progress lines on the terminal")
            .def("2")
            .gt(0));
}

void add_verification_keys(config::Schema& s) {
  s.add(key("verification", Type::kMap, "", "analytic comparison written to summary.json"));
  s.add(key("verification.kind", Type::kEnum, "",
            "elastic_column: stress profile and settlement under self-weight (gravity along "
            "-z); bar_vibration: period of the first axial mode. With the remote model both "
            "need coupling.backend elastic (known moduli)")
            .def("none")
            .one_of({"none", "elastic_column", "bar_vibration"}));
}

void add_column_collapse_keys(config::Schema& s) {
  s.add(key("column_collapse", Type::kMap, "",
            "granular column collapse analysis (two stages, runout, final height, energies, "
            "snapshots; see analysis/column_collapse.hpp). Gravity must point along -z and "
            "the column must stand on the z_min face against the x_min face, neither of them "
            "free"));
  s.add(
      key("column_collapse.region", Type::kString, "", "the column region; empty: the first region")
          .def("''"));
  s.add(key("column_collapse.release_constraint", Type::kString, "",
            "velocity constraint holding the lateral free surface in stage 1, which needs a "
            "release rule; its release starts stage 2 (empty: the first constraint; none: "
            "stage 2 from t = 0)")
            .def("''"));
  s.add(key("column_collapse.duration_t_star", Type::kDouble, "t*",
            "stage-2 length in units of t* = sqrt(H_i/|g|); the run ends then "
            "(solver.end_time stays a cap)")
            .def("6")
            .gt(0));
  s.add(key("column_collapse.snapshots_t_star", Type::kNumberList, "t*",
            "stage-2 times (in t*, increasing, at most duration_t_star; any number of them, [] "
            "for none) at which the state is saved to snapshots/t_star_<k>.h5 for the pictures")
            .def("[1, 3, 6]")
            .ge(0));
  s.add(key("column_collapse.at_rest", Type::kMap, "",
            "optional: end stage 2 once the deposit is at rest, i.e. E_k/E_p0 (E_p0 at the "
            "release, from the base) stayed below kinetic_ratio for hold_t_star without a "
            "break, not before min_t_star; duration_t_star stays the cap. summary.json's "
            "stop says whether and when (docs/column_collapse.md)"));
  s.add(key("column_collapse.at_rest.kinetic_ratio", Type::kDouble, "-", "threshold on E_k/E_p0")
            .req()
            .gt(0)
            .lt(1));
  s.add(key("column_collapse.at_rest.hold_t_star", Type::kDouble, "t*",
            "how long E_k/E_p0 must stay below the threshold; any step at or above it restarts "
            "the wait")
            .req()
            .gt(0));
  s.add(key("column_collapse.at_rest.min_t_star", Type::kDouble, "t*",
            "earliest stage-2 time of the stop (the column is also at rest just after its "
            "release)")
            .def("1")
            .ge(0));
}

}  // namespace

const config::Schema& scene_schema() {
  static const config::Schema schema = [] {
    config::Schema s;
    add_scene_keys(s);
    add_grid_keys(s);
    add_region_keys(s);
    add_wall_keys(s);
    add_constraint_keys(s);
    add_solver_keys(s);
    add_constitutive_keys(s);
    add_generic_coupling_keys(s, {});  // the backends' sections: dem_app validates them
    add_output_keys(s);
    add_verification_keys(s);
    add_column_collapse_keys(s);
    return s;
  }();
  return schema;
}

}  // namespace mpmdem::mpm

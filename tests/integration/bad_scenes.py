#!/usr/bin/python3
"""Validation is complete before anything runs (issue 35, item 3).

A corpus of scenes, each a shipped scene (configs/) with one change that breaks one rule
either program enforces (a key alone, or keys against each other: min/max pairs, lists that
need an item, schedules that cannot happen within solver.end_time, references between
sections). Each goes through scripts/run, which must refuse it in its up-front check:
  - exit code 2;
  - a message naming the key (dotted path), the scene file and the line of the key (or, for
    a key the file does not hold, of its section);
  - nothing written: run once with --out (not created) and once without (the default run
    folder under MPMDEM_RUNS_DIR: left empty);
  - nothing run: mpm_app and dem_app are only asked to check (the test's MPMDEM_BUILD_DIR
    holds wrappers that log each call), and mpirun / ompi-server are never started (PATH
    shims that log a call).
Each base scene is first shown to pass both programs' checks, so each case fails only for
its own change. The scenes are written (with a header naming the rule and the key) by
scripts/lib/scene_overrides.py into a temporary folder; relative packing paths become
absolute, and the DEM bases carry packing_spec "" so that a case that got through by mistake
could never start a packing build.
Usage: bad_scenes.py BUILD_DIR SOURCE_DIR [CASE ...]
"""
import os
import shutil
import stat
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

bin_dir, src = Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve()
only = sys.argv[3:]
sys.path.insert(0, str(src / "scripts" / "lib"))
from scene_overrides import derive_scene  # noqa: E402

# Base scenes: a shipped file and the overrides every case derived from it carries.
BASES = {
    "mc": ("configs/column_collapse_mc.yaml", {}),            # local Drucker-Prager column
    "mu_i": ("configs/column_collapse_mc_mu_i.yaml", {}),     # ... with mu(I)
    "apic": ("configs/column_collapse_mc_apic.yaml", {}),     # ... with APIC
    "elastic": ("configs/elastic_column.yaml", {}),           # local elastic, verification
    "remote": ("configs/elastic_column_remote.yaml", {}),     # remote, elastic backend
    "native": ("configs/column_collapse_3d.yaml",             # remote, native backend
               {"coupling.native.packing_spec": ""}),
    "yade": ("configs/column_collapse.yaml",                  # remote, YADE backend
             {"coupling.yade.packing_spec": ""}),
    "yade_inline": ("configs/stability/free_fall_yade.yaml", {}),  # YADE, in-place packings
}

MC_CONSTRAINT = {"name": "lateral_face", "min": [0.55, 0.0, 0.0], "max": [0.55, 0.11, 1.43],
                 "components": ["x"], "release_kinetic_ratio": 1.0e-4,
                 "release_min_time": 0.05, "release_time": 0.5}
MC_REGION = {"name": "column", "min": [0.0, 0.0, 0.0], "max": [0.55, 0.11, 1.32],
             "points_per_cell_xyz": [2, 1, 2], "placement": "gauss", "density": 1400.0,
             "initial_stress": "geostatic", "k0": 0.7}

# name: (base, rule, key the message must name, overrides)
CASES = {
    # -- regions ---------------------------------------------------------------------------
    "regions_empty": ("mc", "list needs an item: regions lists at least one region",
                      "regions", {"regions": []}),
    "region_max_below_min": ("mc", "min/max pair: regions[].max > min in every component",
                             "regions[0].max", {"regions.0.max": [0.55, 0.11, -0.1]}),
    "region_outside_domain": ("mc", "regions[] boxes lie inside the grid domain",
                              "regions[0].max", {"regions.0.max": [0.55, 0.11, 2.0]}),
    "region_names_repeat": ("mc", "reference: regions[].name are unique", "regions[1].name",
                            {"regions": [MC_REGION, dict(MC_REGION, min=[2.2, 0.0, 0.0],
                                                         max=[2.42, 0.11, 0.22])]}),
    "region_thinner_than_a_point": ("mc", "a region is at least one point spacing thick",
                                    "regions[0]", {"regions.0.max": [0.55, 0.11, 0.01]}),
    "points_per_cell_xyz_fraction": ("mc", "regions[].points_per_cell_xyz holds integers 1-8",
                                     "regions[0].points_per_cell_xyz",
                                     {"regions.0.points_per_cell_xyz": [2, 1.5, 2]}),
    "grid_too_many_cells": ("elastic", "grid.cell_size gives at most 2e8 cells",
                            "grid.cell_size", {"grid.cell_size": 1.0e-4}),
    # -- velocity constraints -----------------------------------------------------------------
    "constraint_components_empty": ("mc", "list needs an item: components lists x, y or z",
                                    "velocity_constraints[0].components",
                                    {"velocity_constraints.0.components": []}),
    "constraint_max_below_min": ("mc", "min/max pair: velocity_constraints[].max >= min",
                                 "velocity_constraints[0].max",
                                 {"velocity_constraints.0.max": [0.5, 0.11, 1.43]}),
    "constraint_without_grid_node": ("mc", "a velocity constraint contains a grid node",
                                     "velocity_constraints[0]",
                                     {"velocity_constraints.0.min": [0.6, 0.0, 0.0],
                                      "velocity_constraints.0.max": [0.6, 0.11, 1.43]}),
    "release_min_time_without_ratio": ("mc", "release_min_time only with release_kinetic_ratio",
                                       "velocity_constraints[0].release_min_time",
                                       {"velocity_constraints.0.release_kinetic_ratio": None}),
    "constraint_names_repeat": ("mc", "reference: velocity_constraints[].name are unique",
                                "velocity_constraints[1].name",
                                {"velocity_constraints": [MC_CONSTRAINT, MC_CONSTRAINT]}),
    "release_min_time_after_release_time": ("mc", "pair: release_min_time < release_time",
                                            "velocity_constraints[0].release_min_time",
                                            {"velocity_constraints.0.release_min_time": 0.6}),
    "release_after_end_time": ("mc", "schedule: the earliest release is before "
                               "solver.end_time", "velocity_constraints[0].release_min_time",
                               {"solver.end_time": 0.04}),
    # -- walls and solver ---------------------------------------------------------------------
    "friction_wall_without_friction": ("mc", "a friction wall needs walls.friction > 0",
                                       "walls.friction", {"walls.z_min": "friction"}),
    "flip_with_xpic": ("elastic", "solver.flip only with transfer pic_flip", "solver.flip",
                       {"solver.transfer": "xpic"}),
    "xpic_order_with_pic_flip": ("elastic", "solver.xpic_order only with transfer xpic",
                                 "solver.xpic_order", {"solver.xpic_order": 4}),
    "apic_with_linear_shape": ("apic", "transfer apic needs shape bspline2", "solver.transfer",
                               {"solver.shape": "linear"}),
    "flip_and_flip_velocity_scale": ("mc", "solver.flip_velocity_scale replaces solver.flip",
                                     "solver.flip_velocity_scale", {"solver.flip": 0.99}),
    "flip_time_and_velocity_scale": ("mc", "flip_velocity_scale sets flip_time_scale: not both",
                                     "solver.flip_velocity_scale",
                                     {"solver.flip_time_scale": 0.03}),
    "dt_fixed_beyond_end_time": ("elastic", "schedule: solver.dt_fixed < solver.end_time",
                                 "solver.dt_fixed", {"solver.dt_fixed": 1.0}),
    # -- constitutive ---------------------------------------------------------------------------
    "remote_without_coupling": ("mc", "reference: model remote needs a coupling: section",
                                "constitutive.model", {"constitutive.model": "remote"}),
    "drucker_prager_without_section": ("elastic", "reference: model drucker_prager needs "
                                       "constitutive.drucker_prager", "constitutive.model",
                                       {"constitutive.model": "drucker_prager"}),
    "dilation_above_friction": ("mc", "pair: dilation_angle_deg <= friction_angle_deg",
                                "constitutive.drucker_prager.dilation_angle_deg",
                                {"constitutive.drucker_prager.dilation_angle_deg": 25}),
    "mu_i_limit_angle_not_above": ("mu_i", "pair: mu_i.friction_angle_2_deg > "
                                   "friction_angle_deg",
                                   "constitutive.drucker_prager.mu_i.friction_angle_2_deg",
                                   {"constitutive.drucker_prager.mu_i.friction_angle_2_deg": 15}),
    "disconnection_ratio_below_one": ("mc", "disconnection_volume_ratio is 0 or > 1",
                                      "constitutive.drucker_prager.disconnection_volume_ratio",
                                      {"constitutive.drucker_prager.disconnection_volume_ratio":
                                       0.9}),
    # -- outputs, verification ------------------------------------------------------------------
    "rve_costs_without_remote": ("elastic", "reference: output.rve_costs needs model remote",
                                 "output.rve_costs", {"output.rve_costs": True}),
    "elastic_column_gravity_sideways": ("elastic", "verification elastic_column needs gravity "
                                        "along -z", "solver.gravity",
                                        {"solver.gravity": [0.0, -9.81, 0.0]}),
    "verification_with_dem_backend": ("remote", "reference: verification with model remote "
                                      "needs coupling.backend elastic", "verification.kind",
                                      {"coupling.backend": "native"}),
    # -- column_collapse ----------------------------------------------------------------------
    "snapshots_not_increasing": ("mc", "column_collapse.snapshots_t_star increase",
                                 "column_collapse.snapshots_t_star",
                                 {"column_collapse.snapshots_t_star": [1, 3, 2]}),
    "snapshot_after_duration": ("mc", "schedule: snapshots_t_star <= duration_t_star",
                                "column_collapse.snapshots_t_star",
                                {"column_collapse.snapshots_t_star": [1, 3, 8]}),
    "at_rest_after_duration": ("mc", "schedule: at_rest.min_t_star < duration_t_star",
                               "column_collapse.at_rest.min_t_star",
                               {"column_collapse.at_rest.min_t_star": 6}),
    "column_region_unknown": ("mc", "reference: column_collapse.region names a region",
                              "column_collapse.region", {"column_collapse.region": "pile"}),
    "release_constraint_unknown": ("mc", "reference: release_constraint names a constraint",
                                   "column_collapse.release_constraint",
                                   {"column_collapse.release_constraint": "gate"}),
    "release_constraint_none_ambiguous": ("mc", "reference: release_constraint none while a "
                                          "constraint is named none",
                                          "column_collapse.release_constraint",
                                          {"velocity_constraints.0.name": "none",
                                           "column_collapse.release_constraint": "none"}),
    "column_never_released": ("mc", "schedule: the column's release constraint has a release "
                              "rule", "velocity_constraints[0]",
                              {"velocity_constraints.0.release_kinetic_ratio": None,
                               "velocity_constraints.0.release_min_time": None,
                               "velocity_constraints.0.release_time": None}),
    "column_off_the_base": ("mc", "the column region stands on the base (min z = origin z)",
                            "regions[0].min", {"regions.0.min": [0.0, 0.0, 0.11]}),
    "column_off_the_back_wall": ("mc", "the column region touches the back wall (min x = "
                                 "origin x)", "regions[0].min",
                                 {"regions.0.min": [0.11, 0.0, 0.0]}),
    "column_free_base": ("mc", "reference: the column's base wall walls.z_min is not free",
                         "walls.z_min", {"walls.z_min": "free"}),
    "column_gravity_sideways": ("mc", "column_collapse needs gravity along -z",
                                "solver.gravity", {"solver.gravity": [-9.81, 0.0, 0.0]}),
    # -- coupling (both programs) ---------------------------------------------------------------
    "elastic_backend_without_section": ("remote", "reference: backend elastic needs "
                                        "coupling.elastic", "coupling.backend",
                                        {"coupling.elastic": None}),
    "outputs_the_backend_lacks": ("remote", "reference: coupling.outputs are computed by the "
                                  "backend", "coupling.outputs",
                                  {"coupling.outputs": ["porosity"]}),
    "service_name_empty": ("remote", "coupling.service_name is not empty",
                           "coupling.service_name", {"coupling.service_name": ""}),
    "substeps_min_above_max": ("native", "min/max pair: ns_min <= ns_max",
                               "coupling.native.ns_min", {"coupling.native.ns_min": 200}),
    "packings_without_packing_dir": ("yade", "reference: packings need a packing_dir",
                                     "coupling.yade.packings", {"coupling.yade.packing_dir": ""}),
    "packing_dir_without_packings": ("native", "list needs an item: a packing_dir needs "
                                     "packings", "coupling.native.packing_dir",
                                     {"coupling.native.packings": []}),
    "packing_spec_without_packing_dir": ("yade_inline", "reference: packing_spec needs a "
                                         "packing_dir", "coupling.yade.packing_spec",
                                         {"coupling.yade.packing_spec": "packings/x.yaml"}),
    "packings_not_in_library": ("native", "reference (files): the named packings exist in "
                                "packing_dir, or a packing_spec builds them",
                                "coupling.native.packings",
                                {"coupling.native.packing_dir": "/nonexistent/packings"}),
    "packing_spec_file_missing": ("native", "reference (files): a packing_spec that must build "
                                  "missing packings exists", "coupling.native.packing_spec",
                                  {"coupling.native.packing_dir": "/nonexistent/packings",
                                   "coupling.native.packing_spec": "no_such_spec.yaml"}),
    "consolidation_on_failure_unknown": ("native", "coupling.native.consolidation_on_failure "
                                         "is error or warn",
                                         "coupling.native.consolidation_on_failure",
                                         {"coupling.native.consolidation_on_failure": "ignore"}),
    "consolidation_cache_a_file": ("native", "reference (files): consolidation_cache is a folder "
                                   "or can be made one", "coupling.native.consolidation_cache",
                                   {"coupling.native.consolidation_cache": str(src / "README.md")}),
    "consolidation_cache_yade": ("yade", "the YADE backend keeps no consolidation cache",
                                 "coupling.yade.consolidation_cache",
                                 {"coupling.yade.consolidation_cache": "cache"}),
}


def key_line(text, key):
    """1-based line of `key` ("velocity_constraints[0].release_time") in the YAML text, or of
    its nearest present section (what the programs report for a key the file lacks)."""
    node = yaml.compose(text)
    line = node.start_mark.line + 1
    for part in key.split("."):
        name, index = part, None
        if part.endswith("]"):
            name, index = part[:-1].split("[")
        if not isinstance(node, yaml.MappingNode):
            break
        found = [(k, v) for k, v in node.value if k.value == name]
        if not found:
            break
        k, node = found[0]
        line = k.start_mark.line + 1
        if index is not None:
            if not isinstance(node, yaml.SequenceNode) or int(index) >= len(node.value):
                break
            node = node.value[int(index)]
            line = node.start_mark.line + 1
    return line


def wrapper(path, real, log):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(f'#!/bin/sh\necho "$(basename "$0") $*" >>"{log}"\n'
                    + (f'exec "{real}" "$@"\n' if real else "exit 97\n"))
    path.chmod(path.stat().st_mode | stat.S_IEXEC)


work = Path(tempfile.mkdtemp(prefix="bad_scenes_"))
fails = []
start = time.monotonic()
try:
    # The build seen by scripts/run: wrappers around the real programs that log each call.
    calls = work / "calls.log"
    build = work / "build"
    for prog in ("mpm_app", "dem_app"):
        wrapper(build / prog / prog, bin_dir / prog / prog, calls)
    shims = work / "shims"
    for prog in ("mpirun", "ompi-server"):
        wrapper(shims / prog, None, calls)
    env = dict(os.environ, MPMDEM_SKIP_SETUP="1", MPMDEM_BUILD_DIR=str(build),
               PATH=f"{shims}:{os.environ['PATH']}")

    # Every base passes both programs' checks: each case fails for its own change only.
    for name, (rel, overrides) in BASES.items():
        scene = derive_scene(src / rel, overrides, work / "bases" / f"{name}.yaml", "base")
        for cmd in ([bin_dir / "mpm_app" / "mpm_app", "--check-config", scene],
                    [bin_dir / "dem_app" / "dem_app", "--check-config", scene]):
            if "dem_app" in str(cmd[0]) and "coupling" not in yaml.safe_load(scene.read_text()):
                continue
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
            if p.returncode != 0:
                fails.append(f"base {name} ({rel}) is refused by {cmd[0].name}: {p.stderr.strip()}")
    rules = {rule for _, rule, _, _ in CASES.values()}
    assert len(rules) == len(CASES), "two cases test the same rule"

    for name, (base, rule, key, overrides) in CASES.items():
        if only and name not in only:
            continue
        rel, base_overrides = BASES[base]
        scene = derive_scene(src / rel, {**base_overrides, **overrides},
                             work / "scenes" / f"{name}.yaml", f"rule: {rule}; key: {key}")
        where = f"{scene} line {key_line(scene.read_text(), key)}"
        # Twice: into --out, and into a default run folder under MPMDEM_RUNS_DIR.
        for how in ("--out", "default"):
            out, runs = work / "out" / how / name, work / "runs" / how / name
            runs.mkdir(parents=True)
            calls.write_text("")
            cmd = [src / "scripts" / "run", scene, "--max-steps", "1"]
            cmd += ["--out", out] if how == "--out" else []
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=60,
                               env=dict(env, MPMDEM_RUNS_DIR=str(runs)))
            msg = (p.stdout + p.stderr).strip()
            problems = []
            if p.returncode != 2:
                problems.append(f"exit {p.returncode}, not 2")
            if key not in msg:
                problems.append(f"message does not name {key}")
            if where not in msg:
                problems.append(f"message does not say '{where}'")
            if out.exists():
                problems.append(f"created {out}")
            if any(runs.iterdir()):
                problems.append(f"wrote into MPMDEM_RUNS_DIR: {sorted(os.listdir(runs))}")
            ran = [c for c in calls.read_text().splitlines()
                   if c.split()[1:2] not in (["--check-config"], ["--print-model"],
                                             ["--print-backend"])]
            if ran:
                problems.append(f"started {ran}")
            if problems:
                fails.append(f"{name} ({rule}), {how}: {'; '.join(problems)}\n      {msg[-400:]}")
            elif how == "--out":
                print(f"ok  {name:38s} {msg.splitlines()[-1][:150]}")
finally:
    shutil.rmtree(work, ignore_errors=True)

seconds = time.monotonic() - start
if fails:
    print("FAIL:\n  " + "\n  ".join(fails))
    sys.exit(1)
print(f"bad_scenes: {len(CASES) if not only else len(only)} scenes, each breaking a different "
      f"rule, refused by scripts/run's check with exit 2, key, file and line; nothing written, "
      f"nothing started ({seconds:.1f} s)")

"""scripts/grid_convergence_study: the local column's convergence in cell size and points per
cell for each base, with the Richardson analysis of each figure (see the script's header)."""
import math
import os
import sys

import yaml

from .. import launch
from ..convergence import richardson_text
from ..entry import parse_options
from ..sweep import StudySpec, Variant, copy_doc, sweep
from . import prepare

STUDY = "grid_convergence_study"
MU_BASE = 0.52  # grain friction (Table 1), walls.friction of the friction base
FIGS = [("runout_m", "runout (m)"), ("runout_front_m", "connected front (m)"),
        ("runout_mass99_m", "99 % of the mass within (m)"),
        ("final_height_m", "H_f (m)"), ("Ed_over_Ep0", "E_d/E_p0")]


def main(argv, script):
    o = parse_options(argv, STUDY, script,
                      {"out": "", "scene": str(launch.ROOT / "configs/column_collapse_mc.yaml"),
                       "cells": "0.11 0.055 0.0275", "ppc": "2 3", "bases": "fixed,friction",
                       "solver": []}, repeatable=("solver",))
    try:
        app, scene, out = prepare(STUDY, o, subdir="runs")
    except launch.LaunchError as e:
        return e.code
    return study(app, scene, out, o["cells"], o["ppc"], o["bases"], o["solver"])


def study(app, scene, out, cells_arg, ppc_arg, bases_arg, solver_args):
    from column_study import set_solver  # scripts/lib

    cells = [float(h) for h in cells_arg.split()]
    ppcs = [int(n) for n in ppc_arg.split()]
    bases = [b for b in bases_arg.split(",") if b]
    for b in bases:
        if b not in ("fixed", "friction", "slip"):
            sys.exit(f"{STUDY}: unknown base '{b}' (fixed, friction, slip)")
    solver = {}
    for kv in solver_args:
        if "=" not in kv:
            sys.exit(f"{STUDY}: --solver takes KEY=VALUE, got '{kv}'")
        k, v = kv.split("=", 1)
        solver[k] = yaml.safe_load(v)
    if any(abs(cells[i + 1] - cells[i] / 2) > 1e-12 for i in range(len(cells) - 1)):
        sys.exit(f"{STUDY}: --cells must halve from one size to the next, got {cells}")
    base = yaml.safe_load(open(scene))
    # Domain length [m]: longer than any runout measured with the shipped transfer
    # (docs/transfers.md), or the scene's own if longer.
    length = max(4.4, base["grid"]["extent"][0])
    col = base["column_collapse"]
    region_name = col.get("region") or base["regions"][0].get("name")
    constraint_name = col.get("release_constraint") or base["velocity_constraints"][0].get("name")

    def make_scene(h, n, wall):
        c = copy_doc(base)
        g = c["grid"]
        g["cell_size"] = h
        g["extent"] = [length, h, math.ceil(g["extent"][2] / h - 1e-9) * h]
        r = next(r for r in c["regions"] if r.get("name") == region_name)
        r["max"][1] = h
        r["points_per_cell_xyz"] = [n, 1, n]
        k = next(k for k in c["velocity_constraints"] if k.get("name") == constraint_name)
        k["max"] = [k["max"][0], h, g["extent"][2]]
        for key in ("x_min", "x_max", "z_min"):
            if key in c["walls"] and c["walls"][key] == "friction":
                c["walls"][key] = "slip"
        c["walls"]["z_min"] = wall
        c["walls"].pop("friction", None)
        if wall == "friction":
            c["walls"]["friction"] = MU_BASE
        set_solver(c, solver)
        c["output"] = {"interval": 0, "energy_interval": 0.005, "vtk": False,
                       "progress_interval_s": 1000, "checkpoint_interval_s": 0}
        return c

    variants = [Variant(f"{wall}_ppc{n}_h{h:g}", make_scene(h, n, wall),
                        dict(base=wall, ppc=n, h=h))
                for wall in bases for n in ppcs for h in cells]

    def metrics(v, s):
        return dict(v.info, runout_m=s["runout_m"], runout_front_m=s["runout_front_m"],
                    detached=s["runout_front_detached_mass_fraction"],
                    runout_mass99_m=s["runout_mass99_m"], final_height_m=s["final_height_m"],
                    Ed_over_Ep0=s["Ed_over_Ep0_final"],
                    Eerr_over_released=s["Eerr_over_released"],
                    Etransfer_over_released=s["Etransfer_over_released"],
                    Etransfer_walls_over_released=s["Etransfer_walls_over_released"],
                    stop=s["stop"]["reason"], t_over_tstar=s["time_over_t_star_final"],
                    steps=s["steps"], points=s["n_material_points"], cpu_s=s["step_cpu_time_s"])

    def report(rows):
        lines = [f"Scene {os.path.basename(scene)}" + (f", solver {solver}" if solver else "") +
                 f"; cells {' / '.join(f'{h:g}' for h in cells)} m.", "",
                 "| base | points/cell | h (m) | runout (m) | front (m) | detached mass "
                 "| 99 % mass (m) | H_f (m) | E_d/E_p0 | E_err/released (transfers [of it at "
                 "the walls] + other) | stop (t/t*) | steps | points | CPU (s) |",
                 "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in rows:
            lines.append(f"| {r['base']} | {r['ppc']} | {r['h']:g} | {r['runout_m']:.3f} "
                         f"| {r['runout_front_m']:.3f} | {100 * r['detached']:.2f} % "
                         f"| {r['runout_mass99_m']:.3f} "
                         f"| {r['final_height_m']:.3f} | {r['Ed_over_Ep0']:.3f} "
                         f"| {100 * r['Eerr_over_released']:.1f} % "
                         f"({100 * r['Etransfer_over_released']:.1f} "
                         f"[{100 * r['Etransfer_walls_over_released']:.1f}] "
                         f"{100 * (r['Eerr_over_released'] - r['Etransfer_over_released']):+.1f} %) "
                         f"| {r['stop']} ({r['t_over_tstar']:.2f}) "
                         f"| {r['steps']} | {r['points']} | {r['cpu_s']:.1f} |")
        # Richardson over each three consecutive cell sizes (with four sizes: the coarse and
        # the fine triplet, to see whether the order settles as h falls).
        for i in range(len(cells) - 2):
            trip = cells[i:i + 3]
            lines += ["", "Richardson analysis over the cell sizes "
                      f"{' / '.join(f'{h:g}' for h in trip)} m (observed order p, extrapolated "
                      "value, GCI of the finest grid):", "",
                      "| base | points/cell | figure | values coarse → fine | p | extrapolated "
                      "| GCI |",
                      "|---|---|---|---|---|---|---|"]
            for wall in bases:
                for n in ppcs:
                    sel = [r for r in rows if r["base"] == wall and r["ppc"] == n][i:i + 3]
                    for key, label in FIGS:
                        vals = [r[key] for r in sel]
                        p, ext, gci = richardson_text(vals)
                        lines.append(f"| {wall} | {n} | {label} "
                                     f"| {' / '.join(f'{v:.3f}' for v in vals)} "
                                     f"| {p} | {ext} | {gci} |")
        return "\n".join(lines) + "\n"

    sweep(StudySpec(STUDY, variants, metrics, report), app, out)
    print(f"results: {out}")
    return 0

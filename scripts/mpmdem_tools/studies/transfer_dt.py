"""scripts/transfer_dt_study: the local column's time-step dependence under each
particle-grid transfer (solver.cfl 0.5, 0.25, 0.125; see the script's header)."""
import os

import yaml

from .. import launch
from ..entry import fail, parse_options
from ..sweep import StudySpec, Variant, copy_doc, sweep
from . import prepare

STUDY = "transfer_dt_study"
# label -> solver keys replacing the scene's shape/transfer/flip keys (and "placement", set
# on every region)
SCHEMES = [
    ("linear, PIC/FLIP, flip_velocity_scale 1.75 m/s",
     {"shape": "linear", "transfer": "pic_flip", "flip_velocity_scale": 1.75}),
    ("linear, PIC/FLIP 0.99 (shipped until 2026-11-25)",
     {"shape": "linear", "transfer": "pic_flip", "flip": 0.99}),
    ("linear, pure FLIP", {"shape": "linear", "transfer": "pic_flip", "flip": 1.0}),
    ("linear, PIC/FLIP, flip_time_scale 0.1 s",
     {"shape": "linear", "transfer": "pic_flip", "flip_time_scale": 0.1}),
    ("linear, PIC/FLIP, flip_time_scale 0.03 s",
     {"shape": "linear", "transfer": "pic_flip", "flip_time_scale": 0.03}),
    ("bspline2 (clamped), PIC/FLIP 0.99",
     {"shape": "bspline2", "transfer": "pic_flip", "flip": 0.99}),
    ("bspline2 (clamped), APIC", {"shape": "bspline2", "transfer": "apic"}),
    ("bspline2 (clamped), APIC, USL", {"shape": "bspline2", "transfer": "apic", "scheme": "usl"}),
    ("linear, PIC (flip 0)", {"shape": "linear", "transfer": "pic_flip", "flip": 0.0}),
    ("linear, XPIC(2)", {"shape": "linear", "transfer": "xpic", "xpic_order": 2}),
    ("linear, XPIC(4)", {"shape": "linear", "transfer": "xpic", "xpic_order": 4}),
    ("linear, XPIC(8)", {"shape": "linear", "transfer": "xpic", "xpic_order": 8}),
    ("linear, XPIC(16)", {"shape": "linear", "transfer": "xpic", "xpic_order": 16}),
    ("linear, XPIC(64)", {"shape": "linear", "transfer": "xpic", "xpic_order": 64}),
    ("linear, XPIC(4), flip_time_scale 0.03 s",
     {"shape": "linear", "transfer": "xpic", "xpic_order": 4, "flip_time_scale": 0.03}),
    ("linear, XPIC(4), flip_time_scale 0.1 s",
     {"shape": "linear", "transfer": "xpic", "xpic_order": 4, "flip_time_scale": 0.1}),
    ("linear, XPIC(1), flip_time_scale 0.1 s",
     {"shape": "linear", "transfer": "xpic", "xpic_order": 1, "flip_time_scale": 0.1}),
    ("bspline2 (clamped), XPIC(4)", {"shape": "bspline2", "transfer": "xpic", "xpic_order": 4}),
    ("bspline2 (clamped), flip_velocity_scale 1.75 m/s",
     {"shape": "bspline2", "transfer": "pic_flip", "flip_velocity_scale": 1.75}),
    ("bspline2 (clamped), flip_velocity_scale 1.75 m/s, placement gauss",
     {"shape": "bspline2", "transfer": "pic_flip", "flip_velocity_scale": 1.75,
      "placement": "gauss"}),
    ("bspline2 (clamped), flip_velocity_scale 1.75 m/s, placement gauss, USL (shipped)",
     {"shape": "bspline2", "transfer": "pic_flip", "flip_velocity_scale": 1.75,
      "placement": "gauss", "scheme": "usl"}),
    # With --scene configs/column_collapse_mc_apic.yaml: the disconnected state on.
    ("bspline2 (clamped), APIC + FLIP share (flip_velocity_scale 1.75 m/s), placement gauss, "
     "USL",
     {"shape": "bspline2", "transfer": "apic", "flip_velocity_scale": 1.75,
      "placement": "gauss", "scheme": "usl"}),
]
CFLS = [0.5, 0.25, 0.125]


def main(argv, script):
    o = parse_options(argv, STUDY, script,
                      {"out": "", "scene": str(launch.ROOT / "configs/column_collapse_mc.yaml"),
                       "base": ""})
    base_wall = o["base"]
    if base_wall not in ("", "fixed", "friction"):
        fail(STUDY, f"--base must be fixed or friction, got '{base_wall}'")
    try:
        app, scene, out = prepare(STUDY, o)
    except launch.LaunchError as e:
        return e.code
    return study(app, scene, out, base_wall)


def study(app, scene, out, base_wall):
    base = yaml.safe_load(open(scene))
    if base_wall:
        base["walls"]["z_min"] = base_wall
        base["walls"].pop("friction", None)
        if base_wall == "friction":
            base["walls"]["friction"] = 0.52
    schemes = [(label, dict(keys)) for label, keys in SCHEMES]
    # Rows that do not name a scheme ran with MUSL, the scenes' scheme until 2026-11-25.
    for _, keys in schemes:
        keys.setdefault("scheme", "musl")
    only = os.environ.get("MPMDEM_STUDY_ONLY")  # substring: run only the matching rows
    if only:
        schemes = [s for s in schemes if only in s[0]]

    def make_scene(keys, cfl):
        cfg = copy_doc(base)
        for k in ("shape", "transfer", "flip", "flip_time_scale", "flip_velocity_scale",
                  "xpic_order", "scheme"):
            cfg["solver"].pop(k, None)
        solver = dict(keys)
        placement = solver.pop("placement", None)  # a region key: every region's points
        cfg["solver"].update(solver)
        if placement:
            for r in cfg["regions"]:
                r["placement"] = placement
        cfg["solver"]["cfl"] = cfl
        cfg.get("output", {}).pop("checkpoint_interval_steps", None)
        cfg.get("column_collapse", {}).pop("at_rest", None)  # to 6 t*, as the docs' tables
        return cfg

    variants = []
    for label, keys in schemes:
        for cfl in CFLS:
            variants.append(Variant(f"{len(variants):02d}", make_scene(keys, cfl),
                                    dict(scheme=label, cfl=cfl)))

    def metrics(v, s):
        return dict(v.info, runout_m=s["runout_m"], runout_front_m=s["runout_front_m"],
                    final_height_m=s["final_height_m"], Ed_over_Ep0=s["Ed_over_Ep0_final"],
                    steps=s["steps"], Eerr_over_released=s["Eerr_over_released"],
                    Etransfer_over_released=s["Etransfer_over_released"],
                    Etransfer_walls_over_released=s["Etransfer_walls_over_released"],
                    Eother_over_released=s["Eother_over_released"], wall_s=s["wall_time_s"])

    def report(rows):
        lines = ["| scheme | runout (m), cfl 0.5 / 0.25 / 0.125 | connected front (m) | H_f (m) "
                 "| E_d/E_p0 | steps | runout change | front change | H_f change "
                 "| E_d/E_p0 change | E_err / released | of which transfers | of them at the walls "
                 "| of which other |",
                 "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for label, _ in schemes:
            r = [x for x in rows if x["scheme"] == label]
            f = lambda k, d: " / ".join(f"{x[k]:.{d}f}" for x in r)  # noqa: E731
            ch = lambda k: f"{100 * (r[-1][k] - r[0][k]) / r[0][k]:+.1f} %"  # noqa: E731
            pct = lambda k: " / ".join(f"{100 * x[k]:.0f} %" for x in r)  # noqa: E731
            pct1 = lambda k: " / ".join(f"{100 * x[k]:+.1f} %" for x in r)  # noqa: E731
            lines.append(
                f"| {label} | {f('runout_m', 3)} | {f('runout_front_m', 3)} "
                f"| {f('final_height_m', 3)} "
                f"| {f('Ed_over_Ep0', 3)} | {' / '.join(str(x['steps']) for x in r)} "
                f"| {ch('runout_m')} | {ch('runout_front_m')} "
                f"| {ch('final_height_m')} | {ch('Ed_over_Ep0')} "
                f"| {pct('Eerr_over_released')} | {pct('Etransfer_over_released')} "
                f"| {pct1('Etransfer_walls_over_released')} | {pct1('Eother_over_released')} |")
        return "\n".join(lines)

    # The runs go into OUT itself (00.yaml, 00/, ...); the table is printed, not written.
    sweep(StudySpec(STUDY, variants, metrics, report, runs_dir="", table_name=None,
                    progress=False), app, out)
    return 0

"""scripts/at_rest_study: the column collapse's at-rest stop on the local column, per transfer
and threshold x hold time, against a run to the full duration (see the script's header)."""
import csv
import os
import subprocess
import sys

import yaml

from .. import launch
from ..entry import parse_options
from ..summary import read_summary
from ..sweep import StudySpec, Variant, copy_doc, sweep
from . import prepare

STUDY = "at_rest_study"
SCHEMES = [("PIC/FLIP, flip_velocity_scale 1.75 m/s (shipped)", "shipped", {}),
           ("flip_time_scale 0.03 s", "fts003", {"flip_time_scale": 0.03})]
SETTINGS = [(r, h) for r in (1e-4, 3e-5, 2e-5, 1e-5) for h in (0.25, 0.5)]


def main(argv, script):
    o = parse_options(argv, STUDY, script,
                      {"out": "", "scene": str(launch.ROOT / "configs/column_collapse_mc.yaml"),
                       "figure": ""})
    try:
        app, scene, out = prepare(STUDY, o)
    except launch.LaunchError as e:
        return e.code
    figure = o["figure"] or f"{out}/at_rest.png"
    return study(app, scene, out, figure)


def run(app, cfg, out, name, study):
    """mpm_app on OUT/NAME.yaml into OUT/NAME (one thread); its summary (no energy shares)."""
    path = os.path.join(out, name + ".yaml")
    with open(path, "w") as f:
        yaml.safe_dump(cfg, f, sort_keys=False)
    d = os.path.join(out, name)
    r = subprocess.run([app, path, "--out", d, "--force", "--threads", "1"],
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit(f"{study}: {name} failed:\n{r.stderr[-2000:]}")
    return read_summary(d)


def study(app, scene, out, figure):
    from column_study import set_solver  # scripts/lib

    base = yaml.safe_load(open(scene))

    def make_scene(keys, at_rest):
        c = copy_doc(base)
        set_solver(c, keys)
        c["column_collapse"].pop("at_rest", None)
        if at_rest:
            c["column_collapse"]["at_rest"] = {"kinetic_ratio": at_rest[0],
                                               "hold_t_star": at_rest[1]}
        c["output"] = {"interval": 0, "energy_interval": 0.005, "vtk": False,
                       "progress_interval_s": 1000, "checkpoint_interval_s": 0}
        return c

    # Per transfer: the full run (the reference), then one run per threshold x hold time.
    variants = []
    for label, tag, keys in SCHEMES:
        variants.append(Variant(f"{tag}_full", make_scene(keys, None), dict(transfer=label)))
        for ratio, hold in SETTINGS:
            variants.append(Variant(f"{tag}_{ratio:g}_{hold:g}", make_scene(keys, (ratio, hold)),
                                    dict(transfer=label, kinetic_ratio=ratio, hold_t_star=hold)))
    refs = {}  # transfer -> the full run's summary
    curves = []

    def metrics(v, s):
        label = v.info["transfer"]
        if "kinetic_ratio" not in v.info:
            refs[label] = s
            curves.append((label, os.path.join(out, v.name), s))
            return None
        ref = refs[label]
        ch = {k: 100 * (s[k] / ref[k] - 1) for k in ("runout_m", "final_height_m",
                                                       "Ed_over_Ep0_final")}
        return dict(v.info, stop=s["stop"]["reason"], t_over_tstar=s["time_over_t_star_final"],
                    steps=s["steps"], steps_full=ref["steps"], **ch)

    def on_run(v, s, row):  # the table, a line per run as it ends
        label = v.info["transfer"]
        if row is None:
            print(f"| {label} | - | - | {s['stop']['reason']} | {s['time_over_t_star_final']:.2f} "
                  f"| {s['steps']} | - | {s['step_cpu_time_s']:.2f} | {s['runout_m']:.4f} m "
                  f"| {s['final_height_m']:.4f} m | {s['Ed_over_Ep0_final']:.4f} |")
            return
        ref = refs[label]
        print(f"| {label} | {row['kinetic_ratio']:g} | {row['hold_t_star']:g} "
              f"| {s['stop']['reason']} "
              f"| {s['time_over_t_star_final']:.2f} | {s['steps']} "
              f"| {100 * (1 - s['steps'] / ref['steps']):.0f} % | {s['step_cpu_time_s']:.2f} "
              f"| {row['runout_m']:+.2f} % | {row['final_height_m']:+.2f} % "
              f"| {row['Ed_over_Ep0_final']:+.2f} % |")

    print("| transfer | kinetic_ratio | hold (t*) | stop | t/t* | steps | saved | step CPU (s) "
          "| runout | H_f | E_d/E_p0 |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    sweep(StudySpec(STUDY, variants, metrics, run=run, runs_dir="", table_name=None,
                    progress=False, on_run=on_run), app, out)
    plot(curves, figure, out)
    return 0


def plot(curves, figure, out):
    """E_k/E_p0 against (t - t_r)/t* of the full runs, with the thresholds."""
    settings = SETTINGS
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    for label, d, s in curves:
        t, ek = [], []
        with open(os.path.join(d, "energies.csv")) as f:
            for row in csv.DictReader(f):
                tt = (float(row["time"]) - s["stage1_time_s"]) / s["t_star_s"]
                if tt > 0:
                    t.append(tt)
                    ek.append(max(float(row["E_k"]) / s["Ep0_release_J"], 1e-9))
        ax.semilogy(t, ek, label=label)
    for ratio in sorted({r for r, _ in settings}):
        ax.axhline(ratio, color="grey", lw=0.6, ls=":")
    ax.axhline(2e-5, color="k", lw=1, ls="--", label="2e-5 (the scenes' kinetic_ratio)")
    ax.set_xlabel("(t - t_r) / t*")
    ax.set_ylabel("E_k / E_p0")
    ax.set_ylim(1e-7, 1)
    ax.set_xlim(0, 6.05)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Local column (a = 2.4): kinetic energy after the release", fontsize=10)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(figure)), exist_ok=True)
    fig.savefig(figure, dpi=110)
    print(f"\nfigure: {figure}\nresults: {out}")

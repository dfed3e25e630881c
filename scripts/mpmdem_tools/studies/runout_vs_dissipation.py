"""scripts/runout_vs_dissipation: runout against the numerical share of the energy released,
over folders of finished column runs, fitted per group (see the script's header)."""
import glob
import os
import sys

import yaml

from ..entry import header_help
from ..summary import SummaryError, read_summary

tool = "runout_vs_dissipation"


def main(argv, script):
    if not argv:
        print(f"{tool}: give one or more folders of column runs", file=sys.stderr)
        return 2
    if argv[0] in ("-h", "--help"):
        print(header_help(script))
        return 0
    return report(argv)


def report(dirs):
    from column_study import has_mu_i, linear_fit  # scripts/lib

    runs = []
    for d in dirs:
        if not os.path.isdir(d):
            sys.exit(f"{tool}: no folder '{d}'")
        found = sorted(glob.glob(os.path.join(d, "**", "summary.json"), recursive=True))
        n_col = 0
        for path in found:
            try:
                s = read_summary(path)
            except SummaryError as e:
                sys.exit(f"{tool}: {e}")
            if s.get("status") != "complete" or "runout_m" not in s:
                continue  # not a column, or a run that did not finish
            try:
                scene = yaml.safe_load(open(s["config_file"]))
                base = scene["walls"]["z_min"]
                g = scene["grid"]
                shape = "slice" if round(g["extent"][1] / g["cell_size"]) == 1 else "3D"
                # a different law: never one line with the plain one
                model = s["model"] + (" + mu(I)" if has_mu_i(scene) else "")
                run = dict(group=(model, shape, base, round(s["aspect_ratio"], 3)),
                           N=s["energy_budget"]["E_err_share"], runout=s["runout_m"],
                           mass99=s["runout_mass99_m"])
            except (OSError, KeyError, TypeError, ValueError) as e:
                sys.exit(f"{tool}: cannot read the scene or budget of {path}: {e!r}")
            n_col += 1
            if run not in runs:
                runs.append(run)
        if n_col == 0:
            sys.exit(f"{tool}: no complete column run (summary.json with a runout) under '{d}'")
    print("| model | domain | base | a | runs | N range | figure | at N = 0 (m) | per 0.01 of N (m) "
          "| R^2 |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for group in sorted({r["group"] for r in runs}):
        model, shape, base, a_ratio = group
        sel = [r for r in runs if r["group"] == group]
        head = f"| {model} | {shape} | {base} | {a_ratio:g} | {len(sel)}"
        if len(sel) < 3:
            print(f"{head} | - | no fit: fewer than 3 runs | - | - | - |")
            continue
        N = [r["N"] for r in sel]
        for key, label in (("runout", "runout"), ("mass99", "99 % of the mass within")):
            a, b, r2 = linear_fit(N, [r[key] for r in sel])
            print(f"{head} | {min(N):.3f}-{max(N):.3f} | {label} | {a:.2f} | {0.01 * b:+.3f} "
                  f"| {r2:.2f} |")
    return 0

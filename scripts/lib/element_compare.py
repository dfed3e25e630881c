"""Overlay the element tests of two DEM backends (scripts/element_test --compare A,B).

  element_compare.py DIR A B [--criterion DEG]

Reads DIR/A and DIR/B (each a scripts/element_test output folder: plan.json, <path>.csv,
summary.json), and writes
  DIR/compare.png   per path run by both: q/p and volumetric strain (compression positive)
                    against the path's strain (axial for the triaxial paths), A and B overlaid;
  DIR/compare.json  per path: phi_peak_deg, phi_cs_deg (definitions of scripts/lib/
                    element_test.py), strain at the peak, final volumetric strain, wall and CPU
                    times of each backend, the differences B - A and whether |difference| <=
                    the criterion (default 1.5 deg, issue 15);
  DIR/compare.md    the same as a markdown table.
Run under Debian's /usr/bin/python3 (numpy, matplotlib). Exit 0 (also when the criterion is
not met: the table says so), 1 when an input is missing.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import element_test as et  # noqa: E402  (analyse, summarise, read_csv)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))  # scripts/
from mpmdem_tools.summary import read_summary  # noqa: E402  (the one summary.json reader)

STYLE = ({"color": "tab:blue", "lw": 1.3}, {"color": "tab:red", "lw": 1.0, "ls": "--"})


def load(folder):
    with open(os.path.join(folder, "plan.json")) as f:
        plan = json.load(f)
    summary = read_summary(folder)
    series = {}
    for t in plan["tests"]:
        csv = os.path.join(folder, t["path"] + ".csv")
        if os.path.exists(csv):
            series[t["path"]] = et.analyse(et.read_csv(csv), t, plan["rves"], plan["pressure"])
    return plan, summary, series


def compare(out, names, criterion):
    runs = {}
    for b in names:
        folder = os.path.join(out, b)
        if not os.path.exists(os.path.join(folder, "summary.json")):
            print("element_compare: %s has no summary.json (did the %s run fail?)" % (folder, b),
                  file=sys.stderr)
            return 1
        runs[b] = load(folder)
    a, b = names
    paths = [p for p in runs[a][2] if p in runs[b][2] and p in runs[a][1]["tests"]
             and p in runs[b][1]["tests"]]
    if not paths:
        print("element_compare: no path run by both %s and %s" % (a, b), file=sys.stderr)
        return 1
    table = {}
    keys = ("phi_peak_deg", "strain_at_peak", "phi_cs_deg", "q_over_p_peak", "q_over_p_cs",
            "volumetric_strain_final", "porosity_initial", "p_initial_Pa", "wall_time_s",
            "cpu_time_s")
    for p in paths:
        row = {k: {x: runs[x][1]["tests"][p].get(k) for x in names} for k in keys}
        for k in ("phi_peak_deg", "phi_cs_deg"):
            d = row[k][b] - row[k][a]
            row[k]["difference"] = d
            row[k]["within_criterion"] = abs(d) <= criterion
        table[p] = row
    plan = runs[a][0]
    doc = {"config": plan["config"], "packings": plan["packings"], "pressure_Pa": plan["pressure"],
           "rves": plan["rves"], "backends": list(names), "criterion_deg": criterion,
           "difference": "%s - %s" % (b, a), "tests": table,
           "all_within_criterion": all(r[k]["within_criterion"] for r in table.values()
                                       for k in ("phi_peak_deg", "phi_cs_deg"))}
    with open(os.path.join(out, "compare.json"), "w") as f:
        json.dump(doc, f, indent=1)
    md = markdown(doc, names)
    with open(os.path.join(out, "compare.md"), "w") as f:
        f.write(md)
    plot({x: runs[x][2] for x in names}, paths, names, os.path.join(out, "compare.png"), plan)
    print(md, end="")
    print("element_compare: wrote %s/compare.png, compare.json, compare.md" % out)
    return 0


def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def markdown(doc, names):
    a, b = names
    lines = ["%s, %s, p0 = %.3g Pa, %d RVE(s); difference = %s - %s, criterion |difference| <= "
             "%.1f deg" % (os.path.basename(doc["config"]), ",".join(doc["packings"]) or "inline",
                           doc["pressure_Pa"], doc["rves"], b, a, doc["criterion_deg"]), "",
             "| path | phi_peak %s | phi_peak %s | diff. | phi_cs %s | phi_cs %s | diff. | "
             "strain at peak %s / %s | vol. strain end %s / %s | wall s %s / %s | CPU s %s / %s |"
             % ((a, b, a, b) + (a, b) * 4),
             "|---" * 11 + "|"]
    for p, r in doc["tests"].items():
        ok = lambda k: "" if r[k]["within_criterion"] else " (> %.1f)" % doc["criterion_deg"]  # noqa
        lines.append(
            "| %s | %.2f | %.2f | %+.2f%s | %.2f | %.2f | %+.2f%s | %s / %s | %s / %s | %s / %s | "
            "%s / %s |" % (
                p, r["phi_peak_deg"][a], r["phi_peak_deg"][b], r["phi_peak_deg"]["difference"],
                ok("phi_peak_deg"), r["phi_cs_deg"][a], r["phi_cs_deg"][b],
                r["phi_cs_deg"]["difference"], ok("phi_cs_deg"),
                fmt(r["strain_at_peak"][a], ".3f"), fmt(r["strain_at_peak"][b], ".3f"),
                fmt(r["volumetric_strain_final"][a], ".4f"),
                fmt(r["volumetric_strain_final"][b], ".4f"),
                fmt(r["wall_time_s"][a], ".0f"), fmt(r["wall_time_s"][b], ".0f"),
                fmt(r["cpu_time_s"][a], ".0f"), fmt(r["cpu_time_s"][b], ".0f")))
    lines += ["", "All within the criterion: %s" % ("yes" if doc["all_within_criterion"] else "no"),
              ""]
    return "\n".join(lines)


def plot(series, paths, names, png, plan):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    fig, ax = plt.subplots(2, len(paths), figsize=(4.2 * len(paths), 6.0), squeeze=False)
    for j, p in enumerate(paths):
        for k, b in enumerate(names):
            s = series[b][p]
            x = [r["x"] for r in s]
            ax[0][j].plot(x, [r["q_over_p"] for r in s], label=b, **STYLE[k])
            ax[1][j].plot(x, [r["eps_v"] for r in s], label=b, **STYLE[k])
        ax[0][j].set_title({"triaxial": "drained triaxial", "constant_volume":
                            "constant-volume triaxial", "simple_shear": "constant-volume simple shear"}
                           .get(p, p))
        ax[0][j].set_ylabel("q/p")
        ax[1][j].set_ylabel("volumetric strain (compression +)")
        ax[1][j].set_xlabel({"simple_shear": "shear strain gamma", "isotropic":
                             "volumetric strain"}.get(p, "axial strain (Hencky)"))
        ax[0][j].legend()
        for r in (0, 1):
            ax[r][j].grid(alpha=0.3)
            ax[r][j].xaxis.set_major_locator(MaxNLocator(5))
    fig.suptitle("%s (%s, %d RVE(s), p0 = %.3g Pa): %s vs %s" % (
        os.path.basename(plan["config"]), ",".join(plan["packings"]) or "inline", plan["rves"],
        plan["pressure"], names[0], names[1]))
    fig.tight_layout()
    fig.savefig(png, dpi=90)


def main(argv):
    crit = 1.5
    if "--criterion" in argv:
        i = argv.index("--criterion")
        crit = float(argv[i + 1])
        argv = argv[:i] + argv[i + 2:]
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 1
    return compare(argv[0], argv[1:], crit)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

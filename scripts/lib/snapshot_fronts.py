#!/usr/bin/python3
"""The column's fronts at each snapshot of a run (snapshots/t_star_<k>.h5).

Usage: snapshot_fronts.py RUN_DIR... [--json OUT]

For each run and snapshot it prints, from the points' positions x and masses:
- the farthest point's centre, max_p x_p (summary.json's runout_m adds half a point's extent,
  s_x / 2, at the end of the run: compare like with like);
- the 99 %-mass front: the points sorted by x, the x of the first whose cumulative mass
  reaches 0.99 of the total (summary.json's runout_mass99_m, computed the same way);
- the highest point's centre, max_p z_p.
x and z are measured from the grid's origin (the back wall and the base of the column scenes).
"""
import glob
import json
import os
import re
import sys


def fronts(path):
    import h5py
    import numpy as np
    with h5py.File(path, "r") as f:
        x = np.asarray(f["x"])
        m = np.asarray(f["mass"]).ravel()
    x = x.reshape(-1, 3)
    order = np.argsort(x[:, 0], kind="stable")
    cum = np.cumsum(m[order])
    k = int(np.searchsorted(cum, 0.99 * cum[-1]))
    return {"farthest_point_m": float(x[:, 0].max()),
            "mass99_m": float(x[order[k], 0]),
            "highest_point_m": float(x[:, 2].max()),
            "points": int(len(m))}


def main(argv):
    out = None
    if "--json" in argv:
        i = argv.index("--json")
        if i + 1 >= len(argv):
            print("snapshot_fronts: --json needs a file", file=sys.stderr)
            return 2
        out = argv[i + 1]
        del argv[i:i + 2]
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    doc = {}
    print("| run | t* | farthest point (m) | 99 % mass (m) | highest point (m) |")
    print("|---|---|---|---|---|")
    for run in argv[1:]:
        snaps = glob.glob(os.path.join(run, "snapshots", "t_star_*.h5"))
        if not snaps:
            print("snapshot_fronts: %s: no snapshots/t_star_*.h5" % run, file=sys.stderr)
            return 1
        key = lambda p: float(re.search(r"t_star_([0-9.]+)\.h5$", p).group(1))
        doc[run] = {}
        for p in sorted(snaps, key=key):
            f = fronts(p)
            doc[run][str(key(p))] = f
            print("| %s | %g | %.3f | %.3f | %.3f |" % (run, key(p), f["farthest_point_m"],
                                                    f["mass99_m"], f["highest_point_m"]))
    if out:
        with open(out, "w") as fh:
            json.dump(doc, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

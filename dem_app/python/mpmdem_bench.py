"""Cost per RVE per coupling step: the server's Python path (RveSet.step) vs raw YADE.

  /usr/bin/python3 dem_app/python/mpmdem_bench.py inproc DIR NAME [--ns 10] [--steps 40]
        [--eps 1e-5] [--json FILE]
  /usr/bin/python3 dem_app/python/mpmdem_bench.py memory DIR NAME [--counts 1,5,20] [--json FILE]

DIR/NAME.yade.bz2 from scripts/build_packings. Run by scripts/bench_dem (which adds the same
through dem_app over MPI); OMP_NUM_THREADS=1 (as dem_app sets it).

inproc: resident scenes of the same packing, one per configuration, all in this process:
  raw          O.cell.velGrad = L once, ns x O.step(), utils.getStress()  (what a standalone
               YADE script does for one coupling step; L = log(1 - eps)/(ns dt) on zz)
  stress       RveSet.step with stiffness none, no optional outputs (the issue's target)
  stiffness    + the stiffness bound (coupling.yade.stiffness tangent, the default)
  all          + all four optional outputs (rotation, porosity, coordination, unbalanced)
  raw_multi    (--multi K > 1) raw YADE cycling K resident scenes (switchToScene, then as
               raw), time per RVE: what a server rank with K RVEs must be compared with (a
               switch leaves the next scene's data out of cache: the first substep after it
               costs ~1 ms instead of ~0.35 ms on 800 spheres)
Each coupling step dF = diag(1, 1, 1 - eps). The configurations are interleaved step by step,
in an order rotated every step (machine noise hits all alike); the figure of a configuration
is the median over steps of its time, and its overhead the median over steps of its time
divided by raw's time in the same step.

memory: RSS of this process after loading 1, 5, 20 (--counts) resident RVEs through RveSet
(plus one step each); the slope of a least-squares line is the memory per resident RVE.
"""
import argparse
import json
import math
import statistics
import struct
import sys
import time

import mpmdem_rve as R


def base_params(d, name, ns, n_rve=1):
    return dict(first_rve=0, n_rve=n_rve, outputs=0, packings=[name], packing_dir=d, seed=1,
                inline_packing={}, damping=0.2, stiffness="none", consolidation_tol=1e-3,
                consolidation_unbalanced=0.01, consolidation_max_steps=200000,
                ns_rule="fixed", ns=ns, ns_factor=1e5, ns_min=2, ns_max=100, ke_threshold=10.0)


def rss_mb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return float(line.split()[1]) / 1024.0
    return 0.0


def inproc(a):
    configs = [("stress", {}), ("stiffness", {"stiffness": "tangent"}),
               ("all", {"stiffness": "tangent", "outputs": 15})]
    zero = struct.pack("9d", *[0.0] * 9)
    dF = struct.pack("9d", 1, 0, 0, 0, 1, 0, 0, 0, 1 - a.eps)
    fl = struct.pack("I", 0)
    sets = {}
    for label, extra in configs:
        rs = R.RveSet(dict(base_params(a.dir, a.name, a.ns), **extra))
        rs.initialise(zero)  # zero stress: no consolidation, the packing as built
        sets[label] = rs
    y = rs.y
    O = y.O
    raw_scene = O.addScene()
    O.switchToScene(raw_scene)
    O.load("%s/%s.yade.bz2" % (a.dir, a.name))
    n_spheres = len(O.bodies)
    L = y.Matrix3(0, 0, 0, 0, 0, 0, 0, 0, math.log(1 - a.eps) / (a.ns * O.dt))
    utils = y.utils
    step = O.step

    def raw():
        O.switchToScene(raw_scene)
        O.cell.velGrad = L
        for _ in range(a.ns):
            step()
        return utils.getStress()

    def server(rs):
        return lambda: rs.step(dF, fl, 0)

    runs = [("raw", raw)] + [(label, server(sets[label])) for label, _ in configs]
    multi = []
    for _ in range(a.multi if a.multi > 1 else 0):
        multi.append(O.addScene())
        O.switchToScene(multi[-1])
        O.load("%s/%s.yade.bz2" % (a.dir, a.name))

    def raw_multi():
        for idx in multi:
            O.switchToScene(idx)
            O.cell.velGrad = L
            for _ in range(a.ns):
                step()
            utils.getStress()

    if multi:
        runs.append(("raw_multi", raw_multi))
    per_rve = {"raw_multi": max(1, len(multi))}
    for _, f in runs:  # warm-up: first step after a load rebuilds the collider
        f()
    times = {label: [] for label, _ in runs}
    perf = time.perf_counter
    for n in range(a.steps):
        order = runs[n % len(runs):] + runs[:n % len(runs)]
        for label, f in order:
            t = perf()
            f()
            times[label].append((perf() - t) / per_rve.get(label, 1))
    raw_t = times["raw"]
    res = {"mode": "inproc", "packing": a.name, "n_spheres": n_spheres, "ns": a.ns,
           "steps": a.steps, "eps": a.eps, "multi": len(multi), "configs": {}}
    for label, ts in times.items():
        ratio = [t / r for t, r in zip(ts, raw_t)]
        med = statistics.median(ts)
        res["configs"][label] = {
            "median_ms": 1e3 * med, "mean_ms": 1e3 * statistics.fmean(ts),
            "median_ratio_to_raw": statistics.median(ratio),
            "particle_steps_per_s": n_spheres * a.ns / med}
    t = perf()
    for _ in range(20):
        utils.getStressAndTangent(symmetry=True)
    res["getStressAndTangent_ms"] = 1e3 * (perf() - t) / 20
    t = perf()
    for _ in range(20):
        utils.getStress()
    res["getStress_ms"] = 1e3 * (perf() - t) / 20
    print("inproc %s: %d spheres, ns %d, %d interleaved steps" % (a.name, n_spheres, a.ns, a.steps))
    for label, c in res["configs"].items():
        print("  %-10s median %7.3f ms/RVE-step  (mean %7.3f)  vs raw %+6.1f %%  %.3g "
              "particle-steps/s" % (label, c["median_ms"], c["mean_ms"],
                                    100 * (c["median_ratio_to_raw"] - 1),
                                    c["particle_steps_per_s"]))
    print("  getStressAndTangent %.3f ms, getStress %.3f ms"
          % (res["getStressAndTangent_ms"], res["getStress_ms"]))
    return res


def memory(a):
    counts = sorted(int(c) for c in a.counts.split(","))
    zero = struct.pack("9d", *[0.0] * 9)
    rows = []
    loaded = 0
    keep = []
    base = rss_mb()
    for c in counts:
        add = c - loaded
        if add > 0:
            rs = R.RveSet(base_params(a.dir, a.name, 10, add))
            rs.initialise(struct.pack("%dd" % (9 * add), *[0.0] * (9 * add)))
            dF = struct.pack("%dd" % (9 * add), *([1, 0, 0, 0, 1, 0, 0, 0, 1 - 1e-5] * add))
            rs.step(dF, struct.pack("%dI" % add, *[0] * add), 1)
            keep.append(rs)
            loaded = c
        rows.append((c, rss_mb()))
    n = len(rows)
    mx = sum(r[0] for r in rows) / n
    my = sum(r[1] for r in rows) / n
    sxx = sum((r[0] - mx) ** 2 for r in rows)
    slope = sum((r[0] - mx) * (r[1] - my) for r in rows) / sxx if sxx else 0.0
    res = {"mode": "memory", "packing": a.name, "rss_before_mb": base,
           "rss_mb": [{"rves": c, "rss_mb": m} for c, m in rows], "mb_per_rve": slope,
           "intercept_mb": my - slope * mx}
    print("memory %s: RSS before %.1f MB; %s; %.2f MB per resident RVE"
          % (a.name, base, ", ".join("%d RVEs %.1f MB" % r for r in rows), slope))
    del zero
    return res


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mode", choices=["inproc", "memory"])
    ap.add_argument("dir")
    ap.add_argument("name")
    ap.add_argument("--ns", type=int, default=10)
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--eps", type=float, default=1e-5)
    ap.add_argument("--counts", default="1,5,20")
    ap.add_argument("--multi", type=int, default=0, help="also raw YADE cycling K scenes")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    res = inproc(a) if a.mode == "inproc" else memory(a)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(res, f, indent=1)


if __name__ == "__main__":
    main(sys.argv[1:])

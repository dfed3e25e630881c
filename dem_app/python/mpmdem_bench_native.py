"""Native vs YADE backend cost on one packing, one core (issue 15, item 3; first part).

  /usr/bin/python3 mpmdem_bench_native.py --packing-dir DIR --packing NAME --replay BIN
        [--ns 2 20] [--steps 2000] [--rounds 3] [--raw] [--json FILE]
The packing DIR/NAME.yade.bz2 must have its DIR/NAME.native.txt (scripts/export_native_packings).
Each round, for each ns: YADE backend (mpmdem_rve.RveSet.step, in process, stress and
stiffness as the server computes them) then native (native_replay, its own process), both
on the packing as saved (no consolidation) with a monotonic oedometric increment
dF = diag(1, 1, 1 - 5e-6) (1 % strain over 2000 steps). Not alternating increments: at
ns = 2 the velGrad-lag correction then makes the cell's rate grow step after step (see
docs/dem_backend.md, native backend).
With --raw, each round also runs raw YADE on the packing with the server's engines
(mpmdem_packing.engines without triax; O.cell.velGrad = L, ns x O.step(), utils.getStress()
per coupling step: YADE without the server around it).
Prints particle-steps/s (spheres * ns * coupling steps / wall) per backend, the median over
rounds, the ratios, and the native binary state size and encode/decode times; --json writes
them.
"""
import argparse
import json
import math
import os
import statistics
import struct
import subprocess
import sys
import tempfile
import time

import mpmdem_packing as pk
import mpmdem_rve

ap = argparse.ArgumentParser()
ap.add_argument("--packing-dir", required=True)
ap.add_argument("--packing", required=True)
ap.add_argument("--replay", required=True)
ap.add_argument("--ns", type=int, nargs="+", default=[2, 20])
ap.add_argument("--steps", type=int, default=2000)
ap.add_argument("--rounds", type=int, default=3)
ap.add_argument("--raw", action="store_true")
ap.add_argument("--json")
a = ap.parse_args()

y = pk._import_yade()
dfs = [[1, 0, 0, 0, 1, 0, 0, 0, 1 - 5e-6]]
tmp = tempfile.mkdtemp(prefix="mpmdem_bench_native_")
df_file = os.path.join(tmp, "df.txt")
with open(df_file, "w") as f:
    for d in dfs:
        f.write(" ".join(repr(float(v)) for v in d) + "\n")


def yade_rate(ns):
    p = {"packing_dir": a.packing_dir, "packings": [a.packing], "seed": 1,
         "inline_packing": {}, "ns_rule": "fixed", "ns": ns, "ns_factor": 1e5, "ns_min": 2,
         "ns_max": 100, "damping": 0.2, "ke_threshold": 1e30, "stiffness": "tangent",
         "consolidation_tol": 1e-3, "consolidation_unbalanced": 0.01,
         "consolidation_max_steps": 1000, "first_rve": 0, "n_rve": 1, "outputs": 0}
    rs = mpmdem_rve.make(json.dumps(p))
    rs.initialise(struct.pack("9d", *([0.0] * 9)), struct.pack("Q", 0))
    n = len(y.O.bodies)
    blobs = [struct.pack("9d", *d) for d in dfs]
    flags = struct.pack("I", 0)
    t0 = time.perf_counter()
    for k in range(a.steps):
        rs.step(blobs[0], flags, k + 1)
    return n * ns * a.steps / (time.perf_counter() - t0)


def raw_rate(ns):
    O = y.O
    scene = O.addScene()
    O.switchToScene(scene)
    O.load(os.path.join(a.packing_dir, a.packing + ".yade.bz2"))
    # The engines the server steps with (mpmdem_rve.RveSet._setup_engines: no triax).
    O.engines = pk.engines(y, 0.2, False)
    O.engines[1].allowBiggerThanPeriod = True
    n = len(O.bodies)
    L = y.Matrix3(0, 0, 0, 0, 0, 0, 0, 0, math.log(dfs[0][8]) / (ns * O.dt))
    step, stress = O.step, y.utils.getStress
    t0 = time.perf_counter()
    for _ in range(a.steps):
        O.cell.velGrad = L
        for _ in range(ns):
            step()
        stress()
    return n * ns * a.steps / (time.perf_counter() - t0)


def native_rate(ns):
    out = subprocess.run([a.replay, "--packing",
                          os.path.join(a.packing_dir, a.packing + ".native.txt"),
                          "--df", df_file, "--ns", str(ns), "--repeat", str(a.steps)],
                         check=True, capture_output=True, text=True).stdout.split("\n")
    rate = [float(l.split()[1]) for l in out if l.startswith("particle_steps_per_s")][0]
    state = [l for l in out if l.startswith("state_bytes")][0]
    return rate, state


res = {ns: {"yade": [], "native": [], "raw": []} for ns in a.ns}
state = ""
for r in range(a.rounds):
    for ns in a.ns:
        res[ns]["yade"].append(yade_rate(ns))
        rate, state = native_rate(ns)
        res[ns]["native"].append(rate)
        if a.raw:
            res[ns]["raw"].append(raw_rate(ns))
print("packing %s, %d coupling steps per run, %d rounds (medians)" % (a.packing, a.steps,
                                                                       a.rounds))
summary = {"packing": a.packing, "steps": a.steps, "rounds": a.rounds, "runs": {}, "ns": {}}
for ns in a.ns:
    yv, nv = statistics.median(res[ns]["yade"]), statistics.median(res[ns]["native"])
    line = ("ns=%-3d YADE backend %.3g particle-steps/s, native %.3g, ratio %.1f"
            % (ns, yv, nv, nv / yv))
    summary["ns"][ns] = {"yade_backend": yv, "native": nv, "native_over_yade_backend": nv / yv}
    if a.raw:
        rv = statistics.median(res[ns]["raw"])
        line += "; raw YADE %.3g, native / raw %.1f" % (rv, nv / rv)
        summary["ns"][ns].update({"raw_yade": rv, "native_over_raw_yade": nv / rv})
    print(line)
    summary["runs"][ns] = res[ns]
print("native " + state)
f = state.split()
summary["state"] = {f[i]: float(f[i + 1]) for i in range(0, len(f) - 1, 2)}
if a.json:
    with open(a.json, "w") as fh:
        json.dump(summary, fh, indent=1)
sys.stdout.flush()

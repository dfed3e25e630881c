"""Cost per RVE per coupling step: mpmdem_rve (the server's Python path) vs raw YADE.

  /usr/bin/python3 dem_app/python/mpmdem_bench.py DIR NAME [ns] [steps]

DIR/NAME.yade.bz2 from scripts/build_packings. Both paths run on resident scenes, one thread.
"""
import struct
import sys
import time

import mpmdem_rve as R


def main(d, name, ns=10, steps=50):
    base = dict(first_rve=0, n_rve=1, outputs=0, packings=[name], packing_dir=d, seed=1,
                inline_packing={}, damping=0.2, stiffness="none", consolidation_tol=1e-3,
                consolidation_unbalanced=0.01, consolidation_max_steps=200000,
                ns_rule="fixed", ns=ns, ns_factor=1e5, ns_min=2, ns_max=100, ke_threshold=10.0)
    zero = struct.pack("9d", *[0.0] * 9)
    dF = struct.pack("9d", 1 - 1e-5, 0, 0, 0, 1, 0, 0, 0, 1)
    fl = struct.pack("I", 0)
    res = {}
    for label, extra in [("stress only", {}), ("+ tangent stiffness", {"stiffness": "tangent"}),
                         ("+ all outputs", {"stiffness": "tangent", "outputs": 15})]:
        p = dict(base, **extra)
        rs = R.RveSet(p)
        rs.initialise(zero)  # zero stress: no consolidation, packing as built
        rs.step(dF, fl, 0)
        t = time.perf_counter()
        for n in range(steps):
            rs.step(dF, fl, n)
        res[label] = (time.perf_counter() - t) / steps
    # Raw YADE: same scene kind, same substeps, velGrad set once per burst, getStress once.
    y = rs.y
    O = y.O
    O.switchToScene(rs.scenes[0])
    L = y.Matrix3(-1e-5 / (ns * O.dt), 0, 0, 0, 0, 0, 0, 0, 0)
    t = time.perf_counter()
    for n in range(steps):
        O.cell.velGrad = L
        for _ in range(ns):
            O.step()
        s = y.utils.getStress()
    raw = (time.perf_counter() - t) / steps
    t = time.perf_counter()
    for n in range(steps):
        y.utils.getStressAndTangent(symmetry=True)
    tan = (time.perf_counter() - t) / steps
    print("spheres %d ns %d: raw YADE %.3f ms/RVE-step; tangent alone %.3f ms" %
          (len(O.bodies), ns, raw * 1e3, tan * 1e3))
    for k, v in res.items():
        print("  mpmdem_rve %-20s %.3f ms  (overhead %+.1f%%)" % (k, v * 1e3, 100 * (v / raw - 1)))
    del s


if __name__ == "__main__":
    a = sys.argv[1:]
    main(a[0], a[1], int(a[2]) if len(a) > 2 else 10, int(a[3]) if len(a) > 3 else 50)

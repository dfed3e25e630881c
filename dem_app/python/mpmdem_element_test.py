"""Drained triaxial element test on YADE RVEs through mpmdem_rve (the server's Python path,
without MPI: the stand-in for scripts/element_test until it drives the real server).

  /usr/bin/python3 dem_app/python/mpmdem_element_test.py --out DIR [--packing-dir D --packing N]
      [--spheres 60] [--pressure 1e5] [--axial 0.15] [--rate 1e-4] [--ns 20]

Axial (z) compression at a constant strain increment per step; the lateral stresses are held
at -pressure by the driver's mixed control (PI on the lateral strain increment, scaled by the
RVE's stiffness estimate M). Writes DIR/triaxial.csv, DIR/triaxial.png, DIR/summary.json with
phi_peak_deg, phi_cs_deg (mean q/p over the last 20% of the axial strain), porosity_initial,
wall_time_s.
"""
import argparse
import json
import math
import os
import struct
import time

import mpmdem_rve as R


def phi_from_ratio(m):
    """Friction angle of triaxial compression from q/p = M: sin(phi) = 3M/(6+M)."""
    return math.degrees(math.asin(max(-1.0, min(1.0, 3 * m / (6 + m)))))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", required=True)
    ap.add_argument("--packing-dir", default="")
    ap.add_argument("--packing", default="")
    ap.add_argument("--spheres", type=int, default=60)
    ap.add_argument("--pressure", type=float, default=1e5)
    ap.add_argument("--axial", type=float, default=0.15)
    ap.add_argument("--rate", type=float, default=1e-4, help="axial strain per coupling step")
    ap.add_argument("--ns", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    t0 = time.time()
    p = dict(first_rve=0, n_rve=1, outputs=R.OUT_POR, packings=[a.packing] if a.packing else [],
             packing_dir=a.packing_dir, seed=a.seed,
             inline_packing={"n_spheres": a.spheres, "porosity_init": 0.65, "max_strain_rate": 10.0},
             damping=0.2, stiffness="tangent", consolidation_tol=1e-3,
             consolidation_unbalanced=0.01, consolidation_max_steps=400000, ns_rule="fixed",
             ns=a.ns, ns_factor=1e5, ns_min=2, ns_max=1000, ke_threshold=10.0)
    rs = R.RveSet(p)
    s0 = [-a.pressure, 0, 0, 0, -a.pressure, 0, 0, 0, -a.pressure]
    r, _ = rs.initialise(struct.pack("9d", *s0))
    r = struct.unpack("18d", r)
    n0 = r[12]
    rows = []
    ex = ey = ez = 0.0
    gain = 0.5
    ix = iy = 0.0  # integral terms of the lateral control
    n_steps = int(round(a.axial / a.rate))
    for n in range(n_steps):
        M = max(r[15], 10 * a.pressure)
        # PI control of the lateral strain rate: the tangent M is the elastic contact
        # stiffness, far stiffer than the flowing packing, so a pure P term lags.
        erx, ery = (-a.pressure - r[0]) / M, (-a.pressure - r[4]) / M
        ix += 0.1 * erx
        iy += 0.1 * ery
        dx = gain * erx + ix
        dy = gain * ery + iy
        dF = [math.exp(dx), 0, 0, 0, math.exp(dy), 0, 0, 0, math.exp(-a.rate)]
        ex += dx
        ey += dy
        ez -= a.rate
        b, faults = rs.step(struct.pack("9d", *dF), struct.pack("I", 0), n)
        r = struct.unpack("18d", b)
        if faults:
            raise SystemExit(faults[0])
        sx, sy, sz = -r[0], -r[4], -r[8]  # compression positive for soil mechanics
        pm = (sx + sy + sz) / 3
        q = sz - 0.5 * (sx + sy)
        rows.append((-ez, -(ex + ey + ez), pm, q, q / pm if pm > 0 else 0.0, r[12], r[16]))
    with open(os.path.join(a.out, "triaxial.csv"), "w") as f:
        f.write("axial_strain,volumetric_strain,p_Pa,q_Pa,q_over_p,porosity,status\n")
        for row in rows:
            f.write(",".join("%.9g" % v for v in row) + "\n")
    ratios = [row[4] for row in rows]
    tail = ratios[int(0.8 * len(ratios)):]
    summary = {
        "phi_peak_deg": phi_from_ratio(max(ratios)),
        "phi_cs_deg": phi_from_ratio(sum(tail) / len(tail)),
        "porosity_initial": n0,
        "porosity_final": rows[-1][5],
        "wall_time_s": time.time() - t0,
        "pressure_Pa": a.pressure, "steps": n_steps, "ns": a.ns,
        "n_spheres": len(rs.y.O.bodies),
    }
    with open(os.path.join(a.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(2, 1, sharex=True, figsize=(5, 6))
        ax[0].plot([r_[0] for r_ in rows], ratios)
        ax[0].set_ylabel("q/p")
        ax[1].plot([r_[0] for r_ in rows], [r_[1] for r_ in rows])
        ax[1].set_ylabel("volumetric strain (compression +)")
        ax[1].set_xlabel("axial strain")
        fig.savefig(os.path.join(a.out, "triaxial.png"), dpi=100)
    except ImportError:
        pass
    print(json.dumps(summary))


if __name__ == "__main__":
    main()

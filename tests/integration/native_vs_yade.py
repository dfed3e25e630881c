"""Native backend vs YADE backend on one packing and one seeded dF sequence (issue 15, item 2).

Run by native_vs_yade.sh under Debian's /usr/bin/python3 (YADE as a module):
  native_vs_yade.py WORK_DIR NATIVE_REPLAY_BINARY [E_N]
With E_N: both with the frict_visco law (coupling.*.contact_law frict_visco,
restitution_normal E_N: FrictViscoMat and Law2_ScGeom_FrictViscoPhys_CundallStrackVisco in
YADE), same tolerances (measured: docs/theory_contact_law.md).
Builds a 40-sphere Table 1 packing at 10 kPa with YADE, saves it (.yade.bz2) and exports it
(.native.txt); then the YADE backend's RveSet (mpmdem_rve.py) and native_replay each load it,
initialise it without consolidation (zero RveInit stress: the packing's own state after the
two preparation steps) and apply the same 10 random increments (|dF - I| ~ 1e-5, typical of
the column) at ns = 10. Checks, relative to the largest stress component: the initial stress
equal to 1e-12 and the stresses of the 10 steps to 1e-10. The two backends evaluate the same
formulas, mostly in the same order: measured 1.7e-13 and 7.4e-12 (docs/dem_backend.md), so a
change of the contact law or the integrator at the level of 1e-9 fails. Prints every step's
difference.
"""
import json
import math
import os
import random
import struct
import subprocess
import sys

work, replay = sys.argv[1], sys.argv[2]
e_n = float(sys.argv[3]) if len(sys.argv) > 3 else None
import mpmdem_native_packing as npk  # noqa: E402
import mpmdem_packing as pk  # noqa: E402
import mpmdem_rve  # noqa: E402

y = pk._import_yade()
O = y.O
q = dict(pk.TABLE1)
q.update(n_spheres=40, porosity_init=0.65, max_strain_rate=10.0, seed=3, pressure=1.0e4)
pk.build_into_current_scene(q)
base = os.path.join(work, "pack")
O.save(base + ".yade.bz2")
O.load(base + ".yade.bz2")
npk.export_current_scene(y, base + ".native.txt")

params = {"packing_dir": work, "packings": ["pack"], "seed": 1,
          "inline_packing": {"n_spheres": 40, "porosity_init": 0.65, "max_strain_rate": 10.0},
          "ns_rule": "fixed", "ns": 10, "ns_factor": 1e5, "ns_min": 2, "ns_max": 100,
          "damping": 0.2, "ke_threshold": 10.0, "stiffness": "tangent",
          "consolidation_tol": 1e-3, "consolidation_unbalanced": 0.01,
          "consolidation_max_steps": 200000, "first_rve": 0, "n_rve": 1, "outputs": 0}
if e_n is not None:
    # beta_n as dem_app's YADE backend sends it (17 digits of the C++ value)
    lg = math.log(e_n)
    params.update(contact_law="frict_visco", restitution_normal=e_n,
                  beta_n=float("%.17g" % (-lg / math.sqrt(math.pi * math.pi + lg * lg))))
rs = mpmdem_rve.make(json.dumps(params))
reply, _ = rs.initialise(struct.pack("9d", *([0.0] * 9)), struct.pack("Q", 0))
yade = [list(struct.unpack("19d", reply)[0:9])]
rng = random.Random(2026)
dfs = []
for n in range(10):
    dF = [(1.0 if i % 4 == 0 else 0.0) + rng.uniform(-1e-5, 1e-5) for i in range(9)]
    dF[8] -= 2e-5  # some compression
    dfs.append(dF)
    reply, _ = rs.step(struct.pack("9d", *dF), struct.pack("I", 0), n + 1)
    yade.append(list(struct.unpack("19d", reply)[0:9]))
if e_n is not None:
    # YADE's side really has the dashpot: every contact a FrictViscoPhys with c_n > 0 (the
    # scene was converted), and the law it dispatches to acts (a non-zero viscous force).
    phys = [i.phys for i in O.interactions if i.isReal]
    assert phys and all(type(ph).__name__ == "FrictViscoPhys" and ph.cn > 0 for ph in phys), \
        set(type(ph).__name__ for ph in phys)
    assert max(ph.normalViscous.norm() for ph in phys) > 0, "no viscous force in YADE"
    print("YADE: %d FrictViscoPhys contacts, max |normalViscous| %.3g N"
          % (len(phys), max(ph.normalViscous.norm() for ph in phys)))
with open(os.path.join(work, "df.txt"), "w") as f:
    for dF in dfs:
        f.write(" ".join(repr(v) for v in dF) + "\n")

out = subprocess.run([replay, "--packing", base + ".native.txt", "--df",
                      os.path.join(work, "df.txt"), "--ns", "10", "--damping", "0.2"]
                     + ([] if e_n is None else ["--restitution", repr(e_n)]),
                     check=True, capture_output=True, text=True).stdout.split("\n")
native = [[float(v) for v in line.split()[-10:-1]] for line in out if line.strip()]
assert len(native) == len(yade) == 11, (len(native), len(yade))
worst_init = worst_steps = 0.0
for n, (a, b) in enumerate(zip(yade, native)):
    scale = max(abs(v) for v in a)
    err = max(abs(u - v) for u, v in zip(a, b)) / scale
    print("%s: YADE s_zz %.10g native %.10g  rel diff %.3g"
          % ("init" if n == 0 else "step %d" % n, a[8], b[8], err))
    if n == 0:
        worst_init = err
    else:
        worst_steps = max(worst_steps, err)
TOL_INIT, TOL_STEPS = 1e-12, 1e-10
ok = worst_init < TOL_INIT and worst_steps < TOL_STEPS
print("initial stress rel diff %.3g (< %g), steps 1-10 max rel diff %.3g (< %g): %s"
      % (worst_init, TOL_INIT, worst_steps, TOL_STEPS, "PASS" if ok else "FAIL"))
sys.exit(0 if ok else 1)

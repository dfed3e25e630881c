"""Standalone YADE reference for the side-by-side test (tests/integration/side_by_side.sh):
one process, one scene, no mpmdem code, YADE's Python API only.

  /usr/bin/python3 yade_standalone.py PACKING.yade.bz2 DF_FILE NS DAMPING OUT_CSV

Does to the packing what one RVE of `dem_app --backend yade` does (docs/dem_backend.md):
  * kInitialise with a zero stress (no consolidation): engines ForceResetter,
    InsertionSortCollider, InteractionLoop (ScGeom, FrictPhys, CundallStrack), NewtonIntegrator
    (damping); velGrad zeroed, two steps (YADE applies a velGrad from the step after it is
    set), velocities zeroed, reference positions/orientations reset; then a fresh engine list
    for the coupling steps;
  * per dF (one line of DF_FILE, row-major): NS substeps whose cell velocity gradients make the
    cell's transformation after the burst exactly dF times the one before: YADE integrates
    trsf <- (I + dt L) trsf with the L set *before the previous* step, so substep 1 runs with
    the L left pending by the previous burst; the L for substeps 2..NS-1 is set once (before
    substep 1) to spread what remains uniformly, the L for substep NS (set before substep
    NS-1) closes the gap exactly, and the L set before substep NS, pending for the next
    burst's substep 1, is this burst's mean rate (dF - I)/(NS dt).
Writes OUT_CSV: step, the symmetrised utils.getStress() (9, row-major, tension positive), and
the Hencky strain log V of trsf trsf0^-1 (9). The substep schedule is the documented one of the
server, coded here again from YADE's API (no import of dem_app/python); numpy only for I/O and
log V.
"""
import os
import shutil
import signal
import sys
import tempfile

import numpy as np


def import_yade():
    """Import YADE as a module, leaving no folder behind: neither the symlink's nor YADE's own
    /tmp/yade-XXXXXX (removed only when the yade program exits; see yade_import_tmp.py)."""
    tmp = tempfile.mkdtemp(prefix="yade_standalone_")
    os.symlink("/usr/bin/yade", os.path.join(tmp, "yadeimport.py"))
    sys.path.insert(0, tmp)
    argv, sys.argv = sys.argv, ["standalone"]  # YADE parses sys.argv on import
    handler = signal.getsignal(signal.SIGINT)
    try:
        import yadeimport
    finally:
        sys.argv = argv
        signal.signal(signal.SIGINT, handler or signal.SIG_DFL)
        sys.path.remove(tmp)
        shutil.rmtree(tmp, ignore_errors=True)
    own = os.path.dirname(yadeimport.O.tmpFilename())
    if os.path.basename(own).startswith("yade-") and os.path.dirname(own) == "/tmp":
        shutil.rmtree(own, ignore_errors=True)
    return yadeimport


def engine_list(y, damping):
    return [
        y.ForceResetter(),
        y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
        y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_FrictMat_FrictMat_FrictPhys()],
                          [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
        y.NewtonIntegrator(damping=damping),
    ]


def to_np(m):
    return np.array([[m[i, j] for j in range(3)] for i in range(3)])


def to_yade(y, a):
    return y.Matrix3(*[float(a[i, j]) for i in range(3) for j in range(3)])


def hencky(F):
    w, v = np.linalg.eigh(F @ F.T)
    return v @ np.diag(0.5 * np.log(w)) @ v.T


def main(packing, df_file, ns, damping, out):
    y = import_yade()
    O = y.O
    O.load(packing)
    O.engines = engine_list(y, damping)
    O.cell.velGrad = y.Matrix3.Zero
    O.step()
    O.step()
    for b in O.bodies:
        b.state.refPos = b.state.pos
        b.state.refOri = b.state.ori
        b.state.vel = y.Vector3.Zero
        b.state.angVel = y.Vector3.Zero
    O.engines = engine_list(y, damping)
    dt = O.dt
    trsf0 = to_np(O.cell.trsf)

    dfs = [np.array([float(x) for x in line.split()]).reshape(3, 3)
           for line in open(df_file) if line.strip() and not line.lstrip().startswith("#")]
    rows = []

    def record(n):
        s = to_np(y.utils.getStress())
        s = 0.5 * (s + s.T)
        eps = hencky(to_np(O.cell.trsf) @ np.linalg.inv(trsf0))
        rows.append([n] + list(s.ravel()) + list(eps.ravel()))

    record(0)
    # The schedule in YADE's own Matrix3 arithmetic (what trsf integration uses too).
    I = y.Matrix3.Identity
    pending = y.Matrix3.Zero  # the velGrad YADE will use in the next step
    for n, dF in enumerate(dfs, start=1):
        target = to_yade(y, dF) * O.cell.trsf
        for j in range(1, ns + 1):
            left = ns - j
            if j == 1 or left == 1:
                after = (I + pending * dt) * O.cell.trsf  # trsf once step j is done
                pending = (target * after.inverse() - I) / (left * dt)
                O.cell.velGrad = pending
            if left == 0:  # pending for the next burst's substep 1: this burst's mean rate
                pending = (to_yade(y, dF) - I) / (ns * dt)
                O.cell.velGrad = pending
            O.step()
        record(n)
    with open(out, "w") as f:
        f.write("step," + ",".join("sigma_%d" % i for i in range(9)) + ","
                + ",".join("eps_%d" % i for i in range(9)) + "\n")
        for r in rows:
            f.write("%d," % r[0] + ",".join(repr(float(v)) for v in r[1:]) + "\n")
    want = trsf0
    for dF in dfs:
        want = dF @ want
    print("yade_standalone: %d spheres, %d increments, ns %d, dt %.4g s, max |trsf - "
          "dF_n..dF_1 trsf0| = %.3g" % (len(O.bodies), len(dfs), ns, dt,
                                        float(np.abs(to_np(O.cell.trsf) - want).max())))


if __name__ == "__main__":
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), sys.argv[5])
    sys.stdout.flush()
    os._exit(0)  # skip YADE's slow/noisy teardown

"""Periodic sphere packings for mpmdem RVEs (paper Table 1 defaults), built with YADE.

Two uses:
  * library: ``scripts/build_packings --config FILE --out DIR`` runs this file as a script
    (inside Debian's /usr/bin/python3, YADE imported as a module) and writes, per packing,
    ``<name>.yade.bz2`` (YADE O.save) and ``<name>.json`` (parameters, seed, porosity,
    coordination, stress);
  * in process: mpmdem_rve imports build_into_current_scene() to make small packings on the
    fly when the scene names no library (tests).

Table 1 mapping (see docs/dem_backend.md): 800 spheres, radius uniform 0.92-1.38 mm
(``size_is: radius``; ``diameter`` halves it: Lajeunesse et al.'s beads had diameters in that
range), density 2500 kg/m3, E = 600 MPa, friction 0.518 (tan 27.4 deg), linear law
(Law2_ScGeom_FrictPhys_CundallStrack) with ks/kn given through FrictMat.poisson (in YADE's
Ip2_FrictMat_FrictMat_FrictPhys, poisson is the ks/kn ratio, not Poisson's ratio).
"""
import json
import math
import os
import sys

TABLE1 = {
    "n_spheres": 800,
    "size_min": 0.92e-3,  # m
    "size_max": 1.38e-3,  # m
    "size_is": "radius",  # radius | diameter
    "density": 2500.0,  # kg/m3
    "young": 6.0e8,  # Pa (contact modulus E of FrictMat)
    "ks_kn": 0.8,  # FrictMat.poisson = ks/kn (not given by Table 1; YADE FEMxDEM value)
    "friction": 0.518,  # interparticle friction coefficient
    "pressure": 1.0e4,  # Pa, isotropic consolidation pressure (compression)
    "protocol": "loose",  # loose: friction on while compacting; dense: frictionless first
    "porosity_init": 0.75,  # porosity of the initial cloud (cell sized to it)
    "damping": 0.2,  # Newton non-viscous damping during preparation
    "unbalanced_tol": 0.01,  # stop consolidation below this unbalanced force ...
    "stress_tol": 1e-3,  # ... and this relative stress error
    "max_steps": 400000,
    "max_strain_rate": 1.0,  # 1/s, cap of the controller's cell strain rate
    "seed": 1,
}


def _import_yade():
    """Import YADE as a module (argv, symlink, SIGINT: see docs/dem_backend.md)."""
    if "yadeimport" in sys.modules:
        return sys.modules["yadeimport"]
    import shutil
    import signal
    import tempfile

    # The symlink is needed only while importing: removed right after, so that no process
    # leaves a folder in $TMPDIR (tests/integration/yade_import_tmp.cmake).
    tmp = tempfile.mkdtemp(prefix="mpmdem_yade_")
    os.symlink("/usr/bin/yade", os.path.join(tmp, "yadeimport.py"))
    sys.path.insert(0, tmp)
    argv = sys.argv
    sys.argv = ["rve"]
    handler = signal.getsignal(signal.SIGINT)
    try:
        import yadeimport  # noqa: F401  (prints YADE's banner)
    finally:
        sys.argv = argv
        signal.signal(signal.SIGINT, handler if handler is not None else signal.SIG_DFL)
        sys.path.remove(tmp)
        shutil.rmtree(tmp, ignore_errors=True)
    y = sys.modules["yadeimport"]
    # YADE's Omega also makes /tmp/yade-XXXXXX (a fixed /tmp, not $TMPDIR) for O.tmpFilename(),
    # which only its plot server uses, and removes it only when the yade program exits: every
    # process that imports YADE left one behind (hundreds after a CI run). Removed now.
    own = os.path.dirname(y.O.tmpFilename())
    if os.path.basename(own).startswith("yade-") and os.path.dirname(own) == "/tmp":
        shutil.rmtree(own, ignore_errors=True)
    return y


def radii_range(p):
    f = 1.0 if p["size_is"] == "radius" else 0.5
    return p["size_min"] * f, p["size_max"] * f


def engines(y, damping, with_triax, contact_law="frict"):
    """Engine list; order is fixed so engines can be addressed by index after a switch:
    0 ForceResetter, 1 collider, 2 InteractionLoop, [3 PeriTriaxController], last Newton.
    contact_law: frict (FrictMat, CundallStrack) or frict_visco (FrictViscoMat with a normal
    dashpot, CundallStrackVisco; the scene's bodies converted by to_frict_visco)."""
    if contact_law == "frict_visco":
        ip2, law2 = y.Ip2_FrictViscoMat_FrictViscoMat_FrictViscoPhys(), \
            y.Law2_ScGeom_FrictViscoPhys_CundallStrackVisco()
    else:
        ip2, law2 = y.Ip2_FrictMat_FrictMat_FrictPhys(), y.Law2_ScGeom_FrictPhys_CundallStrack()
    e = [
        y.ForceResetter(),
        y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
        y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [ip2], [law2]),
    ]
    if with_triax:
        e.append(y.PeriTriaxController(dynCell=True, stressMask=7, goal=(0, 0, 0), maxUnbalanced=1e9))
    e.append(y.NewtonIntegrator(damping=damping))
    return e


def to_frict_visco(y, beta_n):
    """The current scene (one FrictMat) with the frict_visco law: every body gets a
    FrictViscoMat of the same moduli, density and friction with betan = beta_n, and every
    real interaction a FrictViscoPhys computed as Ip2_FrictViscoMat_FrictViscoMat_FrictViscoPhys
    does (kn, ks harmonic means of E r and E r poisson; cn = betan 2 sqrt(m* kn)), keeping its
    shear and normal force. The scene is then reloaded from a string: an interaction keeps the
    law functor it was first dispatched to (Interaction::functorCache), which the reload
    clears, so that the new engines' CundallStrackVisco acts on every contact."""
    O = y.O
    old = O.bodies[0].mat
    mat = y.FrictViscoMat(young=old.young, poisson=old.poisson, density=old.density,
                          frictionAngle=old.frictionAngle, betan=beta_n)
    O.materials.append(mat)
    for b in O.bodies:
        b.mat = mat
    ea = eb = mat.young
    va = vb = mat.poisson
    for i in O.interactions:
        if not i.isReal:
            continue
        ra, rb = i.geom.refR1, i.geom.refR2
        kn = 2. * ea * ra * eb * rb / (ea * ra + eb * rb)
        ks = 2. * ea * ra * va * eb * rb * vb / (ea * ra * va + eb * rb * vb)
        ma, mb = O.bodies[i.id1].state.mass, O.bodies[i.id2].state.mass
        mbar = ma * mb / (ma + mb)
        cn_crit = 2. * math.sqrt(mbar * kn)
        cn = cn_crit * ((beta_n + beta_n) / 2.) if beta_n != 0 else 0.
        p = y.FrictViscoPhys(kn=kn, ks=ks, tangensOfFrictionAngle=math.tan(mat.frictionAngle),
                             cn=cn, cn_crit=cn_crit)
        p.shearForce = i.phys.shearForce
        p.normalForce = i.phys.normalForce
        i.phys = p
    O.stringToScene(O.sceneToString())


def consolidate(y, goal, p, max_steps=None, unb_tol=None):
    """Drive the current scene (engines from engines(..., with_triax=True)) to the principal
    stress `goal` (tension positive, Pa) with PeriTriaxController; returns steps used."""
    O = y.O
    tri = O.engines[3]
    tri.goal = tuple(goal)
    tri.stressMask = 7
    tri.maxUnbalanced = 1e9  # we test convergence ourselves
    tri.relStressTol = p["stress_tol"]
    tri.maxStrainRate = (p["max_strain_rate"],) * 3
    max_steps = max_steps or p["max_steps"]
    unb_tol = unb_tol or p["unbalanced_tol"]
    scale = max(abs(g) for g in goal)
    steps = 0
    while steps < max_steps:
        for _ in range(100):
            O.step()
        steps += 100
        s = y.utils.getStress()
        err = max(abs(s[i, i] - goal[i]) for i in range(3)) / scale
        if err < 0.2:  # close to the goal: settle at the careful rate
            tri.maxStrainRate = (min(p["max_strain_rate"], 1.0),) * 3
        if err < p["stress_tol"] * 10 and y.utils.unbalancedForce() < unb_tol:
            break
    return steps


def finish_preparation(y):
    """Remove the controller, stop the cell, reset reference positions and orientations."""
    O = y.O
    O.engines = [e for e in O.engines if not isinstance(e, y.PeriTriaxController)]
    O.cell.velGrad = y.Matrix3.Zero
    O.step()  # the zero velGrad becomes active from the next step
    O.step()
    for b in O.bodies:
        b.state.refPos = b.state.pos
        b.state.refOri = b.state.ori
        b.state.vel = y.Vector3.Zero
        b.state.angVel = y.Vector3.Zero


def build_into_current_scene(p):
    """Make a consolidated packing from parameters p (TABLE1 keys) in the current scene."""
    y = _import_yade()
    O = y.O
    rmin, rmax = radii_range(p)
    rmean = 0.5 * (rmin + rmax)
    fuzz = (rmax - rmin) / (rmax + rmin)
    vol_s = p["n_spheres"] * 4.0 / 3.0 * math.pi * rmean**3 * (1 + fuzz**2)
    edge = (vol_s / (1 - p["porosity_init"])) ** (1.0 / 3.0)
    O.periodic = True
    O.cell.setBox(edge, edge, edge)
    mu_deg = math.degrees(math.atan(p["friction"]))
    mat = y.FrictMat(young=p["young"], poisson=p["ks_kn"], density=p["density"],
                     frictionAngle=math.radians(mu_deg))
    O.materials.append(mat)
    sp = y.pack.SpherePack()
    sp.makeCloud((0, 0, 0), (edge, edge, edge), rMean=rmean, rRelFuzz=fuzz, num=p["n_spheres"],
                 periodic=True, seed=int(p["seed"]))
    sp.toSimulation(material=mat)
    O.engines = engines(y, p["damping"], True)
    O.dt = 0.5 * y.utils.PWaveTimeStep()
    goal = (-p["pressure"],) * 3
    if p["protocol"] == "dense":
        for b in O.bodies:
            b.mat = mat  # shared material
        mat.frictionAngle = 0.0
        consolidate(y, goal, p, unb_tol=max(p["unbalanced_tol"], 1e-2))
        mat.frictionAngle = math.radians(mu_deg)
        for i in O.interactions:  # contacts made frictionless keep tan(phi)=0: update them
            if i.isReal:
                i.phys.tangensOfFrictionAngle = p["friction"]
    steps = consolidate(y, goal, p)
    finish_preparation(y)
    return steps


def state_summary(y):
    O = y.O
    s = y.utils.getStress()
    s = 0.5 * (s + s.transpose())
    return {
        "porosity": y.utils.porosity(),
        "coordination": y.utils.avgNumInteractions(),
        "stress": [[float(s[i, j]) for j in range(3)] for i in range(3)],
        "mean_stress": float(s.trace() / 3.0),
        "unbalanced_force": y.utils.unbalancedForce(),
        "n_spheres": len(O.bodies),
        "cell_edge": [float(O.cell.hSize[i, i]) for i in range(3)],
        "dt": O.dt,
    }


def _read_config(path):
    import yaml  # Debian python3-yaml

    with open(path) as f:
        doc = yaml.safe_load(f) or {}
    block = doc.get("packings", doc)
    common = {k: v for k, v in block.items() if k not in ("items",)}
    items = block.get("items") or [{"name": "table1"}]
    out = []
    for it in items:
        p = dict(TABLE1)
        p.update(common)
        p.update(it)
        unknown = set(p) - set(TABLE1) - {"name", "copies"}
        if unknown:
            raise SystemExit("%s: unknown packing keys %s (known: %s)" % (path, sorted(unknown), sorted(TABLE1)))
        if p["size_is"] not in ("radius", "diameter") or p["protocol"] not in ("loose", "dense"):
            raise SystemExit("%s: size_is must be radius|diameter, protocol loose|dense" % path)
        for k, v in TABLE1.items():  # YAML 1.1 reads 1.0e4 as a string: coerce
            p[k] = type(v)(p[k])
        for c in range(int(p.get("copies", 1))):
            q = dict(p)
            q.pop("copies", None)
            q["seed"] = int(p["seed"]) + c
            q["name"] = "%s_s%d" % (p.get("name", "packing"), q["seed"])
            out.append(q)
    return out


def main(argv):
    import argparse
    import time

    ap = argparse.ArgumentParser(description="Build mpmdem RVE packings (Table 1 defaults).")
    ap.add_argument("--config", help="YAML file with a `packings:` block (keys of TABLE1, "
                    "optional items: [{name, seed, copies, ...}])")
    ap.add_argument("--out", required=True, help="packing library folder")
    a = ap.parse_args(argv)
    items = _read_config(a.config) if a.config else [dict(TABLE1, name="table1_s1")]
    os.makedirs(a.out, exist_ok=True)
    y = _import_yade()
    for p in items:
        t0 = time.time()
        y.O.switchToScene(0)
        y.O.reset()
        steps = build_into_current_scene(p)
        info = {"parameters": p, "steps": steps, "wall_s": time.time() - t0}
        info.update(state_summary(y))
        base = os.path.join(a.out, p["name"])
        y.O.save(base + ".yade.bz2")
        with open(base + ".json", "w") as f:
            json.dump(info, f, indent=1)
        print("%s: porosity %.4f coordination %.3f mean stress %.1f Pa (%d steps, %.1f s)"
              % (p["name"], info["porosity"], info["coordination"], info["mean_stress"], steps,
                 info["wall_s"]))


if __name__ == "__main__":
    main(sys.argv[1:])

"""Export YADE scenes (packing libraries, *.yade.bz2) to the native backend's packing format.

``scripts/export_native_packings --in DIR [--out DIR] [NAME ...]`` runs this file under
Debian's /usr/bin/python3 with YADE imported as a module, and writes ``<name>.native.txt``
next to (or into --out) each ``<name>.yade.bz2``: dt, the material, the cell (hSize, trsf,
velGrad, prevVelGrad), every sphere (radius, mass, inertia, position, velocity, angular
velocity, orientation, reference orientation) and every real contact (ids, cellDist, kn, ks,
tan(friction), normal, shear force, normal force, penetration), all in full precision
(repr), so that the native backend continues exactly the state YADE saved
(dem_app/src/backends/native/packing.hpp reads it).
"""
import math
import os
import sys

import mpmdem_packing as pk

MAGIC = "mpmdem-native-packing 1"


def _r(x):
    return repr(float(x))


def _vec(v):
    return " ".join(_r(v[i]) for i in range(3))


def _mat(m):
    return " ".join(_r(m[i, j]) for i in range(3) for j in range(3))


def _quat(q):
    x, y, z, w = list(q)
    return " ".join(_r(c) for c in (w, x, y, z))


def _finite_or_zero(x):
    # ScGeom.penetrationDepth is not saved (NaN after O.load); every step recomputes it.
    return x if math.isfinite(x) else 0.0


def export_current_scene(y, path):
    """Write the current YADE scene (periodic, spheres of one FrictMat) to `path`."""
    O = y.O
    if not O.periodic:
        raise SystemExit("%s: the scene is not periodic" % path)
    mats = {(b.material.young, b.material.poisson, b.material.density,
             b.material.frictionAngle): b.material for b in O.bodies}
    if len(mats) != 1:
        raise SystemExit("%s: expected one material, found %d" % (path, len(mats)))
    m = list(mats.values())[0]
    c = O.cell
    lines = [MAGIC, "dt " + _r(O.dt),
             "material %s %s %s %s" % (_r(m.young), _r(m.poisson), _r(m.density),
                                       _r(m.frictionAngle)),
             "hsize " + _mat(c.hSize), "trsf " + _mat(c.trsf),
             "vel_grad " + _mat(c.nextVelGrad if c.velGradChanged else c.velGrad),
             "prev_vel_grad " + _mat(c.prevVelGrad)]
    ids = [b.id for b in O.bodies]
    if ids != list(range(len(ids))):
        raise SystemExit("%s: body ids are not 0..n-1" % path)
    lines.append("spheres %d" % len(ids))
    for b in O.bodies:
        s = b.state
        lines.append(" ".join([_r(b.shape.radius), _r(s.mass), _r(s.inertia[0]), _vec(s.pos),
                               _vec(s.vel), _vec(s.angVel), _quat(s.ori), _quat(s.refOri)]))
    real = [i for i in O.interactions if i.isReal]
    lines.append("contacts %d" % len(real))
    for i in real:
        g, p = i.geom, i.phys
        cd = i.cellDist
        lines.append(" ".join(["%d %d %d %d %d" % (i.id1, i.id2, cd[0], cd[1], cd[2]),
                               _r(p.kn), _r(p.ks), _r(p.tangensOfFrictionAngle),
                               _vec(g.normal), _vec(p.shearForce), _vec(p.normalForce),
                               _r(_finite_or_zero(g.penetrationDepth))]))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main(argv):
    import argparse
    import glob

    ap = argparse.ArgumentParser(description="Export YADE packings to the native format.")
    ap.add_argument("--in", dest="src", required=True, help="packing library folder")
    ap.add_argument("--out", help="output folder (default: --in)")
    ap.add_argument("names", nargs="*", help="packing names (default: every *.yade.bz2)")
    a = ap.parse_args(argv)
    out = a.out or a.src
    os.makedirs(out, exist_ok=True)
    names = a.names or sorted(os.path.basename(p)[:-len(".yade.bz2")]
                              for p in glob.glob(os.path.join(a.src, "*.yade.bz2")))
    y = pk._import_yade()
    for name in names:
        y.O.load(os.path.join(a.src, name + ".yade.bz2"))
        path = os.path.join(out, name + ".native.txt")
        export_current_scene(y, path)
        print("%s: %d spheres -> %s" % (name, len(y.O.bodies), path))


if __name__ == "__main__":
    main(sys.argv[1:])

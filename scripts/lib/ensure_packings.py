"""Make sure the packing library a YADE scene names exists; build it from the scene's
packing spec if it does not.

  /usr/bin/python3 scripts/lib/ensure_packings.py SCENE.yaml

Reads coupling.backend, coupling.yade.packing_dir, .packings and .packing_spec (paths
relative to the scene file's folder unless absolute). Nothing to do for other backends, for
inline packings (empty packing_dir) or when every <packing_dir>/<name>.yade.bz2 exists.
Otherwise runs scripts/build_packings --config <packing_spec> --out <packing_dir> and checks
that it produced every packing the scene names. The spec's SHA-256 is kept in
<packing_dir>/.spec_sha256: when the spec changes, the packings are rebuilt.
Several runs started together (one checkout, one packing_dir) build the library once: the
check and the build hold an exclusive flock on <packing_dir>/.lock, so the other runs wait
for it and then find the library ready.
Exit codes: 0 ready, 2 the scene names packings that are missing and cannot be built (the
message says which key to change), 1 the builder failed.
"""
import fcntl
import hashlib
import os
import subprocess
import sys

import yaml


def fail(msg, code=2):
    print("ensure_packings: " + msg, file=sys.stderr)
    sys.exit(code)


def main(scene):
    try:
        doc = yaml.safe_load(open(scene)) or {}
    except (OSError, yaml.YAMLError) as e:
        fail(f"cannot read {scene}: {e}")
    coupling = doc.get("coupling") or {}
    if coupling.get("backend") != "yade":
        return 0
    yade = coupling.get("yade") or {}
    base = os.path.dirname(os.path.abspath(scene))
    pdir = yade.get("packing_dir") or ""
    names = yade.get("packings") or []
    if not pdir:
        return 0
    pdir = os.path.normpath(os.path.join(base, pdir))
    spec = yade.get("packing_spec") or ""
    if spec:  # buildable: one process at a time checks and builds (the lock is freed at exit)
        try:
            os.makedirs(pdir, exist_ok=True)
            lock = open(os.path.join(pdir, ".lock"), "a")
        except OSError as e:
            fail(f"cannot create coupling.yade.packing_dir {pdir} ({scene}): {e}")
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            print(f"ensure_packings: waiting for another run building into {pdir}", flush=True)
            fcntl.flock(lock, fcntl.LOCK_EX)
    missing = [n for n in names if not os.path.exists(os.path.join(pdir, n + ".yade.bz2"))]
    digest, stamp = None, os.path.join(pdir, ".spec_sha256")
    if spec:
        spec_path = os.path.normpath(os.path.join(base, spec))
        if os.path.exists(spec_path):
            digest = hashlib.sha256(open(spec_path, "rb").read()).hexdigest()
            old = open(stamp).read().strip() if os.path.exists(stamp) else None
            if not missing and old != digest:
                print(f"ensure_packings: {spec_path} changed since {pdir} was built: rebuilding",
                      flush=True)
                missing = list(names)
    if not missing:
        return 0
    if not spec:
        fail(f"coupling.yade.packings {missing} are not in coupling.yade.packing_dir {pdir} "
             f"({scene}), and coupling.yade.packing_spec is empty: build them with "
             "scripts/build_packings --config SPEC --out DIR, or name a spec")
    spec = os.path.normpath(os.path.join(base, spec))
    if not os.path.exists(spec):
        fail(f"coupling.yade.packing_spec {spec} does not exist ({scene})")
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    builder = os.path.join(root, "scripts", "build_packings")
    print(f"ensure_packings: building {len(missing)} missing packing(s) into {pdir} from {spec}",
          flush=True)
    os.makedirs(pdir, exist_ok=True)
    rc = subprocess.call([builder, "--config", spec, "--out", pdir])
    if rc != 0:
        fail(f"scripts/build_packings failed (exit {rc})", 1)
    still = [n for n in names if not os.path.exists(os.path.join(pdir, n + ".yade.bz2"))]
    if still:
        fail(f"{spec} did not produce {still} that coupling.yade.packings names ({scene}); "
             "make the spec's item names and copies match")
    if digest:
        with open(stamp, "w") as f:
            f.write(digest + "\n")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))

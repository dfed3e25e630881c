"""Make sure the packing library a YADE or native scene names exists; build it from the
scene's packing spec if it does not.

  /usr/bin/python3 scripts/lib/ensure_packings.py SCENE.yaml

Reads coupling.backend and coupling.<backend>.packing_dir, .packings and .packing_spec
(paths relative to the scene file's folder unless absolute). Nothing to do for other
backends, for inline packings (empty packing_dir) or when every packing exists
(<packing_dir>/<name>.yade.bz2 for yade, <name>.native.txt for native). Otherwise runs
scripts/build_packings --config <packing_spec> --out <packing_dir> (for native: only for the
YADE packings that are missing too, then scripts/export_native_packings --in <packing_dir>
for the names) and checks that it produced every packing the scene names. The spec's SHA-256 is kept in
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


def key_line(text, path):
    """1-based line of the key at `path` (["coupling", "yade", "packings"]) in the YAML text,
    or of its nearest present section (as mpm_app and dem_app report a key)."""
    node = yaml.compose(text)
    line = node.start_mark.line + 1 if node is not None else 1
    for part in path:
        found = [(k, v) for k, v in node.value if k.value == part] \
            if isinstance(node, yaml.MappingNode) else []
        if not found:
            break
        line, node = found[0][0].start_mark.line + 1, found[0][1]
    return line


def main(scene):
    try:
        text = open(scene).read()
        doc = yaml.safe_load(text) or {}
    except (OSError, yaml.YAMLError) as e:
        fail(f"cannot read {scene}: {e}")
    coupling = doc.get("coupling") or {}
    backend = coupling.get("backend")
    if backend == "cuda":  # the GPU backend runs the native backend's packings (coupling.native)
        backend = "native"
    if backend not in ("yade", "native"):
        return 0
    ext = ".yade.bz2" if backend == "yade" else ".native.txt"
    yade = coupling.get(backend) or {}
    base = os.path.dirname(os.path.abspath(scene))
    pdir = yade.get("packing_dir") or ""
    names = yade.get("packings") or []
    if not pdir:
        return 0
    pdir = os.path.normpath(os.path.join(base, pdir))
    spec = yade.get("packing_spec") or ""

    def at(key):  # "(SCENE line N)" of coupling.<backend>.<key>
        return f"({scene} line {key_line(text, ['coupling', backend, key])})"

    if spec and not os.path.exists(os.path.normpath(os.path.join(base, spec))) and any(
            not os.path.exists(os.path.join(pdir, n + ext)) for n in names):
        # Refused before anything is created (the lock below makes packing_dir).
        fail(f"coupling.{backend}.packing_spec {os.path.normpath(os.path.join(base, spec))} "
             f"does not exist {at('packing_spec')}, and packings it would build are missing")
    if spec:  # buildable: one process at a time checks and builds (the lock is freed at exit)
        try:
            os.makedirs(pdir, exist_ok=True)
            lock = open(os.path.join(pdir, ".lock"), "a")
        except OSError as e:
            fail(f"cannot create coupling.{backend}.packing_dir {pdir} {at('packing_dir')}: {e}")
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            print(f"ensure_packings: waiting for another run building into {pdir}", flush=True)
            fcntl.flock(lock, fcntl.LOCK_EX)
    missing = [n for n in names if not os.path.exists(os.path.join(pdir, n + ext))]
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
        fail(f"coupling.{backend}.packings {missing} are not in coupling.{backend}.packing_dir "
             f"{pdir} {at('packings')}, and coupling.{backend}.packing_spec is empty: build them with "
             "scripts/build_packings --config SPEC --out DIR"
             + (" and scripts/export_native_packings --in DIR" if backend == "native" else "")
             + ", or name a spec")
    spec = os.path.normpath(os.path.join(base, spec))  # exists: checked above
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    builder = os.path.join(root, "scripts", "build_packings")
    os.makedirs(pdir, exist_ok=True)
    stale = digest is not None and (not os.path.exists(stamp) or open(stamp).read().strip() != digest)
    if backend == "yade" or stale or any(
            not os.path.exists(os.path.join(pdir, n + ".yade.bz2")) for n in missing):
        print(f"ensure_packings: building {len(missing)} missing packing(s) into {pdir} from "
              f"{spec}", flush=True)
        rc = subprocess.call([builder, "--config", spec, "--out", pdir])
        if rc != 0:
            fail(f"scripts/build_packings failed (exit {rc})", 1)
    if backend == "native":
        rc = subprocess.call([os.path.join(root, "scripts", "export_native_packings"), "--in",
                              pdir, "--out", pdir] + missing)
        if rc != 0:
            fail(f"scripts/export_native_packings failed (exit {rc})", 1)
    still = [n for n in names if not os.path.exists(os.path.join(pdir, n + ext))]
    if still:
        fail(f"{spec} did not produce {still} that coupling.{backend}.packings names "
             f"{at('packings')}; "
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

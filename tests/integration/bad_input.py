#!/usr/bin/python3
"""Bad input, nothing lost (issue 6, item 4).

Every broken scene below goes through scripts/run and through mpm_app directly. Each must:
exit with code 2, print a message naming the problem (the key or what is wrong, and the
file), and leave the --out folder uncreated. Then: a pre-existing run folder is never
overwritten without --force (a valid scene with --out pointing at it exits 2 and leaves it
byte-identical), and a broken scene with --force does not touch it either.
Usage: bad_input.py BUILD_DIR SOURCE_DIR
"""
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile

bin_dir, src = sys.argv[1], sys.argv[2]
mpm_app = os.path.join(bin_dir, "mpm_app", "mpm_app")
run = os.path.join(src, "scripts", "run")
base = open(os.path.join(src, "configs", "elastic_column.yaml")).read()
remote_base = open(os.path.join(src, "configs", "column_collapse.yaml")).read()

# name: (scene text, words the message must contain)
def edit(text, *pairs):
    for old, new in pairs:
        assert old in text, old
        text = text.replace(old, new, 1)
    return text

CASES = {
    "missing_key": (edit(base, ("    density: 2000.0\n", "")), ["regions[0].density", "required"]),
    "wrong_type": (edit(base, ("cell_size: 0.02", "cell_size: abc")), ["grid.cell_size", "number", "'abc'"]),
    "zero_density": (edit(base, ("density: 2000.0", "density: 0")), ["regions[0].density", "> 0", "got 0"]),
    "negative_density": (edit(base, ("density: 2000.0", "density: -5")), ["regions[0].density", "-5"]),
    "negative_cell_size": (edit(base, ("cell_size: 0.02", "cell_size: -0.02")), ["grid.cell_size", "-0.02"]),
    "zero_extent": (edit(base, ("extent: [0.02, 0.02, 1.1]", "extent: [0.0, 0.02, 1.1]")), ["grid.extent"]),
    "unknown_key": (edit(base, ("  scheme: musl\n", "  scheme: musl\n  sheme: usl\n")), ["solver.sheme"]),
    "malformed_yaml": (edit(base, ("regions:\n", "regions: [\n")), ["malformed YAML"]),
    "wrong_config_version": (edit(base, ("config_version: 1", "config_version: 7")), ["config_version", "7"]),
    "domain_smaller_than_material": (edit(base, ("extent: [0.02, 0.02, 1.1]", "extent: [0.02, 0.02, 0.5]")),
                                     ["regions[0].max", "outside the domain"]),
    "empty_region": (edit(base, ("max: [0.02, 0.02, 1.0]", "max: [0.02, 0.02, 1.0e-9]")),
                     ["regions[0]", "no material points"]),
    "missing_packing_file": (edit(remote_base, ("packing_dir: ../packings/column_collapse", "packing_dir: /nonexistent/packings"),
                                  ("packing_spec: packings/column_collapse.yaml", "packing_spec: \"\"")),
                             ["coupling.yade.packings", "/nonexistent/packings", "packing_spec"]),
    "rve_costs_without_remote": (edit(base, ("output:\n", "output:\n  rve_costs: true\n")),
                                 ["output.rve_costs", "linear_elastic", "remote"]),
    "empty_file": ("", ["empty"]),
}

env = dict(os.environ, MPMDEM_SKIP_SETUP="1", MPMDEM_BUILD_DIR=bin_dir)
fails = []
work = tempfile.mkdtemp(prefix="bad_input_")


def tree_hash(d):
    h = hashlib.sha256()
    for root, dirs, files in sorted(os.walk(d)):
        dirs.sort()
        for f in sorted(files):
            p = os.path.join(root, f)
            h.update(p.encode())
            h.update(open(p, "rb").read())
    return h.hexdigest()


try:
    for name, (text, words) in CASES.items():
        scene = os.path.join(work, name + ".yaml")
        open(scene, "w").write(text)
        for how, cmd in (("scripts/run", [run, scene, "--out", os.path.join(work, "out_run_" + name)]),
                         ("mpm_app", [mpm_app, scene, "--out", os.path.join(work, "out_app_" + name)])):
            if name == "missing_packing_file" and how == "mpm_app":
                continue  # packings are the DEM side's: scripts/run checks them before starting it
            p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
            msg = p.stdout + p.stderr
            out = cmd[-1]
            problems = []
            if p.returncode != 2:
                problems.append(f"exit {p.returncode}")
            missing = [w for w in words + [os.path.basename(scene)] if w not in msg]
            if missing and name != "empty_file":
                problems.append(f"message lacks {missing}")
            if os.path.exists(out):
                problems.append("created the output folder")
            if problems:
                fails.append(f"{name} via {how}: {'; '.join(problems)}\n    {msg.strip()[:300]}")
            else:
                print(f"ok  {name:30s} {how:11s} {msg.strip().splitlines()[-1][:110]}")

    # A finished run is never overwritten without --force, and a bad scene never touches it.
    good = os.path.join(work, "good.yaml")
    open(good, "w").write(edit(base, ("end_time: 0.5", "end_time: 0.01")))
    prev = os.path.join(work, "previous_run")
    p = subprocess.run([run, good, "--out", prev], capture_output=True, text=True, env=env, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    before = tree_hash(prev)
    for label, cmd in (("same scene, no --force", [run, good, "--out", prev]),
                       ("mpm_app, no --force", [mpm_app, good, "--out", prev]),
                       ("bad scene with --force", [run, os.path.join(work, "zero_density.yaml"), "--out", prev, "--force"])):
        p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
        if p.returncode != 2 or tree_hash(prev) != before:
            fails.append(f"{label}: exit {p.returncode}, folder {'unchanged' if tree_hash(prev) == before else 'CHANGED'}")
        else:
            print(f"ok  previous run kept: {label}")
finally:
    shutil.rmtree(work, ignore_errors=True)

if fails:
    print("FAIL:\n  " + "\n  ".join(fails))
    sys.exit(1)
print(f"bad_input: {len(CASES)} broken scenes rejected with exit 2 before any output; previous run kept")

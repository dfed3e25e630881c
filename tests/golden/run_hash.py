#!/usr/bin/python3
"""The physics of a run directory as one hash: what must stay bit for bit the same when code is
reshaped (issue 37) or a launcher changes (one host against several).

  run_hash.py RUN_DIR          prints the hash and what went into it (one line per part)

Hashed: every dataset of final_state.h5 (bytes, in name order) with its step and time, and
every figure of summary.json except those that depend on the machine, the clock or the paths
(wall and CPU times, per-phase timings, imbalance, checkpoint counts, rebalances, directories,
version). Figures are hashed as repr() of the JSON values, so a change in the last bit shows.
"""
import hashlib
import json
import re
import sys

import h5py
import numpy as np

# Summary keys that are not physics: they differ between machines, loads or run folders.
NOT_PHYSICS = re.compile(r"(wall|cpu|^time_(p2g|grid|g2p_dF|stress|exchange|dem_max|dem_mean|comm)_s$"
                         r"|ns_per_point_step|imbalance|checkpoint|^rebalances$|^run_directory$"
                         r"|^config_file$|^program_version$|^threads$|^dem_ranks$|^resumed_from_step$"
                         r"|^steps_after_resume$)")


def flatten(prefix, value, out):
    if isinstance(value, dict):
        for k in sorted(value):
            flatten(f"{prefix}.{k}" if prefix else k, value[k], out)
    else:
        out[prefix] = value


def run_hash(run_dir):
    h = hashlib.sha256()
    parts = []
    with h5py.File(f"{run_dir}/final_state.h5", "r") as f:
        for name in sorted(f.keys()):
            a = np.ascontiguousarray(f[name][()])
            h.update(name.encode() + str(a.dtype).encode() + str(a.shape).encode() + a.tobytes())
            parts.append(f"final_state.h5/{name} {a.dtype}{list(a.shape)}")
        for k in ("step", "time"):
            h.update(f"{k}={f.attrs[k]!r}".encode())
    flat = {}
    flatten("", json.load(open(f"{run_dir}/summary.json")), flat)
    keys = [k for k in sorted(flat) if not NOT_PHYSICS.search(k.split(".")[-1])]
    for k in keys:
        h.update(f"{k}={flat[k]!r}\n".encode())
    parts.append(f"summary.json: {len(keys)} figures")
    return h.hexdigest()[:16], parts


if __name__ == "__main__":
    digest, parts = run_hash(sys.argv[1])
    print(digest)
    for p in parts:
        print("  " + p)

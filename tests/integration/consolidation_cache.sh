#!/usr/bin/env bash
# Consolidation once per (packing, stress) and its cache on disk (issue 36, item 5;
# coupling.native.consolidation_cache). The tiny native block (tests/integration/
# native_block_tiny.yaml twice as long: 16 points on 2 depths) with two 40-sphere packings
# (tests/integration/packings: clouds written by native::build_cloud, seeds 36 and 37) on 2
# DEM ranks, 3 MPM steps, run four times:
#   off   no cache folder: each rank still consolidates each distinct (packing, stress) once
#   cold  an empty cache folder: the states are consolidated and stored, one file per key
#   warm  the same folder: every state is read from it, no DEM step is run to consolidate
#   mended  one file truncated: it is consolidated again (a warning), and rewritten
# All four end bitwise equal (final_state.h5) and with equal summary figures; the counts come
# from dem_app's log ("N distinct (packing, stress): C consolidated here ..., H from the
# consolidation cache"). A cache path that is a file is refused up front (exit 2, the key,
# its value, the file and the line), before any run directory is made.
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir). scripts/run starts and stops every
# process by PID.
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir consolidation_cache
fail() { echo "FAIL: $*" >&2; exit 1; }

scene() {  # scene DEST CACHE
  sed -e "s|^  extent: \[0.5, 0.5, 0.75\]|  extent: [1.0, 0.5, 0.75]|" \
    -e "s|^    max: \[0.5, 0.5, 0.5\]|    max: [1.0, 0.5, 0.5]|" \
    -e "s|^    inline_spheres: 40|    packing_dir: $src/tests/integration/packings\n    packings: [cloud40_s1, cloud40_s2]\n    consolidation_cache: \"$2\"|" \
    "$src/tests/integration/native_block_tiny.yaml" >"$1"
  grep -q "consolidation_cache: \"$2\"" "$1" && grep -q "max: \[1.0, 0.5, 0.5\]" "$1" ||
    fail "scene edit"
}
scene "$work/off.yaml" ""
scene "$work/cache.yaml" "$work/cache"
run_job "$work/off.log" "$work/off.yaml" --out "$work/off" --dem-ranks 2 --max-steps 3
run_job "$work/cold.log" "$work/cache.yaml" --out "$work/cold" --dem-ranks 2 --max-steps 3
run_job "$work/warm.log" "$work/cache.yaml" --out "$work/warm" --dem-ranks 2 --max-steps 3
ls "$work/cache"/*.consol >/dev/null 2>&1 || fail "no cache entry in $work/cache"
first=$(ls "$work/cache"/*.consol | head -n 1)
truncate -s -16 "$first"
run_job "$work/mended.log" "$work/cache.yaml" --out "$work/mended" --dem-ranks 2 --max-steps 3

/usr/bin/python3 - "$work" <<'PY' || fail "the runs"
import glob, json, re, sys
import h5py, numpy as np
w = sys.argv[1]
line = re.compile(r"prepared (\d+) RVEs in \S+ s \(CPU \S+ s\); (\d+) consolidated, DEM steps mean \d+, max \d+; "
                  r"(\d+) distinct \(packing, stress\): (\d+) consolidated here in (\d+) DEM steps, "
                  r"(\d+) from the consolidation cache")
def counts(run):
    rows = [tuple(map(int, m.groups())) for m in line.finditer(open(f"{w}/{run}/logs/dem_app.log").read())]
    assert len(rows) == 2, (run, rows)  # one line per rank
    return [sum(r[i] for r in rows) for i in range(6)]  # rves, consolidated, distinct, here, steps, hits
entries = len(glob.glob(f"{w}/cache/*.consol"))
assert not glob.glob(f"{w}/cache/*.tmp.*"), "a temporary file was left"
off, cold, warm, mended = (counts(r) for r in ("off", "cold", "warm", "mended"))
print("rves, consolidated, distinct, here, steps, hits:", off, cold, warm, mended, "entries", entries)
assert off[0] == off[1] == 16, off
assert off[2] <= 2 * 4, f"more groups than (2 packings x 2 depths) per rank: {off}"  # the grouping
assert off[3] == off[2] and off[5] == 0 and off[4] > 0, off
# cold: every distinct state of a rank consolidated by it or taken from the other rank's file
assert cold[3] + cold[5] == cold[2] == off[2] and cold[3] >= entries > 0, (cold, entries)
assert warm[5] == warm[2] == off[2] and warm[3] == 0 and warm[4] == 0, warm
assert mended[3] >= 1 and mended[3] + mended[5] == off[2], mended
log = open(f"{w}/mended/logs/dem_app.log").read()
assert "is not used: truncated" in log, "no warning for the truncated entry"
ref = h5py.File(f"{w}/off/final_state.h5", "r")
s0 = json.load(open(f"{w}/off/summary.json"))
# Every RVE holds its packing's 40 spheres and carries the geostatic stress of its point
# (rho g depth within 10 %, as in mpm_block.sh): copies are whole states, not empty ones.
assert s0["n_rve_particles"] == 16 * 40, s0["n_rve_particles"]
sigma, x0 = ref["stress"][:], ref["x0"][:]
expected = -1500.0 * 9.81 * (0.5 - x0[:, 2])
err = np.abs(sigma[:, 2, 2] - expected) / np.abs(expected)
assert err.max() < 0.10, ("sigma_zz", sigma[:, 2, 2], expected)
for run in ("cold", "warm", "mended"):
    f = h5py.File(f"{w}/{run}/final_state.h5", "r")
    assert sorted(f.keys()) == sorted(ref.keys())
    for k in ref.keys():
        if isinstance(ref[k], h5py.Dataset):
            assert np.array_equal(np.asarray(f[k]), np.asarray(ref[k])), f"{run}: {k} differs"
    s = json.load(open(f"{w}/{run}/summary.json"))
    for k in ("steps", "time_s", "E_d_J", "E_k_J", "energy_budget", "n_rve_particles",
              "rve_no_contact_updates"):
        assert s.get(k) == s0.get(k), f"{run}: summary {k} {s.get(k)} != {s0.get(k)}"
print("consolidation_cache: off, cold, warm and mended runs bitwise equal")
PY

# A cache path that is a file: refused before anything runs.
touch "$work/not_a_folder"
scene "$work/bad.yaml" "$work/not_a_folder"
"$src/scripts/run" "$work/bad.yaml" --out "$work/bad" --dem-ranks 1 >"$work/bad.log" 2>&1
rc=$?
[[ $rc == 2 && ! -e $work/bad ]] || fail "a file as the cache gave exit $rc: $(tail -n 5 "$work/bad.log")"
grep -q "coupling.native.consolidation_cache '$work/not_a_folder' .*exists and is not a folder.*bad.yaml line" "$work/bad.log" ||
  fail "no message naming the key, value, file and line: $(cat "$work/bad.log")"
echo "consolidation_cache: a file as the cache folder refused (exit 2)"

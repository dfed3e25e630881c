#!/usr/bin/env bash
# A minimal multiscale column collapse (tests/integration/column_yade_tiny.yaml) through
# scripts/run: mpm_app against dem_app --backend yade on 2 ranks, then the same run resumed
# from a checkpoint (scripts/run --resume) must end in exactly the same state.
# Checks: complete, mass conserved exactly, no point left the domain, nothing non-finite,
# E_d >= 0 (within 1% of E_p0) after the release, the column spread (runout > L_i), the
# report and pictures written; resumed positions, velocities and stresses equal to the
# uninterrupted run's (the YADE restore is exact, docs/dem_backend.md).
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir). scripts/run stops every process it
# starts by PID.
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir column_yade
tiny_column_scene "$work/scene.yaml"
run_job "$work/full.log" "$work/scene.yaml" --out "$work/full" --dem-ranks 2
# Resume a copy from the newest checkpoint at or before step 80 (drop the later ones).
resume_from "$work/full" "$work/resumed" 80 "$work/resumed.log"
/usr/bin/python3 - "$work/full" "$work/resumed" <<'PY'
import csv, json, math, os, sys
import h5py, numpy as np
full, res = sys.argv[1], sys.argv[2]
s = json.load(open(full + "/summary.json"))
assert s["status"] == "complete", s
assert abs(s["mass_grid_kg"] - s["mass_initial_kg"]) <= 1e-12 * s["mass_initial_kg"], "grid mass after the last P2G differs from the point mass"
assert s["removed_points"] == 0, "a point left the grid"
assert s["n_rve_particles"] == 8 * 100, s["n_rve_particles"]  # 8 RVEs of 100 spheres
# Per-phase timing: the DEM time of the slowest rank is inside the exchange, >= the mean.
assert 0 < s["time_dem_mean_s"] <= s["time_dem_max_s"] <= s["time_exchange_s"], s
assert s["dem_imbalance"] >= 1.0, s["dem_imbalance"]
assert sum(1 for _ in open(full + "/timings.csv")) >= s["steps"] + 1
t_r, ep0 = s["stage1_time_s"], s["Ep0_release_J"]
assert 0.02 <= t_r <= 0.1 + 0.01, t_r
worst = 0.0
for r in csv.DictReader(open(full + "/energies.csv")):
    vals = [float(v) for v in r.values()]
    assert all(math.isfinite(v) for v in vals), r
    if float(r["time"]) >= t_r:
        worst = min(worst, ep0 - float(r["E_p"]) - float(r["E_k"]))
assert worst >= -0.01 * ep0, f"E_d dips to {worst / ep0:.3g} E_p0"
assert s["runout_m"] > 0.22 + 0.02 and s["final_height_m"] < 0.44 - 0.02, \
    f"runout {s['runout_m']}, height {s['final_height_m']}: the column did not collapse"
assert s["Ed_over_Ep0_final"] > 0.0, s["Ed_over_Ep0_final"]
for f in ["report.md", "energies.png", "velocity.png", "rotation.png"]:
    assert os.path.exists(os.path.join(full, f)), f + " missing"
a, b = h5py.File(full + "/final_state.h5"), h5py.File(res + "/final_state.h5")
assert a.attrs["step"] == b.attrs["step"], (a.attrs["step"], b.attrs["step"])
x = a["x"][:]
assert np.all(np.isfinite(x)) and x[:, 0].max() <= 1.1 and x[:, 2].min() >= 0.0
for k in ["x", "v", "stress"]:
    d = np.abs(a[k][:] - b[k][:]).max()
    assert d == 0.0, f"resumed {k} differs by {d}"
r = json.load(open(res + "/summary.json"))
print(f"column_yade: complete, {s['steps']} steps, stage 1 {t_r:.3f} s, runout {s['runout_m']:.3f} m, "
      f"E_d/E_p0 {s['Ed_over_Ep0_final']:.3f}; resumed run identical ({r['steps']} steps)")
PY

#!/usr/bin/env bash
# Lazy RVE evaluation (issue 6, item 2) on the tiny multiscale column (8 YADE RVEs, 2 DEM
# ranks) through scripts/run (which stops every process by PID):
#  - with coupling.lazy_tolerance 2e-4 RVEs are skipped (counted in summary.json, every
#    request either ran or was skipped), mass is conserved, and runout, final height and
#    E_d/E_p0 stay within the spread a mere checkpoint reload causes in this chaotic
#    collapse (see load_balance.sh) of the run without lazy evaluation;
#  - a run resumed from a checkpoint (pending accumulated dF saved in mpm.h5) ends bitwise
#    equal to the uninterrupted lazy run.
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir lazy
tiny_column_scene "$work/plain.yaml"
sed -e 's/^  backend: yade/  backend: yade\n  lazy_tolerance: 2.0e-4/' "$work/plain.yaml" >"$work/lazy.yaml"
for name in plain lazy; do
  run_job "$work/$name.log" "$work/$name.yaml" --out "$work/$name" --dem-ranks 2
done
resume_from "$work/lazy" "$work/resumed" 80 "$work/resumed.log"
/usr/bin/python3 - "$work" <<'PY'
import json, sys
import h5py, numpy as np
w = sys.argv[1]
plain, lazy, res = (json.load(open(f"{w}/{n}/summary.json")) for n in ("plain", "lazy", "resumed"))
for s in (plain, lazy, res):
    assert s["status"] == "complete", s["status"]
    assert abs(s["mass_grid_kg"] - s["mass_initial_kg"]) <= 1e-12 * s["mass_initial_kg"] and s["removed_points"] == 0
n = lazy["n_material_points"]
assert plain["rve_skipped"] == 0 and plain["rve_evaluations"] == n * plain["steps"], plain
assert lazy["rve_evaluations"] + lazy["rve_skipped"] == n * lazy["steps"], lazy
assert lazy["rve_skipped"] > 0, "nothing skipped"
for key, tol in (("runout_m", 0.03), ("final_height_m", 0.03), ("Ed_over_Ep0_final", 0.1)):
    rel = abs(lazy[key] - plain[key]) / abs(plain[key])
    assert rel <= tol, f"{key}: {lazy[key]} vs {plain[key]} ({rel:.3g} > {tol})"
a, b = h5py.File(f"{w}/lazy/final_state.h5"), h5py.File(f"{w}/resumed/final_state.h5")
for k in ("x", "v", "stress", "F"):
    assert np.array_equal(np.asarray(a[k]), np.asarray(b[k])), f"resumed {k} differs"
assert res["rve_skipped"] == lazy["rve_skipped"], (res["rve_skipped"], lazy["rve_skipped"])
frac = lazy["rve_skipped"] / (n * lazy["steps"])
print(f"lazy: {lazy['rve_skipped']} of {n * lazy['steps']} RVE updates skipped ({100 * frac:.0f} %), "
      f"DEM time {lazy['time_dem_mean_s']:.2f} vs {plain['time_dem_mean_s']:.2f} s; runout "
      f"{lazy['runout_m']:.4f} vs {plain['runout_m']:.4f} m, H_f {lazy['final_height_m']:.4f} vs "
      f"{plain['final_height_m']:.4f} m, Ed/Ep0 {lazy['Ed_over_Ep0_final']:.4f} vs "
      f"{plain['Ed_over_Ep0_final']:.4f}; resumed run bitwise equal")
PY

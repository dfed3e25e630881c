#!/usr/bin/env bash
# scripts/grid_convergence_study on the two coarsest grids (0.11 and 0.055 m, 2 points per
# cell, both bases; ~15 s): every run is complete with the cell size and base asked for, mass
# is conserved, the CSV matches the runs' summaries, and the Coulomb friction base
# (mu_b = 0.52) lets the deposit run out farther than the no-slip base on each grid (with the
# scene's clamped B-splines the no-slip base holds only the wall's own function, so the margin
# is small on the finer grid: 0.23 and 0.04 m measured), and the transfers' loss at the walls
# is a positive part of theirs. The Richardson analysis is checked on
# f(h) = 1 + h^2 and 1 + h (orders 2 and 1, extrapolated value 1), on an oscillating and on a
# diverging sequence. A base that is not a wall condition exits non-zero and runs nothing.
# scripts/runout_vs_dissipation's line fit is checked on made-up studies.
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir grid_convergence_study
fail() { echo "FAIL: $*" >&2; exit 1; }
export MPM_APP=$bin/mpm_app/mpm_app

PYTHONPATH="$src/scripts/lib" /usr/bin/python3 - <<'PY' || fail "richardson()"
import math
from column_study import richardson
for order in (1, 2):
    r = richardson([1 + 0.4 ** order, 1 + 0.2 ** order, 1 + 0.1 ** order])
    assert r["kind"] == "converging" and abs(r["p"] - order) < 1e-9, r
    assert abs(r["extrapolated"] - 1) < 1e-12, r
    # GCI = 1.25 |e21 / f1| / (2^p - 1)
    assert abs(r["gci"] - 1.25 * (0.2 ** order - 0.1 ** order) / (1 + 0.1 ** order) / (2 ** order - 1)) < 1e-12
assert richardson([1.0, 1.2, 1.1])["kind"] == "oscillatory"
assert richardson([1.0, 1.1, 1.3])["kind"] == "slow"
from column_study import linear_fit
a, b, r2 = linear_fit([0.1, 0.2, 0.4], [4 - 8 * 0.1, 4 - 8 * 0.2, 4 - 8 * 0.4])
assert abs(a - 4) < 1e-12 and abs(b + 8) < 1e-12 and abs(r2 - 1) < 1e-12, (a, b, r2)
a, b, r2 = linear_fit([0, 1, 2, 3], [0, 1, 0, 1])  # least squares: 0.2 + 0.2 x, R^2 0.2
assert abs(a - 0.2) < 1e-12 and abs(b - 0.2) < 1e-12 and abs(r2 - 0.2) < 1e-12, (a, b, r2)
PY
# scripts/runout_vs_dissipation on two made-up studies whose runs lie on runout = 4 - 8 N and
# 99 % mass = 3 - 5 N (N = 1 - W_int_share) on the fixed base; the second study repeats one run
# of the first (counted once), and the friction base has too few runs for a fit.
PYTHONPATH="$src/scripts/lib" /usr/bin/python3 - "$work/fit" <<'PY' || fail "made-up studies"
import csv, json, os, sys
root = sys.argv[1]
for study, rows in (("a", [("fixed", 0.1, 0.05), ("fixed", 0.05, 0.1), ("friction", 0.1, 0.2)]),
                    ("b", [("fixed", 0.05, 0.1), ("fixed", 0.025, 0.3)])):
    d = os.path.join(root, study)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "study.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["base", "ppc", "h"])
        for base, h, N in rows:
            w.writerow([base, 2, h])
            run = os.path.join(d, "runs", f"{base}_ppc2_h{h:g}")
            os.makedirs(run, exist_ok=True)
            json.dump({"energy_budget": {"W_int_share": 1 - N}, "runout_m": 4 - 8 * N,
                       "runout_mass99_m": 3 - 5 * N}, open(os.path.join(run, "summary.json"), "w"))
PY
"$src/scripts/runout_vs_dissipation" "$work/fit/a" "$work/fit/b" >"$work/fit.md" 2>&1 ||
  { cat "$work/fit.md" >&2; fail "runout_vs_dissipation"; }
grep -q "^| fixed | 3 | 0.050-0.300 | runout | 4.00 | -0.080 | 1.00 |$" "$work/fit.md" &&
  grep -q "^| fixed | 3 | 0.050-0.300 | 99 % of the mass within | 3.00 | -0.050 | 1.00 |$" "$work/fit.md" &&
  grep -q "^| friction | 1 | - | no fit: fewer than 3 runs | - | - | - |$" "$work/fit.md" ||
  { cat "$work/fit.md" >&2; fail "runout_vs_dissipation's table"; }
if "$src/scripts/runout_vs_dissipation" "$work/nothing" >"$work/fit_bad.log" 2>&1; then
  fail "a folder without study.csv was accepted"
fi
grep -q "no study.csv in '$work/nothing'" "$work/fit_bad.log" || { cat "$work/fit_bad.log" >&2; fail "no message"; }
"$src/scripts/grid_convergence_study" --out "$work/s" --cells "0.11 0.055" --ppc 2 \
  >"$work/s.log" 2>&1 || { tail -n 30 "$work/s.log" >&2; fail "study failed"; }
/usr/bin/python3 - "$work/s" <<'PY' || exit 1
import csv, json, sys
import yaml
w = sys.argv[1]
rows = list(csv.DictReader(open(w + "/study.csv")))
assert [(r["base"], float(r["h"])) for r in rows] == [
    ("fixed", 0.11), ("fixed", 0.055), ("friction", 0.11), ("friction", 0.055)], rows
front = {}
for r in rows:
    name = f"{r['base']}_ppc2_h{float(r['h']):g}"
    cfg = yaml.safe_load(open(f"{w}/runs/{name}.yaml"))
    assert cfg["grid"]["cell_size"] == float(r["h"]) and cfg["walls"]["z_min"] == r["base"]
    assert cfg["walls"].get("friction") == (0.52 if r["base"] == "friction" else None)
    s = json.load(open(f"{w}/runs/{name}/summary.json"))
    assert s["status"] == "complete", (name, s["status"])
    assert s["mass_final_kg"] == s["mass_initial_kg"] and s["removed_points"] == 0, name
    assert float(r["runout_front_m"]) == s["runout_front_m"] <= s["runout_m"], name
    # The transfers' loss at the walls is a positive part of the transfers' (energies.csv).
    walls = float(r["Etransfer_walls_over_released"])
    transfers = float(r["Etransfer_over_released"])
    assert 0 < walls < transfers, (name, walls, transfers)
    front[(r["base"], float(r["h"]))] = s["runout_front_m"]
for h in (0.11, 0.055):
    assert front[("friction", h)] > front[("fixed", h)], (h, front)
print("fronts:", front)
PY
if "$src/scripts/grid_convergence_study" --out "$work/bad" --bases fixed,rough >"$work/bad.log" 2>&1; then
  fail "an unknown base was accepted"
fi
grep -q "unknown base 'rough'" "$work/bad.log" || { cat "$work/bad.log" >&2; fail "no message"; }
[[ ! -e $work/bad/runs/fixed_ppc2_h0.11 ]] || fail "ran something with a bad base"
echo "grid_convergence_study smoke: ok"

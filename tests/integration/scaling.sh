#!/usr/bin/env bash
# scripts/scaling_study, scripts/cost_model and the Amdahl fit (issue 5, items 2-3).
#  - the fit recovers a known serial fraction exactly (scripts/lib/amdahl.py self-test);
#  - a study of the elastic-stub column on 1 and 2 DEM ranks (20 steps, --set override)
#    writes its table and both figures, every phase time is positive and the step time is
#    the sum of its phases; with 2 repetitions the per-repetition DEM efficiencies (each
#    2-rank run against the 1-rank run beside it) and their median are reported; with
#    --rve-costs every run logs each RVE's cost per step and the 2-rank runs' partition
#    efficiency is reported (partition_efficiency.py self-test: known answers);
#  - scripts/cost_model --from the study's runs takes every cost from them: its inputs (MPM
#    time per point-step, DEM time per RVE-step, imbalance, exchange time per RVE-step) equal
#    those computed here from the runs' timings.csv and summary.json, and its step time on
#    1 and 128 nodes is the model's formula on them; a run without a DEM side is refused.
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir scaling
/usr/bin/python3 "$src/scripts/lib/amdahl.py" || { echo "FAIL: amdahl self-test" >&2; exit 1; }
/usr/bin/python3 "$src/scripts/lib/partition_efficiency.py" || { echo "FAIL: partition_efficiency self-test" >&2; exit 1; }
if ! "$src/scripts/scaling_study" "$src/configs/elastic_column_remote.yaml" --ranks 1,2 \
  --steps 20 --warmup 2 --repeat 2 --set solver.end_time=0.1 --rve-costs --out "$work/study" >"$work/study.log" 2>&1; then
  echo "FAIL: scaling_study failed" >&2; tail -n 30 "$work/study.log" >&2; exit 1
fi
"$src/scripts/scaling_study" "$src/configs/elastic_column_remote.yaml" --ranks 1,x >/dev/null 2>&1
[[ $? == 2 ]] || { echo "FAIL: a bad --ranks must exit 2" >&2; exit 1; }
runs=$(printf '%s,' "$work"/study/runs/ranks_*_[0-9])
"$src/scripts/cost_model" --from "${runs%,}" --threads 4 --out "$work/cost" >"$work/cost.log" 2>&1 ||
  { echo "FAIL: cost_model" >&2; cat "$work/cost.log" >&2; exit 1; }
# A local run has no DEM side to measure: refused (exit 2), naming the run.
local_run=$work/local
"$src/scripts/run" "$src/configs/column_collapse_mc.yaml" --out "$local_run" --max-steps 5 >"$work/local.log" 2>&1 ||
  { echo "FAIL: local run" >&2; tail "$work/local.log" >&2; exit 1; }
"$src/scripts/cost_model" --from "$local_run" --out "$work/cost_local" >"$work/cost_local.log" 2>&1
[[ $? == 2 ]] && grep -q "no DEM side measured in $local_run" "$work/cost_local.log" ||
  { echo "FAIL: cost_model on a local run must exit 2 naming it" >&2; cat "$work/cost_local.log" >&2; exit 1; }
/usr/bin/python3 - "$work" <<'PY'
import csv, os, re, sys
w = sys.argv[1]
rows = list(csv.DictReader(open(f"{w}/study/scaling.csv")))
assert [int(r["ranks"]) for r in rows] == [1, 2], rows
for r in rows:
    for k in ("mpm", "dem", "dem_mean", "comm", "step"):
        assert float(r[k]) > 0, (k, r)
    assert float(r["dem"]) >= float(r["dem_mean"]) * (1 - 1e-12)
assert abs(float(rows[0]["speedup"]) - 1.0) < 1e-12
for f in ("scaling.md", "fig3_phases.png", "fig4_speedup.png", "scene.yaml", "raw.csv"):
    assert os.path.getsize(f"{w}/study/{f}") > 0, f
raw = list(csv.DictReader(open(f"{w}/study/raw.csv")))
assert sorted((int(r["ranks"]), int(r["repetition"])) for r in raw) == [(1, 0), (1, 1), (2, 0), (2, 1)]
# The per-repetition efficiencies: each 2-rank run against the 1-rank run of its repetition.
dem = {(int(r["ranks"]), int(r["repetition"])): float(r["dem"]) for r in raw}
want = [100 * dem[1, k] / (2 * dem[2, k]) for k in (0, 1)]
line = re.search(r"- 2 ranks: ([0-9.]+), ([0-9.]+) %; median ([0-9.]+) %",
                 open(f"{w}/study/scaling.md").read())
assert line, "no per-repetition DEM efficiency in scaling.md"
got = [float(line.group(1)), float(line.group(2))]
assert all(abs(g - e) < 0.051 for g, e in zip(got, want)), (got, want)
assert abs(float(line.group(3)) - sum(want) / 2) < 0.051, (line.group(3), want)
# --rve-costs: each run logged 20 rows of costs; the 2-rank runs' rank map is the
# interleaved split, so the partition efficiency (the 1-rank costs summed over the 2-rank
# ranks) is recorded per repetition, and at most 1.
for n in (1, 2):
    costs = open(f"{w}/study/runs/ranks_{n}_0/rve_costs.csv").read().splitlines()
    assert len(costs) == 21, len(costs)
ranks = open(f"{w}/study/runs/ranks_2_0/rve_ranks.csv").read().splitlines()
assert len(ranks) == 2 and sorted(set(ranks[1].split(",")[1:])) == ["0", "1"], ranks
pe = {int(r["repetition"]): r["partition_efficiency"] for r in raw if r["ranks"] == "2"}
assert all(0.5 < float(pe[k]) <= 1.0 for k in (0, 1)), pe
assert re.search(r"- 2 ranks: partition [0-9.]+, [0-9.]+ %", open(f"{w}/study/scaling.md").read())
for n in (1, 2):
    s = open(f"{w}/study/runs/ranks_{n}_0/summary.json").read()
    assert '"status": "truncated"' in s and '"steps": 20' in s, f"ranks {n}: not cut at 20 steps"
# The cost model's inputs, computed here from the runs (their first step left out).
import glob, json, math
t_mpm = n_ps = dem = rve_steps = dmax = dmean = comm = 0.0
for run in sorted(glob.glob(f"{w}/study/runs/ranks_*_[0-9]")):
    s = json.load(open(run + "/summary.json"))
    rows = list(csv.DictReader(open(run + "/timings.csv")))[1:]
    col = lambda k: sum(float(r[k]) for r in rows)
    n, pts, ranks = len(rows), s["n_material_points"], s["dem_ranks"]
    assert ranks == int(run.split("_")[-2]), (run, ranks)
    t_mpm += col("p2g") + col("grid") + col("g2p_dF") + col("stress") - col("exchange")
    n_ps += n * pts
    dem += col("dem_mean") * ranks
    rve_steps += n * pts
    dmax, dmean, comm = dmax + col("dem_max"), dmean + col("dem_mean"), comm + col("comm")
cm = json.load(open(f"{w}/cost/cost_model.json"))
got = cm["inputs"]
want = {"t_point_s": t_mpm / n_ps, "s_omp": 1.0, "c_rve_s": dem / rve_steps,
        "imbalance": dmax / dmean, "c_comm_s": comm / rve_steps}
for k, v in want.items():
    assert abs(got[k] - v) <= 1e-9 * abs(v), (k, got[k], v)
assert all(x > 0 for x in want.values()), want
o = cm["options"]
for r in cm["rows"]:
    if r["nodes"] in (1, 128):
        p = r["nodes"] * o["cores"]
        t = (v := want)["c_rve_s"] * math.ceil(o["n_rve"] / p) * v["imbalance"] \
            + o["n_rve"] * v["t_point_s"] + o["n_rve"] * v["c_comm_s"] + 2 * p * o["alpha_us"] * 1e-6
        assert abs(r["t_step"] - t) <= 1e-9 * t, (r["nodes"], r["t_step"], t)
r128 = next(r for r in cm["rows"] if r["nodes"] == 128)
print(f"scaling: study ok; cost model from the runs: {1e9 * want['t_point_s']:.0f} ns per point-step, "
      f"{1e6 * want['c_rve_s']:.1f} us per RVE-step, imbalance {want['imbalance']:.3f}; "
      f"{r128['speedup']:.1f}x at 128 nodes")
PY

#!/usr/bin/env bash
# Resume on another DEM rank count (issue 16, item 2), through scripts/run:
#   a run written with 2 DEM ranks (checkpoints every K steps) is copied, cut back to an
#   early checkpoint and continued with scripts/run --resume COPY --dem-ranks M, M = 1 and
#   3; its end state (final_state.h5: x, v, stress) must equal the uninterrupted run's bit
#   for bit: every RVE's state is found by its id in the checkpoint, whichever rank wrote
#   it, and the partition does not change any RVE's arithmetic.
#   elastic: the elastic column against dem_app --backend elastic (to the end), with
#            time-triggered checkpoints (every 0.1 s of wall time or more, spaced to cost at
#            most 2 % of the run): resumed from
#            the oldest one kept, whichever step the clock picked;
#   yade:    the tiny multiscale column (8 YADE RVEs), 60 steps (--max-steps).
# Usage: resume_ranks.sh elastic|yade. Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
# scripts/run stops every process it starts by PID.
set -uo pipefail
case_name=${1:?usage: resume_ranks.sh elastic|yade}
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir "resume_ranks_$case_name"
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
ok() { echo "ok: $*"; }

if [[ $case_name == elastic ]]; then
  # 0.4 s of simulated time: ~5 s of wall time on an idle 2-core machine. Checkpoints are
  # spaced to cost at most 2 % of the run (a 27 ms checkpoint: one per 1.35 s or more), so a
  # run of ~1.4 s (end_time 0.1, seen in a CI run) writes only one.
  sed -e 's/^  end_time: .*/  end_time: 0.4/' \
    -e 's/^  energy_interval: .*/&\n  checkpoint_interval_s: 0.1\n  checkpoints_kept: 10/' \
    "$src/configs/elastic_column_remote.yaml" >"$work/scene.yaml"
  limit=() cut=""
else
  tiny_column_scene "$work/scene.yaml"
  sed -i -e 's/^  checkpoint_interval_steps: .*/  checkpoint_interval_steps: 20\n  checkpoint_interval_s: 0/' "$work/scene.yaml"
  limit=(--max-steps 60) cut=20
fi
grep -q '^  checkpoint_interval_s: 0' "$work/scene.yaml" || { echo "FAIL: scene edit" >&2; exit 1; }
run_job "$work/full.log" "$work/scene.yaml" --out "$work/full" --dem-ranks 2 "${limit[@]}"
if [[ -z $cut ]]; then  # time-triggered: the oldest complete checkpoint kept
  ckpts=("$work"/full/checkpoints/step_*/COMPLETE)
  ((${#ckpts[@]} >= 2)) && [[ -f ${ckpts[0]} ]] || { echo "FAIL: fewer than 2 time-triggered checkpoints" >&2; exit 1; }
  first=${ckpts[0]%/COMPLETE}
  cut=$((10#${first##*step_}))
  ok "${#ckpts[@]} time-triggered checkpoints kept (steps ${ckpts[*]//[^0-9 ]/}); resuming from step $cut"
  [[ -n $(ls "$first/dem") ]] || fail "the DEM side saved nothing in $first/dem"
fi
for m in 1 3; do
  copy=$work/ranks_$m
  resume_from "$work/full" "$copy" "$cut" "$work/ranks_$m.log" "$m" "${limit[@]}"
  grep -q "on $m rank(s)" "$work/ranks_$m.log" && ok "resumed from step $cut on $m DEM rank(s)" ||
    fail "the resume did not run on $m rank(s)"
  /usr/bin/python3 - "$work/full" "$copy" "$case_name" <<'PY' || fail "resumed on $m ranks: end state differs"
import json, sys
import h5py, numpy as np
full, res, case = sys.argv[1:4]
s, r = json.load(open(full + "/summary.json")), json.load(open(res + "/summary.json"))
assert r["status"] == s["status"] and r.get("error", "") == "", (s["status"], r)
a, b = h5py.File(full + "/final_state.h5"), h5py.File(res + "/final_state.h5")
assert a.attrs["step"] == b.attrs["step"] == s["steps"], (a.attrs["step"], b.attrs["step"])
szz = a["stress"][:].reshape(-1, 9)[:, 8]
assert szz.min() < (-1.0e4 if case == "elastic" else 0.0), szz.min()  # loaded by its weight
for k in ["x", "v", "stress"]:
    d = np.abs(a[k][:] - b[k][:]).max()
    assert d == 0.0, f"{k} differs by {d}"
print(f"ok: end state at step {s['steps']} identical to the 2-rank uninterrupted run (x, v, stress)")
PY
done
left=$(pgrep -f -- "$work/" || true)
[[ -z $left ]] || { fail "processes left: $left"; kill -KILL $left 2>/dev/null; }
if ((failures)); then echo "resume_ranks_$case_name: $failures failure(s)" >&2; exit 1; fi
echo "resume_ranks_$case_name: passed"

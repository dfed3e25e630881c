# Shared set-up of the integration scripts that run whole jobs through scripts/run (which
# starts and stops every process by PID). Source it after setting `src`:
#   src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
#   source "$src/tests/integration/common.sh"
#   test_workdir NAME [keep]  # bin, work=$bin/test-runs/NAME (emptied unless `keep`)
# Env: MPMDEM_BIN (build dir, required), MPMDEM_SRC (source dir).

test_workdir() {
  bin=${MPMDEM_BIN:?set MPMDEM_BIN to the build directory}
  work=$bin/test-runs/$1
  [[ ${2:-} == keep ]] || rm -rf "$work"
  mkdir -p "$work"
  export MPMDEM_SKIP_SETUP=1 MPMDEM_BUILD_DIR=$bin
}

# tiny_column_scene DEST: the tiny multiscale column (8 YADE RVEs) with the test packings.
tiny_column_scene() {
  sed -e "s|PACKING_DIR|$bin/test-packings/column_collapse|" \
    -e "s|PACKING_SPEC|$src/configs/packings/column_collapse.yaml|" \
    "$src/tests/integration/column_yade_tiny.yaml" >"$1"
}

# run_job LOG ARGS...: scripts/run ARGS with output in LOG; on failure print its tail, exit 1.
run_job() {
  local log=$1
  shift
  if ! "$src/scripts/run" "$@" >"$log" 2>&1; then
    echo "FAIL: scripts/run $* failed" >&2
    tail -n 40 "$log" >&2
    exit 1
  fi
}

# resume_from RUN COPY STEP LOG [RANKS [ARGS...]]: copy RUN to COPY, keep its checkpoints up to
# STEP, and resume the copy (scripts/run --resume on RANKS DEM ranks, default 2, with ARGS);
# on failure exit 1.
resume_from() {
  local run=$1 copy=$2 step=$3 log=$4 ranks=${5:-2} d n
  shift $(($# < 5 ? $# : 5))
  rm -rf "$copy"
  cp -r "$run" "$copy"
  for d in "$copy"/checkpoints/step_*; do
    n=$((10#${d##*step_}))
    ((n > step)) && rm -rf "$d"
  done
  rm -f "$copy/summary.json" "$copy/final_state.h5"
  local from
  from=$(newest_checkpoint_step "$copy")
  run_job "$log" --resume "$copy" --dem-ranks "$ranks" "$@"
  check_resumed "$copy" "$from"
}

# newest_checkpoint_step RUN: the step of RUN's newest complete checkpoint (the one
# scripts/run --resume continues from), -1 if none.
newest_checkpoint_step() {
  local d n newest=-1
  for d in "$1"/checkpoints/step_*; do
    [[ -f $d/COMPLETE ]] || continue
    n=$((10#${d##*step_}))
    ((n > newest)) && newest=$n
  done
  echo "$newest"
}

# check_resumed RUN STEP: RUN's summary.json says it resumed from STEP and ran its remaining
# steps itself (a fresh re-run of deterministic code would end in the same state, so an equal
# end state alone does not show a resume); on failure exit 1.
check_resumed() {
  /usr/bin/python3 - "$1/summary.json" "$2" <<'PY' || exit 1
import json, sys
s, step = json.load(open(sys.argv[1])), int(sys.argv[2])
got = s.get("resumed_from_step")
if got != step or s.get("steps_after_resume") != s["steps"] - step or s["steps"] <= step:
    sys.exit("FAIL: %s: resumed_from_step %s (expected %d), steps_after_resume %s, steps %s"
             % (sys.argv[1], got, step, s.get("steps_after_resume"), s["steps"]))
print("resumed from step %d, %d steps after it" % (step, s["steps_after_resume"]))
PY
}

# Processes a test starts in the background, each stopped by its PID when the script exits,
# also on failure or interruption (the script sets `trap bg_stop EXIT`):
#   bg_start LOG CMD ARGS...  run CMD in the background, output in LOG; its index in bg_pids is
#                             the number of earlier bg_start calls
#   bg_wait K                 wait for the K-th (from 0); returns its exit status
#   bg_stop                   stop those not yet waited for
# A PID that was waited for is forgotten, so that bg_stop never signals a reused PID.
bg_pids=()
bg_start() {
  local log=$1
  shift
  "$@" >"$log" 2>&1 &
  bg_pids+=($!)
}
bg_wait() {
  local k=$1 rc=0
  wait "${bg_pids[$k]}" || rc=$?
  bg_pids[$k]=""
  return $rc
}
bg_stop() {
  local p
  for p in "${bg_pids[@]}"; do
    [[ -n $p ]] && kill -TERM "$p" 2>/dev/null && wait "$p" 2>/dev/null
  done
  bg_pids=()
}

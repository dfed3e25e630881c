#!/usr/bin/env bash
# The GPU backend's device check (issue 39): validate the device kernel against the host batch
# path on the same RVEs (1e-10 relative on stresses; the two are expected to agree bit for
# bit), then sphere-steps/s of the batch in FP64 at 1,560 x 100, 10,000 x 100, 10,000 x 800
# and 70,389 x 800 (or the largest that fits), beside one core of the native backend on the
# same RVEs. The GPU host has no Debian packages and cannot build the project, so:
#
#   tests/device/check.sh prepare [DIR]   here, after scripts/build (MPMDEM_WITH_CUDA on):
#       copies build/dem_app/batch_bench and the shared libraries it needs but glibc's into
#       DIR (default .device-check, ignored by git), and the RVEs into DIR: the default
#       column's four 100-sphere packings (packings/column_collapse, built by scripts/run)
#       and four 800-sphere Table 1 clouds consolidated to 10 kPa. ~1 minute on 2 cores.
#   tests/device/check.sh run [DIR]       on the GPU host, from the repository root, DIR
#       carried along (device tool: carry [".device-check"]): ~3-5 minutes; prints the table
#       and writes it to DIR/results.txt (and $OUT/results.txt where OUT is set).
#   tests/device/check.sh host [DIR]      here: the run's steps on the host batch path, small
#       (checks the script and the prepared files without a GPU).
# Exit status: 0 when the validation passed, 1 when it failed, 2 on a usage or set-up error.
set -uo pipefail
mode=${1:-}
dir=${2:-.device-check}
root=$(cd "$(dirname "$0")/../.." && pwd)

prepare() {
  local bench=$root/build/dem_app/batch_bench
  [[ -x $bench ]] || { echo "check.sh: $bench missing: scripts/build first" >&2; exit 2; }
  mkdir -p "$dir/lib"
  cp "$bench" "$dir/"
  ldd "$bench" | awk '/=>/ {print $3}' | grep -v -E '/(libc|libm|libpthread|libdl|librt)\.so' |
    while read -r lib; do cp -L "$lib" "$dir/lib/"; done
  local p=$root/packings/column_collapse
  [[ -f $p/col100_s1.native.txt ]] || {
    echo "check.sh: $p/col100_s*.native.txt missing: scripts/run configs/column_collapse_3d.yaml builds them" >&2
    exit 2
  }
  "$dir/batch_bench" --packings "$p/col100_s1,$p/col100_s2,$p/col100_s3,$p/col100_s4" \
    --rves 0 --save "$dir/rves100.bin" || exit 2
  OMP_NUM_THREADS=4 "$dir/batch_bench" --spheres 800 --distinct 4 --rves 0 \
    --save "$dir/rves800.bin" || exit 2
  (cd "$root" && git rev-parse HEAD) >"$dir/COMMIT" 2>/dev/null
  du -sh "$dir"
}

run() {  # $1: gpu or host; the sizes scale down on the host
  local device=$1 bench=$dir/batch_bench out=$dir/results.txt status=0
  [[ -x $bench && -f $dir/rves100.bin && -f $dir/rves800.bin ]] || {
    echo "check.sh: $dir is not prepared (tests/device/check.sh prepare)" >&2
    exit 2
  }
  export LD_LIBRARY_PATH=$dir/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  local big=70389 mid=10000 small=1560 vr=512 vr8=128 nat=64 nat8=16 t=120
  if [[ $device == host ]]; then big=16 mid=8 small=8 vr=0 vr8=0 nat=4 nat8=2 t=60; fi
  : >"$out"
  say() { echo "$*" | tee -a "$out"; }
  say "# GPU backend device check, commit $(cat "$dir/COMMIT" 2>/dev/null || echo '?'), $(date -u +%F)"
  if [[ $device == gpu ]]; then
    say "device: $(nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader 2>/dev/null | head -1)"
    # 1. the device against the host path (the same batch code), mixed ns in one launch
    timeout 150 "$bench" --load "$dir/rves100.bin" --validate $vr --steps 20 --ns 100 --mixed |
      grep -E '^validate' | tee -a "$out"
    [[ ${PIPESTATUS[0]} == 0 ]] || status=1
    timeout 150 "$bench" --load "$dir/rves800.bin" --validate $vr8 --steps 2 --ns 100 --mixed |
      grep -E '^validate' | tee -a "$out"
    [[ ${PIPESTATUS[0]} == 0 ]] || status=1
  fi
  # 2. sphere-steps/s, FP64; native one core on the same RVEs beside it
  b() { timeout "$t" "$bench" --device "$device" "$@" 2>&1 | grep -E '^(batch|native|batch_bench)' | tee -a "$out"; }
  b --load "$dir/rves100.bin" --rves $small --ns 100 --steps 5 --native $nat
  b --load "$dir/rves100.bin" --rves $mid --ns 100 --steps 3
  b --load "$dir/rves800.bin" --rves $mid --ns 800 --steps 1 --native $nat8
  local n=$big
  while true; do  # the largest that fits (halved from 70,389 down to 1,000)
    local line
    line=$(b --load "$dir/rves800.bin" --rves $n --ns 800 --steps 1)
    echo "$line"
    [[ $line == *"batch on"* ]] && break
    say "($n x 800 did not fit or did not finish in $t s)"
    [[ $device == host ]] && break
    n=$((n / 2))
    ((n >= 1000)) || break
  done
  say "validation: $([[ $status == 0 ]] && echo passed || echo FAILED)"
  [[ -n ${OUT:-} && -d ${OUT:-/nonexistent} ]] && cp "$out" "$OUT/results.txt"
  return $status
}

case $mode in
  prepare) prepare ;;
  run) run gpu ;;
  host) run host ;;
  *) sed -n '2,22p' "$0"; exit 2 ;;
esac

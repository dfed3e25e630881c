#!/usr/bin/env bash
# Results bit for bit unchanged: four scenes run with fixed arguments, and the physics of each
# run (tests/golden/run_hash.py: final_state.h5 and summary.json's figures) hashed and compared
# with the hash recorded in tests/golden/hashes.txt before a change that must not change them
# (a redesign, a new launcher):
#   default  the default 3D column (native RVEs), its first 3 steps, 2 DEM ranks
#   elastic  configs/elastic_column_remote.yaml (elastic stub over MPI), 200 steps
#   local    configs/column_collapse_mc.yaml (local Drucker-Prager) to its end
#   apic     configs/column_collapse_mc_apic.yaml (APIC, USL), 300 steps
#   xpic     tests/golden/column_xpic_musl.yaml (XPIC(2), MUSL), 300 steps
#   yade     the tiny YADE column (tests/integration/column_yade_tiny.yaml), 10 steps
# Usage: golden.sh [--record] [SCENE...]   (--record rewrites hashes.txt: say why in the commit)
# CTest runs one scene per test (tests/golden/golden.cmake; yade: skipped without the backend).
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=../integration/common.sh
source "$src/tests/integration/common.sh"
test_workdir golden
record=0
[[ ${1:-} == --record ]] && { record=1; shift; }
scenes=("$@")
((${#scenes[@]})) || scenes=(default elastic local apic xpic yade)
hashes=$src/tests/golden/hashes.txt
failures=0
for s in "${scenes[@]}"; do
  args=(--threads 1 --out "$work/$s")
  case $s in
    default) args+=("$src/configs/column_collapse_3d.yaml" --max-steps 3 --dem-ranks 2) ;;
    elastic) args+=("$src/configs/elastic_column_remote.yaml" --max-steps 200 --dem-ranks 1) ;;
    local) args+=("$src/configs/column_collapse_mc.yaml") ;;
    apic) args+=("$src/configs/column_collapse_mc_apic.yaml" --max-steps 300) ;;
    xpic) args+=("$src/tests/golden/column_xpic_musl.yaml" --max-steps 300) ;;
    yade)
      tiny_column_scene "$work/yade_scene.yaml"
      args+=("$work/yade_scene.yaml" --max-steps 10 --dem-ranks 2) ;;
    *) echo "golden: unknown scene '$s'" >&2; exit 2 ;;
  esac
  run_job "$work/$s.log" "${args[@]}"
  got=$(/usr/bin/python3 "$src/tests/golden/run_hash.py" "$work/$s") || exit 1
  got=${got%%$'\n'*}
  if ((record)); then
    sed -i "/^$s /d" "$hashes" 2>/dev/null
    echo "$s $got" >>"$hashes"
    echo "golden: $s recorded $got"
    continue
  fi
  want=$(sed -n "s/^$s //p" "$hashes")
  if [[ $got == "$want" ]]; then
    echo "ok: $s $got"
  else
    echo "FAIL: $s: hash $got, recorded ${want:-none} (tests/golden/hashes.txt)" >&2
    failures=$((failures + 1))
  fi
done
((record)) && sort -o "$hashes" "$hashes"
if ((failures)); then echo "golden: $failures scene(s) changed" >&2; exit 1; fi
echo "golden: passed"

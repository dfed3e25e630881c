#!/usr/bin/env bash
# Native vs YADE backend on one packing and one seeded dF sequence: see native_vs_yade.py.
#   native_vs_yade.sh [E_N]: with E_N, the frict_visco law with restitution E_N.
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir). Starts only python3 in the
# foreground (it runs native_replay to completion itself).
set -uo pipefail
bin=${MPMDEM_BIN:?set MPMDEM_BIN to the build directory}
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
work=$bin/test-runs/native_vs_yade${1:+_visco_$1}
rm -rf "$work"
mkdir -p "$work"
export OMP_NUM_THREADS=1 PYTHONPATH="$src/dem_app/python"
/usr/bin/python3 "$src/tests/integration/native_vs_yade.py" "$work" \
  "$bin/dem_app/native_replay" "$@" 2>&1 | grep -v -e '^Welcome' -e 'X rendering' -e 'python version'
exit "${PIPESTATUS[0]}"

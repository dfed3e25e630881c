#!/usr/bin/env bash
# A native scene whose packings do not exist yet (coupling.native.packing_spec): scripts/run
# builds the YADE library from the spec and exports the named packings to the native format
# (scripts/lib/ensure_packings.py), once; a second run finds them and builds nothing. The
# RVEs start from the exported packing (8 x 100 spheres, not 8 in-place clouds of 40). A
# spec that does not exist exits 2 naming coupling.native.packing_spec, before any run
# directory is made.
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir native_packing_spec
fail() { echo "FAIL: $*" >&2; exit 1; }

scene() {  # scene DEST SPEC
  sed -e "s|^    inline_spheres: 40|    packing_dir: $work/packings\n    packing_spec: $2\n    packings: [col100_s1]|" \
    "$src/tests/integration/native_block_tiny.yaml" >"$1"
  grep -q "packing_spec: $2" "$1" || fail "scene edit"
}
scene "$work/scene.yaml" "$src/configs/packings/column_collapse.yaml"
run_job "$work/run1.log" "$work/scene.yaml" --out "$work/run1" --dem-ranks 1 --max-steps 2
run_job "$work/run2.log" "$work/scene.yaml" --out "$work/run2" --dem-ranks 1 --max-steps 2
builds=$(grep -c "ensure_packings: building" "$work/run1.log")
((builds == 1)) || fail "run 1 built the library $builds times"
! grep -q "ensure_packings: building" "$work/run2.log" || fail "run 2 built the library again"
[[ -s $work/packings/col100_s1.yade.bz2 && -s $work/packings/col100_s1.native.txt ]] ||
  fail "col100_s1.yade.bz2 or .native.txt missing"
[[ ! -e $work/packings/col100_s2.native.txt ]] || fail "exported a packing the scene does not name"
/usr/bin/python3 - "$work" <<'PY' || fail "the runs or the export"
import json, sys
w = sys.argv[1]
for r in ("run1", "run2"):
    s = json.load(open(f"{w}/{r}/summary.json"))
    assert s["status"] == "truncated" and s["steps"] == 2, (r, s["status"], s["steps"])
    assert s["n_rve_particles"] == 8 * 100, (r, s["n_rve_particles"])  # 8 RVEs of col100_s1
assert json.load(open(f"{w}/packings/col100_s1.json"))["parameters"]["n_spheres"] == 100
PY
scene "$work/bad.yaml" "$work/no_such_spec.yaml"
sed -i "s|packing_dir: $work/packings|packing_dir: $work/empty|" "$work/bad.yaml"
"$src/scripts/run" "$work/bad.yaml" --out "$work/bad" --dem-ranks 1 >"$work/bad.log" 2>&1
rc=$?
[[ $rc == 2 && ! -e $work/bad ]] || fail "a missing spec gave exit $rc: $(tail -n 5 "$work/bad.log")"
grep -q "coupling.native.packing_spec .*no_such_spec.yaml does not exist" "$work/bad.log" ||
  fail "no message naming the key: $(cat "$work/bad.log")"
echo "native_packing_spec: library built once, exported, reused; missing spec refused"

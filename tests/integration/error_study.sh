#!/usr/bin/env bash
# scripts/error_vs_runtime (issue 6, item 1):
#  - the elastic column over three cell sizes against the closed form: the table, the CSV and
#    the figure are written, every run is complete, the stress error falls at first order
#    and the settlement error at least at first order as the cell halves (docs/accuracy.md);
#  - a second invocation with the same --out reuses every run (nothing is run again);
#  - a study against a reference run (elastic stub, 2 DEM ranks): the reference's own error
#    is 0, the coarser run's error is larger than the default's;
#  - a broken study file (unknown key, bad version, a knob default not among its values, a
#    key path into a scalar) exits 2 naming the key and the file, and runs nothing.
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir error_study
evr=$src/scripts/error_vs_runtime
studies=$src/tests/integration/studies
fail() { echo "FAIL: $*" >&2; exit 1; }

"$evr" "$studies/elastic_quick.yaml" --out "$work/el" >"$work/el.log" 2>&1 ||
  { tail -n 30 "$work/el.log" >&2; fail "elastic study failed"; }
"$evr" "$studies/elastic_quick.yaml" --out "$work/el" >"$work/el2.log" 2>&1 || fail "re-run failed"
[[ $(grep -c ': reused ' "$work/el2.log") == 3 ]] || { cat "$work/el2.log" >&2; fail "runs not reused"; }
"$evr" "$studies/remote_reference.yaml" --out "$work/ref" >"$work/ref.log" 2>&1 ||
  { tail -n 30 "$work/ref.log" >&2; fail "reference study failed"; }

/usr/bin/python3 - "$work" <<'PY' || exit 1
import csv, os, sys
w = sys.argv[1]
rows = {r["run"]: r for r in csv.DictReader(open(f"{w}/el/study.csv"))}
assert set(rows) == {"cell_size=0.04", "base", "cell_size=0.01"}, rows.keys()
for r in rows.values():
    assert r["status"] == "complete" and float(r["wall_s"]) > 0 and float(r["cpu_s"]) > 0, r
e = [rows[n] for n in ("cell_size=0.04", "base", "cell_size=0.01")]
s = [float(r["err_stress_rel_error"]) for r in e]
u = [float(r["err_settlement_rel_error"]) for r in e]
for a, b in zip(s, s[1:]):
    assert 1.6 < a / b < 2.6, f"stress error not first order: {s}"
for a, b in zip(u, u[1:]):
    assert a / b > 1.8, f"settlement error not at least first order: {u}"
assert int(e[2]["steps"]) > int(e[1]["steps"]) > int(e[0]["steps"])
for f in ("study.md", "error_vs_runtime.png", "error_vs_cputime.png", "scenes/base.yaml"):
    assert os.path.getsize(f"{w}/el/{f}") > 0, f
ref = {r["run"]: r for r in csv.DictReader(open(f"{w}/ref/study.csv"))}
assert set(ref) == {"reference", "base", "cell_size=0.1"}, ref.keys()
for m in ("settlement_top_m", "E_d_over_E_p0"):
    assert float(ref["reference"][f"err_{m}"]) == 0.0, ref["reference"]
x = lambda n, m: float(ref[n][m])
err = abs(x("base", "settlement_top_m") - x("reference", "settlement_top_m")) / abs(x("reference", "settlement_top_m"))
assert abs(float(ref["base"]["err_settlement_top_m"]) - err) <= 1e-3 * err  # 4 digits in the CSV
assert float(ref["cell_size=0.1"]["err_settlement_top_m"]) > float(ref["base"]["err_settlement_top_m"]), ref
print(f"error_study: stress errors {s}, settlement errors {u}")
PY

# Broken study files: exit 2, a message naming the key and the file, nothing run.
bad() {  # name, sed expression applied to elastic_quick.yaml, expected text
  local f=$studies/bad_$1.yaml
  sed -e "$2" "$studies/elastic_quick.yaml" >"$f"
  "$evr" "$f" --out "$work/bad_$1" >"$work/bad_$1.log" 2>&1
  local rc=$?
  rm -f "$f"
  [[ $rc == 2 ]] || { cat "$work/bad_$1.log" >&2; fail "bad study $1: exit $rc, want 2"; }
  grep -q -- "$3" "$work/bad_$1.log" && grep -q "bad_$1.yaml" "$work/bad_$1.log" ||
    { cat "$work/bad_$1.log" >&2; fail "bad study $1: message does not name '$3' and the file"; }
  [[ ! -e $work/bad_$1/runs ]] || fail "bad study $1: something was run"
}
bad unknown_key 's/^design: full/design: full\nrepeats: 3/' "unknown key 'repeats'"
bad version 's/^study_version: 1/study_version: 7/' "study_version 7"
bad default 's/default: 0.02/default: 0.03/' "knobs\[0\].default 0.03"
bad path 's/grid.extent: \[\$v, \$v, 1.2\]/grid.cell_size.x: 1/' "grid.cell_size.x"
# A shipped study that moves the YADE slice to native RVEs (configs/studies/grain_stiffness.yaml):
# its scenes are written without running (--dry-run); a null override removes the key
# (coupling.yade), native packing paths are made absolute against the file that sets them,
# and every scene loads.
"$evr" "$src/configs/studies/grain_stiffness.yaml" --dry-run --out "$work/gs" >"$work/gs.log" 2>&1 ||
  { cat "$work/gs.log" >&2; fail "grain_stiffness dry run"; }
/usr/bin/python3 - "$work/gs/scenes" "$src" <<'PY' || exit 1
import os, sys, yaml
d, src = sys.argv[1:3]
names = sorted(os.listdir(d))
assert names == ["base.yaml", "grain_young=2e+08.yaml", "grain_young=2e+09.yaml",
                 "grain_young=6e+07.yaml", "reference.yaml"], names
for n in names:
    c = yaml.safe_load(open(os.path.join(d, n)))
    assert "flip" not in c["solver"] and c["solver"]["flip_velocity_scale"] == 1.75, (n, c["solver"])
    assert "yade" not in c["coupling"] and c["coupling"]["backend"] == "native", n
    nat = c["coupling"]["native"]
    for k in ("packing_dir", "packing_spec"):
        assert os.path.isabs(nat[k]), (n, k, nat[k])
    assert os.path.isfile(nat["packing_spec"]), (n, nat["packing_spec"])
ref = yaml.safe_load(open(os.path.join(d, "reference.yaml")))["coupling"]["native"]
assert ref["packing_spec"] == os.path.join(src, "configs/studies/packings/column_collapse_E6e8.yaml"), ref
base = yaml.safe_load(open(os.path.join(d, "base.yaml")))["coupling"]["native"]
assert base["packing_spec"] == os.path.join(src, "configs/packings/column_collapse.yaml"), base
print("grain_stiffness scenes: ok")
PY
for f in "$work"/gs/scenes/*.yaml; do
  "$MPMDEM_BIN/mpm_app/mpm_app" --check-config "$f" >/dev/null || fail "$f does not load"
done
[[ ! -e $work/gs/runs/base ]] || fail "the dry run ran something"

# The cell-size study (full design): the reference at 0.055 m and the 2 x 2 runs, each
# scene loads, and the Coulomb ones carry the base's friction.
"$evr" "$src/configs/studies/cell_size_base.yaml" --dry-run --out "$work/csb" >"$work/csb.log" 2>&1 ||
  { cat "$work/csb.log" >&2; fail "cell_size_base dry run"; }
/usr/bin/python3 - "$work/csb/scenes" <<'PY' || exit 1
import os, sys, yaml
d = sys.argv[1]
names = sorted(os.listdir(d))
assert names == ["base.yaml", "base=friction.yaml", "base=friction__cell_size=0.1375.yaml",
                 "cell_size=0.1375.yaml", "reference.yaml"], names
for n in names:
    c = yaml.safe_load(open(os.path.join(d, n)))
    h = {"reference.yaml": 0.055}.get(n, 0.1375 if "0.1375" in n else 0.11)
    assert c["grid"]["cell_size"] == h and c["grid"]["extent"][1] == h, (n, c["grid"])
    assert c["regions"][0]["max"][1] == h, (n, c["regions"][0])
    friction = "friction" in n
    assert c["walls"]["z_min"] == ("friction" if friction else "fixed"), (n, c["walls"])
    assert c["walls"].get("friction") == (0.52 if friction else None), (n, c["walls"])
print("cell_size_base scenes: ok")
PY
for f in "$work"/csb/scenes/*.yaml; do
  "$MPMDEM_BIN/mpm_app/mpm_app" --check-config "$f" >/dev/null || fail "$f does not load"
done

# The APIC slice study: APIC with a FLIP share everywhere but the pic_flip run, on the 4.4 m
# domain; cfl and base as named.
"$evr" "$src/configs/studies/transfer_apic_slice.yaml" --dry-run --out "$work/tas" >"$work/tas.log" 2>&1 ||
  { cat "$work/tas.log" >&2; fail "transfer_apic_slice dry run"; }
/usr/bin/python3 - "$work/tas/scenes" <<'PY' || exit 1
import os, sys, yaml
d = sys.argv[1]
names = sorted(os.listdir(d))
assert names == ["base.yaml", "base=friction.yaml", "cfl=0.25.yaml", "reference.yaml",
                 "transfer=pic_flip.yaml"], names
for n in names:
    c = yaml.safe_load(open(os.path.join(d, n)))
    s = c["solver"]
    assert s["transfer"] == ("pic_flip" if "pic_flip" in n else "apic"), (n, s)
    assert s["flip_velocity_scale"] == 1.75 and s["cfl"] == (0.25 if "cfl" in n else 0.5), (n, s)
    h = 0.055 if n == "reference.yaml" else 0.11
    assert c["grid"]["extent"] == [4.4, h, 1.43] and c["grid"]["cell_size"] == h, (n, c["grid"])
    assert c["walls"]["z_min"] == ("friction" if "friction" in n else "fixed"), (n, c["walls"])
print("transfer_apic_slice scenes: ok")
PY
for f in "$work"/tas/scenes/*.yaml; do
  "$MPMDEM_BIN/mpm_app/mpm_app" --check-config "$f" >/dev/null || fail "$f does not load"
done
echo "error_study: ok"

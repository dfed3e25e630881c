#!/usr/bin/python3
"""Driver of scripts/stability_suite (run under Debian's /usr/bin/python3: yaml, numpy, h5py).

  stability_suite.py OUT_DIR [--quick] [--only NAME[,NAME...]]

Generates each case's scene from the bases in configs/stability/ (the overrides are listed in
CASES below), runs it in OUT_DIR/<case>/ through scripts/run (MPM scenes; every process it
starts is stopped by PID) or scripts/element_test (dF increments into YADE RVEs), then reads
what the run wrote and writes OUT_DIR/stability.csv, OUT_DIR/stability.md and
OUT_DIR/summary.json. Exit code 0 when every case behaved as expected (stable cases stable,
the deliberately unstable one detected with the point and the step) and no output file holds
a NaN or an Inf; 1 otherwise.

Columns (docs/stability.md):
  stable       yes: the run completed, every output finite; no: it stopped on an instability
  dt_s         time step of the MPM run (min-max when it changed); '-' for element tests
  energy_err   max over the logged steps of |E_err| / E_ref, E_err the energies.csv column
               (E_p0 + E_k0 - E_p - E_k - W_int - W_damp - W_bc) and
               E_ref = E_k0 + max_t |E_p0 - E_p(t)| (the kinetic energy at the start plus the
               most potential energy released)
  energy_other max over the logged steps of |E_err - W_transfer| / E_ref: the residual less
               what the particle-grid transfers removed (time integration, instabilities)
  max_v        max |v_p| over the VTK frames [m/s]
  faults       what the run reported: the error (point or RVE id and step), RVE statuses
"""
import csv
import json
import math
import os
import re
import signal
import subprocess
import sys
import time

import numpy as np
import yaml

from stability_outputs import energy_error, last_frame, max_velocity, non_finite_files

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))  # scripts/
from mpmdem_tools.summary import read_summary  # noqa: E402  (the one summary.json reader)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CFG = os.path.join(ROOT, "configs", "stability")
G = 9.81
RVE_STATUS = {1: "kNoContacts", 2: "kNonFinite", 3: "kExploding", 4: "kBackendError"}


def setp(doc, path, value):
    """Set doc[a][b]... for a dotted path; list indices as integers (regions.0.max)."""
    keys = path.split(".")
    node = doc
    for k in keys[:-1]:
        node = node[int(k)] if isinstance(node, list) else node.setdefault(k, {})
    last = keys[-1]
    if isinstance(node, list):
        node[int(last)] = value
    else:
        node[last] = value


def stiff_case(E):
    nu, rho, H = 0.3, 2000.0, 1.0
    M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    period = 4 * H / math.sqrt(M / rho)
    return {
        "name": "stiff_E%.0e" % E,
        "what": "elastic column, E = %.0e Pa, automatic dt" % E,
        "kind": "mpm", "base": "elastic_column_stiff.yaml", "expect": "stable",
        "quick": E in (1e6, 1e9, 1e11), "E": E, "M": M, "rho": rho,
        "set": {"constitutive.linear_elastic.youngs_modulus": E,
                "solver.end_time": 2 * period, "output.interval": period / 10},
    }


def column_case(a):
    L, h = 0.55, 0.11
    H = a * L
    # Room for the runout (Lajeunesse et al. 2005: dL/L = 1.2 a below a = 3, 1.9 a^(2/3) above)
    # with a margin, in whole cells.
    runout = L * (1 + (1.2 * a if a < 3 else 1.9 * a ** (2.0 / 3.0)))
    length = h * math.ceil(1.5 * runout / h + 2)
    height = h * math.ceil(H / h + 1)
    H = round(H / 0.055) * 0.055  # whole point spacings (2 points per 0.11 m cell)
    return {
        "name": "column_a%g" % a,
        "what": "Drucker-Prager column collapse, a = %g (H = %.3g m), 3 t*" % (a, H),
        "kind": "mpm", "base": "column_collapse_dp.yaml", "expect": "stable", "quick": a == 0.5,
        "set": {"regions.0.max": [L, 0.11, H], "grid.extent": [length, 0.11, height],
                "velocity_constraints.0.max": [L, 0.11, height]},
    }


def impact_case(model):
    return {
        "name": "impact_%s" % ("elastic" if model == "linear_elastic" else "dp"),
        "what": "bar hitting a fixed wall at 50 m/s, %s" % model.replace("_", " "),
        "kind": "mpm", "base": "impact.yaml", "expect": "stable", "quick": model == "linear_elastic",
        "check": "impact", "set": {"constitutive.model": model},
    }


def element_case(name, what, strain_per_step, protocol="loose", porosity=0.65, expect="stable"):
    steps = max(1, int(round(0.02 / strain_per_step)))
    return {
        "name": name, "what": what, "kind": "element", "base": "element_test_rve.yaml",
        "expect": expect, "quick": False, "strain_per_step": strain_per_step,
        "set": {"element_test.tests": [{"path": "triaxial", "strain": steps * strain_per_step,
                                        "steps": steps}],
                "packings.protocol": protocol, "packings.porosity_init": porosity,
                "packings.items": [{"name": "stab_%s" % protocol, "seed": 4}],
                "coupling.yade.packings": ["stab_%s_s4" % protocol],
                "coupling.yade.packing_dir": "PACKINGS/%s_n%g" % (protocol, porosity),
                "coupling.service_name": "mpmdem_stability_%s" % name},
    }


def unstable_case():
    """The column at E = 1e7 Pa with a forced step 3 h / c: 6x the automatic one (cfl 0.5)."""
    c = stiff_case(1e7)
    c.update(name="unstable_dt_fixed", expect="unstable", quick=True,
             what="elastic column, E = 1e7 Pa, solver.dt_fixed = 3 h / c (3x the CFL limit)")
    c["set"] = dict(c["set"], **{"solver.dt_fixed": 3 * 0.02 / math.sqrt(c["M"] / c["rho"])})
    return c


CASES = (
    [stiff_case(E) for E in (1e6, 1e7, 1e8, 1e9, 1e10, 1e11)]
    + [column_case(a) for a in (0.5, 2.4, 6, 12)]
    + [impact_case("linear_elastic"), impact_case("drucker_prager")]
    + [{"name": "free_fall_rves", "what": "multiscale block in free fall, 40-sphere YADE RVEs",
        "kind": "mpm", "base": "free_fall_yade.yaml", "expect": "stable", "quick": False,
        "check": "free_fall", "set": {}}]
    + [element_case("dF_1e-4", "triaxial dF increments 1e-4 per step into a YADE RVE", 1e-4),
       element_case("dF_1e-3", "triaxial dF increments 1e-3 per step into a YADE RVE", 1e-3),
       element_case("dF_1e-2", "triaxial dF increments 1e-2 per step into a YADE RVE", 1e-2),
       element_case("packing_loose", "very loose packing (porosity_init 0.75), 1e-3 per step",
                    1e-3, "loose", 0.75),
       element_case("packing_dense", "very dense packing (frictionless consolidation), 1e-3 per step",
                    1e-3, "dense", 0.65)]
    + [unstable_case()]
)

def free_fall_check(run_dir, r):
    """Every point falls with v = g t and carries no stress once its RVE lost its contacts."""
    t, a = last_frame(run_dir)
    if t is None or "velocity" not in a or "stress" not in a:
        return False, "no last frame"
    vz = a["velocity"][:, 2]
    rel = float(np.max(np.abs(vz + G * t)) / (G * t))
    smax = float(np.max(np.abs(a["stress"])))
    r["notes"].append("last frame t = %.4g s: v_z %.4g..%.4g m/s against -g t = %.4g "
                      "(max rel. diff %.2g), max |sigma| = %.3g Pa"
                      % (t, vz.min(), vz.max(), -G * t, rel, smax))
    no_contacts = r["summary"].get("rve_no_contact_points_final", 0) == r["summary"].get(
        "n_material_points", -1)
    ok = rel < 0.02 and smax == 0.0 and no_contacts
    return ok, "" if ok else "free fall: v != g t, stress left or contacts kept"


# ---------------------------------------------------------------------------------------------
# Running

def run(cmd, log_path, timeout, env):
    """Runs cmd in its own session with output to log_path; on timeout stops it (SIGTERM to the
    launcher, which stops what it started by PID; then SIGKILL to its group). Returns rc."""
    with open(log_path, "w") as log:
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env,
                                start_new_session=True, cwd=ROOT)
        try:
            return proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.send_signal(signal.SIGTERM)
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
            return 124


def write_scene(case, out_dir, packings_dir):
    doc = yaml.safe_load(open(os.path.join(CFG, case["base"])))
    for k, v in case["set"].items():
        if isinstance(v, str):
            v = v.replace("PACKINGS", packings_dir)
        setp(doc, k, v)
    if "scene" in doc:
        doc["scene"]["name"] = "stability_" + case["name"]
    path = os.path.join(out_dir, case["name"] + ".yaml")
    with open(path, "w") as f:
        f.write("# Generated by scripts/lib/stability_suite.py from configs/stability/%s\n"
                % case["base"])
        yaml.safe_dump(doc, f, sort_keys=False)
    return path


def mpm_case(case, out, env, timeout):
    scene = write_scene(case, out, "")
    run_dir = os.path.join(out, case["name"])
    t0 = time.time()
    rc = run([os.path.join(ROOT, "scripts", "run"), scene, "--out", run_dir, "--force",
              "--dem-ranks", "1", "--threads", "1"],
             os.path.join(out, case["name"] + ".log"), timeout, env)
    r = {"rc": rc, "wall_s": time.time() - t0}
    summ_path = os.path.join(run_dir, "summary.json")
    summ = read_summary(summ_path) if os.path.exists(summ_path) else {}
    r["status"] = summ.get("status", "no summary")
    r["steps"] = summ.get("steps")
    r["time_s"] = summ.get("time_s")
    dt0, dt1 = summ.get("dt_min_s"), summ.get("dt_max_s")
    r["dt_min"], r["dt_max"] = dt0, dt1
    r["dt"] = "-" if not dt0 else ("%.3g" % dt0 if abs(dt1 - dt0) <= 1e-3 * dt0
                                   else "%.3g-%.3g" % (dt0, dt1))
    en = os.path.join(run_dir, "energies.csv")
    r["energy_err"], r["energy_other"], r["E_ref"] = (
        energy_error(en) if os.path.exists(en) else (float("nan"), float("nan"), 0))
    r["max_v"] = max_velocity(run_dir) if os.path.isdir(run_dir) else float("nan")
    faults = []
    if summ.get("error"):
        faults.append(summ["error"])
    analysis = summ  # the analysis figures are top-level keys of summary.json
    if analysis.get("rve_no_contact_updates"):
        faults.append("kNoContacts (not fatal): %d point-updates, %d of %d points at the end"
                      % (analysis["rve_no_contact_updates"],
                         analysis.get("rve_no_contact_points_final", 0),
                         summ.get("n_material_points", 0)))
    if summ.get("removed_points"):
        faults.append("%d point(s) left the grid (on_exit remove)" % summ["removed_points"])
    r["faults"] = faults
    r["checked"], r["nan_files"] = non_finite_files(run_dir) if os.path.isdir(run_dir) else (0, [])
    r["stable"] = rc == 0 and r["status"] == "complete" and not r["nan_files"]
    r["summary"] = {k: v for k, v in summ.items() if isinstance(v, (int, float))}
    r["notes"] = []
    if "E" in case and dt0:
        r["notes"].append("dt sqrt(E) = %.4g s Pa^0.5; c = sqrt(M/rho) = %.4g m/s, h/c = %.3g s"
                          % (dt0 * math.sqrt(case["E"]), math.sqrt(case["M"] / case["rho"]),
                             0.02 / math.sqrt(case["M"] / case["rho"])))
    if "runout_m" in summ:
        r["notes"].append("runout %.3g m, final height %.3g m (H = %.3g m), E_d/E_p0 %.3g"
                          % (summ["runout_m"], summ.get("final_height_m", float("nan")),
                             summ.get("initial_height_m", float("nan")),
                             summ.get("E_d_over_E_p0", float("nan"))))
    if case.get("check") == "impact" and os.path.isdir(run_dir):
        t, a = last_frame(run_dir)
        if "velocity" in a:
            vz = a["velocity"][:, 2]
            r["rebound_v"] = float(vz.mean())
            r["E_k_final_over_E_ref"] = summ.get("E_k_J", float("nan")) / r["E_ref"]
            r["notes"].append("last frame t = %.4g s: mean v_z %.4g m/s (rebound; impact at -50), "
                              "v_z %.4g..%.4g m/s, E_k/E_ref %.3g" % (
                                  t, vz.mean(), vz.min(), vz.max(),
                                  summ.get("E_k_J", float("nan")) / r["E_ref"]))
    if case.get("check") == "free_fall" and os.path.isdir(run_dir):
        ok, why = free_fall_check(run_dir, r)
        r["check_failed"] = "" if ok else why
    return r


def element_case_run(case, out, env, timeout):
    cfg = write_scene(case, out, os.path.join(out, "packings"))
    run_dir = os.path.join(out, case["name"])
    t0 = time.time()
    rc = run([os.path.join(ROOT, "scripts", "element_test"), cfg, "--out", run_dir],
             os.path.join(out, case["name"] + ".log"), timeout, env)
    r = {"rc": rc, "wall_s": time.time() - t0, "dt": "-", "energy_err": float("nan"),
         "energy_other": float("nan"), "max_v": float("nan"), "steps": None}
    faults, finite, statuses = [], True, {}
    path = os.path.join(run_dir, "triaxial.csv")
    rows = list(csv.DictReader(open(path))) if os.path.exists(path) else []
    for row in rows:
        vals = [float(v) for k, v in row.items() if k not in ("step", "rve", "status")]
        if not all(math.isfinite(v) for v in vals):
            finite = False
        st = int(float(row["status"]))
        if st != 0:
            statuses.setdefault(st, []).append((int(float(row["rve"])), int(float(row["step"]))))
    for st, where in sorted(statuses.items()):
        rve, step = where[0]
        faults.append("%s at RVE %d from step %d (%d reply(ies))"
                      % (RVE_STATUS.get(st, "status %d" % st), rve, step, len(where)))
    if rc != 0:
        faults.append("scripts/element_test exited %d (log %s.log)" % (rc, case["name"]))
    if not rows:
        faults.append("no triaxial.csv")
    r["steps"] = max((int(float(x["step"])) for x in rows), default=0)
    fatal = any(st in (2, 3, 4) for st in statuses)
    summ_path = os.path.join(run_dir, "summary.json")
    summ = read_summary(summ_path) if os.path.exists(summ_path) else {}
    tri = (summ.get("tests") or {}).get("triaxial", {}) if isinstance(summ.get("tests"), dict) else {}
    r["porosity_initial"] = summ.get("porosity_initial")
    r["phi_peak_deg"] = tri.get("phi_peak_deg", summ.get("phi_peak_deg"))
    if rows:
        last = rows[-1]
        r["final_p"] = -(float(last["sigma_xx"]) + float(last["sigma_yy"]) + float(last["sigma_zz"])) / 3
        r["final_q_over_p"] = float(last["q"]) / float(last["p"]) if float(last["p"]) else float("nan")
    r["faults"] = faults
    inc = case["strain_per_step"]
    # The proportional rule of the scene: ns = clamp(ceil(ns_factor max|dF - I|), ns_min, ns_max)
    # with the defaults 1e5, 2, 100 (docs/config_reference.md); max|dF - I| = the axial increment.
    ns = min(100, max(2, math.ceil(1e5 * inc - 1e-9)))
    r["notes"] = ["ns = %d DEM substeps per step (rule)" % ns]
    if rows:
        r["notes"].append("final p = %.4g kPa, q/p = %.3g, porosity %.3f -> %.3f" % (
            r["final_p"] / 1e3, r["final_q_over_p"], float(rows[0]["porosity"]),
            float(rows[-1]["porosity"])))
    r["status"] = "complete" if rc == 0 and rows and not fatal else "failed"
    r["checked"], r["nan_files"] = non_finite_files(run_dir) if os.path.isdir(run_dir) else (0, [])
    if not finite:
        r["nan_files"].append("triaxial.csv (non-finite stress)")
    r["stable"] = r["status"] == "complete" and finite and not r["nan_files"]
    return r


def verdict(case, r):
    """Did the case behave as expected? (bool, why)."""
    if r["nan_files"]:
        return False, "non-finite values in " + ", ".join(r["nan_files"])
    if r.get("check_failed"):
        return False, r["check_failed"]
    if case["expect"] == "stable":
        return (True, "") if r["stable"] else (False, "expected stable, got " + r["status"])
    err = " ".join(r["faults"])
    named = re.search(r"material point \d+", err) and re.search(r"at step \d+", err)
    if r["status"] == "failed" and r["rc"] not in (0, 124) and named:
        return True, ""
    return False, "instability not detected with point and step (status %s, rc %s)" % (
        r["status"], r["rc"])


def fmt(x, spec="%.3g"):
    return "-" if x is None or (isinstance(x, float) and not math.isfinite(x)) else spec % x


def usage_error(msg):
    print("stability_suite: " + msg, file=sys.stderr)
    sys.exit(2)


def main(argv):
    out, quick, only = None, False, None
    i = 0
    while i < len(argv):
        if argv[i] == "--quick":
            quick = True
        elif argv[i] == "--only":
            only = set(argv[i + 1].split(","))
            i += 1
        elif out is None:
            out = argv[i]
        else:
            usage_error("unexpected argument %s" % argv[i])
        i += 1
    if out is None:
        usage_error("usage: stability_suite.py OUT_DIR [--quick] [--only NAMES]")
    os.makedirs(out, exist_ok=True)
    out = os.path.abspath(out)
    env = dict(os.environ, MPMDEM_SKIP_SETUP="1", OMP_NUM_THREADS="1")
    cases = [c for c in CASES if (not quick or c["quick"]) and (only is None or c["name"] in only)]
    if only and len(cases) != len(only):
        usage_error("unknown case(s): %s (known: %s)" % (", ".join(sorted(only - {c["name"] for c in cases})),
                                                          ", ".join(c["name"] for c in CASES)))
    t_all = time.time()
    results = []
    for c in cases:
        print("stability_suite: %-18s %s ..." % (c["name"], c["what"]), flush=True)
        runner = mpm_case if c["kind"] == "mpm" else element_case_run
        r = runner(c, out, env, timeout=900)
        ok, why = verdict(c, r)
        r.update(name=c["name"], what=c["what"], expect=c["expect"], ok=ok, why=why)
        if "E" in c:
            r["E"] = c["E"]
        results.append(r)
        print("  -> %s, %s, dt %s s, energy err %s, max |v| %s m/s, %.1f s wall%s" % (
            "stable" if r["stable"] else "NOT stable", "as expected" if ok else "UNEXPECTED: " + why,
            r["dt"], fmt(r["energy_err"]), fmt(r["max_v"]), r["wall_s"],
            ("; " + " | ".join(r["faults"])) if r["faults"] else ""), flush=True)
    wall = time.time() - t_all
    write_tables(out, results, wall, quick)
    bad = [r["name"] for r in results if not r["ok"]]
    print("stability_suite: %d case(s), %d as expected, %.0f s wall; table %s/stability.md"
          % (len(results), len(results) - len(bad), wall, out))
    if bad:
        print("stability_suite: UNEXPECTED: " + ", ".join(bad))
    return 1 if bad else 0


def write_tables(out, results, wall, quick):
    cols = ["case", "expected", "stable", "as_expected", "dt_s", "energy_err", "energy_other",
            "max_v_m_s",
            "steps", "wall_s", "faults", "notes"]
    with open(os.path.join(out, "stability.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in results:
            w.writerow([r["name"], r["expect"], "yes" if r["stable"] else "no",
                        "yes" if r["ok"] else "no", r["dt"], fmt(r["energy_err"], "%.4g"),
                        fmt(r["energy_other"], "%.4g"),
                        fmt(r["max_v"], "%.4g"), r["steps"] if r["steps"] is not None else "-",
                        "%.1f" % r["wall_s"], " | ".join(r["faults"] + ([r["why"]] if r["why"] else [])),
                        " | ".join(r.get("notes", []))])
    lines = ["| case | what | stable | dt [s] | energy-balance error | of which not the transfers' "
             "| max \\|v\\| [m/s] | steps | wall [s] | faults |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        stable = "yes" if r["stable"] else "no"
        if r["expect"] == "unstable":
            stable += " (detected)" if r["ok"] else " (NOT detected)"
        elif not r["ok"]:
            stable += " (UNEXPECTED)"
        faults = " ; ".join(x.replace("|", "\\|") for x in r["faults"]) or "none"
        lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %.1f | %s |" % (
            r["name"], r["what"], stable, r["dt"], fmt(r["energy_err"]),
            fmt(r["energy_other"]), fmt(r["max_v"]),
            r["steps"] if r["steps"] is not None else "-", r["wall_s"], faults))
    stiff = [r for r in results if r["name"].startswith("stiff_") and r.get("dt_min")]
    extra = []
    if len(stiff) >= 2:
        k = [r["dt_min"] * math.sqrt(r["E"]) for r in stiff]
        extra.append("dt sqrt(E) over the stiffness sweep: %.4g to %.4g s Pa^0.5 (spread %.2g %%)"
                     % (min(k), max(k), 100 * (max(k) - min(k)) / min(k)))
    n_ok = sum(r["ok"] for r in results)
    with open(os.path.join(out, "stability.md"), "w") as f:
        f.write("# Stability suite%s\n\n%d case(s), %d as expected, %.0f s wall.\n\n"
                % (" (--quick)" if quick else "", len(results), n_ok, wall))
        f.write("\n".join(lines) + "\n\n")
        for e in extra:
            f.write(e + "\n\n")
        f.write("Notes per case:\n\n")
        for r in results:
            if r.get("notes"):
                f.write("- %s: %s\n" % (r["name"], "; ".join(r["notes"])))
        f.write("\n")
        nan_checked = sum(r["checked"] for r in results)
        f.write("Output files scanned for NaN/Inf: %d, with a non-finite value: %d.\n"
                % (nan_checked, sum(len(r["nan_files"]) for r in results)))
    summary = {"cases": results, "wall_time_s": wall, "quick": quick,
               "as_expected": n_ok, "n_cases": len(results)}
    with open(os.path.join(out, "summary.json"), "w") as f:
        f.write(json.dumps(clean(summary), indent=1, allow_nan=False) + "\n")


def clean(x):
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [clean(v) for v in x]
    return x


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

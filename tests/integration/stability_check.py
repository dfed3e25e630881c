#!/usr/bin/python3
"""Checks the table of scripts/stability_suite (registered by stability.cmake).

  stability_check.py OUT_DIR quick|yade SUITE_EXIT_CODE
"""
import json
import math
import re
import sys

out, kind, rc = sys.argv[1], sys.argv[2], int(sys.argv[3])
doc = json.load(open(out + "/summary.json"))
cases = {c["name"]: c for c in doc["cases"]}
fails = []


def check(cond, what):
    if not cond:
        fails.append(what)


check(rc == 0, "scripts/stability_suite exited %d" % rc)
for name, c in cases.items():
    check(c["ok"], "%s: not as expected: %s" % (name, c["why"]))
    check(not c["nan_files"], "%s: NaN/Inf in %s" % (name, c["nan_files"]))
    check(c["checked"] >= 3, "%s: only %d output files scanned" % (name, c["checked"]))

if kind == "quick":
    want = {"stiff_E1e+06", "stiff_E1e+09", "stiff_E1e+11", "column_a0.5", "impact_elastic",
            "unstable_dt_fixed"}
    check(set(cases) == want, "cases %s, expected %s" % (sorted(cases), sorted(want)))
    # Stiff cases: stable; the automatic dt is cfl h / (c + |v|) with c = sqrt(M / rho), so
    # dt sqrt(E) is the same for E = 1e6 ... 1e11 Pa (|v| << c: within 2 %).
    h, cfl, rho, nu = 0.02, 0.5, 2000.0, 0.3
    k = []
    for name in sorted(n for n in cases if n.startswith("stiff_")):
        c = cases[name]
        E = c["E"]
        M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
        dt_cfl = cfl * h / math.sqrt(M / rho)
        check(c["stable"], name + ": not stable")
        check(abs(c["dt_max"] - dt_cfl) <= 0.01 * dt_cfl,
              "%s: dt_max %.4g s, cfl h / c = %.4g s" % (name, c["dt_max"], dt_cfl))
        check(dt_cfl * 0.97 <= c["dt_min"] <= c["dt_max"], "%s: dt_min %.4g" % (name, c["dt_min"]))
        check(c["energy_err"] is not None and c["energy_err"] < 0.1,
              "%s: energy-balance error %s" % (name, c["energy_err"]))
        k.append(c["dt_min"] * math.sqrt(E))
    check(len(k) == 3 and max(k) / min(k) < 1.02, "dt sqrt(E) not constant: %s" % k)
    # Stiffer is not less accurate: the balance of the stiff columns closes within 1 %.
    for name in ("stiff_E1e+09", "stiff_E1e+11"):
        check(cases[name]["energy_err"] < 0.01, "%s: energy error %s" % (name, cases[name]["energy_err"]))
    u = cases["unstable_dt_fixed"]
    err = " ".join(u["faults"])
    check(not u["stable"] and u["status"] == "failed" and u["rc"] == 4,
          "unstable case: stable %s status %s rc %s" % (u["stable"], u["status"], u["rc"]))
    check(re.search(r"material point \d+ .*at step \d+", err) is not None,
          "unstable case: error does not name point and step: " + err)
    check(u["energy_err"] is None or u["energy_err"] > 1.0,
          "unstable case: energy error %s (expected the blow-up to show)" % u["energy_err"])
    # The elastic bar hits the wall at 50 m/s and must come back: an elastic rebound leaves with
    # the impact speed and the initial kinetic energy (wave transit 2 L / c = 3.1 ms, over by
    # t = 5.1 ms of the 10 ms). Measured (2026-11-28): mean v_z +44.7 m/s in the last frame,
    # E_k / E_k0 = 0.949, balance error 0.129 (FLIP 0.99 keeps the bar ringing). A bar that
    # stops, sticks, passes through the wall or gains energy fails.
    imp = cases["impact_elastic"]
    v_out, ek = imp.get("rebound_v", float("nan")), imp.get("E_k_final_over_E_ref", float("nan"))
    check(imp["stable"], "impact: not stable")
    check(40.0 <= v_out <= 51.0, "impact: mean rebound velocity %s m/s, expected 40-51 (impact at -50)" % v_out)
    check(0.85 <= ek <= 1.02, "impact: E_k after the rebound / E_k0 = %s, expected 0.85-1.02" % ek)
    check(imp["energy_err"] < 0.2, "impact: energy-balance error %s (>= 0.2)" % imp["energy_err"])
else:
    ff = cases["free_fall_rves"]
    check(ff["stable"], "free fall: not stable")
    check(any("kNoContacts" in f for f in ff["faults"]), "free fall: kNoContacts not reported")
    check(any("max |sigma| = 0 Pa" in n for n in ff["notes"]), "free fall: stress left: %s" % ff["notes"])
    d = cases["dF_1e-2"]
    check(d["stable"] and d["steps"] == 2, "dF 1e-2: stable %s steps %s" % (d["stable"], d["steps"]))
    check(d.get("final_p") and 1e5 < d["final_p"] < 1e8, "dF 1e-2: final p %s" % d.get("final_p"))

if fails:
    print("stability_check: FAILED\n  " + "\n  ".join(fails))
    sys.exit(1)
print("stability_check: %d case(s) checked, all as expected" % len(cases))

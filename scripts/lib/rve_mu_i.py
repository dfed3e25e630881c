#!/usr/bin/env python3
"""mu(I) of an RVE from drained triaxial element tests at imposed inertial numbers.

Used by scripts/rve_mu_i_study (which runs scripts/element_test once per inertial number);
run with /usr/bin/python3 (Debian's numpy, yaml, matplotlib).

  rve_mu_i.py config IN I OUT --grain-diameter D --grain-density RHO
      write element_test config IN with element_test.dt and the triaxial path's steps set
      so that it runs at the nominal inertial number I = sqrt(3) rate d / sqrt(P / rho_s),
      rate the nominal axial Hencky strain rate -log(1 - strain) / (steps dt) and P its
      pressure. The step: dt = max(MIN_DT, MAX_STEP_STRAIN / rate), so that a slow test
      takes steps of at most 1e-4 strain (the driver's mixed control corrects the lateral
      stress once per step: a quasi-static RVE's stress moves ~1 kPa per 1e-4) and a fast
      one updates at most every MIN_DT (~5 DEM steps: ceil(dt / dt_dem) then adds < 20 %
      to the DEM time, which the analysis counts). IN must have exactly one test, a triaxial
      path, and the `rate` substep rule in its coupling (otherwise dt would not set the
      RVE's strain rate): exit 2 naming the key. Prints dt and steps.
  rve_mu_i.py config-proportional IN NS_FACTOR NS_MAX OUT
      write IN with the `proportional` substep rule (ns = clamp(ceil(NS_FACTOR max|dF - I|),
      ns_min, NS_MAX): a fixed strain per DEM substep, the shipped column's rule) and IN's
      own dt and steps: the RVE's strain rate is then the rule's, whatever dt. Its point is
      shown beside the rate rule's and left out of the fit.
  rve_mu_i.py analyse DIR RUN... --grain-diameter D --grain-density RHO [--figure PNG]
      read DIR/RUN/triaxial.csv, plan.json and scene.yaml of each run (a run named
      `proportional` is shown, not fitted); write DIR/mu_i.json, DIR/mu_i.md and the figure.
  rve_mu_i.py --self-test

Definitions (the local law's, mpm_app/src/constitutive/drucker_prager.hpp):
- the window is the last 20 % of the steps (the element tests' phi_cs window);
- phi = asin((s1 - s3) / (s1 + s3)) of the RVE-mean stress per step, averaged over the
  window; its standard error from the RVEs' own window means;
- shear rate gamma_dot = sqrt(2 de:de) / t_window, de the deviator of the RVE-mean Hencky
  strain's change over the window (sqrt(3) times the axial rate at constant volume), t_window
  the DEM time the window's updates ran (rate rule: each update ceil(dt / dt_dem) DEM steps
  of the packing's dt_dem, a few % above the updates' dt when dt spans few DEM steps;
  proportional rule: ceil(ns_factor x the step's axial strain) of them; within ns_min,
  ns_max; mean over the packings);
- I = gamma_dot d / sqrt(p / rho_s), p the window's mean pressure;
- the fit: sin phi(I) = a + b I / (I_0 + I) (Jop, Forterre & Pouliquen 2006, with sin phi
  for mu as the local law's plane-strain matching has it), least squares in sin phi, I_0 on
  a log grid with a and b linear; also with I_0 = 0.279 held (Jop et al.'s glass beads).
"""
import json
import math
import os
import sys

FRACTION = 0.2          # the window: the last 20 % of the steps
JOP_I0 = 0.279
MAX_STEP_STRAIN = 1e-4  # nominal axial strain per step, at most
MIN_DT = 2.5e-5         # s, the shortest update (the column's 20 MPa grains: dt_dem ~5.2e-6 s)


def fail(msg, code=2):
    print("rve_mu_i: " + msg, file=sys.stderr)
    sys.exit(code)


def nominal_step(strain, inertial_number, pressure, d, rho_s):
    """(dt, steps) of a triaxial path to `strain` at the nominal inertial number."""
    rate = inertial_number * math.sqrt(pressure / rho_s) / (math.sqrt(3.0) * d)
    hencky = -math.log(1.0 - strain)
    dt = max(MIN_DT, MAX_STEP_STRAIN / rate)
    steps = max(1, round(hencky / (rate * dt)))
    return hencky / (steps * rate), steps   # dt adjusted to the whole number of steps


def write_config(src, inertial_number, dst, d, rho_s, proportional=None):
    """IN with dt and steps set for the nominal I (rate rule), or with the proportional rule
    (ns_factor, ns_max) = proportional and IN's dt and steps."""
    import yaml
    with open(src) as f:
        cfg = yaml.safe_load(f)
    et = cfg.get("element_test") or {}
    tests = et.get("tests") or []
    if len(tests) != 1 or tests[0].get("path") != "triaxial":
        fail("%s: element_test.tests must be exactly one triaxial path, got %s"
             % (src, [t.get("path") for t in tests]))
    coupling = cfg.get("coupling") or {}
    yade_rule = (coupling.get("yade") or {}).get("ns_rule")
    native_rule = (coupling.get("native") or {}).get("ns_rule", yade_rule)  # as element_test derives it
    if yade_rule != "rate" or native_rule != "rate":
        fail("%s: coupling.yade.ns_rule (and coupling.native.ns_rule, if given) must be rate, "
             "so that each update's dt sets the RVE's strain rate; got %s / %s"
             % (src, yade_rule, native_rule))
    if proportional:
        for b in ("yade", "native"):
            if coupling.get(b):
                coupling[b].update({"ns_rule": "proportional", "ns_factor": proportional[0],
                                    "ns_max": proportional[1]})
        suffix = "proportional"
    else:
        if not (inertial_number > 0 and math.isfinite(inertial_number)):
            fail("inertial number %r: give a finite I > 0" % inertial_number)
        t = tests[0]
        et["dt"], t["steps"] = nominal_step(float(t["strain"]), inertial_number,
                                            float(et["pressure"]), d, rho_s)
        suffix = "I%.3g" % inertial_number
    # one service name per run, so that runs started together do not meet
    coupling["service_name"] = "%s_%s" % (coupling.get("service_name", "mu_i"), suffix)
    with open(dst, "w") as f:
        yaml.safe_dump(cfg, f, sort_keys=False)
    return et["dt"], tests[0]["steps"]


def dem_time_per_update(scene_path, dt, step_strain):
    """DEM time an update of dt runs, as the native backend's substep rule gives it.

    scene_path: the run's scene.yaml (the coupling section dem_app read). Rate rule: ns =
    clamp(ceil(dt / dt_dem), ns_min, ns_max) substeps of the RVE's own dt_dem (the `dt` line
    of its native packing), at least dt, at most one DEM step more unless clamped.
    Proportional rule: ns = clamp(ceil(ns_factor step_strain), ns_min, ns_max), step_strain
    the update's max|dF - I| (the axial strain per step of the triaxial path). The mean over
    the packings, which the RVEs are drawn from.
    """
    import yaml
    with open(scene_path) as f:
        co = (yaml.safe_load(f) or {}).get("coupling") or {}
    native = co.get("native") or {}
    rule = native.get("ns_rule")
    if co.get("backend") != "native" or rule not in ("rate", "proportional"):
        fail("%s: coupling.backend %r, coupling.native.ns_rule %r: the analysis needs the "
             "native backend's rate or proportional rule (it reads each RVE's DEM step from "
             "its native packing); run the study with --backend native"
             % (scene_path, co.get("backend"), rule))
    ns_min, ns_max = int(native.get("ns_min", 2)), int(native.get("ns_max", 100))
    times = []
    for name in native.get("packings") or []:
        path = os.path.join(native["packing_dir"], name + ".native.txt")
        dt_dem = None
        with open(path) as f:
            for line in f:
                if line.startswith("dt "):
                    dt_dem = float(line.split()[1])
                    break
        if not dt_dem or dt_dem <= 0:
            fail("%s: no 'dt' line with a DEM step > 0" % path, 1)
        want = dt / dt_dem if rule == "rate" else float(native.get("ns_factor", 1e5)) * step_strain
        times.append(min(max(math.ceil(want), ns_min), ns_max) * dt_dem)
    if not times:
        fail("%s: coupling.native.packings is empty" % scene_path, 1)
    return sum(times) / len(times)


def principal_phi(s):
    """Mohr-Coulomb angle (deg) of a stress, element_test.mobilised_phi's; nan for a zero
    stress (an RVE with no contact: DEM stresses are never tensile), left out of the means."""
    import numpy as np
    from element_test import mobilised_phi
    return float("nan") if np.trace(s) >= 0 else mobilised_phi(s)


def window_figures(csv_path, dt, d, rho_s, t_update=None):
    """The window's figures of one run (see the module's definitions)."""
    import numpy as np
    from element_test import read_csv
    rows = {}
    for r in read_csv(csv_path):
        rows.setdefault(int(r["step"]), []).append(r)
    steps = sorted(rows)
    n = steps[-1]
    first = [k for k in steps if k >= n - FRACTION * n]
    k0, k1 = first[0], n
    comp = ("xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz")

    def mat(r, name):
        return np.array([float(r["%s_%s" % (name, c)]) for c in comp]).reshape(3, 3)

    def mean(k, name):
        return sum(mat(r, name) for r in rows[k]) / len(rows[k])

    phis, ps = [], []
    for k in first:
        s = mean(k, "sigma")
        phis.append(principal_phi(s))
        ps.append(-np.trace(s) / 3.0)
    per_rve = {}
    for k in first:
        for r in rows[k]:
            per_rve.setdefault(r["rve"], []).append(principal_phi(mat(r, "sigma")))
    rve_means = [float(np.nanmean(v)) for v in per_rve.values()]
    de = mean(k1, "eps") - mean(k0, "eps")
    dev = de - np.trace(de) / 3.0 * np.eye(3)
    t = (k1 - k0) * (t_update or dt)
    gamma_dot = math.sqrt(2.0 * float(np.sum(dev * dev))) / t
    p = float(np.mean(ps))
    phi = float(np.nanmean(phis))
    se = float(np.std(rve_means, ddof=1) / math.sqrt(len(rve_means))) \
        if len(rve_means) > 1 else float("nan")
    axial = -float(de[2, 2])
    vol = -float(np.trace(de))   # compression positive
    coord = [r["coordination"] for k in first for r in rows[k] if "coordination" in r]
    return {
        "steps": n, "window_steps": [k0, k1], "dt_s": dt, "dem_time_per_update_s": t_update or dt,
        "phi_deg": phi, "phi_se_deg": se, "sin_phi": math.sin(math.radians(phi)),
        "p_Pa": p, "gamma_dot_per_s": gamma_dot,
        "inertial_number": gamma_dot * d / math.sqrt(p / rho_s),
        "dilatancy": vol / axial if axial else float("nan"),   # d eps_v / d eps_a, window
        "coordination": float(np.mean(coord)) if coord else float("nan"),
        "rves": len(rve_means),
    }


def fit(I, y, i0=None):
    """Least squares of y = a + b I / (i0 + I); i0 from a log grid unless given."""
    import numpy as np
    I, y = np.asarray(I, float), np.asarray(y, float)
    grid = [i0] if i0 is not None else np.logspace(-4, 1, 501)
    best = None
    for c in grid:
        x = I / (c + I)
        A = np.vstack([np.ones_like(x), x]).T
        (a, b), *_ = np.linalg.lstsq(A, y, rcond=None)
        sse = float(np.sum((A @ [a, b] - y) ** 2))
        if best is None or sse < best["sse"]:
            best = {"a": float(a), "b": float(b), "i0": float(c), "sse": sse}
    n = len(y)
    best["rms"] = math.sqrt(best["sse"] / n)
    best["i0_on_grid_edge"] = i0 is None and (best["i0"] <= 1.001e-4 or best["i0"] >= 9.99)
    return best


def mu_of(params, I):
    return params["a"] + params["b"] * I / (params["i0"] + I)


def analyse(folder, runs, d, rho_s, figure):
    res, prop = [], []   # the rate rule's runs (fitted), the proportional rule's (shown)
    for run in runs:
        base = os.path.join(folder, run)
        try:
            with open(os.path.join(base, "plan.json")) as f:
                plan = json.load(f)
        except OSError as e:
            print("rve_mu_i: %s: %s (did this run fail?)" % (base, e), file=sys.stderr)
            continue
        dt = float(plan["dt"])
        t = plan["tests"][0]
        step_strain = 1.0 - (1.0 - float(t["strain"])) ** (1.0 / int(t["steps"]))
        w = window_figures(os.path.join(base, "triaxial.csv"), dt, d, rho_s,
                           dem_time_per_update(os.path.join(base, "scene.yaml"), dt,
                                               step_strain))
        w["run"] = run
        (prop if run == "proportional" else res).append(w)
    if len(res) < 3:
        fail("%d complete runs in %s: the fit needs 3 or more" % (len(res), folder), 1)
    res.sort(key=lambda r: r["inertial_number"])
    I = [r["inertial_number"] for r in res]
    y = [r["sin_phi"] for r in res]
    free, jop = fit(I, y), fit(I, y, JOP_I0)
    for p in (free, jop):
        p["phi_s_deg"] = math.degrees(math.asin(p["a"]))
        p["phi_2_deg"] = math.degrees(math.asin(min(1.0, p["a"] + p["b"])))
    doc = {"grain_diameter_m": d, "grain_density": rho_s, "window_fraction": FRACTION,
           "runs": res, "proportional_runs": prop, "fit": free, "fit_i0_jop": jop,
           "definitions": __doc__.split("Definitions")[1].strip()}
    with open(os.path.join(folder, "mu_i.json"), "w") as f:
        json.dump(doc, f, indent=1)
    lines = ["| run | dt (s) | DEM time / dt | I | shear rate (1/s) | p (Pa) | phi (deg) | ± s.e. | "
             "d eps_v / d eps_a | coordination |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in res + prop:
        lines.append("| %s | %.3g | %.3f | %.3g | %.3g | %.0f | %.2f | %.2f | %+.3f | %.2f |"
                     % (r["run"], r["dt_s"], r["dem_time_per_update_s"] / r["dt_s"],
                        r["inertial_number"], r["gamma_dot_per_s"],
                        r["p_Pa"], r["phi_deg"], r["phi_se_deg"], r["dilatancy"],
                        r["coordination"]))
    lines.append("")
    for name, p in (("I_0 fitted", free), ("I_0 = 0.279 held", jop)):
        lines.append("- fit (%s): phi_s %.2f deg, phi_2 %.2f deg (sin: %.4f + %.4f I / (%.3g + I)),"
                     " rms %.4f in sin phi%s" % (name, p["phi_s_deg"], p["phi_2_deg"], p["a"],
                                                 p["b"], p["i0"], p["rms"],
                                                 ", I_0 at the grid's edge"
                                                 if p["i0_on_grid_edge"] else ""))
    md = "\n".join(lines) + "\n"
    with open(os.path.join(folder, "mu_i.md"), "w") as f:
        f.write(md)
    print(md, end="")
    if figure:
        plot(res, prop, free, jop, figure)
    return 0


def plot(res, prop, free, jop, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    I = np.array([r["inertial_number"] for r in res])
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.errorbar(I, [r["phi_deg"] for r in res], yerr=[r["phi_se_deg"] for r in res],
                fmt="o", color="k", capsize=3, label="RVEs, rate rule, drained triaxial (± s.e.)")
    if prop:
        ax.errorbar([r["inertial_number"] for r in prop], [r["phi_deg"] for r in prop],
                    yerr=[r["phi_se_deg"] for r in prop], fmt="s", color="C3", capsize=3,
                    label="RVEs, proportional rule (the shipped column's; not fitted)")
    x = np.logspace(math.log10(I.min() / 3), math.log10(I.max() * 3), 200)
    for p, style, name in ((free, "-", "fit"), (jop, "--", "fit, I_0 = 0.279")):
        ax.plot(x, np.degrees(np.arcsin(np.clip(mu_of(p, x), -1, 1))), style,
                label="%s: %.1f → %.1f deg, I_0 %.3g" % (name, p["phi_s_deg"], p["phi_2_deg"],
                                                         p["i0"]))
    local = {"a": math.sin(math.radians(20)), "b": math.sin(math.radians(37))
             - math.sin(math.radians(20)), "i0": JOP_I0}
    ax.plot(x, np.degrees(np.arcsin(mu_of(local, x))), ":", color="grey",
            label="local scene column_collapse_mc_mu_i (20 → 37 deg)")
    ax.set_xscale("log")
    ax.set_xlabel("inertial number I")
    ax.set_ylabel("friction angle in the last 20 % (deg)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def self_test():
    # nominal_step inverts the definition of I, with steps of at most MAX_STEP_STRAIN
    # (slow) and updates of at least MIN_DT (fast)
    for i in (1e-4, 1e-2, 0.3):
        dt, n = nominal_step(0.35, i, 5e3, 2.3e-3, 2500.0)
        rate = -math.log(0.65) / (n * dt)
        assert abs(math.sqrt(3) * rate * 2.3e-3 / math.sqrt(2.0) - i) < 1e-12 * i, (i, dt, n)
        assert rate * dt < MAX_STEP_STRAIN * 1.01 or dt < MIN_DT * 1.01, (i, dt, n)
        assert dt > MIN_DT * 0.99, (i, dt)
    assert nominal_step(0.35, 0.3, 5e3, 2.3e-3, 2500.0)[1] < 200
    # the fit recovers a known mu(I), I_0 free and held
    I = [1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3]
    true = {"a": 0.34, "b": 0.26, "i0": 0.05}
    y = [mu_of(true, i) for i in I]
    f = fit(I, y)
    assert abs(f["a"] - 0.34) < 1e-3 and abs(f["b"] - 0.26) < 5e-3, f
    assert abs(math.log(f["i0"] / 0.05)) < 0.03, f
    g = fit(I, y, JOP_I0)
    assert g["i0"] == JOP_I0 and g["rms"] > 1e-3, g   # the wrong I_0 cannot fit exactly
    # the angle of a triaxial stress: s1 = 3, s3 = 1 -> asin(1/2) = 30 deg
    import numpy as np
    assert abs(principal_phi(np.diag([-1.0, -1.0, -3.0])) - 30.0) < 1e-12
    print("rve_mu_i: self-test passed")
    return 0


def option(argv, name, default=None):
    if name in argv:
        i = argv.index(name)
        if i + 1 >= len(argv):
            fail("%s needs a value" % name)
        v = argv[i + 1]
        del argv[i:i + 2]
        return v
    return default


def main(argv):
    argv = list(argv)
    if argv[1:2] == ["--self-test"]:
        return self_test()
    try:
        d = float(option(argv, "--grain-diameter", "nan"))
        rho = float(option(argv, "--grain-density", "nan"))
    except ValueError as e:
        fail(str(e))
    figure = option(argv, "--figure")
    if not (d > 0 and rho > 0):
        fail("give --grain-diameter D > 0 (m) and --grain-density RHO > 0 (kg/m3)")
    if len(argv) == 5 and argv[1] == "config":
        try:
            i = float(argv[3])
        except ValueError:
            fail("inertial number '%s' is not a number" % argv[3])
        print("%.6g %d" % write_config(argv[2], i, argv[4], d, rho))
        return 0
    if len(argv) == 6 and argv[1] == "config-proportional":
        try:
            nsf, nsm = float(argv[3]), int(argv[4])
        except ValueError:
            fail("NS_FACTOR %r / NS_MAX %r: give a number and an integer" % (argv[3], argv[4]))
        if not (nsf > 0 and nsm >= 2):
            fail("NS_FACTOR %r / NS_MAX %r: give NS_FACTOR > 0 and NS_MAX >= 2" % (nsf, nsm))
        print("%.6g %d" % write_config(argv[2], 0.0, argv[5], d, rho, (nsf, nsm)))
        return 0
    if len(argv) >= 4 and argv[1] == "analyse":
        return analyse(argv[2], argv[3:], d, rho, figure)
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))

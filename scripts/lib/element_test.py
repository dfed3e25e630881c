"""Helper of scripts/element_test (run under Debian's /usr/bin/python3: yaml, matplotlib).

  element_test.py plan CONFIG OUT_DIR [BACKEND [PATHS]]
                                          validate CONFIG, write OUT_DIR/scene.yaml (the
                                          config's config_version + coupling: section, with
                                          packing_dir made absolute; BACKEND, default the
                                          config's coupling.backend, replaces it; for native
                                          the coupling.native section is derived from
                                          coupling.yade, see native_section) and print the
                                          plan as shell lines `key value...` (see
                                          scripts/element_test); PATHS (comma-separated)
                                          keeps only those of the config's tests
  element_test.py report OUT_DIR          read OUT_DIR/plan.json and OUT_DIR/<path>.csv, write
                                          OUT_DIR/element_tests.png and OUT_DIR/summary.json

CONFIG keys (documented in configs/element_test/table1_dense.yaml and docs/element_tests.md):
the top level holds config_version, packings (scripts/build_packings' block), coupling (read by dem_app and
element_test, validated by them), element_test; unknown keys are rejected here (exit 2).
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "dem_app",
                                "python"))  # mpmdem_packing: TABLE1 and the packings: reader
EXIT_CONFIG = 2
PATHS = ("isotropic", "triaxial", "constant_volume", "simple_shear")
BACKENDS = ("elastic", "yade", "native")
TOP_KEYS = {"config_version", "packings", "coupling", "element_test"}
# element_test section: key -> (type, default, description)
SECTION_KEYS = {
    "server_ranks": (int, 1, "dem_app MPI ranks"),
    "rves": (int, 1, "RVEs driven along each path (the report uses their mean stress)"),
    "pressure": (float, 1.0e5, "Pa, isotropic initial stress (RveInit) of every RVE"),
    "dt": (float, 1.0e-3, "s, MPM time step written into the requests (under ns_rule rate it sets each update's DEM time)"),
    "timeout_s": (float, 1800.0, "s, longest wall time allowed per path"),
    "build_packings": (bool, True,
                       "build missing packings of coupling.yade.packings with the packings: block"),
    "tests": (list, None, "list of {path, strain, steps}"),
}
TEST_KEYS = {"path", "strain", "steps"}
CS_TAIL = 0.2  # critical state: mean over the last 20 % of the strain


class ConfigFault(Exception):
    pass


def fail(cfg, key, what):
    raise ConfigFault("%s: %s: %s" % (cfg, key, what))


def native_section(path, co):
    """The coupling.native section of a native run: the keys of coupling.yade that the
    native backend shares (all but packing_spec; same meaning, docs/dem_backend.md), with
    packing_dir the YADE library's folder (the <name>.native.txt files are exported next to
    the <name>.yade.bz2 ones by scripts/export_native_packings), overridden key by key by a
    coupling.native section of the config when there is one (its packing_dir relative to the
    working directory, like coupling.yade.packing_dir)."""
    native = {k: v for k, v in (co.get("yade") or {}).items() if k != "packing_spec"}
    own = co.get("native") or {}
    if not isinstance(own, dict):
        fail(path, "coupling.native", "must be a map")
    native.update(own)
    native["packing_dir"] = os.path.abspath(native["packing_dir"]) if native.get("packing_dir") else ""
    return json.loads(json.dumps(native))  # deep copy


def substep_rule(section):
    """(ns_rule, ns) of a backend section as dem_app reads it (schema defaults: proportional,
    ns 10); ns only means something under the fixed rule, else None."""
    rule = section.get("ns_rule", "proportional")
    return rule, (section.get("ns", 10) if rule == "fixed" else None)


def load_config(path, backend=None, paths=None):
    import yaml

    try:
        with open(path) as f:
            doc = yaml.safe_load(f)
    except OSError as e:
        raise ConfigFault("%s: cannot read: %s" % (path, e))
    except yaml.YAMLError as e:
        raise ConfigFault("%s: malformed YAML: %s" % (path, e))
    if not isinstance(doc, dict):
        raise ConfigFault("%s: the top level must be a map of sections" % path)
    for k in doc:
        if k not in TOP_KEYS:
            fail(path, k, "unknown top-level key (known: %s)" % ", ".join(sorted(TOP_KEYS)))
    for k in ("config_version", "coupling", "element_test"):
        if k not in doc:
            fail(path, k, "missing (required)")
    sec = doc["element_test"]
    if not isinstance(sec, dict):
        fail(path, "element_test", "must be a map")
    plan = {}
    for k in sec:
        if k not in SECTION_KEYS:
            fail(path, "element_test.%s" % k,
                 "unknown key (known: %s)" % ", ".join(sorted(SECTION_KEYS)))
    for k, (typ, default, _) in SECTION_KEYS.items():
        v = sec.get(k, default)
        if v is None:
            fail(path, "element_test.%s" % k, "missing (required)")
        plan[k] = coerce(path, "element_test.%s" % k, v, typ)
    for k in ("server_ranks", "rves"):
        if plan[k] < 1:
            fail(path, "element_test.%s" % k, "must be >= 1, got %r" % plan[k])
    for k in ("pressure", "dt", "timeout_s"):
        if not plan[k] > 0:
            fail(path, "element_test.%s" % k, "must be > 0, got %r" % plan[k])
    tests = []
    if not plan["tests"]:
        fail(path, "element_test.tests", "needs at least one {path, strain, steps}")
    for i, t in enumerate(plan["tests"]):
        where = "element_test.tests[%d]" % i
        if not isinstance(t, dict):
            fail(path, where, "must be a map {path, strain, steps}")
        for k in t:
            if k not in TEST_KEYS:
                fail(path, "%s.%s" % (where, k), "unknown key (known: path, strain, steps)")
        for k in TEST_KEYS:
            if k not in t:
                fail(path, "%s.%s" % (where, k), "missing (required)")
        if t["path"] not in PATHS:
            fail(path, where + ".path", "%r is not one of %s" % (t["path"], ", ".join(PATHS)))
        if t["path"] in [x["path"] for x in tests]:
            fail(path, where + ".path", "%r listed twice" % t["path"])
        strain = coerce(path, where + ".strain", t["strain"], float)
        steps = coerce(path, where + ".steps", t["steps"], int)
        if not 0 < strain < (10.0 if t["path"] == "simple_shear" else 1.0):
            fail(path, where + ".strain", "must be in (0, 1) (simple_shear: (0, 10)), got %r" % strain)
        if steps < 2:
            fail(path, where + ".steps", "must be >= 2, got %r" % steps)
        tests.append({"path": t["path"], "strain": strain, "steps": steps})
    if paths:
        unknown = [p for p in paths if p not in [t["path"] for t in tests]]
        if unknown:
            raise ConfigFault("--paths %s: not among the tests of %s (%s)" % (
                ",".join(unknown), path, ", ".join(t["path"] for t in tests)))
        tests = [t for t in tests if t["path"] in paths]
    plan["tests"] = tests
    co = doc["coupling"]
    if not isinstance(co, dict):
        fail(path, "coupling", "must be a map")
    yade = co.get("yade") or {}
    plan["backend"] = backend or co.get("backend", "elastic")
    if plan["backend"] not in BACKENDS:
        fail(path, "coupling.backend", "%r is not one of %s" % (plan["backend"], ", ".join(BACKENDS)))
    plan["packing_dir"] = os.path.abspath(yade["packing_dir"]) if yade.get("packing_dir") else ""
    plan["packings"] = list(yade.get("packings") or [])
    plan["ns_rule"], plan["ns"] = substep_rule(yade)
    plan["native_dir"] = ""
    if plan["backend"] == "native":
        native = native_section(path, co)
        plan["native_dir"] = native["packing_dir"]
        plan["packings"] = list(native.get("packings") or [])
        plan["ns_rule"], plan["ns"] = substep_rule(native)
        plan["native"] = native
    if "porosity" not in (co.get("outputs") or []):
        fail(path, "coupling.outputs", "must list porosity (summary.json reports porosity_initial)")
    if plan["packing_dir"] and "packings" in doc:
        check_packings_block(path, doc["packings"])
    plan["config"] = os.path.abspath(path)
    plan["doc"] = doc
    return plan


def coerce(cfg, key, v, typ):
    try:
        if typ is bool:
            if not isinstance(v, bool):
                raise ValueError
            return v
        if typ is int:
            if isinstance(v, bool) or float(v) != int(float(v)):
                raise ValueError
            return int(float(v))
        if typ is float:
            if isinstance(v, bool):
                raise ValueError
            return float(v)  # YAML 1.1 reads 1.0e5 as a float, 1e5 as a string
        if typ is list:
            if not isinstance(v, list):
                raise ValueError
            return v
    except (TypeError, ValueError):
        pass
    fail(cfg, key, "expected %s, got %r" % (typ.__name__, v))


def check_packings_block(cfg, block):
    from mpmdem_packing import TABLE1  # no YADE import at module level

    if not isinstance(block, dict):
        fail(cfg, "packings", "must be a map (keys of scripts/build_packings)")
    for k in block:
        if k != "items" and k not in TABLE1:
            fail(cfg, "packings.%s" % k, "unknown key (known: items, %s)" % ", ".join(sorted(TABLE1)))
    for i, it in enumerate(block.get("items") or []):
        for k in it:
            if k not in TABLE1 and k not in ("name", "copies"):
                fail(cfg, "packings.items[%d].%s" % (i, k), "unknown key (known: name, copies, %s)"
                     % ", ".join(sorted(TABLE1)))


def stale_packings(cfg_path, plan, doc):
    """Packings in packing_dir built with other parameters than the packings: block says."""
    from mpmdem_packing import _read_config  # the builder's own reading of the block

    wanted = {p["name"]: p for p in _read_config(cfg_path)}
    stale = []
    for name in plan["packings"]:
        js = os.path.join(plan["packing_dir"], name + ".json")
        if name not in wanted or not os.path.exists(js):
            continue
        with open(js) as f:
            built = json.load(f).get("parameters", {})
        diff = ["%s %r (config %r)" % (k, built.get(k), v) for k, v in sorted(wanted[name].items())
                if built.get(k) != v]
        if diff:
            stale.append("%s was built with %s" % (js, ", ".join(diff)))
    return stale


def cmd_plan(cfg_path, out, backend=None, paths=None):
    import yaml

    try:
        plan = load_config(cfg_path, backend, [p for p in (paths or "").split(",") if p])
    except ConfigFault as e:
        print("element_test: config error: %s" % e, file=sys.stderr)
        return EXIT_CONFIG
    os.makedirs(out, exist_ok=True)
    doc = plan.pop("doc")
    coupling = json.loads(json.dumps(doc["coupling"]))  # deep copy
    coupling["backend"] = plan["backend"]
    if plan["packing_dir"]:
        coupling["yade"]["packing_dir"] = plan["packing_dir"]
    if plan["backend"] == "native":
        coupling["native"] = plan.pop("native")
    with open(os.path.join(out, "scene.yaml"), "w") as f:
        f.write("# Written by scripts/element_test from %s (coupling section, packing_dir "
                "absolute, backend %s)\n" % (plan["config"], plan["backend"]))
        yaml.safe_dump({"config_version": doc["config_version"], "coupling": coupling}, f,
                       sort_keys=False)
    has = lambda d, n, ext: os.path.exists(os.path.join(d, n + ext))  # noqa: E731
    missing = [n for n in plan["packings"]
               if plan["packing_dir"] and not has(plan["packing_dir"], n, ".yade.bz2")]
    missing_native = []
    if plan["backend"] == "native" and plan["native_dir"]:
        # exported (again) when absent or older than the YADE packing it comes from
        missing_native = [n for n in plan["packings"] if not has(plan["native_dir"], n, ".native.txt")
                          or (has(plan["packing_dir"], n, ".yade.bz2") and os.path.getmtime(
                              os.path.join(plan["native_dir"], n + ".native.txt")) < os.path.getmtime(
                              os.path.join(plan["packing_dir"], n + ".yade.bz2")))]
        if not plan["packing_dir"] and missing_native:
            print("element_test: config error: %s: coupling.native.packings: %s not in %s and no "
                  "coupling.yade.packing_dir to export them from" % (
                      cfg_path, ", ".join(missing_native), plan["native_dir"]), file=sys.stderr)
            return EXIT_CONFIG
        missing = [n for n in missing if n in missing_native]  # YADE packings needed for export
    if missing and not (plan["build_packings"] and "packings" in doc):
        print("element_test: config error: %s: coupling.yade.packings: %s not in %s (add a "
              "packings: block and element_test.build_packings: true, or run scripts/build_packings)"
              % (cfg_path, ", ".join(missing), plan["packing_dir"]), file=sys.stderr)
        return EXIT_CONFIG
    stale = stale_packings(cfg_path, plan, doc) if "packings" in doc else []
    if stale:
        print("element_test: config error: %s: packings: %s; delete those packings (or use "
              "another coupling.yade.packing_dir) to rebuild them" % (cfg_path, "; ".join(stale)),
              file=sys.stderr)
        return EXIT_CONFIG
    plan["missing_packings"] = missing
    plan["missing_native"] = missing_native
    with open(os.path.join(out, "plan.json"), "w") as f:
        json.dump(plan, f, indent=1)
    for k in ("server_ranks", "rves", "pressure", "dt", "timeout_s", "backend", "packing_dir",
              "native_dir"):
        print(k, plan[k])
    print("missing_packings", " ".join(missing))
    print("missing_native", " ".join(missing_native))
    for t in plan["tests"]:
        print("test", t["path"], repr(t["strain"]), t["steps"])
    return 0


# -- report -----------------------------------------------------------------------------------
def read_csv(path):
    import csv

    with open(path) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def principal(sig):
    import numpy as np

    return np.linalg.eigvalsh(0.5 * (sig + sig.T))


def mobilised_phi(sig):
    """Mohr-Coulomb mobilised friction angle asin((s1 - s3)/(s1 + s3)) of the compressive
    principal stresses s1 >= s3 [deg]; for triaxial compression (s2 = s3) it equals
    asin(3M/(6+M)) with M = q/p."""
    ev = principal(sig)
    s1, s3 = -ev[0], -ev[2]
    if s1 + s3 <= 0:
        return 0.0
    return math.degrees(math.asin(max(-1.0, min(1.0, (s1 - s3) / (s1 + s3)))))


def analyse(rows, test, n_rve, pressure):
    """Per step: RVE-mean stress and strain measures of one path."""
    import numpy as np

    by_step = {}  # one pass: the rows of each step, in file order
    for r in rows:
        by_step.setdefault(int(r["step"]), []).append(r)
    steps = sorted(by_step)
    comps = ("xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz")
    out = []
    for n in steps:
        rs = by_step[n]
        if len(rs) != n_rve:
            raise SystemExit("step %d has %d rows, expected %d RVEs" % (n, len(rs), n_rve))
        sig = np.mean([[r["sigma_" + c] for c in comps] for r in rs], axis=0).reshape(3, 3)
        eps = np.mean([[r["eps_" + c] for c in comps] for r in rs], axis=0).reshape(3, 3)
        p = -np.trace(sig) / 3.0
        s = sig + p * np.eye(3)
        q = math.sqrt(1.5 * float(np.sum(s * s)))
        if test["path"] == "simple_shear":
            x = n * test["strain"] / test["steps"]  # engineering shear strain gamma
        elif test["path"] == "isotropic":
            x = -float(np.trace(eps))
        else:
            x = -float(eps[2, 2])  # axial strain, compression positive
        out.append({
            "step": n, "x": x, "p": p, "q": q, "q_over_p": q / p if p > 0 else 0.0,
            "eps_v": -float(np.trace(eps)),  # Hencky, compression positive
            "phi": mobilised_phi(sig),
            "lateral": -0.5 * float(sig[0, 0] + sig[1, 1]),
            "porosity": float(np.mean([r["porosity"] for r in rs])),
            "coordination": float(np.mean([r["coordination"] for r in rs])),
            "no_contacts": sum(1 for r in rs if int(r["status"]) == 1),  # RveStatus::kNoContacts
            "fatal": sum(1 for r in rs if int(r["status"]) >= 2),  # non-finite, exploding, error
        })
    return out


def summarise(series, test, pressure):
    after = series[1:]
    xs = [s["x"] for s in after]
    tail = [s for s in after if s["x"] >= (1 - CS_TAIL) * xs[-1]] or after[-1:]
    peak = max(after, key=lambda s: s["phi"])
    d = {
        "path": test["path"], "strain_target": test["strain"], "steps": test["steps"],
        "strain_reached": xs[-1],
        "strain_measure": {"simple_shear": "engineering shear strain gamma = F_xz",
                           "isotropic": "volumetric Hencky strain (compression +)"}.get(
                               test["path"], "axial Hencky strain -eps_zz (compression +)"),
        "phi_peak_deg": peak["phi"], "strain_at_peak": peak["x"],
        "phi_cs_deg": sum(s["phi"] for s in tail) / len(tail),
        "q_over_p_peak": max(s["q_over_p"] for s in after),
        "q_over_p_cs": sum(s["q_over_p"] for s in tail) / len(tail),
        "p_initial_Pa": series[0]["p"], "p_final_Pa": series[-1]["p"],
        "q_final_Pa": series[-1]["q"],
        "volumetric_strain_final": series[-1]["eps_v"],
        "porosity_initial": series[0]["porosity"], "porosity_final": series[-1]["porosity"],
        "coordination_initial": series[0]["coordination"],
        "coordination_final": series[-1]["coordination"],
        "no_contact_rows": sum(s["no_contacts"] for s in series),  # zero stress, not fatal
        "fatal_status_rows": sum(s["fatal"] for s in series),
    }
    if test["path"] == "triaxial":
        half = after[len(after) // 2:]
        d["lateral_stress_max_rel_error_2nd_half"] = max(abs(s["lateral"] - pressure) for s in half) / pressure
        d["lateral_stress_mean_Pa_2nd_half"] = sum(s["lateral"] for s in half) / len(half)
    if test["path"] in ("constant_volume", "simple_shear"):
        d["volumetric_strain_max_abs"] = max(abs(s["eps_v"]) for s in series)
    return d


def cmd_report(out):
    with open(os.path.join(out, "plan.json")) as f:
        plan = json.load(f)
    walls, cpus = {}, {}
    if os.path.exists(os.path.join(out, "wall_times.txt")):
        for line in open(os.path.join(out, "wall_times.txt")):
            k, v, *cpu = line.split()  # path wall_s [cpu_s of every process the path started]
            walls[k] = float(v)
            if cpu:
                cpus[k] = float(cpu[0])
    tests, series = {}, {}
    for t in plan["tests"]:
        csv = os.path.join(out, t["path"] + ".csv")
        if not os.path.exists(csv):
            continue
        series[t["path"]] = analyse(read_csv(csv), t, plan["rves"], plan["pressure"])
        tests[t["path"]] = summarise(series[t["path"]], t, plan["pressure"])
        tests[t["path"]]["wall_time_s"] = walls.get(t["path"])
        tests[t["path"]]["cpu_time_s"] = cpus.get(t["path"])
    if not tests:
        raise SystemExit("element_test: no CSV in %s" % out)
    head = tests.get("triaxial") or next(iter(tests.values()))
    summary = {
        "phi_peak_deg": head["phi_peak_deg"], "phi_cs_deg": head["phi_cs_deg"],
        "porosity_initial": head["porosity_initial"], "wall_time_s": walls.get("total"),
        "cpu_time_s": cpus.get("total"),
        "headline_from": head["path"],
        "definitions": {
            "phi": "Mohr-Coulomb mobilised angle asin((s1-s3)/(s1+s3)) of the RVE-mean "
                   "stress (compressive principal stresses)",
            "phi_cs_deg": "mean over the last %d %% of the strain reached" % round(100 * CS_TAIL),
            "porosity_initial": "porosity after initialise (coupling.outputs: porosity; YADE: "
                                "utils.porosity(), native: the same formula)",
            "cpu_time_s": "user + system CPU time of every process started (ompi-server, "
                          "dem_app, element_test and their mpirun)",
        },
        "config": plan["config"], "backend": plan["backend"], "packings": plan["packings"],
        "pressure_Pa": plan["pressure"], "rves": plan["rves"],
        "server_ranks": plan["server_ranks"], "ns_rule": plan["ns_rule"], "ns": plan["ns"],
        "tests": tests,
    }
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    plot(series, tests, os.path.join(out, "element_tests.png"), plan)
    for name, t in tests.items():
        print("element_test: %-16s strain %.4g  phi_peak %.2f deg  phi_cs %.2f deg  porosity0 %.4f"
              "  eps_v %.4g  wall %s s  cpu %s s" % (
                  name, t["strain_reached"], t["phi_peak_deg"], t["phi_cs_deg"],
                  t["porosity_initial"], t["volumetric_strain_final"], t["wall_time_s"],
                  t["cpu_time_s"]))
    print("element_test: wrote %s/summary.json, element_tests.png" % out)
    return 0


def plot(series, tests, png, plan):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(series)
    fig, ax = plt.subplots(3, len(names), figsize=(3.6 * len(names), 8), squeeze=False)
    for j, name in enumerate(names):
        s = series[name]
        x = [r["x"] for r in s]
        ax[0][j].plot(x, [r["q_over_p"] for r in s])
        ax[0][j].set_title(name)
        ax[0][j].set_ylabel("q/p")
        ax[1][j].plot(x, [r["eps_v"] for r in s])
        ax[1][j].set_ylabel("volumetric strain (compression +)")
        ax[2][j].plot(x, [r["p"] / 1e3 for r in s], label="p")
        ax[2][j].plot(x, [r["q"] / 1e3 for r in s], label="q")
        ax[2][j].set_ylabel("kPa")
        ax[2][j].legend()
        ax[2][j].set_xlabel({"simple_shear": "shear strain gamma",
                             "isotropic": "volumetric strain"}.get(name, "axial strain"))
    fig.suptitle("%s, backend %s, %s, %d RVE(s), p0 = %.3g Pa" % (
        os.path.basename(plan["config"]), plan["backend"], ",".join(plan["packings"]) or "inline",
        plan["rves"], plan["pressure"]))
    fig.tight_layout()
    fig.savefig(png, dpi=90)


def main(argv):
    if 3 <= len(argv) <= 5 and argv[0] == "plan":
        return cmd_plan(*argv[1:])
    if len(argv) == 2 and argv[0] == "report":
        return cmd_report(argv[1])
    print(__doc__, file=sys.stderr)
    return EXIT_CONFIG


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

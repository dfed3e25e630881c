"""scripts/element_seed_study's two steps (run under Debian's /usr/bin/python3):

  element_seeds.py config CONFIG SEED OUT   CONFIG with its packing rebuilt from SEED
  element_seeds.py summary DIR SEED...      DIR/seed_<S>/compare.json -> DIR/seeds.{md,json}
  element_seeds.py --self-test              checks the statistics on known numbers

`config`: the packing of coupling.yade.packings[0] is <item>_s<seed> for one item of the
`packings:` block; the new config keeps that item (protocol and parameters) with the new seed,
and names it in coupling.yade.packings (and coupling.native.packings, if present).
"""
import json
import math
import os
import sys

import yaml


def fail(msg):
    print("element_seed_study: " + msg, file=sys.stderr)
    sys.exit(2)


def seeded_config(path, seed):
    with open(path) as f:
        cfg = yaml.safe_load(f)
    block = cfg.get("packings") or {}
    packing = ((cfg.get("coupling") or {}).get("yade") or {}).get("packings") or []
    if not packing:
        fail("%s: coupling.yade.packings is empty: no packing to reseed" % path)
    name = packing[0]
    item = next((i for i in block.get("items", [])
                 if name == "%s_s%s" % (i.get("name"), i.get("seed", block.get("seed", 1)))),
                None)
    if item is None:
        fail("%s: no item of packings.items builds coupling.yade.packings[0] = '%s' "
             "(name_s<seed>)" % (path, name))
    new = dict(item, seed=seed)
    new.pop("copies", None)
    block["items"] = [new]
    cfg["packings"] = block
    new_name = "%s_s%d" % (item["name"], seed)
    cfg["coupling"]["yade"]["packings"] = [new_name]
    if "packings" in (cfg["coupling"].get("native") or {}):
        cfg["coupling"]["native"]["packings"] = [new_name]
    return cfg


def stats(values):
    """Mean and standard error of the mean (0 for one value)."""
    n = len(values)
    mean = sum(values) / n
    if n < 2:
        return mean, 0.0
    var = sum((v - mean) ** 2 for v in values) / (n - 1)
    return mean, math.sqrt(var / n)


def summary(folder, seeds):
    runs = {}
    for s in seeds:
        path = os.path.join(folder, "seed_%s" % s, "compare.json")
        if not os.path.exists(path):
            print("element_seed_study: %s missing (did seed %s fail?)" % (path, s),
                  file=sys.stderr)
            continue
        with open(path) as f:
            runs[s] = json.load(f)
    if not runs:
        print("element_seed_study: no seed completed", file=sys.stderr)
        return 1
    first = next(iter(runs.values()))
    a, b = first["backends"]
    doc = {"backends": [a, b], "difference": "%s - %s" % (b, a), "seeds": list(runs),
           "criterion_deg": first["criterion_deg"], "paths": {}}
    lines = ["Packings %s; difference = %s - %s; mean ± standard error over %d packings\n"
             % (", ".join(r["packings"][0] for r in runs.values()), b, a, len(runs)), "",
             "| path | angle | per packing: %s / %s (difference) | mean %s | mean %s | "
             "mean difference | std. error |" % (a, b, a, b), "|---|---|---|---|---|---|---|"]
    for p in first["tests"]:
        doc["paths"][p] = {}
        for k, label in (("phi_peak_deg", "phi_peak"), ("phi_cs_deg", "phi_cs")):
            rows = [r["tests"][p][k] for r in runs.values() if p in r["tests"]]
            d_mean, d_se = stats([x["difference"] for x in rows])
            a_mean, _ = stats([x[a] for x in rows])
            b_mean, _ = stats([x[b] for x in rows])
            doc["paths"][p][k] = {"per_seed": rows, "mean_" + a: a_mean, "mean_" + b: b_mean,
                                  "mean_difference": d_mean, "standard_error": d_se}
            per = "; ".join("%.2f / %.2f (%+.2f)" % (x[a], x[b], x["difference"]) for x in rows)
            lines.append("| %s | %s | %s | %.2f | %.2f | %+.2f | %.2f |"
                         % (p, label, per, a_mean, b_mean, d_mean, d_se))
    with open(os.path.join(folder, "seeds.json"), "w") as f:
        json.dump(doc, f, indent=1)
    md = "\n".join(lines) + "\n"
    with open(os.path.join(folder, "seeds.md"), "w") as f:
        f.write(md)
    print(md, end="")
    return 0


def self_test():
    m, se = stats([1.0, 2.0, 3.0, 4.0])
    assert abs(m - 2.5) < 1e-15 and abs(se - math.sqrt(5.0 / 12.0)) < 1e-12
    m, se = stats([-0.5])
    assert m == -0.5 and se == 0.0
    print("element_seeds: self-test passed")
    return 0


def main(argv):
    if argv[1:2] == ["--self-test"]:
        return self_test()
    if len(argv) == 5 and argv[1] == "config":
        try:
            seed = int(argv[3])
        except ValueError:
            fail("seed '%s' is not an integer" % argv[3])
        cfg = seeded_config(argv[2], seed)  # exits 2 before anything is written
        with open(argv[4], "w") as f:
            yaml.safe_dump(cfg, f, sort_keys=False)
        return 0
    if len(argv) >= 4 and argv[1] == "summary":
        return summary(argv[2], argv[3:])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))

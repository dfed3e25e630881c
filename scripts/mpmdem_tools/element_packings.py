"""The `packings:` block scripts/element_test hands scripts/build_packings: the config's block
with only the items (one per seed) whose packings are missing.

Usage: python3 -m mpmdem_tools.element_packings CONFIG "NAME_sSEED ..."  (YAML on stdout)
"""
import sys

import yaml


def missing_block(config, names):
    doc = yaml.safe_load(open(config))
    want = set(names.split())
    block = dict(doc["packings"])
    items = []
    for it in block.pop("items", None) or [{"name": "table1"}]:
        seed = int(it.get("seed", block.get("seed", 1)))
        for c in range(int(it.get("copies", 1))):
            if "%s_s%d" % (it.get("name", "packing"), seed + c) in want:
                items.append(dict(it, seed=seed + c, copies=1))
    block["items"] = items
    return {"packings": block}


def main(argv):
    yaml.safe_dump(missing_block(argv[0], argv[1]), sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

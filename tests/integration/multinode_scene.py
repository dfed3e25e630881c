#!/usr/bin/python3
"""Scenes of the multi-node tests (tests/integration/multinode*.sh), derived from the
checked-in ones so that they follow them:

  multinode_scene.py column SRC DST SERVICE   the default 3D column (configs/
      column_collapse_3d.yaml) made cheap to start on 2 cores: in-place 100-sphere native
      packings (no YADE library to build) and no geostatic consolidation (initial_stress
      none: the RVEs start as packed, the column settles from there); the load balance on
      at every 4th step (threshold 0.01), so RVEs migrate between the DEM jobs
  multinode_scene.py elastic SRC DST SERVICE  the elastic column (configs/
      elastic_column_remote.yaml), 0.1 s, a checkpoint every 100 steps, peer_timeout_s 3
"""
import sys

import yaml


def main(kind, src, dst, service):
    s = yaml.safe_load(open(src))
    c = s["coupling"]
    c["service_name"] = service
    if kind == "column":
        s["regions"][0]["initial_stress"] = "none"
        n = c["native"]
        for k in ("packing_dir", "packing_spec", "packings"):
            n.pop(k)
        n["inline_spheres"] = 100
        c["load_balance"] = {"threshold": 0.01, "min_interval_steps": 4}
    elif kind == "elastic":
        s["solver"]["end_time"] = 0.1
        c["peer_timeout_s"] = 3
        s["output"]["checkpoint_interval_steps"] = 100
        s["output"]["checkpoints_kept"] = 3
    else:
        sys.exit("multinode_scene.py: unknown kind " + kind)
    yaml.safe_dump(s, open(dst, "w"), sort_keys=False)


if __name__ == "__main__":
    main(*sys.argv[1:5])

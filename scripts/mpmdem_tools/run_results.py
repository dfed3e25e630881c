"""The headline figures scripts/run prints at the end of a run, from its summary.json.

Usage: python3 -m mpmdem_tools.run_results RUN_DIR/summary.json
"""
import sys

from .summary import read_summary

KEYS = ["status", "error", "model", "steps", "n_material_points", "time_s", "wall_time_s",
        "ns_per_point_step", "E_d_over_E_p0"]


def main(argv):
    s = read_summary(argv[0])
    for k in KEYS:
        if k in s:
            print(f"  {k:24s} {s[k]}")
    for k, v in (s.get("verification") or {}).items():
        print(f"  {'verification.' + k:24s} {v}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

"""mpmdem: one command line for the project's scripts.

Usage: scripts/mpmdem SUBCOMMAND [ARGS...]   (or, from scripts/, python3 -m mpmdem_tools ...)
  run [ARGS]               a scene (scripts/run: set-up, build, the pair, clean-up)
  packings [ARGS]          build RVE packings (scripts/build_packings)
  export-packings [ARGS]   YADE packings to the native format (scripts/export_native_packings)
  element-test [ARGS]      element tests on DEM RVEs (scripts/element_test)
  bench mpm|dem [ARGS]     scripts/bench_mpm, scripts/bench_dem
  study NAME [ARGS]        a study (NAME from `study --list`); ARGS as the study script's
  test [ARGS]              the whole suite (scripts/test)
Each subcommand takes the arguments of the script it names (its --help says them); the
exit code is that script's.
"""
import os
import sys

from . import SCRIPTS_DIR

SCRIPTS = {"run": "run", "packings": "build_packings", "export-packings": "export_native_packings",
           "element-test": "element_test", "test": "test"}
BENCHES = {"mpm": "bench_mpm", "dem": "bench_dem"}
# study NAME -> its script in scripts/ (each runs through the sweep runner, or is its own
# analysis or suite)
STUDIES = {
    "grid_convergence": "grid_convergence_study",
    "transfer_dt": "transfer_dt_study",
    "aspect_ratio": "aspect_ratio_study",
    "at_rest": "at_rest_study",
    "runout_vs_dissipation": "runout_vs_dissipation",
    "bspline_wall_quadrature": "bspline_wall_quadrature",
    "verify_elastic": "verify_elastic",
    "error_vs_runtime": "error_vs_runtime",
    "scaling": "scaling_study",
    "cost_model": "cost_model",
    "element_seed": "element_seed_study",
    "rve_mu_i": "rve_mu_i_study",
    "stability": "stability_suite",
}


def usage(code):
    try:
        print(__doc__.strip(), file=sys.stderr if code else sys.stdout)
    except BrokenPipeError:  # e.g. --help | head
        pass
    return code


def run_script(name, args):
    """Replaces this process with scripts/NAME ARGS (its exit code, signals and output)."""
    path = str(SCRIPTS_DIR / name)
    os.execv(path, [path, *args])


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        return usage(0 if argv else 2)
    cmd, rest = argv[0], argv[1:]
    if cmd in SCRIPTS:
        return run_script(SCRIPTS[cmd], rest)
    if cmd == "bench":
        if not rest or rest[0] not in BENCHES:
            print("mpmdem: bench needs mpm or dem", file=sys.stderr)
            return 2
        return run_script(BENCHES[rest[0]], rest[1:])
    if cmd == "study":
        if rest[:1] == ["--list"]:
            for name, script in STUDIES.items():
                print(f"{name:24s} scripts/{script}")
            return 0
        if not rest or rest[0] not in STUDIES:
            print(f"mpmdem: study needs a NAME, one of: {', '.join(STUDIES)}", file=sys.stderr)
            return 2
        return run_script(STUDIES[rest[0]], rest[1:])
    print(f"mpmdem: unknown subcommand '{cmd}'", file=sys.stderr)
    return usage(2)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

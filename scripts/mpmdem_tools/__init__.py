"""mpmdem_tools: the project's one Python tool.

Everything the scripts in scripts/ do in Python lives here, one concept per module:

  summary      read a run's summary.json (typed access; a missing file or key is named)
  launch       find the built programs (mpm_app, dem_app, element_test) and launch a run
               (scripts/run): the one way to do either
  convergence  Richardson extrapolation, observed order, grid convergence index (GCI)
  sweep        the one sweep runner: a study is a declarative spec (base scene, variants as
               overrides, metrics, report)
  entry        the thin entries' shared command-line handling (--help from the header)
  studies/     the studies (each a spec for the sweep runner, or its own analysis)
  bench_mpm, bench_dem_report, element_packings, run_results: the rest of the scripts' Python

Command line: `/usr/bin/python3 -m mpmdem_tools SUBCOMMAND` from scripts/ (or scripts/mpmdem
SUBCOMMAND): run, packings, element-test, bench mpm|dem, study NAME (see --help).
The scripts keep their names, arguments and outputs; each is a thin entry into this package.
"""
from pathlib import Path

SCRIPTS_DIR = Path(__file__).resolve().parent.parent
ROOT = SCRIPTS_DIR.parent
LIB_DIR = SCRIPTS_DIR / "lib"

# The modules of scripts/lib (column_study, scene_overrides, ...) import by their plain names.
import sys as _sys

if str(LIB_DIR) not in _sys.path:
    _sys.path.append(str(LIB_DIR))

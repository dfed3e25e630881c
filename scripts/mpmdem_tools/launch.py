"""The one way to find the built programs and to launch a run.

  mpm_app()             $MPM_APP, else scripts/build (quiet) then BUILD/mpm_app/mpm_app
  build_dir()           $MPMDEM_BUILD_DIR, else build/ of the checkout
  built(name, ...)      BUILD/<dir>/<name> that must exist (dem_app, element_test, ...)
  run(args)             scripts/run with those arguments (set-up, build, the pair, clean-up)

Shell entries use the command line: `python3 -m mpmdem_tools.launch mpm-app` prints the
path (building first unless $MPM_APP is set) and exits with scripts/build's code on failure.
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from . import ROOT

PROGRAMS = {"mpm_app": "mpm_app", "dem_app": "dem_app", "element_test": "dem_app",
            "native_replay": "dem_app"}


class LaunchError(RuntimeError):
    """A program is not built or the build failed; the message says what to run."""

    def __init__(self, message: str, code: int = 1):
        super().__init__(message)
        self.code = code


def build_dir(env_var: str = "MPMDEM_BUILD_DIR") -> Path:
    """The build folder: $MPMDEM_BUILD_DIR (or the given variable), else build/."""
    return Path(os.environ.get(env_var) or ROOT / "build")


def build() -> None:
    """scripts/build with its output discarded (errors still on stderr); LaunchError with
    its exit code if it fails."""
    rc = subprocess.run([str(ROOT / "scripts" / "build")], stdout=subprocess.DEVNULL).returncode
    if rc != 0:
        raise LaunchError(f"scripts/build failed (exit {rc})", rc)


def built(name: str, folder: Path | None = None) -> Path:
    """BUILD/<app dir>/<name>; LaunchError naming it when it is not there."""
    exe = (folder or build_dir()) / PROGRAMS.get(name, name) / name
    if not os.access(exe, os.X_OK):
        raise LaunchError(f"{exe} not built (run scripts/build or set MPMDEM_BUILD_DIR)", 2)
    return exe


def mpm_app() -> str:
    """$MPM_APP if set (no build); else builds (quietly) and returns BUILD/mpm_app/mpm_app, as
    the study scripts always did."""
    if os.environ.get("MPM_APP"):
        return os.environ["MPM_APP"]
    build()
    return str(build_dir() / "mpm_app" / "mpm_app")


def run(args: list[str], **kw) -> int:
    """scripts/run ARGS (the one way to launch a run); returns its exit code."""
    return subprocess.run([str(ROOT / "scripts" / "run"), *args], **kw).returncode


def main(argv: list[str]) -> int:
    if argv[:1] == ["mpm-app"] and len(argv) == 1:
        try:
            print(mpm_app())
        except LaunchError as e:
            return e.code
        return 0
    print("usage: python3 -m mpmdem_tools.launch mpm-app", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

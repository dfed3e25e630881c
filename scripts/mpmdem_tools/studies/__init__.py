"""The studies: each module has main(argv, script) called by its thin entry in scripts/."""
import os
import time

from .. import ROOT


def default_out(study: str) -> str:
    """runs/<study>-<UTC yyyymmdd-HHMMSS> under the checkout (the scripts' default --out)."""
    return os.path.join(str(ROOT), "runs", f"{study}-{time.strftime('%Y%m%d-%H%M%S', time.gmtime())}")


def prepare(study: str, o: dict, subdir: str = "", scene_option: bool = True):
    """The set-up every study entry does before its runs, in this order: the scene file of
    --scene exists (else exit 2 naming it), OUT is --out or default_out(study), mpm_app is found
    or built (launch.mpm_app: its LaunchError reaches the caller, which returns its .code),
    and OUT[/subdir] exists. Returns (app, scene, out); scene is None without scene_option."""
    from .. import launch
    from ..entry import fail

    scene = o["scene"] if scene_option else None
    if scene is not None and not os.path.isfile(scene):
        fail(study, f"no scene file '{scene}'")
    out = o["out"] or default_out(study)
    app = launch.mpm_app()
    os.makedirs(os.path.join(out, subdir) if subdir else out, exist_ok=True)
    return app, scene, out

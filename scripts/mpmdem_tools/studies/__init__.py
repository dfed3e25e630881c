"""The studies: each module has main(argv, script) called by its thin entry in scripts/."""
import os
import time

from .. import ROOT


def default_out(study: str) -> str:
    """runs/<study>-<UTC yyyymmdd-HHMMSS> under the checkout (the scripts' default --out)."""
    return os.path.join(str(ROOT), "runs", f"{study}-{time.strftime('%Y%m%d-%H%M%S', time.gmtime())}")

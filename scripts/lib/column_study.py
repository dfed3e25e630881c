"""Shared by the column studies (scripts/transfer_dt_study, aspect_ratio_study,
grid_convergence_study): run one generated scene with mpm_app on one thread and collect its
figures."""
import csv
import os
import subprocess
import sys
import time
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # scripts/: mpmdem_tools
from mpmdem_tools.convergence import richardson  # noqa: E402,F401  (the one copy, re-exported)
from mpmdem_tools.summary import read_summary  # noqa: E402


# The solver keys that set the PIC/FLIP blend's share; a scene sets at most one of them.
BLEND_KEYS = ("flip", "flip_time_scale", "flip_velocity_scale")


def set_solver(cfg, keys):
    """Applies the solver keys `keys` to the scene `cfg`. When they set a blend of their own
    (one of BLEND_KEYS) or a transfer other than pic_flip, the scene's blend key is removed
    first, so that the scene's and the study's blend keys never meet."""
    if any(k in keys for k in BLEND_KEYS) or keys.get("transfer", "pic_flip") != "pic_flip":
        for k in BLEND_KEYS:
            cfg["solver"].pop(k, None)
    cfg["solver"].update(keys)


def run_column(app, cfg, out, name, study):
    """Writes cfg to OUT/NAME.yaml, runs it into OUT/NAME and returns summary.json as a dict
    with more keys: Eerr_over_released (the energy budget's residual E_err as a share of the
    potential energy released; energies.csv's last row), Etransfer_over_released (the part
    of E_err the particle-grid transfers removed, W_transfer), Etransfer_walls_over_released
    (the part of that at the walls, W_transfer_walls; NaN for logs without it),
    Eother_over_released (the rest: time integration) and run_s (wall time of the process).
    On failure exits naming the run."""
    path = os.path.join(out, name + ".yaml")
    with open(path, "w") as f:
        yaml.safe_dump(cfg, f, sort_keys=False)
    run = os.path.join(out, name)
    t0 = time.time()
    r = subprocess.run([app, path, "--out", run, "--force", "--threads", "1"],
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit(f"{study}: {name} failed (exit {r.returncode}):\n{r.stderr[-2000:]}")
    s = read_summary(run)
    with open(os.path.join(run, "energies.csv")) as f:
        last = list(csv.DictReader(f))[-1]
    released = float(last["E_p0"]) - float(last["E_p"])
    share = (lambda W: W / released) if released > 0 else (lambda W: float("nan"))
    s["Eerr_over_released"] = share(float(last["E_err"]))
    s["Etransfer_over_released"] = share(float(last["W_transfer"]))
    s["Etransfer_walls_over_released"] = share(float(last.get("W_transfer_walls", "nan")))
    s["Eother_over_released"] = share(float(last["E_err"]) - float(last["W_transfer"]))
    s["run_s"] = time.time() - t0
    return s


def drucker_prager(cfg):
    """The scene `cfg`'s (a loaded YAML dict) constitutive.drucker_prager block, {} if none."""
    return (cfg.get("constitutive") or {}).get("drucker_prager") or {}


def has_mu_i(cfg):
    """True when the scene `cfg` gives its Drucker-Prager law the mu(I) rheology
    (constitutive.drucker_prager.mu_i)."""
    return bool(drucker_prager(cfg).get("mu_i"))


def linear_fit(x, y):
    """Least-squares line y = a + b x through the points; returns (a, b, R^2). Needs at least two
    distinct x; R^2 is 1 where y does not vary."""
    n = len(x)
    if n != len(y) or n < 2:
        raise ValueError(f"linear_fit: need two or more (x, y) pairs, got {n} and {len(y)}")
    mx, my = sum(x) / n, sum(y) / n
    sxx = sum((xi - mx) ** 2 for xi in x)
    if sxx == 0.0:
        raise ValueError("linear_fit: all x are equal")
    b = sum((xi - mx) * (yi - my) for xi, yi in zip(x, y)) / sxx
    a = my - b * mx
    syy = sum((yi - my) ** 2 for yi in y)
    sres = sum((yi - a - b * xi) ** 2 for xi, yi in zip(x, y))
    return a, b, (1.0 - sres / syy) if syy > 0.0 else 1.0

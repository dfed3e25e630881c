"""Convergence under refinement: observed order, Richardson extrapolation, GCI (the one copy).

For a figure f computed on grids refined by a constant ratio r (f1 finest, f2, f3 coarser):
  observed order   p     = ln|(f3 - f2)/(f2 - f1)| / ln r
  extrapolated     f_ext = f1 + (f1 - f2)/(r^p - 1)
  GCI (fine grid)  1.25 |(f1 - f2)/f1| / (r^p - 1)        (Roache 1994, safety factor 1.25)
and, from two errors against a known answer, p = ln(e_coarse / e_fine) / ln r.
"""
from __future__ import annotations

import math


def observed_order_from_errors(e_coarse: float, e_fine: float, ratio: float = 2.0) -> float:
    """Order p of an error e ~ h^p from its values on two grids refined by `ratio`."""
    return math.log(e_coarse / e_fine, ratio)


def observed_order(f: list[float], ratio: float = 2.0) -> float:
    """Order p from three values f = [coarse, medium, fine] (no known answer needed)."""
    f3, f2, f1 = f
    return math.log(abs((f3 - f2) / (f2 - f1))) / math.log(ratio)


def extrapolate(f_medium: float, f_fine: float, p: float, ratio: float = 2.0) -> float:
    """Richardson's extrapolated value of order p from the two finest values."""
    return f_fine + (f_fine - f_medium) / (ratio ** p - 1.0)


def gci(f_medium: float, f_fine: float, p: float, ratio: float = 2.0,
        safety: float = 1.25) -> float:
    """Roache's grid convergence index of the fine grid, a fraction of f_fine."""
    return safety * abs((f_medium - f_fine) / f_fine) / (ratio ** p - 1.0)


def richardson(f, ratio=2.0, safety=1.25):
    """Richardson analysis of a figure on three grids refined by `ratio`, f = [coarse, medium,
    fine]. Returns a dict: kind "converging" with p (observed order), extrapolated and gci
    (Roache's grid convergence index of the fine grid, a fraction); "oscillatory" when the two
    differences differ in sign; "slow" (with p) when p < 0.5 (diverging or not asymptotic);
    "exact" when the fine and medium values are equal."""
    f3, f2, f1 = f
    e21, e32 = f2 - f1, f3 - f2
    if e21 == 0.0:
        return {"kind": "exact"}
    if e21 * e32 < 0:
        return {"kind": "oscillatory"}
    p = math.log(abs(e32 / e21)) / math.log(ratio)
    if p < 0.5:
        return {"kind": "slow", "p": p}
    d = ratio ** p - 1.0
    return {"kind": "converging", "p": p, "extrapolated": f1 + (f1 - f2) / d,
            "gci": safety * abs(e21 / f1) / d}


def richardson_text(f, ratio=2.0):
    """richardson() as three table cells: order, extrapolated value, GCI."""
    r = richardson(f, ratio)
    if r["kind"] == "exact":
        return "exact", f"{f[-1]:.3f}", "0"
    if r["kind"] == "oscillatory":
        return "oscillatory", "-", "-"
    if r["kind"] == "slow":
        return f"{r['p']:.2f} (p < 0.5)", "-", "-"
    return f"{r['p']:.2f}", f"{r['extrapolated']:.3f}", f"{100 * r['gci']:.1f} %"

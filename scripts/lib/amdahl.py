"""Amdahl's law fitted to strong-scaling times (issue 5; the paper's Eq. 4).

T(N) = T1 * (s + p / N) with s + p = 1: the time per step on N ranks of a fixed workload.
The fit is linear least squares of T against 1/N (T = a + b / N), so s = a / (a + b),
p = b / (a + b), and the speedup T(1)/T(N) = 1 / (s + p / N). With two rank counts the fit
is exact (two parameters, two points); say so when reporting it.
"""
from __future__ import annotations

import math
from typing import Sequence


def fit(ranks: Sequence[float], times: Sequence[float]) -> dict:
    """Fit T(N) = a + b/N. Returns a, b, s, p, the fitted T1 = a + b and rms relative residual."""
    if len(ranks) != len(times) or len(ranks) < 2:
        raise ValueError("need at least two (ranks, time) points to fit Amdahl's law")
    if len(set(ranks)) < 2:
        raise ValueError("need at least two different rank counts to fit Amdahl's law")
    if any(n <= 0 for n in ranks) or any(not (t > 0 and math.isfinite(t)) for t in times):
        raise ValueError("ranks and times must be positive and finite")
    x = [1.0 / n for n in ranks]
    m = len(x)
    mx, my = sum(x) / m, sum(times) / m
    sxx = sum((xi - mx) ** 2 for xi in x)
    sxy = sum((xi - mx) * (yi - my) for xi, yi in zip(x, times))
    b = sxy / sxx
    a = my - b * mx
    t1 = a + b
    resid = [((a + b * xi) - yi) / yi for xi, yi in zip(x, times)]
    rms = math.sqrt(sum(r * r for r in resid) / m)
    return {"a": a, "b": b, "s": a / t1, "p": b / t1, "T1": t1, "rms_rel_residual": rms,
            "exact": m == 2}


def speedup(s: float, p: float, n: float) -> float:
    """Amdahl's speedup 1 / (s + p/N) (relative to N = 1)."""
    return 1.0 / (s + p / n)


def _self_test() -> None:
    # A synthetic workload with a known serial fraction must be recovered exactly.
    s_true, t1 = 0.02, 18.26
    ranks = [1, 2, 4, 8, 16, 64, 128]
    times = [t1 * (s_true + (1 - s_true) / n) for n in ranks]
    f = fit(ranks, times)
    assert abs(f["s"] - s_true) < 1e-12 and abs(f["p"] - (1 - s_true)) < 1e-12, f
    assert abs(f["T1"] - t1) < 1e-9 and f["rms_rel_residual"] < 1e-12, f
    assert abs(speedup(f["s"], f["p"], 128) - 1 / (0.02 + 0.98 / 128)) < 1e-9
    # Perfectly parallel: s = 0; the speedup is N.
    f = fit([1, 2, 4], [8.0, 4.0, 2.0])
    assert abs(f["s"]) < 1e-12 and abs(speedup(f["s"], f["p"], 4) - 4) < 1e-12, f
    for bad in (([1], [1.0]), ([2, 2], [1.0, 1.0]), ([1, 2], [1.0, float("nan")])):
        try:
            fit(*bad)
        except ValueError:
            continue
        raise AssertionError(f"fit accepted {bad}")
    print("amdahl self-test: ok")


if __name__ == "__main__":
    _self_test()

"""How well an n-rank run's partition divides the DEM work, apart from how fast each core ran
(issue 5, item 6; scripts/scaling_study --rve-costs).

Inputs are the files output.rve_costs writes (mpm_app/src/output/rve_cost_log.hpp):
rve_costs.csv (step, then each material point's RVE backend time in us) and rve_ranks.csv
(step, then each point's server rank from that step on). Results are bitwise the same on
any rank count, so the work of every RVE in every step is the same in all runs of a scene;
its cost is taken from one reference run (the 1-rank run of the same time-sliced
repetition). With W[t][q] = the reference costs of the points rank q ran in step t:

    partition efficiency = sum_t sum_q W[t][q] / (n * sum_t max_q W[t][q])

1 when every step's work is split evenly. The measured DEM efficiency divided by it is what
the cores themselves lost: run-queue waits, shared caches, and a VM whose cores change
speed from one step to the next. The last shows in speed_spread: per step, each rank's
median over its RVEs of cost(this run) / cost(reference run), the slowest rank's over the
fastest's (1: the ranks ran equally fast in that step).
"""
from __future__ import annotations

import csv
import statistics
from pathlib import Path
from typing import Iterable


def read_costs(run_dir: Path) -> dict[int, list[float]]:
    """step -> cost of each point [s]."""
    with (run_dir / "rve_costs.csv").open() as f:
        r = csv.reader(f)
        next(r)
        return {int(row[0]): [float(c) * 1e-6 for c in row[1:]] for row in r}


def read_ranks(run_dir: Path) -> list[tuple[int, list[int]]]:
    """(first step, rank of each point), in step order."""
    with (run_dir / "rve_ranks.csv").open() as f:
        r = csv.reader(f)
        next(r)
        return [(int(row[0]), [int(q) for q in row[1:]]) for row in r]


def owners(ranks: list[tuple[int, list[int]]], t: int) -> list[int]:
    """Each point's rank in step t: the last rank map written at or before t."""
    owner = None
    for first, r in ranks:
        if first <= t:
            owner = r
    if owner is None:
        raise ValueError(f"no rank map for step {t}")
    return owner


def efficiency(ref_costs: dict[int, list[float]], ranks: list[tuple[int, list[int]]],
               n_ranks: int, steps: Iterable[int]) -> float:
    """Partition efficiency over `steps` (each in ref_costs and covered by `ranks`)."""
    total = busiest = 0.0
    for t in sorted(steps):
        owner = owners(ranks, t)
        c = ref_costs[t]
        if len(c) != len(owner):
            raise ValueError(f"step {t}: {len(c)} costs but {len(owner)} ranks")
        w = [0.0] * n_ranks
        for cost, q in zip(c, owner):
            w[q] += cost
        total += sum(w)
        busiest += max(w)
    if busiest <= 0:
        raise ValueError("no work in the steps given")
    return total / (n_ranks * busiest)


def speed_spread(ref_costs: dict[int, list[float]], costs: dict[int, list[float]],
                 ranks: list[tuple[int, list[int]]], n_ranks: int,
                 steps: Iterable[int]) -> list[float]:
    """Per step: the slowest rank's median cost ratio over the fastest's (RVEs with a cost
    in both runs only)."""
    out = []
    for t in sorted(steps):
        owner = owners(ranks, t)
        ratios: list[list[float]] = [[] for _ in range(n_ranks)]
        for c_ref, c, q in zip(ref_costs[t], costs[t], owner):
            if c_ref > 0 and c > 0:
                ratios[q].append(c / c_ref)
        med = [statistics.median(r) for r in ratios if r]
        if len(med) == n_ranks:
            out.append(max(med) / min(med))
    return out


def _self_test() -> None:
    costs = {1: [1.0, 1.0, 1.0, 3.0], 2: [2.0, 2.0, 2.0, 2.0]}
    # Step 1 on ranks 0,0,1,1: W = (2, 4); step 2 after a migration, 0,1,0,1: W = (4, 4).
    ranks = [(1, [0, 0, 1, 1]), (2, [0, 1, 0, 1])]
    e = efficiency(costs, ranks, 2, [1, 2])
    assert abs(e - 14.0 / (2 * 8.0)) < 1e-12, e
    assert abs(efficiency(costs, ranks, 2, [2]) - 1.0) < 1e-12
    assert abs(efficiency(costs, [(1, [0, 0, 0, 0])], 1, [1, 2]) - 1.0) < 1e-12
    try:
        efficiency(costs, [(2, [0, 0, 1, 1])], 2, [1])
    except ValueError:
        pass
    else:
        raise AssertionError("a step before the first rank map must be refused")
    slow = {1: [1.0, 1.0, 1.5, 4.5], 2: [2.0, 2.0, 2.0, 2.0]}  # rank 1 1.5x slower in step 1
    s = speed_spread(costs, slow, ranks, 2, [1, 2])
    assert all(abs(x - y) < 1e-12 for x, y in zip(s, [1.5, 1.0])), s
    print("partition_efficiency: self-test ok")


if __name__ == "__main__":
    _self_test()

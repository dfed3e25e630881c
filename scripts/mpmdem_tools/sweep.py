"""The one sweep runner: a study is a declarative spec, run variant by variant.

  spec = StudySpec(
      name="grid_convergence_study",                  # messages, progress
      variants=[Variant("fixed_ppc2_h0.11", scene_doc, {"base": "fixed", ...}), ...],
      metrics=lambda v, s: {...},                      # one CSV row from a run's Summary
      report=lambda rows: "table text",                # written to table.md and printed
  )
  rows = sweep(spec, app, out_dir)

A variant is its base scene with overrides applied (a loaded YAML document: build it with
`derived(base, {...})` or a study's own function of the base); each runs with
scripts/lib/column_study.run_column (mpm_app on one thread; summary.json read through
mpmdem_tools.summary, plus the energy budget's shares), or the spec's own `run`.
Variants may be a generator: a later variant can depend on earlier rows.
"""
from __future__ import annotations

import copy
import csv
import os
import sys
from dataclasses import dataclass, field
from typing import Callable, Iterable

import yaml


@dataclass
class Variant:
    name: str                # run folder and scene file stem
    scene: dict              # the scene document to run
    info: dict = field(default_factory=dict)  # what the study knows of it before the run


@dataclass
class StudySpec:
    name: str
    variants: Iterable[Variant]
    metrics: Callable[[Variant, dict], dict | None]  # None: no CSV row for this run
    report: Callable[[list], str] | None = None
    run: Callable | None = None        # run(app, scene, out, name, study) -> summary dict
    runs_dir: str = "runs"             # where the runs go, under the study's folder ("": in it)
    csv_name: str | None = "study.csv"
    table_name: str | None = "table.md"
    progress: bool = True              # "  NAME: N steps, T s" on stderr after each run
    on_run: Callable | None = None     # on_run(variant, summary, row), after each run


def copy_doc(doc: dict) -> dict:
    """A deep copy of a scene document (as YAML would round-trip it)."""
    return yaml.safe_load(yaml.safe_dump(doc))


def derived(base: dict, overrides: dict) -> dict:
    """The base scene with dotted-key overrides (scene_overrides.set_key: a None removes)."""
    from scene_overrides import set_key  # scripts/lib

    doc = copy_doc(base)
    for key, value in overrides.items():
        set_key(doc, key, copy.deepcopy(value), "the study's base scene")
    return doc


def write_csv(path: str, rows: list) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def sweep(spec: StudySpec, app: str, out: str) -> list:
    """Runs every variant of the spec into OUT/<runs_dir>/<name>, collects the metrics rows,
    writes OUT/<csv_name> and, with a report, OUT/<table_name> (also printed). Returns rows."""
    if spec.run is None:
        from column_study import run_column  # scripts/lib

        run = run_column
    else:
        run = spec.run
    where = os.path.join(out, spec.runs_dir) if spec.runs_dir else out
    rows = []
    for v in spec.variants:
        s = run(app, v.scene, where, v.name, spec.name)
        row = spec.metrics(v, s)
        if row is not None:
            rows.append(row)
        if spec.progress:
            print(f"  {v.name}: {s['steps']} steps, {s['run_s']:.1f} s", file=sys.stderr)
        if spec.on_run:
            spec.on_run(v, s, row)
    if spec.csv_name and rows:
        write_csv(os.path.join(out, spec.csv_name), rows)
    if spec.report:
        text = spec.report(rows)
        if spec.table_name:
            with open(os.path.join(out, spec.table_name), "w") as fh:
                fh.write(text)
        print(text)
    return rows

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
Variants may be a generator: a later variant can depend on earlier rows. The CSV is written
row by row as the runs end: a study stopped by a failed run keeps the rows before it.
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
    csv_lineterminator: str = "\r\n"  # the csv module's; "\n" where a study's CSV always had it
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


class CsvRows:
    """OUT/<csv_name>, opened at the first row (its keys are the header) and flushed at each:
    the rows of the runs done so far are on disk whatever ends the study."""

    def __init__(self, path: str | None, lineterminator: str):
        self.path, self.lineterminator = path, lineterminator
        self.fh = self.writer = None

    def add(self, row: dict) -> None:
        if not self.path:
            return
        if self.writer is None:
            self.fh = open(self.path, "w", newline="")
            self.writer = csv.DictWriter(self.fh, fieldnames=list(row),
                                         lineterminator=self.lineterminator)
            self.writer.writeheader()
        self.writer.writerow(row)
        self.fh.flush()

    def close(self) -> None:
        if self.fh:
            self.fh.close()


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
    table = CsvRows(spec.csv_name and os.path.join(out, spec.csv_name), spec.csv_lineterminator)
    try:
        for v in spec.variants:
            s = run(app, v.scene, where, v.name, spec.name)
            row = spec.metrics(v, s)
            if row is not None:
                rows.append(row)
                table.add(row)
            if spec.progress:
                print(f"  {v.name}: {s['steps']} steps, {s['run_s']:.1f} s", file=sys.stderr)
            if spec.on_run:
                spec.on_run(v, s, row)
    finally:
        table.close()
    if spec.report:
        text = spec.report(rows)
        if spec.table_name:
            with open(os.path.join(out, spec.table_name), "w") as fh:
                fh.write(text)
        print(text)
    return rows

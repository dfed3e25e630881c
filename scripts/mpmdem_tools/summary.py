"""A run's summary.json, read one way.

  from mpmdem_tools.summary import read_summary
  s = read_summary("runs/x")            # a run directory or the summary.json itself
  s["runout_m"]                         # a missing key: SummaryError naming key and file
  s.get("verification", {})             # optional keys as with a dict
  s.path("energy_budget.E_err_share")   # a dotted path into nested sections

A missing or unreadable file is a SummaryError that names the file and what to do.
"""
from __future__ import annotations

import json
from pathlib import Path


class SummaryError(KeyError):
    """summary.json is missing, unreadable, or lacks a key; the message names the file."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class Summary(dict):
    """summary.json's document (a dict) that knows its file: a missing key names both."""

    def __init__(self, doc: dict, file: Path):
        super().__init__(doc)
        self.file = Path(file)

    def __missing__(self, key):
        raise SummaryError(f"{self.file}: no key '{key}' (keys: {', '.join(sorted(self))})")

    def path(self, dotted: str):
        """The value at a dotted path ("energy_budget.E_err_share"); SummaryError if absent."""
        node = self
        for i, part in enumerate(dotted.split(".")):
            if not isinstance(node, dict) or part not in node:
                where = ".".join(dotted.split(".")[:i]) or "the top level"
                raise SummaryError(f"{self.file}: no key '{dotted}' ('{part}' missing in {where})")
            node = node[part]
        return node

    @property
    def complete(self) -> bool:
        return self.get("status") == "complete"

    def require_complete(self) -> "Summary":
        """Itself when status is complete; otherwise SummaryError with its status and error."""
        if not self.complete:
            raise SummaryError(f"{self.file}: status {self.get('status')!r}, not 'complete'"
                               + (f" ({self['error']})" if self.get("error") else ""))
        return self


def summary_file(run: str | Path) -> Path:
    """summary.json of a run directory, or the path itself when it names a file."""
    p = Path(run)
    return p / "summary.json" if p.is_dir() else p


def read_summary(run: str | Path) -> Summary:
    """The Summary of a run directory (or of a summary.json path)."""
    f = summary_file(run)
    try:
        with open(f) as fh:
            doc = json.load(fh)
    except FileNotFoundError:
        raise SummaryError(f"{f}: no summary.json (the run did not get to its end; see its "
                           "logs/)") from None
    except (OSError, ValueError) as e:
        raise SummaryError(f"{f}: cannot read summary.json: {e}") from None
    if not isinstance(doc, dict):
        raise SummaryError(f"{f}: summary.json is not a JSON object")
    return Summary(doc, f)

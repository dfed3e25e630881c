#!/usr/bin/python3
"""One figure, one place: the figures the README and the docs quote match docs/results.md.

docs/results.md holds every headline figure in tables whose first column is `id` (a stable
name in backticks) and which have a `value` column. A page quotes a figure as a Markdown link
whose text is the value and whose title is the id:

    [2.16 m](docs/results.md#default-job-accuracy "default.runout_m")

This script fails (exit 1, one line per problem) when
  - a quote's text differs from the value on the results page, or names an id the page lacks,
    or links to an anchor (heading) the page does not have;
  - the results page repeats an id, leaves a value empty, or leaves the command, date or
    machine of a measured row empty;
  - the README quotes no figure at all, or does not link the docs index (docs/README.md).
Links, anchors and the reachability of every page are docs_links.py's (docs_links_and_commands).
It then checks itself on the same texts with one README value changed and with an unknown
id, so it cannot pass by finding nothing.

Usage: docs_figures.py SOURCE_DIR
"""
import os
import re
import sys
from pathlib import Path

QUOTE = re.compile(r'\[([^\]]+)\]\(([^)\s"]*results\.md)(#[^)\s"]*)?\s+"([^"]+)"\)')
ANY_RESULTS_LINK = re.compile(r'\[[^\]]+\]\([^)]*results\.md[^)]*\)')
LINK = re.compile(r'\]\(([^)\s"#]+\.md)(#[^)\s"]*)?(?:\s+"[^"]*")?\)')
MEASURED_COLUMNS = ("command", "date", "machine")


def norm(text: str) -> str:
    return " ".join(text.replace("\u00a0", " ").split())


def cells(line: str) -> list:
    return [c.strip() for c in line.strip().strip("|").split("|")]


def slug(heading: str) -> str:
    """GitHub's anchor for a heading."""
    s = heading.strip().lower().replace("`", "")
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def parse_results(text: str, errors: list) -> tuple:
    """Return ({id: value}, {anchor}) of the results page."""
    figures, anchors = {}, set()
    header = None
    for n, line in enumerate(text.splitlines(), 1):
        if line.startswith("#"):
            anchors.add(slug(line.lstrip("#")))
        if not line.lstrip().startswith("|"):
            header = None
            continue
        row = cells(line)
        if header is None:
            header = [c.lower() for c in row]
            continue
        if set("".join(row)) <= set("-: "):
            continue  # the separator line
        if not header or header[0] != "id":
            continue
        rid = row[0].strip("`")
        if not rid:
            errors.append(f"docs/results.md:{n}: a row without an id")
            continue
        if len(row) != len(header):
            errors.append(f"docs/results.md:{n}: {rid}: {len(row)} cells, header has {len(header)}")
            continue
        rec = dict(zip(header, row))
        if rid in figures:
            errors.append(f"docs/results.md:{n}: id {rid} appears twice")
        if "value" not in rec or not rec["value"]:
            errors.append(f"docs/results.md:{n}: {rid}: no value")
            continue
        for col in MEASURED_COLUMNS:
            if col in rec and not rec[col]:
                errors.append(f"docs/results.md:{n}: {rid}: empty '{col}'")
        figures[rid] = norm(rec["value"])
    return figures, anchors


def check_quotes(name: str, text: str, figures: dict, anchors: set, errors: list) -> int:
    """Check every quote of the page (a quote's link text may wrap over lines)."""
    def line(pos: int) -> str:
        return f"{name}:{text.count(chr(10), 0, pos) + 1}"

    for m in ANY_RESULTS_LINK.finditer(text):
        if '"' in m.group(0) and not QUOTE.fullmatch(m.group(0)):
            errors.append(f"{line(m.start())}: a malformed quote: {norm(m.group(0))}")
    count = 0
    for m in QUOTE.finditer(text):
        value, target, anchor, rid = norm(m.group(1)), m.group(2), m.group(3), m.group(4)
        count += 1
        where = line(m.start())
        if os.path.normpath(os.path.join(os.path.dirname(name), target)) != "docs/results.md":
            errors.append(f"{where}: {rid}: links {target}, not docs/results.md")
        if rid not in figures:
            errors.append(f"{where}: quotes id '{rid}', which docs/results.md does not have")
            continue
        if value != figures[rid]:
            errors.append(f"{where}: {rid} is '{value}' here, '{figures[rid]}' on docs/results.md")
        if anchor and anchor[1:] not in anchors:
            errors.append(f"{where}: {rid}: docs/results.md has no heading for {anchor}")
    return count


def md_links(name: str, text: str) -> list:
    """The .md files a page links to, as paths relative to the source root."""
    out = []
    for m in LINK.finditer(text):
        target = m.group(1)
        if "://" in target:
            continue
        out.append(os.path.normpath(os.path.join(os.path.dirname(name), target)))
    return out


def check(pages: dict) -> list:
    """pages: {relative path: text} for README.md and docs/**/*.md."""
    errors = []
    if "docs/results.md" not in pages:
        return ["docs/results.md is missing"]
    figures, anchors = parse_results(pages["docs/results.md"], errors)
    if not figures:
        errors.append("docs/results.md: no figure table (first column 'id', a 'value' column)")
    for name, text in sorted(pages.items()):
        n = check_quotes(name, text, figures, anchors, errors)
        if name == "README.md" and n == 0:
            errors.append("README.md quotes no figure of docs/results.md")
    if "docs/README.md" not in md_links("README.md", pages.get("README.md", "")):
        errors.append("README.md does not link the docs index docs/README.md")
    return errors


def self_check(pages: dict) -> list:
    """The checker must catch a changed README figure and an unknown id."""
    problems = []
    readme = pages["README.md"]
    m = QUOTE.search(readme)
    if not m:
        return ["self-check: no quote in README.md to change"]
    changed = readme[:m.start(1)] + m.group(1) + "0" + readme[m.end(1):]
    if not any(m.group(4) in e for e in check({**pages, "README.md": changed})):
        problems.append(f"self-check: a changed value of {m.group(4)} in README.md was not caught")
    unknown = readme[:m.start(4)] + "no.such_figure" + readme[m.end(4):]
    if not any("no.such_figure" in e for e in check({**pages, "README.md": unknown})):
        problems.append("self-check: an unknown id in README.md was not caught")
    return problems


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    root = Path(sys.argv[1])
    pages = {"README.md": (root / "README.md").read_text(encoding="utf-8")}
    for p in sorted((root / "docs").rglob("*.md")):
        pages[p.relative_to(root).as_posix()] = p.read_text(encoding="utf-8")
    errors = check(pages)
    for e in errors:
        print(f"docs_figures: {e}")
    if errors:
        print(f"docs_figures: FAILED ({len(errors)} problems)")
        return 1
    problems = self_check(pages)
    for p in problems:
        print(f"docs_figures: {p}")
    if problems:
        return 1
    figures, _ = parse_results(pages["docs/results.md"], [])
    quoted = sum(len(QUOTE.findall(t)) for t in pages.values())
    print(f"docs_figures: ok: {len(figures)} figures on docs/results.md, {quoted} quotes in "
          f"{len(pages)} pages match")
    return 0


if __name__ == "__main__":
    sys.exit(main())

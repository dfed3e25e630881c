#!/usr/bin/python3
"""The folders are the architecture (issue 37, item 1): mpm_app and dem_app never depend on
each other; both depend only on interface/ (the coupling contract) and laws/ (the closed-form
laws both evaluate); interface/ and laws/ depend on neither app.

Checked two ways, from the sources alone (no build needed):
  - includes: every `#include "..."` of a folder's C++/CUDA files resolves inside the folder
    itself or a folder it may use (relative to the including file, or to an include root:
    <folder>/src, <folder>/include, <folder>);
  - CMake: every target a folder's CMake files link (target_link_libraries) is a target of
    the folder itself, of a folder it may use, or not a target of this project (Eigen3::Eigen,
    MPI::MPI_CXX, ...).
Usage: architecture_edges.py SOURCE_DIR   (exit 0: no edge that must not be; 1: a list of them)
"""
import re
import sys
from pathlib import Path

src = Path(sys.argv[1]).resolve()
MAY_USE = {  # folder -> folders it may depend on (besides itself)
    "interface": [],
    "laws": [],
    "mpm_app": ["interface", "laws"],
    "dem_app": ["interface", "laws"],
}
SOURCES = ("*.cpp", "*.hpp", "*.h", "*.cu", "*.cuh")
faults = []


def roots(folder):
    base = src / folder
    return [base / "src", base / "include", base]


def owner(path):
    rel = path.resolve().relative_to(src)
    return rel.parts[0]


for folder, allowed in MAY_USE.items():
    ok = [folder] + allowed
    files = [f for pat in SOURCES for f in (src / folder).rglob(pat)]
    for f in sorted(files):
        for n, line in enumerate(f.read_text(errors="replace").splitlines(), 1):
            m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
            if not m:
                continue
            inc = m.group(1)
            candidates = [f.parent / inc] + [r / inc for o in ok for r in roots(o)]
            if any(c.is_file() for c in candidates):
                continue
            # Not found where it may be: name where it is, if it is in another folder.
            elsewhere = [g for o in MAY_USE if o not in ok for g in (src / o).rglob(Path(inc).name)
                         if g.as_posix().endswith("/" + inc)]
            where = (owner(elsewhere[0]) + "/" if elsewhere else "no folder it may use")
            faults.append(f"{f.relative_to(src)}:{n}: includes \"{inc}\", found in {where}")

targets = {}  # target -> folder that defines it
links = []  # (folder, file, target, linked)
for folder in MAY_USE:
    for f in sorted(list((src / folder).rglob("CMakeLists.txt")) + list((src / folder).rglob("*.cmake"))):
        text = re.sub(r"#[^\n]*", "", f.read_text())
        for m in re.finditer(r"add_(?:library|executable)\(\s*([A-Za-z0-9_]+)", text):
            targets[m.group(1)] = folder
        for m in re.finditer(r"target_link_libraries\(\s*([A-Za-z0-9_]+)([^)]*)\)", text):
            for lib in m.group(2).split():
                if lib not in ("PUBLIC", "PRIVATE", "INTERFACE"):
                    links.append((folder, f, m.group(1), lib.strip('"')))
for folder, f, target, lib in links:
    if lib in targets and targets[lib] not in [folder] + MAY_USE[folder]:
        faults.append(f"{f.relative_to(src)}: {target} links {lib}, a target of {targets[lib]}/")

for fault in faults:
    print("edge that must not be:", fault)
print(f"architecture_edges: {len(targets)} targets, {len(links)} links, "
      f"{len(faults)} edges that must not be")
sys.exit(1 if faults else 0)

"""A scene file with some keys overridden: the one place scripts derive scene variants.

  from scene_overrides import derive_scene
  path = derive_scene(SCENE, {"grid.cell_size": 0.05, "regions.0.max": [1, 1, 2]}, OUT, note)

Keys are dotted paths into the YAML document; a numeric part indexes a list
("regions.0.points_per_cell_xyz"). A missing section is created; a null value removes the key
(e.g. "solver.flip": None where solver.flip_time_scale replaces it, "coupling.yade": None for
a scene moved to the native backend); indexing past a list's end or into a scalar is an error
naming the key and the scene. Relative paths in the copy are made absolute against the
original scene's folder (coupling.yade|native.packing_dir / packing_spec, and the same keys if
an override sets them relative to the study file: pass `relative_to`).
"""
from __future__ import annotations

import copy
from pathlib import Path

import yaml

PATH_KEYS = ("packing_dir", "packing_spec")
BACKENDS = ("yade", "native")  # coupling sections that hold PATH_KEYS


class OverrideError(ValueError):
    pass


def set_key(doc: dict, key: str, value, where: str) -> None:
    node = doc
    parts = key.split(".")
    for i, p in enumerate(parts):
        last = i == len(parts) - 1
        if isinstance(node, list):
            if not p.isdigit() or int(p) >= len(node):
                raise OverrideError(f"{key}: '{p}' is not an index of the list "
                                    f"'{'.'.join(parts[:i])}' ({len(node)} items) in {where}")
            if last:
                node[int(p)] = value
            else:
                node = node[int(p)]
        elif isinstance(node, dict):
            if last and value is None:
                node.pop(p, None)
            elif last:
                node[p] = value
            else:
                node = node.setdefault(p, {})
        else:
            raise OverrideError(f"{key}: '{'.'.join(parts[:i])}' is a value, not a section, "
                                f"in {where}")


def absolute_paths(doc: dict, base: Path) -> None:
    for b in BACKENDS:
        y = ((doc.get("coupling") or {}).get(b)) or {}
        for key in PATH_KEYS:
            if isinstance(y.get(key), str) and y[key] and not Path(y[key]).is_absolute():
                y[key] = str((base / y[key]).resolve())


def derive_doc(scene: Path, overrides: dict, relative_to: Path | None = None) -> dict:
    """The scene's document with the overrides applied (paths absolute)."""
    scene = Path(scene).resolve()
    doc = yaml.safe_load(scene.read_text())
    absolute_paths(doc, scene.parent)
    for key, value in overrides.items():
        set_key(doc, key, copy.deepcopy(value), str(scene))
    if relative_to is not None:  # paths set by the overrides are relative to their own file
        for b in BACKENDS:
            y = ((doc.get("coupling") or {}).get(b)) or {}
            for key in PATH_KEYS:
                if f"coupling.{b}.{key}" in overrides and not Path(y[key]).is_absolute():
                    y[key] = str((Path(relative_to).resolve().parent / y[key]).resolve())
    return doc


def derive_scene(scene: Path, overrides: dict, out: Path, note: str,
                 relative_to: Path | None = None) -> Path:
    """Write the derived scene to OUT (a file path) with a header comment; return OUT."""
    doc = derive_doc(scene, overrides, relative_to)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(f"# {note}\n# derived from {Path(scene).resolve()}\n"
                   + yaml.safe_dump(doc, sort_keys=False, default_flow_style=None))
    return out

"""Reading what a run wrote, for scripts/lib/stability_suite.py (Debian's /usr/bin/python3:
numpy, h5py): VTK frames of mpm_app, NaN/Inf scan of a run directory, the energy-balance
error of energies.csv, the largest point speed over the frames."""
import csv
import os
import re
import struct

import numpy as np


def vtu_float_arrays(path):
    """{name: np.array} of the Float64 arrays of a .vtu written by mpm_app (raw appended)."""
    raw = open(path, "rb").read()
    start = raw.find(b"<AppendedData encoding=\"raw\">")
    head = raw[:start].decode()
    data = raw.index(b"_", start) + 1
    out = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)"(?: NumberOfComponents="(\d+)")? '
                         r'format="appended" offset="(\d+)"/>', head):
        typ, name, comps, off = m.group(1), m.group(2), int(m.group(3) or 1), int(m.group(4))
        if typ != "Float64":
            continue
        (nbytes,) = struct.unpack_from("<Q", raw, data + off)
        a = np.frombuffer(raw, "<f8", nbytes // 8, data + off + 8)
        out[name] = a.reshape(-1, comps) if comps > 1 else a
    return out


TOKEN = re.compile(r"(^|[,:\s\[])[-+]?(nan|inf)", re.I)


def non_finite_files(run_dir):
    """Files of a run directory holding a NaN or an Inf: CSV/JSON/PVD text, VTK Float64 arrays,
    HDF5 float datasets and attributes (final state, snapshots, checkpoints). Returns
    (files checked, [offending paths])."""
    import h5py
    checked, bad = 0, []
    for dirpath, _, names in os.walk(run_dir):
        for n in names:
            p = os.path.join(dirpath, n)
            ext = os.path.splitext(n)[1]
            ok = True
            if ext in (".csv", ".json", ".pvd"):
                ok = not TOKEN.search(open(p, errors="replace").read())
            elif ext == ".vtu":
                ok = all(np.isfinite(a).all() for a in vtu_float_arrays(p).values())
            elif ext == ".h5":
                def visit(_, obj):
                    nonlocal ok
                    for v in obj.attrs.values():
                        if isinstance(v, (float, np.floating, np.ndarray)) and \
                                np.issubdtype(np.asarray(v).dtype, np.floating) and \
                                not np.isfinite(v).all():
                            ok = False
                    if isinstance(obj, h5py.Dataset) and np.issubdtype(obj.dtype, np.floating):
                        if not np.isfinite(obj[()]).all():
                            ok = False
                with h5py.File(p, "r") as f:
                    visit("/", f)
                    f.visititems(visit)
            else:
                continue
            checked += 1
            if not ok:
                bad.append(os.path.relpath(p, run_dir))
    return checked, bad


def energy_error(path):
    """(max |E_err| / E_ref, max |E_err - W_transfer| / E_ref, E_ref) over the rows of an
    energies.csv: the residual, and the part of it the transfers do not explain (time
    integration; what an instability would inject)."""
    rows = list(csv.DictReader(open(path)))
    if not rows:
        return float("nan"), float("nan"), 0.0
    ep0, ek0 = float(rows[0]["E_p0"]), float(rows[0]["E_k0"])
    e_ref = ek0 + max(abs(ep0 - float(r["E_p"])) for r in rows)
    err = max(abs(float(r["E_err"])) for r in rows)
    other = max(abs(float(r["E_err"]) - float(r["W_transfer"])) for r in rows)
    if not e_ref > 0:
        return float("nan"), float("nan"), e_ref
    return err / e_ref, other / e_ref, e_ref


def max_velocity(run_dir):
    vmax = 0.0
    for n in sorted(os.listdir(run_dir)):
        if n.endswith(".vtu"):
            v = vtu_float_arrays(os.path.join(run_dir, n)).get("velocity")
            if v is not None and len(v):
                vmax = max(vmax, float(np.linalg.norm(v, axis=1).max()))
    return vmax


def last_frame(run_dir):
    """(time, arrays) of the last frame listed in frames.pvd, or (None, {})."""
    pvd = os.path.join(run_dir, "frames.pvd")
    if not os.path.exists(pvd):
        return None, {}
    frames = re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', open(pvd).read())
    if not frames:
        return None, {}
    t, f = frames[-1]
    return float(t), vtu_float_arrays(os.path.join(run_dir, f))



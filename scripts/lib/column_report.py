"""Pictures and a markdown report of a granular column collapse run (paper Figs. 5-7).

  /usr/bin/python3 scripts/lib/column_report.py RUN_DIR

Reads RUN_DIR/summary.json (the column_collapse figures mpm_app wrote), energies.csv,
snapshots/t_star_*.h5 and final_state.h5; writes into RUN_DIR:
  energies.png        E_p/E_p0, E_k/E_p0, E_d/E_p0 against t/t* in stage 2 (Fig. 7)
  velocity.png        side views (x-z) coloured by |v| at the snapshot times (Fig. 5), the
                      deposit from Lajeunesse et al. (2005)'s scaling laws dashed
  rotation.png        accumulated mean particle rotation of the RVEs at the end (Fig. 6), if
                      the scene asked the RVEs for it (coupling.outputs: [rotation])
  report.md           these beside the paper's figures and the bands of
                      shared/notes/validation.md
Stage-2 energies: E_p is measured from the base and E_p0 is its value at the release of the
stage-1 constraint (summary: Ep0_release_J, stage1_time_s); E_d = E_p0 - E_p - E_k.
Needs Debian's python3-numpy, python3-h5py, python3-matplotlib. Exit 0 on success, 1 if the
run has no column_collapse figures, 2 on a missing or unreadable file or a figure missing from
summary.json (read by mpmdem_tools.summary: the message names the file and the key).
"""
import csv
import glob
import math
import os
import sys
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # scripts/: mpmdem_tools
from mpmdem_tools.summary import SummaryError, read_summary  # noqa: E402  (the one reader)

# Paper and published laws (shared/notes/validation.md).
PAPER_ED_OVER_EP0 = 0.549
RUNOUT_LAWS = [("1.2 a (short-column regime)", 1.2, 1.0),
               ("1.9 a^(2/3) (tall-column regime)", 1.9, 2.0 / 3.0),
               ("1.8 a (Lajeunesse 2005 as quoted by Lagree 2011)", 1.8, 1.0)]
HEIGHT_LAWS = [("a^(1/3)", 1.0 / 3.0), ("a^(2/5)", 0.4)]


def load_energies(path, t_release, t_star, ep0_release):
    rows = list(csv.DictReader(open(path)))
    t = np.array([float(r["time"]) for r in rows])
    ep = np.array([float(r["E_p"]) for r in rows])
    ek = np.array([float(r["E_k"]) for r in rows])
    # E_p in the CSV is measured from z = 0 of the grid; shift it so that E_p(t_r) = E_p0.
    ep = ep - (np.interp(t_release, t, ep) - ep0_release)
    stage2 = t >= t_release - 1e-12
    tau = (t[stage2] - t_release) / t_star
    ep, ek = ep[stage2] / ep0_release, ek[stage2] / ep0_release
    return tau, ep, ek, 1.0 - ep - ek


def deposit_from_laws(a, L_i):
    """Wedge from the back wall (height H_f) to the front (runout L_f), with Lajeunesse et al.
    (2005)'s quasi-2D laws: dL/L_i = 1.2 a for a < 3 (1.9 a^(2/3) above), H_f/L_i = a^(2/5)."""
    dl = 1.2 * a if a < 3.0 else 1.9 * a ** (2.0 / 3.0)
    L_f = L_i * (1.0 + dl)
    H_f = min(L_i * a ** 0.4, a * L_i)
    return [0.0, 0.0, L_f], [H_f, H_f, 0.0], L_f, H_f


def side_view(ax, f, s, vmax, title, L_i):
    x = f["x"][:]
    v = np.linalg.norm(f["v"][:], axis=1)
    sc = ax.scatter(x[:, 0], x[:, 2], c=v, s=6, cmap="viridis", vmin=0.0, vmax=vmax,
                    marker="s", linewidths=0)
    xs, zs, _, _ = deposit_from_laws(s["aspect_ratio"], L_i)
    ax.plot(xs, zs, "k--", lw=1.0)
    ax.set_title(title, fontsize=9)
    return sc


def main(run_dir):
    try:
        return report(run_dir)
    except SummaryError as e:  # no or unreadable summary.json, or a figure missing from it
        print(f"column_report: {e}", file=sys.stderr)
        return 2


def report(run_dir):
    s = read_summary(os.path.join(run_dir, "summary.json"))
    if "t_star_s" not in s:
        print(f"column_report: {run_dir}/summary.json has no column_collapse figures "
              "(the scene has no column_collapse: section)", file=sys.stderr)
        return 1
    t_star, L_i, H_i = s["t_star_s"], s["initial_length_m"], s["initial_height_m"]
    t_r, ep0 = s.get("stage1_time_s"), s.get("Ep0_release_J")
    made = []

    # Fig. 7: energies.
    if t_r is not None and ep0:
        tau, ep, ek, ed = load_energies(os.path.join(run_dir, "energies.csv"), t_r, t_star, ep0)
        fig, ax = plt.subplots(figsize=(5, 3.4))
        ax.plot(tau, ep, label="$E_p/E_p^0$")
        ax.plot(tau, ek, label="$E_k/E_p^0$")
        ax.plot(tau, ed, label="$E_d/E_p^0$")
        ax.axhline(PAPER_ED_OVER_EP0, color="gray", ls=":", lw=1,
                   label=f"paper final $E_d/E_p^0$ = {PAPER_ED_OVER_EP0}")
        ax.set_xlabel("$t/t^*$")
        ax.set_ylabel("energy / $E_p^0$")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(os.path.join(run_dir, "energies.png"), dpi=130)
        plt.close(fig)
        made.append("energies.png")

    # Fig. 5: velocity snapshots.
    snaps = sorted(glob.glob(os.path.join(run_dir, "snapshots", "t_star_*.h5")),
                   key=lambda p: float(os.path.basename(p)[7:-3]))
    # A run ended by the at-rest stop has no snapshots after it: its deposit is the final state.
    if s.get("stop", {}).get("reason") == "at_rest" and os.path.exists(
            os.path.join(run_dir, "final_state.h5")):
        snaps.append(os.path.join(run_dir, "final_state.h5"))
    if snaps:
        files = [h5py.File(p, "r") for p in snaps]
        vmax = max(float(np.linalg.norm(f["v"][:], axis=1).max()) for f in files) or 1.0
        xmax = max(float(f["x"][:, 0].max()) for f in files)
        fig, axes = plt.subplots(len(files), 1, figsize=(8, 2.6 * len(files) + 0.4),
                                 squeeze=False, constrained_layout=True)
        for ax, f in zip(axes[:, 0], files):
            tau = (f.attrs["time"] - t_r) / t_star
            sc = side_view(ax, f, s, vmax, f"t = {tau:.2f} t*  (t = {f.attrs['time']:.3f} s)",
                           L_i)
            ax.set_xlim(0, max(xmax, s["runout_m"]) * 1.05)
            ax.set_ylim(0, H_i * 1.05)
            ax.set_ylabel("z (m)")
        axes[-1, 0].set_xlabel("x (m)")
        fig.colorbar(sc, ax=axes[:, 0].tolist(), label="|v| (m/s)", shrink=0.8)
        axes[-1, 0].plot([], [], "k--", label="deposit, Lajeunesse et al. (2005) laws")
        axes[-1, 0].legend(fontsize=7, loc="upper right")
        fig.savefig(os.path.join(run_dir, "velocity.png"), dpi=130)
        plt.close(fig)
        for f in files:
            f.close()
        made.append("velocity.png")

    # Fig. 6: accumulated mean particle rotation.
    final = os.path.join(run_dir, "final_state.h5")
    rot_note = "not requested by the scene (coupling.outputs has no rotation)"
    if os.path.exists(final):
        with h5py.File(final, "r") as f:
            if "rotation" in f:
                x = f["x"][:]
                rot = np.degrees(np.linalg.norm(f["rotation"][:], axis=1))
                fig, ax = plt.subplots(figsize=(7, 2.6))
                sc = ax.scatter(x[:, 0], x[:, 2], c=rot, s=8, cmap="magma_r", marker="s",
                                linewidths=0)
                fig.colorbar(sc, ax=ax, label="mean particle rotation (deg)")
                ax.set_aspect("equal")
                ax.set_xlabel("x (m)")
                ax.set_ylabel("z (m)")
                ax.set_title("accumulated mean particle rotation at the end", fontsize=9)
                fig.tight_layout()
                fig.savefig(os.path.join(run_dir, "rotation.png"), dpi=130)
                plt.close(fig)
                made.append("rotation.png")
                rot_note = (f"max {rot.max():.1f} deg, median {np.median(rot):.2f} deg; "
                            f"{100.0 * np.mean(rot < 1.0):.0f}% of the points rotated < 1 deg")

    thin = 0
    log = os.path.join(run_dir, "logs", "dem_app.log")
    if os.path.exists(log):
        thin = sum(1 for line in open(log, errors="replace") if "packing tiled" in line)
    write_report(run_dir, s, made, rot_note, thin)
    print("column_report: wrote " + ", ".join(made + ["report.md"]) + f" in {run_dir}")
    return 0


def band(values):
    return f"{min(values):.2f} - {max(values):.2f}"


def write_report(run_dir, s, made, rot_note, thin):
    a, L_i, H_i = s["aspect_ratio"], s["initial_length_m"], s["initial_height_m"]
    L_f, H_f = s["runout_m"], s["final_height_m"]
    laws_L = [L_i * (1.0 + c * a ** e) for _, c, e in RUNOUT_LAWS]
    laws_H = [L_i * a ** e for _, e in HEIGHT_LAWS]
    ed = s.get("Ed_over_Ep0_final")
    lo_bound = 1.0 - H_f / H_i
    hi_bound = 1.0 - L_i / L_f if L_f > 0 else float("nan")

    def budget_text(b):
        keys = ("W_int_share", "W_bc_share", "E_err_transfer_share", "E_err_other_share")
        if not all(isinstance(b.get(k), (int, float)) for k in keys):
            return "n/a"
        parts = [f"{100 * b[k]:.1f} %" for k in keys]
        walls = b.get("E_err_transfer_walls_share")  # absent in runs before 2026-11-26
        if isinstance(walls, (int, float)):
            bulk = b["E_err_transfer_share"] - walls
            parts[2] += f" ({100 * walls:.1f} % at the walls, {100 * bulk:.1f} % in the bulk)"
        return " / ".join(parts)

    def fmt(v, d=3):
        return "n/a" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.{d}f}"

    lines = [
        f"# Column collapse: {s.get('scene', '')}",
        "",
        f"Run `{s.get('run_directory', run_dir)}`, status **{s.get('status')}**, model "
        f"`{s.get('model')}`, {s.get('n_material_points')} material points"
        + (f", {s['n_rve_particles']} RVE particles" if "n_rve_particles" in s else "")
        + f", wall time {s.get('wall_time_s', 0):.0f} s.",
        "",
        f"H_i = {H_i:.3f} m, L_i = {L_i:.3f} m, a = {a:.2f}, t* = {s['t_star_s']:.4f} s; "
        f"stage 1 (lateral face held) took {fmt(s.get('stage1_time_s'))} s; stage 2 ran "
        f"{fmt(s.get('time_over_t_star_final'), 2)} t*"
        + (" (ended by the at-rest stop: E_k/E_p0 < "
           f"{s['stop'].get('kinetic_ratio')} for {s['stop'].get('hold_t_star')} t*)"
           if s.get("stop", {}).get("reason") == "at_rest" else "") + ".",
        "",
        "| figure | this run | reference |",
        "|---|---|---|",
        f"| runout L_f (m) | {L_f:.3f} | {band(laws_L)} (scaling laws, validation.md) |",
        f"| (L_f - L_i)/L_i | {s['runout_normalized']:.2f} | "
        f"{band([(x - L_i) / L_i for x in laws_L])} |",
        f"| final height H_f (m) | {H_f:.3f} | {band(laws_H)} (H_f/L_i = a^(1/3)..a^(2/5)) |",
        f"| E_d/E_p0 at the end | {fmt(ed)} | {PAPER_ED_OVER_EP0} (paper); geometric bounds "
        f"{lo_bound:.3f} - {hi_bound:.3f} for this deposit |",
        f"| E_k/E_p0 at the end | {fmt(s.get('Ek_over_Ep0_final'), 4)} | ~0 (deposit at rest by "
        "6 t*; at-rest stop below its kinetic_ratio) |",
        f"| energy released since t = 0: stress work / base and walls / transfers / rest | "
        f"{budget_text(s.get('energy_budget', {}))} | the transfers' part is numerical "
        "dissipation (docs/transfers.md); the rest is the time integration's error |",
        f"| RVE updates with no contacts | {int(s.get('rve_no_contact_updates', 0))} | - |",
        f"| RVE cells tiled because the MPM stretch made them too thin (dem_app log) | {thin} | "
        "- (each doubles that RVE's spheres) |",
        "",
        "Mean particle rotation: " + rot_note + ". The paper (Fig. 6) finds no rotation in the "
        "static corner zone at the base of the back wall.",
        "",
        "Pictures: " + ", ".join(f"[{m}]({m})" for m in made) + ". The dashed line in "
        "velocity.png is a wedge with the runout and height of Lajeunesse et al. (2005)'s "
        "quasi-2D laws (dL/L_i = 1.2 a, H_f/L_i = a^(2/5)), not digitised data.",
        "",
        "The paper's column (configs/column_collapse_paper.yaml) is 3D, 0.45 m wide, with "
        "0.05 m cells and 800-sphere RVEs; compare like with like (docs/column_collapse.md: what "
        "the default scene leaves out).",
        "",
    ]
    tmp = os.path.join(run_dir, "report.md.tmp")
    with open(tmp, "w") as f:
        f.write("\n".join(lines))
    os.replace(tmp, os.path.join(run_dir, "report.md"))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))

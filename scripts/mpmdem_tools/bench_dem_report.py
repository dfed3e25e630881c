"""The reports of scripts/bench_dem, from the JSON and logs its blocks wrote into OUT.

Usage: python3 -m mpmdem_tools.bench_dem_report native OUT
         (OUT/native_report.txt's text on stdout; writes OUT/native_summary.json)
       python3 -m mpmdem_tools.bench_dem_report server OUT N_INPROC NS "I:K ..."
         (writes OUT/summary.json and OUT/report.txt; the report on stdout)
"""
import json
import re
import statistics as st
import sys


def native(out):
    col, big = (json.load(open(f"{out}/native_{k}.json")) for k in ("col100", "800"))
    mem = {}
    for line in open(f"{out}/native_memory.log"):
        name = line.split(":")[0]
        mem[name] = float(re.search(r"rss_kb_per_rve ([\d.]+)", line).group(1))
    print(open(f"{out}/machine.txt").read().rstrip())
    print("| RVE | ns | YADE backend | raw YADE | native | native / YADE backend | native / raw YADE |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for label, d in (("100 spheres (col100_s1)", col), (f"800 spheres ({big['packing']})", big)):
        for ns, v in d["ns"].items():
            raw = v.get("raw_yade")
            rr = f"{v['native_over_raw_yade']:.1f}" if raw else "-"
            rv = f"{raw:.3g}" if raw else "-"
            print(f"| {label} | {ns} | {v['yade_backend']:.3g} | {rv} | {v['native']:.3g} | "
                  f"{v['native_over_yade_backend']:.1f} | {rr} |")
    for label, d in (("col100_s1", col), (big["packing"], big)):
        s = d["state"]
        print(f"{label}: binary state {s['state_bytes'] / 1024:.1f} KB, encode {s['encode_us']:.3g} us, "
              f"decode {s['decode_us']:.3g} us; RSS {mem.get(label, float('nan')):.1f} KB per resident RVE")
    json.dump({"col100": col, "800": big, "rss_kb_per_rve": mem},
              open(f"{out}/native_summary.json", "w"), indent=1)


def server(out, n_inproc, ns, blocks):
    n_inproc, ns, blocks = int(n_inproc), int(ns), blocks.split()
    A = [json.load(open(f"{out}/inproc_{j}.json")) for j in range(n_inproc + 1)]
    nsph = A[0]["n_spheres"]
    lines = [open(f"{out}/machine.txt").read().rstrip(), ""]
    lines.append(f"packing {A[0]['packing']}: {nsph} spheres, ns {ns}, {A[0]['steps']} coupling steps per block")
    lines.append("")
    lines.append("In process, interleaved step by step (medians over steps; overhead = median of per-step ratios):")
    lines.append("| block | raw YADE ms | stress ms (vs raw) | + stiffness ms (vs raw) | + all outputs ms (vs raw) | raw YADE cycling K scenes ms (K) |")
    lines.append("|---|---:|---:|---:|---:|---:|")
    summ = {"n_spheres": nsph, "ns": ns, "inproc": A, "server": []}
    for j, a in enumerate(A):
        c = a["configs"]
        cell = lambda k: f"{c[k]['median_ms']:.3f} ({100 * (c[k]['median_ratio_to_raw'] - 1):+.1f} %)"
        rm = f"{c['raw_multi']['median_ms']:.3f} ({a['multi']})" if "raw_multi" in c else "-"
        lines.append(f"| A{j} | {c['raw']['median_ms']:.3f} | {cell('stress')} | {cell('stiffness')} | {cell('all')} | {rm} |")
    ov = {k: st.median([a["configs"][k]["median_ratio_to_raw"] for a in A]) for k in ("stress", "stiffness", "all")}
    lines.append(f"| median of blocks | {st.median([a['configs']['raw']['median_ms'] for a in A]):.3f} | "
                 f"{100 * (ov['stress'] - 1):+.1f} % | {100 * (ov['stiffness'] - 1):+.1f} % | {100 * (ov['all'] - 1):+.1f} % | |")
    lines.append("")
    lines.append("dem_app over MPI (1 rank, element_test client), between in-process blocks A(j) and A(j+1):")
    lines.append("Raw reference of a block with K RVEs: raw YADE cycling K scenes (raw_multi) in the adjacent")
    lines.append("A blocks run with the same K (raw on one scene for K = 1).")
    lines.append("| block | RVEs | server ms per RVE-step | exchange ms per step | raw YADE 1 scene ms | raw YADE K scenes ms | server / raw K scenes | server / raw 1 scene | server RSS MB |")
    lines.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    pat = re.compile(r"(\d+) steps, (\d+) RVEs, compute per step median ([\d.]+) ms mean ([\d.]+) ms, "
                     r"per RVE-step median ([\d.]+) ms; exchange per step median ([\d.]+) ms; RSS ([\d.]+) MB, peak ([\d.]+) MB")
    mem_pts = []
    for b in blocks:
        j, k = map(int, b.split(":"))
        m = pat.search(open(f"{out}/server_{j}/server.log").read())
        steps, K, med, mean, per, exch, rss, peak = m.groups()
        per, rss, exch = float(per), float(rss), float(exch)
        raw1 = 0.5 * (A[j]["configs"]["raw"]["median_ms"] + A[j + 1]["configs"]["raw"]["median_ms"])
        key = "raw_multi" if int(K) > 1 else "raw"
        rk = [a["configs"][key]["median_ms"] for a in (A[j], A[j + 1])
              if key in a["configs"] and (key == "raw" or a.get("multi") == int(K))]
        rawk = st.fmean(rk) if rk else float("nan")
        summ["server"].append({"block": j, "rves": int(K), "ms_per_rve_step": per, "exchange_ms": exch,
                               "raw_ms": raw1, "raw_k_scenes_ms": rawk, "ratio_raw_k": per / rawk,
                               "ratio_raw_1": per / raw1, "rss_mb": rss, "peak_mb": float(peak),
                               "particle_steps_per_s": nsph * ns / (per * 1e-3)})
        mem_pts.append((int(K), rss))
        lines.append(f"| B{j} | {K} | {per:.3f} | {exch:.3f} | {raw1:.3f} | {rawk:.3f} | {per / rawk:.3f} | "
                     f"{per / raw1:.3f} | {rss:.1f} |")
    if len(mem_pts) >= 2:
        n = len(mem_pts); mx = sum(p[0] for p in mem_pts) / n; my = sum(p[1] for p in mem_pts) / n
        slope = sum((p[0] - mx) * (p[1] - my) for p in mem_pts) / sum((p[0] - mx) ** 2 for p in mem_pts)
        summ["server_mb_per_rve"] = slope
        lines.append(f"server RSS fit: {slope:.2f} MB per resident RVE (+ {my - slope * mx:.1f} MB)")
    mem = json.load(open(f"{out}/memory.json"))
    summ["memory"] = mem
    lines.append("in-process RSS: " + ", ".join(f"{r['rves']} RVEs {r['rss_mb']:.1f} MB" for r in mem["rss_mb"])
                 + f" -> {mem['mb_per_rve']:.2f} MB per resident RVE")
    rawps = st.median([a["configs"]["raw"]["particle_steps_per_s"] for a in A])
    srvps = st.median([a["configs"]["stress"]["particle_steps_per_s"] for a in A])
    lines.append(f"particle-steps/s per core: raw YADE {rawps:.3g}, RveSet.step (stress only) {srvps:.3g}, "
                 + ", ".join(f"dem_app K={s['rves']} {s['particle_steps_per_s']:.3g}" for s in summ["server"]))
    summ["overhead_inproc"] = {k: v - 1 for k, v in ov.items()}
    json.dump(summ, open(f"{out}/summary.json", "w"), indent=1)
    open(f"{out}/report.txt", "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


def main(argv):
    if argv[:1] == ["native"] and len(argv) == 2:
        native(argv[1])
    elif argv[:1] == ["server"] and len(argv) == 5:
        server(*argv[1:])
    else:
        print(__doc__, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

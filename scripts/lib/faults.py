#!/usr/bin/python3
"""The peer faults a run healed from (scripts/run --on-fault resume; docs/cluster.md).

  faults.py record RUN            after an attempt ended with a peer fault: append it to
                                  RUN/faults.json and print the DEM hosts to drop (none for a
                                  rank that died on mpm_app's host: that host still runs);
                                  exit 1, saying why, when the run cannot continue by itself
  faults.py restarted RUN EPOCH   the next attempt's mpm_app started at EPOCH (s): completes
                                  the last fault's relaunch_s and wall_time_lost_s
  faults.py merge RUN             writes the list into RUN/summary.json as "faults"

Each fault: hosts, ranks, kind ("no_reply": a stall past coupling.peer_timeout_s; "died":
probed on mpm_app's host), step (the last step completed), checkpoint (the one the next
attempt resumed from) and its step, and the wall time lost: redo_s (the failed attempt's
wall time after that checkpoint: work done again, plus the wait until the fault was
detected) + relaunch_s (from the failed mpm_app's summary to the next mpm_app's start:
stopping the jobs, starting new ones).
"""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))  # scripts/
from mpmdem_tools.summary import read_summary  # noqa: E402  (the one summary.json reader)


def newest_complete(run):
    best = None
    top = os.path.join(run, "checkpoints")
    for name in sorted(os.listdir(top)) if os.path.isdir(top) else []:
        d = os.path.join(top, name)
        if name.startswith("step_") and os.path.isfile(os.path.join(d, "COMPLETE")):
            best = d
    return best


def load(run):
    path = os.path.join(run, "faults.json")
    return json.load(open(path)) if os.path.exists(path) else []


def save(run, faults):
    path = os.path.join(run, "faults.json")
    with open(path + ".tmp", "w") as f:
        json.dump(faults, f, indent=2)
    os.replace(path + ".tmp", path)


def record(run):
    summary = os.path.join(run, "summary.json")
    s = read_summary(summary) if os.path.exists(summary) else {}
    fault = s.get("peer_fault")
    if s.get("status") != "failed" or not fault:
        print("run: --on-fault resume: the run did not fail by a lost DEM rank (%s): not resuming"
              % (s.get("error") or "no summary.json"), file=sys.stderr)
        return 1
    if not fault["exact"]:
        print("run: --on-fault resume: the stall was in a collective, so the silent DEM host is "
              "not known (named: %s): not resuming; resume by hand with the hosts that answer "
              "(scripts/run --resume %s --dem-hosts ...)" % (", ".join(sorted(set(fault["hosts"]))), run),
              file=sys.stderr)
        return 1
    ckpt = newest_complete(run)
    if not ckpt:
        print("run: --on-fault resume: no complete checkpoint to resume from", file=sys.stderr)
        return 1
    hosts = sorted(set(fault["hosts"]))
    faults = load(run)
    faults.append({
        "kind": fault["kind"],
        "hosts": hosts,
        "ranks": fault["ranks"],
        "step": fault["step"],
        "checkpoint": ckpt,
        "checkpoint_step": int(os.path.basename(ckpt)[len("step_"):]),
        "redo_s": round(s["wall_time_s"] - fault["wall_time_at_checkpoint_s"], 3),
        "detected_at_epoch_s": os.path.getmtime(summary),
    })
    save(run, faults)
    what = "did not answer" if fault["kind"] == "no_reply" else "died"
    print("run: fault %d: DEM rank(s) %s on host(s) %s %s after step %d; resuming from %s"
          % (len(faults), ", ".join(map(str, fault["ranks"])), ", ".join(hosts), what,
             fault["step"], os.path.basename(ckpt)), file=sys.stderr)
    # A rank that died on mpm_app's host was probed there: the host runs. A silent host goes.
    if fault["kind"] == "no_reply":
        print(" ".join(hosts))
    return 0


def restarted(run, epoch):
    faults = load(run)
    if faults and "relaunch_s" not in faults[-1]:
        f = faults[-1]
        f["relaunch_s"] = round(float(epoch) - f["detected_at_epoch_s"], 3)
        f["wall_time_lost_s"] = round(f["redo_s"] + f["relaunch_s"], 3)
        save(run, faults)
    return 0


def merge(run):
    summary = os.path.join(run, "summary.json")
    if not os.path.exists(summary):
        return 0
    s = read_summary(summary)
    s["faults"] = load(run)
    with open(summary + ".tmp", "w") as f:
        json.dump(s, f, indent=2)
        f.write("\n")
    os.replace(summary + ".tmp", summary)
    return 0


if __name__ == "__main__":
    cmd, args = sys.argv[1], sys.argv[2:]
    sys.exit({"record": record, "restarted": restarted, "merge": merge}[cmd](*args))

#!/usr/bin/python3
"""A client of the coupling protocol written from docs/protocol.md alone (not from the C++).

It plays mpm_app's part against `dem_app --backend elastic`: finds the server's port,
connects, runs the handshake with its own config hash, initialises N RVEs, runs steps with
known incremental deformation gradients dF (a distinct one per RVE, so that a partition or
ordering error shows), one step with kFlagQueryOnly / kFlagSkip requests, a kRebalance when
the server has two or more ranks, a kCheckpoint (and reads the files the elastic backend
wrote), then kShutdown. Every reply is checked against the closed-form linear-elastic law
(docs/protocol.md, "The elastic stub backend") to REL_TOL relative.

Usage:
  reference_client.py --print-config-hash SCENE      # like dem_app --print-config-hash (no MPI)
  mpirun ... -np 1 reference_client.py --scene SCENE --run-dir DIR [--n N] [--steps S]
Exit codes: 0 all checks passed; 1 a check failed (the client sent kAbort); 3 handshake
refused; 4 no server, an MPI failure or a server rank that stopped answering.

Needs Debian's python3-mpi4py, python3-numpy and python3-yaml (run with /usr/bin/python3).
"""
import argparse
import math
import os
import socket
import sys
import time
from pathlib import Path

import numpy as np
import yaml

# --- docs/protocol.md, "Constants" --------------------------------------------------------
VERSION_MAJOR, VERSION_MINOR = 5, 1
MAGIC = 0x4D504D44
K_HELLO, K_INITIALISE, K_STEP, K_CHECKPOINT, K_SHUTDOWN, K_ABORT, K_REBALANCE = 1, 2, 3, 4, 5, 6, 7
OUTPUT_BITS = {"rotation": 1 << 0, "porosity": 1 << 1, "coordination": 1 << 2,
               "unbalanced_force": 1 << 3}
KNOWN_OUTPUTS = 0xF
FLAG_QUERY_ONLY, FLAG_SKIP = 1 << 0, 1 << 1
STATUS_OK, STATUS_NO_CONTACTS = 0, 1  # 2 non-finite, 3 exploding, 4 backend error: fatal
TAG_REPLIES, TAG_REPORT = 41, 42
LABEL_SIZE = 256

# --- docs/protocol.md, "Struct layouts" (native byte order: both sides on one architecture) --
def layout(fields, size):
    names, formats, offsets = zip(*fields)
    dt = np.dtype({"names": names, "formats": formats, "offsets": offsets, "itemsize": size})
    assert dt.itemsize == size
    return dt


HELLO = layout([("magic", "u4", 0), ("version_major", "u2", 4), ("version_minor", "u2", 6),
                ("request_size", "u4", 8), ("reply_size", "u4", 12), ("n_rve", "u8", 16),
                ("n_partitions", "i4", 24), ("outputs", "u4", 28), ("config_hash", "u8", 32),
                ("program", "S16", 40), ("program_version", "S32", 56),
                ("backend", "S32", 88)], 120)
HEADER = layout([("kind", "i4", 0), ("reserved", "i4", 4), ("step", "i8", 8),
                 ("time", "f8", 16), ("dt", "f8", 24), ("path", "S224", 32)], 256)
RVE_INIT = layout([("stress", ("f8", (9,)), 0), ("point", "u8", 72)], 80)
RVE_REQUEST = layout([("dF", ("f8", (9,)), 0), ("dt", "f8", 72), ("flags", "u4", 80),
                      ("reserved", "u4", 84)], 88)
RVE_REPLY = layout([("stress", ("f8", (9,)), 0), ("rotation", ("f8", (3,)), 72),
                    ("porosity", "f8", 96), ("coordination", "f8", 104),
                    ("unbalanced_force", "f8", 112), ("stiffness", "f8", 120),
                    ("cost_s", "f8", 128), ("status", "i4", 136), ("n_substeps", "i4", 140)], 144)
RANK_REPORT = layout([("rank", "i4", 0), ("status", "i4", 4), ("n_faults", "i4", 8),
                      ("first_fault_rve", "i4", 12), ("compute_s", "f8", 16),
                      ("message", "S232", 24)], 256)
RANK_IDENTITY = layout([("rank", "i4", 0), ("pid", "i4", 4), ("host", "S120", 8)], 128)

# --- docs/protocol.md, "The config hash" ---------------------------------------------------
# The generic coupling keys: (type, default). Every other key of the section (a backend's own
# section) enters the text as written in the file.
GENERIC_KEYS = {
    "backend": ("string", "elastic"),
    "outputs": ("string_list", []),
    "service_name": ("string", "mpmdem"),
    "connect_timeout_s": ("double", "60"),
    "peer_timeout_s": ("double", "300"),
    "port_file": ("string", "dem_port.txt"),
    "lazy_tolerance": ("double", "0"),
    "rve_order": ("string", "interleaved"),
    "load_balance": ("map", {"threshold": ("double", "0"),
                             "min_interval_steps": ("int", "50"),
                             "smoothing": ("double", "0.2")}),
}
NULL_TAG = "tag:yaml.org,2002:null"
PLAIN = set("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.+-")


def format_number(v):
    """A double in shortest round-trip form; whole numbers below 1e15 without exponent."""
    if v == 0.0:
        return "0"
    if abs(v) < 1e15 and v == math.trunc(v):
        return "%.0f" % v
    for precision in range(1, 18):
        text = "%.*g" % (precision, v)
        if float(text) == v:
            break
    return text


def scalar_text(s):
    if s and s != "~" and set(s) <= PLAIN:
        return s
    out = []
    for c in s:
        if c == '"':
            out.append('\\"')
        elif c == "\\":
            out.append("\\\\")
        elif c == "\n":
            out.append("\\n")
        elif c == "\t":
            out.append("\\t")
        elif ord(c) < 0x20:
            out.append("\\x%02x" % ord(c))
        else:
            out.append(c)
    return '"' + "".join(out) + '"'


def emit(v):
    """v: None (null), str (a scalar's text), list or dict (keys: emitted text)."""
    if v is None:
        return "~"
    if isinstance(v, str):
        return scalar_text(v)
    if isinstance(v, list):
        return "[" + ", ".join(emit(x) for x in v) + "]"
    items = sorted(v.items(), key=lambda kv: kv[0].encode())
    return "{" + ", ".join(k + ": " + emit(x) for k, x in items) + "}"


def as_written(node):
    """A YAML node as the tree emit() takes: scalars keep their text from the file."""
    if isinstance(node, yaml.ScalarNode):
        return None if node.tag == NULL_TAG else node.value
    if isinstance(node, yaml.SequenceNode):
        return [as_written(x) for x in node.value]
    return {emit(as_written(k)): as_written(v) for k, v in node.value}


def filled(spec, node):
    """The generic keys of `spec` from the mapping `node` (or None), defaults filled in."""
    present = {}
    if isinstance(node, yaml.MappingNode):
        present = {k.value: v for k, v in node.value}
    out = {}
    for name, (kind, default) in spec.items():
        v = present.get(name)
        if v is not None and isinstance(v, yaml.ScalarNode) and v.tag == NULL_TAG:
            v = None
        if kind == "map":
            out[name] = filled(default, v)
        elif kind == "string_list":
            out[name] = [x.value for x in v.value] if v is not None else list(default)
        else:
            text = v.value if v is not None else default
            if kind == "double":
                text = format_number(float(text))
            elif kind == "int":
                text = str(int(text, 10))
            out[name] = text
    return out


def canonical_text(scene):
    with open(scene, encoding="utf-8") as f:
        root = yaml.compose(f)
    coupling = None
    if isinstance(root, yaml.MappingNode):
        for k, v in root.value:
            if k.value == "coupling":
                coupling = v
    text = filled(GENERIC_KEYS, coupling)
    if isinstance(coupling, yaml.MappingNode):
        for k, v in coupling.value:
            if k.value not in GENERIC_KEYS:
                text[emit(as_written(k))] = as_written(v)
    return emit(text)


def fnv1a64(data):
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


# --- the closed-form elastic law (docs/protocol.md, "The elastic stub backend") ------------
def law_update(sigma, dF, E, nu):
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    mu = E / (2.0 * (1.0 + nu))
    eye = np.eye(3)
    H = dF - eye
    E_gl = 0.5 * (H + H.T + H.T @ H)
    e, Q = np.linalg.eigh(E_gl)
    d_eps = Q @ np.diag(0.5 * np.log1p(2.0 * e)) @ Q.T
    dU_inv = Q @ np.diag(1.0 / np.sqrt(1.0 + 2.0 * e)) @ Q.T
    dR = dF @ dU_inv
    s = dR @ (sigma + lam * np.trace(d_eps) * eye + 2.0 * mu * d_eps) @ dR.T
    return 0.5 * (s + s.T)


def rotation(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def increment(k, step, big=False):
    """dF of RVE k in a step: a rotation times a stretch-and-shear, distinct per RVE."""
    rng = np.random.default_rng(1000 * step + k)
    scale = 2e-2 if big else 3e-5  # |E| above / below the law's series limit 1e-3
    G = scale * rng.uniform(-1.0, 1.0, (3, 3))
    return rotation(rng.uniform(-1.0, 1.0, 3), 0.01 * (k + 1)) @ (np.eye(3) + G)


# --- the client's constants and layouts against the tables of docs/protocol.md ------------
# (so that a change to the doc or to this client that leaves them apart fails the test)
TYPE_SIZE = {"int32": 4, "uint32": 4, "uint16": 2, "int64": 8, "uint64": 8, "double": 8, "char": 1}


def doc_tables(doc):
    import re
    values, structs, current = {}, {}, None
    for line in Path(doc).read_text(encoding="utf-8").splitlines():
        m = re.match(r"^`(\w+)` \((\d+) B\):$", line)
        if m:
            current = structs.setdefault(m.group(1), {"size": int(m.group(2)), "fields": []})
            continue
        m = re.match(r"^\| (\d+) \| `(\w+)(?:\[(\d+)\])?` \| `(\w+)` \|", line)
        if m and current is not None:
            size = TYPE_SIZE[m.group(2)] * int(m.group(3) or 1)
            current["fields"].append((m.group(4), int(m.group(1)), size))
            continue
        if not line.startswith("|"):
            current = None if line.strip() else current
        m = re.match(r"^\| `(k\w+)` \| (?:`1 << \d+` = )?`?(0x[0-9A-Fa-f]+|\d+)`? \|", line)
        if m:
            values[m.group(1)] = int(m.group(2), 0)
        m = re.match(r"^\s+\| `([\w.]+)` \| (choice|string|list of strings|number|integer|map) "
                     r"\| `?([^`|]*)`? \|$", line)
        if m:
            values["coupling." + m.group(1)] = (m.group(2), m.group(3))
            continue
        m = re.match(r"^\| tag of a server rank's (replies|`RankReport`) .*\| (\d+) \|$", line)
        if m:
            values["tag " + m.group(1).strip("`")] = int(m.group(2))
    return values, structs


def check_doc(doc):
    values, structs = doc_tables(doc)
    mine = {"kVersionMajor": VERSION_MAJOR, "kVersionMinor": VERSION_MINOR, "kMagic": MAGIC,
            "kHello": K_HELLO, "kInitialise": K_INITIALISE, "kStep": K_STEP,
            "kCheckpoint": K_CHECKPOINT, "kShutdown": K_SHUTDOWN, "kAbort": K_ABORT,
            "kRebalance": K_REBALANCE, "kOutputRotation": OUTPUT_BITS["rotation"],
            "kOutputPorosity": OUTPUT_BITS["porosity"],
            "kOutputCoordination": OUTPUT_BITS["coordination"],
            "kOutputUnbalancedForce": OUTPUT_BITS["unbalanced_force"],
            "kKnownOutputs": KNOWN_OUTPUTS, "kFlagQueryOnly": FLAG_QUERY_ONLY,
            "kFlagSkip": FLAG_SKIP, "kOk": STATUS_OK, "kNoContacts": STATUS_NO_CONTACTS,
            "kNonFinite": 2, "kExploding": 3, "kBackendError": 4,
            "tag replies": TAG_REPLIES, "tag RankReport": TAG_REPORT}
    kinds = {"string": "string", "double": "number", "int": "integer", "string_list": "list of strings"}

    def generic(spec, prefix):
        for key, (kind, default) in spec.items():
            if kind == "map":
                yield prefix + key, ("map", values.get(prefix + key, ("map", ""))[1])
                yield from generic(default, prefix + key + ".")
            else:
                doc_kind = values.get(prefix + key, ("",))[0]
                shown = "choice" if doc_kind == "choice" and kind == "string" else kinds[kind]
                yield prefix + key, (shown, "[]" if default == [] else default)

    mine.update(generic(GENERIC_KEYS, "coupling."))
    problems = [f"{k}: client {v}, doc {values.get(k)}" for k, v in mine.items()
                if values.get(k) != v]
    problems += [f"the doc has {k} = {v}, the client does not" for k, v in values.items()
                 if k not in mine]
    layouts = {"Hello": HELLO, "ControlHeader": HEADER, "RveInit": RVE_INIT,
               "RveRequest": RVE_REQUEST, "RveReply": RVE_REPLY, "RankReport": RANK_REPORT,
               "RankIdentity": RANK_IDENTITY}
    for name, dt in layouts.items():
        doc_struct = structs.get(name)
        if doc_struct is None:
            problems.append(f"the doc has no layout table of {name}")
            continue
        got = [(f, dt.fields[f][1], dt.fields[f][0].itemsize) for f in dt.names]
        if doc_struct["size"] != dt.itemsize or doc_struct["fields"] != got:
            problems.append(f"{name}: client {dt.itemsize} B {got}, doc {doc_struct}")
    problems += [f"the doc has a layout of {k}, the client does not" for k in structs
                 if k not in layouts]
    return problems


class Failed(Exception):
    """A check failed: the client aborts the run (kAbort)."""


class Lost(Exception):
    """The server stopped answering: nothing to abort."""


class Client:
    def __init__(self, MPI, args):
        self.MPI = MPI
        self.args = args
        self.inter = None
        self.peers = None
        self.host = socket.gethostname()

    # Waits without a blocking call: probe the server ranks on this host, bound the wait.
    def wait(self, requests, what, limit_s=30.0):
        MPI = self.MPI
        t0 = time.monotonic()
        while not MPI.Request.Testall(requests):
            time.sleep(0.001)
            for p in self.peers if self.peers is not None else []:
                if p["host"].decode() == self.host:
                    try:
                        os.kill(int(p["pid"]), 0)
                    except ProcessLookupError:
                        raise Lost(f"DEM server rank {p['rank']} (pid {p['pid']}) died during {what}")
            if time.monotonic() - t0 > limit_s:
                raise Lost(f"no answer from the DEM server within {limit_s} s during {what}")

    def connect(self, cfg):
        MPI = self.MPI
        port_file = Path(self.args.run_dir) / cfg["port_file"]
        deadline = time.monotonic() + float(cfg["connect_timeout_s"])
        port = None
        while port is None:
            if port_file.is_file():
                line = port_file.read_text().split("\n")[0]
                if line:
                    port = line
                    break
            try:
                port = MPI.Lookup_name(cfg["service_name"])
                break
            except MPI.Exception:
                pass
            if time.monotonic() > deadline:
                print(f"reference_client: no DEM server found (service {cfg['service_name']}, "
                      f"port file {port_file})", file=sys.stderr)
                sys.exit(4)
            time.sleep(0.2)
        self.inter = MPI.COMM_WORLD.Connect(port, MPI.INFO_NULL, 0)
        self.inter.Set_errhandler(MPI.ERRORS_RETURN)
        self.n_servers = self.inter.Get_remote_size()

    def handshake(self, n_rve, outputs, config_hash, backend):
        MPI, inter = self.MPI, self.inter
        mine = np.zeros(1, HELLO)
        mine["magic"], mine["version_major"], mine["version_minor"] = MAGIC, VERSION_MAJOR, VERSION_MINOR
        mine["request_size"], mine["reply_size"] = RVE_REQUEST.itemsize, RVE_REPLY.itemsize
        mine["n_rve"], mine["n_partitions"], mine["outputs"] = n_rve, self.n_servers, outputs
        mine["config_hash"] = config_hash
        mine["program"], mine["program_version"], mine["backend"] = b"ref_client.py", b"1", backend.encode()
        server = np.zeros(1, HELLO)
        inter.Bcast([mine, MPI.BYTE], root=MPI.ROOT)  # blocking, client first
        inter.Bcast([server, MPI.BYTE], root=0)
        s = server[0]
        if s["magic"] == MAGIC and s["version_major"] == VERSION_MAJOR:
            label = bytearray(LABEL_SIZE)
            text = self.args.scene.encode()[: LABEL_SIZE - 1]
            label[: len(text)] = text
            theirs = bytearray(LABEL_SIZE)
            inter.Bcast([label, MPI.CHAR], root=MPI.ROOT)
            inter.Bcast([theirs, MPI.CHAR], root=0)
            print("server's config label: " + theirs.split(b"\0")[0].decode())
        problems = []
        if s["magic"] != MAGIC:
            problems.append(f"magic {s['magic']:#x}")
        elif s["version_major"] != VERSION_MAJOR:
            problems.append(f"major version {s['version_major']}")
        else:
            if (s["request_size"], s["reply_size"]) != (RVE_REQUEST.itemsize, RVE_REPLY.itemsize):
                problems.append(f"struct sizes {s['request_size']}/{s['reply_size']}")
            if s["n_rve"] not in (0, n_rve):
                problems.append(f"n_rve {s['n_rve']}")
            if s["n_partitions"] != self.n_servers:
                problems.append(f"n_partitions {s['n_partitions']} vs {self.n_servers}")
            if outputs & ~int(s["outputs"]):
                problems.append(f"outputs {outputs:#x} not in {s['outputs']:#x}")
            if s["backend"] != backend.encode():
                problems.append(f"backend {s['backend']!r}")
            if s["config_hash"] != config_hash:
                problems.append(f"config hash: mine {config_hash:016x}, server {int(s['config_hash']):016x}")
        if problems:
            print("reference_client: handshake refused: " + "; ".join(problems), file=sys.stderr)
            inter.Disconnect()
            sys.exit(3)
        if s["version_minor"] != VERSION_MINOR:
            print(f"note: server speaks {s['version_major']}.{s['version_minor']}")
        self.peers = np.zeros(self.n_servers, RANK_IDENTITY)
        inter.Gather(None, [self.peers, MPI.BYTE], root=MPI.ROOT)
        for r, p in enumerate(self.peers):
            if p["rank"] != r:
                raise Failed(f"RankIdentity {r} names rank {p['rank']}")
        print(f"connected to {self.n_servers} server rank(s): " +
              ", ".join(f"rank {p['rank']} pid {p['pid']} on {p['host'].decode()}" for p in self.peers))

    def header(self, kind, step=0, time_s=0.0, dt=0.0, path=b""):
        h = np.zeros(1, HEADER)
        h["kind"], h["step"], h["time"], h["dt"], h["path"] = kind, step, time_s, dt, path
        self.wait([self.inter.Ibcast([h, self.MPI.BYTE], root=self.MPI.ROOT)], f"header {kind}")

    def reports(self, what):
        MPI = self.MPI
        rep = np.zeros(self.n_servers, RANK_REPORT)
        T = MPI.BYTE.Create_contiguous(RANK_REPORT.itemsize).Commit()
        reqs = [self.inter.Irecv([rep[r:r + 1], 1, T], source=r, tag=TAG_REPORT)
                for r in range(self.n_servers)]
        self.wait(reqs, what + " (reports)")
        T.Free()
        for r, x in enumerate(rep):
            if x["rank"] != r or x["status"] not in (STATUS_OK, STATUS_NO_CONTACTS):
                raise Failed(f"{what}: rank {r} reports status {x['status']} "
                             f"(RVE {x['first_fault_rve']}): {x['message'].decode()}")
        return rep

    def exchange(self, kind, items, item_type, counts, displs, step=0, dt=0.0):
        MPI = self.MPI
        self.header(kind, step=step, dt=dt)
        T_item = MPI.BYTE.Create_contiguous(item_type.itemsize).Commit()
        T_reply = MPI.BYTE.Create_contiguous(RVE_REPLY.itemsize).Commit()
        self.wait([self.inter.Iscatterv([items, counts, displs, T_item], None, root=MPI.ROOT)],
                  f"scatter of exchange {kind}")
        replies = np.zeros(len(items), RVE_REPLY)
        reqs = [self.inter.Irecv([replies[d:d + c], c, T_reply], source=r, tag=TAG_REPLIES)
                for r, (c, d) in enumerate(zip(counts, displs))]
        self.wait(reqs, f"replies of exchange {kind}")
        T_item.Free()
        T_reply.Free()
        self.reports(f"exchange {kind} step {step}")
        return replies

    def rebalance(self, offsets, step):
        MPI = self.MPI
        self.header(K_REBALANCE, step=step)
        buf = np.array(offsets, dtype=np.uint64)
        self.wait([self.inter.Ibcast([buf, MPI.UINT64_T], root=MPI.ROOT)], "rebalance offsets")
        self.reports("rebalance")

    def abort(self, reason):
        try:
            self.header(K_ABORT, path=reason.encode()[:223])
            self.inter.Disconnect()
        except Exception:  # the connection is broken: give it up
            pass


def partition(n, parts):
    counts = [n // parts + (1 if r < n % parts else 0) for r in range(parts)]
    return counts, [sum(counts[:r]) for r in range(parts)]


def check(replies, expected, stiffness, what):
    worst = 0.0
    for k, (rep, sig) in enumerate(zip(replies, expected)):
        got = rep["stress"].reshape(3, 3)  # row-major
        err = np.abs(got - sig).max() / np.abs(sig).max()
        worst = max(worst, err)
        if err > REL_TOL:
            raise Failed(f"{what}: RVE {k}: stress differs from the law by {err:.3g} relative:\n"
                         f"{got}\nexpected\n{sig}")
        if rep["status"] != STATUS_OK or rep["n_substeps"] != 0:
            raise Failed(f"{what}: RVE {k}: status {rep['status']}, n_substeps {rep['n_substeps']}")
        if abs(rep["stiffness"] - stiffness) > REL_TOL * stiffness:
            raise Failed(f"{what}: RVE {k}: stiffness {rep['stiffness']!r}, expected {stiffness!r}")
        if rep["rotation"].any() or rep["porosity"] or rep["coordination"] or rep["unbalanced_force"]:
            raise Failed(f"{what}: RVE {k}: an output that was not asked for is not zero")
    return worst


REL_TOL = 1e-13


def run(args):
    text = canonical_text(args.scene)
    config_hash = fnv1a64(text.encode())
    scene = yaml.safe_load(open(args.scene, encoding="utf-8"))
    c = scene.get("coupling") or {}
    cfg = {"port_file": c.get("port_file", "dem_port.txt"),
           "service_name": c.get("service_name", "mpmdem"),
           "connect_timeout_s": c.get("connect_timeout_s", 60)}
    E = float(c["elastic"]["youngs_modulus"])
    nu = float(c["elastic"]["poisson_ratio"])
    outputs = 0
    for name in c.get("outputs") or []:
        outputs |= OUTPUT_BITS[name]
    stiffness = E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))

    import mpi4py
    mpi4py.rc.thread_level = "funneled"
    from mpi4py import MPI

    client = Client(MPI, args)
    client.connect(cfg)
    n = args.n
    worst = 0.0
    try:
        client.handshake(n, outputs, config_hash, c.get("backend", "elastic"))
        counts, displs = partition(n, client.n_servers)
        # kInitialise: a distinct starting stress per RVE (slot k holds point n-1-k: the order
        # on the wire is the client's).
        sigma = []
        init = np.zeros(n, RVE_INIT)
        for k in range(n):
            s = -1e5 * (1.0 + 0.1 * k) * np.eye(3)
            s[0, 1] = s[1, 0] = 2e3 * (k + 1)
            s[1, 2] = s[2, 1] = -1e3 * k
            init[k]["stress"] = s.reshape(9)
            init[k]["point"] = n - 1 - k
            sigma.append(s)
        replies = client.exchange(K_INITIALISE, init, RVE_INIT, counts, displs)
        worst = max(worst, check(replies, sigma, stiffness, "kInitialise"))

        dt = 1e-3
        step = 0
        rebalanced = False
        for step in range(1, args.steps + 1):
            req = np.zeros(n, RVE_REQUEST)
            for k in range(n):
                flags = 0
                if step == 3:  # one step with query-only and skipped RVEs: nothing applied
                    flags = (0, FLAG_QUERY_ONLY, FLAG_SKIP)[k % 3]
                dF = increment(k, step, big=step == 2)
                req[k]["dF"], req[k]["dt"], req[k]["flags"] = dF.reshape(9), dt, flags
                if not flags:
                    sigma[k] = law_update(sigma[k], dF, E, nu)
            replies = client.exchange(K_STEP, req, RVE_REQUEST, counts, displs, step=step, dt=dt)
            worst = max(worst, check(replies, sigma, stiffness, f"step {step}"))
            if step == args.steps // 2 and client.n_servers >= 2 and not rebalanced:
                # Rank 0 gives all but one of its RVEs to rank 1 (still contiguous).
                offsets = [0, 1] + [displs[r] for r in range(2, client.n_servers)] + [n]
                client.rebalance(offsets, step)
                counts = [offsets[r + 1] - offsets[r] for r in range(client.n_servers)]
                displs = offsets[:-1]
                rebalanced = True
                print(f"rebalanced after step {step}: offsets {offsets}")

        # kCheckpoint: every rank writes elastic_rank<r>.bin under run-dir/ckpt.
        client.header(K_CHECKPOINT, step=step, path=b"ckpt")
        client.reports("checkpoint")
        ckpt = Path(args.run_dir) / "ckpt"
        seen = set()
        for r in range(client.n_servers):
            data = (ckpt / f"elastic_rank{r}.bin").read_bytes()
            if data[:8] != b"MPMDELA1":
                raise Failed(f"elastic_rank{r}.bin: magic {data[:8]!r}")
            first, count = np.frombuffer(data, np.uint64, 2, 8)
            if (first, count) != (displs[r], counts[r]):
                raise Failed(f"elastic_rank{r}.bin holds RVEs [{first}, +{count}), rank {r} "
                             f"owns [{displs[r]}, +{counts[r]})")
            stresses = np.frombuffer(data, np.float64, 9 * int(count), 24).reshape(-1, 9)
            for i, s in enumerate(stresses):
                if not np.array_equal(s, replies[int(first) + i]["stress"]):
                    raise Failed(f"checkpoint of RVE {int(first) + i} differs from its last reply")
                seen.add(int(first) + i)
        if seen != set(range(n)):
            raise Failed(f"the checkpoint holds {len(seen)} of {n} RVEs")
        print(f"checkpoint: {client.n_servers} file(s) under {ckpt}, {n} RVEs equal to the last replies")
    except Failed as e:
        print(f"FAIL: {e}", file=sys.stderr)
        client.abort("reference_client: " + str(e))
        return 1
    except Lost as e:  # MPI_Finalize would wait for the lost peer: end without it
        print(f"FAIL: {e}", file=sys.stderr)
        sys.stderr.flush()
        sys.stdout.flush()
        os._exit(4)

    client.header(K_SHUTDOWN, step=step)
    client.inter.Disconnect()
    print(f"reference client: {n} RVEs, {args.steps} steps, worst relative stress error {worst:.3g} "
          f"(tolerance {REL_TOL:g})")
    return 0


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--print-config-hash", metavar="SCENE")
    p.add_argument("--check-doc", metavar="PROTOCOL_MD",
                   help="compare the client's constants and struct layouts with the doc's tables")
    p.add_argument("--scene")
    p.add_argument("--run-dir")
    p.add_argument("--n", type=int, default=11)
    p.add_argument("--steps", type=int, default=6)
    args = p.parse_args()
    if args.print_config_hash:
        text = canonical_text(args.print_config_hash)
        print("%016x\n%s" % (fnv1a64(text.encode()), text))
        return 0
    if args.check_doc:
        problems = check_doc(args.check_doc)
        for line in problems:
            print("doc/client mismatch: " + line, file=sys.stderr)
        if not problems:
            print(f"{args.check_doc}: every constant, struct layout and generic coupling key equals the client's")
        return 1 if problems else 0
    if not args.scene or not args.run_dir:
        p.error("--scene and --run-dir are required")
    return run(args)


if __name__ == "__main__":
    sys.exit(main())

"""Resident YADE RVEs of one dem_app rank (driven by the C++ yade backend).

One RveSet per rank. Every scene stays in memory (O.addScene / O.switchToScene); engines are
addressed by index (0 ForceResetter, 1 collider, 2 InteractionLoop, 3 NewtonIntegrator).
The C++ side makes ONE call per exchange: initialise(stress_bytes) or step(dF_bytes, flags),
with the batch as packed float64 bytes, and gets back packed bytes of kReplyWidth doubles per
RVE plus a list of fault messages.

Exact deformation: YADE applies O.cell.velGrad from the step after the one it is set in
(nextVelGrad), and trsf_{k+1} = (I + dt L_k) trsf_k. We track the velGrad already pending
for the next step and, before each substep, choose the one after it from the remaining gap
to trsf_target = dF * trsf_start (exact on the last substep), so that after the burst
O.cell.trsf equals the product of all dF to round-off. Only two velGrad sets per burst are
needed (substeps 1 and ns-1); the last one stays pending (rate continuity), which the next
burst accounts for.
"""
import json
import math
import os
import random
import struct

import mpmdem_packing as pk

REPLY_WIDTH = 18  # stress[9] rot[3] porosity coordination unbalanced stiffness status nsub
OUT_ROT, OUT_POR, OUT_COORD, OUT_UNB = 1, 2, 4, 8
OK, NO_CONTACTS, NON_FINITE, EXPLODING = 0, 1, 2, 3


def _mat(y, a):
    return y.Matrix3(*a)


def make(params_json):
    """Entry point of the C++ backend (the set is also kept in _sets for tests)."""
    _sets.append(RveSet(json.loads(params_json)))
    return _sets[-1]


_sets = []


class RveSet:
    def __init__(self, params):
        """params: dict from the C++ side (coupling.yade.* keys, ids, outputs)."""
        self.p = params
        self.y = pk._import_yade()
        self.ids = list(range(params["first_rve"], params["first_rve"] + params["n_rve"]))
        self.scenes = []  # YADE scene index per RVE
        self.state = []  # per RVE: dict(trsf0, pending, step, p0, packing)
        self.step_no = 0

    # -- helpers ---------------------------------------------------------------------------
    def _packing_for(self, gid):
        names = self.p["packings"]
        if not names:
            return None
        if len(names) == 1:
            return names[0]
        return random.Random(self.p["seed"] * 1000003 + gid).choice(names)

    def _new_scene(self, gid, pressure):
        y = self.y
        O = y.O
        idx = O.addScene()
        O.switchToScene(idx)
        name = self._packing_for(gid)
        if name is None:  # no library: build a small packing in place (tests)
            q = dict(pk.TABLE1)
            q.update(self.p["inline_packing"])
            q["seed"] = int(self.p["seed"]) + gid
            q["pressure"] = max(pressure, 1.0)
            pk.build_into_current_scene(q)
        else:
            O.load(os.path.join(self.p["packing_dir"], name + ".yade.bz2"))
        return idx, name

    def _setup_engines(self, with_triax):
        y = self.y
        O = y.O
        O.engines = pk.engines(y, self.p["damping"], with_triax)

    def _stress(self):
        s = self.y.utils.getStress()
        return 0.5 * (s + s.transpose())

    def _reply(self, k, out, status, nsub, stiffness_needed=True):
        """Fill REPLY_WIDTH doubles for the current scene."""
        y = self.y
        O = y.O
        r = [0.0] * REPLY_WIDTH
        n_contacts = O.interactions.countReal()
        if n_contacts == 0:
            status = status or NO_CONTACTS
        if status == OK:
            s = self._stress()
            vals = [s[i, j] for i in range(3) for j in range(3)]
            if not all(math.isfinite(v) for v in vals):
                status = NON_FINITE
            else:
                r[0:9] = vals
                if stiffness_needed:
                    r[15] = self._stiffness()
        o = self.p["outputs"]
        if status in (OK, NO_CONTACTS):
            if o & OUT_ROT:
                rx = ry = rz = 0.0
                n = 0
                for b in O.bodies:
                    v = b.state.rot()
                    rx += v[0]
                    ry += v[1]
                    rz += v[2]
                    n += 1
                r[9:12] = [rx / n, ry / n, rz / n]
            if o & OUT_POR:
                r[12] = y.utils.porosity()
            if o & OUT_COORD:
                r[13] = y.utils.avgNumInteractions()
            if o & OUT_UNB and n_contacts:
                r[14] = y.utils.unbalancedForce()
        r[16] = float(status)
        r[17] = float(nsub)
        return r, status

    def _stiffness(self):
        """Constrained modulus estimate: max diagonal C_iiii of YADE's Kruyt-Rothenburg tangent
        (utils.getStressAndTangent), floored by the contact-stiffness bound."""
        if self.p["stiffness"] == "tangent":
            _, C = self.y.utils.getStressAndTangent(symmetry=True)
            return max(C[0, 0], C[1, 1], C[2, 2])
        return 0.0

    def _fault(self, gid, status, what):
        names = {NON_FINITE: "non-finite values", EXPLODING: "exploding kinetic energy"}
        return "RVE %d step %d: %s%s" % (gid, self.step_no, names.get(status, "fault"), what)

    # -- protocol calls ---------------------------------------------------------------------
    def initialise(self, stress_bytes):
        """Build/load each RVE and consolidate it to the diagonal of its initial stress."""
        y = self.y
        O = y.O
        n = len(self.ids)
        st = struct.unpack("%dd" % (9 * n), stress_bytes)
        out = []
        faults = []
        for k, gid in enumerate(self.ids):
            sig = st[9 * k : 9 * k + 9]
            goal = [sig[0], sig[4], sig[8]]
            idx, name = self._new_scene(gid, -sum(goal) / 3.0)
            self._setup_engines(True)
            if max(abs(g) for g in goal) > 0:
                q = dict(pk.TABLE1)
                q["stress_tol"] = self.p["consolidation_tol"]
                q["unbalanced_tol"] = self.p["consolidation_unbalanced"]
                q["max_steps"] = self.p["consolidation_max_steps"]
                pk.consolidate(y, goal, q)
            pk.finish_preparation(y)
            self._setup_engines(False)
            self.scenes.append(idx)
            t = O.cell.trsf
            self.state.append({"trsf0": [t[i, j] for i in range(3) for j in range(3)],
                               "pending": [0.0] * 9, "packing": name,
                               "p0": max(abs(sum(goal) / 3.0), 1.0)})
            r, status = self._reply(k, out, OK, 0)
            out.extend(r)
            if status in (NON_FINITE, EXPLODING):
                faults.append(self._fault(gid, status, ""))
        return struct.pack("%dd" % len(out), *out), faults

    def n_substeps(self, dF):
        if self.p["ns_rule"] == "fixed":
            return int(self.p["ns"])
        g = max(abs(dF[3 * i + j] - (1.0 if i == j else 0.0)) for i in range(3) for j in range(3))
        ns = int(math.ceil(self.p["ns_factor"] * g))
        return max(int(self.p["ns_min"]), min(int(self.p["ns_max"]), ns))

    def _burst(self, dF, ns):
        """Apply dF over ns substeps with the velGrad lag corrected (see module doc)."""
        y = self.y
        O = y.O
        dt = O.dt
        target = _mat(y, dF) * O.cell.trsf
        I = y.Matrix3.Identity
        step = O.step
        for j in range(1, ns + 1):
            remaining = ns - j  # steps after this one in the burst
            if j == 1 or remaining == 1:
                # L active during step j is the pending one; predict trsf after step j, and
                # set the next one: uniform over the rest (j=1) or exact (j=ns-1). In between
                # the active velGrad simply persists, so plain O.step() calls suffice.
                L = _mat(y, self._pending)
                after = (I + L * dt) * O.cell.trsf
                nxt = (target * after.inverse() - I) / (remaining * dt)
                O.cell.velGrad = nxt
                self._pending = [nxt[a, b] for a in range(3) for b in range(3)]
            step()
        # The last L stays pending (rate continuity): the next burst accounts for it.

    def step(self, dF_bytes, flags_bytes, step_no):
        y = self.y
        O = y.O
        n = len(self.ids)
        dFs = struct.unpack("%dd" % (9 * n), dF_bytes)
        flags = struct.unpack("%dI" % n, flags_bytes)
        self.step_no = step_no
        out = []
        faults = []
        for k, gid in enumerate(self.ids):
            O.switchToScene(self.scenes[k])
            s = self.state[k]
            ns = 0
            if not (flags[k] & 1):
                dF = dFs[9 * k : 9 * k + 9]
                ns = self.n_substeps(dF)
                self._pending = s["pending"]
                self._burst(dF, ns)
                s["pending"] = self._pending
            status = OK
            ke = y.utils.kineticEnergy()
            if not math.isfinite(ke):
                status = NON_FINITE
            elif ke / O.cell.volume > self.p["ke_threshold"] * s["p0"]:
                status = EXPLODING
            r, status = self._reply(k, out, status, ns)
            out.extend(r)
            if status in (NON_FINITE, EXPLODING):
                faults.append(self._fault(gid, status, " (kinetic energy %g J)" % ke))
        return struct.pack("%dd" % len(out), *out), faults

    def trsf(self, k):
        """Cell transformation of local RVE k relative to its start: trsf * trsf0^-1."""
        y = self.y
        y.O.switchToScene(self.scenes[k])
        m = y.O.cell.trsf * _mat(y, self.state[k]["trsf0"]).inverse()
        return [m[i, j] for i in range(3) for j in range(3)]

    # -- checkpoint -------------------------------------------------------------------------
    def checkpoint(self, d):
        O = self.y.O
        os.makedirs(d, exist_ok=True)
        for k, gid in enumerate(self.ids):
            O.switchToScene(self.scenes[k])
            path = os.path.join(d, "rve_%d.yade.bz2" % gid)
            O.save(path)
            # Continue from the saved state itself: a reload rebuilds the interaction container
            # and collider in load order, so a later restart follows the same summation order
            # (bitwise-identical stresses; without it they differ at ~1e-11 relative).
            O.load(path)
            with open(os.path.join(d, "rve_%d.json" % gid), "w") as f:
                json.dump(dict(self.state[k], id=gid, step=self.step_no), f)

    def restore(self, d):
        O = self.y.O
        self.scenes = []
        self.state = []
        for gid in self.ids:
            with open(os.path.join(d, "rve_%d.json" % gid)) as f:
                s = json.load(f)
            idx = O.addScene()
            O.switchToScene(idx)
            O.load(os.path.join(d, "rve_%d.yade.bz2" % gid))
            self.scenes.append(idx)
            self.step_no = s.pop("step")
            s.pop("id")
            self.state.append(s)

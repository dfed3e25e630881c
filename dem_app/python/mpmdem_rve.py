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
O.cell.trsf equals the product of all dF to round-off. The velGrad set before substep ns
(pending for the first substep of the next burst) is this burst's mean rate (dF - I)/(ns dt):
rate continuity. Keeping the exact last correction pending instead made the rate of the
next burst's substeps alternate, and grow without bound under increments that alternate in
sign at ns = 2 (docs/dem_backend.md, "velGrad lag at ns = 2").
"""
import glob
import json
import math
import os
import pickle
import random
import struct
import time

import mpmdem_packing as pk

REPLY_WIDTH = 19  # stress[9] rot[3] porosity coordination unbalanced stiffness status nsub cost
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
        self._dmax = {}  # largest sphere diameter per RVE (cell regularisation)
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

    def _new_scene(self, point, pressure):
        y = self.y
        O = y.O
        idx = O.addScene()
        O.switchToScene(idx)
        name = self._packing_for(point)
        if name is None:  # no library: build a small packing in place (tests)
            q = dict(pk.TABLE1)
            q.update(self.p["inline_packing"])
            q["seed"] = int(self.p["seed"]) + point
            q["pressure"] = max(pressure, 1.0)
            pk.build_into_current_scene(q)
        else:
            O.load(os.path.join(self.p["packing_dir"], name + ".yade.bz2"))
        if self._law() == "frict_visco":
            pk.to_frict_visco(y, self.p["beta_n"])
        # Large shear (a column's shear band reaches gamma > 1) flattens the periodic cell
        # until a sphere spans half of it and the collider stops. Flipping re-chooses the
        # cell's base vectors (hSize) as an equivalent, less skewed lattice; the integrated
        # transformation trsf (what the exact-dF tracking uses) and the volume are unchanged.
        O.cell.flipFlippable = True
        return idx, name

    def _setup_engines(self, with_triax):
        y = self.y
        O = y.O
        O.engines = pk.engines(y, self.p["damping"], with_triax, self._law())
        # Cells are kept thick enough by tiling (_regularise_cell, every 10th step); between
        # two checks a fast-thinning cell may still dip below two diameters for a few steps:
        # let the collider continue then instead of stopping the run.
        O.engines[1].allowBiggerThanPeriod = True

    def _law(self):
        """coupling.yade.contact_law (frict when the C++ side does not send it)."""
        return self.p.get("contact_law", "frict")

    def _stress_and_stiffness(self, want_stiffness):
        """Love-Weber stress (symmetrised) and, if asked, the stiffness bound (see _stiffness).
        utils.getStressAndTangent returns the same stress as utils.getStress (same loop over
        the same interactions: bitwise equal, measured), so when the stiffness is wanted one
        call gives both (110 us on 800 spheres, vs 45 us for getStress alone)."""
        if want_stiffness:
            s, C = self.y.utils.getStressAndTangent(symmetry=True)
            return 0.5 * (s + s.transpose()), self._stiffness(C)
        s = self.y.utils.getStress()
        return 0.5 * (s + s.transpose()), 0.0

    def _reply(self, k, out, status, nsub, stiffness_needed=True):
        """Fill REPLY_WIDTH doubles for the current scene."""
        y = self.y
        O = y.O
        r = [0.0] * REPLY_WIDTH
        n_contacts = O.interactions.countReal()
        if n_contacts == 0:
            status = status or NO_CONTACTS
        if status == OK:
            want = stiffness_needed and self.p["stiffness"] == "tangent"
            s, stiff = self._stress_and_stiffness(want)
            vals = [s[0, 0], s[0, 1], s[0, 2], s[1, 0], s[1, 1], s[1, 2], s[2, 0], s[2, 1], s[2, 2]]
            if not all(map(math.isfinite, vals)):
                status = NON_FINITE
            else:
                r[0:9] = vals
                r[15] = stiff
        o = self.p["outputs"]
        if o and status in (OK, NO_CONTACTS):
            if o & OUT_ROT:
                # Per-body Python access (~1.1 us per body, ~0.9 ms on 800 spheres): YADE has
                # no C-level sum of state.rot(); it is computed only when the scene asks for it.
                rots = [b.state.rot() for b in O.bodies]
                n = len(rots)
                if n:
                    r[9] = sum(v[0] for v in rots) / n
                    r[10] = sum(v[1] for v in rots) / n
                    r[11] = sum(v[2] for v in rots) / n
            if o & OUT_POR:
                r[12] = y.utils.porosity()
            if o & OUT_COORD:
                r[13] = y.utils.avgNumInteractions()
            if o & OUT_UNB and n_contacts:
                r[14] = y.utils.unbalancedForce()
        r[16] = float(status)
        r[17] = float(nsub)
        return r, status

    def _stiffness(self, C):
        """Upper bound M_b of the constrained (P-wave) modulus of the contact network, from the
        6x6 Kruyt-Rothenburg tangent C of utils.getStressAndTangent (no extra cost).

        The affine (Voigt) modulus of a linear contact network with fixed contacts,
          M_V,i = (1/V) sum_c l^2 n_i^2 [kn n_i^2 + ks (1 - n_i^2)]   (l = branch, n = normal),
        bounds the incremental response from above (the affine field is kinematically
        admissible: relaxation, sliding and lost contacts only lower it). YADE's tangent keeps
        the shear stiffness only along the current shear-force direction t,
          C_ii = (1/V) sum_c l^2 n_i^2 [kn n_i^2 + ks t_i^2]  (t = 0 without shear force),
        so it can fall below M_V. With l parallel to n and t perpendicular to both,
          S_i = C_0i + C_1i + C_2i = (1/V) sum_c kn l^2 n_i^2   (the ks t-terms cancel),
        and with a = max ks/kn <= 1 (FrictPhys: ks/kn lies between the materials' poisson):
          M_V,i <= (1 - a) C_ii + a S_i = M_b,i.
        Returned: max_i M_b,i. Measured (docs/dem_backend.md): 1.03-1.04 M_V, 1.4-1.7x the
        response at ns = 10 and 2.3-3.5x the quasi-static one."""
        a = max((getattr(m, "poisson", 0.0) for m in self.y.O.materials), default=1.0)
        best = 0.0
        for i in range(3):
            S = C[0, i] + C[1, i] + C[2, i]
            b = (1.0 - a) * C[i, i] + a * S if a <= 1.0 else C[i, i] + a * S
            best = max(best, b)
        return best

    def _name(self, k, gid):
        """How messages name RVE k (slot gid): with its material point when that differs."""
        point = self.state[k].get("point", gid)
        return "RVE %d" % gid if point == gid else "RVE %d (material point %d)" % (gid, point)

    def _fault(self, k, gid, status, what):
        names = {NON_FINITE: "non-finite values", EXPLODING: "exploding kinetic energy"}
        return "%s step %d: %s%s" % (self._name(k, gid), self.step_no,
                                     names.get(status, "fault"), what)

    # -- protocol calls ---------------------------------------------------------------------
    def initialise(self, stress_bytes, point_bytes=None):
        """Build/load each RVE and consolidate it to the diagonal of its initial stress.
        point_bytes: RveInit::point of each RVE (protocol 4.0), the name its packing is drawn
        from; without it the RVE's slot (global id) is its name."""
        y = self.y
        O = y.O
        n = len(self.ids)
        st = struct.unpack("%dd" % (9 * n), stress_bytes)
        points = struct.unpack("%dQ" % n, point_bytes) if point_bytes else self.ids
        out = []
        faults = []
        for k, gid in enumerate(self.ids):
            sig = st[9 * k : 9 * k + 9]
            goal = [sig[0], sig[4], sig[8]]
            idx, name = self._new_scene(points[k], -sum(goal) / 3.0)
            self._setup_engines(True)
            if max(abs(g) for g in goal) > 0:
                q = dict(pk.TABLE1)
                q["stress_tol"] = self.p["consolidation_tol"]
                q["unbalanced_tol"] = self.p["consolidation_unbalanced"]
                q["max_steps"] = self.p["consolidation_max_steps"]
                pk.consolidate(y, goal, q)
            pk.finish_preparation(y)
            # coupling.yade.time_step_scale: the updates' DEM step below the packing's 0.5
            # PWaveTimeStep (the consolidation above kept it; 1, the default, leaves it).
            scale = self.p.get("time_step_scale", 1.0)
            if scale != 1.0:
                O.dt = O.dt * scale
            self._setup_engines(False)
            self.scenes.append(idx)
            t = O.cell.trsf
            self.state.append({"trsf0": [t[i, j] for i in range(3) for j in range(3)],
                               "pending": [0.0] * 9, "packing": name, "point": points[k],
                               "p0": max(abs(sum(goal) / 3.0), 1.0)})
            r, status = self._reply(k, out, OK, len(O.bodies))  # protocol 1.1: particles
            out.extend(r)
            if status in (NON_FINITE, EXPLODING):
                faults.append(self._fault(k, gid, status, ""))
        return struct.pack("%dd" % len(out), *out), faults

    def n_substeps(self, dF, dt=0.0):
        """DEM substeps for one update: fixed; proportional to max|dF - I|; or rate, the
        update's dt over the DEM step (the RVE strained at the MPM's rate). Clamped to
        [ns_min, ns_max] as native_backend.cpp's n_substeps."""
        rule = self.p["ns_rule"]
        if rule == "fixed":
            return int(self.p["ns"])
        if rule == "rate":
            if not (math.isfinite(dt) and dt >= 0.0):
                raise ValueError("ns_rule rate: the update's dt is %r s; the client must send a "
                                 "finite dt >= 0 (RveRequest::dt)" % dt)
            want = dt / self.y.O.dt
        else:
            g = max(abs(dF[3 * i + j] - (1.0 if i == j else 0.0))
                    for i in range(3) for j in range(3))
            want = self.p["ns_factor"] * g
        ns = int(math.ceil(min(want, float(self.p["ns_max"]))))
        return max(int(self.p["ns_min"]), ns)

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
            if remaining == 0:
                # Pending for the next burst's first substep: this burst's mean rate (the
                # next burst accounts for it). Step ns still runs with the exact one above.
                self._pending = [(dF[k] - (1.0 if k % 4 == 0 else 0.0)) / (ns * dt)
                                 for k in range(9)]
                O.cell.velGrad = _mat(y, self._pending)
            step()

    def step(self, dF_bytes, flags_bytes, step_no, dt_bytes=None):
        y = self.y
        O = y.O
        n = len(self.ids)
        dFs = struct.unpack("%dd" % (9 * n), dF_bytes)
        flags = struct.unpack("%dI" % n, flags_bytes)
        dts = struct.unpack("%dd" % n, dt_bytes) if dt_bytes else [0.0] * n
        self.step_no = step_no
        out = []
        faults = []
        cache = self.__dict__.setdefault("_last_reply", {})
        for k, gid in enumerate(self.ids):
            t0 = time.perf_counter()
            if flags[k] & 2 and gid in cache:  # kFlagSkip: the last reply, nothing computed
                r = list(cache[gid])
                r[17] = 0.0
                r[18] = time.perf_counter() - t0
                out.extend(r)
                continue
            O.switchToScene(self.scenes[k])
            s = self.state[k]
            ns = 0
            if not (flags[k] & 3):  # neither query-only nor skip (skip without a cached reply)
                dF = dFs[9 * k : 9 * k + 9]
                ns = self.n_substeps(dF, dts[k])
                self._pending = s["pending"]
                self._burst(dF, ns)
                s["pending"] = self._pending
            status = OK
            ke = y.utils.kineticEnergy()
            if not math.isfinite(ke):
                status = NON_FINITE
            elif ke / O.cell.volume > self.p["ke_threshold"] * s["p0"]:
                status = EXPLODING
            self._regularise_cell(k, gid)
            r, status = self._reply(k, out, status, ns)
            r[18] = time.perf_counter() - t0  # this RVE's cost (load balance)
            cache[gid] = r
            out.extend(r)
            if status in (NON_FINITE, EXPLODING):
                faults.append(self._fault(k, gid, status, " (kinetic energy %g J)" % ke))
        return struct.pack("%dd" % len(out), *out), faults

    TILE_HEIGHT = 2.2  # in largest sphere diameters: below this the cell is tiled

    def _regularise_cell(self, k, gid):
        """Keep the periodic cell at least TILE_HEIGHT largest diameters high along every
        lattice direction. The MPM may stretch an element a lot (a spreading column flattens
        its elements to F_zz ~ 0.3): a cell thinner than two diameters is refused by YADE's
        collider, or (allowBiggerThanPeriod) misses contacts with a second image and loses
        its stress. Tiling the packing along the thin lattice vector (every sphere copied one
        period further, the period doubled) is an exact change of the periodic unit: same
        state, same stress, twice the spheres. Contacts are rebuilt by the collider, which
        resets their tangential forces (a small transient). Checked every 10th step (~20 us)."""
        if self.step_no % 10:
            return
        y = self.y
        O = y.O
        h = O.cell.hSize
        cols = [h.col(i) for i in range(3)]
        vol = abs(h.determinant())
        heights = [vol / cols[(i + 1) % 3].cross(cols[(i + 2) % 3]).norm() for i in range(3)]
        i = min(range(3), key=lambda a: heights[a])
        dmax = self._dmax.get(gid)
        if dmax is None:
            dmax = self._dmax[gid] = 2.0 * max(b.shape.radius for b in O.bodies)
        if heights[i] >= self.TILE_HEIGHT * dmax:
            return
        shift = cols[i]
        trsf = y.Matrix3(O.cell.trsf)
        L = y.Matrix3(O.cell.velGrad)
        copies = []
        for b in list(O.bodies):
            c = y.utils.sphere(b.state.pos + shift, b.shape.radius, material=b.material)
            c.state.vel = b.state.vel + L * shift
            c.state.angVel = b.state.angVel
            c.state.ori = b.state.ori
            c.state.refOri = b.state.refOri
            c.state.refPos = b.state.refPos + shift
            copies.append(c)
        O.interactions.clear()
        O.bodies.append(copies)
        hs = y.Matrix3(h)
        for r in range(3):
            hs[r, i] = 2.0 * h[r, i]
        O.cell.hSize = hs
        O.cell.trsf = trsf
        self.tilings = getattr(self, "tilings", 0) + 1
        import sys

        sys.stderr.write(
            "dem_app: %s at step %d: cell %.3g m high along lattice vector %d (< %.1f "
            "largest diameters): packing tiled, %d spheres now\n"
            % (self._name(k, gid), self.step_no, heights[i], i, self.TILE_HEIGHT, len(O.bodies)))
        sys.stderr.flush()

    def n_spheres(self, k):
        """Spheres in local RVE k (grows when its cell is tiled)."""
        self.y.O.switchToScene(self.scenes[k])
        return len(self.y.O.bodies)

    def dem_dt(self, k):
        """DEM time step of local RVE k [s]."""
        self.y.O.switchToScene(self.scenes[k])
        return self.y.O.dt

    def trsf(self, k):
        """Cell transformation of local RVE k relative to its start: trsf * trsf0^-1."""
        y = self.y
        y.O.switchToScene(self.scenes[k])
        m = y.O.cell.trsf * _mat(y, self.state[k]["trsf0"]).inverse()
        return [m[i, j] for i in range(3) for j in range(3)]

    def probe_modulus(self, k, eps=1e-5, ns=10, axis=2):
        """Diagnostic (tests, docs): measured constrained modulus of local RVE k along `axis`.
        Two copies of its scene (O.sceneToString) get dF = I -+ eps e_axis e_axis over ns
        substeps (no lag correction needed: the strain is read from the cells);
        returns (sigma(-) - sigma(+)) / (eps(-) - eps(+)) [Pa] (symmetric: drift and
        second-order terms cancel). The RVE itself is untouched; the two probe scenes are
        reused by later probes."""
        y = self.y
        O = y.O
        O.switchToScene(self.scenes[k])
        blob = O.sceneToString()
        if not hasattr(self, "_probe_scenes"):
            self._probe_scenes = [O.addScene(), O.addScene()]
        sig, eps_log = [], []
        for idx, sign in zip(self._probe_scenes, (-1.0, 1.0)):
            O.switchToScene(idx)
            O.stringToScene(blob)
            t0 = O.cell.trsf[axis, axis]
            L = y.Matrix3.Zero
            L[axis, axis] = math.log(1.0 + sign * eps) / (ns * O.dt)
            O.cell.velGrad = L
            for _ in range(ns):
                O.step()
            O.cell.velGrad = y.Matrix3.Zero
            sig.append(y.utils.getStress()[axis, axis])
            eps_log.append(math.log(O.cell.trsf[axis, axis] / t0))
        O.switchToScene(self.scenes[k])
        return (sig[0] - sig[1]) / (eps_log[0] - eps_log[1])

    # -- checkpoint -------------------------------------------------------------------------
    def checkpoint(self, d):
        O = self.y.O
        os.makedirs(d, exist_ok=True)
        # Replies after a checkpoint come from the reloaded scenes, in this run as in one
        # resumed from it (kFlagSkip's cache is not saved): same path, same bits.
        self._last_reply = {}
        for k, gid in enumerate(self.ids):
            O.switchToScene(self.scenes[k])
            # Uncompressed binary: 3x quicker to save and load than .yade.bz2 (1.5-1.8x the size;
            # docs/outputs.md, "Checkpoints"), the same bits.
            path = os.path.join(d, "rve_%d.yade" % gid)
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
            # Per RVE: d/rve_<id>.*, whichever rank saved it. Checkpoints written before
            # 2026-11 hold d/rank_<r>/rve_<id>.* (the writer's rank, possibly another one).
            src = d
            if not os.path.exists(os.path.join(d, "rve_%d.json" % gid)):
                hits = glob.glob(os.path.join(d, "rank_*", "rve_%d.json" % gid))
                if hits:
                    src = os.path.dirname(hits[0])
            with open(os.path.join(src, "rve_%d.json" % gid)) as f:
                s = json.load(f)
            idx = O.addScene()
            O.switchToScene(idx)
            path = os.path.join(src, "rve_%d.yade" % gid)
            if not os.path.exists(path):  # written before 2026-11 (compressed)
                path += ".bz2"
            O.load(path)
            self.scenes.append(idx)
            self.step_no = s.pop("step")
            s.pop("id")
            self.state.append(s)

    # -- load balance -----------------------------------------------------------------------
    def export(self, gid):
        """The whole state of RVE gid (scene, bookkeeping) as bytes for adopt() elsewhere."""
        k = self.ids.index(gid)
        O = self.y.O
        O.switchToScene(self.scenes[k])
        return pickle.dumps({"scene": O.sceneToString(), "state": self.state[k],
                             "dmax": self._dmax.get(gid)}, protocol=4)

    def adopt(self, first, n, incoming):
        """Own RVEs [first, first + n): keep the ones already here, add the incoming ones
        (gid -> bytes from export), free the scenes of the RVEs that left."""
        O = self.y.O
        ids = list(range(first, first + n))
        here = {gid: k for k, gid in enumerate(self.ids)}
        scenes, state = [], []
        for gid in ids:
            if gid in here:
                scenes.append(self.scenes[here[gid]])
                state.append(self.state[here[gid]])
                continue
            d = pickle.loads(incoming[gid])
            idx = O.addScene()
            O.switchToScene(idx)
            O.stringToScene(d["scene"])
            scenes.append(idx)
            state.append(d["state"])
            if d["dmax"] is not None:
                self._dmax[gid] = d["dmax"]
        keep = set(ids)
        for gid, k in here.items():
            if gid not in keep:
                O.switchToScene(self.scenes[k])
                O.resetThisScene()  # frees the bodies and interactions of an RVE that left
                self._dmax.pop(gid, None)
        self.ids, self.scenes, self.state = ids, scenes, state

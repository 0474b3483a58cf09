"""Fixed-step closed-loop simulation on the generated step function.

One step (plant + controller + actuators, RK4 over dt) is one compiled call; steps run in a C
loop (``runtime/csrc/sim_loop.c``) in chunks, so Python is entered once per chunk (for the
progress bar and the random torques), not once per step.

The noise inputs w (random torques, 000 eq. 5, and measurement noise) are standard-normal
samples drawn in C as a pure function of (seed, step, index) (:mod:`rpo.runtime.run.noise`) and held
over each step: the same seed gives the same run whatever the chunk size, and the same case run
alone or in any lane of a batch gives the same bits.
"""

from __future__ import annotations

import ctypes
import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.model.functions import CompiledFunction
from rpo.runtime.model.loader import Model
from rpo.runtime.run import noise
from rpo.runtime.run.result import Divergence, RunResult

_DP = ctypes.POINTER(ctypes.c_double)

#: Divergence limits per state field (|value| above the limit stops the run).  Quaternions are
#: renormalised every step, so |q_i| > 1 + 1e-6 cannot happen in a healthy run.
DEFAULT_BOUNDS = {
    "q_c": 1 + 1e-6, "q_t": 1 + 1e-6,
    "w_c": 20.0, "w_t": 20.0,           # rad/s: far beyond any spacecraft rate
    "h_w": 1e3,                         # N m s
    "r": 1e8, "v": 1e5,                 # m, m/s
}


def record_grid(last: int, every: int) -> np.ndarray:
    """The steps a run records: every ``every``-th from 0, and always ``last``."""
    G = np.arange(0, last + 1, every)
    return G if G[-1] == last else np.append(G, last)


class Simulation:
    """A closed loop (model + controller + parameters) ready to run from initial states.

    Parameters are given by field name (see ``rpo info`` or the manifest) and default to the
    values recorded in the manifest.
    """

    def __init__(self, model: Model, controller: str = "baseline", params: dict | None = None,
                 gains: dict | None = None, bounds: dict | None = None, *, packed_p: np.ndarray | None = None):
        """``packed_p``: ``model.vector("p", params)`` when the caller has packed it already (the
        pre-flight, from :func:`~rpo.runtime.scenario.initial_state.packed_run_inputs`); the
        Simulation keeps it as its own (not a copy)."""
        entry = model.manifest.controller(controller)
        self.model = model
        self.controller = controller
        self._params_given, self._gains_given = dict(params or {}), dict(gains or {})
        self.p = model.vector("p", params) if packed_p is None else packed_p
        self.k = model.vector(entry.gains, gains)
        self.z_layout = entry.z_layout
        self.y_layout = entry.y_layout
        self.step_fn = model.function(entry.step, p=self.p).clone()
        self._step_covers = self.model.needs([entry.step], self.p)
        self.nz = model.layout_size(self.z_layout)
        self.ny = model.layout_size(self.y_layout)
        self.nw = model.layout_size("w")
        self.dt = float(self.p[model.offsets("p")["dt"]][0])
        if not self.dt > 0:
            raise ModelError(f"dt must be > 0, got {self.dt}")
        self._check_delay(self.p)
        self.bound = np.full(self.nz, np.inf)
        offs = model.offsets(self.z_layout)
        for name, b in {**DEFAULT_BOUNDS, **(bounds or {})}.items():
            if name not in offs:
                raise ModelError(f"bounds: unknown state field {name!r}")
            self.bound[offs[name]] = b

    def _cover(self, P: np.ndarray) -> None:
        """Make the step function one whose library holds the plant copies the parameters ``P`` select
        (a Simulation whose p was changed, or a batch's per-case p, may need another copy)."""
        need = self.model.needs([self.step_fn.name], P)
        if not need <= self._step_covers:
            self.step_fn = self.model.function(self.step_fn.name, p=np.vstack([np.atleast_2d(P), self.p])).clone()
            self._step_covers = self.model.needs([self.step_fn.name], np.vstack([np.atleast_2d(P), self.p]))

    def _check_delay(self, p: np.ndarray) -> None:
        delay = float(p[self.model.offsets("p")["wheel_delay"]][0])
        slots = self.model.manifest.delay_slots
        if not 0 <= delay < slots * self.dt:
            # the delay line holds `slots` past commands; a longer delay cannot be represented
            raise ModelError(f"wheel_delay = {delay} s must be in [0, {slots} dt) = [0, {slots * self.dt:g}) s")

    def _check_run_args(self, z0, duration, t0, record_every, chunk) -> tuple[int, int, int]:
        if not np.isfinite(duration) or not np.isfinite(t0):
            raise ModelError(f"duration and t0 must be finite, got {duration}, {t0}")
        n_total = int(round(duration / self.dt))
        if n_total < 1:
            raise ModelError(f"duration {duration} s is shorter than one step ({self.dt} s)")
        if int(record_every) != record_every or record_every < 1 or int(chunk) != chunk or chunk < 1:
            raise ModelError(f"record_every and chunk must be integers >= 1, got {record_every}, {chunk}")
        if not np.all(np.isfinite(z0)):
            raise ModelError("initial state has non-finite entries")
        return n_total, int(record_every), int(chunk)

    def initial_state(self, plant: dict, controller: dict | None = None) -> np.ndarray:
        """Packed z0 from plant fields (q_c, w_c, h_w, q_t, w_t, r, v; optionally r_T, v_T) and
        controller states.

        Actuator states start at rest (empty delay line, PWPF filters at 0, thrusters off);
        ``m_prop`` starts at 0; the target's ECI state r_T, v_T, unless given, is the parameters'
        Keplerian orbit at t = 0 (a run that starts at another t0 gives them).
        """
        values = {"m_prop": 0.0, **plant, **{f"xc_{k}": v for k, v in (controller or {}).items()}}
        z = np.zeros(self.nz)
        offs = self.model.offsets(self.z_layout)
        if "r_T" in offs and not {"r_T", "v_T"} & set(values):
            # the target's own orbit (plant.target_orbit = "propagated") starts on the Keplerian
            # orbit of the parameters at t = 0: the generated target_orbit's ECI state
            orbit = self.model.functions["target_orbit"](0.0, self.p)
            values["r_T"], values["v_T"] = np.ravel(orbit[5]), np.ravel(orbit[6])
        for name, v in values.items():
            if name not in offs:
                raise ModelError(f"initial state: unknown field {name!r}")
            v = np.atleast_1d(np.asarray(v, float)).ravel()
            if v.size != offs[name].stop - offs[name].start:
                raise ModelError(f"initial state: {name} needs {offs[name].stop - offs[name].start} values")
            z[offs[name]] = v
        for q in ("q_c", "q_t"):
            n = np.linalg.norm(z[offs[q]])
            if abs(n - 1) > 1e-6:
                raise ModelError(f"initial state: {q} must be a unit quaternion (|q| = {n:.9g})")
        # the sensor hold (layout "hold": sensor_<field>, the last value the sensor of <field> gave)
        # starts at the noise-free first measurement (bias included), which a sensor frozen from
        # t = 0 repeats: measured with the freeze windows closed
        hold_offs = self.model.offsets("hold")
        nx = self.model.layout_size("x")
        p_open = self.p.copy()
        freeze = self.model.offsets("p")["fault_sensor_freeze_start"]
        p_open[freeze] = self.model.vector("p")[freeze]  # the manifest default: a window that never opens
        truth = np.concatenate([z[offs[name.removeprefix("sensor_")]] for name in hold_offs])
        m0 = np.ravel(self.model.functions["measure"](z[:nx], truth, 0.0, p_open, np.zeros(self.nw))[1])
        for name, sl in hold_offs.items():
            z[offs[name]] = m0[sl]
        entry = self.model.manifest.controllers[self.controller]
        if entry.xc0 is not None and not controller:
            # the design starts its states from the first (noise-free) measurement
            hold = np.concatenate([z[offs[name]] for name in hold_offs])
            meas = self.model.functions["measure"](z[:nx], hold, 0.0, self.p, np.zeros(self.nw))[0]
            xc0 = np.ravel(self.model.functions[entry.xc0](meas, self.p, self.k)[0])
            first = self.nz - xc0.size  # controller states close the packed state (closed_loop.state_layout)
            z[first:] = xc0
        return z

    def run(self, z0: np.ndarray, duration: float, seed: int = 0, t0: float = 0.0, record_every: int = 1,
            chunk: int = 4096, progress: Callable[[int, int], None] | None = None,
            stop: Callable[[], bool] | None = None) -> RunResult:
        """Run ``round(duration / dt)`` steps from ``z0`` at ``t0``.

        Records every ``record_every``-th state and always the final one; if the run diverges, the
        last good state (with the output of the failing step) is the final row.  ``stop()`` is
        asked after every chunk: True ends the run there (``meta["interrupted"]`` True, the state
        reached is the final row, ``steps_done`` < ``steps_requested``).
        """
        n_total, record_every, chunk = self._check_run_args(z0, duration, t0, record_every, chunk)
        self._cover(self.p)
        seed = noise.check_seed(seed)
        key = noise.key(seed)
        nz, ny = self.nz, self.ny
        Zc = np.empty((chunk + 1, nz))
        Yc = np.empty((chunk, ny))
        # recorded steps: every record_every-th, and always the last one
        G = record_grid(n_total, record_every)
        Z = np.full((G.size, nz), np.nan)
        Y = np.full((G.size, ny), np.nan)
        Z[0] = z0
        z = np.array(z0, float)
        done = 0
        divergence = None
        last_good = None  # (step, state, output) when the run stops early
        interrupted = False
        wall0 = time.perf_counter()
        runner = self._c_runner()
        while done < n_total:
            n = min(chunk, n_total - done)
            Zc[0] = z
            ok, bad = runner(Zc, Yc, key, n, done, t0) if runner else self._py_run(Zc, Yc, seed, n, done, t0)
            # copy recorded rows: global step g = done + i has state Zc[i] and output Yc[i]; the
            # rows of G in [done, done + ok] are kept (slices, no per-step Python)
            lo, hi = np.searchsorted(G, done), np.searchsorted(G, done + ok, side="right")
            idx = G[lo:hi] - done
            Z[lo:hi] = Zc[idx]
            has_y = idx < ok
            Y[lo:hi][has_y] = Yc[idx[has_y]]
            if ok < n:
                last = done + ok
                z_bad = Zc[ok + 1].copy()
                divergence = self._divergence(last, t0, int(bad), z_bad, Zc[ok].copy(), Yc[ok].copy())
                last_good = (last, Zc[ok].copy(), Yc[ok].copy())  # output of the failing step at its start
                done = last
                break
            z = Zc[n].copy()
            done += n
            if progress:
                progress(done, n_total)
            if stop is not None and done < n_total and stop():
                interrupted = True
                break
        keep = int(np.searchsorted(G, done, side="right"))
        G, Z, Y = G[:keep], Z[:keep], Y[:keep]
        if interrupted and G[-1] != done:  # the state reached, off the recording grid: the final row
            G, Z, Y = np.append(G, done), np.vstack([Z, z]), np.vstack([Y, np.full(ny, np.nan)])
        if last_good is not None:
            g, zg, yg = last_good
            if G[-1] == g:
                Y[-1] = yg
            else:  # the last good state was not on the recording grid: keep it as the final row
                G, Z, Y = np.append(G, g), np.vstack([Z, zg]), np.vstack([Y, yg])
        if divergence is None:  # the outputs at the final state (one more evaluation, next state discarded)
            Y[-1] = self._final_output(Z[-1], int(G[-1]), seed, t0)
        T = t0 + G * self.dt
        return RunResult(
            t=T, z=Z, y=Y,
            z_labels=self.model.labels(self.z_layout), z_units=self.model.units(self.z_layout),
            y_labels=self.model.labels(self.y_layout), y_units=self.model.units(self.y_layout),
            steps_done=done, steps_requested=n_total, dt=self.dt,
            wall_time=time.perf_counter() - wall0, divergence=divergence,
            meta={"controller": self.controller, "seed": seed, "record_every": record_every,
                  "backend": self.model.backend, **({"interrupted": True} if interrupted else {})},
            field_labels=self._field_labels(),
        )

    def run_batch(self, Z0: np.ndarray, duration: float, seeds, params=None, gains=None, t0: float = 0.0,
                  record_every: int = 1, chunk: int = 4096,
                  progress: Callable[[int, int], None] | None = None, lanes: bool = True) -> list[RunResult]:
        """Run N cases in lockstep, K at a time (K = :attr:`lanes`, the machine's vector width).

        ``Z0`` (N, nz) initial states; ``seeds`` N random-torque seeds; ``params`` / ``gains``:
        None (this simulation's), one dict of field overrides for every case, a sequence of N
        such dicts (per-case parameters and gains, over this simulation's), or an (N, size) array
        of the packed vectors (layout ``p`` / the controller's gains).  Every case must have
        this simulation's ``dt``.  Returns one :class:`RunResult` per case, each bit-identical to
        ``run(Z0[i], duration, seeds[i], ...)`` with that case's parameters and gains; a case that
        diverges stops (its result says where) and the others go on.  ``progress(done, total)``
        counts run-steps.  ``lanes=False``: the scalar loop, one case after the other (the same
        results; for a batch too short to pay for compiling the lane library).
        """
        Z0 = np.atleast_2d(np.asarray(Z0, float))
        if Z0.ndim != 2 or Z0.shape[1] != self.nz:
            raise ModelError(f"run_batch: Z0 must have shape (N, {self.nz}), got {np.shape(Z0)}")
        n_runs = Z0.shape[0]
        seeds = [noise.check_seed(s) for s in seeds]
        if len(seeds) != n_runs:
            raise ModelError(f"run_batch: {n_runs} initial states but {len(seeds)} seeds")
        P = self._per_case("params", params, n_runs, "p", self._params_given)
        G = self._per_case("gains", gains, n_runs, self.model.manifest.controllers[self.controller].gains,
                           self._gains_given)
        dt_col = self.model.offsets("p")["dt"].start
        for i in range(n_runs):
            if P[i, dt_col] != self.dt:
                raise ModelError(f"run_batch: case {i} has dt = {P[i, dt_col]:g} s; all cases of a batch step "
                                 f"together with dt = {self.dt:g} s")
            self._check_delay(P[i])
        n_total, record_every, chunk = self._check_run_args(Z0, duration, t0, record_every, chunk)
        name = self.step_fn.name
        lane_lib = self.model.lanes([name], P) if self.model.backend == "compiled" and lanes else None
        if lane_lib is None or not lane_lib.has(name):
            # no lane form (CasADi backend, or an operation rpo_math.h lacks): the scalar runs, same results
            return [Simulation._with(self, P[i], G[i]).run(Z0[i], duration, seed=seeds[i], t0=t0,
                                                            record_every=record_every, chunk=chunk)
                    for i in range(n_runs)]
        K = lane_lib.width
        results: list[RunResult | None] = [None] * n_runs
        wall0 = time.perf_counter()
        for b in range(0, n_runs, K):
            idx = list(range(b, min(b + K, n_runs)))
            pad = idx + [idx[-1]] * (K - len(idx))
            block = self._run_block(lane_lib, Z0[pad], [seeds[i] for i in pad], P[pad], G[pad], len(idx), n_total,
                                    t0, record_every, chunk,
                                    None if progress is None else (lambda d, _b=b: progress(_b * n_total + d,
                                                                                            n_runs * n_total)))
            for j, i in enumerate(idx):
                results[i] = block[j]
        wall = time.perf_counter() - wall0
        for i, r in enumerate(results):
            assert r is not None
            r.wall_time = wall / n_runs
            r.meta.update({"seed": seeds[i], "lanes": K, "batch_index": i})
        return [r for r in results if r is not None]

    def _per_case(self, what: str, values, n: int, layout: str, base: dict) -> np.ndarray:
        if isinstance(values, np.ndarray):  # the packed vectors themselves, one row per case
            size = self.model.layout_size(layout)
            if values.shape != (n, size):
                raise ModelError(f"run_batch: {what} as an array must have shape ({n}, {size}), got {values.shape}")
            if not np.all(np.isfinite(values)):
                raise ModelError(f"run_batch: {what} has non-finite entries")
            return np.array(values, float)
        if values is None or isinstance(values, dict):
            v = self.model.vector(layout, {**base, **(values or {})})
            return np.tile(v, (n, 1))
        values = list(values)
        if len(values) != n:
            raise ModelError(f"run_batch: {what} has {len(values)} entries for {n} cases")
        return np.array([self.model.vector(layout, {**base, **(d or {})}) for d in values])

    @staticmethod
    def _with(sim: Simulation, p: np.ndarray, k: np.ndarray) -> Simulation:
        other = object.__new__(Simulation)
        other.__dict__.update(sim.__dict__)
        other.p, other.k = np.array(p), np.array(k)
        return other

    def _run_block(self, lanes, Z0, seeds, P, G, n_real, n_total, t0, record_every, chunk, progress):
        K, nz, ny = lanes.width, self.nz, self.ny
        chunk = max(record_every, (chunk // record_every) * record_every)  # chunks start on the recording grid
        keys = np.array([noise.key(s) for s in seeds], dtype=np.uint64)
        Z = np.ascontiguousarray(Z0, dtype=float)
        P, G = np.ascontiguousarray(P), np.ascontiguousarray(G)
        status = np.zeros(K, dtype=np.intc)
        status[:n_real] = 1
        steps_ok = np.zeros(K, dtype=np.int64)
        bad = np.full(K, -2, dtype=np.intc)
        Zbad, Ylast = np.zeros((K, nz)), np.zeros((K, ny))
        # each run's record, written in place by the C loop: the grid's rows, and one more for the end
        rows = (n_total - 1) // record_every + 2
        Zall = [np.empty((rows, nz)) for _ in range(K)]
        Yall = [np.empty((rows, ny)) for _ in range(K)]
        last_good: list = [None] * K
        fn, sz_w = lanes.pointers[self.step_fn.name], lanes.work[self.step_fn.name]
        call = self._lane_caller(lanes, fn, sz_w, t0, P, G, keys)
        done = 0
        while done < n_total and status.any():
            n = min(chunk, n_total - done)
            row0 = done // record_every  # done is on the grid
            was = status.copy()
            call(done, n, record_every, Z, Zall, Yall, row0, status, steps_ok, bad, Zbad, Ylast)
            for l in range(n_real):
                if was[l] and not status[l]:
                    last_good[l] = (int(steps_ok[l]), Z[l].copy(), Ylast[l].copy(), Zbad[l].copy(), int(bad[l]))
            done += n
            if progress:
                progress(min(done, n_total), n_total)
        # the outputs at each healthy run's final state: one more step of the block from its end
        # states with that step's noise (its next state discarded), as run() does it one run at a
        # time (_final_output); NaN where the step function reports an error
        live = np.array([l < n_real and last_good[l] is None for l in range(K)], dtype=np.intc)
        final = np.full((K, ny), np.nan)
        if live.any():
            Zf, Yf = [np.empty((1, nz)) for _ in range(K)], [np.full((1, ny), np.nan) for _ in range(K)]
            bad_f = np.full(K, -2, dtype=np.intc)
            call(n_total, 1, 1, Z.copy(), Zf, Yf, 0, live, np.zeros(K, dtype=np.int64), bad_f,
                 np.zeros((K, nz)), np.zeros((K, ny)))
            for l in range(n_real):
                if last_good[l] is None and bad_f[l] != -1:
                    final[l] = Yf[l][0]
        out = [self._assemble(Zall[l], Yall[l], Z[l], last_good[l], n_total, t0, record_every, seeds[l])
               for l in range(n_real)]
        for l, r in enumerate(out):
            if r.divergence is None:
                r.y[-1] = final[l]
        return out

    def _lane_caller(self, lanes, fn, sz_w, t0, P, G, keys):
        """``call(k0, n, every, Z, Zrec, Yrec, row0, status, steps_ok, bad, Zbad, Ylast)``: n steps of
        the block from global step k0 by rpo_run_lanes (runtime/csrc/lanes_loop.c), recording into
        rows row0... of each lane's Zrec / Yrec arrays."""
        PP = ctypes.POINTER(_DP)
        nz, ny, nw, K = self.nz, self.ny, self.nw, lanes.width
        fixed = (ctypes.c_void_p(fn), ctypes.c_longlong(sz_w), ctypes.c_double(t0), ctypes.c_double(self.dt))
        pg = (P.ctypes.data_as(_DP), ctypes.c_int(P.shape[1]), G.ctypes.data_as(_DP), ctypes.c_int(G.shape[1]),
              keys.ctypes.data_as(ctypes.POINTER(ctypes.c_ulonglong)), ctypes.c_int(nw))
        bound = self.bound.ctypes.data_as(_DP)

        def call(k0, n, every, Z, Zrec, Yrec, row0, status, steps_ok, bad, Zbad, Ylast):
            zr = (_DP * K)(*[ctypes.cast(a.ctypes.data + row0 * nz * 8, _DP) for a in Zrec])
            yr = (_DP * K)(*[ctypes.cast(a.ctypes.data + row0 * ny * 8, _DP) for a in Yrec])
            rc = lanes.run(*fixed, ctypes.c_longlong(k0), ctypes.c_int(n), ctypes.c_longlong(every), *pg,
                           Z.ctypes.data_as(_DP), ctypes.c_int(nz), ctypes.cast(zr, PP), ctypes.cast(yr, PP),
                           ctypes.c_int(ny), bound, status.ctypes.data_as(ctypes.POINTER(ctypes.c_int)),
                           steps_ok.ctypes.data_as(ctypes.POINTER(ctypes.c_longlong)),
                           bad.ctypes.data_as(ctypes.POINTER(ctypes.c_int)), Zbad.ctypes.data_as(_DP),
                           Ylast.ctypes.data_as(_DP))
            if rc != 0:
                raise MemoryError("rpo_run_lanes could not allocate its work space")

        return call

    def _assemble(self, Zr, Yr, z_end, lg, n_total, t0, record_every, seed) -> RunResult:
        """A :class:`RunResult` from a run's record (the grid's steps: the state at the start and the
        step's output, one spare row) and its end state, laid out as :meth:`run` lays it out."""
        nz, ny = self.nz, self.ny
        divergence = None
        if lg is None:
            G = np.arange(0, n_total, record_every)
            Zr[G.size], Yr[G.size] = z_end, np.nan
            G = np.append(G, n_total)
            Z, Y = Zr[: G.size], Yr[: G.size]
            done = n_total
        else:
            last, zg, yg, z_bad, j = lg
            G = np.arange(0, last + 1, record_every)
            if G.size == 0 or G[-1] != last:  # the last good state is off the grid: one more row
                Zr[G.size], Yr[G.size] = zg, yg
                G = np.append(G, last)
            Z, Y = Zr[: G.size], Yr[: G.size]
            divergence = self._divergence(last, t0, j, z_bad, zg, yg)
            done = last
        assert Z.shape == (G.size, nz) and Y.shape == (G.size, ny)
        return RunResult(
            t=t0 + G * self.dt, z=Z, y=Y,
            z_labels=self.model.labels(self.z_layout), z_units=self.model.units(self.z_layout),
            y_labels=self.model.labels(self.y_layout), y_units=self.model.units(self.y_layout),
            steps_done=done, steps_requested=n_total, dt=self.dt, wall_time=0.0, divergence=divergence,
            meta={"controller": self.controller, "seed": seed, "record_every": record_every,
                  "backend": self.model.backend},
            field_labels=self._field_labels(),
        )

    def _divergence(self, last: int, t0: float, j: int, z_bad: np.ndarray, z_good: np.ndarray,
                    y_bad: np.ndarray) -> Divergence:
        """The report of a run that stopped in step ``last``: ``j`` is the loops' index of the
        offending entry (< nz: the next state ``z_bad``; nz + e: output e of ``y_bad``, the step's
        outputs; -1: the step function failed)."""
        common: dict[str, Any] = dict(step=last, time=t0 + (last + 1) * self.dt, state=z_bad, last_good_state=z_good,
                      output=np.array(y_bad, float))
        if j < 0:
            return Divergence(label="step function", value=float("nan"), bound=float("nan"), where="step", **common)
        if j < self.nz:
            return Divergence(label=self.model.labels(self.z_layout)[j], value=float(z_bad[j]),
                              bound=float(self.bound[j]), **common)
        e = j - self.nz
        return Divergence(label=self.model.labels(self.y_layout)[e], value=float(y_bad[e]), bound=float("inf"),
                          where="output", **common)

    def _field_labels(self) -> Mapping[str, Sequence[str]]:
        """Layout field -> column labels, state fields then outputs (for :class:`RunResult` access)."""
        return self.model.field_labels(self.z_layout, self.y_layout)

    def _final_output(self, z_end: np.ndarray, step: int, seed: int, t0: float) -> np.ndarray:
        """The outputs y at the final state: one more step from ``z_end`` at global ``step`` with
        that step's noise, by the same code path as the run (the C loop when compiled), its next
        state discarded.  NaN if the step function reports an error."""
        Zc, Yc = np.empty((2, self.nz)), np.full((1, self.ny), np.nan)
        Zc[0] = z_end
        runner = self._c_runner()
        if runner:
            _, bad = runner(Zc, Yc, noise.key(seed), 1, step, t0)
        else:
            _, bad = self._py_run(Zc, Yc, seed, 1, step, t0)
        return Yc[0] if bad != -1 else np.full(self.ny, np.nan)

    # -- backends --------------------------------------------------------------------------

    def _c_runner(self):
        run = self.model.run_function
        f = self.step_fn
        if run is None or not isinstance(f, CompiledFunction):
            return None
        if f.sz_arg > 5 or f.sz_res > 2:  # sim_loop.c passes arg[5] and res[2]
            raise ModelError(f"{f.name} needs {f.sz_arg} argument and {f.sz_res} result slots; the loop driver "
                             "passes 5 and 2: rebuild with a matching runtime")
        fn_ptr = ctypes.cast(f.c_function, ctypes.c_void_p)
        bad = ctypes.c_int(0)
        p, k, bound = self.p, self.k, self.bound
        args_fixed = (f._iw_p, f._w_p)

        def runner(Zc, Yc, key, n, k0, t0):
            ok = run(fn_ptr, *args_fixed, ctypes.c_double(t0), ctypes.c_double(self.dt), ctypes.c_longlong(k0),
                     ctypes.c_int(n), p.ctypes.data_as(_DP), k.ctypes.data_as(_DP), ctypes.c_ulonglong(key),
                     ctypes.c_int(self.nw), Zc.ctypes.data_as(_DP), ctypes.c_int(self.nz),
                     Yc.ctypes.data_as(_DP), ctypes.c_int(self.ny), bound.ctypes.data_as(_DP), ctypes.byref(bad))
            return ok, bad.value

        return runner

    def _py_run(self, Zc, Yc, seed, n, k0, t0):
        """Per-step Python loop (CasADi fallback backend), with the NumPy version of the noise."""
        W = noise.noise(seed, k0, n, self.nw)
        for i in range(n):
            t = t0 + (k0 + i) * self.dt
            zn, y = self.step_fn(Zc[i], t, self.p, self.k, W[i])
            Zc[i + 1] = zn
            Yc[i] = y
            bad = ~np.isfinite(zn) | (np.abs(zn) > self.bound)
            if bad.any():
                return i, int(np.argmax(bad))
            bad_y = ~np.isfinite(y)  # the outputs too, after the state, as the C loops check them
            if bad_y.any():
                return i, self.nz + int(np.argmax(bad_y))
        return n, -2

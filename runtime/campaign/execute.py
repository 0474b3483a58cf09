"""Flying a campaign: batches of runs on every local core, or on a Dask cluster.

The cases still to fly are cut into batches (``campaign.batch`` runs, default four blocks of the
machine's lanes).  A batch is one task: :func:`fly_batch` draws its cases, validates each run's
scenario and makes its pre-flight (an invalid draw is recorded, not flown), flies the valid ones
together with the lockstep runner (:meth:`Simulation.run_batch`: K runs per SIMD step, each
bit-identical to the same run alone), computes each run's metrics and verdict from its in-memory
record, writes their histories (one file a batch) and returns the rows.  The parent appends the
rows to ``manifest.jsonl`` (fsynced off the critical path) as batches come back, in whatever
order, and at the end writes ``summary.parquet`` sorted by case: the same bytes with 1 worker, N
workers or Dask.

Executors: ``workers == 1`` flies in this process; otherwise the standard library's
:class:`~concurrent.futures.ProcessPoolExecutor` with ``workers`` processes (default: every core
this process may use); ``dask="local"`` a ``dask.distributed.LocalCluster`` of ``workers``
single-threaded processes; ``dask="tcp://host:8786"`` (any scheduler address) a running cluster,
whose workers need rpo installed and must see the campaign folder (a shared filesystem: they write
the histories there).  A task that fails (an exception, a worker lost) records its runs as status
``error``; ``rpo mc resume`` flies them again.
"""

from __future__ import annotations

import gc
import math
import os
import time
import traceback
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rpo.runtime.campaign import storage
from rpo.runtime.campaign.fingerprint import fingerprint, model_changes
from rpo.runtime.campaign.folder import first_difference
from rpo.runtime.campaign.lock import LOCK, folder_lock
from rpo.runtime.campaign.requirements import write_summary
from rpo.runtime.campaign.spec import DERIVED, Campaign, campaign_from_resolved
from rpo.runtime.errors import CampaignError, RpoError
from rpo.runtime.model.manifest import Manifest
from rpo.runtime.outputs.metrics import UNITS, compute_metrics, error_signals, norm_rows
from rpo.runtime.outputs.verdict import declared_constraints, verdict, violated_constraints
from rpo.runtime.run import interrupts

#: Lane blocks per batch by default: enough runs per task to amortise its start, small enough that
#: the last tasks finish together on every core.
BLOCKS_PER_BATCH = 4


@dataclass
class CampaignOutcome:
    """What :func:`run_campaign` did: the folder, the counts by status and the wall time [s]."""

    folder: Path
    runs: int
    flown_now: int
    counts: dict[str, int]
    wall_s: float
    #: the signal that stopped it (SIGINT, SIGTERM), None when every batch came back
    interrupted: int | None = None
    missing: list[int] = field(default_factory=list)
    #: the manifest lines not counted (storage.scan_manifest), the cases whose history is not verified (no sha256)
    problems: list[str] = field(default_factory=list)
    unverified: list[int] = field(default_factory=list)


# --------------------------------------------------------------------------- the worker side

_MODELS: dict[tuple, Any] = {}
_CAMPAIGNS: dict[str, Campaign] = {}


def worker_model(controller: str) -> Any:
    """The model of this process (loaded once per process and controller)."""
    from rpo.runtime.model.loader import load_model
    key = (controller, os.environ.get("RPO_CACHE_DIR"))
    if key not in _MODELS:
        _MODELS[key] = load_model("auto", controllers=[controller])
    return _MODELS[key]


def _campaign(resolved: dict, manifest: Manifest, key: str) -> Campaign:
    if key not in _CAMPAIGNS:
        _CAMPAIGNS[key] = campaign_from_resolved(resolved, manifest)
    return _CAMPAIGNS[key]


def fly_batch(resolved: dict, key: str, cases: Sequence[int], folder: str,
              model: Any = None, lanes: bool = True) -> list[dict[str, Any]]:
    """Fly ``cases`` of the campaign ``resolved`` (its hash ``key``) and write their histories into
    ``folder``; return one row per case (JSON-ready).  Never raises for a run: a refused draw is
    ``invalid``, anything else that fails is ``error`` with its message."""
    try:
        model = model if model is not None else worker_model(resolved["controller"])
        camp = _campaign(resolved, model.manifest, key)
        return _fly(camp, model, list(cases), Path(folder), lanes)
    except Exception as exc:  # the whole task failed: its runs are recorded as errors, resume re-flies them
        return error_rows(resolved, cases, f"{type(exc).__name__}: {exc}", traceback.format_exc(limit=5))


def error_rows(resolved: dict, cases: Iterable[int], message: str, tb: str | None = None) -> list[dict[str, Any]]:
    """The rows of runs that ended in an error (flown again by resume): ``message``'s first line."""
    extra = {} if tb is None else {"traceback": tb}
    return [{"case": int(c), "seed": run_seed_of(resolved, c), "status": "error", "message": message.splitlines()[0],
             "draws": {}, "outcome": {}, "metrics": {}, **extra} for c in cases]


def run_seed_of(resolved: dict, case: int) -> int:
    from rpo.runtime.campaign.sampling import noise_case, run_seed
    return run_seed(int(resolved["seed"]), noise_case(resolved["sampling"], len(resolved["dispersions"]), int(case)))


def prepare_case(camp: Campaign, model: Any, case: int,
                 draws: dict[str, Any] | None = None) -> tuple[dict, dict[str, Any], Any]:
    """(the row so far, the draw columns, the pre-flight or the refusal text) of one case: its
    draws (``camp.draws(case)`` unless given), its scenario validated as `rpo run` would, and the
    pre-flight checks."""
    from rpo.runtime.run.preflight import preflight
    from rpo.runtime.scenario import validate_scenario

    if draws is None:
        draws = camp.draws(case)
    cols: dict[str, Any] = {}
    for d in camp.dispersions:
        cols.update(d.columns(draws[d.key]))
    row = {"case": case, "seed": camp.seed_of(case), "draws": cols}
    try:
        sc = validate_scenario(camp.case_data(case, draws, share=True), camp.case_source(case), model.manifest,
                               own=True)
        pre = preflight(sc, model)
    except RpoError as exc:
        return row, draws, str(exc)
    return row, draws, pre


def _fly(camp: Campaign, model: Any, cases: list[int], folder: Path, lanes: bool = True) -> list[dict[str, Any]]:
    rows: dict[int, dict] = {}
    ready: list[tuple[int, Any]] = []
    for case, draws in zip(cases, camp.draws_many(cases), strict=True):
        row, _draws, pre = prepare_case(camp, model, case, draws)
        rows[case] = row
        if isinstance(pre, str):
            row.update(status="invalid", message=pre.removeprefix(f"{camp.case_source(case)}: "),
                       outcome={}, metrics={}, draws=_json_draws(row["draws"]))
        else:
            ready.append((case, pre))
    # one lockstep batch per step size (dt is a parameter a campaign may disperse)
    by_dt: dict[float, list[tuple[int, Any]]] = {}
    for case, pre in ready:
        by_dt.setdefault(pre.sim.dt, []).append((case, pre))
    nominal = _nominal_vectors(camp, model)
    for case, pre in ready:
        rows[case]["applied"] = applied(model, pre, nominal)
    histories: dict[int, storage.History] = {}
    units: dict[str, str] = {}
    for group in by_dt.values():
        first = group[0][1]
        results = first.sim.run_batch(np.array([pre.z0 for _, pre in group]), first.inputs.duration,
                                      seeds=[pre.inputs.seed for _, pre in group],
                                      params=np.array([pre.sim.p for _, pre in group]),
                                      gains=np.array([pre.sim.k for _, pre in group]),
                                      record_every=first.inputs.record_every, lanes=lanes)
        for (case, pre), res in zip(group, results, strict=True):
            row, hist, units = run_row(camp, model, pre.inputs, res)
            rows[case].update(row)
            histories[case] = storage.History(case, res.t, hist, {"case": case, "seed": pre.inputs.seed,
                                                                  "status": row["status"]})
    if histories:  # the batch's histories in one file, in case order, before its rows are returned
        name, digest = storage.write_history_file(folder, [histories[c] for c in cases if c in histories], units)
        for c in histories:
            rows[c]["history"] = name
            rows[c]["history_sha256"] = digest
    return [rows[c] for c in cases]


def _json_draws(cols: dict[str, Any]) -> dict[str, Any]:
    """An invalid draw's columns as its manifest line can hold them: a non-finite value (a spread
    wide enough to overflow) as null, since JSON has no inf or NaN; the row's message names the
    value (validation refuses every non-finite entry, so a flown run never has one)."""
    if all(not isinstance(v, float) or math.isfinite(v) for v in cols.values()):
        return cols
    return {k: None if isinstance(v, float) and not math.isfinite(v) else v for k, v in cols.items()}


#: The plant's initial-state fields recorded in each row's ``applied`` (the rest of z0, the
#: actuator and controller states, follows from them and the parameters).
PLANT_STATE = ("q_c", "w_c", "h_w", "q_t", "w_t", "r", "v")
_NOMINAL: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}


def _nominal_vectors(camp: Campaign, model: Any) -> tuple[np.ndarray, np.ndarray] | None:
    """The parameter and gain vectors of the campaign's undispersed scenario (None if refused)."""
    from rpo.runtime.scenario import validate_scenario

    key = (camp.hash, model.manifest.manifest_hash)
    if key not in _NOMINAL:
        sc = validate_scenario(camp.scenario_data, camp.source, model.manifest)
        inputs = sc.to_run(model)
        ctrl = model.manifest.controllers[inputs.controller].gains
        _NOMINAL[key] = (model.vector("p", inputs.params), model.vector(ctrl, inputs.gains))
    return _NOMINAL[key]


def applied(model: Any, pre: Any, nominal: tuple[np.ndarray, np.ndarray] | None) -> dict[str, Any]:
    """What the simulation was handed, read back from the vectors themselves: the plant's initial
    state, and every parameter and gain field whose values differ from the undispersed scenario's
    (the draws, as the model sees them: SI, packed), for the row (and the tests) to check."""
    for name, vec in (("z0", pre.z0), ("p", pre.sim.p), ("k", pre.sim.k)):
        if not np.isfinite(vec).all():  # refused before flying; the manifest line could not hold it
            raise ValueError(f"the {name} handed to the simulation has a non-finite entry after the pre-flight")
    z_offs = model.offsets(pre.sim.z_layout)
    out: dict[str, Any] = {"z0": {f: pre.z0[z_offs[f]].tolist() for f in PLANT_STATE}}
    ctrl = model.manifest.controllers[pre.sim.controller].gains
    for what, vec, layout, base in (("p", pre.sim.p, "p", None if nominal is None else nominal[0]),
                                    ("k", pre.sim.k, ctrl, None if nominal is None else nominal[1])):
        offs = model.offsets(layout)
        if base is None:
            out[what] = {f: vec[sl].tolist() for f, sl in offs.items()}
            continue
        # a field differs where any entry differs (NaN differs from everything, as array_equal has it)
        differs = (vec != base).tolist()
        out[what] = {f: vec[sl].tolist() for f, sl in offs.items() if any(differs[sl])}
    return out


def run_row(camp: Campaign, model: Any, inputs: Any, res: Any) -> tuple[dict[str, Any], dict[str, np.ndarray],
                                                                        dict[str, str]]:
    """(row fields, history columns, their units) of one flown run, from its in-memory record:
    the metrics and verdict of ``rpo run`` (rpo.runtime.outputs.metrics, rpo.runtime.outputs.verdict), the outcome
    flags, the chosen channels and the error signals the envelopes use."""
    cols = dict(zip(res.z_labels, res.z.T, strict=True))  # each column a view of the record
    cols.update(zip(res.y_labels, res.y.T, strict=True))
    goal = np.ravel(inputs.gains["r_goal"]) if "r_goal" in inputs.gains else None
    signals = error_signals(cols, goal, components=False)  # the row needs the error signals only
    met = compute_metrics(res.t, cols, goal=goal, params=inputs.params, per_unit=False, signals=signals)
    ver = verdict(met, res.t, cols, inputs.params, res.divergence, model.manifest.faults)
    goals = ver["goals"]
    att, pos = goals["att"]["reached"], goals["pos"]["reached"]
    # a constraint violated: the verdict's rule (violated_constraints, every run); a failure counts
    # only those the scenario declares ([constraints]: 001's camera cone and envelope spheres; a 000
    # run has no camera): docs/campaigns.md, the report says both
    violated = bool(violated_constraints(ver["constraints"]))
    declared = bool(violated_constraints(ver["constraints"], declared_constraints(camp.scenario_data)))
    diverged = res.divergence is not None
    outcome = {"att_reached": att, "pos_reached": pos, "diverged": diverged, "constraint_violated": violated,
               "failed": bool(diverged or declared or att is False or pos is False)}
    metrics = {k: _finite_or_none(met.get(k)) for k in UNITS}
    sel = _selection(camp, model, inputs.controller)
    ukey = (inputs.controller, model.manifest.manifest_hash)
    units = _UNITS.get(ukey)
    if units is None:  # the record's column units: the same for every run of a controller and model
        units = _UNITS[ukey] = (dict(zip(res.z_labels, res.z_units, strict=True))
                                | dict(zip(res.y_labels, res.y_units, strict=True))
                                | {"err_att_rad": "rad", "err_pos_m": "m", "h_w_norm": "N m s"})
    hist = {lbl: cols[lbl] for lbl in sel.labels}
    sig = signals[0]
    n = res.t.size
    hist["err_att_rad"] = sig["att"] if "att" in sig else np.full(n, np.nan)
    hist["err_pos_m"] = sig["pos"] if "pos" in sig else np.full(n, np.nan)
    hw = [cols[lbl] for lbl in _H_W if lbl in cols]
    hist["h_w_norm"] = norm_rows(*hw) if hw else np.full(n, np.nan)  # |h_w| [N m s]
    assert all(d in hist for d in DERIVED)
    row = {"status": "diverged" if diverged else "ok", "message": res.divergence.message() if diverged else "",
           "outcome": outcome, "metrics": metrics, "verdict": ver["line"]}
    return row, hist, {k: units[k] for k in hist}


_SELECTIONS: dict[tuple, Any] = {}
_UNITS: dict[tuple, dict[str, str]] = {}
_H_W = tuple(f"h_w_{i}" for i in range(1, 5))


def _selection(camp: Campaign, model: Any, controller: str) -> Any:
    """The history's columns (once per campaign, controller and model)."""
    from rpo.runtime.scenario.channels import select
    key = (camp.channels, controller, model.manifest.manifest_hash)
    if key not in _SELECTIONS:
        _SELECTIONS[key] = select(list(camp.channels), model.layouts[f"z_{controller}"],
                                  model.layouts[f"y_{controller}"], strict=False)
    return _SELECTIONS[key]


def _finite_or_none(v: Any) -> float | None:
    if type(v) is float:  # most metrics
        return v if math.isfinite(v) else None
    if v is None or isinstance(v, (dict, list, str)):
        return None
    f = float(v)
    return f if math.isfinite(f) else None


# --------------------------------------------------------------------------- the parent side


def default_workers() -> int:
    """Every core this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def batches(cases: Sequence[int], size: int) -> list[list[int]]:
    return [list(cases[i: i + size]) for i in range(0, len(cases), size)]


def fly_cases(camp: Campaign, model: Any, folder: Path, cases: Sequence[int], *, workers: int = 1,
              dask: str | None = None, batch: int | None = None,
              on_rows: Callable[[list[dict]], None] | None = None) -> int | None:
    """Fly ``cases`` into ``folder``, appending each batch's rows to the manifest as it comes back
    (``on_rows`` sees them too).  None if every batch came back; the signal's number if SIGINT or
    SIGTERM stopped it (the rows recorded so far are kept, the batches in flight are dropped)."""
    resolved, key = camp.resolved(), camp.hash
    use_lanes = lanes_worth_it(camp, model, len(cases))
    lanes = _campaign_lanes(camp, model) if use_lanes else None
    size = batch or camp.settings.batch or BLOCKS_PER_BATCH * (lanes.width if lanes is not None else 8)
    tasks = batches(list(cases), size)

    if not tasks:
        return None
    syncer = storage.Syncer(folder)

    def record(rows: list[dict]) -> None:
        syncer.append(rows)
        if on_rows:
            on_rows(rows)

    try:
        with interrupts.stop_request() as stop, frozen_heap():
            if dask is None and workers <= 1:
                for t in tasks:
                    record(fly_batch(resolved, key, t, str(folder), model=model, lanes=use_lanes))
                    if stop.requested():
                        break
            elif dask is None:
                _warm(camp, model)
                _pool(resolved, key, tasks, folder, workers, record, stop, use_lanes)
            else:
                _dask(resolved, key, tasks, folder, workers, dask, record, stop, use_lanes)
    finally:
        syncer.close()  # every line on disk before the summary is written or the command returns
    return stop.signum


@contextmanager
def frozen_heap() -> Iterator[None]:
    """The objects alive now (the model, its manifest, the imports: ~120,000) out of the garbage
    collector's scans while the campaign flies (:func:`gc.freeze`), back in afterwards.  A batch
    allocates enough to trigger full collections, and each walked them all: ~80 ms each, 0.1-0.3 ms
    a run on one worker.  Pool workers forked meanwhile inherit the frozen heap."""
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


#: Run-steps (runs x steps) from which a campaign compiles the lane library when it is not cached:
#: about 14 s of scalar stepping on one core (7 us per step, scenario III), the time compiling the
#: lane form of the plant's step takes on the 2-core machine.  Shorter campaigns fly the scalar
#: loop (bit-identical results: tests/test_lanes.py); ``rpo build --lanes`` compiles it ahead.
LANES_MIN_RUN_STEPS = 2_000_000


def lanes_worth_it(camp: Campaign, model: Any, n_runs: int) -> bool:
    """Whether the campaign flies in lockstep lanes: when the lane library it needs is built, or
    when ``n_runs`` runs are long enough to pay for compiling it (:data:`LANES_MIN_RUN_STEPS`)."""
    if model.backend != "compiled":
        return False
    controller = camp.scenario_data.get("simulation", {}).get("controller", "baseline")
    nominal = _nominal_vectors(camp, model)
    if controller not in model.manifest.controllers or nominal is None:
        return True
    step = model.manifest.controller(controller).step
    if model.lanes_ready([step], nominal[0]):
        return True
    try:
        sim = camp.scenario_data.get("simulation", {})
        dt = float(nominal[0][model.offsets("p")["dt"]][0])
        steps = float(sim["duration"]) / dt
    except (KeyError, TypeError, ValueError, ZeroDivisionError):
        return True
    return n_runs * steps >= LANES_MIN_RUN_STEPS


def _campaign_lanes(camp: Campaign, model: Any) -> Any:
    """The lane library of the campaign's step with the undispersed parameters' plant copies (a run
    whose draws select another copy has it linked when it flies: Simulation.run_batch), built
    here in the parent so that forked workers find it loaded; None for the CasADi backend."""
    if model.backend != "compiled":
        return None
    controller = camp.scenario_data.get("simulation", {}).get("controller", "baseline")
    if controller not in model.manifest.controllers:
        return model.lanes([])
    nominal = _nominal_vectors(camp, model)
    return model.lanes([model.manifest.controller(controller).step], None if nominal is None else nominal[0])


def _warm(camp: Campaign, model: Any) -> None:
    """What every worker needs, made in the parent before the pool forks it: the imports a batch
    makes on first use (pyarrow's Parquet writer alone is ~0.3 s a process), the undispersed
    vectors and the history's columns."""
    import pyarrow.parquet  # noqa: F401

    _nominal_vectors(camp, model)
    _selection(camp, model, camp.scenario_data.get("simulation", {}).get("controller", "baseline"))
    _campaign(camp.resolved(), model.manifest, camp.hash)


def _pool(resolved, key, tasks, folder, workers, record, stop, lanes: bool = True) -> bool:
    import multiprocessing
    import threading
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
    methods = multiprocessing.get_all_start_methods()
    # fork: the workers start with the model and the lane library already loaded (no import, no
    # load); but forking a process that runs other threads (a Dask client's event loop, say) can
    # copy a lock held by one of them, so then a clean forkserver or spawn start instead
    if "fork" in methods and threading.active_count() == 1:
        method = "fork"
    else:
        method = "forkserver" if "forkserver" in methods else "spawn"
    ctx = multiprocessing.get_context(method)
    pool = ProcessPoolExecutor(max_workers=min(workers, len(tasks)), mp_context=ctx,
                               initializer=_init_worker, initargs=(os.environ.get("RPO_CACHE_DIR"),))
    pending = {pool.submit(fly_batch, resolved, key, t, str(folder), None, lanes): t for t in tasks}
    try:
        while pending:
            done, _ = wait(pending, timeout=0.25, return_when=FIRST_COMPLETED)
            for fut in done:
                t = pending.pop(fut)
                record(_result(fut, resolved, t))
            if stop.requested():
                return False
        return True
    finally:
        _shutdown(pool, bool(pending))


def _init_worker(cache: str | None) -> None:
    import signal
    # the parent decides what a signal means (stop dispatching, keep what came back); a worker
    # killed with the pool is its runs left to resume
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # not the parent's handler: a worker told to stop, stops
    if cache is not None:
        os.environ["RPO_CACHE_DIR"] = cache


def _result(fut: Any, resolved: dict, cases: list[int]) -> list[dict]:
    try:
        return list(fut.result())
    except Exception as exc:  # the worker process died (killed, out of memory): its runs are errors
        return error_rows(resolved, cases, f"worker lost: {type(exc).__name__}: {exc}")


def _shutdown(pool: Any, cancel: bool) -> None:
    if not cancel:
        pool.shutdown(wait=True)
        return
    procs = list(getattr(pool, "_processes", {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for p in procs:  # batches in flight are abandoned: their runs are not in the manifest, resume flies them
        p.terminate()
    for p in procs:
        p.join(timeout=5)


def _dask(resolved, key, tasks, folder, workers, address, record, stop, lanes: bool = True) -> bool:
    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise CampaignError("--dask needs Dask distributed: pip install 'dask[distributed]' "
                            "(or pip install 'rpo[dask]')") from None
    cluster = None
    if address == "local":
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                               env={"RPO_CACHE_DIR": os.environ["RPO_CACHE_DIR"]} if "RPO_CACHE_DIR" in os.environ
                               else None)
        client = Client(cluster)
    else:
        try:
            client = Client(address, timeout=10)
        except (OSError, TimeoutError) as exc:
            raise CampaignError(f"--dask {address}: cannot connect to the scheduler ({exc})") from None
    try:
        futs = {client.submit(fly_batch, resolved, key, t, str(folder), None, lanes, pure=False): t
                for t in tasks}
        ac = as_completed(list(futs))
        for fut in ac:
            record(_result(fut, resolved, futs[fut]))
            if stop.requested():
                for f in futs:
                    f.cancel()
                return False
        return True
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


# --------------------------------------------------------------------------- run and resume


def counts(rows: dict[int, dict]) -> dict[str, int]:
    out = dict.fromkeys(storage.STATUSES, 0)
    for r in rows.values():
        out[r["status"]] = out.get(r["status"], 0) + 1
    return out


def start_folder(camp: Campaign, model: Any, out: str | Path, command: str = "") -> Path:
    """Create the campaign folder (absent or empty: refused otherwise; holding only its lock file
    when the caller locked it first: :mod:`.lock`) with the campaign's text and resolved.json."""
    from rpo.runtime.errors import OutputError
    from rpo.runtime.outputs.writers import check_out_dir
    folder = Path(out)
    if not (folder / LOCK).is_file():
        folder = check_out_dir(out)
    elif any(p.name != LOCK for p in folder.iterdir()):  # made and locked by the caller: nothing else in it
        raise OutputError(f"output folder {folder} is not empty: choose a new folder (--out), or "
                          f"`rpo mc resume {folder}` if it is this campaign's")
    folder.mkdir(parents=True, exist_ok=True)
    (folder / storage.HISTORIES).mkdir(exist_ok=True)
    storage._atomic_write(folder / storage.CAMPAIGN_COPY, camp.text.encode())
    resolved = camp.resolved()
    controller = resolved.get("controller", "baseline")
    storage.write_json(folder / storage.RESOLVED, {**resolved, "hash": camp.hash,
                                                   "model_hash": model.manifest.manifest_hash,
                                                   "model_fingerprint": fingerprint(model, controller),
                                                   "command": command})
    return folder


def run_campaign(camp: Campaign, model: Any, folder: Path, *, cases: Iterable[int] | None = None,
                 workers: int | None = None, dask: str | None = None, batch: int | None = None,
                 on_rows: Callable[[list[dict]], None] | None = None) -> CampaignOutcome:
    """Fly the campaign's ``cases`` (default: every case not yet done, or done with status
    ``error``) into ``folder`` (made by :func:`start_folder`), then write ``summary.parquet``."""
    with folder_lock(folder):  # one command flies a folder at a time
        return _run_locked(camp, model, Path(folder), cases, workers, dask, batch, on_rows)


def _run_locked(camp: Campaign, model: Any, folder: Path, cases: Iterable[int] | None, workers: int | None,
                dask: str | None, batch: int | None, on_rows: Callable[[list[dict]], None] | None) -> CampaignOutcome:
    t0 = time.perf_counter()
    (folder / storage.HISTORIES).mkdir(exist_ok=True)  # removed by hand: the runs that need it fly again
    storage.remove_temporaries(folder)
    done = (scan := storage.scan_manifest(folder, repair=True)).rows
    storage.mark_lost_histories(folder, done)
    todo = sorted(c for c in (range(camp.runs) if cases is None else cases)
                  if c not in done or done[c]["status"] == "error")
    flown: dict[int, dict] = {}

    def collect(batch_rows: list[dict]) -> None:
        flown.update((int(r["case"]), r) for r in batch_rows)
        if on_rows:
            on_rows(batch_rows)

    stopped = fly_cases(camp, model, folder, todo, workers=workers or default_workers(), dask=dask,
                         batch=batch, on_rows=collect)
    # the manifest's latest line per case, as appended (not read back: the summary uses none of
    # what a JSON round trip could change, and draw_columns orders by names, not key order)
    rows = {**done, **flown}
    storage.mark_lost_histories(folder, rows, fresh={r["history"] for r in flown.values() if r.get("history")})
    if stopped is None:  # every batch came back: a history file no row names is a killed batch's
        storage.remove_orphans(folder, rows)
    write_summary(folder, storage.read_resolved(folder), rows)  # storage's, with the requirements' verdicts
    missing = [c for c in range(camp.runs) if c not in rows]
    return CampaignOutcome(folder=folder, runs=camp.runs, flown_now=len(todo), counts=counts(rows),
                           wall_s=time.perf_counter() - t0, interrupted=stopped, missing=missing,
                           problems=scan.problems, unverified=[c for c in scan.unverified if rows[c] is done[c]])


def check_resume(folder: Path, model: Any, camp: Campaign | None) -> Campaign:
    """The campaign of ``folder`` if it can be resumed with this model (and, when given, the
    campaign as read again from its file): refused naming what changed."""
    resolved = storage.read_resolved(folder)
    changed = model_changes(resolved, model)
    if changed:
        raise CampaignError(f"{folder}: the model changed since the campaign started ({changed}): its "
                            "runs would not be comparable; start a new campaign folder")
    try:
        stored = campaign_from_resolved(resolved, model.manifest)
    except (KeyError, TypeError, ValueError) as exc:
        raise CampaignError(f"{folder}/{storage.RESOLVED}: damaged ({type(exc).__name__}: "
                            f"{' '.join(str(exc).split())[:120]}): refusing to resume") from None
    if stored.hash != resolved.get("hash"):
        raise CampaignError(f"{folder}/{storage.RESOLVED}: its content does not match its recorded hash "
                            "(edited?): refusing to resume")
    if camp is not None and camp.hash != stored.hash:
        what = first_difference(stored.resolved(), camp.resolved())
        raise CampaignError(f"{folder}: the campaign changed since it started: {what}; start a new campaign "
                            "folder (or undo the change)")
    return stored


"""The physics-model evidence of a report: the calibration of every gear unit whose drop
model the spec allows, its identification and its sim-to-real gap diagnosis, or plainly why
there is none.

Above :mod:`certkit.physics.calibration`, :mod:`certkit.gear_identification` and
:mod:`certkit.gap.diagnosis`, which it runs; the report only lays out what it returns.

None of these stages is compliance evidence, and none may take the compliance evidence
down: a stage that fails for one gear unit (a fit that meets non-finite residuals, a bound
the model cannot live with, a form that cannot be built, certkit's own bug) becomes a
:class:`StageFailure` that the report states in that stage's appendix, and the other
stages and gear units go on.

The stages of the gear units are independent tasks (per unit: calibration then
identification, which reuses the calibrated model; and the gap diagnosis), run in worker
processes when the machine has more than one core (:func:`workers`).  Each task runs with
one BLAS thread and computes exactly what it computes alone, so the evidence is the same
bytes whatever the number of workers or threads.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field

import numpy as np
from threadpoolctl import threadpool_limits

from certkit.errors import CertkitInputError
from certkit.gap.diagnosis import gap_diagnosis
from certkit.gear_identification import (Identification, identify_gear, not_identified,
                                         plant_note)
from certkit.physics.calibration import (Calibration, calibrate_gear, calibration_runs,
                                         calibration_starts)
from certkit.physics.fitting import FitError
from certkit.physics.gear_model import drop_model_for
from certkit.physics.simulation import SimulationError
from certkit.spec.campaign import Campaign

#: The optional stages, as the report's appendices name them.
CALIBRATION, IDENTIFICATION, GAP = "calibration", "identification", "gap diagnosis"


@dataclass(frozen=True)
class StageFailure:
    """A model stage that could not be computed for one gear unit, in words: why, and what
    to change.  ``internal``: the cause is an error of certkit's own (a bug to report), not
    of the campaign."""

    stage: str
    gear: str
    reason: str
    remedy: str
    internal: bool = False


@dataclass(frozen=True)
class ModelEvidence:
    """What the report's model appendices show: a calibration, or why none."""

    calibration: Calibration | None
    note: str
    synthetic_runs: tuple[str, ...] = ()
    identification: object | None = None   # certkit.gear_identification.Identification
    gap: dict = field(default_factory=dict)  # gear id -> certkit.gap.diagnosis.GapDiagnosis
    gap_notes: tuple[str, ...] = ()          # gear units not diagnosed, and why, in words
    failures: tuple[StageFailure, ...] = ()  # stages that could not be computed
    calibration_starts: int = 0              # further starts of the calibration (the spec's)

    def failed(self, stage: str) -> list[StageFailure]:
        """The failures of ``stage``, in gear-unit order."""
        return [f for f in self.failures if f.stage == stage]


#: What to change when a stage's numerics fail, per stage (a fit or a simulation that
#: meets non-finite values, a bound the model cannot live with).
_NUMERICAL_REMEDY = {
    CALIBRATION: "check the drop model's nominal parameters (gear_units[].strut, "
                 "gear_units[].tyre) against the records, or fit fewer parameters "
                 "(model.calibration.parameters)",
    IDENTIFICATION: "check the recorded load, stroke and tyre channels of the drops, or fix "
                    "the orders and hyper-parameters (model.identification)",
    GAP: "check the drop model's nominal parameters against the records, or choose other "
         "held-out runs (model.gap.held_out)",
}


#: The failures a campaign's data can cause in the numerics (a fit or a simulation meeting
#: non-finite values, an overflow, a singular matrix); any other error is certkit's own.
NUMERICAL = (FitError, SimulationError, FloatingPointError, OverflowError,
             np.linalg.LinAlgError)


def _failure(stage: str, gear: str, error: BaseException) -> StageFailure:
    """``error`` of ``stage`` for ``gear`` in words."""
    if isinstance(error, CertkitInputError):
        reason = " ".join(p.message[:1].upper() + p.message[1:].rstrip(".") + "."
                          for p in error.problems)
        keys = sorted({p.key for p in error.problems if p.key})
        return StageFailure(stage, gear, reason,
                            "correct the spec as stated" + (f" ({', '.join(keys)})"
                                                            if keys else ""))
    if isinstance(error, NUMERICAL):
        return StageFailure(stage, gear, f"the {stage} failed numerically: {error}",
                            _NUMERICAL_REMEDY[stage])
    return StageFailure(stage, gear, f"{type(error).__name__}: {error}",
                        "this is an error of certkit's own: please report it with the "
                        "campaign; the compliance evidence does not depend on this stage",
                        internal=True)


# --------------------------------------------------------------------------- the tasks
#: The campaign the worker processes work on (set before they are forked).
_CAMPAIGN: Campaign | None = None


def _model_task(gear_id: str, identification: bool = True) -> tuple:
    """Calibration, then (``identification``) identification on the calibrated model of
    one gear unit: (calibration or None, identification or None, note, failures)."""
    campaign = _CAMPAIGN
    failures, calibration, identified, note = [], None, None, None
    with threadpool_limits(limits=1):    # one BLAS thread: the same numbers on any machine
        try:
            calibration = calibrate_gear(campaign, gear_id, _knobs(campaign),
                                         run_ids=calibration_runs(campaign, gear_id),
                                         starts=calibration_starts(campaign))
        except Exception as error:   # noqa: BLE001 - stated in the appendix, never fatal
            failures.append(_failure(CALIBRATION, gear_id, error))
        try:
            if identification:
                identified = identify_gear(campaign, gear_id, calibration)
                if identified is None:
                    note = not_identified(campaign, gear_id)
        except Exception as error:   # noqa: BLE001 - stated in the appendix, never fatal
            failures.append(_failure(IDENTIFICATION, gear_id, error))
    return calibration, identified, note, failures


def _gap_task(gear_id: str) -> tuple:
    """The gap diagnosis of one gear unit: (diagnosis or None, note, failures)."""
    with threadpool_limits(limits=1):
        try:
            return gap_diagnosis(_CAMPAIGN, gear_id), None, []
        except CertkitInputError as error:
            # the gear's drops allow no diagnosis (one drop height, nothing left to train on)
            return None, f"{gear_id}: not diagnosed. " + " ".join(
                p.message[:1].upper() + p.message[1:] for p in error.problems), []
        except Exception as error:   # noqa: BLE001 - stated in the appendix, never fatal
            return None, None, [_failure(GAP, gear_id, error)]


def _knobs(campaign: Campaign) -> list[str] | None:
    settings = campaign.spec.model.calibration
    return list(settings.parameters) if settings is not None and settings.parameters else None


def _run(task: tuple) -> tuple:
    kind, gear_id, identification = task
    return task, (_model_task(gear_id, identification) if kind == "model"
                  else _gap_task(gear_id))


def _worker_start() -> None:
    # the parent handles the stop signals and ends the workers; a worker's own numba
    # threads would only compete with the other worker for the cores
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for number in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(number, signal.SIG_DFL)
    try:
        import numba
        numba.set_num_threads(1)
    except (ImportError, ValueError):
        pass


def workers(tasks: int) -> int:
    """How many worker processes the model stages use: ``CERTKIT_WORKERS`` when set, else
    the cores this process may use, at most one per task; 1 means in this process.  Worker
    processes are forked, so only where fork is available, and only before numba has started
    threads of its own in this process (forking those is unsafe)."""
    try:
        from numba.np.ufunc import parallel
        started = bool(parallel._is_initialized)
    except ImportError:
        started = False
    if started or "fork" not in multiprocessing.get_all_start_methods():
        return 1
    wanted = os.environ.get("CERTKIT_WORKERS", "").strip()
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    count = int(wanted) if wanted.isdigit() and int(wanted) > 0 else (cores or 1)
    return max(1, min(count, tasks))


def _results(campaign: Campaign, tasks: list[tuple], progress) -> dict:
    """task -> its result, in worker processes when :func:`workers` allows.  A worker that
    dies (killed, out of memory) costs its tasks, which are then stated as failures."""
    global _CAMPAIGN
    _CAMPAIGN = campaign
    count = workers(len(tasks))
    try:
        if count == 1:
            results = {}
            for task in tasks:
                progress(_words(task))
                results[task] = _run(task)[1]
            return results
        progress("; ".join(_words(t) for t in tasks) + f" ({count} processes)")
        pool = ProcessPoolExecutor(count, mp_context=multiprocessing.get_context("fork"),
                                   initializer=_worker_start)
        try:
            futures = {task: pool.submit(_run, task) for task in tasks}
            results = {}
            for task, future in futures.items():
                try:
                    results[task] = future.result()[1]
                except BrokenProcessPool:
                    results[task] = _lost(task)
            return results
        finally:
            # a stop (Ctrl-C, SIGTERM) while the workers run: end them, do not wait
            pool.shutdown(wait=False, cancel_futures=True)
            for process in list((getattr(pool, "_processes", None) or {}).values()):
                if process.is_alive():
                    process.kill()
    finally:
        _CAMPAIGN = None


def _lost(task: tuple) -> tuple:
    """The result of a task whose worker process died: each of its stages not computed."""
    kind, gear_id, identification = task
    why = ("the process computing it ended without a result (killed, or out of memory)",
           "run the report again; with CERTKIT_WORKERS=1 the stages run in one process")
    if kind == "gap":
        return None, None, [StageFailure(GAP, gear_id, *why)]
    stages = [CALIBRATION] + ([IDENTIFICATION] if identification else [])
    return None, None, None, [StageFailure(stage, gear_id, *why) for stage in stages]


def _words(task: tuple) -> str:
    kind, gear_id, identification = task
    if kind == "gap":
        return f"diagnosing the sim-to-real gap of {gear_id}"
    return (f"calibrating and identifying the drop model of {gear_id}" if identification
            else f"calibrating the drop model of {gear_id}")


# --------------------------------------------------------------------------- the evidence
def model_evidence(campaign: Campaign, identification: bool = True,
                   gap: bool = True, progress=None) -> ModelEvidence:
    """Calibrate every recorded gear unit that the spec gives the model's parameters for,
    identify its block-oriented models (``identification``) and diagnose its sim-to-real
    gap (``gap``); otherwise say plainly why a section is empty.  ``progress(message)`` is
    told each step as it starts.  A stage that fails for a gear unit is recorded as a
    :class:`StageFailure`; nothing raised inside a stage escapes."""
    progress = progress or (lambda message: None)
    spec = campaign.spec
    synthetic = tuple(r.id for r in spec.runs
                      if r.data is not None and r.data.origin == "synthetic")
    recorded = [g.id for g in spec.gear_units
                if any(s is not None and g.id in s.gears for s in campaign.series.values())]
    if not recorded:
        return ModelEvidence(None, "No run has time histories, so the drop model cannot be "
                                   "compared with or calibrated against the tests.", synthetic,
                             calibration_starts=calibration_starts(campaign))
    ready, missing = [], []
    for gear_id in recorded:
        run = next(r for r in spec.runs if gear_id in r.gear_units)
        try:
            drop_model_for(spec, run, gear_id, campaign.spec_path.name, campaign.lines)
            ready.append(gear_id)
        except CertkitInputError as error:
            missing += [f"{p.key} ({p.message})" for p in error.problems]
    if not ready:
        return ModelEvidence(None, "The drop model cannot be built from the spec: "
                                   + "; ".join(missing) + ".", synthetic,
                             calibration_starts=calibration_starts(campaign))
    note = "" if not missing else ("Not modelled (the drop model cannot be built from the "
                                   "spec): " + "; ".join(missing) + ".")
    # the longest tasks first, so that the processes finish together
    tasks = ([("gap", g, False) for g in ready] if gap else []) + [("model", g, identification)
                                                                    for g in ready]
    results = _results(campaign, tasks, progress)
    calibrations, identified, skipped, failures = [], [], [], []
    diagnoses, gap_notes = {}, []
    for gear_id in ready:
        calibrated, gear_identification, why_not, failed = results[("model", gear_id,
                                                                    identification)]
        if calibrated is not None:
            calibrations.append(calibrated)
        if gear_identification is not None:
            identified.append(gear_identification)
        elif why_not:
            skipped.append(why_not)
        failures += failed
        if gap:
            diagnosis, gap_note, failed = results[("gap", gear_id, False)]
            if diagnosis is not None:
                diagnoses[gear_id] = diagnosis
            if gap_note:
                gap_notes.append(gap_note)
            failures += failed
    calibration = Calibration(tuple(spec.model.effects), tuple(calibrations))
    return ModelEvidence(calibration, note, synthetic,
                         Identification(identified, plant_note(campaign), skipped)
                         if identification else None,
                         diagnoses, tuple(gap_notes), tuple(failures),
                         calibration_starts(campaign))

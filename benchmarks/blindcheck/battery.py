"""How far the gap diagnosis can be trusted: a blind check on synthetic campaigns whose
effect is withheld (a battery sized for one machine).

Every case is a campaign simulated from the template campaign's spec:

- the nominal model (no optional effects) of every gear unit, its calibrated parameters
  (orifice C_d, gas pre-charge, polytropic exponent, tyre stiffness) scattered uniformly by
  a few percent from the spec values;
- none, one or two effects of the library switched on, each in a form that differs from the
  diagnosis's candidate where the library allows (:data:`TRUTHS`: Stribeck friction against
  a Coulomb candidate, a Butterworth filter plus a pure delay against a first-order lag,
  …), sized so that it changes the load channel of the diagnosed gear by a chosen multiple
  of the load noise (RMS over the first compression and rebound of every run, where the
  effect acts, not over late bounces whose phase it shifts; a recorder's delay is aligned
  away first, as the diagnosis aligns on the touchdown);
- sensor noise, quantisation, zero offsets and an error in the recorded zero offsets;
- written to disk in the campaign's own data format under an opaque case id, with a note
  that names no effect.

The diagnosis (:func:`certkit.gap.selection.diagnose`) sees only the written campaign.  The
outcome is then scored against the sealed truth (:func:`score`).  Cases run in a local
process pool, or on a dask.distributed cluster when a scheduler address is given: the same
function runs in both.  Seeds are fixed; the same inputs give the same result document.
"""

from __future__ import annotations

import contextlib
import hashlib
import math
import multiprocessing
import tempfile
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path

import numba
import numpy as np
from threadpoolctl import threadpool_limits

from certkit.compliance.clauses import ideal_impact_velocity
from certkit.compliance.measures import touchdown_time
from certkit.errors import CampaignError, CertkitInputError
from certkit.gap.holdout import split_for
from certkit.gap.phases import segment
from certkit.gap.residuals import harmed
from certkit.gap.selection import diagnose, pooled
from certkit.physics.calibration import KNOBS, aligned_records
from certkit.physics.drop_model import DropModel
from certkit.physics.drops import recorded_drops
from certkit.physics.effects import TRUTHS, Truth
from certkit.physics.gear_model import drop_model_for
from certkit.physics.simulation import simulate_batch
from certkit.physics.synthetic import NO_SENSOR_EFFECTS, SensorModel, simulate_campaign
from certkit.spec.blind_record import template_fingerprint
from certkit.spec.campaign import load_campaign
from certkit.units import STANDARD_GRAVITY
from certkit.version import VERSION

from blindcheck.record import provenance
from blindcheck.scoring import SCORED_FROM, score

#: How far a sized effect's load change may miss its target (a share).
SIZE_TOLERANCE = 0.05
#: Length of every simulated record from touchdown [s] (as the example campaign's).
DURATION = 2.0
#: Knobs of the nominal calibration whose true values are scattered in every case.
SCATTERED = ("discharge-coefficient", "gas-precharge", "polytropic-exponent", "tyre-stiffness")



class SizingError(ValueError):
    """An effect cannot be sized to the asked multiple of the noise on this campaign."""


@dataclass(frozen=True)
class Settings:
    """What the battery is made of; every case is reproducible from these and its seed."""

    ratios: tuple = (1.0, 2.0, 5.0)     # effect size / load noise RMS
    seeds: tuple = (21, 22, 23)         # fresh: 1-3 and 11-13 were used while developing
    effects: tuple = tuple(TRUTHS)
    null_cases: int = 12
    pairs: tuple = (("seal friction", "tyre hysteresis"), ("rebound orifice", "heat transfer"),
                    ("leg flexibility", "sensor lag"))
    pair_ratio: float = 5.0
    scatter: float = 0.03               # ± share of the scattered nominal parameters
    load_noise: float = 20.0            # N
    load_step: float = 1.0              # N
    load_offset: float = 10.0           # N
    load_zero_error: float = 2.0        # N
    travel_noise: float = 5.0e-5        # m
    travel_step: float = 1.0e-5         # m
    travel_offset: float = 2.0e-4       # m
    travel_zero_error: float = 2.0e-5   # m


@dataclass(frozen=True)
class Case:
    id: str                  # opaque: a hash of the three below, nothing the diagnosis can read
    truths: tuple            # effect names; empty: nominal with nuisances only
    ratio: float | None
    seed: int

    @property
    def key(self) -> int:
        """The case's own random seed, from its truths, size and seed alone: every case
        has its own noise, offsets and scatter, whatever else is in the battery."""
        text = f"{'+'.join(self.truths)}|{self.ratio}|{self.seed}"
        return int.from_bytes(hashlib.sha256(text.encode("utf-8")).digest()[:8], "little")


def _case(truths: tuple, ratio: float | None, seed: int) -> Case:
    text = f"{'+'.join(truths)}|{ratio}|{seed}"
    return Case("case-" + hashlib.sha256(text.encode("utf-8")).hexdigest()[:10], truths,
                ratio, seed)


def battery(settings: Settings = Settings()) -> list[Case]:
    """Single-effect cases (every effect × ratio × seed), no-effect cases, and two-effect
    cases (every pair × the first two seeds), in that order."""
    plan = [((effect,), ratio, seed) for effect in settings.effects
            for ratio in settings.ratios for seed in settings.seeds]
    plan += [((), None, 100 * settings.seeds[k % len(settings.seeds)] + k)
             for k in range(settings.null_cases)]
    plan += [(tuple(pair), settings.pair_ratio, seed) for pair in settings.pairs
             for seed in settings.seeds[:2]]
    return [_case(*item) for item in plan]


# --------------------------------------------------------------------------- one case
def _scattered(model: DropModel, factors: dict) -> DropModel:

    for name, factor in factors.items():
        knob = KNOBS[name]
        model = knob.write(model, knob.read(model) * factor)
    return model


def first_cycle(time: np.ndarray, load: np.ndarray, stroke: np.ndarray,
                weight: float) -> slice:
    """The samples of a drop's first compression and rebound: from touchdown to the end
    of the rebound (:func:`certkit.gap.phases.segment`), or to the end of the record when
    the strut does not extend again within it."""
    phases = {p.name: p for p in segment(time, load, stroke, weight)}
    start = phases["tyre-only contact"].start if "tyre-only contact" in phases else 0
    end = phases["rebound"].stop if "rebound" in phases else time.size
    return slice(start, end)


def _load_effect(models: list[DropModel], velocities, truth: Truth, sizes: np.ndarray,
                 rate: float, duration: float) -> np.ndarray:
    """RMS of the load with the truth at each size minus without it [N], over the first
    compression and rebound of every run (:func:`first_cycle` of the run without the
    truth): an effect's size measured where it acts, not inflated by late bounces that
    shift in phase."""

    batch = [truth.model(m, s) for s in sizes for m in models] + list(models)
    speeds = np.array(list(velocities) * (len(sizes) + 1))
    drops = simulate_batch(batch, speeds, duration, rate)
    load = drops.load.reshape(len(sizes) + 1, len(models), -1)
    stroke = drops.stroke.reshape(len(sizes) + 1, len(models), -1)
    windows = [first_cycle(drops.time, load[-1][k], stroke[-1][k],
                           m.total_mass * STANDARD_GRAVITY) for k, m in enumerate(models)]
    out = []
    for index, size in enumerate(sizes):
        recorder = truth.recorder(size)
        changed = load[index]
        if recorder is not None:
            # a recorder delays the record, which the diagnosis's alignment on the touchdown
            # absorbs: only what remains with the touchdowns aligned counts
            changed = np.array([aligned_on_touchdown(drops.time, recorder.apply(drops.time, row),
                                                     plain, touchdown_level(model))
                                for row, plain, model in zip(load[index], load[-1], models)])
        squares = [np.mean((changed[k][w] - load[-1][k][w]) ** 2)
                   for k, w in enumerate(windows)]
        out.append(float(np.sqrt(np.mean(squares))))
    return np.array(out)


def touchdown_level(model: DropModel) -> float:
    """The load at which the touchdown detector fires on a noise-free record: 2 % of the
    unit's static weight (:func:`certkit.compliance.measures.touchdown_index`)."""
    return 0.02 * (model.upper_mass + model.lower_mass) * STANDARD_GRAVITY


def aligned_on_touchdown(time: np.ndarray, recorded: np.ndarray, plain: np.ndarray,
                         level: float) -> np.ndarray:
    """``recorded`` shifted so that it crosses ``level`` when ``plain`` does."""

    shift = (touchdown_time(time, recorded, None, level=level)[0]
             - touchdown_time(time, plain, None, level=level)[0])
    return np.interp(time + shift, time, recorded)


def size_for(truth: Truth, models: list[DropModel], velocities, target: float, rate: float,
             duration: float) -> float:
    """The size s at which ``truth`` changes the load by ``target`` N RMS (log-log
    interpolation on a grid, then one secant refinement)."""
    grid = np.geomspace(*truth.sizes, 25)
    effect = np.empty(0)
    for chunk in np.array_split(grid, 5):       # up the grid until the target is passed:
        effect = np.append(effect, _load_effect(models, velocities, truth, chunk, rate,
                                                duration))
        if effect[-1] >= target:                # large sizes are the slow ones to simulate
            break
    grid = grid[:effect.size]
    above = np.nonzero(effect >= target)[0]
    if above.size == 0 or above[0] == 0:
        raise SizingError(f"{truth.candidate}: a load change of {target:g} N RMS lies outside "
                         f"sizes {truth.sizes} ({effect.min():.3g}–{effect.max():.3g} N)")
    i = int(above[0])
    slope = math.log(effect[i] / effect[i - 1]) / math.log(grid[i] / grid[i - 1])
    size = grid[i - 1] * (target / effect[i - 1]) ** (1.0 / slope)
    refined = _load_effect(models, velocities, truth, np.array([size]), rate, duration)[0]
    size = float(size * (target / refined) ** (1.0 / slope))
    reached = _load_effect(models, velocities, truth, np.array([size]), rate, duration)[0]
    if abs(reached / target - 1.0) > SIZE_TOLERANCE:
        raise SizingError(f"{truth.candidate}: sized for {target:g} N RMS, reached "
                          f"{reached:.4g} N (the load change is not monotonic there)")
    return size


def write_case(template: str, gear_id: str, case: Case, settings: Settings,
               folder: str | Path, clean: bool = False) -> tuple[Path, dict]:
    """Simulate ``case`` from the ``template`` campaign into ``folder``: returns the written
    spec's path and the size of every truth effect (sealed: not written).  ``clean``: the
    same truth without noise, quantisation or offsets (for scoring only)."""

    campaign = load_campaign(template)
    spec = campaign.spec
    rng = np.random.default_rng(case.key)
    factors = {gear: {name: float(1 + rng.uniform(-settings.scatter, settings.scatter))
                      for name in SCATTERED} for gear in (g.id for g in spec.gear_units)}
    recorded = set(recorded_drops(campaign, gear_id))          # as the diagnosis has them
    runs = [r for r in spec.runs if r.id in recorded]
    rate = float(campaign.series[runs[0].id].declared_rate)
    base = [_scattered(drop_model_for(spec, r, gear_id, campaign.spec_path.name, campaign.lines,
                                      []), factors[gear_id]) for r in runs]
    velocities = [ideal_impact_velocity(r.drop_height.si) for r in runs]
    sizes = {name: size_for(TRUTHS[name], [TRUTHS[name].start(m) for m in base], velocities,
                            case.ratio * settings.load_noise, rate, DURATION)
             for name in case.truths}

    def truth(gear: str, model: DropModel) -> DropModel:
        model = _scattered(model, factors[gear])
        for name, size in sizes.items():
            model = TRUTHS[name].model(TRUTHS[name].start(model), size)
        return model

    recorders = [TRUTHS[n].recorder(s) for n, s in sizes.items() if TRUTHS[n].sensor]
    sensors = NO_SENSOR_EFFECTS if clean else SensorModel(
        settings.load_noise, settings.load_step, settings.load_offset, settings.travel_noise,
        settings.travel_step, settings.travel_offset, load_zero_error=settings.load_zero_error,
        travel_zero_error=settings.travel_zero_error)
    written = simulate_campaign(
        campaign, Path(folder) / (case.id + ("-clean" if clean else "")), seed=case.key,
        sensors=sensors, duration=DURATION,
        effects=[], truth=truth, recorder=recorders[0] if recorders else None,
        note=f"Blind-check {case.id}: synthetic runs; what was simulated is withheld.")
    return written, sizes


def run_case(template: str, gear_id: str, case: Case, settings: Settings = Settings()) -> dict:
    """Write ``case`` (:func:`write_case`) into a temporary folder, diagnose ``gear_id``
    blind, and return the outcome with its sealed truth (a plain dict, so that it travels
    between processes and machines)."""


    try:
        numba.set_num_threads(1)          # one case per core
    except (ImportError, ValueError):
        pass
    truth = {"id": case.id, "truth": list(case.truths),
             "form": "; ".join(TRUTHS[n].form for n in case.truths) or "none (nuisances only)",
             "ratio": case.ratio, "seed": case.seed}
    empty = {"sizes": {}, "named": [], "held_out": [], "before": None, "after": None,
             "shrink": 0.0, "closed": None, "harmed": False, "harmed_any": False,
             "channels": {}}
    with tempfile.TemporaryDirectory() as folder, threadpool_limits(limits=1):
        try:
            written, sizes = write_case(template, gear_id, case, settings, folder)
            diagnosis = diagnose(load_campaign(written), gear_id)
            clean, _ = write_case(template, gear_id, case, settings, folder, clean=True)
            gap = _gap_to_truth(load_campaign(clean), gear_id, diagnosis)
        except SizingError as error:
            # the effect cannot be sized as asked on this campaign: no case to score
            return {**truth, **empty, "statement": f"not generated: {error}", "error": None,
                    "skipped": str(error)}
        except Exception as error:   # noqa: BLE001 -- recorded and scored as a failure
            # kept as an outcome, so that one case cannot sink a battery of hours
            return {**truth, **empty, "statement": f"failed: {type(error).__name__}: {error}",
                    "error": f"{type(error).__name__}: {error}", "skipped": None}
    before = {(run, ch): v for (label, run, ch), v in diagnosis.held_out_rmse.items()
              if label == "nominal"}
    after = {(run, ch): v for (label, run, ch), v in diagnosis.held_out_rmse.items()
             if label != "nominal"} or before
    load_before, load_after = (_pooled(rmse, "load") for rmse in (before, after))
    pooled_before, pooled_after = pooled(before), pooled(after)
    noise = diagnosis.noise or {}
    return {**truth, "sizes": {n: float(s) for n, s in sizes.items()},
            "named": list(diagnosis.answer), "undecided": list(diagnosis.undecided),
            "recalibrated": [d.rule for d in diagnosis.recalibrated],
            "statement": diagnosis.statement, "error": None,
            "skipped": None, "held_out": list(diagnosis.held_out),
            "before": load_before, "after": load_after,
            "shrink": 1.0 - load_after / load_before if load_before > 0 else 0.0,
            "closed": 1.0 - gap[1] / gap[0] if gap[0] > 0 else None,
            "truth_gap": list(gap),
            "harmed": bool(diagnosis.answer) and harmed(load_before, load_after,
                                                         noise.get("load", 0.0)),
            "harmed_any": bool(diagnosis.answer) and any(
                harmed(pooled_before[c], pooled_after[c], noise.get(c, 0.0))
                for c in pooled_before),
            "channels": {f"{run} {ch}": [float(before[(run, ch)]), float(after[(run, ch)])]
                         for run, ch in sorted(before)}}


def _pooled(rmse: dict, channel: str) -> float:
    """RMS over the held-out runs of one channel's RMSE (run, channel) -> value."""
    return float(math.sqrt(np.mean([v ** 2 for (_, ch), v in rmse.items() if ch == channel])))


def _gap_to_truth(clean, gear_id: str, diagnosis) -> tuple[float, float]:
    """Held-out load RMSE against the noise-free truth (``clean``: the case written without
    sensor noise, quantisation or offsets) of the calibrated nominal model and of the model
    the diagnosis leaves: the gap itself, before and after, which no noise inflates."""

    out = []
    for configure in (diagnosis.calibration.apply, diagnosis.configure):
        records = aligned_records(clean, gear_id, configure, list(diagnosis.held_out),
                                  effects=[])
        out.append(_pooled({(run, "load"): float(np.sqrt(np.mean(
            (r.simulated["load"][r.after] - r.measured["load"][r.after]) ** 2)))
            for run, r in records.items()}, "load"))
    return out[0], out[1]


# --------------------------------------------------------------------------- the battery
def _executor(workers: int | None, scheduler: str | None):
    """A concurrent.futures executor: local processes, or a dask.distributed cluster's."""
    if scheduler:
        try:
            from distributed import Client
        except ImportError as error:
            raise BlindCheckError("--scheduler needs dask.distributed: pip install "
                                  "'certkit[cluster]'") from error
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError) as error:
            raise BlindCheckError(f"cannot reach the dask scheduler at {scheduler}: "
                                  f"{error}") from error
        return contextlib.closing(client), client.get_executor()

    pool = ProcessPoolExecutor(max_workers=workers,
                               mp_context=multiprocessing.get_context("spawn"))
    return contextlib.nullcontext(), pool


class BlindCheckError(CampaignError, RuntimeError):
    """The battery cannot run (no cluster to run it on)."""


def blind_check(template: str | Path, gear_id: str | None = None,
                settings: Settings = Settings(), cases: list[Case] | None = None,
                workers: int | None = None, scheduler: str | None = None,
                progress: Callable[[dict], None] | None = None) -> dict:
    """Run the blind check on ``template`` (a campaign spec path) and return its document:
    settings, metrics against the targets, the curve, the confusion matrix and every case.

    ``workers``: local processes (default: one per core); ``scheduler``: the address of a
    dask.distributed scheduler to run the cases on instead (certkit installed on its
    workers, the template readable at the same path; one thread per worker, since each
    case sets the process's BLAS and numba threads to one).

    Raises
    ------
    CertkitInputError
        When the template cannot be diagnosed at all (no such gear unit, drops at one drop
        height only, ...): checked before any case is simulated.
    BlindCheckError
        When the cluster cannot be reached.
    """

    template = str(Path(template).resolve())
    campaign = load_campaign(template)
    recorded = [g.id for g in campaign.spec.gear_units
                if any(s is not None and g.id in s.gears for s in campaign.series.values())]
    if gear_id is None and recorded:
        gear_id = recorded[0]
    if gear_id not in recorded:
        raise CertkitInputError.single(
            campaign.spec_path.name, None, "gear_units",
            f"gear unit {gear_id} has no drop with time histories to simulate a blind check "
            f"from; recorded: {', '.join(recorded) or 'none'}")
    split_for(campaign, gear_id)     # the template itself must allow a diagnosis
    cases = battery(settings) if cases is None else cases
    outcomes = []
    command = f"benchmarks/blind_own.py {Path(template).name} -g {gear_id}"
    run_by = provenance(command)        # who runs the cases, taken before they run
    owner, pool = _executor(workers, scheduler)
    with owner, pool:
        futures = [pool.submit(run_case, template, gear_id, case, settings) for case in cases]
        for future in futures:
            outcomes.append(future.result())
            if progress:
                progress(outcomes[-1])
    document = {"kind": "certkit blind check", "certkit": VERSION,
                "template": {"spec": Path(template).name,
                             "sha256": template_fingerprint(campaign),
                             "fingerprint": "SHA-256 of the spec's content as validated "
                                            "(canonical JSON) without model.gap.blind_check, "
                                            "model.gap.sealed_blind_check and the audit's "
                                            "thresholds",
                             "code": run_by["code"],
                             "gear": gear_id},
                "command": command, "run_by": run_by, "scored_by": provenance(command),
                "settings": {**{k: v for k, v in asdict(settings).items()
                                if not isinstance(v, tuple) or k in ("ratios", "seeds")},
                             "effects": list(settings.effects),
                             "pairs": [list(p) for p in settings.pairs],
                             "scored_from": SCORED_FROM, "cases": len(cases),
                             "forms": {n: TRUTHS[n].form for n in settings.effects}}}
    document.update(score(outcomes, settings.effects))
    document["cases"] = outcomes
    return document



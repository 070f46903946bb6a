"""How far the gap diagnosis can be trusted: a blind check on synthetic campaigns whose
effect is withheld (issue 5; the protocol of gap-diagnosis.md §5.2, cut to this machine).

Every case is a campaign simulated from the template campaign's spec:

- the nominal model (no optional effects) of every gear unit, its calibrated parameters
  (orifice C_d, gas pre-charge, polytropic exponent, tyre stiffness) scattered uniformly by
  a few percent from the spec values;
- none, one or two effects of the library switched on, each in a form that differs from the
  diagnosis's candidate where the library allows (:data:`TRUTHS`: Stribeck friction against
  a Coulomb candidate, a Butterworth filter plus a pure delay against a first-order lag,
  …), sized so that it changes the load channel of the diagnosed gear by a chosen multiple
  of the load noise (RMS over the runs' records from touchdown; a recorder's delay is
  aligned away first, as the diagnosis aligns on the touchdown);
- sensor noise, quantisation, zero offsets and an error in the recorded zero offsets;
- written to disk in the campaign's own data format under an opaque case id, with a note
  that names no effect.

The diagnosis (:func:`certkit.attribution.diagnose`) sees only the written campaign.  The
outcome is then scored against the sealed truth (:func:`score`).  Cases run in a local
process pool, or on a dask.distributed cluster when a scheduler address is given: the same
function runs in both.  Seeds are fixed; the same inputs give the same result document.
"""

from __future__ import annotations

import hashlib
import math
import statistics
import tempfile
from collections.abc import Callable
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from .drop_model import DropModel
from .effects import (GasHeatTransfer, LegFlexibility, ReboundOrifice, SealFriction,
                      SensorDynamics, TyreHysteresis)
from .units import STANDARD_GRAVITY

#: Length of every simulated record from touchdown [s] (as the example campaign's).
DURATION = 2.0
#: Knobs of the nominal calibration whose true values are scattered in every case.
SCATTERED = ("discharge-coefficient", "gas-precharge", "polytropic-exponent", "tyre-stiffness")



class SizingError(ValueError):
    """An effect cannot be sized to the asked multiple of the noise on this campaign."""


@dataclass(frozen=True)
class Truth:
    """An effect as the truth generator has it, at a size s > 0 (s = 1: ``unit_size``)."""

    candidate: str        # the library candidate a right diagnosis names
    form: str             # the truth's form, and how it differs from the candidate
    sizes: tuple          # (smallest, largest) s searched when sizing
    mechanics: Callable[[DropModel, float], DropModel] | None = None
    sensor: Callable[[float], SensorDynamics] | None = None
    #: what the truth's size is measured from, when that is not the nominal model itself
    base: Callable[[DropModel], DropModel] | None = None

    def model(self, model: DropModel, size: float) -> DropModel:
        return self.mechanics(model, size) if self.mechanics else model

    def start(self, model: DropModel) -> DropModel:
        return self.base(model) if self.base else model

    def recorder(self, size: float) -> SensorDynamics | None:
        return self.sensor(size) if self.sensor else None


def _friction(model: DropModel, s: float) -> DropModel:
    level = 0.05 * model.upper_mass * STANDARD_GRAVITY * s
    return model.with_effect(SealFriction(level, breakaway=0.5 * level, stribeck_velocity=0.02))


def _leg(model: DropModel, s: float) -> DropModel:
    axle, stiffness = 0.35 * model.lower_mass, 3.0e6 / s
    damping = 2 * 0.05 * math.sqrt(stiffness * axle)           # 5 % of critical
    return model.with_effect(LegFlexibility(axle, stiffness, damping))


TRUTHS: dict[str, Truth] = {truth.candidate: truth for truth in (
    Truth("seal friction", "Stribeck seal friction: breakaway force 1.5 times the Coulomb "
                           "level, decaying over 20 mm/s (the candidate: Coulomb only)",
          (0.02, 20.0), mechanics=_friction),
    Truth("rebound orifice", "rebound damping K_reb − K_h (the candidate's own form)",
          (0.01, 20.0),
          mechanics=lambda m, s: m.with_effect(ReboundOrifice(3.0 * m.orifice.coefficient * s))),
    Truth("tyre hysteresis", "a tyre hysteresis loop switching within 5 mm/s (the "
                             "candidate: 10 mm/s)", (0.02, 20.0),
          mechanics=lambda m, s: m.with_effect(TyreHysteresis(0.05 * s, smoothing_velocity=0.005))),
    Truth("heat transfer", "nitrogen (γ = 1.4) exchanging heat with the walls, sized from "
                           "its adiabatic limit (the candidate: γ = the calibrated "
                           "polytropic exponent n)", (0.01, 50.0),
          mechanics=lambda m, s: m.with_effect(GasHeatTransfer(1.0 / s, 1.4)),
          base=lambda m: replace(m, gas=replace(m.gas, exponent=1.4))),
    Truth("leg flexibility", "a leg mode with 35 % of the unsprung mass at the axle and 5 % "
                             "damping (the candidate: 50 %, undamped)", (0.02, 5.0),
          mechanics=_leg),
    Truth("sensor lag", "a 2nd-order Butterworth low-pass plus a pure delay of a fifth of "
                        "its low-frequency group delay on every channel, sized by what "
                        "remains after the best time shift (the candidate: a first-order lag)",
          (0.7, 20.0), sensor=lambda s: SensorDynamics(300.0 / s, 2, 0.0001 * s)),
)}


@dataclass(frozen=True)
class Settings:
    """What the battery is made of; every case is reproducible from these and its seed."""

    ratios: tuple = (1.0, 2.0, 5.0)     # effect size / load noise RMS
    seeds: tuple = (1, 2, 3)
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
    id: str                  # opaque: what the diagnosis could see of it
    truths: tuple            # effect names; empty: nominal with nuisances only
    ratio: float | None
    seed: int


def battery(settings: Settings = Settings()) -> list[Case]:
    """Single-effect cases (every effect × ratio × seed), no-effect cases, and two-effect
    cases (every pair × seed), in that order, numbered."""
    plan = [((effect,), ratio, seed) for effect in settings.effects
            for ratio in settings.ratios for seed in settings.seeds]
    plan += [((), None, 100 * settings.seeds[k % len(settings.seeds)] + k)
             for k in range(settings.null_cases)]
    plan += [(tuple(pair), settings.pair_ratio, seed) for pair in settings.pairs
             for seed in settings.seeds[:2]]
    return [Case(f"case-{i + 1:03d}", truths, ratio, seed)
            for i, (truths, ratio, seed) in enumerate(plan)]


# --------------------------------------------------------------------------- one case
def _scattered(model: DropModel, factors: dict) -> DropModel:
    from .calibration import KNOBS

    for name, factor in factors.items():
        knob = KNOBS[name]
        model = knob.write(model, knob.read(model) * factor)
    return model


def _load_effect(models: list[DropModel], velocities, truth: Truth, sizes: np.ndarray,
                 rate: float, duration: float) -> np.ndarray:
    """RMS over the runs of the load with the truth at each size minus without it [N]."""
    from .simulation import simulate_batch

    batch = [truth.model(m, s) for s in sizes for m in models] + list(models)
    speeds = np.array(list(velocities) * (len(sizes) + 1))
    drops = simulate_batch(batch, speeds, duration, rate)
    load = drops.load.reshape(len(sizes) + 1, len(models), -1)
    out = []
    for index, size in enumerate(sizes):
        recorder = truth.recorder(size)
        changed = load[index]
        if recorder is not None:
            # a recorder delays the record, which the diagnosis's alignment on the touchdown
            # absorbs: only what remains with the touchdowns aligned counts
            changed = np.array([_aligned(drops.time, recorder.apply(drops.time, row), plain,
                                         touchdown_level(model))
                                for row, plain, model in zip(load[index], load[-1], models)])
        out.append(float(np.sqrt(np.mean((changed - load[-1]) ** 2))))
    return np.array(out)


def touchdown_level(model: DropModel) -> float:
    """The load at which the touchdown detector fires on a noise-free record: 2 % of the
    unit's static weight (:func:`certkit.measures.touchdown_index`)."""
    return 0.02 * (model.upper_mass + model.lower_mass) * STANDARD_GRAVITY


def _aligned(time: np.ndarray, recorded: np.ndarray, plain: np.ndarray, level: float):
    """``recorded`` shifted so that it crosses ``level`` when ``plain`` does."""
    from .measures import touchdown_time

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
    return float(size * (target / refined) ** (1.0 / slope))


def write_case(template: str, gear_id: str, case: Case, settings: Settings,
               folder: str | Path) -> tuple[Path, dict]:
    """Simulate ``case`` from the ``template`` campaign into ``folder``: returns the written
    spec's path and the size of every truth effect (sealed: not written)."""
    from .campaign import load_campaign
    from .clauses import ideal_impact_velocity
    from .gear_model import drop_model_for
    from .synthetic import SensorModel, simulate_campaign

    campaign = load_campaign(template)
    spec = campaign.spec
    rng = np.random.default_rng([case.seed, int(case.id.split("-")[-1])])
    factors = {gear: {name: float(1 + rng.uniform(-settings.scatter, settings.scatter))
                      for name in SCATTERED} for gear in (g.id for g in spec.gear_units)}
    runs = [r for r in spec.runs if gear_id in r.gear_units and campaign.series.get(r.id)]
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
    sensors = SensorModel(settings.load_noise, settings.load_step, settings.load_offset,
                          settings.travel_noise, settings.travel_step, settings.travel_offset,
                          load_zero_error=settings.load_zero_error,
                          travel_zero_error=settings.travel_zero_error)
    written = simulate_campaign(
        campaign, Path(folder) / case.id, seed=case.seed, sensors=sensors, duration=DURATION,
        effects=[], truth=truth, recorder=recorders[0] if recorders else None,
        note=f"Blind-check {case.id}: synthetic runs; what was simulated is withheld.")
    return written, sizes


def run_case(template: str, gear_id: str, case: Case, settings: Settings = Settings()) -> dict:
    """Write ``case`` (:func:`write_case`) into a temporary folder, diagnose ``gear_id``
    blind, and return the outcome with its sealed truth (a plain dict, so that it travels
    between processes and machines)."""
    from threadpoolctl import threadpool_limits

    from .attribution import diagnose
    from .campaign import load_campaign
    from .errors import CertkitInputError
    from .fitting import FitError
    from .simulation import SimulationError

    try:
        import numba
        numba.set_num_threads(1)          # one case per core
    except (ImportError, ValueError):
        pass
    truth = {"id": case.id, "truth": list(case.truths),
             "form": "; ".join(TRUTHS[n].form for n in case.truths) or "none (nuisances only)",
             "ratio": case.ratio, "seed": case.seed}
    with tempfile.TemporaryDirectory() as folder, threadpool_limits(limits=1):
        try:
            written, sizes = write_case(template, gear_id, case, settings, folder)
            diagnosis = diagnose(load_campaign(written), gear_id)
        except SizingError as error:
            # the effect cannot be that large (or small) on this campaign: no case to score
            return {**truth, "sizes": {}, "named": [], "statement": f"not generated: {error}",
                    "error": None, "skipped": str(error), "held_out": [], "before": None,
                    "after": None, "shrink": 0.0, "closed": None, "channels": {}}
        except (SimulationError, FitError, CertkitInputError) as error:
            # kept as an outcome (scored as a failure), so one case cannot sink a battery
            return {**truth, "sizes": {}, "named": [], "statement": f"failed: {error}",
                    "error": str(error), "skipped": None, "held_out": [], "before": None,
                    "after": None, "shrink": 0.0, "closed": None, "channels": {}}
    before = {(run, ch): v for (label, run, ch), v in diagnosis.held_out_rmse.items()
              if label == "nominal"}
    after = {(run, ch): v for (label, run, ch), v in diagnosis.held_out_rmse.items()
             if label != "nominal"} or before
    load_before = math.sqrt(np.mean([v ** 2 for (r, ch), v in before.items() if ch == "load"]))
    load_after = math.sqrt(np.mean([v ** 2 for (r, ch), v in after.items() if ch == "load"]))
    # the part of the error above the sensor noise (noise and quantisation are known here,
    # not to the diagnosis): how much of the gap itself the named effect closed
    floor = settings.load_noise ** 2 + settings.load_step ** 2 / 12.0
    excess_before = math.sqrt(max(load_before ** 2 - floor, 0.0))
    excess_after = math.sqrt(max(load_after ** 2 - floor, 0.0))
    return {**truth, "sizes": {n: float(s) for n, s in sizes.items()},
            "closed": float(1.0 - excess_after / excess_before) if excess_before > 0 else None,
            "named": list(diagnosis.answer), "statement": diagnosis.statement, "error": None,
            "skipped": None,
            "held_out": list(diagnosis.held_out),
            "before": float(load_before), "after": float(load_after),
            "shrink": float(1.0 - load_after / load_before) if load_before > 0 else 0.0,
            "channels": {f"{run} {ch}": [float(before[(run, ch)]), float(after[(run, ch)])]
                         for run, ch in sorted(before)}}


# --------------------------------------------------------------------------- scoring
#: Targets of issue 5 (at effect/noise ≥ 2): (value, "at least" | "at most").
TARGETS = {"top1": (0.85, "at least"), "false_attribution": (0.10, "at most"),
           "median_shrink": (0.50, "at least"), "harm_rate": (0.10, "at most")}
SCORED_FROM = 2.0
TIED = "cannot tell apart"


def wilson(count: int, cases: int, z: float = 1.959964) -> list[float] | None:
    """95 % Wilson score interval of a proportion count/cases (None without cases)."""
    if not cases:
        return None
    p, n = count / cases, cases
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return [max(0.0, centre - half), min(1.0, centre + half)]


def _metric(name: str, value, count, cases) -> dict:
    target, direction = TARGETS.get(name, (None, None))
    met = None
    if target is not None and value is not None:
        met = bool(value >= target) if direction == "at least" else bool(value <= target)
    return {"value": value, "count": count, "cases": cases, "target": target,
            "direction": direction, "met": met,
            "interval": wilson(count, cases) if count is not None else None}


def _named_label(outcome: dict) -> str:
    if outcome["named"]:
        return outcome["named"][0]
    return TIED if "cannot be told apart" in outcome["statement"] else "none"


def score(outcomes: list[dict], effects=tuple(TRUTHS)) -> dict:
    """The blind check's metrics from case outcomes (see :func:`run_case`).

    - top-1 accuracy: single-effect cases at effect/noise ≥ :data:`SCORED_FROM` whose first
      named effect is the truth (an abstention or a tie is wrong);
    - false attribution: no-effect cases in which any effect is named;
    - set precision / recall: two-effect cases, pooled over the cases;
    - median held-out shrink: 1 − RMSE_after/RMSE_before of the held-out load channel, over
      the cases with an effect at ratio ≥ :data:`SCORED_FROM` (an abstention shrinks 0);
    - harm rate: cases (all of them) in which the named effect made the held-out load
      error worse;
    - median gap closed: as the shrink, on the part of the held-out load RMSE above the
      known sensor noise (√(RMSE² − σ²)), which no model can remove;
    - the curve: top-1 and median shrink of the single-effect cases at every ratio;
    - the confusion matrix of truth (single effect or none) against first named effect.

    A case that failed (``error``) names nothing and shrinks nothing: it counts as wrong.  A
    case whose effect cannot be sized as asked on this campaign (``skipped``) is not scored;
    it is listed.
    """
    skipped = [o["id"] for o in outcomes if o.get("skipped")]
    outcomes = [o for o in outcomes if not o.get("skipped")]
    single = [o for o in outcomes if len(o["truth"]) == 1]
    scored = [o for o in single if o["ratio"] >= SCORED_FROM]
    null = [o for o in outcomes if not o["truth"]]
    pairs = [o for o in outcomes if len(o["truth"]) == 2]
    effect_cases = [o for o in outcomes if o["truth"] and o["ratio"] >= SCORED_FROM]
    named = [o for o in outcomes if o["named"]]

    def rate(hits, cases):
        return hits / len(cases) if cases else None

    correct = sum(o["named"][:1] == o["truth"] for o in scored)
    false = sum(bool(o["named"]) for o in null)
    right = sum(len(set(o["named"]) & set(o["truth"])) for o in pairs)
    said = sum(len(o["named"]) for o in pairs)
    wanted = sum(len(o["truth"]) for o in pairs)
    harmed = sum(o["after"] > o["before"] for o in named)
    failed = [o["id"] for o in outcomes if o.get("error")]
    shrinks = [o["shrink"] for o in effect_cases]
    closed = [o["closed"] if o.get("closed") is not None else 0.0 for o in effect_cases]
    metrics = {
        "top1": _metric("top1", rate(correct, scored), correct, len(scored)),
        "false_attribution": _metric("false_attribution", rate(false, null), false, len(null)),
        "set_precision": _metric("set_precision", right / said if said else None, right, said),
        "set_recall": _metric("set_recall", right / wanted if wanted else None, right, wanted),
        "median_shrink": _metric("median_shrink",
                                 statistics.median(shrinks) if shrinks else None, None,
                                 len(shrinks)),
        "harm_rate": _metric("harm_rate", rate(harmed, outcomes), harmed, len(outcomes)),
        "median_gap_closed": _metric("median_gap_closed",
                                     statistics.median(closed) if closed else None, None,
                                     len(closed)),
    }
    curve = []
    for ratio in sorted({o["ratio"] for o in single}):
        at = [o for o in single if o["ratio"] == ratio]
        curve.append({"ratio": ratio, "cases": len(at),
                      "top1": sum(o["named"][:1] == o["truth"] for o in at) / len(at),
                      "median_shrink": statistics.median(o["shrink"] for o in at)})
    truths = [e for e in effects if any(o["truth"] == [e] for o in single)] + ["none"]
    columns = list(effects) + ["none", TIED]
    counts = [[0] * len(columns) for _ in truths]
    for o in single + null:
        row = truths.index(o["truth"][0] if o["truth"] else "none")
        counts[row][columns.index(_named_label(o))] += 1
    return {"metrics": metrics, "curve": curve, "failed": failed, "skipped": skipped,
            "confusion": {"truths": truths, "named": columns, "counts": counts}}


# --------------------------------------------------------------------------- the battery
def template_fingerprint(campaign) -> str:
    """SHA-256 of the spec's content (canonical JSON of the validated spec) without
    ``model.gap.blind_check``: the same before and after the spec names its blind-check
    record, different after any change that could change the battery."""
    import json

    content = campaign.spec.model_dump(mode="json")
    gap = (content.get("model") or {}).get("gap")
    if isinstance(gap, dict):
        gap.pop("blind_check", None)
    text = json.dumps(content, sort_keys=True, ensure_ascii=False, separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()



def _executor(workers: int | None, scheduler: str | None):
    if scheduler:
        from distributed import Client   # optional: pip install certkit[cluster]

        return Client(scheduler).get_executor()
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    return ProcessPoolExecutor(max_workers=workers,
                               mp_context=multiprocessing.get_context("spawn"))


def blind_check(template: str | Path, gear_id: str | None = None,
                settings: Settings = Settings(), cases: list[Case] | None = None,
                workers: int | None = None, scheduler: str | None = None,
                progress: Callable[[dict], None] | None = None) -> dict:
    """Run the blind check on ``template`` (a campaign spec path) and return its document:
    settings, metrics against the targets, the curve, the confusion matrix and every case.

    ``workers``: local processes (default: one per core); ``scheduler``: the address of a
    dask.distributed scheduler to run the cases on instead (certkit installed on its
    workers, the template readable at the same path)."""
    from . import __version__
    from .campaign import load_campaign

    template = str(Path(template).resolve())
    campaign = load_campaign(template)
    if gear_id is None:
        gear_id = next(g.id for g in campaign.spec.gear_units
                       if any(s is not None and g.id in s.gears
                              for s in campaign.series.values()))
    cases = battery(settings) if cases is None else cases
    outcomes = []
    with _executor(workers, scheduler) as pool:
        futures = [pool.submit(run_case, template, gear_id, case, settings) for case in cases]
        for future in futures:
            outcomes.append(future.result())
            if progress:
                progress(outcomes[-1])
    document = {"kind": "certkit blind check", "certkit": __version__,
                "template": {"spec": Path(template).name,
                             "sha256": template_fingerprint(campaign),
                             "fingerprint": "SHA-256 of the spec's content as validated "
                                            "(canonical JSON) without model.gap.blind_check",
                             "gear": gear_id},
                "command": f"certkit gap --blind-check {Path(template).name} -g {gear_id}",
                "settings": {**{k: v for k, v in asdict(settings).items()
                                if not isinstance(v, tuple) or k in ("ratios", "seeds")},
                             "effects": list(settings.effects),
                             "pairs": [list(p) for p in settings.pairs],
                             "scored_from": SCORED_FROM, "cases": len(cases),
                             "forms": {n: TRUTHS[n].form for n in settings.effects}}}
    document.update(score(outcomes, settings.effects))
    document["cases"] = outcomes
    return document


def write_blind_check(document: dict, folder: str | Path) -> None:
    """``blind-check.json`` (the whole document) and ``blind-check-cases.csv`` (a row per
    case: truth, size, what was named, held-out load RMSE before and after)."""
    import csv
    import json

    folder = Path(folder)
    text = json.dumps(document, indent=1, sort_keys=True, ensure_ascii=False) + "\n"
    (folder / "blind-check.json").write_text(text, encoding="utf-8")
    with (folder / "blind-check-cases.csv").open("w", encoding="utf-8", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(["case", "truth", "effect/noise", "seed", "named", "statement",
                         "held-out load RMSE before [N]", "after [N]", "shrink [%]"])
        for o in document["cases"]:
            writer.writerow([o["id"], " + ".join(o["truth"]) or "none",
                             "" if o["ratio"] is None else f"{o['ratio']:g}", o["seed"],
                             " + ".join(o["named"]) or "none", o["statement"],
                             "" if o["before"] is None else f"{o['before']:.6g}",
                             "" if o["after"] is None else f"{o['after']:.6g}",
                             f"{100 * o['shrink']:.4g}"])

"""Calibrating the drop model of each gear unit against the campaign's measured runs.

For one gear unit, the chosen parameters are fitted to its training runs jointly (every
drop height of them at once; by default the drops that :func:`certkit.physics.drops.default_split`
does not hold out, the spec's ``model.calibration.runs`` when it names them), by bounded
least squares on normalised residuals of all its
recorded channels (:func:`certkit.physics.fitting.fit`).  The simulation is the batched fast path
at a step fixed for the whole fit, so the residuals are a smooth function of the
parameters and a finite-difference Jacobian is one batched call.

Alignment: the measured and the simulated load go through the same touchdown detector
(:func:`certkit.compliance.measures.touchdown_time`), and the simulation is shifted so the two
touchdowns coincide.  Each run starts from its contact velocity, measured from the
drop-mass displacement when the run records it, else the ideal √(2·g·h).

Residuals of a channel are divided by the measured channel's range over the run, so load
and travel weigh alike; the standard errors then follow from the scatter of those
residuals.  Model-error residuals are correlated in time, so the standard errors are
lower bounds on the real uncertainty.
"""

from __future__ import annotations

import copyreg
import pickle
from dataclasses import dataclass, replace

import numpy as np

from certkit.compliance.clauses import ideal_impact_velocity
from certkit.compliance.measures import contact_velocity, touchdown_time
from certkit.errors import CertkitInputError
from certkit.physics.drop_model import DropModel
from certkit.physics.drops import default_split, recorded_drops
from certkit.physics.effects import KNOBS as EFFECT_KNOBS
from certkit.physics.effects.base import Knob, set_effect
from certkit.physics.fitting import FitParameter, FitResult, fit
from certkit.physics.gear_model import drop_model_for
from certkit.physics.simulation import batch_step, simulate_batch
from certkit.physics.starts import MOST_STARTS, StartSearch, best_of_starts, starts_document
from certkit.spec.campaign import Campaign
from certkit.units import STANDARD_GRAVITY
from certkit.threads import one_blas_thread

CHANNELS = ("load", "stroke", "tyre")
CHANNEL_UNITS = {"load": "N", "stroke": "m", "tyre": "m"}


# --------------------------------------------------------------------------- the knobs
def _set_term(model: DropModel, attribute: str, **values) -> DropModel:
    return replace(model, **{attribute: replace(getattr(model, attribute), **values)})


def _set_discharge(model: DropModel, value: float) -> DropModel:
    """One C_d for every orifice: the nominal one, the metering pin and the rebound orifice
    (K ∝ 1/C_d², so the rebound orifice's excess scales with it)."""
    old = model.orifice.discharge
    model = _set_term(model, "orifice", discharge=value)
    for effect in model.effects:
        if effect.name == "metering pin":
            model = set_effect(model, "metering pin", discharge=value)
        if effect.name == "rebound orifice":
            model = set_effect(model, "rebound orifice",
                                extra_coefficient=effect.extra_coefficient * (old / value) ** 2)
    return model


def _relative(low: float, high: float):
    return lambda nominal: (low * nominal, high * nominal)


def _absolute(low: float, high: float):
    return lambda nominal: (min(low, nominal), max(high, nominal))


KNOBS: dict[str, Knob] = {knob.name: knob for knob in [
    Knob("discharge-coefficient", "discharge coefficient C_d (all orifices)", "1",
         lambda m: m.orifice.discharge, _set_discharge, _absolute(0.2, 1.2)),
    Knob("gas-precharge", "gas pre-charge p_a0 (absolute)", "Pa",
         lambda m: m.gas.precharge, lambda m, v: _set_term(m, "gas", precharge=v),
         _relative(0.5, 1.5)),
    Knob("gas-volume", "gas volume V0", "m^3",
         lambda m: m.gas.volume, lambda m, v: _set_term(m, "gas", volume=v),
         _relative(0.8, 1.3)),
    Knob("polytropic-exponent", "polytropic exponent n", "1",
         lambda m: m.gas.exponent, lambda m, v: _set_term(m, "gas", exponent=v),
         _absolute(1.0, 1.4)),
    Knob("tyre-stiffness", "tyre load F_ref at δ_ref", "N",
         lambda m: m.tyre.reference_load, lambda m, v: _set_term(m, "tyre", reference_load=v),
         _relative(0.5, 2.0)),
    Knob("tyre-exponent", "tyre exponent b", "1",
         lambda m: m.tyre.exponent, lambda m, v: _set_term(m, "tyre", exponent=v),
         _absolute(1.0, 2.0)),
    Knob("tyre-damping", "tyre damping C_T", "s/m",
         lambda m: m.tyre.damping, lambda m, v: _set_term(m, "tyre", damping=v),
         _absolute(0.0, 0.5)),
    Knob("top-out-compression", "compression of the top-out stop under the preload", "m",
         lambda m: -m.stops.hang(m.gas.preload),
         lambda m, v: _set_term(m, "stops", top_out=v), _absolute(1e-5, 5e-3)),
] + list(EFFECT_KNOBS)}


def registered_knob(name: str, label: str) -> Knob:
    """The knob ``name`` of :data:`KNOBS`: how a pickled knob (whose read and write
    functions are lambdas) comes back; an error when this certkit has no such knob."""
    knob = KNOBS.get(name)
    if knob is None or knob.label != label:
        raise pickle.UnpicklingError(f"no calibration knob {name!r} ({label}) in this certkit")
    return knob


copyreg.pickle(Knob, lambda knob: (registered_knob, (knob.name, knob.label)))

#: Calibrated unless the spec chooses: the gas law, the orifice, the tyre's stiffness and
#: exponent (a real tyre's curve is a power law only roughly), how far the hanging strut
#: sits into its top-out stop (a real stop is an elastomer pad, not rigid: the stroke starts
#: softly at touchdown), and the friction level when seal friction is on, the load-cell
#: gain when that is on.
DEFAULT_KNOBS = ("discharge-coefficient", "gas-precharge", "polytropic-exponent",
                 "tyre-stiffness", "tyre-exponent", "top-out-compression", "friction",
                 "load-cell-gain")


# --------------------------------------------------------------------------- results
@dataclass(frozen=True)
class ChannelError:
    """RMSE of one channel of one run, nominal and calibrated model (SI); ``role`` says
    whether the run was fitted ("training") or only simulated ("held out")."""

    run: str
    channel: str
    unit: str
    nominal: float
    calibrated: float
    measured_range: float
    role: str = "training"


@dataclass(frozen=True)
class Trace:
    """Measured, nominal and calibrated histories of one channel of one run (SI)."""

    run: str
    channel: str
    time: np.ndarray          # from the measured touchdown [s]
    measured: np.ndarray
    nominal: np.ndarray
    calibrated: np.ndarray


@dataclass(frozen=True)
class GearCalibration:
    gear_id: str
    runs: tuple[str, ...]          # the runs fitted (training)
    knobs: tuple[Knob, ...]
    fit: FitResult
    errors: tuple[ChannelError, ...]
    traces: tuple[Trace, ...]
    contact_velocities: dict       # run id -> (velocity [m/s], source)
    step: float                    # RK4 step of the final simulations [s]
    nominal_model: DropModel
    calibrated_model: DropModel
    held_out: tuple[str, ...] = ()   # recorded drops not fitted, simulated to validate
    search: StartSearch | None = None   # the further starts, when the fit was given some

    def apply(self, model: DropModel) -> DropModel:
        """``model`` (of this gear, any run) with the calibrated values."""
        for knob, value in zip(self.knobs, self.fit.estimate):
            model = knob.write(model, float(value))
        return model


@dataclass(frozen=True)
class Calibration:
    effects: tuple[str, ...]
    gears: tuple[GearCalibration, ...]


# --------------------------------------------------------------------------- the fit
#: How a run's contact velocity was found when the drop-mass displacement is recorded.
FROM_DISPLACEMENT = "from the recorded drop-mass displacement before touchdown"


@dataclass
class _Run:
    run_id: str
    model: DropModel           # nominal model of this gear in this run
    velocity: float
    velocity_source: str
    time: np.ndarray           # measured sample times from the measured touchdown
    channels: dict             # channel -> measured values on ``time``
    scales: dict               # channel -> measured range
    level: float               # touchdown threshold used on the measured load
    duration: float

    def contact_velocity(self, model: DropModel) -> float:
        """The drop mass's velocity at ``model``'s contact.  A velocity measured from the
        displacement is read at the touchdown found on the measured load; when ``model``
        records the load τ behind the other channels (:meth:`DropModel.record_delay`, a
        load chain's skew), its contact came τ before that touchdown, and the drop mass,
        falling freely until contact, was slower by g·τ then.  Without it a skew of 1 ms
        would start the model about 0.01 m/s fast, a load error the skew cannot undo."""
        delay = model.record_delay("load")
        if not delay or self.velocity_source != FROM_DISPLACEMENT:
            return self.velocity
        return self.velocity - STANDARD_GRAVITY * delay


def _runs_for(campaign: Campaign, gear_id: str, effects, run_ids) -> list[_Run]:
    spec = campaign.spec
    unit = campaign.gear_units[gear_id]
    weight = unit.static_weight.si
    chosen = []
    runs = {run.id: run for run in spec.runs}
    for run_id in recorded_drops(campaign, gear_id):
        if run_ids is not None and run_id not in run_ids:
            continue
        run, series = runs[run_id], campaign.series[run_id]
        gear = series.gears[gear_id]
        found = touchdown_time(series.time, gear.load, weight)
        if found is None:
            continue
        t_contact, level = found
        model = drop_model_for(spec, run, gear_id, campaign.spec_path.name, campaign.lines,
                               effects)
        velocity, source = None, "ideal √(2·g·h) from the drop height"
        if series.displacement is not None:
            velocity = contact_velocity(series.time, series.displacement, t_contact)
            source = FROM_DISPLACEMENT
        if velocity is None:
            velocity, source = ideal_impact_velocity(run.drop_height.si), \
                "ideal √(2·g·h) from the drop height"
        after = series.time >= t_contact
        channels = {"load": gear.load[after]}
        if gear.stroke is not None:
            channels["stroke"] = gear.stroke[after]
        if gear.tyre is not None:
            channels["tyre"] = gear.tyre[after]
        time = series.time[after] - t_contact
        scales = {name: float(np.ptp(values)) or 1.0 for name, values in channels.items()}
        chosen.append(_Run(run.id, model, float(velocity), source, time, channels, scales,
                           level, float(time[-1]) + 0.01))
    return chosen


def _simulated(runs: list[_Run], models: list[DropModel], step: float, rate: float) -> list[dict]:
    """Simulate each (run, model) pair; channels aligned on the measured touchdown."""
    duration = max(r.duration for r in runs)
    drops = simulate_batch(models, [r.contact_velocity(m) for r, m in zip(runs, models)],
                           duration=duration, sample_rate=rate, step=step)
    out = []
    for index, run in enumerate(runs):
        load = drops.load[index]
        found = touchdown_time(drops.time, load, None, level=run.level)
        shift = found[0] if found is not None else 0.0
        at = run.time + shift
        out.append({"load": np.interp(at, drops.time, load),
                    "stroke": np.interp(at, drops.time, drops.stroke[index]),
                    "tyre": np.interp(at, drops.time, drops.tyre[index])})
    return out


def _residual_vector(runs: list[_Run], simulated: list[dict]) -> np.ndarray:
    parts = []
    for run, sim in zip(runs, simulated):
        for name, measured in run.channels.items():
            parts.append((sim[name] - measured) / run.scales[name])
    return np.concatenate(parts)


# --------------------------------------------------------------------------- further starts
#: The fit's budget and tolerance (``least_squares``'s max_nfev and its three tolerances).
FIT_EVALUATIONS = 60
FIT_TOLERANCE = 1e-6
#: The finite-difference step of every drop-model fit (a share of each parameter's size,
#: :attr:`certkit.physics.fitting.FitParameter.size`): the calibration, its further starts
#: and the gap diagnosis's refits and Jacobians.  The residuals come from a fixed-step RK4
#: integration of force laws that switch (seal friction's sign, the top-out stop, the tyre
#: leaving the ground, the rebound valve): they are smooth only between the parameter
#: values where a switch crosses an integration step, so a step near the rounding optimum
#: eps^(1/3) differences the kinks, not the slope (J. J. Moré and S. M. Wild, "Estimating
#: computational noise", SIAM J. Sci. Comput. 33(3) (2011) 1292-1314; "Estimating
#: derivatives of noisy simulations", ACM TOMS 38(3) (2012) 19); docs/drop-model.md.
FIT_STEP = 3e-3


def _size(value: float, low: float, high: float) -> float:
    """A knob's size from its nominal value, also where the bounds exclude that value:
    |value|, or the larger bound magnitude when it is zero."""
    return abs(value) if value != 0.0 else max(abs(low), abs(high))


@one_blas_thread
def calibrate_gear(campaign: Campaign, gear_id: str, knobs: list[str] | None = None,
                   effects: list[str] | None = None, run_ids: list[str] | None = None,
                   start: list[float] | None = None, starts: int = 0,
                   step: float = FIT_STEP) -> GearCalibration:
    """Fit ``knobs`` of ``gear_id``'s drop model to the runs ``run_ids`` (default: every
    run recording it); every other recorded drop of the gear is simulated with the nominal
    and the fitted parameters and compared with its record (``role`` "held out").

    ``start``: the knobs' values the fit starts from (SI, one per knob fitted, in their
    order; default the nominal ones).  The bounds are the nominal values' either way, and
    so are the errors' "nominal" RMSEs; the fit's own starting point (each parameter's
    ``nominal``, ``fit.cost_nominal``) is the start.  The gap diagnosis starts a
    calibration again where a refit's bare parameters lay; the campaign's calibration
    always starts from the nominal values.

    ``starts``: further starts within the bounds the fit is tried from (0 to
    :data:`certkit.physics.starts.MOST_STARTS`), kept only when one reaches a lower cost
    (:func:`certkit.physics.starts.best_of_starts`; recorded in ``search``).  A fit of a drop model can stop in a basin of its cost far from the best
    one (a stiff top-out pad, say, barely moves the load until it is much softer); the
    gap diagnosis calibrates its nominal model so.

    ``step``: the fits' finite-difference step (:data:`FIT_STEP`); each knob is sized by
    its nominal value wherever a fit starts.  A start outside a knob's bounds (a rebound
    orifice wider than the main one) is moved to the nearer bound.

    Raises
    ------
    CertkitInputError
        When no run records the gear unit, or a knob needs an effect that is off.
    ValueError
        When ``starts`` is not a whole number from 0 to MOST_STARTS (before any fit).
    """
    if isinstance(starts, bool) or not isinstance(starts, int) or not 0 <= starts <= MOST_STARTS:
        raise ValueError(f"further starts: expected a whole number from 0 to {MOST_STARTS}, "
                         f"got {starts!r}")
    spec_file = campaign.spec_path.name
    chosen_effects = list(campaign.spec.model.effects if effects is None else effects)
    runs = _runs_for(campaign, gear_id, chosen_effects, run_ids)
    if not runs:
        raise CertkitInputError.single(spec_file, None, "runs",
                                       f"no run records gear unit {gear_id} with time histories: "
                                       "nothing to calibrate against")
    base = runs[0].model
    names = list(knobs) if knobs is not None else [
        k for k in DEFAULT_KNOBS if KNOBS[k].needs is None or base.effect(KNOBS[k].needs)]
    unknown = [n for n in names if n not in KNOBS]
    if unknown:
        raise CertkitInputError.single(spec_file, None, "model.calibration.parameters",
                                       f"unknown parameter(s) {', '.join(unknown)}; expected "
                                       f"some of {', '.join(KNOBS)}")
    chosen = [KNOBS[n] for n in names]
    for knob in chosen:
        if knob.needs is not None and base.effect(knob.needs) is None:
            raise CertkitInputError.single(
                spec_file, None, "model.calibration.parameters",
                f"{knob.name} needs the effect '{knob.needs}', which is off")
    if base.orifice is None:
        chosen = [k for k in chosen if k.name != "discharge-coefficient"]
    nominal = [knob.read(base) for knob in chosen]
    if start is not None and len(start) != len(chosen):
        raise ValueError(f"start has {len(start)} values for {len(chosen)} knobs "
                         f"({', '.join(k.name for k in chosen)})")
    first = nominal if start is None else [float(v) for v in start]
    parameters = []
    for knob, value, initial in zip(chosen, nominal, first):
        low, high = knob.bounds(value)
        parameters.append(FitParameter(knob.name, knob.unit, min(max(initial, low), high),
                                       low, high, size=_size(value, low, high)))

    def configure(model: DropModel, values) -> DropModel:
        for knob, value in zip(chosen, values):
            model = knob.write(model, float(value))
        return model

    rate = 1.0 / float(np.median(np.diff(runs[0].time)))

    def many(matrix: np.ndarray) -> np.ndarray:
        # one step for every row of a call (a Jacobian's stencil sees one discretisation);
        # between calls the step may change with the parameters, which moves the
        # residuals by the RK4 error only (below 1e-6 of the signals)
        batch_runs = [run for _ in matrix for run in runs]
        models = [configure(run.model, x) for x in matrix for run in runs]
        dt = batch_step(models, [r.velocity for r in batch_runs], rate)
        simulated = _simulated(batch_runs, models, dt, rate)
        width = len(runs)
        return np.array([_residual_vector(runs, simulated[i * width:(i + 1) * width])
                         for i in range(len(matrix))])

    result = fit(lambda x: many(np.asarray(x)[None, :])[0], parameters, residuals_many=many,
                 max_evaluations=FIT_EVALUATIONS, tolerance=FIT_TOLERANCE, relative_step=step)
    search = None
    if starts:
        result, search = best_of_starts(result, parameters,
                                        lambda x: many(np.asarray(x)[None, :])[0], many,
                                        starts, FIT_EVALUATIONS, FIT_TOLERANCE, step=step)

    fitted_ids = {r.run_id for r in runs}
    held = [] if run_ids is None else [r for r in _runs_for(campaign, gear_id, chosen_effects,
                                                            None) if r.run_id not in fitted_ids]
    shown = runs + held
    nominal_models = [configure(r.model, nominal) for r in shown]
    fitted_models = [configure(r.model, result.estimate) for r in shown]
    dt = batch_step(nominal_models + fitted_models, [r.velocity for r in shown] * 2, rate)
    before = _simulated(shown, nominal_models, dt, rate)
    after = _simulated(shown, fitted_models, dt, rate)
    errors, traces = [], []
    for run, sim0, sim1 in zip(shown, before, after):
        role = "training" if run.run_id in fitted_ids else "held out"
        for name, measured in run.channels.items():
            errors.append(ChannelError(
                run.run_id, name, CHANNEL_UNITS[name],
                float(np.sqrt(np.mean((sim0[name] - measured) ** 2))),
                float(np.sqrt(np.mean((sim1[name] - measured) ** 2))), run.scales[name], role))
            traces.append(Trace(run.run_id, name, run.time, measured, sim0[name], sim1[name]))
    return GearCalibration(
        gear_id=gear_id, runs=tuple(r.run_id for r in runs), knobs=tuple(chosen), fit=result,
        errors=tuple(errors), traces=tuple(traces),
        contact_velocities={r.run_id: (r.velocity, r.velocity_source) for r in shown},
        step=dt, nominal_model=base, calibrated_model=configure(base, result.estimate),
        held_out=tuple(r.run_id for r in held), search=search)


def calibration_runs(campaign: Campaign, gear_id: str) -> list[str]:
    """The runs ``gear_id``'s drop model is fitted to: the spec's ``model.calibration.runs``
    when it names them, else the training drops of
    :func:`certkit.physics.drops.default_split` (every drop when that holds out all of
    them: drops at one height)."""
    settings = campaign.spec.model.calibration
    if settings is not None and settings.runs:
        return list(settings.runs)
    training, held = default_split(campaign, gear_id)
    return training if training else held


def calibration_starts(campaign: Campaign) -> int:
    """How many further starts the campaign's calibration is tried from: the spec's
    ``model.calibration.starts``, else none."""
    settings = campaign.spec.model.calibration
    return settings.starts if settings is not None else 0


@one_blas_thread
def calibrate(campaign: Campaign, knobs: list[str] | None = None,
              gears: list[str] | None = None, effects: list[str] | None = None,
              run_ids: list[str] | None = None, starts: int | None = None) -> Calibration:
    """Calibrate every gear unit (or ``gears``) that some run records with time histories,
    each on ``run_ids`` (default: :func:`calibration_runs`), validated on its other drops,
    from the spec's values and ``starts`` further starts (default
    :func:`calibration_starts`)."""
    spec = campaign.spec
    settings = spec.model.calibration
    if knobs is None and settings is not None and settings.parameters:
        knobs = list(settings.parameters)
    starts = calibration_starts(campaign) if starts is None else starts
    recorded = [g.id for g in spec.gear_units
                if any(s is not None and g.id in s.gears for s in campaign.series.values())]
    chosen = recorded if gears is None else [g for g in gears if g in recorded]
    results = tuple(calibrate_gear(campaign, gear_id, knobs, effects,
                                   run_ids if run_ids is not None
                                   else calibration_runs(campaign, gear_id),
                                   starts=starts)
                    for gear_id in chosen)
    return Calibration(tuple(spec.model.effects if effects is None else effects), results)


def _finite(value: float):
    return float(value) if np.isfinite(value) else None


def calibration_document(calibration: Calibration) -> dict:
    """Plain, JSON-ready summary (SI): estimates, standard errors, correlations, RMSEs."""
    gears = []
    for gear in calibration.gears:
        fit_ = gear.fit
        gears.append({
            "gear_unit": gear.gear_id,
            "runs": list(gear.runs), "held_out": list(gear.held_out),
            "contact_velocity": {run: {"value_m_per_s": v, "source": source}
                                 for run, (v, source) in gear.contact_velocities.items()},
            "parameters": [
                {"name": p.name, "unit": p.unit, "nominal": p.nominal, "lower": p.lower,
                 "upper": p.upper, "estimate": float(e), "standard_error": _finite(se)}
                for p, e, se in zip(fit_.parameters, fit_.estimate, fit_.standard_error)],
            "correlation": [[_finite(c) for c in row] for row in fit_.correlation],
            "warnings": list(fit_.warnings),
            "normalised_rms": {"nominal": fit_.cost_nominal, "calibrated": fit_.cost},
            "rmse": [{"run": e.run, "role": e.role, "channel": e.channel, "unit": e.unit,
                      "nominal": e.nominal, "calibrated": e.calibrated} for e in gear.errors],
            "converged": bool(fit_.success), "message": fit_.message,
            "evaluations": fit_.evaluations, "step_s": gear.step,
            "further_starts": starts_document(gear.search),
        })
    return {"effects": list(calibration.effects), "gear_units": gears}


def simulate_like_runs(campaign: Campaign, gear_id: str, configure=lambda model: model,
                       run_ids: list[str] | None = None, effects: list[str] | None = None
                       ) -> dict:
    """Each run's channels as the (configured) drop model simulates them, aligned on the
    measured touchdown and sampled at the measured times: run id -> {"time", "load",
    "stroke", "tyre"} (SI, time from the measured touchdown).  ``effects``: the optional
    effects of the model (default: the spec's)."""
    chosen = list(campaign.spec.model.effects if effects is None else effects)
    runs = _runs_for(campaign, gear_id, chosen, run_ids)
    if not runs:
        return {}
    models = [configure(r.model) for r in runs]
    rate = 1.0 / float(np.median(np.diff(runs[0].time)))
    simulated = _simulated(runs, models, batch_step(models, [r.velocity for r in runs], rate),
                           rate)
    return {r.run_id: dict(sim, time=r.time) for r, sim in zip(runs, simulated)}


class RunResiduals:
    """The normalised residuals of a gear unit's runs, for any drop models: the same rows
    (runs × recorded channels × samples from the measured touchdown) the calibration fits.

    ``evaluate(model_sets)`` takes one list of models per candidate (one model per run, in
    :attr:`run_ids` order) and returns the residual vectors as rows, in one batched call.
    """

    def __init__(self, campaign: Campaign, gear_id: str, run_ids: list[str] | None = None,
                 effects: list[str] | None = None):
        chosen = list(campaign.spec.model.effects if effects is None else effects)
        self.runs = _runs_for(campaign, gear_id, chosen, run_ids)
        if not self.runs:
            raise CertkitInputError.single(campaign.spec_path.name, None, "runs",
                                           f"no run records gear unit {gear_id} with time "
                                           "histories")
        self.run_ids = [r.run_id for r in self.runs]
        self.models = [r.model for r in self.runs]
        self.rate = 1.0 / float(np.median(np.diff(self.runs[0].time)))

    def segments(self) -> list[tuple[str, str, slice, float]]:
        """(run id, channel, its rows in a residual vector, its scale [SI]), in row order."""
        out, start = [], 0
        for run in self.runs:
            for name, measured in run.channels.items():
                out.append((run.run_id, name, slice(start, start + measured.size),
                            run.scales[name]))
                start += measured.size
        return out

    def measured(self) -> dict[str, list[np.ndarray]]:
        """Channel -> the measured records from touchdown of every run [SI]."""
        out: dict[str, list[np.ndarray]] = {}
        for run in self.runs:
            for name, values in run.channels.items():
                out.setdefault(name, []).append(values)
        return out

    def channel_rmse(self, vector: np.ndarray) -> dict[str, float]:
        """Channel -> RMS over every run of that channel's rows of a residual vector, back
        in the channel's SI unit."""
        sums: dict[str, list[float]] = {}
        for _, name, rows, scale in self.segments():
            part = vector[rows] * scale
            total = sums.setdefault(name, [0.0, 0.0])
            total[0] += float(part @ part)
            total[1] += part.size
        return {name: float(np.sqrt(total / count)) for name, (total, count) in sums.items()}

    def evaluate(self, model_sets: list[list[DropModel]]) -> np.ndarray:
        runs = [run for _ in model_sets for run in self.runs]
        models = [m for models in model_sets for m in models]
        step = batch_step(models, [r.velocity for r in runs], self.rate)
        simulated = _simulated(runs, models, step, self.rate)
        width = len(self.runs)
        return np.array([_residual_vector(self.runs, simulated[i * width:(i + 1) * width])
                         for i in range(len(model_sets))])


@dataclass(frozen=True)
class AlignedRecord:
    """A run's recorded channels beside the model's, over the whole record (SI).

    The model is at rest in free fall before the measured touchdown (all channels 0);
    ``after`` marks the samples from touchdown on."""

    time: np.ndarray
    after: np.ndarray
    measured: dict
    simulated: dict


def aligned_records(campaign: Campaign, gear_id: str, configure=lambda model: model,
                    run_ids: list[str] | None = None, effects: list[str] | None = None
                    ) -> dict[str, AlignedRecord]:
    """:func:`simulate_like_runs` over each run's whole record, beside its measured channels."""
    simulated = simulate_like_runs(campaign, gear_id, configure, run_ids, effects)
    weight = campaign.gear_units[gear_id].static_weight.si
    records = {}
    for run_id, channels in simulated.items():
        series = campaign.series[run_id]
        gear = series.gears[gear_id]
        measured = {name: values for name, values in
                    (("load", gear.load), ("stroke", gear.stroke), ("tyre", gear.tyre))
                    if values is not None}
        t_contact, _ = touchdown_time(series.time, gear.load, weight)
        after = series.time >= t_contact
        model = {}
        for name in measured:
            values = np.zeros(series.time.size)
            values[after] = channels[name]
            model[name] = values
        records[run_id] = AlignedRecord(series.time, after, measured, model)
    return records

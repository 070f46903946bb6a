"""Identification of block-oriented models of each gear unit from its drop runs: the drop
protocol that applies the engines of :mod:`certkit.ident` (which know nothing of campaigns)
to a campaign, with the gear's calibrated drop model as the Wiener plant
(:func:`physics_plant`).

Input the platform's vertical load [kN], outputs the strut stroke and the tyre deflection
[mm], one SISO model per output, as in the seed paper (§3-§5), each starting at
touchdown.  Models: Hammerstein LS-SVM (:mod:`certkit.ident.hammerstein`), Wiener by the
seed's small-signal method and by the best linear approximation (:mod:`certkit.ident.wiener`,
the plant being the gear's calibrated drop model driven by a prescribed ground load),
LS-SVM NARX (:mod:`certkit.ident.lssvm`), and the governing equations, nominal and calibrated.

Two validation protocols:

* the seed paper's: train on the first 200 samples (0.2 s) after touchdown of a run and
  simulate that whole run (0-1 s): in-sample for its first fifth, and it is what the paper did;
* the honest one: train and tune on some drop heights, simulate the held-out drops in free
  run (the rule the gap diagnosis uses too, :func:`certkit.physics.drops.default_split`:
  the highest height, and the middle one from four heights up); the held-out runs are used
  for nothing else (calibration included).

Every figure is a free-run simulation (only the input and, for the models that need one,
an initialisation window of na measured samples); one-step-ahead prediction errors are
reported separately and labelled.

Identification runs at one sample rate, :data:`MODEL_RATE` (1 kHz, the seed paper's
logger).  The models' lag orders (na, nb), the initialisation window, the whiteness lags
and the Wiener plant's records count samples at that rate, so every record logged at
another rate is first resampled to it (:func:`at_model_rate`): the same drops logged at
2 kHz or at 1 kHz then give the same regressors, with lags that span the same time.
Left as they are, the spec's orders (the seed's 6/4) would span half the time at 2 kHz;
scaled with the rate, they would double the regressor (and the LS-SVM kernel's input
dimension), which makes other models, not the same ones.
"""

from __future__ import annotations

import contextlib
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.signal import butter, sosfiltfilt
from sklearn.base import clone
from threadpoolctl import threadpool_limits

from certkit.compliance.measures import touchdown_index, touchdown_time
from certkit.display import number, with_unit
from certkit.errors import CertkitInputError
from certkit.ident.hammerstein import HammersteinLSSVM
from certkit.ident.linear_models import ARX
from certkit.ident.narx import NARX
from certkit.ident.search_space import SearchEdgeWarning
from certkit.ident.tuning import tune_free_run
from certkit.ident.validation import fit_percent, max_abs_error, nrmse, residual_analysis, rmse
from certkit.ident.wiener import (Plant, SmallSignalExperiment, WienerLSSVM,
                                  best_linear_records, small_signal_records)
from certkit.physics.calibration import calibrate_gear, calibration_starts, simulate_like_runs
from certkit.physics.drops import default_split, drop_heights, recorded_drops
from certkit.physics.gear_model import drop_model_for
from certkit.physics.simulation import simulate_driven
from certkit.spec.campaign import Campaign
from certkit.spec.rundata import CHANNEL_LABELS
from certkit.threads import one_blas_thread
from certkit.units import STANDARD_GRAVITY

#: How reports and the terminal name the validation protocols (Score.protocol).
PROTOCOL_NAMES = {"paper": "short training", "held-out": "held-out"}
OUTPUTS = ("stroke", "tyre")
OUTPUT_LABELS = {name: CHANNEL_LABELS[name] for name in OUTPUTS}
#: Sample rate every model is identified at [Hz]: the seed paper's logger rate, at which its
#: orders were chosen.  Records at another rate are resampled to it (:func:`at_model_rate`).
MODEL_RATE = 1000.0
WINDOW_DURATION = 1.0           # s from touchdown (the paper's figures: 0-1 s)
PAPER_TRAINING_DURATION = 0.2   # s: the paper's "initial 200 data points" at its 1 kHz
PLANT_DURATION = 2.0            # s: each record of the Wiener plant (small-signal, BLA)
WINDOW = round(WINDOW_DURATION * MODEL_RATE)                    # samples at MODEL_RATE
PAPER_TRAINING = round(PAPER_TRAINING_DURATION * MODEL_RATE)    # samples at MODEL_RATE
PLANT_SAMPLES = round(PLANT_DURATION * MODEL_RATE)              # samples at MODEL_RATE
WHITENESS_LAGS = 25     # residual correlation lags at MODEL_RATE (Ljung 1999, §16.6)
WHITENESS_CONFIDENCE = 0.99


@dataclass(frozen=True)
class Drop:
    run: str
    load: np.ndarray        # kN, from touchdown, at MODEL_RATE
    outputs: dict           # output -> mm, from touchdown, at MODEL_RATE
    time: np.ndarray = field(repr=False, compare=False)  # s from the touchdown instant


#: Anti-alias low-pass applied before a record is brought down to MODEL_RATE: Butterworth,
#: run forward and backward (no delay), cut-off a share of MODEL_RATE below its Nyquist
#: frequency (drop dynamics lie below about 100 Hz).
ANTI_ALIAS_ORDER = 8
ANTI_ALIAS_CUTOFF = 0.4     # × MODEL_RATE
#: Rates within this relative distance of MODEL_RATE are taken as MODEL_RATE (no resampling).
RATE_MATCH = 1e-6


def at_model_rate(time: np.ndarray, channels: dict) -> tuple[np.ndarray, dict]:
    """A record's channels at :data:`MODEL_RATE`, on a grid starting at its first sample.

    The rate is the time column's (``1/median(Δt)``; certkit's reader has checked it
    against the declared ``sampling_rate``).  A record already at MODEL_RATE is returned
    as it is.  Otherwise: a faster record is low-passed first (:data:`ANTI_ALIAS_ORDER`-th
    order Butterworth at :data:`ANTI_ALIAS_CUTOFF`·MODEL_RATE, zero phase), and every
    channel is interpolated on the MODEL_RATE grid by a cubic spline in time.
    """

    time = np.asarray(time, dtype=float)
    rate = 1.0 / float(np.median(np.diff(time)))
    if abs(rate / MODEL_RATE - 1.0) <= RATE_MATCH:
        return time, channels
    grid = time[0] + np.arange(int(np.floor((time[-1] - time[0]) * MODEL_RATE)) + 1) / MODEL_RATE
    low_pass = (butter(ANTI_ALIAS_ORDER, ANTI_ALIAS_CUTOFF * MODEL_RATE, fs=rate, output="sos")
                if rate > MODEL_RATE else None)
    resampled = {}
    for name, values in channels.items():
        if values is None:
            resampled[name] = None
            continue
        values = np.asarray(values, dtype=float)
        if low_pass is not None:
            values = sosfiltfilt(low_pass, values)
        resampled[name] = CubicSpline(time, values)(grid)
    return grid, resampled


@dataclass(frozen=True)
class Score:
    """One model's free-run error on one run and output."""

    model: str
    protocol: str
    output: str
    run: str
    rmse: float             # mm
    nrmse: float
    fit: float              # %
    max_error: float        # mm
    simulated: np.ndarray = field(repr=False, compare=False)


@dataclass
class GearIdentification:
    gear_id: str
    training: tuple[str, ...]
    held_out: tuple[str, ...]       # the first is the paper protocol's run
    scores: list = field(default_factory=list)           # Score
    one_step: list = field(default_factory=list)         # (model, output, run, rmse mm)
    whiteness: list = field(default_factory=list)        # (model, output, dict)
    linear_blocks: dict = field(default_factory=dict)    # (route, output) -> ARX
    nonlinearities: dict = field(default_factory=dict)   # (model, output) -> (x, f(x))
    small_signal: dict = field(default_factory=dict)     # output -> steps
    hammerstein_ratio: dict = field(default_factory=dict)
    measured: dict = field(default_factory=dict)         # run -> Drop
    notes: list = field(default_factory=list)


@dataclass
class Identification:
    gears: list
    plant_note: str
    #: why a gear unit was not identified (runs too short, too few drops), in words
    skipped: list = field(default_factory=list)


def _drops(campaign: Campaign, gear_id: str, unused: list | None = None) -> list[Drop]:
    """The drops of ``gear_id`` the models are fitted on; why a recorded run is not one of
    them is appended to ``unused``."""
    weight = campaign.gear_units[gear_id].static_weight.si
    drops = []
    unused = [] if unused is None else unused
    runs = {run.id: run for run in campaign.spec.runs}
    for run_id in recorded_drops(campaign, gear_id):
        run, series = runs[run_id], campaign.series[run_id]
        gear = series.gears[gear_id]
        if gear.stroke is None or gear.tyre is None:
            unused.append(f"run {run.id} records no stroke or no tyre deflection")
            continue
        time, channels = at_model_rate(series.time, {"load": gear.load, "stroke": gear.stroke,
                                                     "tyre": gear.tyre})
        start = touchdown_index(channels["load"], weight)
        # the touchdown instant of the record as logged, which the drop model is aligned on
        found = touchdown_time(series.time, gear.load, weight)
        if start is None or found is None:
            unused.append(f"run {run.id} shows no touchdown")
            continue
        if start + WINDOW > time.size:
            unused.append(f"run {run.id} has {(time.size - start) / MODEL_RATE:.3g} s recorded "
                          f"after touchdown, identification needs {WINDOW_DURATION:g} s")
            continue
        contact, _ = found
        window = slice(start, start + WINDOW)
        drops.append(Drop(run.id, channels["load"][window] / 1e3,
                          {"stroke": channels["stroke"][window] * 1e3,
                           "tyre": channels["tyre"][window] * 1e3}, time[window] - contact))
    return drops


#: Every model is scored from this sample on: the Hammerstein and NARX free runs copy their
#: first measured samples (the initialisation window), which must not count.
SCORED_FROM = 10


def _score(name: str, protocol: str, output: str, run: str, measured, simulated) -> Score:
    y, y_hat = np.asarray(measured)[SCORED_FROM:], np.asarray(simulated)[SCORED_FROM:]
    return Score(name, protocol, output, run, rmse(y, y_hat), nrmse(y, y_hat),
                 fit_percent(y, y_hat), max_abs_error(y, y_hat), np.asarray(simulated))


#: The spec's σ² of the Hammerstein map and of the Wiener static map is in the load's unit
#: squared (kN²; the NARX's in standardised units): those kernels run on the load as it is
#: (input_scale 1), not on the estimators' default standardised input.
RAW_UNITS = 1.0


def _drop_by_drop_cost(estimator, drops) -> float:
    """The protocol's tuning cost of a Hammerstein model (a ``cost`` of
    :func:`certkit.ident.tune_free_run`): the sum of the free-run NRMSEs of each training
    drop simulated by the model fitted on the others; with one training drop, of its second
    half simulated by the model fitted on its first half.  An unstable AR part is no
    candidate (+inf)."""
    if len(drops) > 1:
        folds = [([d for d in drops if d is not held], held, 0) for held in drops]
    else:
        (u, y), = drops
        half = y.size // 2
        folds = [([(u[:half], y[:half])], drops[0], half)]
    total = 0.0
    for fit_on, (u, y), scored_from in folds:
        model = clone(estimator)
        try:
            model.fit([d[0] for d in fit_on], [d[1] for d in fit_on])
        except (ValueError, np.linalg.LinAlgError):
            return float("inf")
        if not model.stable_:
            return float("inf")
        simulated = model.simulate(u, y[:model.na])
        if not np.all(np.isfinite(simulated)):
            return float("inf")
        total += nrmse(y[scored_from:], simulated[scored_from:])
    return total


def _hammerstein(train: list[Drop], output: str, settings) -> HammersteinLSSVM:
    """Hammerstein LS-SVM; (γ, σ²) from the spec, or tuned on free-run error
    (:func:`_drop_by_drop_cost`, a 3 x 3 grid and 6 refinement steps)."""
    loads, outputs = [d.load for d in train], [d.outputs[output] for d in train]
    estimator = HammersteinLSSVM(settings.na, settings.nb, input_scale=RAW_UNITS)
    gamma, sigma2 = settings.gamma, settings.sigma2
    if gamma is None or sigma2 is None:
        model, _ = tune_free_run(estimator, loads, outputs, cost=_drop_by_drop_cost,
                                 gamma=gamma.si if gamma else (1e1, 1e6),
                                 sigma2=sigma2.si if sigma2 else (1e-1, 1e3), grid=3,
                                 max_refine=6)
        return model
    return estimator.set_params(gamma=gamma.si, sigma2=sigma2.si).fit(loads, outputs)


def _refit(model, train: list[Drop], output: str):
    """The same model class and hyper-parameters fitted to other data (the paper's
    protocol reuses what was tuned on the training runs)."""
    return model.fit([d.load for d in train], [d.outputs[output] for d in train])


def _governing_equation(campaign: Campaign, gear_id: str, result: GearIdentification,
                        held: list[Drop], calibration=None):
    """Nominal and calibrated (on the training runs only) drop models on the held-out runs;
    returns the calibrated model of the first held-out run (the Wiener plant), or None.
    ``calibration``: the gear's drop model already calibrated, used when it was fitted to
    exactly these training runs (one calibrated model for the report), else made here."""
    try:
        if calibration is None or set(calibration.runs) != set(result.training):
            calibration = calibrate_gear(campaign, gear_id, run_ids=list(result.training),
                                         starts=calibration_starts(campaign))
    except CertkitInputError as error:
        result.notes.append("governing equation not simulated: " + "; ".join(
            p.message for p in error.problems))
        return None
    for name, configure in (("governing equation, nominal", lambda m: m),
                            ("governing equation, calibrated", calibration.apply)):
        simulated = simulate_like_runs(campaign, gear_id, configure, [d.run for d in held])
        for drop in held:
            run = simulated[drop.run]   # on the logged samples from the touchdown instant
            for output in OUTPUTS:
                values = np.interp(drop.time, run["time"], run[output]) * 1e3
                result.scores.append(_score(name, "held-out", output, drop.run,
                                            drop.outputs[output], values))
    run = next(r for r in campaign.spec.runs if r.id == held[0].run)
    return calibration.apply(drop_model_for(campaign.spec, run, gear_id))


def _recorded_small_signal(campaign: Campaign, gear_id: str):
    """A recorded small-signal run of the gear: (run id, load deviation [N], outputs' [m])."""
    for run in campaign.spec.runs:
        series = campaign.series.get(run.id)
        if run.test_type != "small-signal" or series is None or gear_id not in series.gears:
            continue
        gear = series.gears[gear_id]
        if gear.stroke is None or gear.tyre is None:
            continue
        _, channels = at_model_rate(series.time, {"load": gear.load, "stroke": gear.stroke,
                                                  "tyre": gear.tyre})
        centred = {name: values - values.mean() for name, values in channels.items()}
        return run.id, centred.pop("load"), centred
    return None


def physics_plant(model, samples: int, sample_rate: float, outputs=("stroke", "tyre")) -> Plant:
    """The drop model driven by a prescribed ground load around its resting point.

    The applied force is the unit's weight less lift plus the excitation; the outputs are
    the departures of stroke and tyre deflection from their resting values."""

    time = np.arange(samples) / sample_rate
    weight = model.total_mass * STANDARD_GRAVITY - model.lift
    rest = simulate_driven(model, time, np.full(samples, weight))
    base = {"stroke": rest.stroke, "tyre": rest.tyre}

    def plant(force: np.ndarray) -> dict:
        response = simulate_driven(model, time, weight + np.asarray(force, dtype=float))
        values = {"stroke": response.stroke, "tyre": response.tyre}
        return {name: values[name] - base[name] for name in outputs}

    return plant


def _whiteness(result, name, output, test, predicted):
    y = test.outputs[output]
    result.one_step.append((name, output, test.run, rmse(y, predicted)))
    result.whiteness.append((name, output, residual_analysis(
        y - predicted, test.load, max_lag=WHITENESS_LAGS, confidence=WHITENESS_CONFIDENCE)))

SYMBOLS = {"gamma": "γ", "sigma2": "σ²"}   # how the notes name a tuned hyper-parameter


@contextlib.contextmanager
def _edges_as_notes(result: GearIdentification, output: str, model: str, block: str):
    """The search edges of the tuning inside the block as notes of ``result`` (appendix B),
    not as :class:`~certkit.ident.search_space.SearchEdgeWarning`s (the protocol keeps its
    ranges: a run acts only on values fixed in the spec); others shown, also on an error."""
    caught: list = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", SearchEdgeWarning)
            yield
    finally:
        for warning in caught:
            if not isinstance(warning.message, SearchEdgeWarning):
                warnings.warn_explicit(warning.message, warning.category, warning.filename,
                                       warning.lineno)
                continue
            where = "; ".join(f"{SYMBOLS.get(e.parameter, e.parameter)} = {number(e.value)}"
                              f"{' kN²' * (e.parameter == 'sigma2' and block != 'narx')}, its "
                              f"{e.side} end" for e in warning.message.edges)
            keys = ", ".join(f"model.identification.{block}.{e.parameter}" for e in
                             warning.message.edges)
            result.notes.append(f"{OUTPUT_LABELS[output]}, {model}: the tuned point lies on "
                                f"the edge of the protocol's search ({where}); a better fit "
                                f"may lie beyond it. The protocol keeps its ranges; a value set"
                                f" in the spec ({keys}) is used instead of tuning")


@one_blas_thread
def identify_gear(campaign: Campaign, gear_id: str,
                  calibration=None) -> GearIdentification | None:
    """Identify and validate every model of ``gear_id``; None without two usable runs.
    ``calibration``: the gear's calibrated drop model
    (:class:`certkit.physics.calibration.GearCalibration`), reused when it was fitted to the
    identification's training runs.

    Orders, hyper-parameters, the held-out runs and the small-signal settings come from
    the spec's ``model.identification`` (defaults: the seed's orders, everything tuned,
    the held-out drops of :func:`certkit.physics.drops.default_split`)."""
    units = campaign.spec.report.units
    settings = campaign.spec.model.identification
    drops = _drops(campaign, gear_id)
    if len(drops) < 2:
        return None
    heights = drop_heights(campaign)
    drops.sort(key=lambda d: heights[d.run])
    held_out = settings.held_out or default_split(campaign, gear_id)[1]
    held = [d for d in drops if d.run in held_out]
    held.sort(key=lambda d: -heights[d.run])
    train = [d for d in drops if d not in held]
    if not held or not train:
        return None
    result = GearIdentification(gear_id, tuple(d.run for d in train),
                                tuple(d.run for d in held), measured={d.run: d for d in drops})
    plant_model = _governing_equation(campaign, gear_id, result, held, calibration)
    first = held[0]   # the paper's protocol: the first 200 samples of the highest held-out drop
    paper_train = Drop(first.run, first.load[:PAPER_TRAINING],
                       {k: v[:PAPER_TRAINING] for k, v in first.outputs.items()},
                       first.time[:PAPER_TRAINING])
    recorded = _recorded_small_signal(campaign, gear_id)
    plant = (physics_plant(plant_model, PLANT_SAMPLES, MODEL_RATE) if plant_model is not None
             else None)
    grid = np.linspace(0.0, max(d.load.max() for d in drops), 200)
    for output in OUTPUTS:
        _identify_hammerstein(result, output, train, held, paper_train, settings, grid)
        _identify_narx(result, output, train, held, paper_train, settings)
        routes = _wiener_routes(result, output, recorded, plant, plant_model, train, settings,
                                units)
        _identify_wiener(result, output, routes, train, held, paper_train, settings)
    return result


def _identify_hammerstein(result, output, train, held, paper_train, settings, grid) -> None:
    """Hammerstein LS-SVM of one output: tuned on the training runs, scored on both protocols."""
    first = held[0]
    # Hammerstein: tuned on the training runs only, for both protocols
    with _edges_as_notes(result, output, "Hammerstein", "hammerstein"):
        tuned = _hammerstein(train, output, settings.hammerstein)
    paper = _refit(HammersteinLSSVM(settings.hammerstein.na, settings.hammerstein.nb,
                                    gamma=tuned.gamma, sigma2=tuned.sigma2,
                                    input_scale=RAW_UNITS),
                   [paper_train], output)
    na = settings.hammerstein.na
    for protocol, model in (("held-out", tuned), ("paper", paper)):
        if not model.stable_:
            result.notes.append(
                f"{OUTPUT_LABELS[output]}, {protocol} protocol: the Hammerstein model's AR "
                f"part is unstable (largest |pole| {np.max(np.abs(model.poles_)):.4g}); "
                f"its free run diverges, so it is not scored")
            continue
        for test in (held if protocol == "held-out" else [first]):
            y = test.outputs[output]
            result.scores.append(_score("Hammerstein", protocol, output, test.run, y,
                                        model.simulate(test.load, y[:na])))
            if protocol == "held-out":
                _whiteness(result, "Hammerstein", output, test, model.predict(test.load, y))
    result.hammerstein_ratio[output] = tuned.singular_value_ratio_
    result.nonlinearities[("Hammerstein", output)] = (grid, tuned.nonlinearity(grid))


def _identify_narx(result, output, train, held, paper_train, settings) -> None:
    """The LS-SVM NARX reference of one output, tuned on the training runs' free-run error."""
    first = held[0]
    # NARX (black-box reference), tuned on the training runs' free-run error
    spec = settings.narx
    with _edges_as_notes(result, output, "NARX", "narx"):
        tuned_narx = NARX(spec.na, spec.nb, delay=1,
                          gamma=spec.gamma.si if spec.gamma else None,
                          sigma2=spec.sigma2.si if spec.sigma2 else None, engine="fixed-size",
                          prototypes=150, tuning={"grid": 3, "max_refine": 8}).fit(
            [d.load for d in train], [d.outputs[output] for d in train])
    paper_narx = _refit(NARX(spec.na, spec.nb, delay=1, gamma=tuned_narx.gamma_,
                             sigma2=tuned_narx.sigma2_,
                             engine="fixed-size", prototypes=150), [paper_train], output)
    for test in held:
        y = test.outputs[output]
        result.scores.append(_score("NARX", "held-out", output, test.run, y,
                                    tuned_narx.simulate(test.load, y[:tuned_narx.init_length])))
        _whiteness(result, "NARX", output, test, tuned_narx.predict(test.load, y))
    y = first.outputs[output]
    result.scores.append(_score("NARX", "paper", output, first.run, y,
                                paper_narx.simulate(first.load, y[:paper_narx.init_length])))


def _wiener_routes(result, output, recorded, plant, plant_model, train, settings, units) -> dict:
    """The records a Wiener linear block of one output is identified from, by route: a recorded
    small-signal run, else the small-signal method on the calibrated plant; and the best
    linear approximation on the plant."""
    # Wiener: the linear block from small-signal records, the nonlinearity from drops
    routes = {}
    small = settings.small_signal
    if recorded is not None:
        run_id, force, outputs = recorded
        routes["Wiener (small-signal)"] = SmallSignalExperiment(
            force=[force], responses={output: [outputs[output]]}, accepted=True)
        result.notes.append(f"{OUTPUT_LABELS[output]}: the small-signal Wiener block comes "
                            f"from recorded run {run_id}; with one record the K-scaling "
                            f"linearity check cannot be made")
    elif plant is not None:
        experiment = small_signal_records(plant, [output], PLANT_SAMPLES, MODEL_RATE,
                                          amplitude=small.amplitude.si, gain=small.gain.si,
                                          tolerance=small.tolerance.si)
        result.small_signal[output] = experiment.steps
        if experiment.accepted:
            routes["Wiener (small-signal)"] = experiment
            friction = plant_model.effect("seal friction")
            accepted = max(step.amplitude for step in experiment.steps if step.accepted)
            if friction is not None and output == "stroke":
                breakout = friction.constant + friction.pressure_factor * (
                    plant_model.upper_mass * STANDARD_GRAVITY)
                if 3.0 * accepted < breakout:
                    result.notes.append(
                        f"strut stroke: the small-signal force accepted as linear "
                        f"({with_unit(accepted, 'force', units)} RMS) stays below the seal "
                        f"friction's breakout (about {with_unit(breakout, 'force', units)}): "
                        f"the linear block describes the strut "
                        f"held by its seals, not its dynamics in a drop")
        else:
            result.notes.append(f"{OUTPUT_LABELS[output]}: the small-signal method found no "
                                f"amplitude with a linear response; no small-signal Wiener "
                                f"model")
    if plant is not None:
        amplitude = float(np.sqrt(np.mean(np.concatenate([d.load for d in train]) ** 2)))
        routes["Wiener (BLA)"] = best_linear_records(plant, [output], PLANT_SAMPLES,
                                                     MODEL_RATE, amplitude=amplitude * 1e3)
    return routes


def _identify_wiener(result, output, routes, train, held, paper_train, settings) -> None:
    """Wiener models of one output on each route: the linear block from its records, the
    static nonlinearity from the training drops; scored on both protocols."""
    first = held[0]
    target = settings.nonlinearity_target.si * 1e3
    for name, records in routes.items():
        block = ARX(settings.wiener.na, settings.wiener.nb, fit_intercept=False).fit(
            [f / 1e3 for f in records.force], [r * 1e3 for r in records.responses[output]])
        result.linear_blocks[(name, output)] = block
        if not block.stable_:
            result.notes.append(f"{OUTPUT_LABELS[output]}: the {name} linear block is "
                                f"unstable; no Wiener model on this route")
            continue
        if not block.gain_determined:
            result.notes.append(f"{OUTPUT_LABELS[output]}: the {name} linear block's static "
                                f"gain is not determined (Σb or 1 − Σa near zero); it is "
                                f"scaled to unit ‖b‖ instead of unit gain")
        spec = settings.wiener
        with _edges_as_notes(result, output, name, "wiener"):
            wiener = WienerLSSVM(gamma=spec.gamma.si if spec.gamma else None,
                                 sigma2=spec.sigma2.si if spec.sigma2 else None,
                                 linear_block=block, input_scale=RAW_UNITS,
                                 tuning={"target": target}).fit(
                [d.load for d in train], [d.outputs[output] for d in train])
        z_grid = np.linspace(*wiener.z_range_, 200)
        result.nonlinearities[(name, output)] = (z_grid, wiener.nonlinearity(z_grid))
        for test in held:
            result.scores.append(_score(name, "held-out", output, test.run,
                                        test.outputs[output], wiener.simulate(test.load)))
        fitted = wiener.nonlinearity_   # the paper's protocol reuses the tuned (γ, σ²)
        paper = WienerLSSVM(gamma=fitted.gamma, sigma2=fitted.sigma2, linear_block=block,
                            input_scale=RAW_UNITS).fit(paper_train.load,
                                                       paper_train.outputs[output])
        result.scores.append(_score(name, "paper", output, first.run,
                                    first.outputs[output], paper.simulate(first.load)))


def plant_note(campaign: Campaign) -> str:
    """What the Wiener routes' plant is, in words (the same for every gear unit)."""
    small_signal = [r.id for r in campaign.spec.runs if r.test_type == "small-signal"]
    if not small_signal:
        return ("The campaign has no small-signal run, so the Wiener routes' plant is the "
                "gear's drop model calibrated on the training runs, driven by a prescribed "
                "ground load (the tyre contact replaced by the applied force) around its "
                "resting point.")
    return (f"Small-signal run(s) {', '.join(small_signal)} recorded: the small-signal Wiener "
            f"blocks come from them; the best-linear-approximation route still uses the "
            f"calibrated drop model as its plant.")


def not_identified(campaign: Campaign, gear_id: str) -> str | None:
    """Why ``gear_id`` has no identification, in words (None: it has no drop at all, so
    there is nothing to say)."""
    unused: list[str] = []
    usable = _drops(campaign, gear_id, unused)
    if unused or usable:
        return (f"{gear_id}: {len(usable)} usable drop(s), two needed"
                + (f" ({'; '.join(unused)})" if unused else ""))
    return None


def identify(campaign: Campaign, gears: list[str] | None = None,
             calibrations: dict | None = None) -> Identification:
    """Every gear unit (or ``gears``) with at least two recorded drops; ``calibrations``:
    gear id -> its calibrated drop model, reused where it fits (:func:`identify_gear`)."""
    chosen = [u.id for u in campaign.spec.gear_units if gears is None or u.id in gears]
    # one BLAS thread: the results must not depend on the machine's core count
    with threadpool_limits(limits=1):
        found = [g for g in (identify_gear(campaign, gear_id, (calibrations or {}).get(gear_id))
                             for gear_id in chosen) if g]
    skipped = [note for gear_id in chosen if not any(g.gear_id == gear_id for g in found)
               for note in [not_identified(campaign, gear_id)] if note]
    return Identification(found, plant_note(campaign), skipped)


def identification_document(identification) -> dict | None:
    """Plain, JSON-ready summary: free-run and one-step errors, linear blocks, notes."""
    if identification is None:
        return None
    return {"plant": identification.plant_note, "gear_units": [
        {"gear_unit": g.gear_id, "training": list(g.training), "held_out": list(g.held_out),
         "free_run": [{"model": x.model, "protocol": x.protocol, "output": x.output,
                       "run": x.run, "rmse_mm": x.rmse, "nrmse": x.nrmse, "fit_percent": x.fit,
                       "max_error_mm": x.max_error} for x in g.scores],
         "one_step": [{"model": m, "output": o, "run": r, "rmse_mm": v}
                      for m, o, r, v in g.one_step],
         "linear_blocks": [{"route": route, "output": output, "a": arx.a_.tolist(),
                            "b": arx.b_.tolist(),
                            "static_gain_mm_per_kN": (arx.static_gain_ if np.isfinite(
                                arx.static_gain_) else None),
                            "stable": arx.stable_}
                           for (route, output), arx in g.linear_blocks.items()],
         "hammerstein_singular_value_ratio": g.hammerstein_ratio, "notes": g.notes}
        for g in identification.gears]}

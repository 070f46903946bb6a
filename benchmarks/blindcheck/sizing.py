"""How big a case of the independent battery (``benchmarks/blind_independent.py``) is: the
independent simulator's gear from a campaign's spec, and the size at which a truth form
changes the load by a multiple of the noise where the diagnosis can see it."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import minimize_scalar

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import truthgen  # noqa: E402

from certkit.compliance.clauses import ideal_impact_velocity  # noqa: E402
from certkit.compliance.measures import TOUCHDOWN_SHARE, TOUCHDOWN_SIGMAS  # noqa: E402
from certkit.gap.holdout import split_for  # noqa: E402
from certkit.physics.gear_model import gear_mass  # noqa: E402

from blindcheck import battery as own  # noqa: E402

P_ATM = 101325.0
#: Sizes on a form's size range at which its load change is simulated (then interpolated).
SIZING_GRID = 9
#: The measure of a case sized by what no load-cell gain explains (:func:`beyond_gain`).
BEYOND_GAIN = "beyond gain"
#: The load-cell gain errors ε the search of :func:`beyond_gain` spans.
GAIN_BOUNDS = (-0.5, 1.0)


def gear_of(campaign, run, gear_id: str, factors: dict | None = None) -> truthgen.Gear:
    """The independent simulator's gear from the spec's values (SI), each scattered by
    ``factors`` (name -> factor).  The orifice law K = ρ·A_h³/(2·(C_d·a)²) is the
    textbook square law (Milwitzky & Cook, NACA Report 1154, 1953, eq. 9)."""
    factors = factors or {}
    unit = campaign.gear_units[gear_id]
    strut, tyre = unit.strut, unit.tyre
    total = gear_mass(campaign.spec, run, gear_id)
    unsprung = strut.unsprung_mass.si
    precharge = strut.gas_precharge_pressure.si + (P_ATM if strut.pressure_reference == "gauge"
                                                   else 0.0)
    orifice = (strut.orifice_area.si if strut.orifice_area is not None
               else math.pi / 4 * strut.orifice_diameter.si ** 2)
    discharge = strut.discharge_coefficient.si * factors.get("discharge", 1.0)
    k = strut.oil_density.si * strut.hydraulic_area.si ** 3 / (2 * (discharge * orifice) ** 2)
    return truthgen.Gear(
        upper_mass=total - unsprung, lower_mass=unsprung, piston_area=strut.pneumatic_area.si,
        gas_volume=strut.gas_volume.si,
        precharge_abs=precharge * factors.get("precharge", 1.0),
        polytropic_exponent=strut.polytropic_exponent.si * factors.get("exponent", 1.0),
        compression_coefficient=k, rebound_coefficient=k,
        tyre_reference_load=tyre.load_deflection.reference_load.si * factors.get("tyre", 1.0),
        tyre_reference_deflection=tyre.load_deflection.reference_deflection.si,
        tyre_exponent=tyre.load_deflection.exponent.si,
        tyre_damping=tyre.damping.si if tyre.damping is not None else 0.0)


def _drops(campaign, gear_id: str) -> list:
    recorded = set(split_for(campaign, gear_id)[0]) | set(split_for(campaign, gear_id)[1])
    return [r for r in campaign.spec.runs if r.id in recorded]


def logger_rate(campaign) -> float:
    spec = campaign.spec
    return spec.instrumentation.sampling_rate.si if spec.instrumentation else 1000.0


def detector_level(campaign, gear_id: str, settings) -> float:
    """The load above its pre-contact baseline at which the diagnosis's touchdown detector
    (:func:`certkit.compliance.measures.touchdown_time`, which the calibration and the
    diagnosis align on) reads the contact of a record of this battery's sensors: the larger
    of :data:`TOUCHDOWN_SHARE` of the unit's static weight and :data:`TOUCHDOWN_SIGMAS`
    standard deviations of the load's noise (its random noise and its quantisation's)."""
    sigma = math.sqrt(settings.load_noise ** 2 + settings.load_step ** 2 / 12.0)
    weight = campaign.gear_units[gear_id].static_weight.si
    return max(TOUCHDOWN_SHARE * weight, TOUCHDOWN_SIGMAS * sigma)


def _plain_runs(campaign, gear_id: str, phases: tuple, nuisances: truthgen.Nuisances) -> list:
    """(run, its index, its contact phase, its record without truths) of every drop the
    diagnosis uses."""
    index_of = {run.id: i for i, run in enumerate(campaign.spec.runs)}
    out = []
    for run in _drops(campaign, gear_id):
        index = index_of[run.id]
        plain = truthgen.simulate(gear_of(campaign, run, gear_id),
                                  ideal_impact_velocity(run.drop_height.si), logger_rate(campaign),
                                  drop_index=index, nuisances=nuisances, phase=phases[index])
        out.append((run, index, phases[index], plain))
    return out


def _first_cycle_change(campaign, gear_id: str, truths: tuple, plain_runs: list, level: float,
                        nuisances: truthgen.Nuisances = truthgen.Nuisances(),
                        measure: str = "load") -> float:
    """RMS over the runs of the load change the truths make over each run's first
    compression and rebound (touchdown to the end of the rebound of the run without
    them) [N], with the touchdowns aligned first where the diagnosis's detector reads them
    (``level``, :func:`detector_level`), both records sampled as the logger samples them
    (the case's contact phases): a delay of the whole record, and what of a lag the
    alignment at that level takes out, is what an analysis that aligns on the measured
    touchdown cannot see, so only what remains counts.  ``measure`` :data:`BEYOND_GAIN`:
    only what remains of the change beyond the best load-cell gain (:func:`beyond_gain`)."""
    changed_runs, plain_runs_load, windows = [], [], []
    for run, index, phase, plain in plain_runs:
        gear = gear_of(campaign, run, gear_id)
        changed = truthgen.simulate(gear, ideal_impact_velocity(run.drop_height.si),
                                    logger_rate(campaign), truths=truths, drop_index=index,
                                    nuisances=nuisances, phase=phase)
        weight = (gear.upper_mass + gear.lower_mass) * 9.80665
        changed_runs.append(own.aligned_on_touchdown(plain.time, changed.load, plain.load,
                                                     level))
        plain_runs_load.append((plain.time, plain.load))
        windows.append(own.first_cycle(plain.time, plain.load, plain.stroke, weight))
    if measure == BEYOND_GAIN:
        return beyond_gain(changed_runs, plain_runs_load, windows, level)
    squares = [np.mean((load[w] - plain[w]) ** 2)
               for load, (_, plain), w in zip(changed_runs, plain_runs_load, windows)]
    return float(np.sqrt(np.mean(squares)))


def beyond_gain_noise(campaign, gear_id: str, truths: tuple, settings,
                      nuisances: truthgen.Nuisances, phases: tuple) -> float:
    """What of the load change ``truths`` make over the first cycle no load-cell gain
    explains (:func:`beyond_gain`), in units of the load noise, on the case's nuisances and
    contact phases."""
    plain_runs = _plain_runs(campaign, gear_id, phases, nuisances)
    level = detector_level(campaign, gear_id, settings)
    return _first_cycle_change(campaign, gear_id, truths, plain_runs, level, nuisances,
                               BEYOND_GAIN) / settings.load_noise


def beyond_gain(changed: list, plain: list, windows: list, level: float) -> float:
    """RMS over the runs' ``windows`` of what remains of the records ``changed`` beyond the
    load-cell gain that fits them best: (1 + ε)·F of the records ``plain`` ((time, F) per
    run), aligned on the touchdown at ``level`` as ``changed`` is, one ε for every run (a
    property of the load channel), found by a bounded scalar search.

    The library's gain candidate carries a skew τ too, but the diagnosis aligns each
    simulated load on its own touchdown (:func:`certkit.physics.calibration._simulated`):
    the skew moves the load against the stroke and tyre records, not against the touchdown.
    On the load record aligned there, a gain with any skew is the gain alone (to the
    interpolation's smoothing), and a crosstalk, which leaves stroke and tyre alone, is
    explained by the gain's scale only.  The figure is what a gain alone leaves with the
    nominal parameters as they are, noise-free, over the first cycle; the diagnosis fits a
    gain on the training runs' whole records together with the nominal parameters, which
    may take up part of what remains here."""
    target = [load[w] for load, w in zip(changed, windows)]

    def remains(gain: float) -> float:
        squares = [np.mean((c - own.aligned_on_touchdown(time, (1.0 + gain) * force, force,
                                                         level)[w]) ** 2)
                   for c, (time, force), w in zip(target, plain, windows)]
        return float(np.sqrt(np.mean(squares)))

    found = minimize_scalar(remains, bounds=GAIN_BOUNDS, method="bounded",
                            options={"xatol": 1e-7})
    return min(float(found.fun), remains(0.0))


def effect_sizes(campaign, gear_id: str, form_id: str, shape: tuple, ratios, settings,
                 nuisances: truthgen.Nuisances = truthgen.Nuisances(), phases: tuple = (),
                 measure: str = "load") -> dict:
    """ratio -> the size at which the form (of ``shape``) changes the first-cycle load by
    ratio × the load noise (``measure`` :data:`BEYOND_GAIN`: what of the change no load-cell
    gain explains, :func:`beyond_gain`), interpolated (log-log) on a grid over the form's
    size range (None when the range does not reach it); ``phases``: each run's contact phase
    (default: every contact on a sample)."""
    phases = phases or (0.0,) * len(campaign.spec.runs)
    plain_runs = _plain_runs(campaign, gear_id, phases, nuisances)
    level = detector_level(campaign, gear_id, settings)
    low, high = truthgen.FORMS[form_id].sizes
    grid = np.geomspace(low, high, SIZING_GRID)
    effect = np.array([_first_cycle_change(campaign, gear_id,
                                           (truthgen.Truth(form_id, float(s), shape),),
                                           plain_runs, level, nuisances, measure)
                       for s in grid])
    out = {}
    for ratio in ratios:
        target = ratio * settings.load_noise
        above = np.nonzero(effect >= target)[0]
        if above.size == 0 or above[0] == 0 or effect[above[0] - 1] <= 0:
            out[ratio] = None
            continue
        i = int(above[0])
        slope = math.log(effect[i] / effect[i - 1]) / math.log(grid[i] / grid[i - 1])
        out[ratio] = float(grid[i - 1] * (target / effect[i - 1]) ** (1.0 / slope))
    return out
